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

import math

import numpy as np
import quadprog
from irlc.runtime.ik.compact import CompactBasis, compact_box_qp
from irlc.runtime.ik.qp import QPResult
from scipy.linalg.lapack import dposv as _dposv

_BOX_TOL = 1e-12


class StepOutcome:
    """The step, how it was found, and the active rows with their multipliers."""

    __slots__ = ("active", "dtheta", "multipliers", "relaxed", "singular")

    def __init__(self, dtheta, relaxed: bool, singular: bool, active, multipliers):
        self.dtheta = dtheta
        self.relaxed = relaxed
        self.singular = singular
        self.active = active  # active box rows (see module doc)
        self.multipliers = multipliers


class NewtonStep:
    """Solves one step; keeps the compact basis (and per-basis buffers) from call to call.

    ``ineq = (A, b)`` adds rows ``AΔθ ≥ b`` (coupled joint limits) to both forms; in the
    compact form they become ``(AN)z ≥ b − AΔθ_p``. Active row indices ``≥ 2n`` refer to
    them (row ``r − 2n`` of ``A``).
    """

    def __init__(self, solver, relax_weight: float = 1e6, basis: CompactBasis | None = None):
        self.solver = solver
        self.relax_weight = relax_weight
        self.basis = basis or CompactBasis()
        self._eye_cache: dict[int, np.ndarray] = {}
        self.last_singular = False
        self.scalar_qp = True  # one null-space dimension: closed form (see _scalar_qp)
        self._version = -1

    def hard(self, J, F, H, g, lower, upper, ineq=None) -> StepOutcome | None:
        """The compact QP; ``None`` if singular or infeasible (``singular`` noted)."""
        self.last_singular = False
        split = self.basis.split(J, F)
        if split is None:
            self.last_singular = True
            return None
        dtheta_p, N = split
        if N.shape[1] == 0:  # n = m: no redundancy, the box is only checked
            return _checked(dtheta_p, lower, upper, ineq)
        Ht, gt, Ct, bt = compact_box_qp(H, g, dtheta_p, N, lower, upper)
        return self._solve_reduced(Ht, gt, Ct, bt, dtheta_p, N, ineq)

    def hard_diagonal(self, J, F, w, g, bounds, ineq=None) -> StepOutcome | None:
        """:meth:`hard` for a diagonal ``H = diag(w)`` — the IPO-cycle hot path;
        ``bounds = [lower; upper]`` (2×n) on ``Δθ``.

        With ``−J_m⁻¹[J_free F] = [X y]`` (basic rows of ``N`` and ``Δθ_p``) and
        ``v = g + w∘Δθ_p``: ``H̃ = XᵀW_bX + W_f``, ``g̃ = Xᵀv_b + v_f``; the box rows
        ``[N; −N]`` of ``Ãᵀ`` are rebuilt from ``N`` in place. ``w`` is a criterion's
        constant weights: its basic / free parts are kept while the same array comes."""
        self.last_singular = False
        basis = self.basis
        blocks = basis.blocks(J, F)
        if blocks is None:
            self.last_singular = True
            return None
        y, X = blocks
        if self._version != basis.version:
            self._prepare()
        dp, N = self._dp, self._N
        N.put(self._n_basic, X)  # N[basic] = X (flat indices: cheaper than row indexing)
        dp[self._basic] = y
        nz = N.shape[1]
        if nz == 0:
            return _checked(dp, bounds[0], bounds[1], ineq)
        if nz == 1 and ineq is None and self.scalar_qp:
            out = self._scalar_qp(dp, N[:, 0], w, g, bounds)
            if out is not False:
                return out
        if w is not self._w:  # (the criterion's weights: the same array cycle after cycle)
            self._w, self._w_col, self._neg_w = w, w[:, None], np.negative(w)
        ht, a = self._diagonal_data(N, dp, g)
        if ineq is None:
            dtheta = self._box_minimiser(ht, a, N, dp, bounds)
            if dtheta is not None:
                return StepOutcome(dtheta, False, False, _EMPTY_INT, _EMPTY)
        ct_lo, ct_hi, bt_lo, bt_hi = self._halves
        np.copyto(ct_lo, self._N_T)
        np.negative(ct_lo, out=ct_hi)
        np.subtract(bounds[0], dp, out=bt_lo)
        np.subtract(dp, bounds[1], out=bt_hi)
        gt = np.negative(a)
        return self._solve_reduced(ht, gt, self._ct, self._bt, dp, N, ineq, ineq is not None)

    def _diagonal_data(self, N, dp, g) -> tuple[np.ndarray, np.ndarray]:
        """``(H̃, −g̃)`` of the compact QP for ``H = diag(w)``: one product
        ``Nᵀ[WN | −(WΔθ_p + g)]`` (the identity rows of ``N`` give ``W_f``; views of a
        per-basis buffer, valid until the next call)."""
        np.multiply(self._w_col, N, out=self._wn)
        v = self._v
        np.multiply(self._neg_w, dp, out=v)
        np.subtract(v, g, out=v)
        np.matmul(self._N_T, self._wnv, out=self._hta)
        return self._ht, self._a

    def _box_minimiser(self, ht, a, N, dp, bounds) -> np.ndarray | None:
        """``Δθ = Δθ_p + Nz``, ``z = H̃⁻¹(−g̃)`` (Cholesky), the compact QP's solution when
        it satisfies every box row ``±(Δθ_p + Nz) ≥ ±bound`` with a slack above
        ``μ = 1e-12·(1 + max|Nz|)/(1 − 1e-12)``. That implies the compiled kernel's
        margin ``1e-12·(1 + |b̃_i|)`` on ``[N; −N]z ≥ b̃ = [l − Δθ_p; Δθ_p − u]``
        (``|b̃_i| ≤ slack_i + |Nz_i|``): Goldfarb–Idnani starts from this point and stops
        at once when nothing is violated, so the solver would return it with no active
        row. ``None`` (the solver decides) when some slack is within ``μ``, when ``H̃``
        is not positive definite, or when a number is not finite."""
        _, z, info = _dposv(ht, a)
        if info != 0:
            return None
        step = N @ z
        nzl = step.tolist()
        step += dp  # Δθ
        above, below = np.subtract(step, bounds).tolist()  # Δθ − l, Δθ − u
        mu = 1e-12 * (1.0 + max(max(nzl), -min(nzl))) / (1.0 - 1e-12)
        if min(above) > mu and max(below) < -mu and math.isfinite(sum(nzl) + sum(above)):
            return step
        return None

    def _solve_reduced(self, Ht, gt, Ct, bt, dp, N, ineq, free: bool = True) -> StepOutcome | None:
        """Solve the compact QP in ``z`` (plus any coupled rows); ``Δθ = Δθ_p + N z``.
        ``free``: first try the unconstrained minimiser (:func:`_free_minimiser`)."""
        if ineq is not None:
            Ct, bt = with_rows(Ct, bt, ineq[0], ineq[1], dp, N)
        z = _free_minimiser(Ht, gt, Ct, bt) if free else None
        if z is not None:
            return StepOutcome(dp + N @ z, False, False, _EMPTY_INT, _EMPTY)
        res: QPResult = self.solver.solve_ct(Ht, gt, Ct, bt)
        if not res.ok:
            return None
        return StepOutcome(dp + N @ res.z, False, False, res.active, res.multipliers)

    def _prepare(self) -> None:
        """Per-basis buffers of :meth:`hard_diagonal`."""
        b = self.basis
        self._version = b.version
        self._basic, self._free = b._basic, b._free
        self._N, self._dp = b._N, b._dp
        n, nz = self._N.shape
        self._ct = np.empty((nz, 2 * n))
        self._bt = np.empty(2 * n)
        # views made once: the box columns [Nᵀ, −Nᵀ], their right sides, N's basic rows
        ct, bt = self._ct, self._bt
        self._halves = (ct[:, :n], ct[:, n:], bt[:n], bt[n:])
        self._N_T = self._N.T
        self._n_basic = (self._basic[:, None] * nz + np.arange(nz)).ravel()
        self._zb = np.empty((2, n))
        self._zlo = np.empty(n)
        self._zhi = np.empty(n)
        # H̃ and −g̃ from one product Nᵀ[WN | v] (see _diagonal_data)
        self._wnv = np.empty((n, nz + 1))
        self._wn, self._v = self._wnv[:, :nz], self._wnv[:, nz]
        self._hta = np.empty((nz, nz + 1))
        self._ht, self._a = self._hta[:, :nz], self._hta[:, nz]
        self._w = None  # w as a column and −w are cached per basis and weights

    def _scalar_qp(self, dp, col, w, g, bounds):
        """One null-space dimension, ``Δθ = Δθ_p + col·z``: ``min ½hz² + g̃z`` with
        ``h = colᵀWcol``, ``g̃ = colᵀ(g + WΔθ_p)``, s.t. ``l_j ≤ Δθ_p,j + col_j z ≤ u_j``.
        The minimiser is ``−g̃/h`` clipped to ``[max_j min(a_j, b_j), min_j max(a_j, b_j)]``,
        ``a = (l − Δθ_p)/col``, ``b = (u − Δθ_p)/col`` — the Goldfarb–Idnani result for
        one variable (the active set is the clipping bound, its multiplier
        ``|hz + g̃|/|col_j|``). Empty interval: ``None`` (infeasible). Returns ``False``
        when some ``col_j = 0`` (then the general solver decides)."""
        n = col.shape[0]
        if np.count_nonzero(col) != n:
            return False
        wc = w * col
        h = float(wc.dot(col))
        gt = float(g.dot(col)) + float(wc.dot(dp))
        zb, zlo, zhi = self._zb, self._zlo, self._zhi
        np.subtract(bounds, dp, out=zb)
        zb /= col
        np.minimum(zb[0], zb[1], out=zlo)  # per joint: the bound on z from below …
        np.maximum(zb[0], zb[1], out=zhi)  # … and from above
        lo_list, hi_list = zlo.tolist(), zhi.tolist()  # (builtins beat numpy reductions
        z_lo, z_hi = max(lo_list), min(hi_list)  # on a handful of numbers)
        if not z_lo <= z_hi:
            return None
        z = -gt / h
        if z_lo <= z <= z_hi:
            return StepOutcome(dp + col * z, False, False, _EMPTY_INT, _EMPTY)
        if z < z_lo:
            z, j = z_lo, lo_list.index(z_lo)
            row = j if col[j] > 0.0 else j + n  # n_j z ≥ l_j − dp_j, or the upper row
        else:
            z, j = z_hi, hi_list.index(z_hi)
            row = j + n if col[j] > 0.0 else j
        mult = abs(h * z + gt) / abs(float(col[j]))
        return StepOutcome(dp + col * z, False, False, np.array([row]), np.array([mult]))

    def relaxed_diagonal(self, J, F, w, g, bounds) -> StepOutcome:
        """:meth:`relaxed` for ``H = diag(w)``, box only: the QP divided by ``ρ``
        (``JᵀJ + W/ρ``, ``JᵀF + g/ρ``; entries of order one), quadprog called directly."""
        n = w.shape[0]
        rho = self.relax_weight * max(w.tolist())
        inv_rho = 1.0 / rho
        Hs = J.T @ J
        Hs.flat[:: n + 1] += w * inv_rho
        a = J.T @ F
        a += g * inv_rho
        np.negative(a, out=a)
        bt = np.multiply(bounds, _SIGNS).reshape(-1)  # [lower; −upper]
        try:
            z, _, _, _, lagr, iact = quadprog.solve_qp(Hs, a, self._box_columns(n), bt, 0)
        except ValueError as exc:
            raise FloatingPointError(f"relaxed QP failed ({exc})") from None
        rows = iact[iact > 0] - 1
        mult = lagr[rows] * rho
        return StepOutcome(z, True, self.last_singular, rows, mult)

    def relaxed(self, J, F, H, g, lower, upper, ineq=None) -> StepOutcome:
        """The relaxed QP (always solvable for a non-empty box)."""
        n = H.shape[0]
        rho = self.relax_weight * float(H.diagonal().max())
        Hr = H + rho * (J.T @ J)
        gr = g + rho * (J.T @ F)
        C = self._box_columns(n)
        b = np.concatenate((lower, -upper))
        if ineq is not None:
            C = np.hstack((C, ineq[0].T))
            b = np.concatenate((b, ineq[1]))
        res = self.solver.solve_ct(Hr, gr, C, b)
        if not res.ok:
            raise FloatingPointError(f"relaxed QP failed ({res.status}: {res.message})")
        return StepOutcome(res.z, True, self.last_singular, res.active, res.multipliers)

    def solve(self, J, F, H, g, lower, upper, ineq=None) -> StepOutcome:
        return self.hard(J, F, H, g, lower, upper, ineq) or self.relaxed(
            J, F, H, g, lower, upper, ineq
        )

    def _box_columns(self, n: int) -> np.ndarray:
        a = self._eye_cache.get(n)
        if a is None:
            a = np.hstack((np.eye(n), -np.eye(n)))
            self._eye_cache[n] = a
        return a


