"""Exact closest points vs brute-force sampling and scipy.optimize; penetration sign."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.optimize
from irlc.lang.irdata import ObstacleDef
from irlc.runtime.model import spatial
from irlc.runtime.model.distance import (
    closest_segment_box,
    closest_segment_segment,
    critical_points,
    segment_obstacle,
)
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.model.obstacles import (
    BoxObstacle,
    CapsuleObstacle,
    PlaneObstacle,
    PointObstacle,
    SphereObstacle,
    from_definition,
    from_program_units,
)

from .ik_robots import planar_arm

S = np.linspace(0.0, 1.0, 4001)


def sample_segment(a, b):
    return a + S[:, None] * (b - a)


def box_distance_brute(points, center, rotation, half):
    local = (points - center) @ rotation  # rows: Rᵀ(p − c)
    excess = np.abs(local) - half
    outside = np.linalg.norm(np.maximum(excess, 0.0), axis=1)
    inside = np.minimum(np.max(excess, axis=1), 0.0)
    return outside + inside  # exact signed distance of each point


def random_rotation(rng):
    return spatial.zyx_to_matrix(*rng.uniform(-np.pi, np.pi, 3))


def test_segment_segment_matches_scipy_and_sampling():
    rng = np.random.default_rng(11)
    for _ in range(40):
        p0, p1, q0, q1 = rng.normal(size=(4, 3))
        s, t, c1, c2 = closest_segment_segment(p0, p1, q0, q1)
        d = np.linalg.norm(c1 - c2)
        np.testing.assert_allclose(c1, p0 + s * (p1 - p0), atol=1e-12)
        np.testing.assert_allclose(c2, q0 + t * (q1 - q0), atol=1e-12)

        def f(x, p0=p0, p1=p1, q0=q0, q1=q1):
            return np.sum((p0 + x[0] * (p1 - p0) - q0 - x[1] * (q1 - q0)) ** 2)

        best = min(
            scipy.optimize.minimize(f, x0, bounds=[(0, 1), (0, 1)], method="L-BFGS-B").fun
            for x0 in ([0.5, 0.5], [0, 1], [1, 0])
        )
        assert d <= np.sqrt(best) + 1e-7
        pts_p, pts_q = sample_segment(p0, p1)[::20], sample_segment(q0, q1)[::20]
        grid = np.linalg.norm(pts_p[:, None] - pts_q[None], axis=2)
        assert d <= grid.min() + 1e-12 and grid.min() - d < 0.02


def test_segment_segment_parallel_and_degenerate():
    a, b = np.zeros(3), np.array([1.0, 0.0, 0.0])
    c, d = np.array([0.2, 1.0, 0.0]), np.array([0.7, 1.0, 0.0])
    _, _, c1, c2 = closest_segment_segment(a, b, c, d)  # parallel
    assert np.linalg.norm(c1 - c2) == pytest.approx(1.0)
    p = np.array([3.0, 4.0, 0.0])
    _, _, c1, c2 = closest_segment_segment(a, a, p, p)  # two points
    assert np.linalg.norm(c1 - c2) == pytest.approx(5.0)


@pytest.mark.parametrize("seed", range(5))
def test_segment_box_matches_dense_sampling(seed):
    rng = np.random.default_rng(seed)
    for _ in range(40):
        center = rng.normal(size=3)
        rotation = random_rotation(rng)
        half = rng.uniform(0.1, 1.0, 3)
        a, b = center + rng.normal(scale=1.5, size=(2, 3))
        d, p, q, v = closest_segment_box(a, b, center, rotation, half)
        brute = box_distance_brute(sample_segment(a, b), center, rotation, half)
        assert d <= brute.min() + 1e-12  # exact: never worse than any sample
        assert brute.min() - d < 2e-3 * np.linalg.norm(b - a) + 1e-12
        # the reported points are consistent with the distance and direction
        assert abs(box_distance_brute(p[None], center, rotation, half)[0] - d) < 1e-9
        np.testing.assert_allclose(np.linalg.norm(v), 1.0, atol=1e-12)
        if d > 0:
            np.testing.assert_allclose(p - q, d * v, atol=1e-9)


def test_segment_box_distance_matches_box_surface_sampling():
    """Against the other side: dense samples of the box surface."""
    rng = np.random.default_rng(21)
    half = np.array([0.3, 0.2, 0.5])
    g = np.linspace(-1, 1, 21)
    u, w = np.meshgrid(g, g)
    faces = []
    for axis in range(3):
        for sign in (-1, 1):
            pts = np.zeros((u.size, 3))
            others = [i for i in range(3) if i != axis]
            pts[:, axis] = sign * half[axis]
            pts[:, others[0]] = u.ravel() * half[others[0]]
            pts[:, others[1]] = w.ravel() * half[others[1]]
            faces.append(pts)
    surface = np.vstack(faces)
    for _ in range(30):
        a, b = rng.normal(scale=1.0, size=(2, 3)) + np.array([1.0, 0, 0])
        d, *_ = closest_segment_box(a, b, np.zeros(3), np.eye(3), half)
        if d <= 0:
            continue
        seg = sample_segment(a, b)[::20]
        brute = np.min(np.linalg.norm(seg[:, None] - surface[None], axis=2))
        assert d <= brute + 1e-12 and brute - d < 0.08


def test_penetration_is_negative_with_nearest_face_escape():
    half = np.array([1.0, 2.0, 3.0])
    a, b = np.array([-5.0, 0.0, 0.0]), np.array([5.0, 0.0, 0.0])
    d, _p, _q, v = closest_segment_box(a, b, np.zeros(3), np.eye(3), half)
    assert d == pytest.approx(-1.0)  # the centre is 1 m inside the nearest faces (±x)
    assert abs(v[0]) == pytest.approx(1.0)
    box = BoxObstacle("b", np.zeros(3), 2 * half)
    prox = segment_obstacle(a, b, 0.1, box)
    assert prox.distance == pytest.approx(-1.1)  # the capsule's surface goes 0.1 deeper
    sphere = SphereObstacle("s", np.array([0.0, 0.05, 0.0]), 0.2)
    assert segment_obstacle(a, b, 0.1, sphere).distance == pytest.approx(0.05 - 0.3)


def test_swept_shapes_point_sphere_capsule_plane():
    a, b, r = np.array([0.0, 0.0, 0.0]), np.array([1.0, 0.0, 0.0]), 0.1
    prox = segment_obstacle(a, b, r, PointObstacle("p", np.array([0.5, 1.0, 0.0])))
    assert prox.distance == pytest.approx(0.9)
    np.testing.assert_allclose(prox.robot_point, [0.5, 0.1, 0.0])
    np.testing.assert_allclose(prox.direction, [0.0, -1.0, 0.0])
    prox = segment_obstacle(a, b, r, SphereObstacle("s", np.array([2.0, 0.0, 0.0]), 0.5))
    assert prox.distance == pytest.approx(0.4)
    cap = CapsuleObstacle("c", np.array([0.5, -1, 1.0]), np.array([0.5, 1, 1.0]), 0.2)
    assert segment_obstacle(a, b, r, cap).distance == pytest.approx(0.7)
    floor = PlaneObstacle("f", np.array([0, 0, -0.5]), np.array([0, 0, 1.0]))
    tilted = segment_obstacle(np.array([0, 0, 0.0]), np.array([1, 0, -0.3]), r, floor)
    assert tilted.distance == pytest.approx(0.2 - 0.1)
    np.testing.assert_allclose(tilted.obstacle_point, [1.0, 0.0, -0.5])
    below = segment_obstacle(np.array([0, 0, -1.0]), np.array([1, 0, -1.0]), r, floor)
    assert below.distance == pytest.approx(-0.6)


def test_point_box_matches_scipy_on_random_instances():
    rng = np.random.default_rng(8)
    for _ in range(50):
        rotation = random_rotation(rng)
        half = rng.uniform(0.1, 1.0, 3)
        p = rng.normal(scale=2.0, size=3)
        d, _, _q, _ = closest_segment_box(p, p, np.zeros(3), rotation, half)
        if d <= 0:
            continue
        res = scipy.optimize.minimize(
            lambda x, rotation=rotation, p=p: np.sum((rotation @ x - p) ** 2),
            np.zeros(3),
            bounds=list(zip(-half, half, strict=True)),
            method="L-BFGS-B",
            options={"ftol": 1e-15, "gtol": 1e-12},
        )
        assert d == pytest.approx(np.sqrt(res.fun), abs=1e-6)


def test_critical_points_pick_the_closest_link():
    model = planar_arm(3, radius=0.05)
    kin = Kinematics(model)
    q = np.array([0.0, np.pi / 2, 0.0])  # link 1 along x, links 2–3 along y from (1, 0)
    frames = kin.link_frames(q)
    obstacles = [
        PointObstacle("near2", np.array([1.3, 1.5, 0.0])),
        PointObstacle("near1", np.array([0.5, -0.4, 0.0])),
    ]
    cps = {cp.name: cp for cp in critical_points(kin, frames, obstacles)}
    assert cps["near2"].link == 3 and cps["near2"].distance == pytest.approx(0.25)
    assert cps["near1"].link == 1 and cps["near1"].distance == pytest.approx(0.35)


def test_obstacles_from_program_units():
    box = from_program_units(
        "w", {"kind": "box", "center": [10500, -2500, 2000], "size": [4000, 200, 4000]}
    )
    np.testing.assert_allclose(box.center, [10.5, -2.5, 2.0])
    np.testing.assert_allclose(box.half, [2.0, 0.1, 2.0])
    with pytest.raises(ValueError, match="unknown key"):
        from_program_units("w", {"kind": "sphere", "center": [0, 0, 0], "radius": 1, "size": 2})
    with pytest.raises(ValueError, match="kind must be one of"):
        from_program_units("w", {"kind": "cone"})
    with pytest.raises(ValueError, match="missing key"):
        from_program_units("w", {"kind": "sphere", "center": [0, 0, 0]})


def test_critical_points_equal_exhaustive_search_for_every_kind(koch11):
    """The pruned / vectorised search gives the same closest part as trying all parts."""
    from irlc.runtime.model.distance import robot_parts

    kin = Kinematics(koch11)
    rng = np.random.default_rng(12)
    for _ in range(10):
        q = koch11.home_q() + rng.normal(scale=0.2, size=koch11.n)
        frames = kin.link_frames(q)
        c = kin.tcp(q)[:3, 3] + rng.normal(scale=3.0, size=3)
        obstacles = [
            PointObstacle("p", c),
            SphereObstacle("s", c, 0.4),
            BoxObstacle("b", c, np.array([1.0, 0.5, 2.0]), random_rotation(rng)),
            CapsuleObstacle("c", c, c + rng.normal(size=3), 0.2),
            PlaneObstacle("f", c, np.array([0.0, 0.0, 1.0])),
        ]
        parts = robot_parts(kin, frames)
        for cp, obstacle in zip(critical_points(kin, frames, obstacles), obstacles, strict=True):
            exhaustive = min(segment_obstacle(a, b, r, obstacle).distance for _, a, b, r in parts)
            assert cp.distance == pytest.approx(exhaustive, abs=1e-12)


def test_obstacle_keys_are_the_data_list_keys():
    """The keys of docs/language.md §8 (point ``center``, box ``rotation`` as ZYX degrees)."""
    point = from_program_units("p", {"kind": "point", "center": [1000, 2000, 3000]})
    np.testing.assert_allclose(point.position, [1.0, 2.0, 3.0])
    box = from_program_units(
        "b", {"kind": "box", "center": [0, 0, 0], "size": [2000, 1000, 500], "rotation": [90, 0, 0]}
    )
    # a box turned 90° about z: its local x axis points along the world y axis
    np.testing.assert_allclose(box.rotation @ [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], atol=1e-12)


def test_obstacle_records_become_shapes_directly():
    """The code's typed OBSTACLE record (numbers per key, mm / deg) is the shape's input:
    the same shape as the table form, and a bad record names its key."""
    box = ObstacleDef("b", "box", (("center", (0.0, 0.0, 0.0)), ("size", (2000.0, 1000.0, 500.0)),
                                   ("rotation", (90.0, 0.0, 0.0))))  # fmt: skip
    shape = from_definition(box)
    np.testing.assert_allclose(shape.half, [1.0, 0.5, 0.25])
    np.testing.assert_allclose(shape.rotation @ [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], atol=1e-12)
    sphere = from_definition(ObstacleDef("s", "sphere", (("center", (1000.0, 0.0, 0.0)),
                                                         ("radius", (250.0,)))))  # fmt: skip
    assert sphere.radius == pytest.approx(0.25) and list(sphere.center) == [1.0, 0.0, 0.0]
    with pytest.raises(ValueError, match=r"obstacle s\.radius must be > 0, got \(1\.0, 2\.0\)"):
        from_definition(
            ObstacleDef("s", "sphere", (("center", (0.0,) * 3), ("radius", (1.0, 2.0))))
        )
    with pytest.raises(ValueError, match=r"obstacle p\.center must be 3 finite numbers, got 5\.0"):
        from_definition(ObstacleDef("p", "point", (("center", (5.0,)),)))


def test_runtime_obstacle_rules_are_the_data_list_rules():
    """One schema (IRDATA's OBSTACLE record) and the same positivity rules as the loader:
    a hand-written .ird cannot pass what a data list would reject."""
    with pytest.raises(ValueError, match="radius must be > 0"):
        from_program_units("s", {"kind": "sphere", "center": [0, 0, 0], "radius": 0})
    with pytest.raises(ValueError, match=r"size: box sizes must be positive"):
        from_program_units("b", {"kind": "box", "center": [0, 0, 0], "size": [1, 0, 1]})
    with pytest.raises(ValueError, match=r"normal: the plane normal must not be zero"):
        from_program_units("p", {"kind": "plane", "point": [0, 0, 0], "normal": [0, 0, 0]})
    with pytest.raises(ValueError, match="missing key"):
        from_program_units("b", {"kind": "box", "size": [1, 1, 1]})
