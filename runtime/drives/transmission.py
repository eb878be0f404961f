"""Transmission: joint ↔ motor coordinates of the driven axes.

With the motor map ``θ_m = f(q)`` (``irlc.runtime.motor_maps``, built from the robot
file's ``[transmission]``) and its Jacobian ``K(q) = ∂f/∂q`` (rows of the driven axes)::

    ω_m = K q̇,    τ_joint = Kᵀ τ_m,    rotor inertia (joint side) = Kᵀ diag(J_m) K

Three cases, fastest first:

* plain ratios ``i`` (``K`` diagonal): ``θ_m = i·q``, rotor ``J_m·i²`` on the diagonal;
* linear couplings (``ratio`` rows with ``couple``, the L-1 wrist): ``K`` constant;
* screw levers (IRb-6 A2/A3): ``f`` non-linear, ``K(q)`` evaluated each step.

Without a ``[transmission]`` table the ratios come from ``[drives] ratio``.
"""

from __future__ import annotations

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime.drives.params import DriveParams


class Transmission:
    def __init__(self, model: RobotModel, params: DriveParams):
        self.n = model.n
        self.axes = np.array(params.axes, dtype=int)
        self.ratio = params.ratio.copy()
        self.notes: list[str] = []
        self.map = None
        self.matrix: np.ndarray | None = None  # constant K (linear couplings)
        table = model.extra.get("transmission")
        if not table:
            return
        rows = [table[j] for j in self.axes]
        if all(r.get("type") == "ratio" and not r.get("couple") for r in rows):
            self.ratio = np.array([r["ratio"] for r in rows], dtype=float)
            return
        from irlc.runtime.motor_maps import MotorMap

        self.map = MotorMap.from_model(model)
        if all(r.get("type") == "ratio" for r in table):
            self.matrix = self.map.motor_jacobian(np.zeros(self.n))[self.axes]
        self.notes.append("transmission: motor maps with coupled or non-linear joints")

    @property
    def diagonal(self) -> bool:
        """Plain ratios: ``K = diag(i)`` on the driven joints."""
        return self.map is None

    def to_motor(self, q: np.ndarray) -> np.ndarray:
        """Motor angles of the driven axes; ``q`` may be ``(n,)`` or ``(k, n)``."""
        if self.map is None:
            return q[..., self.axes] * self.ratio
        if self.matrix is not None:
            return q @ self.matrix.T
        if q.ndim == 1:
            return self.map.motor_from_joint(q)[self.axes]
        return np.array([self.map.motor_from_joint(row)[self.axes] for row in q])

    def jacobian(self, q: np.ndarray) -> np.ndarray:
        """``K(q)``: ``(driven, n)``."""
        if self.map is None:
            out = np.zeros((len(self.axes), self.n))
            out[np.arange(len(self.axes)), self.axes] = self.ratio
            return out
        if self.matrix is not None:
            return self.matrix
        return self.map.motor_jacobian(q)[self.axes]

    def local_ratio(self, q: np.ndarray) -> np.ndarray:
        """``∂θ_m,a/∂q_a`` of each driven axis at ``q`` (the plain ratio when diagonal)."""
        if self.map is None:
            return self.ratio
        return self.jacobian(q)[np.arange(len(self.axes)), self.axes]

    def rotor_matrix(self, rotor_inertia: np.ndarray, q: np.ndarray) -> np.ndarray:
        """Joint-side rotor inertia ``Kᵀ diag(J_m) K`` (n×n)."""
        k = self.jacobian(q)
        return k.T @ (rotor_inertia[:, None] * k)

    def reflected(self, rotor_inertia: np.ndarray, n: int) -> np.ndarray:
        """Joint-space diagonal ``J_m·i²`` of plain ratios (zero on joints without drive)."""
        out = np.zeros(n)
        out[self.axes] = rotor_inertia * self.ratio**2
        return out
