"""Motion repeatability: stay close to a reference configuration (seed 4.2.2, eq. 46).

CYCLIC (reference ``θ⁰`` = the configuration at CYCLICSTART) and WITH RECONFIGURATION
``k`` (reference ``θ⁰ = k`` for one statement) minimise ``½(θ − θ⁰)ᵀW(θ − θ⁰)`` with
``θ = θ_k + Δθ``::

    ½(Δθ + θ_k − θ⁰)ᵀW(Δθ + θ_k − θ⁰) = ½ΔθᵀWΔθ + (θ_k − θ⁰)ᵀWΔθ + const
    →  g = W(θ_k − θ⁰),  H = W

A closed TCP path then ends in the configuration it started from: each cycle picks the
configuration on the task manifold nearest (in W) to ``θ⁰`` that the joint box allows,
a function of the pose alone once the box is not binding.
"""

from __future__ import annotations

import numpy as np
from irlc.runtime.ik.state import IterationState


class CyclicReference:
    def __init__(self, weights: np.ndarray, reference: np.ndarray, scale: float = 1.0):
        self.w = scale * np.asarray(weights, dtype=float)
        self.reference = np.asarray(reference, dtype=float)

    def accumulate(self, state: IterationState, g: np.ndarray, H: np.ndarray) -> None:
        g += self.w * (state.theta - self.reference)
        H.flat[:: H.shape[0] + 1] += self.w

    def gradient(self, state: IterationState, out: np.ndarray) -> np.ndarray:
        """``g`` alone (``H = diag(w)`` is constant): the diagonal fast path."""
        np.subtract(state.theta, self.reference, out=out)
        out *= self.w
        return out
