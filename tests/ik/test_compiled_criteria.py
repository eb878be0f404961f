"""R_CRITERION := 'ENERGY' | 'MVR' on the compiled engine equals the numpy path.

Kernel by kernel (the metric of ENERGY, the cost with a full metric, the obstacle terms
alone) against their numpy references, then whole cycles with every option the numpy
path takes — limits that bind, CYCLIC and RECONFIGURATION (the reference metric), avoided
obstacles (a_conf times the criterion), FREEZE, coupled limits (irb6), far targets
(relaxed steps) — compared as tests/ik/test_compiled_cycle.py compares the default
criterion (q and the TCP to 1e-10, iterations, flags, binding)."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("numba")

from irlc.robots import load_robot
from irlc.runtime import accel_support
from irlc.runtime.ik import CycleOptions
from irlc.runtime.ik.compiled import layout as L
from irlc.runtime.ik.criteria import CycleCriteria
from irlc.runtime.ik.obstacle import ObstacleTerm
from irlc.runtime.ik.params import ObstacleParams
from irlc.runtime.ik.state import IterationState
from irlc.runtime.model.dynamics import Dynamics
from irlc.runtime.model.kinematics import Kinematics

from . import test_compiled_cycle as cycle

pytestmark = pytest.mark.skipif(not accel_support.AVAILABLE, reason="no numba or IRLC_ENGINE=numpy")

ROBOTS = ("koch11", "panda", "mobile8", "irb6", "planar3")


@pytest.fixture(scope="module")
def robots():
    return {name: load_robot(name) for name in ROBOTS}


@pytest.mark.parametrize("name", ROBOTS)
def test_inertia_metric_kernel(robots, name):
    """``inertia_metric``: scale·M·Σw/tr M with the links' M (the CRBA of dynamics.py,
    an independent algorithm from the kernel's Jacobian form)."""
    from irlc.runtime.ik.compiled.inertia import inertia_metric

    model = robots[name]
    n, rng = model.n, np.random.default_rng(1)
    dyn = Dynamics(model)
    d = dyn.data
    chain = Kinematics(model).chain_data
    weights = model.weights
    for _ in range(5):
        q = cycle._random_q(model, rng)
        scale = rng.uniform(0.1, 2.0)
        out = np.empty((n, n))
        buf = (np.empty((n + 1, 4, 4)), np.empty((4, 4)), np.zeros(n), np.empty(n))
        dyn_arrays = (d.axes, d.revolute, d.rotor, d.mass, d.com, d.inertia, d.gravity)
        inertia_metric((chain.basis, chain.joints, chain.ends[0]), dyn_arrays, q,
                       float(weights.sum()), scale, buf, out)  # fmt: skip
        m = dyn.mass_matrix(q)  # CRBA, rotor 0
        expected = scale * m * weights.sum() / np.trace(m)
        assert np.allclose(out, expected, rtol=1e-12, atol=1e-12 * np.abs(expected).max())
        assert np.isclose(np.trace(out), scale * weights.sum(), rtol=1e-12)


def _terms_state(model, rng):
    n = model.n
    theta = cycle._random_q(model, rng)
    start = theta - rng.normal(size=n) * 0.01
    return IterationState(theta, start, theta - start)


def test_metric_cost_and_obstacle_cost_kernels(robots):
    """``metric_cost`` (g = MA·x + MC·Σ, H = MA + MC, plus obstacle terms) and
    ``obstacle_cost`` alone against the numpy criteria's ``accumulate``."""
    from irlc.runtime.ik.compiled.cycle import metric_cost, obstacle_cost

    model = robots["panda"]
    n, rng = model.n, np.random.default_rng(2)
    criteria = CycleCriteria(model, model.weights, 0.3)
    params = ObstacleParams()
    for has_ref in (False, True):
        state = _terms_state(model, rng)
        ref = state.theta + rng.normal(size=n) * 0.1
        opts = CycleOptions(criterion="ENERGY", reference=ref if has_ref else None)
        numpy_terms = criteria.terms(opts, state.start, True)
        jac = rng.normal(size=(2, 3, n))
        away = rng.normal(size=(2, 3))
        away /= np.linalg.norm(away, axis=1, keepdims=True)  # unit escape directions
        obstacles = [ObstacleTerm(jac[t], away[t], 0.2 + 0.1 * t, params) for t in range(2)]
        g, H = np.zeros(n), np.zeros((n, n))
        for term in [*numpy_terms, *obstacles]:
            term.accumulate(state, g, H)
        V = np.zeros((L.NV, n))
        V[L.THETA], V[L.SIGMA], V[L.REF] = state.theta, state.sigma, ref
        if has_ref:
            MA, MC = numpy_terms[0].metric, numpy_terms[1].metric
        else:
            MA, MC = numpy_terms[0].metric, np.zeros((n, n))
        ow = np.array([o.weight for o in obstacles])
        opush = np.array([o.push for o in obstacles])
        ojtj = np.array([o.jtj for o in obstacles])
        Hk = np.empty((n, n))
        metric_cost(V, MA, MC, Hk, has_ref, ow, opush, jac, ojtj)
        assert np.allclose(V[L.G], g, rtol=1e-12, atol=1e-12)
        assert np.allclose(Hk, H, rtol=1e-12, atol=1e-12)
        # the obstacle terms alone
        g0, H0 = np.zeros(n), np.zeros((n, n))
        for term in obstacles:
            term.accumulate(state, g0, H0)
        V[L.G] = 0.0
        Hk[:] = 0.0
        obstacle_cost(V, Hk, ow, opush, jac, ojtj)
        assert np.allclose(V[L.G], g0, atol=1e-12) and np.allclose(Hk, H0, atol=1e-12)


