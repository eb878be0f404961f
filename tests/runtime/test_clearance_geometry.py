"""Clearance between links (runtime/model/clearance.py) against independent computations: the
batched segment distances against the scalar Ericson routine and dense sampling, the watched
pairs against their rule, capsule distances in closed form, a single robot's reported
self-clearance against a brute-force sampling of its capsules."""

from __future__ import annotations

import numpy as np
import pytest
from irlc.robots import load_robot
from irlc.runtime.model.clearance import PartSet, RobotParts, segment_distances
from irlc.runtime.model.distance import closest_segment_segment
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.run import placed


def _sampled(p0, p1, q0, q1, n=401):
    """The least distance of two segments by dense sampling (independent of Ericson)."""
    s = np.linspace(0.0, 1.0, n)
    a = p0 + s[:, None] * (p1 - p0)
    b = q0 + s[:, None] * (q1 - q0)
    return float(np.min(np.linalg.norm(a[:, None, :] - b[None, :, :], axis=2)))


def test_batched_segment_distances_equal_the_scalar_routine_and_sampling():
    rng = np.random.default_rng(7)
    P = rng.normal(size=(600, 4, 3))
    P[:100, 1] = P[:100, 0]  # a point against a segment
    P[100:200, 3] = P[100:200, 2]  # a segment against a point
    P[200:250, 1] = P[200:250, 0]  # two points
    P[250 : 250 + 50, 3] = P[250:300, 2] + 1.5 * (P[250:300, 1] - P[250:300, 0])  # parallel
    P[300:350, 2:] = P[300:350, :2] + [0.0, 0.0, 0.3]  # parallel, overlapping in s
    s, t, p, q = segment_distances(P[:, 0], P[:, 1], P[:, 2], P[:, 3])
    assert np.all((s >= 0) & (s <= 1) & (t >= 0) & (t <= 1))
    got = np.linalg.norm(p - q, axis=1)
    for k in range(len(P)):
        _, _, p0, q0 = closest_segment_segment(*P[k])
        assert got[k] == pytest.approx(np.linalg.norm(p0 - q0), abs=1e-12)
    for k in range(0, len(P), 15):  # the points are on the segments, and the least
        assert got[k] == pytest.approx(_sampled(*P[k]), abs=2e-2 * max(1.0, got[k]))
        assert got[k] <= _sampled(*P[k]) + 1e-12


def test_capsule_distance_in_closed_form():
    """Two robots' first links, vertical capsules (radius 0.12 m) with their axes ``D`` apart:
    ``D − 2·0.12`` — the least distance of two straight as6 arms ``D`` apart."""
    as6 = load_robot("as6")
    for d in (1.0, 0.7):
        b = placed(as6, (0.0, d * 1000, 0.0, 0.0, 0.0, 0.0))
        kins = (Kinematics(as6), Kinematics(b))
        parts = PartSet([RobotParts("a", kins[0]), RobotParts("b", kins[1])], own=False)
        q = np.zeros(6)
        a_, b_ = parts.world([k.link_frames(q) for k in kins])
        c = parts.closest(a_, b_)
        assert c.distance == pytest.approx(d - 0.24, abs=1e-12)
        assert (c.robot_a, c.link_a, c.robot_b, c.link_b) == (0, 1, 1, 1)
        assert np.allclose(c.direction, [0.0, -1.0, 0.0])  # from b to a
        assert np.linalg.norm(c.point_a - c.point_b) == pytest.approx(d - 0.24)


@pytest.mark.parametrize("name", ["as6", "panda", "koch11", "planar3"])
def test_own_pairs_follow_the_rule(name):
    """A robot's own watched pairs: links two or more apart, apart at home; the other pairs of
    links two or more apart touch or overlap at home."""
    model = load_robot(name)
    kin = Kinematics(model)
    robot = RobotParts("", kin)
    a, b = robot.world(kin.link_frames(model.home_q()))
    watched = set(zip(*(x.tolist() for x in robot.self_pairs), strict=True))
    for i in range(robot.size):
        for j in range(i + 1, robot.size):
            _, _, p, q = closest_segment_segment(a[i], b[i], a[j], b[j])
            d = np.linalg.norm(p - q) - robot.radius[i] - robot.radius[j]
            far = abs(int(robot.links[i]) - int(robot.links[j])) >= 2
            assert ((i, j) in watched) == (far and d > 0.0), (i, j, d)
    assert np.all(robot.home > 0.0)


def test_keep_between_robots_and_within_one():
    as6 = load_robot("as6")
    parts = PartSet([RobotParts("a", Kinematics(as6)), RobotParts("b", Kinematics(as6))])
    keep = parts.keep(0.05)
    between = parts.robot[parts.i] != parts.robot[parts.j]
    assert np.all(keep[between] == 0.05)
    own = ~between
    assert np.all(keep[own] == np.where(parts.home[own] >= 0.05, 0.05, 0.0))


def test_self_clearance_of_a_program_of_one_robot_against_sampling():
    """square.irl's report states koch11's own links' least distance (not judged): recomputed
    at the reported time by dense sampling of every watched pair of capsules."""
    from pathlib import Path

    from irlc.runtime.run import run_file

    program = Path(__file__).resolve().parents[2] / "programs" / "square.irl"
    run = run_file(program)
    own = run.report["self_clearance"]
    k = int(np.flatnonzero(np.isclose(run.times, own["at_time_s"]))[0])
    kin = Kinematics(run.model)
    robot = RobotParts("", kin)
    a, b = robot.world(kin.link_frames(run.q[k]))
    best, links = np.inf, None
    for i, j in zip(*robot.self_pairs, strict=True):
        d = _sampled(a[i], b[i], a[j], b[j], 301) - robot.radius[i] - robot.radius[j]
        if d < best:
            best, links = d, (int(robot.links[i]), int(robot.links[j]))
    assert own["min_distance_mm"] == pytest.approx(best * 1000, abs=0.5)
    assert (own["link_a"], own["link_b"]) == links
    assert run.status == "ok"  # reported, not judged


@pytest.mark.parametrize("name", ["koch11", "panda", "mobile8", "l1"])
def test_batched_forward_kinematics_is_the_one_at_a_time(name):
    model = load_robot(name)
    kin = Kinematics(model)
    lim = model.position_limits
    qs = lim[:, 0] + np.random.default_rng(1).random((40, model.n)) * (lim[:, 1] - lim[:, 0])
    many = kin.link_frames_many(qs)
    assert all(np.array_equal(many[k], kin.link_frames(q)) for k, q in enumerate(qs))
    seg = RobotParts("", kin).segments
    a, b = seg.world_many(kin, many)
    for k in range(0, 40, 7):
        a1, b1 = seg.world(kin, many[k])
        assert np.allclose(a[k], a1, atol=1e-15) and np.allclose(b[k], b1, atol=1e-15)
