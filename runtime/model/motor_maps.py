"""Motor ↔ joint coordinate maps (transmissions), with their Jacobians. SI units.

Built from a robot's ``[transmission]`` table (``model.extra["transmission"]``, one entry
per joint, validated by the loader); without one every joint is a direct drive.
Couplings only refer to earlier joints, so both directions are solved joint by joint.

* ``ratio`` (with optional ``couple``): ``q_i = θs_i / k_i + Σ_j c_ij q_j`` (j < i).
  The L-1 wrist is of this kind: ``θ5 = θs5/k5 + 0.5·θ4``, ``θ6 = θs6/k6 + 2·θ5``.
  Inverse: ``θs_i = k_i (q_i − Σ_j c_ij q_j)``.
* ``screw_lever``: a ball screw of lead ``h`` sets the distance ``s`` between two lever
  pivots at distances ``a`` and ``b`` from the joint axis; the lever angle is
  ``φ = Σ_j c_j q_j`` (including ``q_i``):
  ``s(φ) = √(a² + b² − 2ab·cos(φ + φ0))``, ``θs_i = 2π (s(φ) − s(0)) / h``,
  ``dθs_i/dφ = (2π/h)·ab·sin(φ + φ0) / s``.
  Inverse: ``s = s(0) + h θs_i / 2π``, ``φ = acos((a² + b² − s²) / 2ab) − φ0``, then
  ``q_i = (φ − Σ_{j≠i} c_j q_j) / c_i``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from irlc.robots.model import RobotModel


@dataclass(frozen=True)
class MotorMap:
    """Transmissions of one robot; ``motor_from_joint`` / ``joint_from_motor`` and Jacobians."""

    entries: tuple[dict, ...]

    @classmethod
    def from_model(cls, model: RobotModel) -> MotorMap:
        rows = model.extra.get("transmission")
        if rows is None:
            rows = [{"type": "ratio", "ratio": 1.0, "couple": []} for _ in range(model.n)]
        return cls(tuple(rows))

    @property
    def n(self) -> int:
        return len(self.entries)

    # -------------------------------------------------------------- joint → motor

    def motor_from_joint(self, q: np.ndarray) -> np.ndarray:
        """Motor angles ``θs`` (rad) of joint coordinates ``q``."""
        q = np.asarray(q, dtype=float)
        out = np.empty(self.n)
        for i, e in enumerate(self.entries):
            if e["type"] == "ratio":
                out[i] = e["ratio"] * (q[i] - sum(c * q[j] for j, c in e["couple"]))
            else:
                phi = sum(c * q[j] for j, c in e["angle"])
                out[i] = 2 * math.pi * (_screw(e, phi) - _screw(e, 0.0)) / e["lead"]
        return out

    def motor_from_joints(self, qs: np.ndarray) -> np.ndarray:
        """:meth:`motor_from_joint` of many configurations at once (``(k, n)`` → ``(k, n)``,
        the same formulas on columns; for traces and reports)."""
        qs = np.atleast_2d(np.asarray(qs, dtype=float))
        out = np.empty(qs.shape)
        for i, e in enumerate(self.entries):
            if e["type"] == "ratio":
                out[:, i] = e["ratio"] * (qs[:, i] - sum(c * qs[:, j] for j, c in e["couple"]))
            else:
                phi = sum(c * qs[:, j] for j, c in e["angle"])
                a, b = e["a"], e["b"]
                s = np.sqrt(a * a + b * b - 2 * a * b * np.cos(phi + e["phi0"]))
                out[:, i] = 2 * math.pi * (s - _screw(e, 0.0)) / e["lead"]
        return out

    def motor_jacobian(self, q: np.ndarray) -> np.ndarray:
        """``∂θs/∂q`` (n×n): motor speeds are ``motor_jacobian(q) @ q̇``."""
        q = np.asarray(q, dtype=float)
        jac = np.zeros((self.n, self.n))
        for i, e in enumerate(self.entries):
            if e["type"] == "ratio":
                jac[i, i] = e["ratio"]
                for j, c in e["couple"]:
                    jac[i, j] -= e["ratio"] * c
            else:
                phi = sum(c * q[j] for j, c in e["angle"])
                d = 2 * math.pi * _screw_slope(e, phi) / e["lead"]
                for j, c in e["angle"]:
                    jac[i, j] += d * c
        return jac

    # -------------------------------------------------------------- motor → joint

    def joint_from_motor(self, theta_s: np.ndarray) -> np.ndarray:
        """Joint coordinates of motor angles (raises ``ValueError`` outside a lever's range)."""
        theta_s = np.asarray(theta_s, dtype=float)
        q = np.empty(self.n)
        for i, e in enumerate(self.entries):
            if e["type"] == "ratio":
                q[i] = theta_s[i] / e["ratio"] + sum(c * q[j] for j, c in e["couple"])
            else:
                s = _screw(e, 0.0) + e["lead"] * theta_s[i] / (2 * math.pi)
                a, b = e["a"], e["b"]
                cos_v = (a * a + b * b - s * s) / (2 * a * b)
                if not -1.0 <= cos_v <= 1.0:
                    raise ValueError(
                        f"joint {i + 1}: motor angle {theta_s[i]:g} rad puts the "
                        "screw outside its lever's reach"
                    )
                phi = math.acos(cos_v) - e["phi0"]
                own = dict(e["angle"])[i]
                q[i] = (phi - sum(c * q[j] for j, c in e["angle"] if j != i)) / own
        return q

    def joint_jacobian(self, q: np.ndarray) -> np.ndarray:
        """``∂q/∂θs`` at joint coordinates ``q`` (the inverse of :meth:`motor_jacobian`)."""
        return np.linalg.inv(self.motor_jacobian(q))


def _screw(e: dict, phi: float) -> float:
    a, b = e["a"], e["b"]
    return math.sqrt(a * a + b * b - 2 * a * b * math.cos(phi + e["phi0"]))


def _screw_slope(e: dict, phi: float) -> float:
    """``ds/dφ``."""
    return e["a"] * e["b"] * math.sin(phi + e["phi0"]) / _screw(e, phi)
