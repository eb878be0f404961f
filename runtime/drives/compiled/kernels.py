"""Compiled kernel (numba) of the averaged DC drive loop — the numbers of the numpy path,
fused.

Loaded by :mod:`.loop` when the compiled engine runs. :func:`run_segment` runs the
steps of :meth:`irlc.runtime.drives.simulate._Simulation.run` from ``start`` until the
held ``M``, ``C q̇ + G`` are due for a refresh (:mod:`..refresh`) or the run ends, and
returns that step, or (coupled level, ``ist[INNER]``) refreshes them itself with
:func:`coupled_terms` — link frames (``ik.compiled.chain.forward_chain``), :func:`mass_and_bias`,
the rotor matrix ``Kᵀ diag(J_m) K``, ``M⁻¹`` (:func:`invert`) — and goes on, so that the
whole run is one call; at the decoupled level the caller refreshes ``G(q)`` in numpy and
resumes. Per step, the same arithmetic as its numpy reference
(named in each docstring), written as loops over the axes:

* transmission (:meth:`..transmission.Transmission.motor_and_jacobian`): ``θ_m = L q`` plus
  the screw-lever rows, ``K`` likewise, ``ω_m = K q̇``;
* the cascade (:class:`..cascade.DcBank`): the fused linear map ``G`` when no limit is
  reached, else P → PI (conditional integration) → current loop → averaged stage with
  the closed-form armature at ``±U`` (:func:`..motor.first_order`) and the current clamp
  (:func:`..power_stage.averaged`), per axis;
* friction and mechanics (:meth:`..mechanics.Mechanics.accel`): ``q̈ = M⁻¹ (T − f − h)``,
  or Karnopp's two passes with the reduced system ``M_ff q̈_f = T_f − f_f − h_f`` solved by
  Gaussian elimination with partial pivoting (numpy: the cached inverse of ``M_ff``);
* semi-implicit Euler ``q̇ += h q̈`` (stuck axes ``q̇ := 0``), ``q += h q̇``.

Packed arguments (indices below): ``ist`` integers, ``fst`` floats, ``par`` per-axis
constants ``(m, N_PAR)``.
"""

from __future__ import annotations

import math

import numpy as np
from irlc.runtime.drives.transmission import (
    LEVER_AB2,
    LEVER_GAIN,
    LEVER_PHI0,
    LEVER_S0,
    LEVER_SQ,
)
from irlc.runtime.ik.compiled.chain import forward_chain
from numba import njit

# numba's cache of a function is keyed by its own source file: run_segment's machine code
# includes ik/compiled/chain.forward_chain, so this digest of its source
# (chain_source_digest(), checked by tests/drives/test_compiled_kernels.py) changes this file
# when forward_chain changes.
CHAIN_SOURCE_DIGEST = "8dbd1c064aac15bf"


def chain_source_digest() -> str:
    """SHA-256 (first 16 hex digits) of the source of ``ik.compiled.chain.forward_chain``."""
    import hashlib
    import inspect

    return hashlib.sha256(inspect.getsource(forward_chain.py_func).encode()).hexdigest()[:16]


# ist (INNER: 1 = refresh the coupled terms inside run_segment, ROTOR: add Kᵀ diag(J_m) K,
# COUNT: refreshes done inside)
START, STEPS, EVERY, MAX_STEPS, S0, FRESH, STICKY, SLIDING, INNER, ROTOR, COUNT = range(11)
N_IST = 11
# fst
H, DQ, DV = range(3)
N_FST = 3
# par (per axis)
KZ, KE, KP, KI, ULIM, R, L, KS, U, IMAX, RUN_M, VISC_M, BAND = range(13)
N_PAR = 13
# lev (per screw-lever row): the columns of TransmissionData.lever
LEV_SQ, LEV_AB2, LEV_PHI0, LEV_GAIN, LEV_S0 = (
    LEVER_SQ, LEVER_AB2, LEVER_PHI0, LEVER_GAIN, LEVER_S0
)  # fmt: skip


