"""One segment's timing: the common bounds of the axes sharing one ``s(t)``, tightened by
the motors, ``WITH TIME`` (and its split over several points) and the profile itself.

Axes ``i`` with travel ``d_i``, speed bound ``v_i`` and acceleration bound ``a_i`` share one
normalised ``s(t) ∈ [0, 1]`` when ``ṡ ≤ min_i v_i / d_i`` and ``s̈ ≤ min_i a_i / d_i``
(:func:`profiles.common_bounds`; with jerks, :func:`scurve.common_bounds`); the axis of the
longest minimum time is the slowest, the one that sets the segment's time. A motor
(:mod:`motor_limits`) is one more such axis with ``d_m = max |dθs_m/ds|``. ``R_OVERRIDE``
``k`` scales the settings (speed ``k``, acceleration ``k²``, jerk ``k³``) and stretches
``WITH TIME t`` to ``t / k``. The profile (trapezoid or S-curve) is rounded up to whole IPO
cycles and never longer than the run's simulated-time budget.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from irlc.runtime import units
from irlc.runtime.errors import RunFailure
from irlc.runtime.model.motor_limits import MotorLimits
from irlc.runtime.plan import scurve as sc
from irlc.runtime.plan.motion_values import MotionValues
from irlc.runtime.plan.profiles import (
    ProfileError,
    Trapezoid,
    common_bounds,
    cycles,
    minimum_time,
    trapezoid,
)

Profile = Trapezoid | sc.SCurve


@dataclass(frozen=True)
class Bounds:
    """Normalised bounds of one segment's ``s(t)`` (``jerk`` ``None``: the trapezoid), the
    axis that sets its time and that minimum time (s)."""

    speed: float
    accel: float
    jerk: float | None
    slowest: int
    t_min: float


def segment_bounds(distances, speeds, accels, jerks=None) -> Bounds:
    """Common bounds of the axes sharing one ``s(t)`` (:func:`profiles.common_bounds`, or
    :func:`scurve.common_bounds` when ``jerks`` are given)."""
    if jerks is None:
        v, a, slowest = common_bounds(distances, speeds, accels)
        return Bounds(v, a, None, slowest, minimum_time(v, a) if slowest >= 0 else 0.0)
    v, a, j, slowest = sc.common_bounds(distances, speeds, accels, jerks)
    return Bounds(v, a, j, slowest, sc.minimum_time(v, a, j) if slowest >= 0 else 0.0)


def motor_bounds(
    b: Bounds, motors: MotorLimits, rates: np.ndarray, pct_v: float, pct_a: float, axes: int
) -> Bounds:
    """``b`` tightened by the motors (:mod:`motor_limits`) as more axes of the same
    ``s(t)``, ``rates`` their ``D_m = max |dθs_m/ds|``: ``v ≤ pct_v · v_m / D_m``,
    ``a ≤ pct_a · a_m / D_m``; the jerk stays the path's. ``slowest ≥ axes`` (the joint
    count, or 2 for a path's position and orientation) names motor ``slowest − axes``."""
    m = motors
    v, a, k = common_bounds(rates, m.speed * pct_v, m.accel * pct_a)
    if k < 0:
        return b
    t_motor = minimum_time(v, a)
    slowest = b.slowest if b.slowest >= 0 and b.t_min >= t_motor else axes + k
    speed, accel = min(b.speed, v), min(b.accel, a)
    t_min = minimum_time(speed, accel) if b.jerk is None else sc.minimum_time(speed, accel, b.jerk)
    return Bounds(speed, accel, b.jerk, slowest, t_min)


def with_time(values: MotionValues, npts: int, line: int) -> float | None:
    """``WITH TIME`` stretched by the override (``t / k``), or ``None``."""
    if values.time is None:
        return None
    if npts > 1:
        raise RunFailure("WITH TIME on a multi-target PTP is not supported", line)
    return values.time


def split_time(
    values: MotionValues, tmins: list[float], limiting: list[str], line: int
) -> list[float | None]:
    """``WITH TIME`` (stretched by the override) over consecutive segments in proportion
    to their minimum times ``tmins`` (each ``None`` without it); shorter than their sum is
    a RunFailure naming what sets the longest segment's time (``limiting``, one per
    segment)."""
    if values.time is None:
        return [None] * len(tmins)
    k = values.k
    total = values.time
    tsum = sum(tmins)
    if total < tsum * (1.0 - 1e-12):
        at = "" if k == 1.0 else f" at R_OVERRIDE {values.override:g} %"
        slowest = limiting[int(np.argmax(tmins))] if limiting else ""
        raise RunFailure(
            f"WITH TIME := {values.written_time:g} s{at} is shorter than the {tsum * k:.6g} s "
            f"the limits allow{_sets_it(slowest)}",
            line,
            constraint=slowest or None,
        )
    if tsum == 0.0:
        return [None] * len(tmins)
    return [total * t / tsum for t in tmins]


def _sets_it(limiting: str) -> str:
    """`` (joint a1 (J1) speed/acceleration sets it)``: what sets a motion's shortest time,
    for a ``WITH TIME`` that is shorter."""
    return f" ({limiting} sets it)" if limiting else ""


def segment_profile(
    b: Bounds, duration, dt: float, line, max_duration: float, limiting: str = ""
) -> Profile:
    """The trapezoid or the S-curve (stretched to ``duration`` if given), rounded up to
    whole cycles; ``limiting`` names what sets the shortest time (a joint, the path speed),
    for the failure of a ``WITH TIME`` shorter than that.

    A motion longer than the run's simulated-time budget (``max_duration``; a speed or
    acceleration so small that the motion never arrives has ``T_min = ∞``; the
    trapezoid's ``T_min`` bounds the S-curve's from below) fails here, before a cycle
    is simulated."""
    v, a, j = b.speed, b.accel, b.jerk
    if duration is not None and not duration <= max_duration:
        raise RunFailure(
            f"WITH TIME := {duration:g} s is longer than the run's simulated-time budget "
            f"of {max_duration:g} s (raise it with --max-time)",
            line,
        )
    if v == np.inf:  # nothing moves
        n = cycles(duration or 0.0, dt)
        return Trapezoid(n * dt, 0.0, 0.0) if n else Trapezoid(0.0, np.inf, np.inf)
    t_min = minimum_time(v, a)
    if not t_min <= max_duration:
        raise RunFailure(
            f"the motion would take {units.seconds_text(t_min)} at the active speed and"
            " acceleration, "
            f"longer than the run's simulated-time budget of {max_duration:g} s "
            "(a speed or acceleration too small for the distance?)",
            line,
        )
    try:
        if j is not None:
            base = sc.scurve(v, a, j, duration)
            return sc.scurve(v, a, j, cycles(base.duration, dt) * dt)
        base = trapezoid(v, a, duration)
        return trapezoid(v, a, cycles(base.duration, dt) * dt)
    except ProfileError as exc:
        if duration is None:
            raise RunFailure(str(exc), line) from None
        raise RunFailure(
            f"WITH TIME: {exc}{_sets_it(limiting)}", line, constraint=limiting or None
        ) from None
