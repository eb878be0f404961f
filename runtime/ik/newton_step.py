"""One Newton–Raphson step: the compact QP, or the relaxed QP when it has no solution.

Hard step (seed eq. 40, solved in the compact form of :mod:`compact`)::

    min ½ΔθᵀHΔθ + gᵀΔθ   s.t.  JΔθ = −F,   lower ≤ Δθ ≤ upper

It has no solution when ``J`` is (numerically) singular or when the box cuts the affine
set ``JΔθ = −F`` off (abrupt start, unreachable target, too-tight limits). Then the
**relaxed** step moves the task into the cost with a large weight ``ρ`` and keeps the box::

    min ½ΔθᵀHΔθ + gᵀΔθ + ½ρ‖JΔθ + F‖²   s.t.  lower ≤ Δθ ≤ upper
    →  H_r = H + ρJᵀJ,   g_r = g + ρJᵀF

which always has a solution when the box is non-empty (``H`` is positive definite) and
is a damped least-squares step near singularities (``H/ρ`` is the damping). ``ρ`` is
``relax_weight · max(diag H)``. Bounds must be finite (use ±1e30 for "none"). The box
rows are ``[I; −I]`` in both forms, so an active row index ``r`` means joint ``r``
(lower) or ``r − n`` (upper) either way.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from irlc.runtime.ik.compact import CompactBasis, compact_box_qp
from irlc.runtime.ik.qp import QPResult

_BOX_TOL = 1e-12


@dataclass
class StepOutcome:
    dtheta: np.ndarray
    relaxed: bool
    singular: bool
    active: np.ndarray  # active box rows (see module doc)
    multipliers: np.ndarray


class NewtonStep:
    """Solves one step; keeps the compact basis from call to call."""

    def __init__(self, solver, relax_weight: float = 1e6, basis: CompactBasis | None = None):
        self.solver = solver
        self.relax_weight = relax_weight
        self.basis = basis or CompactBasis()
        self._eye_cache: dict[int, np.ndarray] = {}
        self.last_singular = False

    def hard(self, J, F, H, g, lower, upper) -> StepOutcome | None:
        """The compact QP; ``None`` if singular or infeasible (``singular`` noted)."""
        self.last_singular = False
        split = self.basis.split(J, F)
        if split is None:
            self.last_singular = True
            return None
        dtheta_p, N = split
        if N.shape[1] == 0:  # n = m: no redundancy, the box is only checked
            if np.all(dtheta_p >= lower - _BOX_TOL) and np.all(dtheta_p <= upper + _BOX_TOL):
                rows = _touching(dtheta_p, lower, upper)
                return StepOutcome(dtheta_p.copy(), False, False, rows, np.zeros(rows.size))
            return None
        Ht, gt, Ct, bt = compact_box_qp(H, g, dtheta_p, N, lower, upper)
        res: QPResult = self.solver.solve_ct(Ht, gt, Ct, bt)
        if not res.ok:
            return None
        return StepOutcome(dtheta_p + N @ res.z, False, False, res.active, res.multipliers)

    def relaxed(self, J, F, H, g, lower, upper) -> StepOutcome:
        """The relaxed QP (always solvable for a non-empty box)."""
        n = H.shape[0]
        rho = self.relax_weight * float(H.diagonal().max())
        Hr = H + rho * (J.T @ J)
        gr = g + rho * (J.T @ F)
        C = self._box_columns(n)
        b = np.concatenate((lower, -upper))
        res = self.solver.solve_ct(Hr, gr, C, b)
        if not res.ok:
            raise FloatingPointError(f"relaxed QP failed ({res.status}: {res.message})")
        return StepOutcome(res.z, True, self.last_singular, res.active, res.multipliers)

    def solve(self, J, F, H, g, lower, upper) -> StepOutcome:
        return self.hard(J, F, H, g, lower, upper) or self.relaxed(J, F, H, g, lower, upper)

    def _box_columns(self, n: int) -> np.ndarray:
        a = self._eye_cache.get(n)
        if a is None:
            a = np.hstack((np.eye(n), -np.eye(n)))
            self._eye_cache[n] = a
        return a


def _touching(x, lower, upper) -> np.ndarray:
    n = x.shape[0]
    lo = np.flatnonzero(x <= lower + _BOX_TOL)
    hi = np.flatnonzero(x >= upper - _BOX_TOL) + n
    return np.concatenate((lo, hi))
