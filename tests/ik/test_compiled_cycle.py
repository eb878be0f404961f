"""The compiled cycle (runtime/ik/compiled/, numba) equals the numpy reference path.

Both solvers get the same inputs every cycle (the numpy result is fed to both), so each
cycle's mapping is compared on its own: q and the TCP to 1e-10, the same iteration
count (hard cycles; a relaxed cycle stops when its step falls below ~1e-13, a round-off
decision), relaxed / converged / singular flags and the same binding text.
"""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("numba")

from irlc.robots import load_robot
from irlc.runtime import accel_support
from irlc.runtime.ik import CycleOptions, IKParams, InverseTransformation, intersect_limits
from irlc.runtime.ik.coupled import CoupledRows
from irlc.runtime.ik.freeze import FreezeError
from irlc.runtime.model import spatial
from irlc.runtime.model.distance import critical_points, robot_parts, segment_obstacle
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.model.obstacles import BoxObstacle, SphereObstacle

pytestmark = pytest.mark.skipif(not accel_support.AVAILABLE, reason="no numba or IRLC_ENGINE=numpy")


def _pair(model, **params):
    out = []
    for flag in (True, False):
        p = IKParams.for_robot(model, accel=flag, **params)
        out.append(InverseTransformation(model, Kinematics(model), p))
    assert out[0].accelerated and not out[1].accelerated
    return out


def _random_q(model, rng, margin=0.15):
    lo, hi = model.position_limits.T
    lo = np.maximum(lo, -3.0)
    hi = np.minimum(hi, 3.0)
    return lo + (hi - lo) * rng.uniform(margin, 1.0 - margin, size=model.n)


def _try(step, *args):
    try:
        return step(*args)
    except Exception as exc:  # compared between the paths by the caller
        return exc


def _link_distance(kin, q, obstacle, link):
    """Distance from ``obstacle`` to the closest part of ``link`` at ``q``."""
    parts = robot_parts(kin, kin.link_frames(q))
    return min(segment_obstacle(a, b, r, obstacle).distance
               for lk, a, b, r in parts if lk == link)  # fmt: skip


def _compare(
    model, options, *, seed=0, starts=6, cycles=25, step=0.01, jump=0.0, start=None, **params
):
    """Random starts (``start(rng)``, default uniform inside the limits), random walks of
    targets; ``jump`` adds far targets (relaxed)."""
    fast, ref = _pair(model, **params)
    kin = Kinematics(model)
    rng = np.random.default_rng(seed)
    stats = {"relaxed": 0, "bound": 0, "cycles": 0, "singular": 0, "failed": 0}
    for _ in range(starts):
        q = _random_q(model, rng) if start is None else start(rng)
        if fast.coupled is not None:  # a start inside the coupled rows
            while np.any(fast.coupled.A[: fast.coupled.npos] @ q - fast.coupled.b < 0.0):
                q = _random_q(model, rng)
        q_prev = q.copy()
        target = kin.tcp(q)
        for c in range(cycles):
            target = target.copy()
            target[:3, 3] += rng.normal(size=3) * step
            if jump and c % 7 == 3:
                target[:3, 3] += rng.normal(size=3) * jump
            a, b = (_try(ik.step, q, q_prev, target, 0.01, options) for ik in (fast, ref))
            if isinstance(a, Exception) or isinstance(b, Exception):  # the same failure
                assert (type(a), str(a)) == (type(b), str(b))
                stats["failed"] += 1
                break
            assert np.allclose(a.q, b.q, rtol=0.0, atol=1e-10), (c, a.q - b.q)
            assert np.allclose(a.tcp, b.tcp, rtol=0.0, atol=1e-10)
            if not b.relaxed:  # relaxed cycles stop when the step is ~1e-13: round-off
                assert a.iterations == b.iterations
            assert (a.relaxed, a.converged, a.singular) == (b.relaxed, b.converged, b.singular)
            assert a.binding == b.binding
            assert a.active == b.active
            assert abs(a.position_error - b.position_error) < 1e-10
            assert a.clearances.keys() == b.clearances.keys()
            for name, (dist, link) in a.clearances.items():
                assert abs(dist - b.clearances[name][0]) < 1e-10
                if link != b.clearances[name][1]:  # only an exact tie of two links
                    obstacle = next(o for o in options.obstacles if o.name == name)
                    assert abs(_link_distance(kin, b.q, obstacle, link) - dist) < 1e-10
            stats["relaxed"] += a.relaxed
            stats["singular"] += a.singular
            stats["bound"] += bool(a.binding)
            stats["cycles"] += 1
            q_prev, q = q, b.q
    return stats


