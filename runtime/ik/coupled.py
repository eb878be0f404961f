"""Coupled joint limits ``A q ≥ b`` (e.g. the IRb-6's ``−40° ≤ θ2+θ3 ≤ 25°``) in the QP.

The rows come from :mod:`irlc.runtime.coupled_limits` (robot file ``[[coupled_limits]]``).
Like the joint box they bound the cycle displacement ``δ = Σ + Δθ``. With the slack
``s = Aθ_s − b ≥ 0`` at the start of the cycle, ``A(θ_s + δ) ≥ b`` is ``Aδ ≥ −s``;
with acceleration limits the combination must also be able to stop before its bound,
the braking form of :mod:`limits` applied to the row::

    Aδ ≥ −brake(s),   brake(s) = 2s / (1 + √(1 + 2s/ε)),   ε_r = Δt²·Σ_j |A_rj|·a_rj

where ``a_rj`` is joint ``j``'s acceleration away from the bound (``θ̈max`` if
``A_rj > 0``, ``−θ̈min`` otherwise), i.e. the deceleration of ``A_r θ`` when every joint
of the row brakes fully. ``brake(s) ≤ s``, so the braking row implies the position row;
with infinite accelerations it is the position row. In Newton iteration ``k`` the rows
on ``Δθ`` are ``AΔθ ≥ −brake(s) − AΣ``. A start configuration that violates a row
raises :class:`CoupledLimitError` (message from :func:`coupled_limits.describe`).

Robots without coupled limits never build this object (zero cost).
"""

from __future__ import annotations

import math

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime import coupled_limits as cl
from irlc.runtime.errors import RunFailure

_TOL = 1e-9  # same slack as the joint box's "outside the limits"


class CoupledLimitError(RunFailure):
    """A coupled joint limit excludes the current state; ``violation`` has the details."""

    def __init__(self, violation: cl.Violation):
        text = cl.describe(violation)
        super().__init__(f"coupled joint limit excludes the current state: {text}", constraint=text)
        self.violation = violation


class CoupledRows:
    """The rows ``A q ≥ b`` of one robot and their per-cycle bound on ``δ``."""

    def __init__(self, model: RobotModel):
        self.limits = cl.coupled_limits(model)
        self.A, self.b = cl.as_inequalities(self.limits, model.n)
        labels = []
        for c in self.limits:
            if math.isfinite(c.lower):
                labels.append((c, "min", c.lower))
            if math.isfinite(c.upper):
                labels.append((c, "max", c.upper))
        self.labels = labels
        self.bound_d = np.zeros(self.b.shape[0])  # Aδ ≥ bound_d this cycle
        self._accel: tuple | None = None

    def __len__(self) -> int:
        return self.b.shape[0]

    def check(self, q: np.ndarray, tol: float = _TOL) -> None:
        """Raise :class:`CoupledLimitError` if ``q`` violates a row by more than ``tol``."""
        found = cl.violations(self.limits, q, tol)
        if found:
            raise CoupledLimitError(max(found, key=lambda v: v.amount))

    def prepare(self, q_start: np.ndarray, dt: float, accel: np.ndarray) -> None:
        """Bounds on ``Aδ`` for this cycle (raises if ``q_start`` violates a row)."""
        slack = self.A @ q_start - self.b
        if slack.min() < -_TOL:
            self.check(q_start)
        np.maximum(slack, 0.0, out=slack)
        two_over_eps = self._two_over_eps(accel, dt)
        root = np.sqrt(1.0 + slack * two_over_eps)
        self.bound_d = -2.0 * slack / (1.0 + root)

    def at(self, sigma: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(A, b_k)`` with ``AΔθ ≥ b_k`` at an iterate with increments ``sigma``."""
        return self.A, self.bound_d - self.A @ sigma

    def describe_row(self, row: int) -> str:
        """``"coupled limit theta2+theta3 max 25 deg"`` (program units: deg | mm)."""
        c, side, _ = self.labels[row]
        return f"coupled limit {cl.row_label(c, side)}"

    def _two_over_eps(self, accel: np.ndarray, dt: float) -> np.ndarray:
        key = self._accel
        if key is None or key[0] is not accel or key[1] != dt:
            acc = np.clip(np.abs(np.asarray(accel, dtype=float)), 0.0, 1e30)
            away = np.where(self.A > 0.0, acc[:, 1], acc[:, 0])  # a_rj per row and joint
            eps = dt * dt * (np.abs(self.A) * away).sum(axis=1)
            self._accel = (accel, dt, 2.0 / np.maximum(eps, 1e-300))
        return self._accel[2]
