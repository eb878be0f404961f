"""Current controller (integrating) with the DC armature, averaged power stage, discretised
exactly.

Controller and armature, state ``x = [i, u]`` (``u`` the armature voltage command)::

    u̇ = kiwzm · (u_i − k·i)
    L di/dt = u − R i − k_s ω

i.e. ``ẋ = A x + B w`` with ``w = [u_i, ω]``::

    A = [[−R/L, 1/L], [−kiwzm·k, 0]],   B = [[0, −k_s/L], [kiwzm, 0]]

With ``w`` held over the step ``h`` (zero-order hold) the update is exact::

    x(h) = Φ x0 + Γ w,            Φ = e^{Ah},  Γ = ∫₀ʰ e^{As} ds B
    x̄    = (Ψ₁ x0 + Ψ₂ B w) / h   (mean over the step: torque and energy use it)

``Φ, Ψ₁ = ∫₀ʰ e^{As}ds, Ψ₂ = ∫₀ʰ (h−s) e^{As} ds`` come from one matrix exponential of
``[[A, I, 0], [0, 0, I], [0, 0, 0]]·h``. So the electrical time constants (L/R ≈ 1 ms)
do not limit the step. The averaged power stage clips ``u`` to ``±U`` and the current
clamp applies ``|i| ≤ i_max`` after the update (both are reported as saturation).
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import expm


class CurrentLoop:
    def __init__(self, R, L, ks, k, kiwzm, h: float):
        m = len(R)
        self.phi = np.empty((m, 2, 2))
        self.gamma = np.empty((m, 2, 2))
        self.mean_x = np.empty((m, 2, 2))
        self.mean_w = np.empty((m, 2, 2))
        big_a = np.zeros((m, 2, 2))
        big_b = np.zeros((m, 2, 2))
        big_a[:, 0, 0], big_a[:, 0, 1], big_a[:, 1, 0] = -R / L, 1.0 / L, -kiwzm * k
        big_b[:, 0, 1], big_b[:, 1, 0] = -ks / L, kiwzm
        z = np.zeros((m, 6, 6))
        z[:, :2, :2], z[:, :2, 2:4], z[:, 2:4, 4:6] = big_a, np.eye(2), np.eye(2)
        e = expm(z * h)  # batched over the axes
        phi, psi1, psi2 = e[:, :2, :2], e[:, :2, 2:4], e[:, :2, 4:6]
        self.phi[:], self.gamma[:] = phi, psi1 @ big_b
        self.mean_x[:], self.mean_w[:] = psi1 / h, psi2 @ big_b / h
        # one (4×4) map per axis: [x_end; x_mean] = big · [x0; w]
        self.big = np.block([[self.phi, self.gamma], [self.mean_x, self.mean_w]])
        self._xw = np.zeros((m, 4))

    @property
    def x(self) -> np.ndarray:
        """State ``[i, u]`` per axis (a view: writes clamp the state)."""
        return self._xw[:, :2]

    @x.setter
    def x(self, value) -> None:
        self._xw[:, :2] = value

    def step(self, u_i, omega):
        """Advance one step; returns the mean state over the step ``(ī, ū)``."""
        xw = self._xw
        xw[:, 2], xw[:, 3] = u_i, omega
        out = np.einsum("aij,aj->ai", self.big, xw)
        xw[:, :2] = out[:, :2]
        return out[:, 2], out[:, 3]
