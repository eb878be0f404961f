"""Time-scaling profiles ``s(t)``: the path parameter from 0 to 1 over a segment.

**Trapezoid** (bang–coast–bang). With normalised speed bound ``v`` (1/s) and
acceleration bound ``a`` (1/s²) for a unit distance, the time-optimal profile is::

    1 ≥ v²/a  (trapezoid):  T = 1/v + v/a,   t_a = v/a,    cruise speed v
    1 < v²/a  (triangle):   T = 2·√(1/a),     t_a = √(1/a), peak speed  √a

    s(t) = ½·a·t²                          0 ≤ t ≤ t_a
         = ½·a·t_a² + v_c·(t − t_a)         t_a ≤ t ≤ T − t_a
         = 1 − ½·a·(T − t)²                 T − t_a ≤ t ≤ T

**Stretching** to a longer time ``T ≥ T_min`` (``WITH TIME``, or rounding up to whole
IPO cycles) keeps the acceleration and lowers the cruise speed: from
``1 = v_c·(T − v_c/a)``, ``v_c = (a·T − √(a²T² − 4a))/2``, which is real exactly when
``T ≥ 2/√a`` (always true for ``T ≥ T_min``) and never exceeds ``v``. A time shorter
than ``T_min`` is infeasible: :func:`trapezoid` raises :class:`ProfileError`.

**Several axes** (joints of a PTP move, position and orientation of a LIN move) share one
``s(t)``: axis ``i`` with distance ``L_i`` and bounds ``v_i``, ``a_i`` needs
``ṡ ≤ v_i/L_i`` and ``s̈ ≤ a_i/L_i``, so the common profile uses ``v = min v_i/L_i``,
``a = min a_i/L_i``; the axis attaining the minimum sets the time (the "slowest" axis).
:func:`shared_bounds` is this rule for any number of derivative orders (the S-curve adds
the jerk: :func:`irlc.runtime.plan.scurve.common_bounds`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from irlc.lang.errors import IrlcError


class ProfileError(IrlcError, ValueError):
    """A requested profile is impossible (time shorter than the limits allow, bad bounds)."""


@dataclass(frozen=True)
class Trapezoid:
    """``s(t)`` from 0 to 1 over ``duration`` with acceleration ``accel`` (both ramps)
    and cruise speed ``cruise`` (1/s). A zero-length profile has ``duration = 0``."""

    duration: float
    accel: float
    cruise: float

    @property
    def t_acc(self) -> float:
        return self.cruise / self.accel if self.accel > 0.0 else 0.0

    def at(self, t: float) -> float:
        """``s(t)`` for one time (the per-cycle hot path; same formula as :meth:`position`)."""
        T = self.duration
        if T == 0.0 or t >= T:
            return 1.0
        if t <= 0.0:
            return 0.0
        a, vc = self.accel, self.cruise
        ta = vc / a if a > 0.0 else 0.0  # a = 0: a hold (nothing moves), as in t_acc
        if t <= ta:
            return 0.5 * a * t * t
        if t >= T - ta:
            return 1.0 - 0.5 * a * (T - t) ** 2
        return 0.5 * a * ta * ta + vc * (t - ta)

    def position(self, t: np.ndarray | float) -> np.ndarray:
        """``s(t)``, clipped to ``[0, 1]`` outside ``[0, duration]``."""
        t = np.clip(np.asarray(t, dtype=float), 0.0, self.duration)
        if self.duration == 0.0:
            return np.ones_like(t)
        a, vc, ta, T = self.accel, self.cruise, self.t_acc, self.duration
        rise = 0.5 * a * t * t
        coast = 0.5 * a * ta * ta + vc * (t - ta)
        fall = 1.0 - 0.5 * a * (T - t) ** 2
        return np.where(t <= ta, rise, np.where(t >= T - ta, fall, coast))

    def speed(self, t: np.ndarray | float) -> np.ndarray:
        t = np.clip(np.asarray(t, dtype=float), 0.0, self.duration)
        if self.duration == 0.0:
            return np.zeros_like(t)
        a, vc, ta, T = self.accel, self.cruise, self.t_acc, self.duration
        return np.where(t <= ta, a * t, np.where(t >= T - ta, a * (T - t), vc))

    def phase(self, t: np.ndarray | float) -> np.ndarray:
        """``1`` while accelerating, ``0`` cruising, ``−1`` braking (per sample)."""
        t = np.asarray(t, dtype=float)
        ta, T = self.t_acc, self.duration
        return np.where(t <= ta, 1, np.where(t >= T - ta, -1, 0))


def minimum_time(speed: float, accel: float) -> float:
    """Time-optimal duration for a unit distance under normalised bounds (s)."""
    if speed == math.inf and accel == math.inf:
        return 0.0
    if not (speed > 0.0 and accel > 0.0):  # a bound that underflowed: it never arrives
        return math.inf
    if 1.0 * accel >= speed * speed:  # reaches the cruise speed
        return 1.0 / speed + speed / accel
    return 2.0 / math.sqrt(accel)


def trapezoid(speed: float, accel: float, duration: float | None = None) -> Trapezoid:
    """The unit-distance trapezoid under ``speed``/``accel`` (normalised, > 0, may be
    ``inf`` for a zero-length move), stretched to ``duration`` if given."""
    if not (speed > 0.0 and accel > 0.0):
        raise ProfileError(f"speed and acceleration bounds must be positive ({speed}, {accel})")
    t_min = minimum_time(speed, accel)
    if duration is None:
        duration = t_min
    elif duration < t_min * (1.0 - 1e-12):
        raise ProfileError(
            f"a time of {duration:.6g} s is shorter than the {t_min:.6g} s the limits allow"
        )
    if duration <= 0.0:
        return Trapezoid(0.0, math.inf, math.inf)
    if accel == math.inf:  # only a speed bound: pick the slowest ramp that fits
        accel = 4.0 / duration**2
    a = accel
    disc = max(0.0, a * a * duration * duration - 4.0 * a)
    cruise = 0.5 * (a * duration - math.sqrt(disc))
    return Trapezoid(duration, a, cruise)


def common_bounds(
    distances: Sequence[float], speeds: Sequence[float], accels: Sequence[float]
) -> tuple[float, float, int]:
    """Normalised ``(v, a, slowest)`` for axes sharing one trapezoid ``s(t)`` (module doc):
    :func:`shared_bounds` with :func:`minimum_time`."""
    (v, a), slowest = shared_bounds(
        distances, (speeds, accels), minimum_time, ("speed", "acceleration")
    )
    return v, a, slowest


def shared_bounds(
    distances: Sequence[float],
    bounds: Sequence[Sequence[float]],
    time_of: Callable[..., float],
    names: Sequence[str],
) -> tuple[tuple[float, ...], int]:
    """Normalised bounds of axes sharing one ``s(t)`` and the axis that sets its time.

    ``bounds[o][i]`` is axis ``i``'s bound of derivative order ``o + 1`` (speed,
    acceleration, jerk, …; positive), ``names[o]`` its name for the error message.
    Axis ``i`` with absolute distance ``L_i`` needs ``s⁽ᵒ⁾ ≤ bound_o,i / L_i``, so the
    common bound of each order is ``min_i bound_o,i / L_i`` (module doc). The *slowest*
    axis is the one whose own normalised bounds give the longest ``time_of(*bounds)``
    (:func:`minimum_time` of the trapezoid or of the S-curve); the first on a tie.
    Axes with zero distance impose nothing, nor do axes whose distance is so small
    (``1e-320``) that a normalised bound overflows: they move by less than a float
    resolves; if every distance is such, the result is ``((inf, …), −1)``.
    """
    low = [math.inf] * len(bounds)
    slowest, worst = -1, 0.0
    for i, (d, *own) in enumerate(zip(distances, *bounds, strict=True)):
        if d <= 0.0:
            continue
        if not all(b > 0.0 for b in own):
            listed = ", ".join(names[:-1]) + f" and {names[-1]}"
            raise ProfileError(f"axis {i}: {listed} bounds must be positive")
        ratios = [b / d for b in own]
        if any(math.isinf(r) and math.isfinite(b) for r, b in zip(ratios, own, strict=True)):
            continue  # overflowed: a distance below what a float resolves at these bounds
        low = [min(x, r) for x, r in zip(low, ratios, strict=True)]
        t = time_of(*ratios)
        if t > worst:
            worst, slowest = t, i
    return tuple(low), slowest


def cycles(duration: float, dt: float) -> int:
    """Number of IPO cycles covering ``duration`` (rounded up, tolerant to rounding);
    :class:`ProfileError` for a duration that is not a finite number of cycles."""
    n = duration / dt - 1e-9
    if not math.isfinite(n):
        raise ProfileError(f"a duration of {duration:g} s is not a finite number of cycles")
    return max(0, math.ceil(n))
