"""Coupled joint limits ``A q ≥ b`` (e.g. the IRb-6's ``−40° ≤ θ2+θ3 ≤ 25°``) in the QP.

The rows come from :mod:`irlc.runtime.model.coupled_limits` (robot file ``[[coupled_limits]]``).
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

**Motor speed rows** (:mod:`irlc.runtime.model.motor_limits`): where a transmission couples
joints and the drive data bound the motor speeds (the L-1 wrist, the IRb-6), the rows
``±K_m δ ≥ −v_m Δt`` (``K = ∂θs/∂q``: constant for a linear map; for a non-linear one
``K(θ_s)`` at the start of each cycle, the rows updated in place — ``varying``) are
appended after the coupled rows: the same machinery, with a fixed bound per cycle instead
of the braking slack.

Robots with neither never build this object (:meth:`CoupledRows.for_model`: zero cost).
"""

from __future__ import annotations

import math

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime.errors import RunFailure
from irlc.runtime.model import coupled_limits as cl
from irlc.runtime.model.motor_limits import MotorLimits, motor_limits

_TOL = 1e-9  # same slack as the joint box's "outside the limits"


class CoupledLimitError(RunFailure):
    """A coupled joint limit excludes the current state; ``violation`` has the details."""

    def __init__(self, violation: cl.Violation):
        text = cl.describe(violation)
        super().__init__(f"coupled joint limit excludes the current state: {text}", constraint=text)
        self.violation = violation


class CoupledRows:
    """The rows ``A q ≥ b`` of one robot and their per-cycle bound on ``δ``."""

    def __init__(self, model: RobotModel, motors: MotorLimits | None = None):
        self.limits = cl.coupled_limits(model)
        self.A, self.b = cl.as_inequalities(self.limits, model.n)
        labels: list[tuple] = []
        for c in self.limits:
            if math.isfinite(c.lower):
                labels.append((c, "min", c.lower))
            if math.isfinite(c.upper):
                labels.append((c, "max", c.upper))
        self.npos = len(labels)  # the position rows come first, then the motor rows
        self.motor_speed = np.zeros(0)  # v_m of each motor row (rad/s)
        self.varying = False  # True: the motor rows are K(q_start) of a non-linear map
        if motors is not None and motors.limited.size:
            m = motors.limited
            K = motors.map.motor_jacobian(model.home_q())[m]
            self.A = np.ascontiguousarray(np.vstack((self.A, K, -K)))
            self.motor_speed = np.concatenate((motors.speed[m], motors.speed[m]))
            labels += [("motor", "min", int(j)) for j in m] + [("motor", "max", int(j)) for j in m]
            self.varying = not motors.linear
            self._map, self._motor_rows = motors.map, m
        self.labels = labels
        self.naming = None  # the program's JointNaming (set by the solver); None: a1 … aN
        self.bound_d = np.zeros(self.A.shape[0])  # Aδ ≥ bound_d this cycle
        self._accel: tuple | None = None

    @classmethod
    def for_model(cls, model: RobotModel) -> CoupledRows | None:
        """The rows of ``model`` (coupled limits, motor speeds), or ``None`` if it has none."""
        rows = cls(model, motor_limits(model))
        return rows if len(rows) else None

    def __len__(self) -> int:
        return self.A.shape[0]

    def check(self, q: np.ndarray, tol: float = _TOL) -> None:
        """Raise :class:`CoupledLimitError` if ``q`` violates a row by more than ``tol``."""
        found = cl.violations(self.limits, q, tol)
        if found:
            raise CoupledLimitError(max(found, key=lambda v: v.amount))

    def prepare(
        self, q_start: np.ndarray, dt: float, accel: np.ndarray, q_prev: np.ndarray | None = None
    ) -> None:
        """Bounds on ``Aδ`` for this cycle (raises if ``q_start`` violates a row).

        A motor row's bound is ``v_m Δt``, or — when the motor already runs faster
        (``q_prev``: the previous cycle's start; a blend can superpose two profiles) — the
        fastest it can be braked within the joints' acceleration box,
        ``|K_m d| − Σ_j |K_mj| a_j Δt²`` with ``d = q_start − q_prev``: never an empty QP."""
        npos = self.npos
        bound = np.empty(self.A.shape[0])
        if npos:
            slack = self.A[:npos] @ q_start - self.b
            if slack.min() < -_TOL:
                self.check(q_start)
            np.maximum(slack, 0.0, out=slack)
            two_over_eps = self._two_over_eps(accel, dt)
            root = np.sqrt(1.0 + slack * two_over_eps)
            bound[:npos] = -2.0 * slack / (1.0 + root)
        if len(self.motor_speed):
            if self.varying:  # linearised at the start of the cycle, rows updated in place
                K = self._map.motor_jacobian(q_start)[self._motor_rows]
                self.A[npos : npos + len(K)] = K
                self.A[npos + len(K) :] = -K
            bound[npos:] = -self._motor_bound(q_start, dt, accel, q_prev)
        self.bound_d = bound

    def at(self, sigma: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(A, b_k)`` with ``AΔθ ≥ b_k`` at an iterate with increments ``sigma``."""
        return self.A, self.bound_d - self.A @ sigma

    def _motor_bound(self, q_start, dt, accel, q_prev) -> np.ndarray:
        """Per motor row: the largest ``±K_m δ`` allowed this cycle (see :meth:`prepare`)."""
        limit = self.motor_speed * dt
        if q_prev is None:
            return limit
        K = self.A[self.npos :]
        acc = np.clip(np.minimum(-accel[:, 0], accel[:, 1]), 0.0, 1e30)  # no 0·inf
        brake = np.abs(K) @ (acc * dt * dt)
        running = np.abs(K @ (np.asarray(q_start) - np.asarray(q_prev))) - brake
        return np.maximum(limit, running)

    def describe_row(self, row: int) -> str:
        """``"coupled limit theta2+theta3 max 25 deg"`` (program units: deg | mm)."""
        c, side, value = self.labels[row]
        if c == "motor":
            v = self.motor_speed[row - self.npos] * (1.0 if side == "max" else -1.0)
            name = f"a{value + 1}" if self.naming is None else self.naming.label(value)
            return f"motor speed of {name} {side} {v:.6g} rad/s"
        return f"coupled limit {cl.row_label(c, side)}"

    def _two_over_eps(self, accel: np.ndarray, dt: float) -> np.ndarray:
        key = self._accel
        if key is None or key[0] is not accel or key[1] != dt:
            acc = np.clip(np.abs(np.asarray(accel, dtype=float)), 0.0, 1e30)
            A = self.A[: self.npos]
            away = np.where(A > 0.0, acc[:, 1], acc[:, 0])  # a_rj per row and joint
            eps = dt * dt * (np.abs(A) * away).sum(axis=1)
            self._accel = (accel, dt, 2.0 / np.maximum(eps, 1e-300))
        return self._accel[2]