@njit(cache=True)
def sign(x):
    return (x > 0.0) - (x < 0.0)


@njit(cache=True)
def clip(x, lo, hi):
    return min(max(x, lo), hi)


@njit(cache=True)
def first_order(i0, volts, omega, r, ell, ks, tau, i_max, res):
    """``motor.first_order`` for one axis: ``res = [i(τ), ∫i, ∫i², ∫u i]``."""
    a = (volts - ks * omega) / r
    big_t = ell / r
    d = i0 - a
    decay = math.exp(-tau / big_t)
    end = a + d * decay
    if abs(end) <= i_max:
        one = big_t * (1.0 - decay)
        area = a * tau + d * one
        res[0] = end
        res[1] = area
        res[2] = a * a * tau + 2.0 * a * d * one + d * d * 0.5 * big_t * (1.0 - decay * decay)
        res[3] = volts * area
        return
    side = sign(a)
    ratio = 0.0
    if abs(a) > i_max and d != 0.0:
        ratio = (side * i_max - a) / d
    t1 = min(tau, -big_t * math.log(clip(ratio, 1e-300, 1.0)))
    t2 = tau - t1
    decay = math.exp(-t1 / big_t)
    one = big_t * (1.0 - decay)
    area1 = a * t1 + d * one
    square1 = a * a * t1 + 2.0 * a * d * one + d * d * 0.5 * big_t * (1.0 - decay * decay)
    held = side * i_max
    res[0] = held if t2 > 0.0 else a + d * decay
    res[1] = area1 + held * t2
    res[2] = square1 + i_max * i_max * t2
    res[3] = volts * area1 + (r * held + ks * omega) * held * t2


@njit(cache=True)
def axis_step(a, d, omega, p, fused, lim5, big, xv, xi, xu, h, out, res):
    """One DC axis: ``out = [τ_m, ī, ū, saturated, ∫u i, ∫R i²]``; updates ``xv, xi, xu``."""
    z0, z1, z2, z3, z4 = d, omega, xv[a], xi[a], xu[a]
    g = fused[a]
    ok = True
    vals = np.empty(7)
    for r in range(7):
        v = g[r, 0] * z0 + g[r, 1] * z1 + g[r, 2] * z2 + g[r, 3] * z3 + g[r, 4] * z4
        vals[r] = v
        if r < 5 and abs(v) > lim5[a, r]:
            ok = False
    if ok:  # cascade.fused_matrix rows [u_ω, u_i, u_end, i_end, ī, x_v', ū]
        xv[a], xu[a], xi[a] = vals[5], vals[2], vals[3]
        i_mean, u_mean = vals[4], vals[6]
        out[0], out[1], out[2], out[3] = p[a, KS] * i_mean, i_mean, u_mean, 0.0
        out[4], out[5] = u_mean * i_mean * h, p[a, R] * i_mean * i_mean * h
        return
    lim = p[a, ULIM]
    raw = p[a, KZ] * d  # position.position_p
    u_w = clip(raw, -lim, lim)
    sat = u_w != raw
    e = u_w - p[a, KE] * omega  # velocity.VelocityPI.step
    raw = p[a, KP] * e + p[a, KI] * xv[a]
    u_i = clip(raw, -lim, lim)
    if u_i != raw:
        sat = True
        if sign(e) != sign(raw):
            xv[a] += h * e
    else:
        xv[a] += h * e
    i0 = xi[a]  # power_stage.averaged
    bg = big[a]
    x_i = bg[0, 0] * i0 + bg[0, 1] * xu[a] + bg[0, 2] * u_i + bg[0, 3] * omega
    x_u = bg[1, 0] * i0 + bg[1, 1] * xu[a] + bg[1, 2] * u_i + bg[1, 3] * omega
    i_mean = bg[2, 0] * i0 + bg[2, 1] * xu[a] + bg[2, 2] * u_i + bg[2, 3] * omega
    u_mean = bg[3, 0] * i0 + bg[3, 1] * xu[a] + bg[3, 2] * u_i + bg[3, 3] * omega
    i_max, r_a = p[a, IMAX], p[a, R]
    over = abs(x_u) > p[a, U]
    if over:
        volts = sign(x_u) * p[a, U]
        first_order(i0, volts, omega, r_a, p[a, L], p[a, KS], h, i_max, res)
        x_i, x_u, i_mean, u_mean = res[0], volts, res[1] / h, volts
    limit = abs(x_i) > i_max or abs(i_mean) > i_max
    if limit:
        x_i = clip(x_i, -i_max, i_max)
        i_mean = clip(i_mean, -i_max, i_max)
        u_mean = r_a * i_mean + p[a, KS] * omega + p[a, L] * (x_i - i0) / h
    xi[a], xu[a] = x_i, x_u
    energy = u_mean * i_mean * h
    copper = r_a * i_mean * i_mean * h
    if over and not limit:
        energy, copper = res[3], r_a * res[2]
    out[0], out[1], out[2] = p[a, KS] * i_mean, i_mean, u_mean
    out[3] = 1.0 if (sat or over or limit) else 0.0
    out[4], out[5] = energy, copper


