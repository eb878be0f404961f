"""irlc's RNEA and M(q) (runtime/dynamics.py) against independent implementations.

* A three-link **cylindrical manipulator** (column turning about z, vertical slide, radial
  slide — the worked example of manipulator dynamics textbooks; seed 004's equations
  (6.10)–(6.11) are not in the sources at hand, so the equations are derived here): the
  Lagrangian ``L = T − V`` is written symbolically with sympy from the link poses alone,
  ``M = ∂²T/∂q̇²`` and ``τ = d/dt ∂L/∂q̇ − ∂L/∂q`` by symbolic differentiation, and both are
  evaluated at random states and random inertial parameters (full inertia tensors, centres of
  mass off the axes).
* **pinocchio** (the ``bench`` extra) for every library robot with inertials: the robot
  model is rebuilt joint by joint in pinocchio (placement = the joint origin, a revolute or
  prismatic joint about the robot file's axis, the link inertia about its centre of mass),
  then RNEA and CRBA are compared at random states.
* **M(q) from the kinetic energy** of the finite-differenced FK link velocities (the
  ``energies`` of test_dynamics.py, no dynamics code): ``T`` is quadratic in ``q̇``, so
  ``M_ij = T(e_i + e_j) − T(e_i) − T(e_j)`` (polarisation), for every library robot.
"""

from __future__ import annotations

import numpy as np
import pytest
from irlc.robots import list_robots, load_robot
from irlc.robots.model import Inertial, Joint, Limits, RobotModel
from irlc.runtime import spatial
from irlc.runtime.dynamics import Dynamics

from .test_dynamics import energies

LIM = Limits((-10.0, 10.0), (-1.0, 1.0), (-1.0, 1.0))


def library_robots_with_inertials() -> list[str]:
    return [name for name in list_robots() if load_robot(name).inertials]


# ----------------------------------------------------------------------------- symbolic


def _random_inertial(rng, link: int) -> Inertial:
    a = rng.normal(size=(3, 3))
    return Inertial(
        link, rng.uniform(1.0, 8.0), rng.normal(size=3) * 0.2, a @ a.T + 0.1 * np.eye(3)
    )


def cylindrical(rng, height: float = 0.4) -> RobotModel:
    """R (about z) – P (along z) – P (along the column's x): a cylindrical arm whose radial
    slide starts ``height`` above the column foot."""
    z, x = np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])
    joints = (
        Joint("turn", "revolute", np.eye(4), z, LIM),
        Joint("lift", "prismatic", np.eye(4), z, LIM),
        Joint("reach", "prismatic", spatial.transform(np.eye(3), [0.0, 0.0, height]), x, LIM),
    )
    inertials = tuple(_random_inertial(rng, k) for k in (1, 2, 3))
    return RobotModel("cylindrical", joints, inertials=inertials)


def symbolic_cylindrical(model: RobotModel):
    """``(M(q), τ(q, q̇, q̈))`` of :func:`cylindrical` as numeric functions, derived with
    sympy from the Lagrangian of the three links (the link poses written out by hand)."""
    sp = pytest.importorskip("sympy", reason="sympy (extra 'test') derives the reference")
    q = sp.symbols("q1:4")
    qd = sp.symbols("qd1:4")
    qdd = sp.symbols("qdd1:4")
    height = float(model.joints[2].origin[2, 3])
    c, s = sp.cos(q[0]), sp.sin(q[0])
    rot = sp.Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])  # every link turns with the column
    origins = [
        sp.Matrix([0, 0, 0]),  # link 1: the column foot
        sp.Matrix([0, 0, q[1]]),  # link 2: the carriage, lifted by q2
        sp.Matrix([0, 0, q[1] + height]) + rot * sp.Matrix([q[2], 0, 0]),  # link 3: the arm
    ]
    omega = sp.Matrix([0, 0, qd[0]])
    g = sp.Matrix(model.gravity.tolist())
    kinetic, potential = 0, 0
    for origin, inertial in zip(origins, model.inertials, strict=True):
        com = origin + rot * sp.Matrix(inertial.com.tolist())
        v = com.jacobian(q) * sp.Matrix(qd)
        inertia = rot * sp.Matrix(inertial.inertia.tolist()) * rot.T
        kinetic += sp.Rational(1, 2) * inertial.mass * (v.T * v)[0]
        kinetic += sp.Rational(1, 2) * (omega.T * inertia * omega)[0]
        potential -= inertial.mass * (g.T * com)[0]
    lagrangian = kinetic - potential
    # d/dt ∂L/∂q̇ along q(t): ∂/∂q (∂L/∂q̇) q̇ + ∂/∂q̇ (∂L/∂q̇) q̈
    dl_dqd = sp.Matrix([sp.diff(lagrangian, v) for v in qd])
    ddt = dl_dqd.jacobian(q) * sp.Matrix(qd) + dl_dqd.jacobian(qd) * sp.Matrix(qdd)
    tau = ddt - sp.Matrix([sp.diff(lagrangian, v) for v in q])
    mass = sp.hessian(kinetic, qd)
    return (
        sp.lambdify([q], mass, "numpy"),
        sp.lambdify([q, qd, qdd], tau, "numpy"),
    )


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_cylindrical_manipulator_against_its_symbolic_lagrangian(seed):
    rng = np.random.default_rng(seed)
    model = cylindrical(rng)
    mass_f, tau_f = symbolic_cylindrical(model)
    dyn = Dynamics(model)
    for _ in range(8):
        q, qd, qdd = rng.normal(size=(3, 3))
        m_ref = np.asarray(mass_f(q), float)
        tau_ref = np.asarray(tau_f(q, qd, qdd), float).ravel()
        assert np.allclose(dyn.mass_matrix(q), m_ref, rtol=1e-12, atol=1e-12)
        assert np.allclose(dyn.rnea(q, qd, qdd), tau_ref, rtol=1e-11, atol=1e-11)
        m_hot, h_hot = dyn.mass_and_bias(q, qd)
        assert np.allclose(m_hot, m_ref, atol=1e-11)
        assert np.allclose(m_hot @ qdd + h_hot, tau_ref, atol=1e-10)


