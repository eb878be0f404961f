"""FREEZE: hold selected joints at fixed values (seed 4.2.5).

The seed adds the constraint function ``Φ(θ) = [θ_i − θ_i⁰]`` for the frozen joints ``i``,
i.e. equality rows ``e_iᵀΔθ = −(θ_k,i − θ_i⁰)`` appended to ``JΔθ = −F``. Equivalent and
cheaper (used by the Newton loop): take the frozen joints out of the variables. Their
step is fixed, ``Δθ_i = θ_i⁰ − θ_k,i`` (zero once they sit at ``θ_i⁰``), its effect on
the task moves to the right-hand side (``F ← F + J_frozen·Δθ_frozen``) and the QP runs
over the free joints only. Both forms have the same solution set; the tests check it.

Freezing so many joints that fewer free joints remain than task rows, or that the free
columns of ``J`` lose rank, makes the task impossible: :class:`FreezeError` says so.
"""

from __future__ import annotations

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime.errors import RunFailure
from irlc.runtime.model.naming import JointNaming, naming_or_default


class FreezeError(RunFailure):
    """Too many joints frozen for the task (cause ``freeze``)."""

    def __init__(self, message: str, **kwargs):
        kwargs.setdefault("cause", "freeze")
        super().__init__(message, **kwargs)


class FrozenJoints:
    """``frozen`` maps 0-based joint index → held value (SI)."""

    def __init__(self, n: int, frozen: dict[int, float] | None = None):
        self.n = n
        self.values = dict(sorted((frozen or {}).items()))
        for j in self.values:
            if not 0 <= j < n:
                raise ValueError(f"frozen joint index {j} out of range 0..{n - 1}")
        self.frozen = np.array(list(self.values), dtype=int)
        self.targets = np.array(list(self.values.values()), dtype=float)
        mask = np.ones(n, dtype=bool)
        mask[self.frozen] = False
        self.free = np.flatnonzero(mask)

    def __bool__(self) -> bool:
        return bool(self.values)

    def step(self, theta: np.ndarray) -> np.ndarray:
        """Fixed step of the frozen joints, ``θ⁰ − θ_k`` (same order as ``frozen``)."""
        return self.targets - theta[self.frozen]

    # --- the equality-row form (Φ) used for checks and by full (non-compact) solvers ---
    def phi(self, theta: np.ndarray) -> np.ndarray:
        """``Φ(θ) = θ_frozen − θ⁰``."""
        return theta[self.frozen] - self.targets

    def phi_jacobian(self) -> np.ndarray:
        """``∂Φ/∂θ``: rows ``e_iᵀ``."""
        return np.eye(self.n)[self.frozen]

    def check_task(
        self, model: RobotModel, task_rows: int, naming: JointNaming | None = None
    ) -> None:
        """Raise :class:`FreezeError` if fewer free joints than task rows remain."""
        if self.free.size < task_rows:
            raise FreezeError(self.describe_impossible(model, task_rows, naming))

    def describe_impossible(
        self, model: RobotModel, task_rows: int, naming: JointNaming | None = None
    ) -> str:
        naming = naming_or_default(naming, model)
        names = naming.labels(self.frozen.tolist())
        return (
            f"FREEZE of joints {names} leaves {self.free.size} free joints, which cannot "
            f"follow the {task_rows}-dimensional task at this configuration"
        )