@njit(cache=True)
def pivot(work, c, rows, width):
    """Partial pivoting at column ``c`` of ``work[:rows, :width]``: the row of ``c`` … ``rows
    − 1`` with the largest ``|work[r, c]|`` swapped into row ``c`` (columns ``c`` on)."""
    piv = c
    for r in range(c + 1, rows):
        if abs(work[r, c]) > abs(work[piv, c]):
            piv = r
    if piv != c:
        for j in range(c, width):
            work[c, j], work[piv, j] = work[piv, j], work[c, j]


@njit(cache=True)
def solve_free(mm, free, nf, rhs, qdd, work):
    """``q̈_f = M_ff⁻¹ rhs_f`` (Gaussian elimination, partial pivoting), ``q̈`` 0 elsewhere."""
    n = mm.shape[0]
    for i in range(n):
        qdd[i] = 0.0
    for i in range(nf):
        for j in range(nf):
            work[i, j] = mm[free[i], free[j]]
        work[i, nf] = rhs[free[i]]
    for c in range(nf):
        pivot(work, c, nf, nf + 1)
        for r in range(c + 1, nf):
            f = work[r, c] / work[c, c]
            for j in range(c, nf + 1):
                work[r, j] -= f * work[c, j]
    for i in range(nf - 1, -1, -1):
        acc = work[i, nf]
        for j in range(i + 1, nf):
            acc -= work[i, j] * qdd[free[j]]
        qdd[free[i]] = acc / work[i, i]


@njit(cache=True)
def karnopp(mm, hb, drive, slide, stuck, static, running, qdd, fric, free, work, base, rhs):
    """``Mechanics._karnopp``: two passes; ``stuck`` becomes the final held set."""
    n = mm.shape[0]
    for i in range(n):
        fric[i] = slide[i]
        base[i] = drive[i] - hb[i]
    for _ in range(2):
        nf = 0
        for i in range(n):
            rhs[i] = base[i] - fric[i]
            if not stuck[i]:
                free[nf] = i
                nf += 1
        solve_free(mm, free, nf, rhs, qdd, work)
        broke = False
        for i in range(n):
            if stuck[i]:
                need = base[i]
                for j in range(n):
                    need -= mm[i, j] * qdd[j]
                if abs(need) <= static[i]:
                    fric[i] = need
                else:
                    fric[i] = running[i] * sign(need)
                    rhs[i] = 1.0  # (marks a break-away)
                    broke = True
                    continue
            rhs[i] = 0.0
        if not broke:
            return
        for i in range(n):  # the broken ones leave the stuck set
            if rhs[i] == 1.0:
                stuck[i] = False


