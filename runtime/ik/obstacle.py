"""Obstacle avoidance (seed 4.2.4, eq. 47–49).

With the critical point ``x_k`` on the arm (closest to the obstacle, moving with link
``l``), the unit escape direction ``v`` (obstacle → arm), the distance ``R`` and the
point Jacobian ``J_k = ∂x_k/∂θ`` (3×n), the seed minimises::

    a_obst·½(αv − J_kΔθ)ᵀ(αv − J_kΔθ) + a_conf·½ΔθᵀWΔθ,      α = c/R

``αv`` is the displacement the critical point should make in this IPO cycle; it grows
as the arm approaches. Expanded (dropping the constant): ``g = −a_obst·α·J_kᵀv``,
``H = a_obst·J_kᵀJ_k + a_conf·W`` (eq. 49). Written, like the other criteria, for the
cycle displacement ``δ = Σ + Δθ`` (equal to the seed's form in the first iteration)::

    g = −a_obst·J_kᵀ(αv − J_kΣ),    H = a_obst·J_kᵀJ_k

The ``a_conf·W`` part is :class:`~irlc.runtime.ik.weighted.WeightedDisplacement` with
``scale = a_conf``, added once however many obstacles are active (for one obstacle this
is exactly eq. 49; several obstacles add their ``a_obst`` terms).

Choices the seed leaves open (defaults in :class:`~irlc.runtime.ik.params.ObstacleParams`):

* ``c = 1e-3 m²`` — the seed's ``α = 1000/R`` in millimetres (see ``params``);
* activation: a smooth weight ``β(R)`` multiplies ``a_obst``: 1 below
  ``R_on = activation·(1 − ramp)``, 0 beyond ``activation``, ``smoothstep`` between,
  so far obstacles contribute nothing and switching on is continuous;
* ``R`` is floored at ``min_distance`` (contact or penetration keeps a finite, maximal
  push);
* ``x_k``, ``v``, ``R``, ``J_k`` are computed once per cycle at ``θ_s``.
"""

from __future__ import annotations

import numpy as np
from irlc.runtime.ik.params import ObstacleParams
from irlc.runtime.ik.state import IterationState
from irlc.runtime.model.bodies import Bodies, bodies_of
from irlc.runtime.model.kinematics import Kinematics


def activation_weight(distance: float, params: ObstacleParams) -> float:
    """``β(R)``: 1 near, 0 far, smoothstep in between."""
    far = params.activation
    near = far * (1.0 - params.ramp)
    if distance >= far:
        return 0.0
    if distance <= near:
        return 1.0
    s = (far - distance) / (far - near)
    return s * s * (3.0 - 2.0 * s)


class ObstacleTerm:
    """``(g, H)`` of one critical point."""

    def __init__(
        self,
        jac: np.ndarray,
        direction: np.ndarray,
        distance: float,
        params: ObstacleParams,
        name: str = "",
    ):
        self.name = name
        self.jac = jac
        self.weight = params.a_obst * activation_weight(distance, params)
        self.alpha = params.c / max(distance, params.min_distance)
        self.push = self.alpha * direction
        self.jtj = jac.T @ jac

    def accumulate(self, state: IterationState, g: np.ndarray, H: np.ndarray) -> None:
        if self.weight == 0.0:
            return
        residual = self.push - self.jac @ state.sigma
        g -= self.weight * (self.jac.T @ residual)
        H += self.weight * self.jtj


def obstacle_terms(
    bodies: Bodies | Kinematics, frames: np.ndarray, obstacles, params: ObstacleParams
):
    """Terms for the active obstacles (one per obstacle, its closest robot part);
    obstacles beyond the activation distance are left out. ``bodies``: the chain's links
    in the world (:mod:`~irlc.runtime.model.bodies`; a ``Kinematics`` stands for its one
    robot) and ``frames`` their world frames."""
    bodies = bodies_of(bodies)
    out = []
    for cp in bodies.critical_points(frames, obstacles):
        if cp.distance >= params.activation:
            continue
        jac = bodies.jacobian(frames, cp.link, cp.robot_point)[:3]
        out.append(ObstacleTerm(jac, cp.direction, cp.distance, params, cp.name))
    return out
