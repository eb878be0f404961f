"""Compiled compact QP of one IK cycle (numba; the package doc lists the numpy
reference of each): the basis split ``−J_m⁻¹[J_free F]`` by LU with partial pivoting
(``split``), the scalar QP of a one-dimensional null space (``scalar_qp``, ``square_step``),
the hard and relaxed QP data in the compact variables (``hard_data``,
``hard_data_general``, ``compact_rest``, ``relaxed_data``) and the QP's answer when no
constraint binds (``unconstrained_qp``; else quadprog is called from Python).
"""

from __future__ import annotations

import math

import numpy as np
from irlc.runtime.ik.compiled.layout import (
    BOX_TOL,
    COND,
    COND_LIMIT,
    DP,
    DTHETA,
    LOWER,
    N_ACTIVE,
    RELAX_W,
    SCALE,
    SIGMA,
    UPPER,
    G,
    W,
)
from numba import njit


@njit(cache=True)
def split(Jt, F, perm, aug, N, dp, fst):
    """``CompactBasis._solve`` + ``split``: ``Δθ_p`` and ``N`` in joint order; False when
    ``J_m`` is singular or its pivot spread exceeds ``fst[COND_LIMIT]``."""
    m, n = Jt.shape
    for i in range(m):
        for j in range(n):
            aug[i, j] = Jt[i, perm[j]]
    for i in range(m):
        aug[i, n] = F[i]
    umax, umin = 0.0, math.inf
    for c in range(m):  # LU with partial pivoting (first largest, as LAPACK)
        p, best = c, abs(aug[c, c])
        for i in range(c + 1, m):
            if abs(aug[i, c]) > best:
                p, best = i, abs(aug[i, c])
        if best == 0.0:
            return False
        if p != c:
            for j in range(n + 1):
                aug[c, j], aug[p, j] = aug[p, j], aug[c, j]
        piv = aug[c, c]
        umax = max(umax, best)
        umin = min(umin, best)
        for i in range(c + 1, m):
            f = aug[i, c] / piv
            aug[i, c] = f
            for j in range(c + 1, n + 1):
                aug[i, j] -= f * aug[c, j]
    cond = umax / umin if umin > 0.0 else math.inf
    fst[COND] = cond
    if not cond <= fst[COND_LIMIT]:
        return False
    for c in range(n + 1 - 1, m - 1, -1):  # back substitution, right-hand columns m..n
        for i in range(m - 1, -1, -1):
            s = aug[i, c]
            for j in range(i + 1, m):
                s -= aug[i, j] * aug[j, c]
            aug[i, c] = s / aug[i, i]
    nz = n - m
    N[:, :] = 0.0
    for i in range(m):
        b = perm[i]
        dp[b] = -aug[i, n]
        for j in range(nz):
            N[b, j] = -aug[i, m + j]
    for j in range(nz):
        N[perm[m + j], j] = 1.0
        dp[perm[m + j]] = 0.0
    return True


@njit(cache=True)
def row_terms(A, r, dp, sigma):
    """Coupled row ``r``: ``(A_r·Δθ_p, A_r·Σ)``."""
    s_dp = 0.0
    s_sig = 0.0
    for j in range(dp.shape[0]):
        s_dp += A[r, j] * dp[j]
        s_sig += A[r, j] * sigma[j]
    return s_dp, s_sig


@njit(cache=True)
def square_step(V, A, bound_d, active, mult, ist):
    """``n = m``: ``Δθ_p`` if inside the box (and the coupled rows)."""
    n = V.shape[1]
    dp, lower, upper = V[DP], V[LOWER], V[UPPER]
    for j in range(n):
        if not (dp[j] >= lower[j] - BOX_TOL and dp[j] <= upper[j] + BOX_TOL):
            return False
    for r in range(A.shape[0]):
        s_dp, s_sig = row_terms(A, r, dp, V[SIGMA])
        if not s_dp >= (bound_d[r] - s_sig) - BOX_TOL:  # AΔθ_p ≥ b_k
            return False
    cnt = 0
    for j in range(n):
        if dp[j] <= lower[j] + BOX_TOL:
            active[cnt] = j
            mult[cnt] = 0.0
            cnt += 1
    for j in range(n):
        if dp[j] >= upper[j] - BOX_TOL:
            active[cnt] = j + n
            mult[cnt] = 0.0
            cnt += 1
    ist[N_ACTIVE] = cnt
    V[DTHETA, :] = dp
    return True