@njit(cache=True)
def refresh_due(s, q, qd, q0, qd0, ist, fst):
    """``Refresh.due``."""
    if ist[EVERY] > 0:
        return s % ist[EVERY] == 0
    if s - ist[S0] >= ist[MAX_STEPS]:
        return True
    dq = 0.0
    dv = 0.0
    for j in range(q.shape[0]):
        dq = max(dq, abs(q[j] - q0[j]))
        dv = max(dv, abs(qd[j] - qd0[j]))
    return dq > fst[DQ] or dv > fst[DV]


@njit(cache=True)
def motor_and_jacobian(lin, rows, coef, lev, q, theta, kmat):
    """``Transmission.motor_and_jacobian`` on :class:`TransmissionData`'s arrays:
    ``θ_m = L q`` and ``K = L``, then the screw-lever rows ``θ_m = gain (s − s0)``,
    ``K = gain·½·2ab·sin(φ + φ0)/s · C``."""
    m, n = lin.shape
    for a in range(m):
        acc = 0.0
        for j in range(n):
            kmat[a, j] = lin[a, j]
            acc += q[j] * lin[a, j]
        theta[a] = acc
    for r in range(rows.shape[0]):
        a = rows[r]
        v = lev[r, LEV_PHI0]
        for j in range(n):
            v += coef[r, j] * q[j]
        sq = math.sqrt(lev[r, LEV_SQ] - lev[r, LEV_AB2] * math.cos(v))
        theta[a] = lev[r, LEV_GAIN] * (sq - lev[r, LEV_S0])
        dk = lev[r, LEV_GAIN] * 0.5 * lev[r, LEV_AB2] * math.sin(v) / sq
        for j in range(n):
            kmat[a, j] = dk * coef[r, j]


@njit(cache=True)
def _cross_into(a, b, out):
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]


