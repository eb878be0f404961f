"""Rigid-body dynamics against independent computations: the Lagrangian of energies built
from finite-differenced link velocities (FK of irlc.runtime.model.kinematics), the potential
energy gradient, and the reflected rotor inertia."""

from __future__ import annotations

import numpy as np
import pytest
from irlc.robots.model import Inertial, Joint, Limits, RobotModel
from irlc.runtime.model import spatial
from irlc.runtime.model.dynamics import Dynamics, MissingInertialData
from irlc.runtime.model.kinematics import Kinematics

LIM = Limits((-3.0, 3.0), (-1.0, 1.0), (-1.0, 1.0))


def random_robot(
    seed: int, kinds=("revolute", "prismatic", "revolute", "revolute", "prismatic", "revolute")
) -> RobotModel:
    rng = np.random.default_rng(seed)

    def rot():
        a = rng.normal(size=3)
        return spatial.axis_angle(a / np.linalg.norm(a), rng.normal())

    joints, inertials = [], []
    for i, kind in enumerate(kinds):
        axis = rng.normal(size=3)
        origin = spatial.transform(rot(), rng.normal(size=3) * 0.3)
        joints.append(
            Joint(
                f"j{i}", kind, origin, axis / np.linalg.norm(axis), LIM, offset=0.1 * rng.normal()
            )
        )
        a = rng.normal(size=(3, 3))
        inertials.append(
            Inertial(i + 1, rng.uniform(1, 5), rng.normal(size=3) * 0.2, a @ a.T + 0.1 * np.eye(3))
        )
    return RobotModel(
        "random",
        tuple(joints),
        base=spatial.transform(rot(), [0.1, 0.2, 0.3]),
        inertials=tuple(inertials),
        gravity=np.array([0.3, -9.81, 0.5]),
    )


def energies(model: RobotModel, q, qd, rotor=None, eps: float = 1e-6):
    """Kinetic and potential energy from FK only: link velocities by central differences of
    the link frames along ``q̇`` (independent of dynamics.py)."""
    kin = Kinematics(model)
    fp, fm = kin.link_frames(q + eps * qd), kin.link_frames(q - eps * qd)
    f0 = kin.link_frames(q)
    kinetic, potential = 0.0, 0.0

    def com(f, k, inertial):
        return f[k, :3, :3] @ inertial.com + f[k, :3, 3]

    for inertial in model.inertials:
        k = inertial.link
        v = (com(fp, k, inertial) - com(fm, k, inertial)) / (2 * eps)
        rdot = (fp[k, :3, :3] - fm[k, :3, :3]) / (2 * eps)
        w_hat = rdot @ f0[k, :3, :3].T
        w = np.array([w_hat[2, 1], w_hat[0, 2], w_hat[1, 0]])
        inertia = f0[k, :3, :3] @ inertial.inertia @ f0[k, :3, :3].T
        kinetic += 0.5 * inertial.mass * v @ v + 0.5 * w @ inertia @ w
        potential -= inertial.mass * model.gravity @ com(f0, k, inertial)
    if rotor is not None:
        kinetic += 0.5 * np.sum(rotor * qd * qd)
    return kinetic, potential


def lagrange_torque(model, q, qd, qdd, rotor=None, h: float = 1e-4):
    """τ = d/dt ∂L/∂q̇ − ∂L/∂q by finite differences of L = T − V."""
    n = len(q)

    def lag(qq, vv):
        t, v = energies(model, qq, vv, rotor)
        return t - v

    def dl_dqd(qq, vv):  # T is quadratic in q̇: central differences are exact
        out = np.empty(n)
        for i in range(n):
            e = np.zeros(n)
            e[i] = 1.0
            out[i] = (lag(qq, vv + e) - lag(qq, vv - e)) / 2.0
        return out

    def path(t):
        return q + qd * t + 0.5 * qdd * t * t, qd + qdd * t

    ddt = (dl_dqd(*path(h)) - dl_dqd(*path(-h))) / (2 * h)
    dl_dq = np.empty(n)
    for i in range(n):
        e = np.zeros(n)
        e[i] = h
        dl_dq[i] = (lag(q + e, qd) - lag(q - e, qd)) / (2 * h)
    return ddt - dl_dq


