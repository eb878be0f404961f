"""The verdict of a drive run: could the drives follow the program, by stated criteria.

Judged on the *actual* motion (:mod:`irlc.runtime.outputs.actual_motion`) at the IPO samples,
as a robot controller supervises its axes (docs/drives.md, "The verdict").
**Failures** (``could_follow = false``; the first in time is the run's error, exit 2):

* ``following_error``: ``|θ_cmd − θ̂| >`` the joint's bound, or lost steps (steppers). The
  bound is ``[drives] following_error_max`` where the robot file states it, else, for a DC
  drive, the range of its position loop ``u_ref_max / kz`` (motor side, over the
  transmission's local ratio at the start): beyond it the position controller's output —
  the speed reference — is saturated and the drive no longer follows, it catches up; else
  5° | 10 mm (steppers: their lost steps decide);
* ``path_tolerance``: actual path error ``>`` the path tolerance stated for the run: the
  user's (``--path-tolerance``, or ``R_PATH_TOL`` where the program set it), else the
  robot's path accuracy (``[drives] path_accuracy``, ISO 9283 AT_p); neither: the path error
  is reported, not judged (the kinematic tolerance judges the set points, not servo lag);
* ``orientation_tolerance``: likewise (``--orientation-tolerance``, else ``[drives]
  orientation_accuracy``);
* ``position_limit``: an actual joint outside the robot file's position limits;
* ``collision``: an actual clearance ``< 0`` (:mod:`irlc.runtime.control.collision`), unless
  collisions are allowed.

**Warnings** (ratings from the robot file, when it has them): peak current above the
motor's peak rating (``[drives.dc] i_peak``), peak torque | force above the gear's rating
(``[drives] torque_max``, joint side).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from irlc.runtime import units
from irlc.runtime.errors import RunFailure

LIMIT_SLACK = 1e-9  # SI: an actual joint this close to its limit is inside


@dataclass
class Verdict:
    criteria: dict
    violations: list[dict] = field(default_factory=list)  # sorted by time
    failure: RunFailure | None = None
    warnings: list[str] = field(default_factory=list)

    @property
    def could_follow(self) -> bool:
        return not self.violations

    def as_dict(self) -> dict:
        return {
            "could_follow": self.could_follow,
            "criteria": self.criteria,
            "violations": self.violations,
        }


def judge(model, names, rec, drive, actual, opts, params) -> Verdict:
    """The :class:`Verdict` of a drive run (module doc). ``actual`` is measured at the IPO
    samples ``rec.times``; ``params`` the robot's drive data (bounds and ratings)."""
    from irlc.runtime.model.naming import JointNaming

    naming = JointNaming.for_model(model, names)
    kinds = model.joint_kinds
    follow = following_bound(model, params, rec.q[0] if len(rec.q) else None)
    bound = follow.bound
    i_peak, torque_max = ratings(model, params)
    scale = units.joint_scale(kinds)
    path = PathTolerance.of(rec, opts, params)
    ori_tol, ori_from = orientation_tolerance(opts, params)
    path_mm, path_from = path.deciding(actual)
    criteria = {
        "path_tolerance_mm": path_mm,
        "path_tolerance_from": path_from,
        "orientation_tolerance_deg": None if ori_tol is None else ori_tol / units.DEG,
        "orientation_tolerance_from": ori_from,
        "following_error_bound": [
            {
                **_joint(naming, j),
                "bound": bound[j] / scale[j],
                "unit": units.joint_unit(kinds[j]),
                "from": follow.source[j],
            }
            for j in range(model.n)
        ],
        "current_peak_A": _per_joint(naming, i_peak),
        "torque_rating": _per_joint(naming, torque_max, kinds),
        "collisions": "allowed" if opts.allow_collisions else "fail",
    }
    found = [
        path.violation(rec, actual),
        _orientation(rec, actual, ori_tol, ori_from),
        *_following(naming, rec, drive, follow),
        _limits(model, naming, rec, actual),
        None if opts.allow_collisions else _collision(rec, actual),
    ]
    violations = sorted((v for v in found if v is not None), key=lambda v: v[0]["time_s"])
    verdict = Verdict(criteria, [v[0] for v in violations])
    if violations:
        verdict.failure = violations[0][1]
    verdict.warnings = _rating_warnings(naming, kinds, drive, i_peak, torque_max)
    return verdict


# --------------------------------------------------------------------------- criteria


