"""Each compiled drive kernel (runtime/drives/compiled/kernels.py) against its numpy
reference, on known cases and randomized inputs: the first-order armature with the
current clamp (``motor.first_order``) and the transmission on its public packed data
(``Transmission.data`` against ``Transmission.motor_and_jacobian``)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from irlc.robots.loader import load_toml
from irlc.runtime.accel_support import AVAILABLE
from irlc.runtime.drives import motor
from irlc.runtime.drives.params import drive_params
from irlc.runtime.drives.transmission import Transmission

ROBOTS = Path(__file__).resolve().parents[2] / "robots"
pytestmark = pytest.mark.skipif(not AVAILABLE, reason="numba not installed / disabled")


def _kernels():
    from irlc.runtime.drives.compiled import kernels

    return kernels


def _first_order(i0, u, omega, R, L, ks, tau, i_max):
    res = np.empty(4)
    _kernels().first_order(i0, u, omega, R, L, ks, tau, i_max, res)
    return res


def test_first_order_known_case():
    """At rest, no back-EMF: i(τ) = (u/R)(1 − e^{−τR/L}), ∫i = (u/R)(τ − (L/R)(1 − e^{−τR/L}))."""
    R, L, u, tau = 2.0, 0.01, 10.0, 0.003
    res = _first_order(0.0, u, 0.0, R, L, 0.1, tau, 100.0)
    decay = math.exp(-tau * R / L)
    assert math.isclose(res[0], u / R * (1 - decay), rel_tol=1e-14)
    assert math.isclose(res[1], u / R * (tau - L / R * (1 - decay)), rel_tol=1e-14)
    assert math.isclose(res[3], u * res[1], rel_tol=1e-14)


def test_first_order_random_with_and_without_the_clamp():
    rng = np.random.default_rng(11)
    clamped = 0
    for _ in range(400):
        i0, u, omega = rng.normal() * 5, rng.normal() * 50, rng.normal() * 100
        R, L, ks = rng.uniform(0.5, 5), rng.uniform(1e-3, 2e-2), rng.uniform(0.02, 0.5)
        tau, i_max = rng.uniform(1e-4, 5e-3), rng.uniform(2, 20)
        i0 = float(np.clip(i0, -i_max, i_max))
        res = _first_order(i0, u, omega, R, L, ks, tau, i_max)
        ref = motor.first_order(np.array([i0]), np.array([u]), np.array([omega]), R, L, ks,
                                tau, i_max)  # fmt: skip
        clamped += bool(ref[4][0])
        for k in range(4):
            assert math.isclose(res[k], float(ref[k][0]), rel_tol=1e-12, abs_tol=1e-14), k
    assert clamped > 20  # the clamp branch was exercised


@pytest.mark.parametrize("robot", ["irb6_track", "koch11", "l1"])
def test_transmission_on_packed_data(robot):
    """θ_m and K(q) from TransmissionData (plain ratios, linear couplings, screw levers)
    equal Transmission.motor_and_jacobian; K matches a finite difference of θ_m."""
    model = load_toml(ROBOTS / f"{robot}.toml")
    params = drive_params(model)
    if params is None:
        pytest.skip(f"{robot} has no drive data")
    trans = Transmission(model, params)
    data = trans.data
    assert not any(a.flags.writeable for a in (data.linear, data.rows, data.angle, data.lever))
    rng = np.random.default_rng(12)
    m = data.linear.shape[0]
    theta, kmat = np.empty(m), np.empty((m, model.n))
    lo, hi = np.clip(model.position_limits, -2.0, 2.0).T
    for _ in range(50):
        q = lo + (hi - lo) * rng.uniform(0.2, 0.8, model.n)
        _kernels().motor_and_jacobian(
            data.linear, data.rows, data.angle, data.lever, q, theta, kmat
        )
        ref_theta, ref_k = trans.motor_and_jacobian(q)
        assert np.allclose(theta, ref_theta, rtol=1e-13, atol=1e-12)
        assert np.allclose(kmat, ref_k, rtol=1e-13, atol=1e-12)
    h = 1e-6
    fd = np.column_stack([(trans.to_motor(q + h * e) - trans.to_motor(q - h * e)) / (2 * h)
                          for e in np.eye(model.n)])  # fmt: skip
    assert np.allclose(kmat, fd, rtol=1e-6, atol=1e-6)


@pytest.mark.parametrize("robot", ["irb6_track", "koch11", "as6", "mobile8"])
def test_mass_and_bias_on_packed_data(robot):
    """M(q) and C q̇ + G from DynamicsData and the link frames equal
    Dynamics.mass_and_bias (prismatic joints included: irb6_track's track, mobile8's
    platform); M is symmetric and its diagonal holds the rotors."""
    from irlc.runtime.model.dynamics import Dynamics
    from irlc.runtime.model.kinematics import Kinematics

    model = load_toml(ROBOTS / f"{robot}.toml")
    rotor = np.linspace(0.1, 0.5, model.n)
    dyn, kin = Dynamics(model, rotor_inertia=rotor), Kinematics(model)
    d = dyn.data
    assert not any(a.flags.writeable for a in (d.axes, d.mass, d.inertia, d.gravity))
    rng = np.random.default_rng(13)
    M, h = np.empty((model.n, model.n)), np.empty(model.n)
    for _ in range(30):
        q, qd = rng.uniform(-1.0, 1.0, model.n), rng.normal(size=model.n)
        _kernels().mass_and_bias(kin.chain(q), d.axes, d.revolute, d.rotor, d.mass, d.com,
                                 d.inertia, d.gravity, qd, M, h)  # fmt: skip
        ref_m, ref_h = dyn.mass_and_bias(q, qd)
        assert np.allclose(M, ref_m, rtol=0, atol=1e-13 * np.abs(ref_m).max())
        assert np.allclose(h, ref_h, rtol=0, atol=1e-13 * max(1.0, np.abs(ref_h).max()))
    assert np.array_equal(M, M.T)
    _kernels().mass_and_bias(kin.chain(q), d.axes, d.revolute, np.zeros(model.n), d.mass, d.com,
                             d.inertia, d.gravity, qd, M, h)  # fmt: skip
    assert np.allclose(np.diag(ref_m) - np.diag(M), rotor, rtol=0, atol=1e-13 * np.abs(M).max())


def test_invert_against_numpy():
    """Gauss–Jordan with partial pivoting equals np.linalg.inv (SPD mass matrices and
    general matrices that need row swaps)."""
    rng = np.random.default_rng(14)
    for n in (1, 2, 6, 11):
        out, work = np.empty((n, n)), np.empty((n, 2 * n))
        for spd in (True, False):
            a = rng.normal(size=(n, n))
            a = a @ a.T + n * np.eye(n) if spd else a
            _kernels().invert(a, out, work)
            ref = np.linalg.inv(a)
            assert np.allclose(out, ref, rtol=0, atol=1e-12 * np.abs(ref).max())
            assert np.allclose(out @ a, np.eye(n), atol=1e-11)
    a = np.array([[0.0, 2.0], [3.0, 1.0]])  # zero on the diagonal: a pivot swap
    out = np.empty((2, 2))
    _kernels().invert(a, out, np.empty((2, 4)))
    assert np.allclose(out, np.linalg.inv(a), rtol=1e-15)


@pytest.mark.parametrize("robot", ["irb6_track", "koch11", "l1"])
def test_coupled_terms_on_packed_data(robot):
    """One compiled refresh (frames, M, C q̇ + G, rotor matrix, M⁻¹) from ChainData,
    DynamicsData and TransmissionData equals the numpy pieces: Dynamics.mass_and_bias
    (rotors of plain ratios on the diagonal) + Transmission.rotor_matrix, np.linalg.inv.
    Screw levers (irb6_track), plain ratios (koch11), linear couplings (l1)."""
    from irlc.runtime.model.dynamics import Dynamics
    from irlc.runtime.model.kinematics import Kinematics

    model = load_toml(ROBOTS / f"{robot}.toml")
    params = drive_params(model)
    trans = Transmission(model, params)
    j_m = np.asarray(params.chain.J_m, dtype=float)
    rotor = trans.reflected(j_m, model.n) if trans.diagonal else np.zeros(model.n)
    dyn, c = Dynamics(model, rotor_inertia=rotor), Kinematics(model).chain_data
    d, t = dyn.data, trans.data
    n, m = model.n, len(params.axes)
    buf = (np.empty((n + 1, 4, 4)), np.empty((4, 4)), np.empty(m), np.empty((m, n)),
           np.empty((n, 2 * n)))  # fmt: skip
    mm, hb, m_inv = np.empty((n, n)), np.empty(n), np.empty((n, n))
    rng = np.random.default_rng(15)
    lo, hi = np.clip(model.position_limits, -2.0, 2.0).T
    for _ in range(20):
        q, qd = lo + (hi - lo) * rng.uniform(0.2, 0.8, n), rng.normal(size=n)
        _kernels().coupled_terms(
            (c.basis, c.joints, c.ends[0]),
            (d.axes, d.revolute, d.rotor, d.mass, d.com, d.inertia, d.gravity),
            (t.linear, t.rows, t.angle, t.lever), j_m, not trans.diagonal, q, qd, mm, hb,
            m_inv, buf,
        )  # fmt: skip
        ref_m, ref_h = dyn.mass_and_bias(q, qd)
        if not trans.diagonal:
            ref_m = ref_m + trans.rotor_matrix(j_m, q)
        scale = np.abs(ref_m).max()
        assert np.allclose(mm, ref_m, rtol=0, atol=1e-13 * scale)
        assert np.allclose(hb, ref_h, rtol=0, atol=1e-13 * max(1.0, np.abs(ref_h).max()))
        ref_inv = np.linalg.inv(ref_m)
        assert np.allclose(m_inv, ref_inv, rtol=0, atol=1e-10 * np.abs(ref_inv).max())
    if not trans.diagonal:  # the coupled rotor terms are exercised (off the diagonal)
        extra = trans.rotor_matrix(j_m, q)
        assert np.abs(extra - np.diag(np.diag(extra))).max() > 0.0


def test_chain_source_digest():
    """run_segment's machine code includes ik/compiled/chain.forward_chain; numba's cache is
    keyed by the kernel module's file only, so a change of forward_chain must change
    CHAIN_SOURCE_DIGEST there."""
    k = _kernels()
    assert k.chain_source_digest() == k.CHAIN_SOURCE_DIGEST, (
        "ik/compiled/chain.forward_chain changed: set CHAIN_SOURCE_DIGEST in "
        f"runtime/drives/compiled/kernels.py to {k.chain_source_digest()!r}"
    )


# ---------------------------------------------------------------------- the rest, one each
def test_sign_clip_and_pivot_against_numpy():
    k = _kernels()
    rng = np.random.default_rng(16)
    for x in (*rng.normal(size=50), 0.0, -0.0, 1e-300, -1e-300):
        assert k.sign(x) == np.sign(x)
        lo, hi = sorted(rng.normal(size=2))
        assert k.clip(x, lo, hi) == np.clip(x, lo, hi)
    for rows in (1, 3, 6):
        for c in range(rows):
            work = rng.normal(size=(rows, rows + 1))
            ref = work.copy()
            k.pivot(work, c, rows, rows + 1)
            best = c + int(np.argmax(np.abs(ref[c:, c])))  # the first largest, as LAPACK
            ref[[c, best], c:] = ref[[best, c], c:]
            np.testing.assert_array_equal(work, ref)


def _spd(rng, n):
    a = rng.normal(size=(n, n))
    return a @ a.T + n * np.eye(n)


def test_solve_free_against_numpy():
    """``q̈_f = M_ff⁻¹ rhs_f`` by elimination with partial pivoting, zero on the held axes."""
    k = _kernels()
    rng = np.random.default_rng(17)
    n = 6
    for _ in range(100):
        mm, rhs = _spd(rng, n), rng.normal(size=n)
        free = np.flatnonzero(rng.uniform(size=n) < 0.7).astype(np.int64)
        qdd, work = np.full(n, np.nan), np.empty((n, n + 1))
        k.solve_free(mm, np.resize(free, n), free.size, rhs, qdd, work)
        ref = np.zeros(n)
        if free.size:
            ref[free] = np.linalg.solve(mm[np.ix_(free, free)], rhs[free])
        np.testing.assert_allclose(qdd, ref, rtol=1e-12, atol=1e-14)


def _mechanics():
    from irlc.runtime.drives.mechanics import Mechanics

    model = load_toml(ROBOTS / "irb6_track.toml")
    n = model.n
    return Mechanics(model, "coupled", np.full(n, 0.1), np.array(model.home_q(), float), None)


def test_karnopp_against_mechanics():
    """Karnopp's two passes on a held M: the same accelerations, joint-side friction and
    final stuck set as Mechanics.accel_driven (Mechanics._karnopp), stuck axes that hold
    and that break away."""
    k, mech = _kernels(), _mechanics()
    n = mech.n
    rng = np.random.default_rng(18)
    broke = held = 0
    for _ in range(200):
        mm, hb = _spd(rng, n), rng.normal(size=n)
        drive, slide = rng.normal(size=n) * 5, rng.normal(size=n) * 0.5
        stuck = rng.uniform(size=n) < 0.5
        static = rng.uniform(0.0, 6.0, n)
        running = static * rng.uniform(0.5, 1.0, n)
        slide[stuck] = 0.0
        ref_qdd, ref_fric, ref_stuck = mech.accel_driven(
            mm, hb, drive, slide, stuck.copy(), static, running, mech.inverse(mm)
        )
        got_stuck, qdd, fric = stuck.copy(), np.empty(n), np.empty(n)
        scratch = (np.empty(n, np.int64), np.empty((n, n + 1)), np.empty(n), np.empty(n))
        k.karnopp(mm, hb, drive, slide, got_stuck, static, running, qdd, fric, *scratch)
        np.testing.assert_array_equal(got_stuck, ref_stuck)
        np.testing.assert_allclose(qdd, ref_qdd, rtol=1e-11, atol=1e-13)
        np.testing.assert_allclose(fric, ref_fric, rtol=1e-11, atol=1e-13)
        broke += int(np.count_nonzero(stuck & ~ref_stuck))
        held += int(np.count_nonzero(ref_stuck))
    assert broke > 20 and held > 20  # both outcomes of the break-away test


def test_refresh_due_against_the_refresh_policy():
    """``Refresh.due``: every k steps, or (adaptive) after the hold time or when q, q̇ moved
    beyond the bounds since the last refresh."""
    from irlc.runtime.drives.refresh import Refresh

    k = _kernels()
    rng = np.random.default_rng(19)
    n, h = 5, 1e-3
    for every in (None, 1, 3):
        ref = Refresh(every, h, n)
        ist, fst = np.zeros(k.N_IST, np.int64), np.zeros(k.N_FST)
        ist[k.EVERY], ist[k.MAX_STEPS] = every or 0, ref.max_steps
        fst[k.DQ], fst[k.DV] = ref.dq, ref.dv
        q, qd = rng.normal(size=n), rng.normal(size=n)
        ref.mark(0, q, qd)
        for s in range(1, 60):
            q = q + rng.normal(size=n) * 1e-3
            qd = qd + rng.normal(size=n) * 1e-2
            ist[k.S0] = ref.s0
            due = ref.due(s, q, qd)
            assert k.refresh_due(s, q, qd, ref.q0, ref.qd0, ist, fst) == due, (every, s)
            if due:
                ref.mark(s, q, qd)


def test_axis_step_against_the_dc_bank():
    """One DC axis of the averaged cascade (the fused linear map, or P → PI → current loop
    → averaged stage with every limit) against DcBank.step on the irb6_track's measured
    chain: torque, mean current and voltage, saturation, energy, copper loss and the new
    state, for small and saturating errors and speeds."""
    from irlc.runtime.drives.cascade import DcBank
    from irlc.runtime.drives.compiled.loop import axis_parameters

    k = _kernels()
    model = load_toml(ROBOTS / "irb6_track.toml")
    params = drive_params(model)
    c, h = params.chain, 1e-3
    m = len(c.kz)
    rng = np.random.default_rng(20)
    bank = DcBank(c, h, False, rng.normal(size=m) * 0.2)
    par = axis_parameters(k, c, params.friction, np.zeros(m))
    out, res, saturated = np.empty(6), np.empty(4), 0
    for trial in range(300):
        scale = (1e-3, 0.05, 5.0)[trial % 3]
        d, omega = rng.normal(size=m) * scale, rng.normal(size=m) * 20 * scale
        z = bank.z  # the bank's state [x_v; i; u] (blocks of m axes), before the step
        xv, xi, xu = z[2 * m : 3 * m].copy(), z[3 * m : 4 * m].copy(), z[4 * m :].copy()
        ref = bank.step(d, np.zeros(m), omega, 0.0)
        for a in range(m):
            k.axis_step(a, d[a], omega[a], par, bank.fused, bank.limits, bank.loop.big, xv, xi,
                        xu, h, out, res)  # fmt: skip
            want = [ref[i][a] for i in (0, 1, 2, 4, 5)]  # τ_m, ī, ū, ∫u i, ∫R i²
            assert out[[0, 1, 2, 4, 5]] == pytest.approx(want, rel=1e-10, abs=1e-12), (trial, a)
            assert bool(out[3]) == bool(ref[3][a]), (trial, a)
            saturated += bool(out[3])
        np.testing.assert_allclose(np.concatenate((xv, xi, xu)), bank.z[2 * m :], rtol=1e-10,
                                   atol=1e-12)  # fmt: skip
    assert saturated > 100  # the limited branches ran


def test_joint_step_against_numpy():
    """The joint side of one step shared by every level: ``T = Kᵀτ_m``, sliding friction
    ``Kᵀf_m``, ``q̈ = M⁻¹(T − f − h)`` or Karnopp (Mechanics.accel_driven), the record row,
    then semi-implicit Euler (stuck axes stop)."""
    k, mech = _kernels(), _mechanics()
    n, m, h = mech.n, mech.n, 1e-3
    rng = np.random.default_rng(26)
    for trial in range(60):
        mm, hb = _spd(rng, n), rng.normal(size=n)
        kmat, tau_m, f_m = rng.normal(size=(m, n)), rng.normal(size=m), rng.normal(size=m)
        static = rng.uniform(0.0, 3.0, n)
        running = static * 0.7
        stuck = rng.uniform(size=n) < (0.4 if trial % 2 else 0.0)
        q, qd = rng.normal(size=n), rng.normal(size=n)
        q_ref, qd_ref = q.copy(), qd.copy()
        rec = tuple(np.zeros((3, n)) for _ in range(4))
        m_inv = mech.inverse(mm)
        got_stuck = stuck.copy()
        k.joint_step(1, h, kmat, tau_m, f_m, True, bool(stuck.any()), got_stuck, mm, hb, m_inv,
                     static, running, q, qd, rec, k.joint_scratch(n))  # fmt: skip
        drive, slide = kmat.T @ tau_m, kmat.T @ f_m
        qdd, fric, ref_stuck = mech.accel_driven(
            mm, hb, drive, slide, stuck.copy(), static, running, m_inv
        )
        np.testing.assert_array_equal(got_stuck, ref_stuck)
        for row, want in zip(rec, (q_ref, qd_ref, drive, fric), strict=True):
            np.testing.assert_allclose(row[1], want, rtol=1e-12, atol=1e-13)
        qd_ref = np.where(ref_stuck, 0.0, qd_ref + h * qdd)
        np.testing.assert_allclose(qd, qd_ref, rtol=1e-12, atol=1e-13)
        np.testing.assert_allclose(q, q_ref + h * qd_ref, rtol=1e-12, atol=1e-13)
