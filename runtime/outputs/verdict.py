"""The verdict of a drive run: could the drives follow the program, by stated criteria.

Judged on the *actual* motion (:mod:`irlc.runtime.outputs.actual_motion`) at the IPO samples.
**Failures** (``could_follow = false``; the first in time is the run's error, exit 2):

* ``path_tolerance``: actual path error ``> R_PATH_TOL`` in effect at that sample
  (start value ``--path-tolerance``, default 0.05 mm);
* ``orientation_tolerance``: actual orientation error ``> --orientation-tolerance``
  (default 0.01°);
* ``following_error``: ``|θ_cmd − θ̂| >`` the joint's bound (``[drives]
  following_error_max``, default 5° | 10 mm), or lost steps (steppers);
* ``position_limit``: an actual joint outside the robot file's position limits;
* ``collision``: an actual clearance ``< 0`` where the commanded motion's was ``≥ 0``.

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
    bound = following_bound(model, params)
    i_peak, torque_max = ratings(model, params)
    scale = units.joint_scale(kinds)
    criteria = {
        "path_tolerance_mm": _tolerance_mm(rec, actual),
        "orientation_tolerance_deg": opts.tol_orientation / units.DEG,
        "following_error_bound": [
            {**_joint(naming, j), "bound": bound[j] / scale[j], "unit": units.joint_unit(kinds[j])}
            for j in range(model.n)
        ],
        "current_peak_A": _per_joint(naming, i_peak),
        "torque_rating": _per_joint(naming, torque_max, kinds),
    }
    found = [
        _path(rec, actual, opts.tol_position),
        _orientation(rec, actual, opts.tol_orientation),
        *_following(naming, rec, drive, bound),
        _limits(model, naming, rec, actual),
        _collision(rec, actual),
    ]
    violations = sorted((v for v in found if v is not None), key=lambda v: v[0]["time_s"])
    verdict = Verdict(criteria, [v[0] for v in violations])
    if violations:
        verdict.failure = violations[0][1]
    verdict.warnings = _rating_warnings(naming, kinds, drive, i_peak, torque_max)
    return verdict


# --------------------------------------------------------------------------- criteria


def following_bound(model, params) -> np.ndarray:
    """Per joint (SI): ``[drives] following_error_max`` where given, else 5° | 10 mm."""
    from irlc.runtime.drives.result import default_tolerance

    out = default_tolerance(model)
    if params is not None and params.following_error_max is not None:
        out[list(params.axes)] = params.following_error_max
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


def _first_over_tolerance(rec, actual) -> int | None:
    """The first sample whose actual path error exceeds the R_PATH_TOL in effect."""
    over = np.flatnonzero(actual.on_path & (actual.pos_error > rec.tol_position))
    return int(over[0]) if over.size else None


def _tolerance_mm(rec, actual) -> float:
    """The path tolerance that decides: at the first violation, else the strictest one in
    effect on the commanded path (R_PATH_TOL may change during a run)."""
    tol = rec.tol_position
    first = _first_over_tolerance(rec, actual)
    if first is not None:
        return tol[first] / units.MM
    on = tol[actual.on_path]
    return float((on.min() if on.size else tol[0]) / units.MM)


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


def _path(rec, actual, start: float):
    """The first sample beyond the R_PATH_TOL in effect; ``start`` (m) is its start value
    (``--path-tolerance``): the option is advised only where that value was in effect."""
    tol = rec.tol_position
    k = _first_over_tolerance(rec, actual)
    if k is None:
        return None
    err, lim = actual.pos_error[k] / units.MM, tol[k] / units.MM
    worst = float(actual.pos_error.max() / units.MM)
    if tol[k] == start:
        loosen = "loosen it with --path-tolerance MM or R_PATH_TOL := MM in the program"
    else:  # the program set it: the option's start value does not reach this statement
        loosen = f"loosen R_PATH_TOL, which the program set to {lim:g} mm"
    msg = (
        f"the actual TCP (simulated drives) leaves the commanded path: {err:.4g} mm at "
        f"t = {rec.times[k]:.3f} s, tolerance {lim:g} mm (R_PATH_TOL); up to {worst:.4g} mm "
        f"in the run; {loosen}, {SLOW_DOWN}"
    )
    return _violation("path_tolerance", rec, k, err, lim, "mm", msg)


def _orientation(rec, actual, tol: float):
    over = np.flatnonzero(actual.on_path & (actual.ori_error > tol))
    if not over.size:
        return None
    k = int(over[0])
    err, lim = actual.ori_error[k] / units.DEG, tol / units.DEG
    msg = (
        f"the actual TCP orientation (simulated drives) leaves the commanded path: "
        f"{err:.4g} deg at t = {rec.times[k]:.3f} s, tolerance {lim:g} deg; loosen it with "
        "--orientation-tolerance DEG, or slow down (R_SPEED_ORI, R_SPEED)"
    )
    return _violation("orientation_tolerance", rec, k, err, lim, "deg", msg)


def _sample_at(rec, t: float) -> int:
    k = int(np.searchsorted(rec.times, t, side="right") - 1)
    return int(np.clip(k, 0, len(rec.times) - 1))


def _following(naming, rec, drive, bound) -> list[tuple[dict, RunFailure]]:
    """One violation per joint whose drive could not follow: at its first recorded row
    beyond its bound; else (the bound was exceeded between recorded rows, or steps were
    lost) at its largest recorded error. Each message names the other joints too."""
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
        what = f"following error {value / sc:.4g} {unit} > bound {limit:g} {unit}"
        if axis.lost_steps:
            what = f"{axis.lost_steps} lost steps"
        others = naming.labels([o for *_, o, _v in found if o != j])
        msg = (
            f"the drive of joint {naming.label(j)} could not follow its setpoint ({what} at "
            f"t = {t:.3f} s)"
            + (f"; also {others}" if others else "")
            + "; slow down or check the drive data"
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
    first = None
    for name in sorted(actual.clearance):
        d = actual.clearance[name]
        hit = np.flatnonzero((d < 0.0) & (rec.clearance[name] >= 0.0))
        if hit.size and (first is None or hit[0] < first[0]):
            first = (int(hit[0]), name)
    if first is None:
        return None
    k, name = first
    depth = float(-actual.clearance[name][k] / units.MM)
    msg = (
        f"the actual motion (simulated drives) collides with obstacle {name} "
        f"({depth:.4g} mm deep) where the commanded motion is clear; slow down"
    )
    row, failure = _violation("collision", rec, k, -depth, 0.0, "mm", msg)
    row["obstacle"] = name
    return row, failure


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
