"""Compiled kernel (numba) of the ``pwm`` drive level — the numbers of the numpy path.

Loaded by :mod:`.pwm_loop` when the compiled engine runs. :func:`run_pwm_segment`
runs the PWM periods of :meth:`irlc.runtime.drives.simulate._Simulation.run` at ``pwm``
(the numpy reference: :class:`..power_stage.PwmStage`) from ``start`` until the held
``M``, ``C q̇ + G`` are due for a refresh (:mod:`..refresh`) or the run ends, and returns
that step; the caller refreshes them and resumes. Per period ``T``, per axis, the
arithmetic of the numpy path (named in each docstring), written as loops:

* position P and velocity PI with conditional integration
  (:meth:`..cascade.DcBank.limited_step`);
* the power stage (:meth:`..power_stage.PwmStage.period`): duty ``d = (1 + u_c/U)/2``
  clipped to ``[0, 1]``, the armature across ``−U`` for ``(1−d)T/2``, ``+U`` for ``dT``,
  ``−U`` for ``(1−d)T/2`` in closed form with the current limit
  (:func:`.kernels.first_order` = :func:`irlc.runtime.drives.motor.first_order`), then
  ``u_c ← sat_{±U}(u_c + kiwzm (u_i T − k ∫ i dt))``;
* transmission, friction, Karnopp, semi-implicit Euler: the helpers of
  :mod:`.kernels`, as in its ``run_segment``.

numba keys the on-disk cache of :func:`run_pwm_segment` by this file's source only, while
its machine code includes the helpers it calls from :mod:`.kernels` (and the lever
column constants of :mod:`..transmission`). :data:`SOURCES_DIGEST` is the digest of those
helpers' sources and constants (:func:`sources_digest`); a test compares them, so a change
there must be recorded here, which changes this file and with it the cache key: the
kernel never runs stale machine code.

Packed arguments (indices below): ``ist`` integers, ``fst`` floats, ``par`` per-axis
constants ``(m, N_PAR)``.
"""

from __future__ import annotations

import hashlib
import inspect

import numpy as np
from irlc.runtime.drives import transmission
from irlc.runtime.drives.compiled.kernels import (  # ist, fst: the layout refresh_due reads
    DQ,
    DV,
    EVERY,
    FRESH,
    MAX_STEPS,
    N_FST,
    N_IST,
    S0,
    SLIDING,
    START,
    STEPS,
    STICKY,
    H,
    clip,
    first_order,
    joint_scratch,
    joint_step,
    karnopp,
    motor_and_jacobian,
    pivot,
    refresh_due,
    sign,
    solve_free,
)
from numba import njit

CALLEES = (
    sign, clip, first_order, pivot, solve_free, karnopp, refresh_due, motor_and_jacobian,
    joint_scratch, joint_step,
)  # fmt: skip
SOURCES_DIGEST = "7e6167bcf4193b34"  # sources_digest() when this file was last updated

# per-axis constants (par columns)
KZ, KE, KP, KI, ULIM, R, L, KS, U, IMAX, KC, KIWZM, RUN_M, VISC_M, BAND = range(15)
N_PAR = 15
LAYOUT = (START, STEPS, EVERY, MAX_STEPS, S0, FRESH, STICKY, SLIDING, N_IST, H, DQ, DV, N_FST)


def sources_digest() -> str:
    """SHA-256 (first 16 hex digits) of the sources of :data:`CALLEES`, the ``ist``/``fst``
    layout (:data:`LAYOUT`) and the lever column constants their machine code freezes."""
    h = hashlib.sha256()
    for f in CALLEES:
        h.update(inspect.getsource(f.py_func).encode())
    levers = (transmission.LEVER_SQ, transmission.LEVER_AB2, transmission.LEVER_PHI0,
              transmission.LEVER_GAIN, transmission.LEVER_S0)  # fmt: skip
    h.update(repr((LAYOUT, levers)).encode())
    return h.hexdigest()[:16]


@njit(cache=True)
def switching_interval(i0, volts, omega, r, ell, ks, tau, i_max, res):
    """One switching interval (:func:`..motor.first_order`): ``res = [i(τ), ∫i, ∫i², ∫u i]``;
    returns True when the current limit was reached inside it (the current then ends at
    exactly ``±i_max``, which the unlimited closed form does not give an axis that ends
    inside the limit)."""
    first_order(i0, volts, omega, r, ell, ks, tau, i_max, res)
    a = (volts - ks * omega) / r
    return abs(a) > i_max and res[0] == sign(a) * i_max


