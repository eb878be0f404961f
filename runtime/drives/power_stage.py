"""Power stage: averaged voltage or PWM with exact switching.

* averaged: the armature sees the commanded voltage, limited to the supply: ``|u| ≤ U``.
* PWM (bipolar, centre-aligned, regular sampled): in each period ``T = 1/f_pwm`` the
  duty ``d = (1 + u_c/U)/2`` (``u_c`` the current controller output sampled at the
  period start, ``0 ≤ d ≤ 1``) gives ``−U`` for ``(1−d)T/2``, ``+U`` for ``dT``, ``−U`` for
  ``(1−d)T/2``. With ``ω`` held over the period the armature current is solved in closed
  form across the switching instants (:func:`.motor.first_order`), so the ripple is exact
  — no step quantises the switching instants. The integrating current controller
  integrates the exact ``∫ i dt``: ``u_c ← u_c + kiwzm (u_i T − k ∫ i dt)``. The current
  limit is exact too: the instant the current reaches ``±i_max`` is solved for.
"""

from __future__ import annotations

import numpy as np
from irlc.runtime.drives import motor


def averaged(loop, u_i, omega, c, h: float):
    """One step of the current loop (:class:`.current.CurrentLoop`) behind an averaged
    stage. Limits, handled exactly where it matters for energy:

    * ``|u| > U``: the armature alone at ``±U`` over the step (closed form), the
      controller output held at ``±U`` (anti-windup);
    * ``|i| > i_max``: the current is held at the limit and the stage delivers only
      ``u = R i + k_s ω + L Δi/h``.

    Returns mean current, mean voltage, ``∫ u i dt``, ``∫ R i² dt`` and the limit flags.
    """
    i0 = loop.x[:, 0].copy()
    i_mean, u_mean = loop.step(u_i, omega)
    x = loop.x
    over = np.abs(x[:, 1]) > c.U
    limit = (np.abs(x[:, 0]) > c.i_max) | (np.abs(i_mean) > c.i_max)
    if not (np.count_nonzero(over) or np.count_nonzero(limit)):  # the common case
        return i_mean, u_mean, u_mean * i_mean * h, c.R * i_mean * i_mean * h, over
    if over.any():
        volts = np.sign(x[:, 1]) * c.U
        end, area, square, work, _ = motor.first_order(i0, volts, omega, c.R, c.L, c.ks, h, c.i_max)
        x[:, 0] = np.where(over, end, x[:, 0])
        x[:, 1] = np.where(over, volts, x[:, 1])
        i_mean = np.where(over, area / h, i_mean)
        u_mean = np.where(over, volts, u_mean)
    limit = (np.abs(x[:, 0]) > c.i_max) | (np.abs(i_mean) > c.i_max)
    if limit.any():
        x[:, 0] = np.clip(x[:, 0], -c.i_max, c.i_max)
        i_mean = np.clip(i_mean, -c.i_max, c.i_max)
        held = c.R * i_mean + c.ks * omega + c.L * (x[:, 0] - i0) / h
        u_mean = np.where(limit, held, u_mean)
    energy = u_mean * i_mean * h
    copper = c.R * i_mean * i_mean * h
    if over.any():
        exact = over & ~limit
        energy = np.where(exact, work, energy)
        copper = np.where(exact, c.R * square, copper)
    return i_mean, u_mean, energy, copper, over | limit


class PwmStage:
    """One PWM period per call, all axes at once."""

    def __init__(self, R, L, ks, k, kiwzm, supply, i_max, frequency: float):
        self.R, self.L, self.ks, self.k, self.kiwzm = R, L, ks, k, kiwzm
        self.U, self.i_max = supply, i_max
        self.T = 1.0 / frequency
        self.i = np.zeros(len(R))
        self.u_c = np.zeros(len(R))
        m = len(R)
        self._big_t = L / R  # the armature time constant, as motor.first_order computes it
        self._volts = np.stack([-supply, supply, -supply]) * np.ones((3, m))
        self._tau = np.zeros((3, m))  # the three intervals' lengths
        self._a = np.zeros((3, m))  # their asymptotic currents
        self._d = np.zeros((3, m))  # initial minus asymptotic current
        self._ends = np.zeros((3, m))  # the currents at their ends
        self._no_hit = np.zeros(m, dtype=bool)

    def period(self, u_i, omega):
        """Advance one period. Returns mean current, mean voltage, ``∫ u i dt`` (J),
        copper loss ``∫ R i² dt`` (J) and the saturation flags (duty or current)."""
        U, T = self.U, self.T
        raw = 0.5 * (1.0 + self.u_c / U)
        duty = np.minimum(np.maximum(raw, 0.0), 1.0)  # np.clip, cheaper on small arrays
        sat = duty != raw
        parts = self._unlimited(duty, omega)
        if parts is None:
            parts = self._limited(duty, omega)
        i, area, energy, square, hit = parts
        self.i = i
        u_c = self.u_c + self.kiwzm * (u_i * T - self.k * area)
        self.u_c = np.minimum(np.maximum(u_c, -U), U)
        return area / T, (2.0 * duty - 1.0) * U, energy, self.R * square, sat | hit

    def _unlimited(self, duty, omega):
        """The three intervals at once when the current stays within ``±i_max``, else
        ``None``: the formulas of :func:`.motor.first_order` on ``(3, axes)`` arrays (rows:
        the intervals at ``−U``, ``+U``, ``−U``), the end currents chained (each interval
        is monotonic, so inside at its ends means never limited)."""
        T, tau, a, d, ends = self.T, self._tau, self._a, self._d, self._ends
        tau[0] = 0.5 * (1.0 - duty) * T
        tau[1] = duty * T
        tau[2] = tau[0]
        np.divide(self._volts - self.ks * omega, self.R, out=a)
        big_t = self._big_t
        decay = np.exp(-tau / big_t)
        np.subtract(self.i, a[0], out=d[0])  # d = i_start − a per interval
        np.add(a[0], d[0] * decay[0], out=ends[0])
        np.subtract(ends[0], a[1], out=d[1])
        np.add(a[1], d[1] * decay[1], out=ends[1])
        np.subtract(ends[1], a[2], out=d[2])
        np.add(a[2], d[2] * decay[2], out=ends[2])
        if np.count_nonzero(np.abs(ends) > self.i_max):
            return None
        one = big_t * (1.0 - decay)
        area = a * tau + d * one
        square = a * a * tau + 2.0 * a * d * one + d * d * 0.5 * big_t * (1.0 - decay * decay)
        return (
            ends[2].copy(),
            area.sum(axis=0),
            (self._volts * area).sum(axis=0),
            square.sum(axis=0),
            self._no_hit,
        )

    def _limited(self, duty, omega):
        """Interval by interval with the current limit (:func:`.motor.first_order`)."""
        U, T = self.U, self.T
        i = self.i
        sat = np.zeros(i.shape, dtype=bool)
        area = np.zeros_like(i)
        energy = np.zeros_like(i)
        square = np.zeros_like(i)
        for volts, tau in (
            (-U, 0.5 * (1.0 - duty) * T),
            (U, duty * T),
            (-U, 0.5 * (1.0 - duty) * T),
        ):
            i, part, sq, work, hit = motor.first_order(
                i, volts, omega, self.R, self.L, self.ks, tau, self.i_max
            )
            sat |= hit
            area += part
            energy += work
            square += sq
        return i, area, energy, square, sat
