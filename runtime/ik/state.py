"""What the criteria see in one Newton iteration of one IPO cycle.

``theta`` is the iterate ``θ_k``, ``start`` the configuration ``θ_s`` at the start of the
cycle and ``sigma = θ_k − θ_s`` the cycle displacement so far. Criteria add their
``(g, H)`` terms in full joint space (``n``); frozen joints are removed afterwards.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np


@dataclass
class IterationState:
    theta: np.ndarray
    start: np.ndarray
    sigma: np.ndarray
    iteration: int = 0


class Criterion(Protocol):
    """A term ``gᵀΔθ + ½ΔθᵀHΔθ`` of the cost; ``accumulate`` adds it in place."""

    def accumulate(self, state: IterationState, g: np.ndarray, H: np.ndarray) -> None: ...