@pytest.fixture(scope="module")
def robots():
    return {name: load_robot(name) for name in ("koch11", "panda", "planar3", "irb6")}


def _tight(model, scale=0.3):
    speed = model.speed_limits * scale
    accel = model.accel_limits * scale
    return intersect_limits(model, None, speed, accel)


@pytest.mark.parametrize("name", ["koch11", "panda", "planar3"])
def test_default_criterion_equal(robots, name):
    stats = _compare(robots[name], CycleOptions(), jump=0.3)
    assert stats["relaxed"] > 0  # the far targets exercised the relaxed QP too


@pytest.mark.parametrize("name", ["koch11", "panda", "planar3"])
def test_tight_limits_equal(robots, name):
    model = robots[name]
    pos, spd, acc = _tight(model)
    stats = _compare(model, CycleOptions(position=pos, speed=spd, accel=acc), step=0.02, seed=1)
    assert stats["bound"] > 0  # some box bound was active


@pytest.mark.parametrize("name", ["koch11", "panda", "planar3"])
def test_cyclic_and_self_motion_equal(robots, name):
    model = robots[name]
    ref = np.clip(np.array(model.home, dtype=float), *model.position_limits.T)
    _compare(model, CycleOptions(reference=ref), seed=2)
    _compare(model, CycleOptions(reference=ref, self_motion=True), seed=3, step=0.0)


def test_planar3_task_rows_and_scalar_qp_off(robots):
    model = robots["planar3"]
    _compare(model, CycleOptions(), seed=4, jump=1.0)
    _compare(model, CycleOptions(), seed=5, scalar_qp=False)


def test_panda_quadprog_for_the_1d_qp_and_no_warm_start(robots):
    _compare(robots["panda"], CycleOptions(), seed=6, scalar_qp=False, jump=0.2)
    _compare(robots["panda"], CycleOptions(), seed=7, warm_start=False)


def test_irb6_coupled_limits_equal(robots):
    model = robots["irb6"]
    fast, _ = _pair(model)
    assert fast.coupled is not None
    stats = _compare(model, CycleOptions(), seed=8, step=0.02, jump=0.2, starts=8)
    assert stats["cycles"] > 0


def test_reported_obstacles_equal(robots):
    model = robots["koch11"]
    kin = Kinematics(model)
    tcp = kin.tcp(np.array(model.home, dtype=float))
    box = BoxObstacle("box", tcp[:3, 3] + (0.0, 0.0, 0.6), np.array([0.2, 0.2, 0.2]), np.eye(3))
    ball = SphereObstacle("ball", tcp[:3, 3] + (0.5, 0.0, 0.0), 0.1)
    _compare(model, CycleOptions(obstacles=[box, ball]), seed=9, starts=3)
    far = CycleOptions(obstacles=[box, ball], active_obstacles=frozenset({"box"}))
    _compare(model, far, seed=10, starts=2)  # avoided, but beyond the activation distance


def _near_home(model, spread=0.02):
    home = np.array(model.home_q(), dtype=float)
    return lambda rng: home + rng.normal(size=model.n) * spread


