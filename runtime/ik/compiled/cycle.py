"""The fused IK cycle (numba): :func:`newton_cycle`, the resumable state machine of the
compiled engine (package doc), with the general cost (``general_cost``: CYCLIC,
``a_conf·W``, obstacle terms; ``metric_cost``: the full metric of ENERGY) and the FREEZE
reduction (``reduce_frozen``) it applies between the kernels of :mod:`.chain`, :mod:`.box`
and :mod:`.qp`.

numba keys the on-disk cache of :func:`newton_cycle` by this file's source only, while
its machine code includes the kernels it calls from the other modules (and the constants
of :mod:`.layout`). :data:`SOURCES_DIGEST` is the digest of those modules' sources
(:func:`sources_digest`); a test compares them, so a change there must be recorded here,
which changes this file and with it the cache key: the cycle is never run from stale
machine code.
"""

from __future__ import annotations

import hashlib
import math
from pathlib import Path

import numpy as np
from irlc.runtime.ik.compiled.box import active_codes, joint_box
from irlc.runtime.ik.compiled.chain import evaluate, tcp_jacobian
from irlc.runtime.ik.compiled.layout import (
    ACCEL_BOUNDED,
    ANY_CODE,
    BASIS_REASON,
    BASIS_STAGE,
    BASIS_VALID,
    BOX_READY,
    CFZ,
    COND_LIMIT,
    COND_MAX,
    DP,
    DTHETA,
    DTOL,
    E0,
    F_A,
    F_AR,
    F_AUG,
    F_BOUND_D,
    F_BOUND_R,
    F_BOUNDS,
    F_BT,
    F_CAND,
    F_CT,
    F_F,
    F_FR,
    F_FRAMES,
    F_FST,
    F_FTARGET,
    F_GREL,
    F_GT,
    F_H,
    F_HR,
    F_HREL,
    F_HT,
    F_J6,
    F_JR,
    F_JT,
    F_MA,
    F_MC,
    F_MULT,
    F_N,
    F_TARGET,
    F_TCP,
    F_V,
    F_VR,
    FULL_METRIC,
    GENERAL,
    HAS_REF,
    HAVE_J,
    I_ACTIVE,
    I_CODES,
    I_FREE,
    I_FZ,
    I_IST,
    I_PERM,
    I_ROWS,
    LAST_SINGULAR,
    LOWER,
    MAX_ITER,
    N_ACTIVE,
    N_FST,
    N_IST_ALL,
    NEED_TERMS,
    NV,
    OE,
    P_APPLY,
    P_APPLY_Z,
    P_SPLIT,
    P_START,
    P_START_CHECKED,
    P_TERMS,
    PE,
    PHASE,
    Q_PREV,
    Q_START,
    REF,
    RELAXED,
    S_BAD_STEP,
    S_BOX_CHECK,
    S_DONE,
    S_FROZEN_FAR,
    S_NEED_BASIS,
    S_NEED_QP,
    S_NEED_RELAXED,
    S_NEED_TERMS,
    S_NOT_FINITE,
    SCALAR,
    SELF_MOTION,
    SIGMA,
    SINGULAR,
    THETA,
    TOL_O,
    TOL_P,
    UPPER,
    WARM,
    WC,
    Z_M,
    Z_N,
    Z_NF,
    Z_NFZ,
    Z_R,
    G,
    K,
    W,
    Z,
)
from irlc.runtime.ik.compiled.qp import (
    hard_data,
    hard_data_general,
    relaxed_data,
    scalar_qp,
    split,
    square_step,
    unconstrained_qp,
)
from numba import njit

# the modules whose code or constants newton_cycle's machine code includes
CALLEES = ("layout", "chain", "box", "qp")
SOURCES_DIGEST = "db314fe06d54eb9c"  # sources_digest() when this file was last updated


def sources_digest() -> str:
    """SHA-256 (first 16 hex digits) of the sources of :data:`CALLEES`, in that order."""
    h = hashlib.sha256()
    for name in CALLEES:
        h.update(Path(__file__).with_name(f"{name}.py").read_bytes())
    return h.hexdigest()[:16]


@njit(cache=True)
def general_cost(V, H, ow, opush, ojac, ojtj):
    """The full cost of ``InverseTransformation._cost`` (after the criterion's ``g`` in
    ``V[G]``): ``g += a_conf·W∘Σ`` (``V[WC]``), ``H = diag(W + a_conf·W)``, and the
    obstacle terms (:func:`obstacle_cost`)."""
    n = V.shape[1]
    sigma, g = V[SIGMA], V[G]
    for j in range(n):
        g[j] += V[WC, j] * sigma[j]
        for i in range(n):
            H[j, i] = 0.0
        H[j, j] = V[W, j] + V[WC, j]
    obstacle_cost(V, H, ow, opush, ojac, ojtj)


@njit(cache=True)
def metric_cost(V, MA, MC, H, has_ref, ow, opush, ojac, ojtj):
    """The cost with a full metric (``R_CRITERION := 'ENERGY'``, :mod:`criteria`):
    ``g = MA·x + MC·Σ`` (``x = θ − θ⁰`` with a reference, else ``Σ``), ``H = MA + MC``,
    and the obstacle terms (:func:`obstacle_cost`)."""
    n = V.shape[1]
    sigma, g = V[SIGMA], V[G]
    for j in range(n):
        s = 0.0
        for i in range(n):
            x = V[THETA, i] - V[REF, i] if has_ref else sigma[i]
            s += MA[j, i] * x + MC[j, i] * sigma[i]
            H[j, i] = MA[j, i] + MC[j, i]
        g[j] = s
    obstacle_cost(V, H, ow, opush, ojac, ojtj)


