"""Why a Cartesian motion could not be followed: the cause, from the solver's state.

When a cycle's TCP deviation exceeds the tolerance, the relaxed step has touched some
bound, but that bound is a symptom: near a singularity or past the workspace every
joint runs into its speed bound, and lowering the speed would not help. The cause is
decided in this order:

0. **position_limit** — the binding bound is a position or braking bound and a joint
   is within 0.5 deg (1 mm) of its active position limit at the failing cycle (or,
   after steps 2–4, anywhere on the walk): the path (as the cycles follow it) needs that
   joint beyond its limit; slower does not help.
1. **singular** — the failing cycle's task Jacobian ``J`` (free joints, controlled rows)
   has ``σ_min/σ_max < SINGULAR_RATIO`` (or no well-conditioned basis was found).
   With ``J = UΣVᵀ`` the last left singular vector ``u_m`` is the task direction the TCP
   has lost, the right one ``v_m`` the joint combination that no longer moves it: the
   joints with ``|v_m,j| ≥ 0.3·max|v_m|`` are named.
2. The whole segment is **walked** from its start configuration (:func:`reach.walk`,
   ≤ 10 mm / 2 deg steps, at most 400, the pose search of the pre-check with its
   restarts). A pose the walk cannot reach: **freeze** if it is reachable with the
   frozen joints free, **position_limit** if joints stop at their position limits,
   else **unreachable**.
3. With frozen joints, if the estimate below says the held joints cannot follow the
   path as programmed but the same walk with them free can: **freeze**.
4. Along the walk, ``σ_min/σ_max`` below ``SINGULAR_RATIO`` → **singular** (there).
5. Otherwise the joint path ``q(s)`` gives the demand: with ``ṡ ≤ v`` (the profile's
   cruise, 1/s) and ``s̈ ≤ a``, joint speed ``|q'|·v`` and acceleration
   ``|q''|·v² + |q'|·a`` (``q'``, ``q''``: finite differences over ``s``). Scaling the
   path speed by ``c`` scales ``v`` by ``c``, so the bounds hold for

       c_v = min_j θ̇max_j / max_s |q'_j|·v,
       c_a = min_j √((θ̈max_j − k_a·max_s |q'_j|·a) / max_s |q''_j|·v²)

   where ``k_a ≤ 1`` scales the path acceleration so that the ramp term uses at most
   half of ``θ̈max`` (``k_a < 1``: the message also suggests ``R_ACC``). The smaller
   factor names the cause (**speed_limit** or **accel_limit**); the suggested speed is
   ``SAFETY·min(c_v, c_a)`` times the segment's peak speed (``R_SPEED`` in mm/s, or
   ``R_SPEED_ORI`` in deg/s when the orientation sets the segment's time), rounded
   down to two significant digits. The segment's speeds are actual ones: ``R_OVERRIDE``
   scales the programmed speeds by ``k = R_OVERRIDE/100`` and accelerations by ``k²``
   (:mod:`~irlc.runtime.plan.preinterp`), so the value to program is the actual bound over
   ``k`` (``k²`` for ``R_ACC``), and the message says at which override it holds.
   A factor ``< MIN_FACTOR`` (a path through a near-singularity, or a jump between
   branches) counts as **singular**.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from irlc.runtime import units
from irlc.runtime.errors import RunFailure
from irlc.runtime.ik import freeze_with_limits, unreachable
from irlc.runtime.ik.limits import format_joint_value
from irlc.runtime.ik.reach import Reach, walk
from irlc.runtime.model.kinematics import Kinematics

SINGULAR_RATIO = 1e-3
LIMIT_MARGIN = (1e-3, 0.5 * units.DEG)  # (prismatic m, revolute rad): "at" a position limit
MIN_FACTOR = 1e-2
SAFETY = 0.8
DIAG_LENGTH = 0.01  # m per walk step of the diagnosis
DIAG_ANGLE = 2.0 * units.DEG
MAX_STEPS = 400
TASK_NAMES = ("x", "y", "z", "rx", "ry", "rz")


def classify(
    message: str,
    res,
    seg,
    q_start: np.ndarray,
    reach: Reach,
    kin: Kinematics,
    line: int,
    time_s: float,
    override: float = 1.0,
) -> RunFailure:
    """The :class:`RunFailure` of a deviation beyond tolerance in segment ``seg`` (which
    started at ``q_start``), with its cause; ``override`` is the factor
    ``k = R_OVERRIDE/100`` the segment was planned with (its suggested speeds are
    programmed values: the actual ones over ``k``, ``k²`` for an acceleration)."""
    constraint = res.binding or None
    free = _free(reach, frozen=True)
    if res._jac is not None:
        sing = _singular(res._jac, reach, free)
        if res.singular or sing[0] < SINGULAR_RATIO:
            if (
                reach.frozen
                and _singular(_task_jacobian(kin, res.q, reach), reach, _free(reach, frozen=False))[
                    0
                ]
                >= SINGULAR_RATIO
            ):
                return _freeze_failure(message, reach, "are singular here", line, time_s)
            return _singular_failure(message, sing, reach, line, time_s, constraint, "here")
    at_limit = _at_position_limit(res.q, reach)
    by_position = bool(constraint) and of_bound(constraint) == "position_limit"
    if at_limit and by_position:
        return _with_freeze(message, reach, seg, q_start, kin, at_limit, line, time_s) or (
            _position_failure(message, reach, res.q, at_limit, constraint, line, time_s)
        )
    held = _survey(reach, seg, q_start, kin, frozen=True)
    if held.failed is not None:
        return _off_workspace(message, reach, seg.path, held, q_start, line, time_s)
    if reach.frozen and not held.feasible:
        freed = _survey(reach, seg, q_start, kin, frozen=False)
        if freed.failed is None and freed.feasible:
            what = (
                "pass a singular configuration on the path"
                if held.worst[0] < SINGULAR_RATIO or held.factor < MIN_FACTOR
                else f"need {_speed_text(seg, held, override)} on this path"
            )
            return _freeze_failure(message, reach, what, line, time_s)
    if held.worst[0] < SINGULAR_RATIO or held.factor < MIN_FACTOR:
        return _singular_failure(
            message, held.worst, reach, line, time_s, constraint, "on the path"
        )
    pressed = _pressed_on_walk(held.q, reach)
    if pressed and by_position:
        # the walk itself needs a joint at its limit: the cycles, which cannot jump to the
        # walk's configurations, would need it beyond; slower does not help
        return _with_freeze(message, reach, seg, q_start, kin, pressed, line, time_s) or (
            _position_failure(message, reach, res.q, pressed, constraint, line, time_s)
        )
    return _speed_failure(message, seg, held, constraint, line, time_s, override)


@dataclass
class _Survey:
    """The segment walked from its start: ``s``, configurations (rows), the failed pose
    search (or ``None``), the most singular point, and the factors of :func:`_factors`."""

    s: np.ndarray
    q: np.ndarray
    failed: object
    worst: tuple = (math.inf, math.inf, [], [])
    c_v: float = math.inf
    c_a: float = math.inf
    k_a: float = 1.0

    @property
    def factor(self) -> float:
        return min(self.c_v, self.c_a)

    @property
    def feasible(self) -> bool:
        """The estimate says the path can be followed as programmed: no speed factor
        below 1, the ramp term within the acceleration limit, not singular."""
        return (
            self.failed is None
            and self.factor >= 1.0
            and 2.0 * self.k_a >= 1.0
            and self.worst[0] >= SINGULAR_RATIO
        )


def _survey(reach: Reach, seg, q_start, kin, *, frozen: bool) -> _Survey:
    timed = any(r >= 3 for r in reach.task_rows)
    path = seg.path
    per_step = max(path.length / DIAG_LENGTH, _angle(path, timed) / DIAG_ANGLE)
    steps = min(max(2, math.ceil(per_step)), MAX_STEPS)
    s_vals, configs, failed = walk(reach, path.at, q_start, 0.0, steps, frozen=frozen)
    s_all = np.concatenate(([0.0], s_vals))
    q_all = np.vstack([q_start, *configs])
    if failed is not None:
        return _Survey(s_all, q_all, failed)
    free = _free(reach, frozen)
    along = [_singular(_task_jacobian(kin, q, reach), reach, free) for q in q_all]
    worst = min(along, key=lambda x: x[0])
    prof = seg.profile
    c_v, c_a, k_a = _factors(*_demand(seg, s_all, q_all), prof.cruise, prof.accel)
    return _Survey(s_all, q_all, None, worst, c_v, c_a, k_a)


def _at_position_limit(q: np.ndarray, reach: Reach) -> list[tuple[int, int]]:
    """Joints within ``LIMIT_MARGIN`` (0.5 deg, 1 mm) of an active position limit, as
    ``(joint, side)`` with side 0 = min, 1 = max."""
    margin = np.array([LIMIT_MARGIN[j.kind == "revolute"] for j in reach.model.joints])
    lo, hi = reach.position[:, 0], reach.position[:, 1]
    out = [(j, 0) for j in np.flatnonzero(q - lo <= margin)]
    out += [(j, 1) for j in np.flatnonzero(hi - q <= margin)]
    return sorted((int(j), side) for j, side in out)


def _pressed_on_walk(configs: np.ndarray, reach: Reach) -> list[tuple[int, int]]:
    """``(joint, side)`` at an active position limit anywhere on the walk (its start
    excluded: that is where the segment began)."""
    return sorted({hit for q in configs[1:] for hit in _at_position_limit(q, reach)})


def _position_failure(message, reach: Reach, q, at_limit, constraint, line, time_s):
    model, naming = reach.model, reach.naming
    parts = [
        f"{naming.label(j)} at its position {('min', 'max')[side]} "
        f"{format_joint_value(model, j, reach.position[j, side], 0)}"
        for j, side in at_limit
    ]
    return RunFailure(
        f"{message}; cause: a joint position limit on this path ({', '.join(parts)}); a "
        "lower speed does not resolve it (another start configuration or a CYCLIC / WITH "
        "RECONFIGURATION reference may)",
        line,
        time_s,
        constraint,
        cause="position_limit",
        details={"joints": [naming.name(j) for j, _ in at_limit]},
    )


def _with_freeze(message, reach: Reach, seg, q_start, kin, at_limit, line, time_s):
    """A position limit a JOINTLIMIT narrowed, pressed while joints are frozen, on a path
    the walk follows as programmed with the frozen joints free: FREEZE and JOINTLIMIT
    together are the cause (freeze_with_limits.py); else ``None``."""
    own = reach.model.position_limits
    narrowed = [j for j, side in at_limit if reach.position[j, side] != own[j, side]]
    if not reach.frozen or not narrowed:
        return None
    freed = _survey(reach, seg, q_start, kin, frozen=False)
    if freed.failed is not None or not freed.feasible:
        return None
    model = reach.model
    bounds = ", ".join(
        f"{reach.naming.label(j)} beyond its JOINTLIMIT {('min', 'max')[side]} "
        f"{format_joint_value(model, j, reach.position[j, side], 0)}"
        for j, side in at_limit
        if j in narrowed
    )
    head = f"{message}; cause: the path needs {bounds}"
    tail = "; with the frozen joints free the path can be followed as programmed"
    return freeze_with_limits.failure(reach, sorted(set(narrowed)), head, tail, line, time_s, {})


def _free(reach: Reach, frozen: bool) -> np.ndarray:
    held = reach.frozen if frozen else {}
    return np.array([j for j in range(reach.model.n) if j not in held], dtype=int)


def _freeze_failure(message, reach: Reach, what: str, line, time_s) -> RunFailure:
    names = reach.naming.labels(sorted(reach.frozen))
    return RunFailure(
        f"{message}; cause: FREEZE of joints {names} leaves too few free joints: the "
        f"others {what}; with them free the path can be followed as programmed",
        line,
        time_s,
        f"FREEZE {names}",
        cause="freeze",
        details={"joints": [reach.naming.name(j) for j in sorted(reach.frozen)]},
    )


def of_bound(binding: str) -> str | None:
    """The cause a bound's label names by itself (``"a4 (J4) speed max 120 deg/s"`` →
    ``speed_limit``), for a held TCP (RECONFIGURATION), where no path is walked."""
    for word, name in (
        (" position ", "position_limit"),
        (" braking ", "position_limit"),
        (" speed ", "speed_limit"),
        (" accel ", "accel_limit"),
    ):
        if word in f" {binding} ":
            return name
    return None


def _angle(path, timed: bool) -> float:
    return path.angle if timed else 0.0


def _task_jacobian(kin: Kinematics, q: np.ndarray, reach: Reach) -> np.ndarray:
    return kin.jacobian(q)[list(reach.task_rows)]


def _singular(jac: np.ndarray, reach: Reach, free: np.ndarray):
    """``(σ_min/σ_max, σ_min, joints, task directions)`` of a task Jacobian. ``jac`` has
    the free joints' columns (the cycle's) or all columns (then restricted here)."""
    J = jac if jac.shape[1] == free.size else jac[:, free]
    m = J.shape[0]
    if J.shape[1] < m:
        return 0.0, 0.0, [], []
    U, s, Vt = np.linalg.svd(J)
    smin = float(s[m - 1])
    ratio = smin / float(s[0]) if s[0] > 0 else 0.0
    v = np.abs(Vt[m - 1])
    joints = [int(free[j]) for j in np.flatnonzero(v >= 0.3 * v.max())]
    u = np.abs(U[:, m - 1])
    tasks = reach.task_rows  # a chain's extra rows (a tool held vertical) follow them
    rows = [
        TASK_NAMES[tasks[i]] if i < len(tasks) else "its extra task rows"
        for i in np.flatnonzero(u >= 0.3 * u.max())
    ]
    return ratio, smin, joints, list(dict.fromkeys(rows))


def _singular_failure(message, sing, reach, line, time_s, constraint, where) -> RunFailure:
    ratio, smin, joints, rows = sing
    naming = reach.naming
    names = naming.labels(joints)
    text = (
        f"{message}; cause: singular configuration {where} (σ_min = {smin:.3g}, "
        f"σ_min/σ_max = {ratio:.3g}): the TCP cannot move along {'/'.join(rows) or '—'}"
        f"{'; joints involved: ' + names if joints else ''}; a lower speed does not help"
    )
    details = {
        "sigma_min_si": smin,  # of the SI Jacobian (m/rad position rows, rad/rad)
        "sigma_ratio": ratio,
        "joints": [naming.name(j) for j in joints],
        "lost_directions": rows,
    }
    return RunFailure(text, line, time_s, constraint, cause="singular", details=details)


def _off_workspace(message, reach, path, survey: _Survey, q_start, line, time_s):
    failed = survey.failed
    s_bad = float(min(1.0, survey.s[-1] + 1.0 / max(1, len(survey.s))))
    where = f"about {s_bad * path.length / units.MM:.4g} mm along the segment"
    details = {
        "distance_mm": failed.position_error / units.MM,
        "distance_deg": failed.orientation_error / units.DEG,
    }
    seed = survey.q[-1]
    if reach.frozen and reach.reached(reach.search(path.at(s_bad), seed, frozen=False)):
        narrowed = freeze_with_limits.narrowed_joints(reach, path.at(s_bad), seed, failed.q)
        if narrowed:  # the JOINTLIMIT is part of the cause: each alone follows the path
            head = f"{message}; cause: the path {where} is out of reach"
            closest = f": the closest pose found is {failed.position_error / units.MM:.4g} mm away"
            tail = closest + freeze_with_limits.EACH_ALONE
            return freeze_with_limits.failure(reach, narrowed, head, tail, line, time_s, details)
        names = reach.naming.labels(sorted(reach.frozen))
        details["joints"] = [reach.naming.name(j) for j in sorted(reach.frozen)]
        return RunFailure(
            f"{message}; cause: FREEZE of joints {names} leaves too few free joints: the "
            f"path {where} is out of reach with them held (closest pose "
            f"{failed.position_error / units.MM:.4g} mm away), reachable with them free",
            line,
            time_s,
            f"FREEZE {names}",
            cause="freeze",
            details=details,
        )
    if "limits reached" in failed.message:  # the branch followed runs into a limit
        cause, what = "position_limit", f"the path {where} needs a joint beyond its limit"
    else:
        cause, what = "unreachable", f"the path {where} is out of reach"
    text = failed.message.replace(unreachable.NOT_REACHABLE, what)
    text = text.replace(unreachable.NOT_FOUND, f"no solution found for the path {where}", 1)
    return RunFailure(f"{message}; cause: {text}", line, time_s, None, cause=cause, details=details)


def _demand(seg, s: np.ndarray, q: np.ndarray):
    """``(|q'|, |q''|, speed limits, acceleration limits)`` along the walk: ``q'`` per
    interval (``(k, n)``), ``q''`` per inner point (``(k − 1, n)``), limits in the
    direction of motion."""
    dq = np.diff(q, axis=0) / np.diff(s)[:, None]
    spd, acc = seg.limits[1], seg.limits[2]
    vlim = np.where(dq >= 0.0, spd[:, 1], -spd[:, 0])
    alim = np.minimum(acc[:, 1], -acc[:, 0])
    if dq.shape[0] >= 2:
        mid = 0.5 * (s[1:] + s[:-1])
        d2 = np.abs(np.diff(dq, axis=0) / np.diff(mid)[:, None])
    else:
        d2 = np.zeros((0, q.shape[1]))
    return np.abs(dq), d2, vlim, alim


def _factors(dq, d2, vlim, alim, v: float, a: float) -> tuple[float, float, float]:
    """``(c_v, c_a, k_a)``: path-speed factors for the speed and acceleration bounds, and
    the factor on the path acceleration (``R_ACC``) needed first (1 when the ramp term
    ``|q'|·a`` uses at most half of ``θ̈max``)."""
    c_v = float(np.min(vlim / np.maximum(dq * v, 1e-300)))
    if d2.shape[0] == 0:
        return c_v, math.inf, 1.0
    slope = np.maximum(dq[1:], dq[:-1])  # |q'| around each inner point
    k_a = float(min(1.0, np.min(0.5 * alim / np.maximum(slope * a, 1e-300))))
    room = alim - slope * a * k_a
    curv = d2 * v * v
    ratio = np.where(curv > 0.0, room / np.maximum(curv, 1e-300), math.inf)
    return c_v, math.sqrt(float(np.min(ratio))), k_a


def _speed_setting(seg) -> tuple[float, str, str, str]:
    """``(size of the segment in program units, unit, setting, report key)``: the path
    length and ``R_SPEED``, or the angle and ``R_SPEED_ORI`` when it sets the time."""
    if seg.limiting == "orientation speed":
        return seg.path.angle / units.DEG, "deg/s", "R_SPEED_ORI", "speed_ori_deg_s"
    return seg.path.length / units.MM, "mm/s", "R_SPEED", "speed_mm_s"


def _suggested(seg, survey: _Survey, override: float) -> float:
    """The programmed speed to suggest: the actual bound (``SAFETY`` below the factor)
    over the override factor ``k``."""
    size = _speed_setting(seg)[0]
    return _round_down(seg.profile.cruise * size * min(survey.factor, 1.0) * SAFETY / override)


def _at_override(override: float) -> str:
    """`` at R_OVERRIDE n %`` when the suggestion holds at an override other than 100 %."""
    return "" if override == 1.0 else f" at R_OVERRIDE {100.0 * override:g} %"


def _speed_text(seg, survey: _Survey, override: float) -> str:
    _, unit, name, _ = _speed_setting(seg)
    return f"{name} ≤ {_suggested(seg, survey, override):g} {unit}{_at_override(override)}"


def _now(now: str, value: float, scale: float, unit: str, override: float) -> str:
    """``(now)``: the segment's actual peak; with an override first what the suggested
    programmed ``value`` is actually (``value·scale``, ``scale`` = ``k`` or ``k²``)."""
    if override == 1.0:
        return f"({now})"
    return f"({value * scale:.4g} {unit} actual; {now})"


def _speed_failure(
    message, seg, survey: _Survey, constraint, line, time_s, override: float
) -> RunFailure:
    c_v, c_a, k_a = survey.c_v, survey.c_a, survey.k_a
    estimate = "speed_limit" if c_v <= c_a and k_a == 1.0 else "accel_limit"
    bound = of_bound(constraint) if constraint else None
    # the bound the failing cycle met names the cause where it is one of the two: the
    # estimate's other factor only shapes the suggestion (one cause, not two)
    cause = bound if bound in ("speed_limit", "accel_limit") else estimate
    what = "speed" if cause == "speed_limit" else "acceleration"
    which = "that joint" if bound == cause else "a joint"
    size, unit, name, key = _speed_setting(seg)
    acc_now = seg.profile.accel * size
    acc_ok = _round_down(acc_now * k_a * SAFETY / override**2) if k_a < 1.0 else None
    fixed = seg.with_time_s
    if fixed is not None:  # WITH TIME fixes the speed: a longer time resolves it
        acc_scale = 1.0 if acc_ok is None else acc_ok * override**2 / acc_now
        longer = _longer_time(seg, survey, fixed, acc_scale)
        how = f"a longer time resolves it: WITH TIME := {longer:g} s or more (now {fixed:g} s)"
        details = {"suggested_time_s": longer}
    else:
        now, suggested = seg.profile.cruise * size, _suggested(seg, survey, override)
        peak = f"the segment peaks at {now:.4g} {unit} now"
        how = (
            f"a lower speed resolves it: {_speed_text(seg, survey, override)} "
            f"{_now(peak, suggested, override, unit, override)}"
        )
        details = {f"suggested_{key}": suggested}
    text = f"{message}; cause: {which} {what} bound; {how}"
    if acc_ok is not None:
        acc_name = "R_ACC" if name == "R_SPEED" else "the orientation acceleration"
        acc_unit = f"{unit}²"
        acc_peak = f"now {acc_now:.4g} {acc_unit}"
        text += (
            f" and {acc_name} ≤ {acc_ok:g} {acc_unit}{_at_override(override)} "
            f"{_now(acc_peak, acc_ok, override**2, acc_unit, override)}"
        )
        if name == "R_SPEED":
            details["suggested_acc_mm_s2"] = acc_ok
    return RunFailure(text, line, time_s, constraint, cause=cause, details=details)


def _longer_time(seg, survey: _Survey, fixed: float, acc_scale: float) -> float:
    """The ``WITH TIME`` (s, programmed) at which the segment's joints can follow: a
    longer time keeps the ramps' acceleration ``a`` (× ``acc_scale`` where the message
    also suggests a lower R_ACC) and lowers the cruise ``v`` (normalised, 1/s) to
    ``v' = SAFETY·min(c_v, c_a)·v``, so the segment takes ``T' = 1/v' + v'/a'`` instead of
    its ``T``; the statement's time scales alike: ``fixed·T'/T``, rounded up to two
    significant digits."""
    prof = seg.profile
    v_new = prof.cruise * SAFETY * min(survey.factor, 1.0)
    a_new = prof.accel * acc_scale
    if not (v_new > 0.0 and a_new > 0.0 and prof.duration > 0.0):
        return fixed
    return _round_up(fixed * (1.0 / v_new + v_new / a_new) / prof.duration)


def _round_up(x: float) -> float:
    """Two significant digits, rounded up (a time that is at least ``x``)."""
    if x <= 0.0 or not math.isfinite(x):
        return x
    step = 10.0 ** (math.floor(math.log10(x)) - 1)
    return round(math.ceil(x / step - 1e-9) * step, 12)


def _round_down(x: float) -> float:
    """Two significant digits, rounded down (a speed that is at most ``x``)."""
    if x <= 0.0 or not math.isfinite(x):
        return 0.0
    step = 10.0 ** (math.floor(math.log10(x)) - 1)
    return math.floor(x / step) * step