@njit(cache=True)
def mass_and_bias(frames, axes, revolute, rotor, mass, com, inertia, gravity, qd, M, h):
    """``Dynamics.mass_and_bias`` on :class:`~irlc.runtime.model.dynamics.DynamicsData` and the
    link frames (``Kinematics.chain``): ``M = Σ m_i J_viᵀJ_vi + J_ωiᵀ I_i J_ωi + diag(J_r)``
    (``J_vi`` columns ``z_j × (c_i − P_j)`` revolute / ``z_j`` prismatic, ``J_ωi`` columns
    ``z_j``, ``j ≤ i``) and ``h = C q̇ + G`` by the RNEA of :mod:`irlc.runtime.model.dynamics`
    with ``q̈ = 0`` and ``a_0 = −g``."""
    n = qd.shape[0]
    p = np.empty((n, 3))
    z = np.empty((n, 3))
    c = np.empty((n, 3))
    ii = np.empty((n, 3, 3))
    for i in range(n):
        f = frames[i + 1]
        for r in range(3):
            p[i, r] = f[r, 3]
            z[i, r] = f[r, 0] * axes[i, 0] + f[r, 1] * axes[i, 1] + f[r, 2] * axes[i, 2]
            c[i, r] = f[r, 3] + f[r, 0] * com[i, 0] + f[r, 1] * com[i, 1] + f[r, 2] * com[i, 2]
        for a in range(3):
            for b in range(3):
                s = 0.0
                for k in range(3):
                    t = 0.0
                    for m in range(3):
                        t += inertia[i, k, m] * f[b, m]
                    s += f[a, k] * t
                ii[i, a, b] = s
    # mass matrix, Jacobian form: column j of link i's J_v and J_ω
    jv = np.zeros((n, 3, n))
    jw = np.zeros((n, 3, n))
    d = np.empty(3)
    col = np.empty(3)
    for i in range(n):
        for j in range(i + 1):
            if revolute[j] != 0.0:
                for r in range(3):
                    d[r] = c[i, r] - p[j, r]
                _cross_into(z[j], d, col)
                for r in range(3):
                    jv[i, r, j] = col[r]
                    jw[i, r, j] = z[j, r]
            else:
                for r in range(3):
                    jv[i, r, j] = z[j, r]
    iw = np.empty(3)
    for a in range(n):
        for b in range(a, n):
            s = 0.0
            for i in range(max(a, b), n):
                lin = 0.0
                for r in range(3):
                    lin += jv[i, r, a] * jv[i, r, b]
                ang = 0.0
                for r in range(3):
                    t = 0.0
                    for k in range(3):
                        t += ii[i, r, k] * jw[i, k, b]
                    ang += jw[i, r, a] * t
                s += mass[i] * lin + ang
            M[a, b] = s
            M[b, a] = s
        M[a, a] += rotor[a]
    # bias: RNEA with q̈ = 0, a_0 = −g
    w = np.zeros(3)
    alpha = np.zeros(3)
    acc = np.empty(3)
    for r in range(3):
        acc[r] = -gravity[r]
    prev = frames[0, :3, 3].copy()
    ac = np.empty((n, 3))
    ws = np.empty((n, 3))
    als = np.empty((n, 3))
    t1 = np.empty(3)
    t2 = np.empty(3)
    for i in range(n):
        for r in range(3):
            d[r] = p[i, r] - prev[r]
        _cross_into(alpha, d, t1)
        _cross_into(w, d, col)
        _cross_into(w, col, t2)
        for r in range(3):
            acc[r] += t1[r] + t2[r]
        for r in range(3):
            col[r] = z[i, r] * qd[i]
        _cross_into(w, col, t1)
        if revolute[i] != 0.0:
            for r in range(3):
                alpha[r] += t1[r]
                w[r] += col[r]
        else:
            for r in range(3):
                acc[r] += 2.0 * t1[r]
        for r in range(3):
            d[r] = c[i, r] - p[i, r]
        _cross_into(alpha, d, t1)
        _cross_into(w, d, col)
        _cross_into(w, col, t2)
        for r in range(3):
            ac[i, r] = acc[r] + t1[r] + t2[r]
            ws[i, r] = w[r]
            als[i, r] = alpha[r]
            prev[r] = p[i, r]
    force = np.zeros(3)
    mom = np.zeros(3)
    fi = np.empty(3)
    for i in range(n - 1, -1, -1):
        if i < n - 1:  # r_{i+1} × f_{i+1}
            for r in range(3):
                d[r] = p[i + 1, r] - p[i, r]
            _cross_into(d, force, t1)
            for r in range(3):
                mom[r] += t1[r]
        for r in range(3):
            fi[r] = mass[i] * ac[i, r]
            d[r] = c[i, r] - p[i, r]
        _cross_into(d, fi, t1)
        for r in range(3):
            iw[r] = ii[i, r, 0] * ws[i, 0] + ii[i, r, 1] * ws[i, 1] + ii[i, r, 2] * ws[i, 2]
        _cross_into(ws[i], iw, t2)
        for r in range(3):
            ia = ii[i, r, 0] * als[i, 0] + ii[i, r, 1] * als[i, 1] + ii[i, r, 2] * als[i, 2]
            mom[r] += t1[r] + ia + t2[r]
            force[r] += fi[r]
        if revolute[i] != 0.0:
            h[i] = z[i, 0] * mom[0] + z[i, 1] * mom[1] + z[i, 2] * mom[2]
        else:
            h[i] = z[i, 0] * force[0] + z[i, 1] * force[1] + z[i, 2] * force[2]


