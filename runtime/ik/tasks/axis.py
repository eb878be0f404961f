"""A body axis held along a world direction: "the tool points vertically down".

Seed 001, ch. 3.2 (cooperating robots, welding): the technological tip of robot II must
point vertically, so two of the coordinates of ``x_II = f_II(θ_II)`` that give its
orientation stay constant — two rows ``Φ(θ_II) = 0`` stacked under the task, whose
Jacobian rows are the matching rows of ``J_II``. The seed's two "orientation angles" depend
on the angle convention; written convention-free, with ``a(θ)`` the axis (unit, world) of
body link ``link`` that should lie along the world direction ``d``, and ``(u, v)`` an
orthonormal pair perpendicular to ``d``::

    F = [ u·a ; v·a ]                  (rad: zero exactly when a ∥ d, F ≈ the tilt angles)
    J = [ (a × u)ᵀ ; (a × v)ᵀ ] · J_ω    (ȧ = ω × a and u·(ω × a) = ω·(a × u))

``J_ω`` the angular rows of the link's Jacobian (3×n, the chain's columns). ``F`` is also
zero for ``a = −d``: a Newton step from near ``d`` stays at ``d``. :meth:`AxisTask.
vertical` is the seed's welding condition on a chain's tool (``Chain.tool_body``).
"""

from __future__ import annotations

import numpy as np
from irlc.runtime.model.chain import Chain, ChainPoint


class AxisTask:
    """Axis ``axis`` (in the frame of body link ``link``) along the world ``direction``:
    two orientation rows (module docstring)."""

    kind = "orientation"
    size = 2

    def __init__(self, link: int, axis, direction=(0.0, 0.0, 1.0), name: str = "axis"):
        self.name = name
        self.link = int(link)
        self.axis = _unit(axis)
        d = _unit(direction)
        helper = np.eye(3)[int(np.argmin(np.abs(d)))]  # the world axis least along d
        u = _unit(np.cross(d, helper))
        self.uv = np.array([u, np.cross(d, u)])  # (u, v): orthonormal, ⟂ d

    @classmethod
    def vertical(cls, chain: Chain, name: str = "vertical") -> AxisTask:
        """The chain's tool z axis vertical in the world (the seed's welding condition)."""
        link, tool = chain.tool_body()
        return cls(link, tool[:3, 2], (0.0, 0.0, 1.0), name)

    def _world_axis(self, at: ChainPoint) -> np.ndarray:
        return at.world[self.link][:3, :3] @ self.axis

    def residual(self, at: ChainPoint) -> np.ndarray:
        return self.uv @ self._world_axis(at)

    def jacobian(self, at: ChainPoint) -> np.ndarray:
        a = self._world_axis(at)
        origin = at.world[self.link][:3, 3]
        omega = at.chain.bodies.jacobian(at.world, self.link, origin)[3:]
        return np.cross(a, self.uv) @ omega


def _unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)