_EMPTY_INT = np.zeros(0, dtype=int)
_EMPTY = np.zeros(0)
_SIGNS = np.array([[1.0], [-1.0]])


def _free_minimiser(Ht, gt, Ct, bt) -> np.ndarray | None:
    """``z = −H̃⁻¹g̃`` (Cholesky) if it satisfies every column ``Ãᵀ`` of the compact QP,
    ``Ãz ≥ b̃``, with the margin ``1e-12·(1 + |b̃_i|)`` (as
    :meth:`NewtonStep._box_minimiser`); else ``None`` (the solver decides)."""
    _, z, info = _dposv(Ht, np.negative(gt))
    if info != 0:
        return None
    slack = z @ Ct
    slack -= bt
    slack -= 1e-12 * np.abs(bt)
    return z if np.count_nonzero(slack > 1e-12) == slack.size else None


def with_rows(Ct, bt, A, b, dp, N):
    """Append the compact form of ``AΔθ ≥ b``: columns ``(AN)ᵀ``, right sides ``b − AΔθ_p``."""
    return np.hstack((Ct, (A @ N).T)), np.concatenate((bt, b - A @ dp))


def _checked(dp, lower, upper, ineq) -> StepOutcome | None:
    """``n = m``: the only solution ``Δθ_p`` if it satisfies the box (and ``ineq``)."""
    inside = np.all(dp >= lower - _BOX_TOL) and np.all(dp <= upper + _BOX_TOL)
    if inside and (ineq is None or np.all(ineq[0] @ dp >= ineq[1] - _BOX_TOL)):
        rows = _touching(dp, lower, upper)
        return StepOutcome(dp.copy(), False, False, rows, np.zeros(rows.size))
    return None


def _touching(x, lower, upper) -> np.ndarray:
    n = x.shape[0]
    lo = np.flatnonzero(x <= lower + _BOX_TOL)
    hi = np.flatnonzero(x >= upper - _BOX_TOL) + n
    return np.concatenate((lo, hi))