@njit(cache=True)
def run_segment(
    ist, fst, par, fused, lim5, big, theta_ref, lin, rows, coef, lev, static_j, running_j,
    q, qd, xv, xi, xu, mm, hb, m_inv, q0, qd0,
    rec_q, rec_qd, rec_tau, rec_f, rec_i, rec_u, rec_sat, energy, copper, terms,
):  # fmt: skip
    """Run steps from ``ist[START]`` until a refresh is due (returns that step) or the end
    (returns ``ist[STEPS]``). ``ist[FRESH] = 1``: the terms were just refreshed at START.
    ``ist[INNER] = 1`` (coupled level): refresh inside instead of returning —
    :func:`coupled_terms` on ``terms = (chain, dyn, J_m)`` (``ist[ROTOR]``: with the rotor
    matrix), then ``Refresh.mark`` (``q0, q̇0 = q, q̇``, ``ist[S0] = s``, ``ist[COUNT] += 1``)
    — so that the whole run is one call."""
    n = q.shape[0]
    m = xv.shape[0]
    h = fst[H]
    sticky = ist[STICKY] != 0
    sliding = ist[SLIDING] != 0
    theta = np.empty(m)
    kmat = np.empty((m, n))
    omega = np.empty(m)
    tau_m = np.empty(m)
    f_m = np.zeros(m)
    stuck = np.zeros(n, dtype=np.bool_)
    scratch = joint_scratch(n)
    rec = (rec_q, rec_qd, rec_tau, rec_f)
    out = np.empty(6)
    res = np.empty(4)
    inner = ist[INNER] != 0
    chain, dyn, j_m = terms
    trans = (lin, rows, coef, lev)
    # (θ_m and K are recomputed right after a refresh: the step's buffers serve it too)
    buf = (np.empty((n + 1, 4, 4)), np.empty((4, 4)), theta, kmat, np.empty((n, 2 * n)))
    for s in range(ist[START], ist[STEPS]):
        if not (s == ist[START] and ist[FRESH] != 0) and refresh_due(s, q, qd, q0, qd0, ist, fst):
            if not inner:
                return s
            coupled_terms(chain, dyn, trans, j_m, ist[ROTOR] != 0, q, qd, mm, hb, m_inv, buf)
            for j in range(n):
                q0[j], qd0[j] = q[j], qd[j]
            ist[S0] = s
            ist[COUNT] += 1
        motor_and_jacobian(lin, rows, coef, lev, q, theta, kmat)  # θ_m, K(q)
        any_stuck = False
        for a in range(m):
            acc = 0.0
            for j in range(n):
                acc += kmat[a, j] * qd[j]
            omega[a] = acc
            axis_step(
                a, theta_ref[s, a] - theta[a], acc, par, fused, lim5, big, xv, xi, xu, h,
                out, res,
            )  # fmt: skip
            tau_m[a] = out[0]
            rec_i[s, a], rec_u[s, a], rec_sat[s, a] = out[1], out[2], out[3] != 0.0
            energy[a] += out[4]
            copper[a] += out[5]
            if sliding:
                f_m[a] = par[a, RUN_M] * sign(acc) + par[a, VISC_M] * acc
            if sticky:
                stuck[a] = abs(acc) < par[a, BAND]
                any_stuck = any_stuck or stuck[a]
        joint_step(
            s, h, kmat, tau_m, f_m, sliding, any_stuck, stuck, mm, hb, m_inv, static_j,
            running_j, q, qd, rec, scratch,
        )  # fmt: skip
    return ist[STEPS]


@njit(cache=True)
def joint_scratch(n):
    """The buffers of :func:`joint_step`: ``(drive, slide, q̈, friction, free, work, base,
    rhs)``."""
    return (
        np.empty(n), np.zeros(n), np.empty(n), np.empty(n), np.empty(n, dtype=np.int64),
        np.empty((n, n + 1)), np.empty(n), np.empty(n),
    )  # fmt: skip


