"""Velocity controller: PI on the tachogenerator signal, output saturated (current ref).

    e   = u_ω − ke · ω                        [V]
    u_i = sat_{±U_ref}( kp · e + ki · x ),    ẋ = e

``kp`` is the dimensionless proportional gain and ``ki`` [1/s] the integral gain (the
interpretation of the published table, see ``docs/drives.md``). Anti-windup by
conditional integration: while the output is saturated, ``x`` only integrates errors
that drive it back out of saturation.
"""

from __future__ import annotations

import numpy as np


class VelocityPI:
    def __init__(self, ke, kp, ki, limit, count: int):
        self.ke, self.kp, self.ki, self.limit = ke, kp, ki, limit
        self.x = np.zeros(count)

    def step(self, u_ref, omega, h: float) -> tuple[np.ndarray, np.ndarray]:
        """Current reference (V) and saturation flags; integrates over ``h``."""
        e = u_ref - self.ke * omega
        raw = self.kp * e + self.ki * self.x
        out = np.minimum(np.maximum(raw, -self.limit), self.limit)  # np.clip, cheaper
        sat = out != raw
        if np.count_nonzero(sat):  # conditional integration: freeze when e pushes further out
            self.x += np.where(sat & (np.sign(e) == np.sign(raw)), 0.0, h * e)
        else:
            self.x += h * e
        return out, sat