def _obstacles_near(model, gaps=(0.25, 0.3)):
    """A sphere and a box beside two parts of the arm at home (within the activation
    distance): several critical points, each with a non-zero weight."""
    kin = Kinematics(model)
    parts = robot_parts(kin, kin.link_frames(np.array(model.home_q(), dtype=float)))
    parts = [p for p in parts if np.linalg.norm(p[2] - p[1]) > 1e-6]  # (not spheres)
    picks = [parts[len(parts) // 2], parts[-2]]
    out = []
    for i, ((_, a, b, r), gap) in enumerate(zip(picks, gaps, strict=True)):
        axis = b - a
        side = np.cross(axis, (0.0, 0.0, 1.0))
        if np.linalg.norm(side) < 1e-9:
            side = np.cross(axis, (1.0, 0.0, 0.0))
        side /= np.linalg.norm(side)
        center = 0.5 * (a + b) + side * (r + gap + 0.05)
        if i == 0:
            out.append(SphereObstacle("ball", center, 0.05))
        else:
            out.append(BoxObstacle("box", center, np.array([0.05, 0.05, 0.05]), np.eye(3)))
    return out


@pytest.mark.parametrize("name", ["koch11", "panda"])
def test_avoided_obstacles_equal(robots, name):
    """OBSTACLE: the criterion's terms (several critical points) in the compiled cycle."""
    model = robots[name]
    obstacles = _obstacles_near(model)
    kin = Kinematics(model)
    home = np.array(model.home_q(), dtype=float)
    near = critical_points(kin, kin.link_frames(home), obstacles)
    assert all(cp.distance < 0.4 for cp in near)  # inside the activation distance
    avoid = CycleOptions(obstacles=obstacles, active_obstacles=frozenset({"ball", "box"}))
    start = _near_home(model)
    _compare(model, avoid, seed=20, starts=3, start=start)
    stats = _compare(model, avoid, seed=24, starts=2, start=start, step=0.0005)
    assert stats["relaxed"] < stats["cycles"]
    ref = home + 0.05
    cyclic = CycleOptions(obstacles=obstacles, active_obstacles=frozenset({"ball"}), reference=ref)
    _compare(model, cyclic, seed=21, starts=2, start=start)
    tight = CycleOptions(
        *_tight(model), obstacles=obstacles, active_obstacles=frozenset({"ball", "box"})
    )
    _compare(model, tight, seed=22, starts=2, start=start, jump=0.2)


def test_planar4_box_obstacle_equal():
    """The planar arm of programs/planar4_obstacle.irl beside its box (task x, y)."""
    model = load_robot("planar4")
    box = BoxObstacle("box", np.array([0.6, -0.15, 0.0]), np.array([0.2, 0.15, 0.5]), np.eye(3))
    avoid = CycleOptions(obstacles=[box], active_obstacles=frozenset({"box"}))
    _compare(model, avoid, seed=23, starts=3, start=_near_home(model, 0.05))


def _frozen(model, joints):
    home = np.array(model.home_q(), dtype=float)
    return {j: float(home[j]) for j in joints}


@pytest.mark.parametrize("name, joints", [("koch11", (1, 2)), ("mobile8", (0, 1)),
                                          ("panda", (3,)), ("planar3", (0,))])  # fmt: skip
def test_freeze_equal(robots, name, joints):
    """FREEZE: the step over the free joints (the frozen ones held), default criterion,
    tight limits and far targets (relaxed steps)."""
    model = robots.get(name) or load_robot(name)
    frozen = _frozen(model, joints)
    start = _near_home(model)

    def held(rng):
        q = start(rng)
        for j, v in frozen.items():
            q[j] = v
        return q

    stats = _compare(model, CycleOptions(frozen=frozen), seed=30, start=held, jump=0.2)
    assert stats["relaxed"] > 0
    stats = _compare(model, CycleOptions(frozen=frozen), seed=37, start=held, step=0.0005)
    if name in ("koch11", "planar3"):  # redundant after FREEZE: hard steps, general QP
        assert stats["relaxed"] < stats["cycles"]
    pos, spd, acc = _tight(model)
    opts = CycleOptions(position=pos, speed=spd, accel=acc, frozen=frozen)
    _compare(model, opts, seed=31, start=held, step=0.02)
    ref = np.array(model.home_q(), dtype=float)
    _compare(model, CycleOptions(frozen=frozen, reference=ref), seed=32, start=held)
    _compare(model, CycleOptions(frozen=frozen, reference=ref, self_motion=True), seed=33,
             start=held, step=0.0)  # fmt: skip


def test_freeze_releases_towards_held_values(robots):
    """A frozen joint away from its held value moves there (step c = θ⁰ − θ_k) on both
    paths; too far for one cycle's box: the same IKFailure."""
    model = robots["koch11"]
    home = np.array(model.home_q(), dtype=float)
    frozen = {1: float(home[1]) + 1e-3}
    _compare(model, CycleOptions(frozen=frozen), seed=34, starts=2, start=lambda rng: home)
    far = CycleOptions(frozen={1: float(home[1]) + 0.5})
    for ik in _pair(model):
        with pytest.raises(Exception, match="frozen joints are away"):
            ik.step(home, home, Kinematics(model).tcp(home), 0.01, far)


@pytest.mark.parametrize("freeze", [False, True])
def test_non_finite_inputs_same_failure(robots, freeze):
    """The kernel's own finiteness test (``S_NOT_FINITE``) raises what the numpy path's
    first test raises; a configuration whose ‖q‖² overflows is finite and gets the
    numpy path's next failure (the joint limits)."""
    model = robots["panda"]
    home = np.array(model.home_q(), dtype=float)
    opts = CycleOptions(frozen={0: float(home[0])} if freeze else {})
    target = Kinematics(model).tcp(home)
    bad_q, bad_t, huge_q = home.copy(), target.copy(), home.copy()
    bad_q[3] = np.nan
    bad_t[1, 2] = np.inf
    huge_q[2] = 1e200
    cases = ((bad_q, target), (home, bad_t), (huge_q, target))
    for q, t in cases:
        with np.errstate(over="ignore"):  # (the numpy path's ‖q‖² overflows for huge_q)
            outcomes = [_try(ik.step, q, home, t, 0.01, opts) for ik in _pair(model)]
        assert all(isinstance(o, Exception) for o in outcomes), outcomes
        assert type(outcomes[0]) is type(outcomes[1])
        assert str(outcomes[0]) == str(outcomes[1])
    fast, _ = _pair(model)
    fast.step(home, home, target, 0.01, opts)  # a failed cycle leaves no state behind


def test_freeze_too_many_joints_same_error(robots):
    model = robots["panda"]
    home = np.array(model.home_q(), dtype=float)
    opts = CycleOptions(frozen=_frozen(model, (0, 1)))
    messages = []
    for ik in _pair(model):
        with pytest.raises(FreezeError) as err:
            ik.step(home, home, Kinematics(model).tcp(home), 0.01, opts)
        messages.append(str(err.value))
    assert messages[0] == messages[1]


def test_irb6_coupled_with_freeze_and_obstacles_equal(robots):
    """Coupled joint limits with FREEZE (position task only: 5 joints, 3 rows, a5 held)
    and with an avoided obstacle."""
    model = robots["irb6"]
    start = _near_home(model)
    frozen = _frozen(model, (4,))
    rows = CoupledRows(model)

    def held(rng):
        q = _random_q(model, rng)
        while np.any(rows.A @ q - rows.b < 0.0):
            q = _random_q(model, rng)
        q[4] = frozen[4]
        return q

    freeze = CycleOptions(*_tight(model), frozen=frozen)
    stats = _compare(model, freeze, seed=35, start=held, step=0.005, starts=4, jump=0.1,
                     task_rows=(0, 1, 2))  # fmt: skip
    assert stats["cycles"] > 50 and stats["bound"] > 0
    obstacles = _obstacles_near(model)
    avoid = CycleOptions(obstacles=obstacles, active_obstacles=frozenset({"ball", "box"}))
    _compare(model, avoid, seed=36, start=start, starts=3, jump=0.1)


def test_the_factory_picks_the_engine(robots, monkeypatch):
    """engine.compiled_cycle: IKParams.accel and IRLC_ENGINE decide (accel_support.decide);
    the default is numpy whatever numba's cache holds (fast first run, same bytes); daqp
    and max_iter < 1 are not covered."""
    model = robots["panda"]

    def compiled(**params) -> bool:
        return InverseTransformation(model, Kinematics(model), IKParams(**params)).accelerated

    assert compiled(accel=False) is False
    assert compiled(accel=True) is True
    monkeypatch.delenv("IRLC_ENGINE", raising=False)
    assert compiled(accel=None) is False
    monkeypatch.setenv("IRLC_ENGINE", "numpy")
    assert compiled(accel=None) is False
    assert compiled(accel=True) is False  # numpy wins over the parameter
    monkeypatch.setenv("IRLC_ENGINE", "compiled")
    assert compiled(accel=None) is True
    assert compiled(accel=False) is False
    assert compiled(accel=None, max_iter=0) is False
    monkeypatch.setenv("IRLC_ENGINE", "auto")
    assert compiled(accel=None) is True


def test_every_option_runs_compiled(robots, monkeypatch):
    """FREEZE, avoided obstacles, CYCLIC, RECONFIGURATION and coupled limits never take
    the numpy cycle on an accelerated solver (before issue 14, FREEZE and OBSTACLE did)."""
    from irlc.runtime.ik.newton import InverseTransformation as IT

    def numpy_cycle(*args, **kwargs):
        raise AssertionError("the numpy cycle ran on an accelerated solver")

    monkeypatch.setattr(IT, "_solve", numpy_cycle)
    monkeypatch.setattr(IT, "_solve_diagonal", numpy_cycle)
    model = robots["koch11"]
    home = np.array(model.home_q(), dtype=float)
    obstacles = _obstacles_near(model)
    ik = _pair(model)[0]
    target = Kinematics(model).tcp(home)
    for opts in (
        CycleOptions(frozen=_frozen(model, (1, 2))),
        CycleOptions(obstacles=obstacles, active_obstacles=frozenset({"ball", "box"})),
        CycleOptions(
            obstacles=obstacles,
            active_obstacles=frozenset({"box"}),
            reference=home,
            frozen=_frozen(model, (4,)),
        ),
        CycleOptions(reference=home + 0.01, self_motion=True),
    ):
        assert ik.step(home, home, target, 0.01, opts).converged
    irb6 = robots["irb6"]
    q = np.array(irb6.home_q(), dtype=float)
    ik = _pair(irb6)[0]
    ik.step(q, q, Kinematics(irb6).tcp(q), 0.01, CycleOptions())


def test_penetrating_obstacles_equal(robots):
    """OBSTACLE with the arm inside a box and a sphere (negative clearances, the box's
    deepest point on a crossing of two faces' depths: a tie that distance.TIE settles
    the same way on both paths)."""
    model = robots["koch11"]
    kin = Kinematics(model)
    home = np.array(model.home_q(), dtype=float)
    parts = robot_parts(kin, kin.link_frames(home))
    _, a, b, _ = max(parts, key=lambda p: np.linalg.norm(p[2] - p[1]))  # the longest part
    box = BoxObstacle("box", 0.5 * (a + b), np.array([0.3, 0.4, 0.5]),
                      spatial.zyx_to_matrix(0.3, -0.2, 0.7))  # fmt: skip
    ball = SphereObstacle("ball", 0.3 * a + 0.7 * b, 0.1)
    near = critical_points(kin, kin.link_frames(home), [box, ball])
    assert all(cp.distance < 0.0 for cp in near)
    avoid = CycleOptions(obstacles=[box, ball], active_obstacles=frozenset({"box", "ball"}))
    stats = _compare(model, avoid, seed=31, starts=3, start=_near_home(model, 0.01))
    assert stats["cycles"] > 0
