"""Permanent-magnet DC motor: armature circuit and torque.

    L di/dt = u − R i − k_s ω,     τ_m = k_s i,     |i| ≤ i_max (clamp)

The armature is linear; it is integrated exactly together with the current controller
(:mod:`.current`) or across PWM switching instants (:mod:`.power_stage`). Energy:
``u i = R i² + d(½ L i²)/dt + τ_m ω``.
"""

from __future__ import annotations

import numpy as np


def torque(ks, current) -> np.ndarray:
    """``τ_m = k_s i``."""
    return ks * current


def first_order(i0, voltage, omega, R, L, ks, tau, i_max):
    """Exact armature current after ``tau`` at constant ``voltage`` and ``omega`` with the
    power stage's current limit, and the integrals over ``[0, tau]``::

        i(t) = a + d e^{−t/T},  a = (u − k_s ω)/R,  d = i0 − a,  T = L/R
        ∫ i  = a t + d T (1 − e^{−t/T})
        ∫ i² = a² t + 2 a d T (1 − e^{−t/T}) + d² (T/2)(1 − e^{−2t/T})

    If ``|a| > i_max`` the current reaches ``s·i_max`` at ``t* = T ln(d / (s·i_max − a))``
    and stays there: the stage then delivers only ``R i + k_s ω`` (the energy counts that).
    Returns ``(i(τ), ∫ i, ∫ i², ∫ u i, limited)``.
    """
    a = (voltage - ks * omega) / R
    big_t = L / R
    d = i0 - a
    decay = np.exp(-tau / big_t)
    end = a + d * decay
    if np.all(np.abs(end) <= i_max):  # monotonic: inside at both ends → never limited
        one = big_t * (1.0 - decay)
        area = a * tau + d * one
        square = a * a * tau + 2.0 * a * d * one + d * d * 0.5 * big_t * (1.0 - decay * decay)
        return end, area, square, voltage * area, np.zeros(end.shape, dtype=bool)
    limited = np.abs(a) > i_max
    side = np.sign(a)
    # e^{−t*/T} = (s·i_max − a)/d ∈ (0, 1] on limited axes; 0 (t* = ∞: never) on the others
    ratio = np.where(limited & (d != 0.0), (side * i_max - a) / np.where(d != 0.0, d, 1.0), 0.0)
    t1 = np.minimum(tau, -big_t * np.log(np.clip(ratio, 1e-300, 1.0)))
    t2 = tau - t1
    decay = np.exp(-t1 / big_t)
    one = big_t * (1.0 - decay)
    area1 = a * t1 + d * one
    square1 = a * a * t1 + 2.0 * a * d * one + d * d * 0.5 * big_t * (1.0 - decay * decay)
    held = side * i_max
    end = np.where(t2 > 0.0, held, a + d * decay)
    area = area1 + held * t2
    square = square1 + i_max * i_max * t2
    energy = voltage * area1 + (R * held + ks * omega) * held * t2
    return end, area, square, energy, limited & (t2 > 0.0)