BOUND_STATED = "[drives] following_error_max"
BOUND_LOOP = "the position loop's range u_ref_max/kz"
BOUND_DEFAULT = "the default 5 deg | 10 mm"


@dataclass
class FollowingBound:
    """Per joint (SI): the following-error bound, where it comes from and, for a DC drive,
    the top speed its position loop commands (``u_ref_max / ke`` over the local ratio;
    ``nan`` elsewhere): at the bound's ``u_ref_max / kz`` the speed reference saturates."""

    bound: np.ndarray
    source: list[str]
    top_speed: np.ndarray


def following_bound(model, params, q0=None) -> FollowingBound:
    """The :class:`FollowingBound` (module doc): ``[drives] following_error_max``; else a DC
    drive's position-loop range ``u_ref_max / (kz·|∂θ_m/∂q|)`` at ``q0`` (default: the
    robot's home, else zeros); else 5° | 10 mm (steppers, joints without drives)."""
    from irlc.runtime.drives.params import DcDrives
    from irlc.runtime.drives.result import default_tolerance

    out = FollowingBound(default_tolerance(model), [BOUND_DEFAULT] * model.n,
                         np.full(model.n, np.nan))  # fmt: skip
    if params is None:
        return out
    axes = list(params.axes)
    chain = params.chain
    if isinstance(chain, DcDrives):
        from irlc.runtime.drives.transmission import Transmission

        if q0 is None:
            q0 = np.array(model.home if model.home is not None else np.zeros(model.n), float)
        ratio = np.abs(Transmission(model, params).local_ratio(np.asarray(q0, dtype=float)))
        out.top_speed[axes] = chain.u_ref_max / (chain.ke * ratio)
        out.bound[axes] = chain.u_ref_max / (chain.kz * ratio)
        for j in axes:
            out.source[j] = BOUND_LOOP
    if params.following_error_max is not None:
        out.bound[axes] = params.following_error_max
        for j in axes:
            out.source[j] = BOUND_STATED
    return out


def ratings(model, params) -> tuple[np.ndarray | None, np.ndarray | None]:
    """Per joint (NaN where unrated): the motor's peak current (A) and the gear's torque
    rating (joint side, N·m | N); ``None`` when the robot file rates no axis."""
    i_peak = torque = None
    if params is not None and getattr(params.chain, "i_peak", None) is not None:
        i_peak = np.full(model.n, np.nan)
        i_peak[list(params.axes)] = params.chain.i_peak
    if params is not None and params.torque_max is not None:
        torque = np.full(model.n, np.nan)
        torque[list(params.axes)] = params.torque_max
    return i_peak, torque


def _joint(naming, j: int) -> dict:
    """A joint in JSON: its program name and the robot file's (``runtime/model/naming.py``)."""
    return {"joint": naming.name(j), "robot_name": naming.robot[j]}


def _per_joint(naming, values, kinds=None) -> list | None:
    if values is None:
        return None
    out = []
    for j, v in enumerate(values):
        row = {**_joint(naming, j), "value": None if np.isnan(v) else float(v)}
        if kinds is not None:
            row["unit"] = "N·m" if kinds[j] == units.REVOLUTE else "N"
        out.append(row)
    return out


PATH_OPTION = "--path-tolerance"
PATH_PROGRAM = "R_PATH_TOL"
PATH_ROBOT = "[drives] path_accuracy"