def test_cylindrical_reference_is_not_trivial():
    """The derivation sees what it must: the centrifugal force on the radial slide grows with
    q̇1², and gravity loads the lift by the whole carried mass (so a wrong sign or a dropped
    term would fail the comparison above)."""
    model = cylindrical(np.random.default_rng(4))
    _, tau_f = symbolic_cylindrical(model)
    q = np.array([0.3, 0.1, 0.5])
    m23 = model.inertials[1].mass + model.inertials[2].mass
    assert float(tau_f(q, [0, 0, 0], [0, 0, 0])[1][0]) == pytest.approx(9.81 * m23)
    spin = float(tau_f(q, [2.0, 0, 0], [0, 0, 0])[2][0])
    still = float(tau_f(q, [0.0, 0, 0], [0, 0, 0])[2][0])
    assert spin < still  # the slide is pulled outwards


# ----------------------------------------------------------------------------- pinocchio


def pinocchio_model(model: RobotModel):
    """The same serial chain in pinocchio: joint ``i`` placed at ``origin_i`` (the base
    before joint 1) in its parent joint's frame, revolute or prismatic about ``axis_i``;
    link ``i``'s inertia appended to joint ``i``. pinocchio's ``q`` is irlc's ``q + offset``."""
    pin = pytest.importorskip("pinocchio", reason="pinocchio is in the 'bench' extra")
    pm = pin.Model()
    pm.gravity.linear = np.asarray(model.gravity, float)
    inertials = {i.link: i for i in model.inertials}
    parent = 0
    for k, joint in enumerate(model.joints, start=1):
        placement = joint.origin if k > 1 else model.base @ joint.origin
        axis = np.asarray(joint.axis, float)
        jmodel = (
            pin.JointModelRevoluteUnaligned(axis)
            if joint.kind == "revolute"
            else pin.JointModelPrismaticUnaligned(axis)
        )
        se3 = pin.SE3(placement[:3, :3].copy(), placement[:3, 3].copy())
        parent = pm.addJoint(parent, jmodel, se3, joint.name)
        if (inertial := inertials.get(k)) is not None:
            inertia = pin.Inertia(inertial.mass, inertial.com, inertial.inertia)
            pm.appendBodyToJoint(parent, inertia, pin.SE3.Identity())
    return pin, pm


@pytest.mark.peer
@pytest.mark.parametrize("name", library_robots_with_inertials())
def test_library_robot_dynamics_against_pinocchio(name):
    model = load_robot(name)
    pin, pm = pinocchio_model(model)
    data = pm.createData()
    dyn = Dynamics(model)
    offsets = np.array([j.offset for j in model.joints])
    rng = np.random.default_rng(len(name))
    lim = model.position_limits
    for _ in range(6):
        q = rng.uniform(lim[:, 0], lim[:, 1])
        qd, qdd = rng.normal(size=(2, model.n))
        m_pin = pin.crba(pm, data, q + offsets)
        m_pin = np.triu(m_pin) + np.triu(m_pin, 1).T
        tau_pin = pin.rnea(pm, data, q + offsets, qd, qdd)
        scale_m, scale_t = np.abs(m_pin).max(), max(1.0, np.abs(tau_pin).max())
        assert np.allclose(dyn.mass_matrix(q), m_pin, atol=1e-10 * scale_m)
        assert np.allclose(dyn.rnea(q, qd, qdd), tau_pin, atol=1e-10 * scale_t)
        assert np.allclose(dyn.gravity_torque(q), pin.computeGeneralizedGravity(
            pm, data, q + offsets), atol=1e-10 * scale_t)  # fmt: skip


def test_every_library_robot_with_inertials_is_cross_checked():
    """The list the pinocchio test runs over is the library's (not a hand-picked subset)."""
    names = library_robots_with_inertials()
    assert {"irb6", "irb6_track", "as6", "l1", "koch11", "panda"} <= set(names)


# ----------------------------------------------------------------------------- energy


@pytest.mark.parametrize("name", library_robots_with_inertials())
def test_mass_matrix_is_the_hessian_of_the_kinetic_energy(name):
    """``M_ij = T(e_i + e_j) − T(e_i) − T(e_j)`` with ``T`` from FK finite differences."""
    model = load_robot(name)
    dyn = Dynamics(model)
    rng = np.random.default_rng(7)
    lim = model.position_limits
    q = rng.uniform(lim[:, 0], lim[:, 1])
    eye = np.eye(model.n)
    single = [energies(model, q, e)[0] for e in eye]
    m_ref = np.array(
        [
            [energies(model, q, eye[i] + eye[j])[0] - single[i] - single[j] for j in range(model.n)]
            for i in range(model.n)
        ]
    )
    m = dyn.mass_matrix(q)
    assert np.allclose(m, m_ref, rtol=1e-6, atol=1e-7 * np.abs(m).max())