@njit(cache=True)
def joint_step(
    s, h, kmat, tau_m, f_m, sliding, any_stuck, stuck, mm, hb, m_inv, static_j, running_j,
    q, qd, rec, scratch,
):  # fmt: skip
    """The joint side of step ``s``, shared by every drive level's kernel: ``T = Kᵀ τ_m``,
    sliding friction ``f = Kᵀ f_m``; ``q̈ = M⁻¹ (T − f − h)``, or Karnopp's two passes when
    an axis sticks (:func:`karnopp`); the record row ``rec = (q, q̇, T, friction)[s]``; then
    semi-implicit Euler ``q̇ += h q̈`` (stuck: ``q̇ := 0``), ``q += h q̇``.
    ``scratch = (drive, slide, q̈, friction, free, work, base, rhs)``."""
    rec_q, rec_qd, rec_tau, rec_f = rec
    drive, slide, qdd, fric, free, work, base, rhs = scratch
    n = q.shape[0]
    m = tau_m.shape[0]
    for j in range(n):  # joint side: Kᵀ τ_m, Kᵀ f_m
        acc = 0.0
        acc_f = 0.0
        for a in range(m):
            acc += kmat[a, j] * tau_m[a]
            acc_f += kmat[a, j] * f_m[a]
        drive[j] = acc
        if sliding:
            slide[j] = acc_f
    if any_stuck:
        karnopp(mm, hb, drive, slide, stuck, static_j, running_j, qdd, fric, free, work, base, rhs)
    else:
        for i in range(n):
            base[i] = drive[i] - slide[i] - hb[i]
            fric[i] = slide[i]
        for i in range(n):
            acc = 0.0
            for j in range(n):
                acc += m_inv[i, j] * base[j]
            qdd[i] = acc
    for j in range(n):
        rec_tau[s, j], rec_q[s, j], rec_qd[s, j], rec_f[s, j] = drive[j], q[j], qd[j], fric[j]
    for j in range(n):
        qd[j] += h * qdd[j]
        if stuck[j]:
            qd[j] = 0.0
        q[j] += h * qd[j]


@njit(cache=True)
def invert(a, out, work):
    """``out = a⁻¹`` (``np.linalg.inv``): Gauss–Jordan elimination with partial pivoting on
    ``work = [a | I]`` (n × 2n)."""
    n = a.shape[0]
    for i in range(n):
        for j in range(n):
            work[i, j] = a[i, j]
            work[i, n + j] = 1.0 if i == j else 0.0
    for c in range(n):
        pivot(work, c, n, 2 * n)
        inv_p = 1.0 / work[c, c]
        for j in range(c, 2 * n):
            work[c, j] *= inv_p
        for r in range(n):
            if r != c:
                f = work[r, c]
                if f != 0.0:
                    for j in range(c, 2 * n):
                        work[r, j] -= f * work[c, j]
    for i in range(n):
        for j in range(n):
            out[i, j] = work[i, n + j]


@njit(cache=True)
def coupled_terms(chain, dyn, trans, j_m, rotor_matrix, q, qd, mm, hb, m_inv, buf):
    """One refresh of the coupled level (``Mechanics.terms`` + ``Mechanics.inverse``):
    link frames ``T_i = T_{i−1}·L_i`` (``Kinematics.chain`` on :class:`ChainData`
    ``chain = (basis, joints, base)``), ``M(q)`` and ``h = C q̇ + G`` (:func:`mass_and_bias`
    on :class:`DynamicsData` ``dyn``), with ``rotor_matrix`` the rotors of a coupled or
    non-linear transmission ``M += Kᵀ diag(J_m) K`` (``Transmission.rotor_matrix``, ``K``
    from :func:`motor_and_jacobian` on :class:`TransmissionData` ``trans``), then ``M⁻¹``
    (:func:`invert`). ``buf = (frames (n+1, 4, 4), local (4, 4), θ_m (m,), K (m, n),
    work (n, 2n))``."""
    basis, joints, base = chain
    axes, revolute, rotor, mass, com, inertia, gravity = dyn
    frames, local, theta, kmat, work = buf
    forward_chain(basis, joints, base, q, frames, local)
    mass_and_bias(frames, axes, revolute, rotor, mass, com, inertia, gravity, qd, mm, hb)
    if rotor_matrix:
        lin, rows, coef, lev = trans
        motor_and_jacobian(lin, rows, coef, lev, q, theta, kmat)
        n, m = mm.shape[0], kmat.shape[0]
        for i in range(n):
            for j in range(n):
                acc = 0.0
                for a in range(m):
                    acc += kmat[a, i] * j_m[a] * kmat[a, j]
                mm[i, j] += acc
    invert(mm, m_inv, work)
