"""When the drive loop recomputes ``M(q)`` and ``h = C(q, q̇) q̇ + G(q)``.

Computing them costs more than the rest of a drive step, while over one step (≤ 1 ms) the
configuration hardly changes. Two policies:

* **fixed** ``every = k``: recompute every ``k`` steps (``k = 1``: exact each step);
* **adaptive** (default): the terms computed at ``(q₀, q̇₀)`` are held while

      |q − q₀|∞ ≤ δ_q,   |q̇ − q̇₀|∞ ≤ δ_v,   t − t₀ ≤ T_max

  (``δ`` in rad, rad/s for revolute joints, m, m/s for prismatic ones). To first order the
  held terms then err by at most::

      |ΔM_ij| ≤ Σ_k |∂M_ij/∂q_k| δ_q,
      |Δh_i|  ≤ Σ_k |∂h_i/∂q_k| δ_q + Σ_k |∂h_i/∂q̇_k| δ_v

  (``tests/drives/test_refresh.py`` checks this bound with finite-difference derivatives
  on a real run, and that the trajectory stays within 0.1 % of the commanded range of the
  every-step run). With the defaults below (5 mrad, 50 mrad/s, 10 ms) the IRb-6's
  gravity torque errs by ≲ 0.2 N·m (0.5 % of its 42 N·m at home); on the bench runs
  the trajectories differ from the every-step runs by ≤ 0.04 % of the commanded range.
"""

from __future__ import annotations

import numpy as np

DELTA_Q = 5e-3  # rad | m
DELTA_V = 5e-2  # rad/s | m/s
HOLD_MAX = 10e-3  # s


class Refresh:
    """``due(s, q, q̇)``: recompute at step ``s``? ``mark(s, q, q̇)`` after recomputing.
    ``due_state(s, x)`` / ``mark_state(s, x)``: the same on the stacked state
    ``x = [q; q̇]`` (one comparison against ``[δ_q…; δ_v…]`` instead of two)."""

    def __init__(self, every: int | None, h: float, n: int):
        self.every = every
        self.max_steps = max(1, int(HOLD_MAX / h + 1e-9))
        self.dq, self.dv = DELTA_Q, DELTA_V
        self.x0 = np.zeros(2 * n)  # [q0; q̇0]
        self.q0, self.qd0 = self.x0[:n], self.x0[n:]  # views
        self.q0[:] = np.inf
        self._bound = np.concatenate([np.full(n, DELTA_Q), np.full(n, DELTA_V)])
        self._diff = np.zeros(2 * n)
        self.s0 = 0
        self.count = 0

    def due(self, s: int, q: np.ndarray, qd: np.ndarray) -> bool:
        if self.every is not None:
            return s % self.every == 0
        return (
            s - self.s0 >= self.max_steps
            or np.abs(q - self.q0).max() > self.dq
            or np.abs(qd - self.qd0).max() > self.dv
        )

    def due_state(self, s: int, x: np.ndarray) -> bool:
        if self.every is not None:
            return s % self.every == 0
        if s - self.s0 >= self.max_steps:
            return True
        diff = self._diff
        np.subtract(x, self.x0, out=diff)
        np.abs(diff, out=diff)
        return bool(np.count_nonzero(diff > self._bound))

    def mark(self, s: int, q: np.ndarray, qd: np.ndarray) -> None:
        self.s0, self.count = s, self.count + 1
        self.q0[:], self.qd0[:] = q, qd

    def mark_state(self, s: int, x: np.ndarray) -> None:
        self.s0, self.count = s, self.count + 1
        self.x0[:] = x