@njit(cache=True)
def obstacle_cost(V, H, ow, opush, ojac, ojtj):
    """Per obstacle term ``t`` (:class:`obstacle.ObstacleTerm`, weight ``ω_t ≠ 0``):
    ``g −= ω_t·J_tᵀ(αv_t − J_tΣ)``, ``H += ω_t·J_tᵀJ_t``."""
    n = V.shape[1]
    sigma, g = V[SIGMA], V[G]
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
def reduce_frozen(V, Jt, F, H, A, bound_d, free, fz, ftarget, Vr, Jr, Fr, Hr, Ar, bound_r):
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
def apply_z(Vr, N, nf, nz):
    """The step from the QP's solution: ``Δθ = Δθ_p + N z`` (particular plus null space)."""
    for j in range(nf):
        s = Vr[DP, j]
        for a in range(nz):
            s += N[j, a] * Vr[Z, a]
        Vr[DTHETA, j] = s


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
def inputs_finite(q_start, target):
    """``InverseTransformation.step``'s first test: ``q_start·q_start`` and the sum of the
    target's first three rows are finite (an overflow of ``‖q‖²`` is no configuration:
    the caller then runs the exact check)."""
    s = 0.0
    for j in range(q_start.shape[0]):
        s += q_start[j] * q_start[j]
    t = 0.0
    for i in range(3):
        for j in range(4):
            t += target[i, j]
    return math.isfinite(s) and math.isfinite(t)


@njit(cache=True)
def newton_cycle(kb, kj, ends, boxc, ow, opush, ojac, ojtj, fw, iw, lay):
    """Run Newton iterations of one cycle from ``ist[PHASE]`` until done or Python is
    needed (returns the status; see the module docstring). At ``P_START`` the cycle's
    inputs (``V[Q_START]``, the target) are first tested (:func:`inputs_finite`;
    ``S_NOT_FINITE``: Python checks them exactly and resumes with ``P_START_CHECKED``).
    The arrays are views of the workspaces ``fw`` (float) and ``iw`` (int) cut by the
    layout ``lay`` (the driver's ``Workspace`` cuts the same). The step is solved
    on the reduced problem ``Vr, Jr, Fr, Hr, Ar, bound_r`` (the free joints under FREEZE;
    without frozen joints the layout points them at the full arrays). When the cycle is
    done, also the active codes (``iw`` at ``I_CODES``, ``ist[ANY_CODE]``)."""
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
    MA, MC = _v2(fw, lay[F_MA], n, n), _v2(fw, lay[F_MC], n, n)
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
    if phase in (P_START, P_START_CHECKED):
        if phase == P_START and not inputs_finite(V[Q_START], target):
            return S_NOT_FINITE
        if ist[BOX_READY] == 0 and not joint_box(
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
        apply_z(Vr, N, nf, nz)
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
            evaluate(kb, kj, ends, target, frames, local, tcp, rows, V, ist, fst)
            if k >= 1:
                if (fst[PE] < fst[TOL_P] and fst[OE] < fst[TOL_O]) or k >= ist[MAX_ITER]:
                    ist[ANY_CODE] = active_codes(V[THETA], V[Q_START], bounds, cand, codes)
                    return S_DONE
                if ist[RELAXED] != 0:
                    dmax = 0.0
                    tmax = 0.0
                    for j in range(n):
                        dmax = max(dmax, abs(V[DTHETA, j]))
                        tmax = max(tmax, abs(V[THETA, j]))
                    if dmax <= 1e-13 * (1.0 + tmax):
                        ist[ANY_CODE] = active_codes(V[THETA], V[Q_START], bounds, cand, codes)
                        return S_DONE
            elif ist[NEED_TERMS] != 0:  # obstacle terms at the first iterate: Python
                ist[PHASE] = P_TERMS
                return S_NEED_TERMS
            stage = 4
        elif stage == 4:
            k = ist[K]
            general = ist[GENERAL] != 0
            full = ist[FULL_METRIC] != 0
            zero_f = k == 0 and ist[SELF_MOTION] != 0
            for i in range(m):
                F[i] = 0.0 if zero_f else fst[E0 + rows[i]]
            tcp_jacobian(frames, kj, tcp[:3, 3], J6)
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
            if full:
                metric_cost(V, MA, MC, H, ist[HAS_REF] != 0, ow, opush, ojac, ojtj)
            elif general:
                general_cost(V, H, ow, opush, ojac, ojtj)
            if nfz > 0 and not reduce_frozen(
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
            if not split(Jr, Fr, perm, aug, N, Vr[DP], fst):
                if ist[BASIS_STAGE] == 0:
                    ist[BASIS_REASON] = 1
                    return S_NEED_BASIS
                ist[LAST_SINGULAR] = 1
                stage = 2
                continue
            res = 2
            if nz == 0:
                res = 1 if square_step(Vr, Ar, bound_r, active, mult, ist) else 0
            elif nz == 1 and Ar.shape[0] == 0 and ist[SCALAR] != 0 and not general:
                res = scalar_qp(Vr, N, active, mult, ist)
                if res < 0:
                    res = 2
            if res == 2:
                if general:
                    hard_data_general(Vr, N, Hr, Ar, bound_r, Ht, gt, Ct, bt, fst)
                else:
                    hard_data(Vr, N, perm, m, Ar, bound_r, Ht, gt, Ct, bt, fst)
                if not unconstrained_qp(Ht, gt, Ct, bt, Vr[Z]):
                    return S_NEED_QP
                ist[N_ACTIVE] = 0
                apply_z(Vr, N, nf, nz)
                res = 1
            stage = 3 if res == 1 else 2
        elif stage == 2:
            relaxed_data(Vr, Jr, Fr, Ar, bound_r, Hr, general, Hrel, grel, bt, fst)
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
