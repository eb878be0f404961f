"""Kinetic-energy criterion, ``R_CRITERION := 'ENERGY'`` (seed chapter 7).

The links' kinetic energy ``E = ½ θ̇ᵀ M(θ) θ̇`` (``M`` the joint-space inertia matrix of
the links from the robot file's ``[[inertials]]``, :meth:`Dynamics.link_mass_matrix`;
motor rotors are not included) is brought to the seed's quadratic form (40a) (seed eq. 40)
as the seed does it, with the *mean* joint speed over the IPO cycle ``Δt``: in iteration ``k``
the cycle has moved the joints by ``Σ = θ_k − θ_s`` so far, and the step ``Δθ`` makes it
``δ = Σ + Δθ``, so ``θ̇ = (Δθ + Σ)/Δt`` and, with ``M`` held at ``M(θ_s)`` for the cycle
(refreshed every IPO cycle)::

    E = ½ (Δθ + Σ)ᵀ M (Δθ + Σ) / Δt²
      = ½ Δθᵀ (M/Δt²) Δθ + (MΣ/Δt²)ᵀ Δθ + ½ ΣᵀMΣ/Δt²        (the last term is constant)
    →  g = M Σ / Δt²,   H = M / Δt²                              (the seed's g and H)

In the first iteration without a warm start (``Σ = 0``) this is the seed's literal
form ``g = 0, H = M/Δt²``; like every criterion here it is written on the cycle
displacement (the whole-cycle criterion, docs/ik.md), so the converged cycle is the
configuration on the task manifold with the least kinetic energy of the cycle's mean
speed — the inertia-weighted pseudoinverse solution, which minimises ``E`` for a given
TCP speed. It is a local (per-cycle) criterion: it does not minimise the integral of
``E`` over a path (docs/ik.md, "ENERGY and MVR: where they do not help").

**Scale.** A positive factor on ``g`` and ``H`` together does not change the minimiser,
so the cycle alone is the same for any factor. The factor matters only where the
criterion is added to other terms (the obstacles' ``a_obst``, the CYCLIC pull), whose
weights were chosen against ``W``. The criterion is therefore used as::

    Ĝ(θ) = M(θ) · Σw / tr M(θ),    g = Ĝ(θ_s) Σ,   H = Ĝ(θ_s)

— the seed's ``g`` and ``H`` times ``κ = Δt²·Σw/tr M(θ_s) > 0`` (``Σw`` the sum of the
robot's redundancy weights), so that ``Ĝ`` has the trace of ``W`` and ``a_conf``/``a_obst``
weigh it as they weigh ``W`` (:mod:`~irlc.runtime.ik.criteria` combines them).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from irlc.lang.signature import criterion_problem
from irlc.robots.model import RobotModel
from irlc.runtime.errors import RunFailure
from irlc.runtime.ik.state import IterationState
from irlc.runtime.model.dynamics import Dynamics


class EnergyNeedsInertia(RunFailure):
    """``R_CRITERION := 'ENERGY'`` on a chain whose links lack inertial data (the message
    names what is missing: :attr:`RobotModel.missing_inertia`)."""


class InertiaMetric:
    """``Ĝ(θ) = M(θ)·Σw/tr M(θ)`` of one chain's links (module doc); raises
    :class:`EnergyNeedsInertia` when a robot's inertials cannot give ``M``.

    ``robots`` are the chain's robots — each one's model and the chain column of each of
    its joints (:meth:`Chain.robot_columns`; default: ``model`` itself). Robots that move
    together (two cooperating robots as one chain) carry their own links, so the chain's
    kinetic energy is the sum of theirs: ``M`` is block-diagonal, robot ``r``'s
    ``M_r(θ_r)`` at its columns (a column taken in reverse by the chain is the same joint
    variable, so ``M_r`` keeps its own order there)."""

    def __init__(
        self,
        model: RobotModel,
        weights: np.ndarray,
        robots: Sequence[tuple[RobotModel, np.ndarray]] | None = None,
    ):
        robots = robots or ((model, np.arange(model.n)),)
        for robot, _ in robots:
            problem = criterion_problem("ENERGY", robot)
            if problem is not None:
                raise EnergyNeedsInertia(problem)
        self.n = model.n
        # no rotor inertia: the links' M
        self.parts = [(Dynamics(r), np.asarray(c, dtype=int)) for r, c in robots]
        one = len(self.parts) == 1 and np.array_equal(self.parts[0][1], np.arange(self.n))
        self.dynamics = self.parts[0][0] if one else None  # the compiled kernel's packed data
        self.weight_sum = float(np.sum(weights))

    def mass_matrix(self, q: np.ndarray) -> np.ndarray:
        """``M(θ)``: the links' inertia matrix of the chain (block-diagonal over robots)."""
        if self.dynamics is not None:
            return self.dynamics.link_mass_matrix(q)
        m = np.zeros((self.n, self.n))
        for dynamics, columns in self.parts:
            m[np.ix_(columns, columns)] = dynamics.link_mass_matrix(q[columns])
        return m

    def __call__(self, q: np.ndarray) -> np.ndarray:
        m = self.mass_matrix(q)
        return m * (self.weight_sum / float(np.trace(m)))


class KineticEnergy:
    """``(g, H)`` of the cycle's kinetic energy: ``g = s·ĜΣ``, ``H = s·Ĝ`` with ``Ĝ`` the
    metric at ``θ_s`` (:class:`InertiaMetric`) and ``s`` the weight of the term (1, or
    ``a_conf`` beside obstacles)."""

    def __init__(self, metric: np.ndarray, scale: float = 1.0):
        self.metric = metric if scale == 1.0 else scale * metric

    def accumulate(self, state: IterationState, g: np.ndarray, H: np.ndarray) -> None:
        g += self.metric @ state.sigma
        H += self.metric


def seed_terms(m: np.ndarray, sigma: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """The seed's ``g = MΣ/Δt²`` and ``H = M/Δt²`` (for tests: the criterion's terms are
    these times ``κ``, module doc)."""
    return m @ sigma / dt**2, m / dt**2
