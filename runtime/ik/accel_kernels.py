"""Compiled kernels (numba) of one IPO cycle — the numbers of :mod:`newton`, fused.

Imported only through :mod:`accel` when numba is available. Each function here is the
same arithmetic as its numpy reference (named in its docstring), written as loops:

* ``_chain``: ``Kinematics.chain`` — ``L_i = A0 + cos v·A1 + sin v·A2 + v·A3``,
  ``T_i = T_{i−1}·L_i``; ``_jacobian``: ``Kinematics.tcp_jacobian`` —
  ``[z_i × (p − o_i); z_i]`` (revolute), ``[z_i; 0]`` (prismatic), ``z_i = R_i·k_i``;
* ``_pose_error``: ``task_error.pose_error_list`` / ``spatial.pose_error`` (near-π branch
  included);
* ``_box``: ``JointBox.prepare`` (signed candidates, braking bound ``2R/(1 + √(1 + 2R/ε))``);
* ``_split``: ``CompactBasis._solve`` — ``−J_m⁻¹[J_free F]`` by LU with partial pivoting,
  the pivot spread as the degradation test;
* ``_scalar_qp`` / ``_checked`` / ``_hard_data``: ``NewtonStep.hard_diagonal``;
  ``_hard_data_general``: ``compact_box_qp`` + ``_with_rows`` (``NewtonStep.hard``);
  ``_relaxed_data``: ``NewtonStep.relaxed_diagonal`` / ``relaxed`` (the QP data only);
  ``_unconstrained_qp``: the compact QP's answer when no constraint binds (else quadprog
  is called from Python);
* ``_general_cost``: ``InverseTransformation._cost`` (CYCLIC, ``a_conf·W``, obstacle
  terms); ``_reduce``: the FREEZE reduction of ``InverseTransformation._solve``;
* ``_active_codes``: ``limits.active_codes``.

:func:`newton_cycle` is a resumable state machine: it runs Newton iterations until the
cycle is done or it needs Python (a quadprog call, a new basis by QR pivoting, the
obstacle terms, the error path of the joint box); the caller does that and resumes it
with a phase code. State lives in the integer / float arrays ``ist`` / ``fst`` (indices
below); every array is a view of one workspace (``accel.Workspace``, layout below).

The kernels stay in one file on purpose: numba's on-disk cache of a function is keyed
by its own source file only, so a kernel calling a kernel of another module would keep
stale machine code after that module changed.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

# phases (ist[PHASE]) the caller resumes with
P_START, P_APPLY, P_APPLY_Z, P_SPLIT, P_RELAX, P_TERMS = 0, 1, 2, 3, 4, 5
# statuses returned
S_DONE, S_BOX_CHECK, S_NEED_BASIS, S_NEED_QP, S_NEED_RELAXED, S_BAD_STEP = 0, 1, 2, 3, 4, 5
S_NEED_TERMS, S_FROZEN_FAR = 6, 7
# ist indices
(
    PHASE,
    K,
    RELAXED,
    SINGULAR,
    LAST_SINGULAR,
    BASIS_VALID,
    BASIS_STAGE,
    BASIS_REASON,
    N_ACTIVE,
    MAX_ITER,
    SELF_MOTION,
    WARM,
    SCALAR,
    HAS_REF,
    ACCEL_BOUNDED,
    BOX_READY,
    NPOS,
    HAVE_J,
    GENERAL,
    NEED_TERMS,
    N_IST,
) = range(21)
# fst indices (E0 … E0 + 5: the last task error, all six components)
TOL_P, TOL_O, COND_MAX, SINGULAR_COND, COND_LIMIT, RELAX_W, PE, OE, SCALE, DTOL, COND, E0 = range(
    12
)
N_FST = E0 + 6
# rows of the (NV, n) vector workspace V (WC: the extra diagonal a_conf·W of the general
# cost; CFZ: the fixed steps θ⁰ − θ_k of the frozen joints, first n_frozen entries)
Q_START, Q_PREV, THETA, DTHETA, SIGMA, G, W, REF, DP, LOWER, UPPER, Z, WC, CFZ, NV = range(15)

_BIG = 1e30
_TOL = 1e-9
_BOX_TOL = 1e-12


@njit(cache=True)
def _chain(basis, joint, base, q, frames, local):
    """FK into ``frames`` (n+1, 4, 4); ``joint[i] = (offset, kx, ky, kz, revolute)``."""
    n = q.shape[0]
    frames[0, :, :] = base
    for i in range(n):
        v = q[i] + joint[i, 0]
        c = math.cos(v)
        s = math.sin(v)
        for e in range(16):
            local[e // 4, e % 4] = (
                basis[i, 0, e] + c * basis[i, 1, e] + s * basis[i, 2, e] + v * basis[i, 3, e]
            )
        for r in range(4):
            f0 = frames[i, r, 0]
            f1 = frames[i, r, 1]
            f2 = frames[i, r, 2]
            f3 = frames[i, r, 3]
            for col in range(4):
                frames[i + 1, r, col] = (
                    f0 * local[0, col]
                    + f1 * local[1, col]
                    + f2 * local[2, col]
                    + f3 * local[3, col]
                )


@njit(cache=True)
def _matmul44(a, b, out):
    for r in range(4):
        for col in range(4):
            out[r, col] = (
                a[r, 0] * b[0, col]
                + a[r, 1] * b[1, col]
                + a[r, 2] * b[2, col]
                + a[r, 3] * b[3, col]
            )


@njit(cache=True)
def _jacobian(frames, joint, p, out):
    """6×n TCP Jacobian at the world point ``p`` (``Kinematics.tcp_jacobian``)."""
    n = joint.shape[0]
    for i in range(n):
        f = frames[i + 1]
        kx, ky, kz = joint[i, 1], joint[i, 2], joint[i, 3]
        zx = f[0, 0] * kx + f[0, 1] * ky + f[0, 2] * kz
        zy = f[1, 0] * kx + f[1, 1] * ky + f[1, 2] * kz
        zz = f[2, 0] * kx + f[2, 1] * ky + f[2, 2] * kz
        if joint[i, 4] != 0.0:
            rx = p[0] - f[0, 3]
            ry = p[1] - f[1, 3]
            rz = p[2] - f[2, 3]
            out[0, i] = zy * rz - zz * ry
            out[1, i] = zz * rx - zx * rz
            out[2, i] = zx * ry - zy * rx
            out[3, i] = zx
            out[4, i] = zy
            out[5, i] = zz
        else:
            out[0, i] = zx
            out[1, i] = zy
            out[2, i] = zz
            out[3, i] = 0.0
            out[4, i] = 0.0
            out[5, i] = 0.0


@njit(cache=True)
def _pose_error(t, d, e):
    """``spatial.pose_error(t, d)`` into ``e`` (6): position, rotation vector of R·R_dᵀ."""
    e[0] = t[0, 3] - d[0, 3]
    e[1] = t[1, 3] - d[1, 3]
    e[2] = t[2, 3] - d[2, 3]
    m = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            m[i, j] = t[i, 0] * d[j, 0] + t[i, 1] * d[j, 1] + t[i, 2] * d[j, 2]
    w0 = m[2, 1] - m[1, 2]
    w1 = m[0, 2] - m[2, 0]
    w2 = m[1, 0] - m[0, 1]
    cos_t = max(-1.0, min(1.0, (m[0, 0] + m[1, 1] + m[2, 2] - 1.0) / 2.0))
    theta = math.acos(cos_t)
    if theta < 1e-6:
        k = 0.5
    elif math.pi - theta > 1e-4:
        k = theta / (2.0 * math.sin(theta))
    else:  # near a half turn: the axis from the symmetric part (spatial.rotation_vector)
        best, kk = -1.0, 0
        for i in range(3):
            a = math.sqrt(max((m[i, i] + 1.0) / 2.0, 0.0))
            if a > best:
                best, kk = a, i
        s = math.sqrt((m[kk, kk] + 1.0) / 2.0)
        a0 = (m[0, kk] + (1.0 if kk == 0 else 0.0)) / 2.0 / s
        a1 = (m[1, kk] + (1.0 if kk == 1 else 0.0)) / 2.0 / s
        a2 = (m[2, kk] + (1.0 if kk == 2 else 0.0)) / 2.0 / s
        if a0 * w0 + a1 * w1 + a2 * w2 < 0.0:
            a0, a1, a2 = -a0, -a1, -a2
        norm = math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
        e[3] = theta * a0 / norm
        e[4] = theta * a1 / norm
        e[5] = theta * a2 / norm
        return
    e[3] = k * w0
    e[4] = k * w1
    e[5] = k * w2


@njit(cache=True)
def _box(boxc, accel_bounded, dtol, q_start, q_prev, cand, bounds):
    """``JointBox.prepare`` without the error path: False when the state needs the
    Python check (outside the limits, or an empty box)."""
    n = q_start.shape[0]
    ok = True
    for j in range(n):
        lo_pos = boxc[0, 0, j] + q_start[j]  # θ_s − θmin
        hi_pos = boxc[0, 1, j] - q_start[j]  # θmax − θ_s
        cand[0, 0, j] = lo_pos
        cand[0, 1, j] = hi_pos
        cand[1, 0, j] = boxc[1, 0, j]
        cand[1, 1, j] = boxc[1, 1, j]
        d = q_start[j] - q_prev[j]
        if lo_pos < -_TOL or hi_pos < -_TOL:
            ok = False
        if -d - boxc[1, 0, j] > dtol or d - boxc[1, 1, j] > dtol:
            ok = False
        if accel_bounded:
            cand[2, 0, j] = boxc[2, 0, j] - d
            cand[2, 1, j] = boxc[2, 1, j] + d
            for side in range(2):
                room = max(cand[0, side, j], 0.0)
                b = math.sqrt(room * boxc[3, side, j] + 1.0) + 1.0
                b = room / b
                cand[3, side, j] = b + b
        else:
            for s in range(2, 4):
                cand[s, 0, j] = _BIG
                cand[s, 1, j] = _BIG
        lo = min(cand[0, 0, j], cand[1, 0, j])
        hi = min(cand[0, 1, j], cand[1, 1, j])
        if accel_bounded:
            lo = min(min(lo, cand[2, 0, j]), cand[3, 0, j])
            hi = min(min(hi, cand[2, 1, j]), cand[3, 1, j])
        bounds[0, j] = -lo
        bounds[1, j] = hi
        if hi + lo < 0.0:
            ok = False
    return ok


@njit(cache=True)
def _split(Jt, F, perm, aug, N, dp, fst):
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
def _row_terms(A, r, dp, sigma):
    """Coupled row ``r``: ``(A_r·Δθ_p, A_r·Σ)``."""
    s_dp = 0.0
    s_sig = 0.0
    for j in range(dp.shape[0]):
        s_dp += A[r, j] * dp[j]
        s_sig += A[r, j] * sigma[j]
    return s_dp, s_sig


@njit(cache=True)
def _checked(V, A, bound_d, active, mult, ist):
    """``n = m``: ``Δθ_p`` if inside the box (and the coupled rows)."""
    n = V.shape[1]
    dp, lower, upper = V[DP], V[LOWER], V[UPPER]
    for j in range(n):
        if not (dp[j] >= lower[j] - _BOX_TOL and dp[j] <= upper[j] + _BOX_TOL):
            return False
    for r in range(A.shape[0]):
        s_dp, s_sig = _row_terms(A, r, dp, V[SIGMA])
        if not s_dp >= (bound_d[r] - s_sig) - _BOX_TOL:  # AΔθ_p ≥ b_k
            return False
    cnt = 0
    for j in range(n):
        if dp[j] <= lower[j] + _BOX_TOL:
            active[cnt] = j
            mult[cnt] = 0.0
            cnt += 1
    for j in range(n):
        if dp[j] >= upper[j] - _BOX_TOL:
            active[cnt] = j + n
            mult[cnt] = 0.0
            cnt += 1
    ist[N_ACTIVE] = cnt
    V[DTHETA, :] = dp
    return True


@njit(cache=True)
def _scalar_qp(V, N, active, mult, ist):
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
def _hard_data(V, N, perm, m, A, bound_d, Ht, gt, Ct, bt, fst):
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
    _compact_rest(V, N, A, bound_d, Ht, gt, Ct, bt, fst)


@njit(cache=True)
def _hard_data_general(V, N, H, A, bound_d, Ht, gt, Ct, bt, fst):
    """The compact QP for a full ``H`` (``compact.compact_box_qp`` + ``_with_rows``, as
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
    _compact_rest(V, N, A, bound_d, Ht, gt, Ct, bt, fst)


@njit(cache=True)
def _compact_rest(V, N, A, bound_d, Ht, gt, Ct, bt, fst):
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
        s_dp, s_sig = _row_terms(A, r, dp, V[SIGMA])
        bt[2 * n + r] = bound_d[r] - s_sig - s_dp
        for a in range(nz):
            s = 0.0
            for j in range(n):
                s += A[r, j] * N[j, a]
            Ct[a, 2 * n + r] = s


@njit(cache=True)
def _unconstrained_qp(H, a, C, b, z):
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
def _relaxed_data(V, Jt, F, A, bound_d, H, general, Hr, gr, bt, fst):
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


@njit(cache=True)
def _general_cost(V, H, ow, opush, ojac, ojtj):
    """The full cost of ``InverseTransformation._cost`` (after the criterion's ``g`` in
    ``V[G]``): ``g += a_conf·W∘Σ`` (``V[WC]``), ``H = diag(W + a_conf·W)``, and per
    obstacle term ``t`` (:class:`obstacle.ObstacleTerm`, weight ``ω_t ≠ 0``):
    ``g −= ω_t·J_tᵀ(αv_t − J_tΣ)``, ``H += ω_t·J_tᵀJ_t``."""
    n = V.shape[1]
    sigma, g = V[SIGMA], V[G]
    for j in range(n):
        g[j] += V[WC, j] * sigma[j]
        for i in range(n):
            H[j, i] = 0.0
        H[j, j] = V[W, j] + V[WC, j]
    for t in range(ow.shape[0]):
        wt = ow[t]
        if wt == 0.0:
            continue
        for r in range(3):
            s = 0.0
            for j in range(n):
                s += ojac[t, r, j] * sigma[j]
            res = opush[t, r] - s
            for j in range(n):
                g[j] -= wt * (ojac[t, r, j] * res)
        for a in range(n):
            for b in range(n):
                H[a, b] += wt * ojtj[t, a, b]


@njit(cache=True)
def _reduce(V, Jt, F, H, A, bound_d, free, fz, ftarget, Vr, Jr, Fr, Hr, Ar, bound_r):
    """FREEZE (``InverseTransformation._solve``): the frozen joints' fixed steps
    ``c = θ⁰ − θ_k`` (into ``V[CFZ]``; False when one leaves its box by more than 1e-12)
    and the problem over the free joints: ``F + J_fz c``, ``J_free``, ``g_free +
    H_free,fz c``, ``H_free,free``, the free bounds, and the coupled rows
    ``A_free Δθ ≥ b − AΣ − A_fz c`` (as ``b_r − A_free Σ_free``)."""
    nf = free.shape[0]
    nfz = fz.shape[0]
    m = Jt.shape[0]
    for i in range(nfz):
        j = fz[i]
        c = ftarget[i] - V[THETA, j]
        V[CFZ, i] = c
        if c < V[LOWER, j] - 1e-12 or c > V[UPPER, j] + 1e-12:
            return False
    for i in range(m):
        s = 0.0
        for k in range(nfz):
            s += Jt[i, fz[k]] * V[CFZ, k]
        Fr[i] = F[i] + s
        for a in range(nf):
            Jr[i, a] = Jt[i, free[a]]
    for a in range(nf):
        j = free[a]
        s = 0.0
        for k in range(nfz):
            s += H[j, fz[k]] * V[CFZ, k]
        Vr[G, a] = V[G, j] + s
        Vr[W, a] = V[W, j]
        Vr[SIGMA, a] = V[SIGMA, j]
        Vr[LOWER, a] = V[LOWER, j]
        Vr[UPPER, a] = V[UPPER, j]
        for b in range(nf):
            Hr[a, b] = H[j, free[b]]
    for r in range(A.shape[0]):
        s = 0.0
        for k in range(nfz):
            s += A[r, fz[k]] * (V[SIGMA, fz[k]] + V[CFZ, k])
        bound_r[r] = bound_d[r] - s
        for a in range(nf):
            Ar[r, a] = A[r, free[a]]
    return True


@njit(cache=True)
def _evaluate(kb, kj, ends, target, frames, local, tcp, rows, V, ist, fst):
    """FK, TCP, task error (``fst[E0:E0 + 6]``) and its norms at ``θ``."""
    e6 = fst[E0 : E0 + 6]
    _chain(kb, kj, ends[0], V[THETA], frames, local)
    _matmul44(frames[frames.shape[0] - 1], ends[1], tcp)
    _pose_error(tcp, target, e6)
    npos = ist[NPOS]
    pe = 0.0
    oe = 0.0
    for i in range(rows.shape[0]):
        x = e6[rows[i]]
        if i < npos:
            pe += x * x
        else:
            oe += x * x
    fst[PE] = math.sqrt(pe)
    fst[OE] = math.sqrt(oe)


# ---------------------------------------------------------------------- one-buffer entry
# Slots of the layout ``lay`` (int64): offsets of each array in the float workspace ``fw``
# or the int workspace ``iw``, then the sizes. One Python→numba call unboxes every array
# argument (≈ 0.15–0.3 µs each), so the cycle passes two buffers and a layout instead of
# forty arrays; :func:`newton_cycle` cuts the same views the driver (``accel.Workspace``)
# uses.
(
    F_V, F_FRAMES, F_TCP, F_J6, F_JT, F_F, F_H, F_A, F_BOUND_D, F_BOUNDS, F_CAND, F_TARGET,
    F_VR, F_JR, F_FR, F_HR, F_AR, F_BOUND_R, F_AUG, F_N, F_HT, F_GT, F_CT, F_BT, F_HREL,
    F_GREL, F_MULT, F_FTARGET, F_FST,
    I_ROWS, I_FREE, I_FZ, I_PERM, I_ACTIVE, I_IST, I_CODES,
    Z_N, Z_M, Z_NF, Z_R, Z_NFZ,
    N_LAY,
) = range(42)  # fmt: skip
ANY_CODE = N_IST  # ist[ANY_CODE]: some joint's displacement is at a box bound (codes set)
N_IST_ALL = N_IST + 1


@njit(cache=True)
def _v1(buf, off, a):
    return buf[off : off + a]


@njit(cache=True)
def _v2(buf, off, a, b):
    return buf[off : off + a * b].reshape((a, b))


@njit(cache=True)
def _v3(buf, off, a, b, c):
    return buf[off : off + a * b * c].reshape((a, b, c))


@njit(cache=True)
def _active_codes(theta, q_start, bounds, cand, codes):
    """``limits.active_codes``: per joint 0 inside, else ``1 + 2·source + side`` (the
    candidate that sets the bound; a joint at both bounds counts as max); True when any
    joint is at a bound."""
    n = theta.shape[0]
    found = False
    for j in range(n):
        d = theta[j] - q_start[j]
        tol = 1e-10 + 1e-9 * abs(d)
        code = 0
        for side in range(2):
            at = d <= bounds[0, j] + tol if side == 0 else d >= bounds[1, j] - tol
            if at:
                src, best = 0, cand[0, side, j]
                for s in range(1, 4):
                    if cand[s, side, j] < best:
                        src, best = s, cand[s, side, j]
                code = 1 + 2 * src + side
        codes[j] = code
        found = found or code != 0
    return found


@njit(cache=True)
def newton_cycle(kb, kj, ends, boxc, ow, opush, ojac, ojtj, fw, iw, lay):
    """Run Newton iterations of one cycle from ``ist[PHASE]`` until done or Python is
    needed (returns the status; see the module docstring). The arrays are views of the
    workspaces ``fw`` (float) and ``iw`` (int) cut by the layout ``lay`` (the driver's
    ``accel.Workspace`` cuts the same). The step is solved on the reduced problem
    ``Vr, Jr, Fr, Hr, Ar, bound_r`` (the free joints under FREEZE; without frozen joints
    the layout points them at the full arrays). When the cycle is done, also the active
    codes (``iw`` at ``I_CODES``, ``ist[ANY_CODE]``)."""
    n, m, nf, r, nfz = lay[Z_N], lay[Z_M], lay[Z_NF], lay[Z_R], lay[Z_NFZ]
    nz = max(nf - m, 0)
    nc = 2 * nf + r
    V = _v2(fw, lay[F_V], NV, n)
    bounds = _v2(fw, lay[F_BOUNDS], 2, n)
    cand = _v3(fw, lay[F_CAND], 4, 2, n)
    ist = _v1(iw, lay[I_IST], N_IST_ALL)
    target = _v2(fw, lay[F_TARGET], 4, 4)
    frames, tcp = _v3(fw, lay[F_FRAMES], n + 1, 4, 4), _v2(fw, lay[F_TCP], 4, 4)
    J6, Jt, F = _v2(fw, lay[F_J6], 6, n), _v2(fw, lay[F_JT], m, n), _v1(fw, lay[F_F], m)
    rows = _v1(iw, lay[I_ROWS], m)
    A, bound_d = _v2(fw, lay[F_A], r, n), _v1(fw, lay[F_BOUND_D], r)
    H = _v2(fw, lay[F_H], n, n)
    free, fz = _v1(iw, lay[I_FREE], nf), _v1(iw, lay[I_FZ], nfz)
    ftarget = _v1(fw, lay[F_FTARGET], nfz)
    Vr, Jr, Fr = _v2(fw, lay[F_VR], NV, nf), _v2(fw, lay[F_JR], m, nf), _v1(fw, lay[F_FR], m)
    Hr, Ar = _v2(fw, lay[F_HR], nf, nf), _v2(fw, lay[F_AR], r, nf)
    bound_r = _v1(fw, lay[F_BOUND_R], r)
    perm, aug = _v1(iw, lay[I_PERM], nf), _v2(fw, lay[F_AUG], m, nf + 1)
    N, Ht, gt = _v2(fw, lay[F_N], nf, nz), _v2(fw, lay[F_HT], nz, nz), _v1(fw, lay[F_GT], nz)
    Ct, bt = _v2(fw, lay[F_CT], nz, nc), _v1(fw, lay[F_BT], nc)
    Hrel, grel = _v2(fw, lay[F_HREL], nf, nf), _v1(fw, lay[F_GREL], nf)
    active, mult = _v1(iw, lay[I_ACTIVE], nc), _v1(fw, lay[F_MULT], nc)
    fst = _v1(fw, lay[F_FST], N_FST)
    codes = _v1(iw, lay[I_CODES], n)
    general = ist[GENERAL] != 0
    local = np.empty((4, 4))
    phase = ist[PHASE]
    stage = 0  # 0 evaluate, 1 split, 2 relax, 3 apply, 4 build the step's data
    if phase == P_START:
        if ist[BOX_READY] == 0 and not _box(
            boxc, ist[ACCEL_BOUNDED] != 0, fst[DTOL], V[Q_START], V[Q_PREV], cand, bounds
        ):
            return S_BOX_CHECK
        for j in range(n):
            t = V[Q_START, j]
            if ist[WARM] != 0 and ist[SELF_MOTION] == 0:
                d = t - V[Q_PREV, j]
                d = max(d, bounds[0, j])
                d = min(d, bounds[1, j])
                t += d
            V[THETA, j] = t
        if ist[WARM] != 0 and ist[SELF_MOTION] == 0:
            for i in range(nfz):  # frozen joints: no repeated displacement
                V[THETA, fz[i]] = V[Q_START, fz[i]] + 0.0
        ist[K] = 0
        ist[RELAXED] = 0
        ist[SINGULAR] = 0
        ist[HAVE_J] = 0
        ist[N_ACTIVE] = 0
    elif phase == P_APPLY_Z:
        for j in range(nf):
            s = Vr[DP, j]
            for a in range(nz):
                s += N[j, a] * Vr[Z, a]
            Vr[DTHETA, j] = s
        stage = 3
    elif phase == P_APPLY:
        stage = 3
    elif phase == P_SPLIT:
        stage = 1
    elif phase == P_TERMS:
        stage = 4
    else:
        stage = 2
    while True:
        if stage == 0:
            k = ist[K]
            _evaluate(kb, kj, ends, target, frames, local, tcp, rows, V, ist, fst)
            if k >= 1:
                if (fst[PE] < fst[TOL_P] and fst[OE] < fst[TOL_O]) or k >= ist[MAX_ITER]:
                    ist[ANY_CODE] = _active_codes(V[THETA], V[Q_START], bounds, cand, codes)
                    return S_DONE
                if ist[RELAXED] != 0:
                    dmax = 0.0
                    tmax = 0.0
                    for j in range(n):
                        dmax = max(dmax, abs(V[DTHETA, j]))
                        tmax = max(tmax, abs(V[THETA, j]))
                    if dmax <= 1e-13 * (1.0 + tmax):
                        ist[ANY_CODE] = _active_codes(V[THETA], V[Q_START], bounds, cand, codes)
                        return S_DONE
            elif ist[NEED_TERMS] != 0:  # obstacle terms at the first iterate: Python
                ist[PHASE] = P_TERMS
                return S_NEED_TERMS
            stage = 4
        elif stage == 4:
            k = ist[K]
            general = ist[GENERAL] != 0
            zero_f = k == 0 and ist[SELF_MOTION] != 0
            for i in range(m):
                F[i] = 0.0 if zero_f else fst[E0 + rows[i]]
            _jacobian(frames, kj, tcp[:3, 3], J6)
            for i in range(m):
                for j in range(n):
                    Jt[i, j] = J6[rows[i], j]
            ist[HAVE_J] = 1
            for j in range(n):
                sig = V[THETA, j] - V[Q_START, j]
                V[SIGMA, j] = sig
                if ist[HAS_REF] != 0:
                    V[G, j] = V[W, j] * (V[THETA, j] - V[REF, j])
                else:
                    V[G, j] = V[W, j] * sig
                V[LOWER, j] = bounds[0, j] - sig
                V[UPPER, j] = bounds[1, j] - sig
            if general:
                _general_cost(V, H, ow, opush, ojac, ojtj)
            if nfz > 0 and not _reduce(
                V, Jt, F, H, A, bound_d, free, fz, ftarget, Vr, Jr, Fr, Hr, Ar, bound_r
            ):
                return S_FROZEN_FAR
            ist[BASIS_STAGE] = 0
            fst[COND_LIMIT] = fst[COND_MAX]
            stage = 2 if ist[RELAXED] != 0 else 1
        elif stage == 1:
            ist[LAST_SINGULAR] = 0
            if ist[BASIS_VALID] == 0:
                ist[BASIS_REASON] = 0
                return S_NEED_BASIS
            if not _split(Jr, Fr, perm, aug, N, Vr[DP], fst):
                if ist[BASIS_STAGE] == 0:
                    ist[BASIS_REASON] = 1
                    return S_NEED_BASIS
                ist[LAST_SINGULAR] = 1
                stage = 2
                continue
            res = 2
            if nz == 0:
                res = 1 if _checked(Vr, Ar, bound_r, active, mult, ist) else 0
            elif nz == 1 and Ar.shape[0] == 0 and ist[SCALAR] != 0 and not general:
                res = _scalar_qp(Vr, N, active, mult, ist)
                if res < 0:
                    res = 2
            if res == 2:
                if general:
                    _hard_data_general(Vr, N, Hr, Ar, bound_r, Ht, gt, Ct, bt, fst)
                else:
                    _hard_data(Vr, N, perm, m, Ar, bound_r, Ht, gt, Ct, bt, fst)
                if not _unconstrained_qp(Ht, gt, Ct, bt, Vr[Z]):
                    return S_NEED_QP
                ist[N_ACTIVE] = 0
                for j in range(nf):
                    s = Vr[DP, j]
                    for a in range(nz):
                        s += N[j, a] * Vr[Z, a]
                    Vr[DTHETA, j] = s
                res = 1
            stage = 3 if res == 1 else 2
        elif stage == 2:
            _relaxed_data(Vr, Jr, Fr, Ar, bound_r, Hr, general, Hrel, grel, bt, fst)
            return S_NEED_RELAXED
        else:  # apply the step in Vr[DTHETA] (scattered to V[DTHETA] under FREEZE)
            if nfz > 0:
                for a in range(nf):
                    V[DTHETA, free[a]] = Vr[DTHETA, a]
                for i in range(nfz):
                    V[DTHETA, fz[i]] = V[CFZ, i]
            s = 0.0
            for j in range(n):
                s += V[DTHETA, j] * V[DTHETA, j]
            if not math.isfinite(s):
                return S_BAD_STEP
            for j in range(n):
                V[THETA, j] += V[DTHETA, j]
            ist[K] += 1
            stage = 0
