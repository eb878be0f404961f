"""Default criterion: minimum weighted joint displacement (seed 4.2, default option).

The seed's criterion for one Newton iteration is ``½ΔθᵀWΔθ`` (``g = 0``, ``H = W``),
``W = diag(w)`` with the robot's redundancy weights (larger near the base, so base joints
move least). Written for the *cycle* displacement ``δ = Σ + Δθ`` it reads::

    ½(Σ + Δθ)ᵀW(Σ + Δθ)  →  g = W·Σ,  H = W        (scaled by ``scale``)

which equals the seed's form in the first iteration (``Σ = 0``) and makes later
iterations minimise the same criterion instead of restarting it; the converged cycle is
the W-closest configuration to ``θ_s`` on the task manifold, independent of how many
iterations it took. With obstacle avoidance on, this term is the seed's
``a_conf·½ΔθᵀWΔθ`` (``scale = a_conf``).
"""

from __future__ import annotations

import numpy as np
from irlc.runtime.ik.state import IterationState


class WeightedDisplacement:
    def __init__(self, weights: np.ndarray, scale: float = 1.0):
        self.w = scale * np.asarray(weights, dtype=float)

    def accumulate(self, state: IterationState, g: np.ndarray, H: np.ndarray) -> None:
        g += self.w * state.sigma
        H.flat[:: H.shape[0] + 1] += self.w

    def gradient(self, state: IterationState, out: np.ndarray) -> np.ndarray:
        """``g`` alone (``H = diag(w)`` is constant): the diagonal fast path."""
        return np.multiply(self.w, state.sigma, out=out)
