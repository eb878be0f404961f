"""A small convex-QP interface with dual active-set backends.

Problem (all matrices dense, float64)::

    minimise   ½ zᵀ H z + gᵀ z
    subject to A z ≥ b          (inequality rows)
               E z = e          (optional equality rows)

``H`` must be symmetric positive definite (both backends are dual methods that
factor ``H``). The result reports ``status`` (``"optimal"`` or ``"infeasible"``),
the indices of the active inequality rows and their multipliers (``λ ≥ 0`` with
``H z + g = Aᵀλ + Eᵀμ``).

Backends:

* :class:`QuadprogSolver` — Goldfarb–Idnani [Goldfarb & Idnani 1983], the method the seed
  prescribes.
  ``quadprog.solve_qp(G, a, C, b, meq)`` minimises ``½xᵀGx − aᵀx`` s.t. ``Cᵀx ≥ b``
  with the first ``meq`` columns of ``C`` equalities, so ``a = −g``, ``C = [Eᵀ Aᵀ]``.
  It raises ``ValueError`` for inconsistent constraints and non-PD ``G``; both become
  a result with ``status="infeasible"`` / ``"error"`` here, never an exception.
* :class:`DaqpSolver` — DAQP [Arnström et al. 2022], another dual active-set solver,
  only if ``daqp`` is importable; used for side-by-side benchmarks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import quadprog

OPTIMAL = "optimal"
INFEASIBLE = "infeasible"
ERROR = "error"  # e.g. H not positive definite

_EMPTY_INT = np.zeros(0, dtype=int)
_EMPTY = np.zeros(0)


@dataclass
class QPResult:
    z: np.ndarray
    status: str
    active: np.ndarray  # indices of active inequality rows of A
    multipliers: np.ndarray  # λ of the active rows, same order as ``active``
    message: str = ""

    @property
    def ok(self) -> bool:
        return self.status == OPTIMAL


class QuadprogSolver:
    """Goldfarb–Idnani dual active-set method via ``quadprog``."""

    name = "quadprog"

    def solve(
        self,
        H: np.ndarray,
        g: np.ndarray,
        A: np.ndarray | None = None,
        b: np.ndarray | None = None,
        E: np.ndarray | None = None,
        e: np.ndarray | None = None,
    ) -> QPResult:
        # scale the cost so max diag(H) = 1: same minimiser, multipliers scaled back;
        # quadprog's feasibility test is absolute and fails for very large costs
        scale = 1.0 / float(np.max(np.abs(np.diag(H)))) if H.shape[0] else 1.0
        H, g = H * scale, g * scale
        meq = 0 if E is None else E.shape[0]
        if meq:
            C = np.vstack((E, A)).T if A is not None else E.T
            rhs = np.concatenate((e, b)) if A is not None else e
        elif A is not None and A.shape[0]:
            C, rhs = A.T, b
        else:
            C, rhs = None, None
        try:
            if C is None:
                z = quadprog.solve_qp(H, -g)[0]
                return QPResult(z, OPTIMAL, _EMPTY_INT, _EMPTY)
            z, _, _, _, lagr, iact = quadprog.solve_qp(H, -g, np.ascontiguousarray(C), rhs, meq)
        except ValueError as exc:
            text = str(exc)
            status = INFEASIBLE if "inconsistent" in text else ERROR
            return QPResult(np.full(H.shape[0], np.nan), status, _EMPTY_INT, _EMPTY, text)
        rows = iact[iact > meq] - 1 - meq  # quadprog's iact is 1-based; keep inequality rows
        return QPResult(z, OPTIMAL, rows, lagr[rows + meq] / scale)

    def solve_ct(self, H, g, C, b) -> QPResult:
        """Hot path: inequalities only, given transposed (``C = Aᵀ``, columns are rows of
        ``A``), as the compact form builds them; quadprog is called directly."""
        scale = 1.0 / _max_diagonal(H)
        try:
            z, _, _, _, lagr, iact = quadprog.solve_qp(H * scale, g * -scale, C, b, 0)
        except ValueError as exc:
            text = str(exc)
            status = INFEASIBLE if "inconsistent" in text else ERROR
            return QPResult(np.full(H.shape[0], np.nan), status, _EMPTY_INT, _EMPTY, text)
        if not np.count_nonzero(iact):  # nothing active (the common cycle): no indexing
            return QPResult(z, OPTIMAL, _EMPTY_INT, _EMPTY)
        rows = iact[iact > 0] - 1
        return QPResult(z, OPTIMAL, rows, lagr[rows] / scale)


def _max_diagonal(H: np.ndarray) -> float:
    """``max(diag H)`` as ``H.diagonal().max()`` (NaN when an entry is NaN; H's diagonal
    is ≥ 0, so the sum is NaN only then), with builtins: a numpy reduction costs more
    than the handful of numbers."""
    d = H.diagonal().tolist()
    return math.nan if math.isnan(sum(d)) else max(d)


class DaqpSolver:
    """DAQP dual active-set solver (optional; benchmarks only)."""

    name = "daqp"

    def __init__(self):
        import daqp

        self._daqp = daqp

    def solve_ct(self, H, g, C, b) -> QPResult:
        return self.solve(H, g, C.T, b)

    def solve(self, H, g, A=None, b=None, E=None, e=None) -> QPResult:
        n = H.shape[0]
        blocks = [m for m in (E, A) if m is not None and m.shape[0]]
        if not blocks:
            return QuadprogSolver().solve(H, g)
        meq = 0 if E is None else E.shape[0]
        M = np.vstack(blocks) if len(blocks) > 1 else blocks[0]
        lower = np.concatenate([v for v in (e, b) if v is not None and v.shape[0]])
        upper = np.full(lower.shape, 1e30)
        upper[:meq] = lower[:meq]
        sense = np.zeros(lower.shape[0], dtype=np.int32)
        sense[:meq] = 5
        z, _, flag, info = self._daqp.solve(
            np.ascontiguousarray(H), g, np.ascontiguousarray(M), upper, lower, sense
        )
        if flag < 0:
            status = INFEASIBLE if flag in (-1, -3) else ERROR
            return QPResult(np.full(n, np.nan), status, _EMPTY_INT, _EMPTY, f"daqp exit {flag}")
        lam = np.asarray(info.get("lam", np.zeros(lower.shape[0])))[meq:]
        rows = np.flatnonzero(np.abs(lam) > 0.0)
        return QPResult(np.asarray(z), OPTIMAL, rows, np.abs(lam[rows]))


def daqp_available() -> bool:
    try:
        import daqp  # noqa: F401
    except ImportError:
        return False
    return True


def make_solver(name: str = "quadprog"):
    """``"quadprog"`` (default) or ``"daqp"`` (raises ``ImportError`` if not installed)."""
    if name == "quadprog":
        return QuadprogSolver()
    if name == "daqp":
        return DaqpSolver()
    raise ValueError(f"unknown QP solver {name!r} (known: quadprog, daqp)")
