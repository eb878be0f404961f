"""irlc's RNEA and M(q) (runtime/model/dynamics.py) against independent implementations.

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
from irlc.fidelity.dynamics_check import (
    cylindrical,
    library_robots_with_inertials,
    pinocchio_states,
    symbolic_cylindrical,
)
from irlc.robots import load_robot
from irlc.runtime.model.dynamics import Dynamics

from .test_dynamics import energies

# ----------------------------------------------------------------------------- symbolic


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_cylindrical_manipulator_against_its_symbolic_lagrangian(seed):
    pytest.importorskip("sympy", reason="sympy (extra 'test') derives the reference")
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
    pytest.importorskip("sympy", reason="sympy (extra 'test') derives the reference")
    model = cylindrical(np.random.default_rng(4))
    _, tau_f = symbolic_cylindrical(model)
    q = np.array([0.3, 0.1, 0.5])
    m23 = model.inertials[1].mass + model.inertials[2].mass
    assert float(tau_f(q, [0, 0, 0], [0, 0, 0])[1][0]) == pytest.approx(9.81 * m23)
    spin = float(tau_f(q, [2.0, 0, 0], [0, 0, 0])[2][0])
    still = float(tau_f(q, [0.0, 0, 0], [0, 0, 0])[2][0])
    assert spin < still  # the slide is pulled outwards


# ----------------------------------------------------------------------------- pinocchio


@pytest.mark.peer
@pytest.mark.parametrize("name", library_robots_with_inertials())
def test_library_robot_dynamics_against_pinocchio(name):
    pytest.importorskip("pinocchio", reason="pinocchio is in the 'bench' extra")
    for _, m, m_pin, tau, tau_pin, g, g_pin in pinocchio_states(name):
        scale_m, scale_t = np.abs(m_pin).max(), max(1.0, np.abs(tau_pin).max())
        assert np.allclose(m, m_pin, atol=1e-10 * scale_m)
        assert np.allclose(tau, tau_pin, atol=1e-10 * scale_t)
        assert np.allclose(g, g_pin, atol=1e-10 * scale_t)


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