@dataclass
class PathTolerance:
    """The path tolerance that judges each sample of a drive run (m; ``inf``: not judged)
    and where it comes from: the user's (``--path-tolerance``; ``R_PATH_TOL`` where the
    program set it to another value than its start value), else the robot file's
    ``[drives] path_accuracy``, else none (module doc)."""

    tol: np.ndarray  # (k,) m
    source: list[str | None]  # per sample

    @classmethod
    def of(cls, rec, opts, params) -> PathTolerance:
        set_tol = rec.tol_position
        start = opts.tol_position
        program = ~np.isclose(set_tol, start, rtol=1e-9, atol=0.0)
        robot = getattr(params, "path_accuracy", None)
        fallback = np.inf if robot is None else robot
        stated = program | opts.path_tolerance_stated
        tol = np.where(stated, set_tol, fallback)
        default = None if robot is None else PATH_ROBOT
        source = [
            (PATH_PROGRAM if p else PATH_OPTION) if s else default
            for p, s in zip(program.tolist(), stated.tolist(), strict=True)
        ]
        return cls(tol, source)

    def first_over(self, actual) -> int | None:
        """The first sample on a Cartesian path whose actual error exceeds its tolerance."""
        over = np.flatnonzero(actual.on_path & (actual.pos_error > self.tol))
        return int(over[0]) if over.size else None

    def deciding(self, actual) -> tuple[float | None, str | None]:
        """The tolerance that decides (mm) and its source: at the first violation, else
        the strictest one judging the commanded path (without one, the one stated at the
        start); ``(None, None)``: not judged."""
        first = self.first_over(actual)
        if first is None:
            on = np.flatnonzero(actual.on_path & np.isfinite(self.tol))
            if not on.size:  # no Cartesian path: the tolerance stated at the start, if any
                on = np.flatnonzero(np.isfinite(self.tol[:1]))
            if not on.size:
                return None, None
            first = int(on[np.argmin(self.tol[on])])
        return float(self.tol[first] / units.MM), self.source[first]

    def violation(self, rec, actual):
        """The first sample beyond the tolerance (:func:`_violation`), naming its source
        and what would loosen it."""
        k = self.first_over(actual)
        if k is None:
            return None
        err, lim = actual.pos_error[k] / units.MM, self.tol[k] / units.MM
        worst = float(actual.pos_error.max() / units.MM)
        source = self.source[k]
        if source == PATH_OPTION:
            loosen = "loosen it with --path-tolerance MM or R_PATH_TOL := MM in the program"
        elif source == PATH_PROGRAM:  # the option's start value does not reach this statement
            loosen = f"loosen R_PATH_TOL, which the program set to {lim:g} mm"
        else:
            loosen = (
                "the robot file's path accuracy; state the tolerance the run is judged by with "
                "--path-tolerance MM"
            )
        msg = (
            f"the actual TCP (simulated drives) leaves the commanded path: {err:.4g} mm at "
            f"t = {rec.times[k]:.3f} s, tolerance {lim:g} mm ({source}); up to {worst:.4g} mm "
            f"in the run; {loosen}, {SLOW_DOWN}"
        )
        return _violation("path_tolerance", rec, k, err, lim, "mm", msg)


def orientation_tolerance(opts, params) -> tuple[float | None, str | None]:
    """The orientation tolerance (rad) that judges a drive run and its source: the
    option's, else the robot file's ``[drives] orientation_accuracy``, else none."""
    if opts.orientation_tolerance_stated:
        return opts.tol_orientation, "--orientation-tolerance"
    robot = getattr(params, "orientation_accuracy", None)
    if robot is not None:
        return robot, "[drives] orientation_accuracy"
    return None, None


def _violation(criterion, rec, k: int, value: float, limit: float, unit: str, message: str):
    t, line = float(rec.times[k]), int(rec.lines[k])
    row = {
        "criterion": criterion,
        "line": line,
        "time_s": t,
        "value": value,
        "limit": limit,
        "unit": unit,
        "message": message,
    }
    return row, RunFailure(message, line, round(t, 9), criterion.replace("_", " "))


SLOW_DOWN = "or slow down (R_SPEED): the drives' following error grows with the speed"


def _orientation(rec, actual, tol: float | None, source: str | None):
    if tol is None:
        return None
    over = np.flatnonzero(actual.on_path & (actual.ori_error > tol))
    if not over.size:
        return None
    k = int(over[0])
    err, lim = actual.ori_error[k] / units.DEG, tol / units.DEG
    msg = (
        f"the actual TCP orientation (simulated drives) leaves the commanded path: "
        f"{err:.4g} deg at t = {rec.times[k]:.3f} s, tolerance {lim:g} deg ({source}); "
        "loosen it with --orientation-tolerance DEG, or slow down (R_SPEED_ORI, R_SPEED)"
    )
    return _violation("orientation_tolerance", rec, k, err, lim, "deg", msg)


def _sample_at(rec, t: float) -> int:
    k = int(np.searchsorted(rec.times, t, side="right") - 1)
    return int(np.clip(k, 0, len(rec.times) - 1))