@njit(cache=True)
def scalar_qp(V, N, active, mult, ist):
    """``NewtonStep._scalar_qp``: 1 step found, 0 infeasible, −1 a zero entry of N."""
    n = V.shape[1]
    dp, w, g, lower, upper = V[DP], V[W], V[G], V[LOWER], V[UPPER]
    for j in range(n):
        if N[j, 0] == 0.0:
            return -1
    h = 0.0
    gc = 0.0
    wd = 0.0
    for j in range(n):
        c = N[j, 0]
        wc = w[j] * c
        h += wc * c
        gc += g[j] * c
        wd += wc * dp[j]
    gt = gc + wd
    z_lo, z_hi = -math.inf, math.inf
    j_lo, j_hi = 0, 0
    for j in range(n):
        c = N[j, 0]
        a = (lower[j] - dp[j]) / c
        b = (upper[j] - dp[j]) / c
        lo = min(a, b)
        hi = max(a, b)
        if j == 0 or lo > z_lo:  # first index of the maximum (list.index)
            z_lo, j_lo = lo, j
        if j == 0 or hi < z_hi:
            z_hi, j_hi = hi, j
    if not z_lo <= z_hi:
        return 0
    z = -gt / h
    cnt = 0
    if z < z_lo:
        z, j = z_lo, j_lo
        row = j if N[j, 0] > 0.0 else j + n
        cnt = 1
    elif z > z_hi:
        z, j = z_hi, j_hi
        row = j + n if N[j, 0] > 0.0 else j
        cnt = 1
    if cnt:
        active[0] = row
        mult[0] = abs(h * z + gt) / abs(N[j, 0])
    ist[N_ACTIVE] = cnt
    for j in range(n):
        V[DTHETA, j] = dp[j] + N[j, 0] * z
    return 1


@njit(cache=True)
def hard_data(V, N, perm, m, A, bound_d, Ht, gt, Ct, bt, fst):
    """The compact QP for quadprog (``hard_diagonal``), cost scaled to max diag H̃ = 1:
    ``H̃ = NᵀWN``, ``g̃ = Nᵀ(g + WΔθ_p)``, columns ``[N, −N, (AN)ᵀ]``."""
    n = V.shape[1]
    nz = n - m
    dp, w, g = V[DP], V[W], V[G]
    v = np.empty(n)
    for j in range(n):
        v[j] = w[j] * dp[j] + g[j]
    for a in range(nz):
        s = 0.0
        for j in range(n):
            s += N[j, a] * v[j]
        gt[a] = s
        for b in range(a, nz):
            s = 0.0
            for j in range(n):
                s += N[j, a] * w[j] * N[j, b]
            Ht[a, b] = s
            Ht[b, a] = s
    compact_rest(V, N, A, bound_d, Ht, gt, Ct, bt, fst)


@njit(cache=True)
def hard_data_general(V, N, H, A, bound_d, Ht, gt, Ct, bt, fst):
    """The compact QP for a full ``H`` (``compact.compact_box_qp`` + ``newton_step.with_rows``, as
    ``NewtonStep.hard``): ``H̃ = Nᵀ(HN)``, ``g̃ = Nᵀ(g + HΔθ_p)``, scaled as ``solve_ct``."""
    n, nz = N.shape
    dp, g = V[DP], V[G]
    hn = np.empty((n, nz))
    v = np.empty(n)
    for i in range(n):
        s = g[i]
        t = 0.0
        for j in range(n):
            t += H[i, j] * dp[j]
        v[i] = s + t
        for a in range(nz):
            t = 0.0
            for j in range(n):
                t += H[i, j] * N[j, a]
            hn[i, a] = t
    for a in range(nz):
        s = 0.0
        for j in range(n):
            s += N[j, a] * v[j]
        gt[a] = s
        for b in range(nz):
            s = 0.0
            for j in range(n):
                s += N[j, a] * hn[j, b]
            Ht[a, b] = s
    compact_rest(V, N, A, bound_d, Ht, gt, Ct, bt, fst)


