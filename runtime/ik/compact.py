"""The compact form of the equality-constrained QP (seed eq. 40–41).

Full problem in ``Δθ ∈ Rⁿ`` with ``J`` of shape ``m×n`` (``m ≤ n``, full row rank)::

    min ½ΔθᵀHΔθ + gᵀΔθ   s.t.  JΔθ = −F,  AΔθ ≥ b

Split the columns ``J = [J_m  J_{n−m}]`` with ``J_m`` an invertible ``m×m`` block (the
*basic* joints). Every solution of the equality is ``Δθ = Δθ_p + N z`` with::

    Δθ_p = [ −J_m⁻¹F ; 0 ],    N = [ −J_m⁻¹J_{n−m} ; I_{n−m} ]

(rows in basic / non-basic order), so the problem becomes, in ``z ∈ R^{n−m}``::

    min ½zᵀH̃z + g̃ᵀz   s.t.  Ãz ≥ b̃
    H̃ = NᵀHN,   g̃ = Nᵀ(g + HΔθ_p),   Ã = AN,   b̃ = b − AΔθ_p

For the joint box ``A = [I; −I]``, ``b = [lower; −upper]``: ``Ã = [N; −N]``.

**Choice of the basic columns.** QR with column pivoting of ``J``
(``scipy.linalg.qr(pivoting=True)``) orders the columns by how much new direction each
adds; the first ``m`` form ``J_m``. The basis is kept from cycle to cycle (the compact
problem is an exact reparametrisation for *any* invertible ``J_m``, so the solution does
not depend on the choice — only the rounding does) and re-chosen when it degrades: when
the spread of the LU pivots of ``J_m`` (``max|u_ii| / min|u_ii|``, a cheap lower bound
of its condition number, free with the solve) exceeds ``cond_max``; if even the new
block's exceeds ``singular_cond``, ``J`` is treated as singular.

**Rank.** If ``|R_mm| ≤ rank_tol·|R_11|`` after pivoting, ``J`` has no invertible
``m×m`` block: :meth:`CompactBasis.split` returns ``None`` and the caller solves the
relaxed (damped) problem instead. ``n = m`` needs no QP: ``Δθ = Δθ_p`` is checked
against the box.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg
from scipy.linalg.lapack import dgesv as _dgesv


class CompactBasis:
    """Basic-column choice for ``J`` plus the particular solution and null-space map."""

    def __init__(self, cond_max: float = 1e4, singular_cond: float = 1e10, rank_tol=1e-10):
        self.cond_max = cond_max
        self.singular_cond = singular_cond
        self.rank_tol = rank_tol
        self.columns: np.ndarray | None = None  # pivot order: first m basic
        self.shape: tuple[int, int] = (0, 0)
        self.rechosen = 0  # statistics: how often QR pivoting ran
        self.version = 0  # bumped on every re-choice (callers cache per-basis arrays)
        self.cond = 1.0

    def choose(self, J: np.ndarray) -> bool:
        """Re-choose the basic columns by QR with column pivoting; False if rank < m."""
        m, n = J.shape
        self.rechosen += 1
        self.version += 1
        if m > n:
            self.columns = None
            return False
        r, perm = scipy.linalg.qr(J, mode="r", pivoting=True, check_finite=False)
        self.columns = perm
        self.shape = J.shape
        self._basic, self._free = perm[:m], perm[m:]
        self._N = np.zeros((n, n - m))  # buffers: the identity rows are set once
        self._N[self._free, np.arange(n - m)] = 1.0
        self._dp = np.zeros(n)
        # J[:, perm] and F side by side: [J_m | J_free | F], solved in one LAPACK call
        self._aug = np.empty((m, n + 1))
        self._aug_perm = self._aug[:, :n]
        self._aug_views = (self._aug[:, -1], self._aug[:, :m], self._aug[:, m:])  # made once
        if m == 0:
            return True
        r00 = abs(r[0, 0])
        return r00 > 0.0 and abs(r[m - 1, m - 1]) > self.rank_tol * r00

    def split(self, J: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
        """``(Δθ_p, N)`` in the original column order, or ``None`` when ``J`` is singular.
        Returns views of reused buffers: valid until the next call."""
        blocks = self.blocks(J, F)
        if blocks is None:
            return None
        self._dp[self._basic] = blocks[0]
        self._N[self._basic] = blocks[1]
        return self._dp, self._N

    def blocks(self, J: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
        """``(−J_m⁻¹F, −J_m⁻¹J_free)`` — the basic rows of ``Δθ_p`` and ``N`` — for the
        current basis (re-chosen if it degrades), or ``None`` when ``J`` is singular."""
        if (self.columns is None or self.shape != J.shape) and not self.choose(J):
            return None
        out = self._solve(J, F, self.cond_max)
        if out is None:  # degraded basis: re-choose once
            if not self.choose(J):
                return None
            out = self._solve(J, F, self.singular_cond)
        return out

    def _solve(self, J: np.ndarray, F: np.ndarray, cond_limit: float):
        f_col, j_m, rhs = self._aug_views
        J.take(self.columns, axis=1, out=self._aug_perm)
        f_col[:] = F
        lu, _, x, info = _dgesv(j_m, rhs)
        if info != 0:
            return None
        # cheap degradation test: spread of the LU pivots (a lower bound of cond(J_m))
        piv = list(map(abs, lu.diagonal().tolist()))
        pmin = min(piv)
        self.cond = max(piv) / pmin if pmin > 0.0 else math.inf
        if not self.cond <= cond_limit:  # also catches NaN
            return None
        np.negative(x, out=x)
        return x[:, -1], x[:, :-1]


def compact_box_qp(
    H: np.ndarray,
    g: np.ndarray,
    dtheta_p: np.ndarray,
    N: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(H̃, g̃, Ãᵀ, b̃)`` for the joint box ``lower ≤ Δθ ≤ upper`` (finite bounds; use
    ±1e30 for "none"). ``Ãᵀ = [Nᵀ  −Nᵀ]`` is returned transposed (columns are
    constraints, quadprog's layout): column ``r < n`` is the lower bound of joint ``r``,
    column ``n + r`` its upper bound.
    """
    n, nz = N.shape
    Ht = N.T @ (H @ N)
    gt = N.T @ (g + H @ dtheta_p)
    Ct = np.empty((nz, 2 * n))
    Ct[:, :n] = N.T
    np.negative(N.T, out=Ct[:, n:])
    bt = np.empty(2 * n)
    np.subtract(lower, dtheta_p, out=bt[:n])
    np.subtract(dtheta_p, upper, out=bt[n:])
    return Ht, gt, Ct, bt