CRITERIA = ("ENERGY", "MVR")


@pytest.mark.parametrize("criterion", CRITERIA)
@pytest.mark.parametrize("name", ["koch11", "panda", "planar3", "mobile8"])
def test_free_cycles_and_limits_equal(robots, name, criterion):
    model = robots[name]
    stats = cycle._compare(model, CycleOptions(criterion=criterion), jump=0.3, starts=3)
    assert stats["cycles"] > 0
    pos, spd, acc = cycle._tight(model)
    tight = CycleOptions(position=pos, speed=spd, accel=acc, criterion=criterion)
    stats = cycle._compare(model, tight, step=0.02, seed=1, starts=3)
    assert stats["bound"] > 0  # some box bound was active


@pytest.mark.parametrize("criterion", CRITERIA)
@pytest.mark.parametrize("name", ["koch11", "panda"])
def test_reference_and_self_motion_equal(robots, name, criterion):
    """CYCLIC (the reference metric kept while θ⁰ is) and RECONFIGURATION (θ⁰ moving)."""
    model = robots[name]
    ref = np.clip(np.array(model.home, dtype=float), *model.position_limits.T)
    cycle._compare(model, CycleOptions(reference=ref, criterion=criterion), seed=2, starts=3)
    moving = CycleOptions(reference=ref, self_motion=True, criterion=criterion)
    cycle._compare(model, moving, seed=3, step=0.0, starts=3)


@pytest.mark.parametrize("criterion", CRITERIA)
def test_avoided_obstacles_equal(robots, criterion):
    model = robots["koch11"]
    obstacles = cycle._obstacles_near(model)
    names = frozenset({"ball", "box"})
    start = cycle._near_home(model)
    avoid = CycleOptions(obstacles=obstacles, active_obstacles=names, criterion=criterion)
    cycle._compare(model, avoid, seed=20, starts=2, start=start)
    ref = np.array(model.home_q(), dtype=float) + 0.05
    both = CycleOptions(obstacles=obstacles, active_obstacles=names, reference=ref,
                        criterion=criterion)  # fmt: skip
    cycle._compare(model, both, seed=21, starts=2, start=start)


@pytest.mark.parametrize("criterion", CRITERIA)
def test_freeze_and_coupled_limits_equal(robots, criterion):
    model = robots["koch11"]
    frozen = cycle._frozen(model, (1, 2))
    start = cycle._near_home(model)

    def held(rng):
        q = start(rng)
        for j, v in frozen.items():
            q[j] = v
        return q

    opts = CycleOptions(frozen=frozen, criterion=criterion)
    stats = cycle._compare(model, opts, seed=30, start=held, jump=0.2, starts=3)
    assert stats["relaxed"] > 0
    ref = np.array(model.home_q(), dtype=float)
    cyclic = CycleOptions(frozen=frozen, reference=ref, criterion=criterion)
    cycle._compare(model, cyclic, seed=32, start=held, starts=3)
    irb6 = robots["irb6"]
    stats = cycle._compare(irb6, CycleOptions(criterion=criterion), seed=8, step=0.02,
                           jump=0.2, starts=4)  # fmt: skip
    assert stats["cycles"] > 0


def test_energy_without_inertials_same_failure():
    """Both paths raise the same positioned-later failure naming what is missing."""
    from .ik_robots import planar_arm

    model = planar_arm(3)  # no [[inertials]]
    assert model.missing_inertia is not None
    q = np.array([0.1, 0.5, -0.5])
    messages = []
    for ik in cycle._pair(model, task_rows=(0, 1)):
        target = ik.kin.tcp(q)
        with pytest.raises(Exception, match="needs the links' inertia matrix") as err:
            ik.step(q, q, target, 0.01, CycleOptions(criterion="ENERGY"))
        messages.append(str(err.value))
    assert messages[0] == messages[1]
