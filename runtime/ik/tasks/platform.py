"""A frame of the chain follows its own path: the mobile robot's platform task.

Seed 001, ch. 3.2 (mobile robots): while the TCP follows ``x(t)``, the platform moves
along its own path ``x_platform(t)``; with ``f_platform(θ_a)`` the forward kinematics of
the platform (its joints ``θ_a`` only) the condition is::

    Φ(θ_a) = f_platform(θ_a) − x_platform(s) = 0

and together with ``f(θ_a, θ_b) = x`` it is the seed's system ``[x; 0] = [f; Φ]``, whose
derivative has the block form ``[J_a J_b; J_platform 0]``. Here ``f_platform`` is the
position of a point ``p`` fixed in body link ``link`` (the frame after the platform's
joints: mobile8's link 2, after ``X`` and ``Y``), in the world, on the coordinates
``coords`` (``0 1 2`` = x y z)::

    F = [p(θ)]_coords − target        (m)
    J = [J_p(θ)]_coords               (the point Jacobian of p: 3×n, linear rows)

``J_p`` has non-zero columns only for the joints before ``link`` — ``θ_a``, as in the
seed's block form. ``target`` is ``x_platform(s)`` of the cycle: the caller sets it before
each cycle (the path parameter ``s`` of the TCP's path, so the platform is "in step").
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from irlc.runtime.model.chain import ChainPoint


class PlatformTask:
    """``Φ = f_platform(θ_a) − x_platform(s)`` (module docstring); rows: ``coords``."""

    kind = "position"

    def __init__(
        self,
        link: int,
        coords: Sequence[int] = (0, 1),
        point: np.ndarray | None = None,
        target: np.ndarray | None = None,
        name: str = "platform",
    ):
        self.name = name
        self.link = int(link)
        self.coords = np.array(coords, dtype=int)
        self.size = int(self.coords.size)
        self.local = np.zeros(3) if point is None else np.asarray(point, dtype=float)
        self.target = None if target is None else np.asarray(target, dtype=float)

    def position(self, at: ChainPoint) -> np.ndarray:
        """``p(θ)`` in the world (all three coordinates)."""
        frame = at.world[self.link]
        return frame[:3, :3] @ self.local + frame[:3, 3]

    def residual(self, at: ChainPoint) -> np.ndarray:
        if self.target is None:
            raise ValueError(f"task {self.name}: no target set for this cycle")
        return self.position(at)[self.coords] - self.target

    def jacobian(self, at: ChainPoint) -> np.ndarray:
        jac = at.chain.bodies.jacobian(at.world, self.link, self.position(at))
        return jac[self.coords]