@njit(cache=True)
def _pwm_axis(a, d, omega, p, xv, xi, xc, h, out, res):
    """One DC axis over one PWM period ``h``: ``out = [τ_m, ī, ū, saturated, ∫u i, ∫R i²]``;
    updates the PI integral ``xv``, the current ``xi`` and the controller output ``xc``."""
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
    supply = p[a, U]  # power_stage.PwmStage.period
    raw = 0.5 * (1.0 + xc[a] / supply)
    duty = clip(raw, 0.0, 1.0)
    sat = sat or duty != raw
    r_a, ell, ks, i_max = p[a, R], p[a, L], p[a, KS], p[a, IMAX]
    side = 0.5 * (1.0 - duty) * h
    i = xi[a]
    area, energy, square = 0.0, 0.0, 0.0
    for k in range(3):
        volts = supply if k == 1 else -supply
        tau = duty * h if k == 1 else side
        if switching_interval(i, volts, omega, r_a, ell, ks, tau, i_max, res):
            sat = True
        i = res[0]
        area += res[1]
        energy += res[3]
        square += res[2]
    xi[a] = i
    u_c = xc[a] + p[a, KIWZM] * (u_i * h - p[a, KC] * area)
    xc[a] = clip(u_c, -supply, supply)
    i_mean = area / h
    out[0], out[1], out[2] = ks * i_mean, i_mean, (2.0 * duty - 1.0) * supply
    out[3] = 1.0 if sat else 0.0
    out[4], out[5] = energy, r_a * square


@njit(cache=True)
def run_pwm_segment(
    ist, fst, par, theta_ref, lin, rows, coef, lev, static_j, running_j,
    q, qd, xv, xi, xc, mm, hb, m_inv, q0, qd0,
    rec_q, rec_qd, rec_tau, rec_f, rec_i, rec_u, rec_sat, energy, copper,
):  # fmt: skip
    """Run PWM periods from ``ist[START]`` until a refresh is due (returns that step) or the
    end (returns ``ist[STEPS]``); ``ist[FRESH] = 1``: the terms were just refreshed. The
    step of :meth:`irlc.runtime.drives.simulate._Simulation.run` at ``pwm``: transmission,
    :func:`_pwm_axis` per axis, sliding friction, ``Kᵀ τ_m``, ``q̈ = M⁻¹ (T − f − h)`` or
    Karnopp's two passes, ``q̇ += h q̈`` (stuck: ``q̇ := 0``), ``q += h q̇``."""
    n = q.shape[0]
    m = xv.shape[0]
    h = fst[H]
    sticky = ist[STICKY] != 0
    sliding = ist[SLIDING] != 0
    theta = np.empty(m)
    kmat = np.empty((m, n))
    tau_m = np.empty(m)
    f_m = np.zeros(m)
    stuck = np.zeros(n, dtype=np.bool_)
    scratch = joint_scratch(n)
    rec = (rec_q, rec_qd, rec_tau, rec_f)
    out = np.empty(6)
    res = np.empty(4)
    for s in range(ist[START], ist[STEPS]):
        if not (s == ist[START] and ist[FRESH] != 0) and refresh_due(s, q, qd, q0, qd0, ist, fst):
            return s
        motor_and_jacobian(lin, rows, coef, lev, q, theta, kmat)  # θ_m, K(q)
        any_stuck = False
        for a in range(m):
            omega = 0.0
            for j in range(n):
                omega += kmat[a, j] * qd[j]
            _pwm_axis(a, theta_ref[s, a] - theta[a], omega, par, xv, xi, xc, h, out, res)
            tau_m[a] = out[0]
            rec_i[s, a], rec_u[s, a], rec_sat[s, a] = out[1], out[2], out[3] != 0.0
            energy[a] += out[4]
            copper[a] += out[5]
            if sliding:
                f_m[a] = par[a, RUN_M] * sign(omega) + par[a, VISC_M] * omega
            if sticky:
                stuck[a] = abs(omega) < par[a, BAND]
                any_stuck = any_stuck or stuck[a]
        joint_step(
            s, h, kmat, tau_m, f_m, sliding, any_stuck, stuck, mm, hb, m_inv, static_j,
            running_j, q, qd, rec, scratch,
        )  # fmt: skip
    return ist[STEPS]
