"""Setpoint interpolation between IPO samples, evaluated on the drive-step grid.

* ``linear``: ``r(t)`` is the piecewise-linear interpolation of the samples
  ``(t_k, q_k)``; held constant before the first and after the last sample.
* ``trapezoid`` (the IRb-6 slave controller): the samples are re-sampled every ``T_pr``
  (``θ_j = r(j·T_pr)``), joined linearly, and each corner is blended by a parabola of
  width ``T_pr`` — a causal moving average of width ``T_b = T_pr``::

      s(t) = (1/T_b) ∫_{t−T_b}^{t} r_pr(τ) dτ

  Between corners ``s`` moves at the segment speed ``(θ_{j+1} − θ_j)/T_pr``, at a corner
  it changes speed with constant acceleration ``Δv/T_b`` (linear with parabolic
  blends), and it lags the samples by ``T_b/2``. The motor-side limits ``v_max, a_max``
  are checked, not enforced: a violation is reported (the slave could not follow).
  For a linear transmission filtering in joint space equals filtering the motor
  setpoints.
"""

from __future__ import annotations

import numpy as np


def linear(times: np.ndarray, q: np.ndarray, grid: np.ndarray) -> np.ndarray:
    """``(len(grid), n)`` linear interpolation of the IPO samples ``q`` (``(k, n)``)."""
    idx = np.clip(np.searchsorted(times, grid, side="right") - 1, 0, len(times) - 1)
    nxt = np.minimum(idx + 1, len(times) - 1)
    span = times[nxt] - times[idx]
    frac = np.where(span > 0.0, (grid - times[idx]) / np.where(span > 0, span, 1.0), 0.0)
    frac = np.clip(frac, 0.0, 1.0)[:, None]
    return q[idx] * (1.0 - frac) + q[nxt] * frac


def trapezoid(times: np.ndarray, q: np.ndarray, grid: np.ndarray, t_pr: float) -> np.ndarray:
    """The slave controller's blended profile ``s(t)`` on ``grid`` (see module doc)."""
    t0 = times[0]
    count = int(np.ceil((max(grid[-1], times[-1]) - t0) / t_pr)) + 2
    knots = t0 + t_pr * np.arange(count)
    theta = linear(times, q, knots)
    # exact running integral of the piecewise-linear r_pr at the knots
    area = np.vstack([np.zeros(q.shape[1]), np.cumsum(0.5 * t_pr * (theta[1:] + theta[:-1]), 0)])
    return (_integral(knots, theta, area, grid) - _integral(knots, theta, area, grid - t_pr)) / t_pr


def _integral(knots, theta, area, t):
    """``∫_{t0}^{t} r_pr`` for any ``t`` (``r_pr`` constant ``θ_0`` before ``t0``)."""
    t_pr = knots[1] - knots[0]
    before = t < knots[0]
    j = np.clip(((t - knots[0]) // t_pr).astype(int), 0, len(knots) - 2)
    dt = (t - knots[j])[:, None]
    slope = (theta[j + 1] - theta[j]) / t_pr
    inside = area[j] + theta[j] * dt + 0.5 * slope * dt * dt
    return np.where(before[:, None], theta[0] * (t - knots[0])[:, None], inside)


def slave_violations(s: np.ndarray, step: float, ratio: np.ndarray, v_max, a_max):
    """Per axis: number of grid steps where ``|ṡ|·ratio > v_max`` or ``|s̈|·ratio > a_max``."""
    v = np.diff(s, axis=0) / step * np.abs(ratio)
    a = np.diff(v, axis=0) / step
    over_v = np.sum(np.abs(v) > v_max * (1 + 1e-9), axis=0)
    over_a = np.sum(np.abs(a) > a_max * (1 + 1e-6), axis=0)
    return over_v + over_a