@pytest.mark.parametrize("seed", [1, 2])
def test_rnea_matches_lagrangian(seed):
    model = random_robot(seed)
    rng = np.random.default_rng(10 + seed)
    rotor = rng.uniform(0.0, 0.5, model.n)
    q, qd, qdd = rng.normal(size=(3, model.n))
    tau = Dynamics(model, rotor_inertia=rotor).rnea(q, qd, qdd)
    ref = lagrange_torque(model, q, qd, qdd, rotor)
    assert np.allclose(tau, ref, rtol=1e-4, atol=1e-4 * np.abs(ref).max())


def test_mass_matrix_symmetric_positive_definite_and_consistent():
    model = random_robot(3)
    dyn = Dynamics(model)
    rng = np.random.default_rng(4)
    for _ in range(5):
        q, qd, qdd = rng.normal(size=(3, model.n))
        m = dyn.mass_matrix(q)
        assert np.allclose(m, m.T, atol=1e-12)
        assert np.linalg.eigvalsh(m).min() > 0.0
        m2, h = dyn.mass_and_bias(q, qd)
        assert np.allclose(m2, m, atol=1e-10)
        assert np.allclose(dyn.rnea(q, qd, qdd), m @ qdd + h, atol=1e-9)
        assert np.allclose(dyn.coriolis(q, qd) + dyn.gravity_torque(q), h, atol=1e-9)
        # kinetic energy from link velocities equals ½ q̇ᵀ M q̇
        kinetic, _ = energies(model, q, qd)
        assert kinetic == pytest.approx(0.5 * qd @ m @ qd, rel=1e-7)


def test_gravity_is_gradient_of_potential_energy():
    model = random_robot(5)
    dyn = Dynamics(model)
    q = np.random.default_rng(6).normal(size=model.n)
    h = 1e-6
    grad = np.array(
        [
            (
                energies(model, q + h * e, np.zeros(model.n))[1]
                - energies(model, q - h * e, np.zeros(model.n))[1]
            )
            / (2 * h)
            for e in np.eye(model.n)
        ]
    )
    assert np.allclose(dyn.gravity_torque(q), grad, rtol=1e-6, atol=1e-6)
    assert np.allclose(dyn.gravity_vector(q), grad, rtol=1e-6, atol=1e-6)


def test_forward_dynamics_inverts_rnea():
    model = random_robot(7)
    dyn = Dynamics(model, rotor_inertia=np.full(model.n, 0.2))
    q, qd, qdd = np.random.default_rng(8).normal(size=(3, model.n))
    assert np.allclose(dyn.forward(q, qd, dyn.rnea(q, qd, qdd)), qdd, atol=1e-9)


def test_rotor_inertia_enters_diagonal_as_jm_times_ratio_squared():
    from irlc.runtime.drives.params import drive_params
    from irlc.runtime.drives.transmission import Transmission

    from .drive_models import dc_drives, planar

    model = planar(3, drives=dc_drives(3, ratio=40.0))
    params = drive_params(model)
    rotor = Transmission(model, params).reflected(params.chain.J_m, model.n)
    q = np.array([0.3, -0.2, 0.5])
    bare = Dynamics(model).mass_matrix(q)
    with_rotor = Dynamics(model, rotor_inertia=rotor).mass_matrix(q)
    expected = np.diag(np.full(3, params.chain.J_m[0] * 40.0**2))
    assert np.allclose(with_rotor - bare, expected)


def test_missing_inertials_is_a_clear_error():
    model = RobotModel("bare", random_robot(1).joints)
    with pytest.raises(MissingInertialData, match="robot bare has no inertial data"):
        Dynamics(model)


def test_real_robot_files_mass_matrices_are_spd():
    from pathlib import Path

    from irlc.robots.loader import load_toml

    folder = Path(__file__).resolve().parents[2] / "robots"
    checked = 0
    for path in sorted(folder.glob("*.toml")):
        model = load_toml(path)
        if not model.inertials:
            continue
        dyn = Dynamics(model)
        q = model.home_q()
        m = dyn.mass_matrix(q)
        assert np.allclose(m, m.T, atol=1e-9 * np.abs(m).max())
        assert np.linalg.eigvalsh(m).min() > 0.0, path.name
        m2, h = dyn.mass_and_bias(q, np.zeros(model.n))
        assert np.allclose(m2, m, atol=1e-9 * np.abs(m).max())
        assert np.allclose(h, dyn.gravity_torque(q), atol=1e-9 * max(1.0, np.abs(h).max()))
        checked += 1
    assert checked >= 1