@njit(cache=True)
def compact_rest(V, N, A, bound_d, Ht, gt, Ct, bt, fst):
    """Scale ``(H̃, g̃)`` to max diag H̃ = 1 (``QuadprogSolver.solve_ct``; ``fst[SCALE]``)
    and write the box columns ``[N, −N]`` and coupled columns ``(AN)ᵀ`` with their right
    sides ``[lower − Δθ_p; Δθ_p − upper; b − AΣ − AΔθ_p]``."""
    n, nz = N.shape
    dp = V[DP]
    hmax = 0.0
    for a in range(nz):
        hmax = max(hmax, Ht[a, a])
    scale = 1.0 / hmax
    fst[SCALE] = scale
    for a in range(nz):
        gt[a] *= -scale
        for b in range(nz):
            Ht[a, b] *= scale
        for j in range(n):
            Ct[a, j] = N[j, a]
            Ct[a, n + j] = -N[j, a]
    for j in range(n):
        bt[j] = V[LOWER, j] - dp[j]
        bt[n + j] = dp[j] - V[UPPER, j]
    for r in range(A.shape[0]):
        s_dp, s_sig = row_terms(A, r, dp, V[SIGMA])
        bt[2 * n + r] = bound_d[r] - s_sig - s_dp
        for a in range(nz):
            s = 0.0
            for j in range(n):
                s += A[r, j] * N[j, a]
            Ct[a, 2 * n + r] = s


@njit(cache=True)
def unconstrained_qp(H, a, C, b, z):
    """The compact QP's answer when no constraint binds: ``z = H⁻¹a`` (quadprog's
    ``½zᵀHz − aᵀz``) if it satisfies every column, ``Cᵀz ≥ b``, with a margin
    ``1e-12·(1 + |b_i|)`` — the Goldfarb–Idnani method starts from this point and stops
    at once when nothing is violated, so quadprog returns the same ``z`` and no active
    constraint. False (quadprog decides) when some slack is within the margin or ``H``
    is not positive definite (Cholesky fails)."""
    nz = H.shape[0]
    L = np.empty((nz, nz))
    for i in range(nz):  # Cholesky H = LLᵀ
        for j in range(i + 1):
            s = H[i, j]
            for k in range(j):
                s -= L[i, k] * L[j, k]
            if i == j:
                if not s > 0.0:
                    return False
                L[i, i] = math.sqrt(s)
            else:
                L[i, j] = s / L[j, j]
    for i in range(nz):  # L y = a
        s = a[i]
        for k in range(i):
            s -= L[i, k] * z[k]
        z[i] = s / L[i, i]
    for i in range(nz - 1, -1, -1):  # Lᵀ z = y
        s = z[i]
        for k in range(i + 1, nz):
            s -= L[k, i] * z[k]
        z[i] = s / L[i, i]
    for c in range(C.shape[1]):
        s = -b[c]
        for i in range(nz):
            s += C[i, c] * z[i]
        if not s > 1e-12 * (1.0 + abs(b[c])):
            return False
    return True


@njit(cache=True)
def relaxed_data(V, Jt, F, A, bound_d, H, general, Hr, gr, bt, fst):
    """Relaxed QP data. Diagonal cost, box only (``relaxed_diagonal``): ``JᵀJ + W/ρ``,
    ``−(JᵀF + g/ρ)``, multipliers ×ρ. With coupled rows or a full ``H`` (``general``;
    ``relaxed``): ``(H + ρJᵀJ)·s``, ``−(g + ρJᵀF)·s``, ``s = 1/max diag``, multipliers
    ÷s; ``ρ = relax_weight·max diag H``. ``fst[SCALE]`` is the multiplier factor."""
    m, n = Jt.shape
    w, g = V[W], V[G]
    wmax = 0.0
    for j in range(n):
        wmax = max(wmax, H[j, j] if general else w[j])
    rho = fst[RELAX_W] * wmax
    for a in range(n):
        for b in range(a, n):
            s = 0.0
            for i in range(m):
                s += Jt[i, a] * Jt[i, b]
            Hr[a, b] = s
            Hr[b, a] = s
        s = 0.0
        for i in range(m):
            s += Jt[i, a] * F[i]
        gr[a] = s
    if not general and A.shape[0] == 0:
        inv = 1.0 / rho
        for a in range(n):
            Hr[a, a] += w[a] * inv
            gr[a] = -(gr[a] + g[a] * inv)
        fst[SCALE] = rho
    else:
        for a in range(n):
            for b in range(n):
                Hr[a, b] *= rho
                if general:
                    Hr[a, b] += H[a, b]
            if not general:
                Hr[a, a] += w[a]
            gr[a] = g[a] + rho * gr[a]
        hmax = 0.0
        for a in range(n):
            hmax = max(hmax, Hr[a, a])
        scale = 1.0 / hmax
        for a in range(n):
            gr[a] *= -scale
            for b in range(n):
                Hr[a, b] *= scale
        fst[SCALE] = 1.0 / scale
    for j in range(n):
        bt[j] = V[LOWER, j]
        bt[n + j] = -V[UPPER, j]
    for r in range(A.shape[0]):
        s = 0.0
        for j in range(n):
            s += A[r, j] * V[SIGMA, j]
        bt[2 * n + r] = bound_d[r] - s
