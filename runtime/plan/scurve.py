"""Jerk-limited (S-curve) time scaling ``s(t)``: the path parameter from 0 to 1, rest to rest.

**Seven phases.** With normalised bounds on speed ``v`` (1/s), acceleration ``a`` (1/s²) and
jerk ``j`` (1/s³) for a unit distance, the time-optimal profile ramps the acceleration up
with jerk ``+j`` for ``t₁``, holds the peak acceleration ``aₚ`` for ``t₂``, ramps it down
with ``−j`` for ``t₁`` (speed ``v_c`` reached after ``t_a = 2t₁ + t₂``), cruises for
``t_v``, and brakes as the mirror image: ``s(t) = 1 − s(T − t)``::

    t₁ = aₚ/j,   t₂ = v_c/aₚ − aₚ/j,   t_a = v_c/aₚ + aₚ/j,   T = t_a + 1/v_c,
    s(t_a) = v_c·t_a/2  (the acceleration phase is point-symmetric about its middle).

**Closed form of the minimum time** (``ProfileError`` unless ``v, a, j`` are finite, > 0):

1. ``v`` reached: ``aₚ = min(a, √(v·j))`` (``a`` is not reached when ``v < a²/j``); the
   profile cruises when ``v·t_a ≤ 1``; then ``v_c = v`` and ``T = t_a + 1/v``.
2. ``v`` not reached, ``a`` reached (no cruise, ``v·t_a = 1``): ``v_c²/a + v_c·a/j = 1``,
   ``v_c = 2/(a/j + √(a²/j² + 4/a))``, ``T = 2·t_a``; valid while ``v_c ≥ a²/j``.
3. neither reached (four pure jerk phases): ``2j·t₁³ = 1``, ``t₁ = (2j)^(−1/3)``,
   ``aₚ = j·t₁``, ``v_c = j·t₁²``, ``T = 4t₁``; the case when ``j·(2j)^(−1/3) ≤ a``
   (equivalently ``a³ ≥ j²/2``), the boundary where cases 2 and 3 coincide.

**Stretching** to a longer time ``T ≥ T_min`` (``WITH TIME``, whole IPO cycles) keeps
``a`` and ``j`` and lowers the cruise speed, like the trapezoid: ``T(v_c) = t_a(v_c) + 1/v_c``
is strictly decreasing on ``(0, v_c,min]`` (``dT/dv_c = 1/a − 1/v_c² < 0`` because
``v_c·t_a ≤ 1`` gives ``v_c² < a``; with ``aₚ = √(v_c·j)``, ``dT/dv_c = 1/√(v_c·j) − 1/v_c² < 0``
because ``4v_c³ ≤ j``), so one ``v_c`` fits. Where ``aₚ = a`` (``T ≤ T(a²/j) = 2a/j + j/a²``)
it is the smaller root of ``v_c²/a + (a/j − T)·v_c + 1 = 0``,
``v_c = 2/(B + √(B² − 4/a))``, ``B = T − a/j``; otherwise ``2√(v_c/j) + 1/v_c = T`` is solved
by bisection (monotone, to the last bit).

**Several axes** share one ``s(t)`` as for the trapezoid: axis ``i`` with distance ``L_i``
needs ``ṡ ≤ v_i/L_i``, ``s̈ ≤ a_i/L_i``, ``s⃛ ≤ j_i/L_i``, so the common profile uses the
minimum of each ratio and all axes start and finish together.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from irlc.runtime.plan.profiles import ProfileError, shared_bounds
from irlc.runtime.plan.profiles import minimum_time as trapezoid_time


@dataclass(frozen=True)
class SCurve:
    """``s(t)`` from 0 to 1 over ``duration``: cruise speed ``cruise`` (1/s), peak
    acceleration ``accel`` (1/s²), jerk ``jerk`` (1/s³) and the acceleration bound
    ``accel_bound`` (``phase`` reports when the profile sits on it)."""

    duration: float
    accel: float
    cruise: float
    jerk: float
    accel_bound: float

    def __post_init__(self) -> None:  # the phase times, once (at() is the per-cycle path)
        t1 = self.accel / self.jerk
        t2 = max(0.0, self.cruise / self.accel - t1)
        object.__setattr__(self, "_t", (t1, t2, 2.0 * t1 + t2))

    @property
    def t_jerk(self) -> float:
        """``t₁``: one jerk phase."""
        return self._t[0]

    @property
    def t_const(self) -> float:
        """``t₂``: the constant-acceleration phase (0 when ``a`` is not reached)."""
        return self._t[1]

    @property
    def t_acc(self) -> float:
        """``t_a``: the whole acceleration phase."""
        return self._t[2]

    def _rise(self, tau: float) -> tuple[float, float, float, float]:
        """``(s, ṡ, s̈, s⃛)`` at ``0 ≤ τ ≤ t_a`` of the acceleration phase."""
        j, ap, vc = self.jerk, self.accel, self.cruise
        t1, t2, ta = self._t
        if tau <= t1:
            return j * tau**3 / 6.0, 0.5 * j * tau * tau, j * tau, j
        if tau <= t1 + t2:
            u = tau - t1
            v1 = 0.5 * j * t1 * t1
            return j * t1**3 / 6.0 + v1 * u + 0.5 * ap * u * u, v1 + ap * u, ap, 0.0
        w = max(0.0, ta - tau)
        return 0.5 * vc * ta - (vc * w - j * w**3 / 6.0), vc - 0.5 * j * w * w, j * w, -j

    def state(self, t: float) -> tuple[float, float, float, float]:
        """``(s, ṡ, s̈, s⃛)`` at time ``t`` (rest at 0 before, at 1 after the profile)."""
        T = self.duration
        if T == 0.0 or t >= T:
            return 1.0, 0.0, 0.0, 0.0
        if t <= 0.0:
            return 0.0, 0.0, 0.0, 0.0
        ta = self._t[2]
        if t <= ta:
            return self._rise(t)
        if t >= T - ta:
            s, v, a, jk = self._rise(T - t)
            return 1.0 - s, v, -a, jk
        return 0.5 * self.cruise * ta + self.cruise * (t - ta), self.cruise, 0.0, 0.0

    def at(self, t: float) -> float:
        """``s(t)`` for one time (the per-cycle hot path)."""
        return self.state(t)[0]

    def _each(self, t: np.ndarray | float, k: int) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        return np.array([self.state(float(x))[k] for x in t.ravel()]).reshape(t.shape)

    def position(self, t: np.ndarray | float) -> np.ndarray:
        return self._each(t, 0)

    def speed(self, t: np.ndarray | float) -> np.ndarray:
        return self._each(t, 1)

    def acceleration(self, t: np.ndarray | float) -> np.ndarray:
        return self._each(t, 2)

    def jerk_at(self, t: np.ndarray | float) -> np.ndarray:
        return self._each(t, 3)

    def phase(self, t: np.ndarray | float) -> np.ndarray:
        """``±1`` while the acceleration is held at ``±accel_bound`` (the constant-
        acceleration phases, when the bound is reached), else ``0`` — where the trapezoid
        says the same, its whole ramps."""
        acc = self.acceleration(t)
        on = np.abs(acc) >= self.accel_bound * (1.0 - 1e-9)
        return np.where(on, np.sign(acc), 0).astype(int)


def _check(speed: float, accel: float, jerk: float) -> None:
    for name, x in (("speed", speed), ("acceleration", accel), ("jerk", jerk)):
        if not (math.isfinite(x) and x > 0.0):
            raise ProfileError(f"the {name} bound of an S-curve must be positive and finite ({x})")


def fastest(speed: float, accel: float, jerk: float) -> tuple[float, float, float]:
    """``(T_min, v_c, aₚ)`` of the time-optimal unit-distance S-curve (module doc, cases 1–3)."""
    _check(speed, accel, jerk)
    v, a, j = speed, accel, jerk
    ap = min(a, math.sqrt(v * j))
    ta = v / ap + ap / j
    if v * ta <= 1.0:  # case 1: cruise at v
        return ta + 1.0 / v, v, ap
    t1 = (2.0 * j) ** (-1.0 / 3.0)
    if j * t1 <= a:  # case 3: a not reached
        return 4.0 * t1, j * t1 * t1, j * t1
    r = a / j  # case 2
    vc = 2.0 / (r + math.sqrt(r * r + 4.0 / a))
    return 2.0 * (vc / a + r), vc, a


def minimum_time(speed: float, accel: float, jerk: float) -> float:
    """Time-optimal duration of a unit distance under normalised bounds (s): never less
    than the trapezoid's under the same speed and acceleration (a jerk bound only adds
    time), which also holds where a subnormal acceleration makes the closed form underflow
    (``4/a`` overflows: it gave 0 s, and a motion that never arrives was skipped)."""
    return max(fastest(speed, accel, jerk)[0], trapezoid_time(speed, accel))


def _cruise_for(duration: float, vmax: float, a: float, j: float) -> float:
    """The cruise speed ``v_c ≤ vmax`` whose profile lasts ``duration`` (module doc)."""
    vb = a * a / j  # the cruise speed from which on a is reached
    if vb < vmax and duration <= 2.0 * a / j + j / (a * a):
        B = duration - a / j
        return 2.0 / (B + math.sqrt(max(0.0, B * B - 4.0 / a)))
    lo, hi = 0.0, min(vmax, vb)  # T(v) = 2√(v/j) + 1/v is decreasing on (0, hi]
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        if 2.0 * math.sqrt(mid / j) + 1.0 / mid > duration:
            lo = mid
        else:
            hi = mid
    return hi


def scurve(speed: float, accel: float, jerk: float, duration: float | None = None) -> SCurve:
    """The unit-distance S-curve under ``speed``/``accel``/``jerk`` (normalised, finite,
    > 0), stretched to ``duration`` if given (shorter than the minimum: ``ProfileError``)."""
    t_min, vc, ap = fastest(speed, accel, jerk)
    if duration is None or duration <= t_min:
        if duration is not None and duration < t_min * (1.0 - 1e-12):
            raise ProfileError(
                f"a time of {duration:.6g} s is shorter than the {t_min:.6g} s the limits allow"
            )
        return SCurve(t_min, ap, vc, jerk, accel)
    vc = min(vc, _cruise_for(duration, vc, accel, jerk))
    ap = min(accel, math.sqrt(vc * jerk))
    return SCurve(duration, ap, vc, jerk, accel)


def common_bounds(
    distances: Sequence[float],
    speeds: Sequence[float],
    accels: Sequence[float],
    jerks: Sequence[float],
) -> tuple[float, float, float, int]:
    """Normalised ``(v, a, j, slowest)`` for axes sharing one S-curve ``s(t)`` (module
    doc): :func:`irlc.runtime.plan.profiles.shared_bounds` with :func:`minimum_time`."""
    (v, a, j), slowest = shared_bounds(
        distances, (speeds, accels, jerks), minimum_time, ("speed", "acceleration", "jerk")
    )
    return v, a, j, slowest
