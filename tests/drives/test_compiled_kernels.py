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