def _following(naming, rec, drive, follow: FollowingBound) -> list[tuple[dict, RunFailure]]:
    """One violation per joint whose drive could not follow: at its first recorded row
    beyond its bound; else (the bound was exceeded between recorded rows, or steps were
    lost) at its largest recorded error. Each message names the other joints too."""
    bound = follow.bound
    err = np.abs(drive.following_error)
    over = err > bound[None, :]
    bad = {a.joint for a in drive.axes if not a.could_follow}
    joints = sorted(bad | {int(j) for j in np.flatnonzero(over.any(axis=0))})
    found = []
    for j in joints:
        axis = drive.axes[j]
        rows = np.flatnonzero(over[:, j])
        if rows.size:
            i = int(rows[0])
            value = float(err[i, j])
        else:
            i = int(np.argmax(err[:, j]))
            value = axis.max_following_error
        found.append((float(drive.t[i]), -value / bound[j], j, value))
    found.sort()  # the first in time first; at one time the farthest beyond its bound
    out = []
    for t, _, j, value in found:
        axis = drive.axes[j]
        sc, unit = units.joint_scale([axis.kind])[0], units.joint_unit(axis.kind)
        limit = float(bound[j] / sc)
        what = (
            f"following error {value / sc:.4g} {unit} at t = {t:.3f} s, beyond the bound "
            f"{limit:.4g} {unit} ({follow.source[j]})"
        )
        if axis.lost_steps:
            what = f"{axis.lost_steps} lost steps at t = {t:.3f} s"
        others = naming.labels([o for *_, o, _v in found if o != j])
        advice = "slow down or check the drive data"
        if np.isfinite(follow.top_speed[j]):
            top = follow.top_speed[j] / sc
            advice = f"slow down: its drive runs at most {top:.4g} {unit}/s (u_ref_max/ke)"
        msg = (
            f"the drive of joint {naming.label(j)} could not follow its setpoint ({what})"
            + (f"; also {others}" if others else "")
            + f"; {advice}"
        )
        k = _sample_at(rec, t)
        row, failure = _violation("following_error", rec, k, value / sc, limit, unit, msg)
        row["time_s"], failure.time_s = t, round(t, 9)
        row.update(_joint(naming, j))
        out.append((row, failure))
    return out


def _limits(model, naming, rec, actual):
    lo = model.position_limits[:, 0] - LIMIT_SLACK
    hi = model.position_limits[:, 1] + LIMIT_SLACK
    out = (actual.q < lo) | (actual.q > hi)
    if not out.any():
        return None
    k = int(np.flatnonzero(out.any(axis=1))[0])
    j = int(np.flatnonzero(out[k])[0])
    kind = model.joints[j].kind
    sc = units.joint_scale([kind])[0]
    unit = units.joint_unit(kind)
    value = float(actual.q[k, j] / sc)
    limit = float((hi[j] - LIMIT_SLACK if actual.q[k, j] > hi[j] else lo[j] + LIMIT_SLACK) / sc)
    msg = (
        f"the actual joint {naming.label(j)} (simulated drives) overshoots its position limit: "
        f"{value:.6g} {unit} beyond {limit:.6g} {unit}; slow down or keep further from the limit"
    )
    row, failure = _violation("position_limit", rec, k, value, limit, unit, msg)
    row.update(_joint(naming, j))
    return row, failure


def _collision(rec, actual):
    """The first actual penetration of an obstacle (:mod:`irlc.runtime.control.collision`)."""
    from irlc.runtime.control.collision import failure, first_collision

    hit = first_collision(actual.times, actual.lines, actual.clearance, actual.clearance_link)
    if hit is None:
        return None
    k = int(np.searchsorted(actual.times, hit.time))  # the IPO sample (actual at rec.times)
    exc = failure(hit, actual=bool(rec.clearance[hit.obstacle][k] >= 0.0))
    row, failure_ = _violation("collision", rec, k, -hit.depth / units.MM, 0.0, "mm", exc.message)
    row.update(obstacle=hit.obstacle, link=hit.link)
    failure_.cause, failure_.details = "obstacle", exc.details
    return row, failure_


# --------------------------------------------------------------------------- warnings


def _rating_warnings(naming, kinds, drive, i_peak, torque_max) -> list[str]:
    out = []
    for a in drive.axes:
        j = a.joint
        if i_peak is not None and not np.isnan(i_peak[j]) and a.peak_current > i_peak[j]:
            out.append(
                f"joint {naming.label(j)}: peak current {a.peak_current:.4g} A is above the "
                f"motor's peak rating {i_peak[j]:g} A ([drives.dc] i_peak)"
            )
        if torque_max is not None and not np.isnan(torque_max[j]) and a.peak_torque > torque_max[j]:
            unit = "N·m" if kinds[j] == units.REVOLUTE else "N"
            what = "torque" if kinds[j] == units.REVOLUTE else "force"
            out.append(
                f"joint {naming.label(j)}: peak {what} {a.peak_torque:.4g} {unit} is beyond "
                f"the gear's rating {torque_max[j]:g} {unit} ([drives] torque_max)"
            )
    return out
