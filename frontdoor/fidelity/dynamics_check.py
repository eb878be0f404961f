"""Independent references for irlc's rigid-body dynamics (runtime/model/dynamics.py).

* :func:`cylindrical` / :func:`symbolic_cylindrical`: a three-link cylindrical manipulator
  (column turning about z, vertical slide, radial slide) with random inertial parameters,
  and its ``M(q)`` and ``τ(q, q̇, q̈)`` derived with sympy from the Lagrangian written from
  the link poses alone (the worked example of seed 004's (6.10)–(6.11), whose text is not
  in the sources at hand). Needs sympy (the ``test`` extra).
* :func:`pinocchio_model`: any irlc robot rebuilt joint by joint in pinocchio (the
  ``bench`` extra).

Used by tests/drives/test_dynamics_crosscheck.py and by the fidelity rows.
"""

from __future__ import annotations

import numpy as np
from irlc.robots import list_robots, load_robot
from irlc.robots.model import Inertial, Joint, Limits, RobotModel
from irlc.runtime.model import spatial
from irlc.runtime.model.dynamics import Dynamics

LIM = Limits((-10.0, 10.0), (-1.0, 1.0), (-1.0, 1.0))


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
    import sympy as sp  # the test extra; a missing sympy is an ImportError

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


def pinocchio_model(model: RobotModel):
    """The same serial chain in pinocchio: joint ``i`` placed at ``origin_i`` (the base
    before joint 1) in its parent joint's frame, revolute or prismatic about ``axis_i``;
    link ``i``'s inertia appended to joint ``i``. pinocchio's ``q`` is irlc's ``q + offset``."""
    import pinocchio as pin  # the bench extra; a missing pinocchio is an ImportError

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


def library_robots_with_inertials() -> list[str]:
    return [name for name in list_robots() if load_robot(name).inertials]


def symbolic_deviation(seeds=(1, 2, 3), samples: int = 8) -> tuple[float, float]:
    """Largest relative deviation of irlc's ``M`` and ``τ`` from the symbolic ones over
    random arms and states."""
    worst_m = worst_t = 0.0
    for seed in seeds:
        rng = np.random.default_rng(seed)
        model = cylindrical(rng)
        mass_f, tau_f = symbolic_cylindrical(model)
        dyn = Dynamics(model)
        for _ in range(samples):
            q, qd, qdd = rng.normal(size=(3, 3))
            m_ref = np.asarray(mass_f(q), float)
            t_ref = np.asarray(tau_f(q, qd, qdd), float).ravel()
            worst_m = max(worst_m, np.abs(dyn.mass_matrix(q) - m_ref).max() / np.abs(m_ref).max())
            worst_t = max(worst_t, np.abs(dyn.rnea(q, qd, qdd) - t_ref).max() / np.abs(t_ref).max())
    return worst_m, worst_t


def pinocchio_states(name: str, samples: int = 6):
    """``(q, M_irlc, M_pin, τ_irlc, τ_pin, G_irlc, G_pin)`` of the library robot ``name``
    at ``samples`` random states (q inside the position limits, q̇ and q̈ normal)."""
    model = load_robot(name)
    pin, pm = pinocchio_model(model)
    data = pm.createData()
    dyn = Dynamics(model)
    offsets = np.array([j.offset for j in model.joints])
    rng = np.random.default_rng(len(name))
    lim = model.position_limits
    for _ in range(samples):
        q = rng.uniform(lim[:, 0], lim[:, 1])
        qd, qdd = rng.normal(size=(2, model.n))
        m_pin = pin.crba(pm, data, q + offsets)
        m_pin = np.triu(m_pin) + np.triu(m_pin, 1).T
        t_pin = np.array(pin.rnea(pm, data, q + offsets, qd, qdd))
        g_pin = np.array(pin.computeGeneralizedGravity(pm, data, q + offsets))
        yield (q, dyn.mass_matrix(q), m_pin, dyn.rnea(q, qd, qdd), t_pin,
               dyn.gravity_torque(q), g_pin)  # fmt: skip


def pinocchio_deviation(samples: int = 6) -> tuple[int, float, float]:
    """(robots compared, largest relative deviation of ``M``, of ``τ``) against pinocchio
    for every library robot with inertials, at random states inside the limits."""
    worst_m = worst_t = 0.0
    names = library_robots_with_inertials()
    for name in names:
        for _, m, m_pin, t, t_pin, _, _ in pinocchio_states(name, samples):
            worst_m = max(worst_m, np.abs(m - m_pin).max() / np.abs(m_pin).max())
            worst_t = max(worst_t, np.abs(t - t_pin).max() / max(1.0, np.abs(t_pin).max()))
    return len(names), worst_m, worst_t
