"""Motion repeatability: stay close to a reference configuration (seed 4.2.2, eq. 46).

CYCLIC (reference ``θ⁰`` = the configuration at CYCLICSTART) and WITH RECONFIGURATION
``k`` (reference ``θ⁰ = k`` for one statement) minimise ``½(θ − θ⁰)ᵀW(θ − θ⁰)`` with
``θ = θ_k + Δθ``::

    ½(Δθ + θ_k − θ⁰)ᵀW(Δθ + θ_k − θ⁰) = ½ΔθᵀWΔθ + (θ_k − θ⁰)ᵀWΔθ + const
    →  g = W(θ_k − θ⁰),  H = W

A closed TCP path then ends in the configuration it started from: each cycle picks the
configuration on the task manifold nearest (in W) to ``θ⁰`` that the joint box allows,
a function of the pose alone once the box is not binding.

Under ``R_CRITERION := 'ENERGY'`` the distance to ``θ⁰`` is measured in the criterion's
metric at the reference, ``G = Ĝ(θ⁰)`` (:class:`MetricReference`, ``g = G(θ_k − θ⁰)``,
``H = G``; :mod:`~irlc.runtime.ik.energy`): a constant ``G`` while ``θ⁰`` is (CYCLIC), so
the configuration is still a function of the pose and a closed path still closes. Under
MVR ``W`` is the MVR weights (:mod:`~irlc.runtime.ik.mvr`).
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


class MetricReference:
    """``g = G(θ_k − θ⁰)``, ``H = G`` for a symmetric positive definite metric ``G``
    (module doc)."""

    def __init__(self, metric: np.ndarray, reference: np.ndarray):
        self.metric = metric
        self.reference = np.asarray(reference, dtype=float)

    def accumulate(self, state: IterationState, g: np.ndarray, H: np.ndarray) -> None:
        g += self.metric @ (state.theta - self.reference)
        H += self.metric
