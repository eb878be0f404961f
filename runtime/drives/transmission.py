"""Transmission: joint ↔ motor coordinates of the driven axes.

With the motor map ``θ_m = f(q)`` (``irlc.runtime.model.motor_maps``, built from the robot
file's ``[transmission]``) and its Jacobian ``K(q) = ∂f/∂q`` (rows of the driven axes)::

    ω_m = K q̇,    τ_joint = Kᵀ τ_m,    rotor inertia (joint side) = Kᵀ diag(J_m) K

Three cases, fastest first:

* plain ratios ``i`` (``K`` diagonal): ``θ_m = i·q``, rotor ``J_m·i²`` on the diagonal;
* linear couplings (``ratio`` rows with ``couple``, the L-1 wrist): ``K`` constant;
* screw levers (IRb-6 A2/A3): ``f`` non-linear, ``K(q)`` evaluated each step, vectorised
  over the lever rows (``φ = C q``, ``s = √(a² + b² − 2ab cos(φ + φ0))``,
  ``θ_m = 2π (s − s(0)) / lead``, ``K = (2π/lead)·ab sin(φ + φ0)/s · C``; the same maps as
  :class:`irlc.runtime.model.motor_maps.MotorMap`, tested against it).

Without a ``[transmission]`` table the ratios come from ``[drives] ratio``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime.drives.params import DriveParams

# columns of TransmissionData.lever
LEVER_SQ, LEVER_AB2, LEVER_PHI0, LEVER_GAIN, LEVER_S0 = range(5)


@dataclass(frozen=True)
class TransmissionData:
    """The motor map of the driven axes as packed, read-only arrays (what compiled
    kernels take; :meth:`Transmission.data`)::

        θ_m = L q,   then for each screw-lever row r (driven axis ``rows[r]``):
        φ_r = C_r q,  s_r = √(sq_r − ab2_r·cos(φ_r + φ0_r)),  θ_m[rows[r]] = gain_r (s_r − s0_r)

    ``linear`` ``L`` (driven × n: plain ratios on the diagonal, linear couplings, or the
    ratio rows of a lever transmission), ``rows`` (levers,), ``angle`` ``C``
    (levers × n) and ``lever`` (levers × 5: columns ``LEVER_SQ … LEVER_S0``: ``a² + b²``,
    ``2ab``, ``φ0``, ``2π/lead``, ``s(0)``). No levers: ``rows``, ``angle`` and ``lever``
    have zero rows, and ``L`` is the constant ``K``."""

    linear: np.ndarray
    rows: np.ndarray
    angle: np.ndarray
    lever: np.ndarray


def _frozen(a: np.ndarray, dtype=float) -> np.ndarray:
    out = np.array(a, dtype=dtype, order="C")
    out.flags.writeable = False
    return out


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
        from irlc.runtime.model.motor_maps import MotorMap

        self.map = MotorMap.from_model(model)
        if all(r.get("type") == "ratio" for r in table):
            self.matrix = self.map.motor_jacobian(np.zeros(self.n))[self.axes]
        else:
            self._levers(rows)
        self.notes.append("transmission: motor maps with coupled or non-linear joints")

    def _levers(self, rows: list[dict]) -> None:
        """Constant arrays of the vectorised screw-lever map (driven rows only)."""
        m = len(rows)
        self._lin = np.zeros((m, self.n))  # the linear (ratio) rows of K
        lever = [a for a, r in enumerate(rows) if r["type"] != "ratio"]
        self._rows = np.array(lever, dtype=int)
        self._coef = np.zeros((len(lever), self.n))  # φ = C q
        for a, r in enumerate(rows):
            if r["type"] == "ratio":
                j = self.axes[a]
                self._lin[a, j] = r["ratio"]
                for i, c in r["couple"]:
                    self._lin[a, i] -= r["ratio"] * c
        for row, a in enumerate(lever):
            for j, c in rows[a]["angle"]:
                self._coef[row, j] += c
        pick = [rows[a] for a in lever]
        self._a = np.array([r["a"] for r in pick])
        self._b = np.array([r["b"] for r in pick])
        self._phi0 = np.array([r["phi0"] for r in pick])
        self._gain = 2.0 * np.pi / np.array([r["lead"] for r in pick])
        self._ab2 = 2.0 * self._a * self._b
        self._sq = self._a**2 + self._b**2
        self._s0 = np.sqrt(self._sq - self._ab2 * np.cos(self._phi0))
        # scatter of the lever rows into θ_m (m × levers) and into K, flattened (levers × m·n)
        self._scatter = np.zeros((m, len(lever)))
        self._scatter[self._rows, np.arange(len(lever))] = 1.0
        self._k_rows = np.einsum("ar,rj->raj", self._scatter, self._coef).reshape(len(lever), -1)
        self._lin_flat = self._lin.ravel()
        self._dk_gain = self._gain * 0.5 * self._ab2

    def _lever_motor(self, q: np.ndarray) -> np.ndarray:
        out = q @ self._lin.T
        s = np.sqrt(self._sq - self._ab2 * np.cos(q @ self._coef.T + self._phi0))
        out[..., self._rows] = self._gain * (s - self._s0)
        return out

    def motor_and_jacobian(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(θ_m, K(q))`` in one pass (the screw levers share ``cos``, ``sin`` and ``s``)."""
        if self.map is None or self.matrix is not None:
            return self.to_motor(q), self.jacobian(q)
        v = self._coef @ q + self._phi0
        s = np.sqrt(self._sq - self._ab2 * np.cos(v))
        theta = self._lin @ q + self._scatter @ (self._gain * (s - self._s0))
        k = (self._lin_flat + (self._dk_gain * np.sin(v) / s) @ self._k_rows).reshape(
            self._lin.shape
        )
        return theta, k

    def _lever_jacobian(self, q: np.ndarray) -> np.ndarray:
        v = self._coef @ q + self._phi0
        s = np.sqrt(self._sq - self._ab2 * np.cos(v))
        k = self._lin.copy()
        k[self._rows] = (self._gain * 0.5 * self._ab2 * np.sin(v) / s)[:, None] * self._coef
        return k

    @property
    def data(self) -> TransmissionData:
        """The packed motor map (:class:`TransmissionData`), built once."""
        cached = getattr(self, "_data", None)
        if cached is not None:
            return cached
        m = len(self.axes)
        lin, rows = np.zeros((m, self.n)), np.zeros(0, dtype=np.int64)
        angle, lever = np.zeros((0, self.n)), np.zeros((0, 5))
        if self.diagonal:
            lin[np.arange(m), self.axes] = self.ratio
        elif self.matrix is not None:
            lin[:] = self.matrix
        else:
            lin[:] = self._lin
            rows, angle = self._rows, self._coef
            lever = np.stack([self._sq, self._ab2, self._phi0, self._gain, self._s0], 1)
        self._data = TransmissionData(
            _frozen(lin), _frozen(rows, np.int64), _frozen(angle), _frozen(lever)
        )
        return self._data

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
        return self._lever_motor(q)

    def jacobian(self, q: np.ndarray) -> np.ndarray:
        """``K(q)``: ``(driven, n)``."""
        if self.map is None:
            out = np.zeros((len(self.axes), self.n))
            out[np.arange(len(self.axes)), self.axes] = self.ratio
            return out
        if self.matrix is not None:
            return self.matrix
        return self._lever_jacobian(q)

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
