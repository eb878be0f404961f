"""The compiled obstacle queries (runtime/ik/compiled/distance.py) against the numpy
reference (runtime/model/distance.py, runtime/ik/obstacle.py) on random configurations: the
same part, distances, points and directions to 1e-12, and the same criterion terms."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("numba")

from irlc.robots import load_robot
from irlc.runtime.ik.compiled import distance as ad
from irlc.runtime.ik.obstacle import obstacle_terms
from irlc.runtime.ik.params import ObstacleParams
from irlc.runtime.model import spatial
from irlc.runtime.model.distance import critical_points, robot_segments
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.model.obstacles import (
    BoxObstacle,
    CapsuleObstacle,
    PlaneObstacle,
    PointObstacle,
    SphereObstacle,
)

from .ik_robots import planar_arm

ROBOTS = ("koch11", "panda", "planar4", "mobile8")


def _model(name):
    return planar_arm(3) if name == "planar3_bare" else load_robot(name)


def _obstacles(rng, kin, q):
    """Every kind, around a random point of the arm (some penetrate, some touch)."""
    frames = kin.link_frames(q)
    seg = robot_segments(kin)
    a, b = seg.world(kin, frames)
    i = rng.integers(a.shape[0])
    c = a[i] + rng.uniform() * (b[i] - a[i]) + rng.normal(scale=0.3, size=3)
    size = rng.uniform(0.05, 1.0, size=3)
    normal = rng.normal(size=3)
    return [
        PointObstacle("p", c),
        SphereObstacle("s", c + rng.normal(scale=0.1, size=3), rng.uniform(0.01, 0.3)),
        BoxObstacle("b", c, size, spatial.zyx_to_matrix(*rng.uniform(-np.pi, np.pi, 3))),
        BoxObstacle("w", c + np.array([0.0, 0.0, 0.2]), np.array([4.0, 0.2, 4.0]), np.eye(3)),
        CapsuleObstacle("c", c, c + rng.normal(scale=0.5, size=3), rng.uniform(0.01, 0.2)),
        CapsuleObstacle("d", a[i], b[i], 0.05),  # along a part: touching cores
        PlaneObstacle("f", c, normal / np.linalg.norm(normal)),
        PointObstacle("on", a[i].copy()),  # on a part's core: the fallback direction
    ]


def _kernel_points(kin, frames, obstacles):
    seg = robot_segments(kin)
    out = np.empty((len(obstacles), ad.N_CP))
    tcp = kin.tcp_from_frames(frames)
    ad.critical_points(frames, tcp, seg.links, seg.a_local, seg.b_local, seg.radius,
                       seg.fallback, ad.pack_obstacles(obstacles), out)  # fmt: skip
    return out


@pytest.mark.parametrize("name", [*ROBOTS, "planar3_bare"])
def test_critical_points_equal_numpy(name):
    model = _model(name)
    kin = Kinematics(model)
    rng = np.random.default_rng(sum(map(ord, name)))
    home = np.array(model.home_q(), dtype=float)
    for _ in range(60):
        q = home + rng.normal(scale=0.4, size=model.n)
        frames = kin.link_frames(q)
        obstacles = _obstacles(rng, kin, q)
        got = _kernel_points(kin, frames, obstacles)
        for row, cp in zip(got, critical_points(kin, frames, obstacles), strict=True):
            assert int(row[ad.D_LINK]) == cp.link, cp.name
            assert row[ad.D_DIST] == pytest.approx(cp.distance, abs=1e-12), cp.name
            np.testing.assert_allclose(row[ad.D_ROBOT : ad.D_ROBOT + 3], cp.robot_point,
                                       rtol=0, atol=1e-12)  # fmt: skip
            np.testing.assert_allclose(row[ad.D_OBST : ad.D_OBST + 3], cp.obstacle_point,
                                       rtol=0, atol=1e-12)  # fmt: skip
            np.testing.assert_allclose(row[ad.D_DIR : ad.D_DIR + 3], cp.direction,
                                       rtol=0, atol=1e-12)  # fmt: skip


def test_the_combined_program_walls_equal_numpy():
    """koch11 beside the two boxes of programs/combined.toml (one 4 m wall): ties and
    pruning as in the numpy search, near and far from the wall."""
    model = load_robot("koch11")
    kin = Kinematics(model)
    wall = BoxObstacle("sciana_1", np.array([10.5, -2.5, 2.0]), np.array([4.0, 0.2, 4.0]))
    window = BoxObstacle("okno", np.array([10.5, 2.6, 3.5]), np.array([1.0, 0.2, 1.0]))
    rng = np.random.default_rng(5)
    home = np.array(model.home_q(), dtype=float)
    for _ in range(200):
        q = home + rng.normal(scale=0.6, size=model.n)
        frames = kin.link_frames(q)
        got = _kernel_points(kin, frames, [wall, window])
        for row, cp in zip(got, critical_points(kin, frames, [wall, window]), strict=True):
            assert int(row[ad.D_LINK]) == cp.link
            assert row[ad.D_DIST] == pytest.approx(cp.distance, abs=1e-12)
            np.testing.assert_allclose(row[ad.D_ROBOT : ad.D_ROBOT + 3], cp.robot_point,
                                       rtol=0, atol=1e-12)  # fmt: skip


@pytest.mark.parametrize("name", ROBOTS)
def test_obstacle_terms_equal_numpy(name):
    """The criterion's terms: weight, push αv, the critical point's Jacobian and JᵀJ."""
    model = _model(name)
    kin = Kinematics(model)
    params = ObstacleParams(activation=1.0)  # (most random obstacles are active)
    rng = np.random.default_rng(3 + len(name))
    home = np.array(model.home_q(), dtype=float)
    chain = kin.chain_data
    seg = robot_segments(kin)
    n, active = model.n, 0
    for _ in range(40):
        q = home + rng.normal(scale=0.4, size=n)
        frames = kin.link_frames(q)
        obstacles = _obstacles(rng, kin, q)
        k = len(obstacles)
        ow, opush = np.empty(k), np.empty((k, 3))
        ojac, ojtj, cps = np.empty((k, 3, n)), np.empty((k, n, n)), np.empty((k, ad.N_CP))
        cnt = ad.obstacle_terms(
            frames, kin.tcp_from_frames(frames), chain.joints, seg.links, seg.a_local,
            seg.b_local, seg.radius, seg.fallback, ad.pack_obstacles(obstacles),
            ad.pack_params(params), cps, ow, opush, ojac, ojtj,
        )  # fmt: skip
        ref = obstacle_terms(kin, frames, obstacles, params)
        assert cnt == len(ref)
        active += cnt
        for t, term in enumerate(ref):
            assert ow[t] == pytest.approx(term.weight, abs=1e-12)
            np.testing.assert_allclose(opush[t], term.push, rtol=1e-12, atol=1e-12)
            np.testing.assert_allclose(ojac[t], term.jac, rtol=0, atol=1e-12)
            np.testing.assert_allclose(ojtj[t], term.jtj, rtol=0, atol=1e-11)
    assert active > 40  # the comparison saw terms


def test_packed_rows_hold_the_shapes():
    box = BoxObstacle("b", np.array([1.0, 2.0, 3.0]), np.array([2.0, 4.0, 6.0]),
                      spatial.zyx_to_matrix(0.3, 0.2, 0.1))  # fmt: skip
    cap = CapsuleObstacle("c", np.zeros(3), np.ones(3), 0.5)
    rows = ad.pack_obstacles([box, cap])
    assert rows.shape == (2, ad.N_COLS) and not rows.flags.writeable
    assert rows[0, ad.C_KIND] == ad.BOX and rows[1, ad.C_KIND] == ad.CAPSULE
    np.testing.assert_array_equal(rows[0, ad.C_HALF : ad.C_HALF + 3], [1.0, 2.0, 3.0])
    np.testing.assert_array_equal(rows[0, ad.C_ROT :].reshape(3, 3), box.rotation)
    np.testing.assert_array_equal(rows[1, ad.C_Q : ad.C_Q + 3], np.ones(3))
    assert rows[1, ad.C_RADIUS] == 0.5


def test_the_kernels_use_the_reference_tolerances():
    """numba freezes these into the machine code: they must stay those of distance.py."""
    from irlc.runtime.model import distance

    assert ad._TIE == distance.TIE and ad._EPS == distance._EPS


def test_the_compiled_cycle_makes_no_numpy_distance_query(monkeypatch):
    """With obstacles avoided and reported, the compiled cycle gets its terms and its
    clearances from the kernels (issue 14: the numpy queries were most of its time),
    with the numbers of the numpy cycle."""
    from irlc.runtime.ik.newton import InverseTransformation
    from irlc.runtime.ik.params import CycleOptions, IKParams
    from irlc.runtime.model import distance

    model = load_robot("koch11")
    kin = Kinematics(model)
    q = np.array(model.home_q(), dtype=float)
    target = kin.tcp(q)
    target[2, 3] -= 2e-3
    tcp = target[:3, 3]
    shapes = (BoxObstacle("box", tcp + np.array([0.0, 0.35, 0.0]), np.array([0.2, 0.2, 0.2])),
              SphereObstacle("ball", tcp + np.array([0.0, -0.4, 0.1]), 0.05))  # fmt: skip
    opts = CycleOptions(obstacles=shapes, active_obstacles=frozenset({"box", "ball"}))
    ref = InverseTransformation(model, kin, IKParams.for_robot(model, accel=False))
    want = ref.step(q, q, target, 0.01, opts)
    fast = InverseTransformation(model, Kinematics(model), IKParams.for_robot(model, accel=True))

    def forbidden(*args, **kwargs):
        raise AssertionError("a numpy distance query on the compiled path")

    for module in (distance,):  # (the chain's bodies call it through the module)
        monkeypatch.setattr(module, "critical_points", forbidden)
    got = fast.step(q, q, target, 0.01, opts)
    np.testing.assert_allclose(got.q, want.q, rtol=0, atol=1e-10)
    assert got.clearances.keys() == want.clearances.keys()
    for name, (dist, link) in want.clearances.items():
        assert got.clearances[name][0] == pytest.approx(dist, abs=1e-12)
        assert got.clearances[name][1] == link
    assert min(d for d, _ in want.clearances.values()) < 0.5  # the criterion was active
