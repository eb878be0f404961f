"""The per-cycle fast paths equal the straightforward computations they replace.

* the interpolator's precomputed slerp equals ``spatial.quat_to_matrix(spatial.slerp(…))``
  bit for bit (lines and arcs), and the reference lookup equals ``np.searchsorted``;
* the recorder's growing arrays hold exactly what was added (past several capacity
  doublings) and its vectorised derivatives equal per-sample backward differences;
* the pruned box search of ``critical_points`` equals an exhaustive search over all
  parts with the plain segment–box routine (ties: the lowest part index);
* a whole run records the TCP of the recorded joints (independent FK) and a path error
  equal to ``spatial.pose_error`` against the interpolated pose.
"""

from __future__ import annotations

import numpy as np
import pytest
from irlc.robots import load_robot
from irlc.runtime.model import spatial
from irlc.runtime.model.distance import TIE, closest_segment_box, critical_points, robot_segments
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.model.obstacles import BoxObstacle, PlaneObstacle
from irlc.runtime.outputs.recorder import Recorder, finite_differences
from irlc.runtime.plan.interpolator import CartesianArc, CartesianLine, ReferencePath


def _pose(rot: np.ndarray, p: np.ndarray) -> np.ndarray:
    t = np.eye(4)
    t[:3, :3], t[:3, 3] = rot, p
    return t


def _slerp_pose(path, position: np.ndarray, s: float) -> np.ndarray:
    t = np.eye(4)
    t[:3, :3] = spatial.quat_to_matrix(spatial.slerp(path._q0, path._q1, s))
    t[:3, 3] = position
    return t


def test_line_and_arc_setpoints_equal_the_spatial_composition_bitwise():
    rng = np.random.default_rng(4)
    for i in range(300):
        r0 = spatial.zyx_to_matrix(*rng.uniform(-3, 3, 3))
        scale = 1e-7 if i % 3 == 0 else 1.0  # nearly equal orientations: linear branch
        r1 = r0 @ spatial.zyx_to_matrix(*(scale * rng.uniform(-3, 3, 3)))
        a, b = _pose(r0, rng.normal(size=3)), _pose(r1, rng.normal(size=3))
        line = CartesianLine(a, b)
        arc = CartesianArc(a, rng.normal(size=3), b)
        for s in [0.0, 1.0, *rng.uniform(0.0, 1.0, 4)]:
            p_line = a[:3, 3] + s * (b[:3, 3] - a[:3, 3])
            assert np.array_equal(line.at(s), _slerp_pose(line, p_line, s))
            assert np.array_equal(arc.at(s), _slerp_pose(arc, arc.position(s), s))


def test_reference_path_equals_searchsorted_interpolation():
    rng = np.random.default_rng(5)
    for _ in range(200):
        m = int(rng.integers(2, 5))
        knots = np.sort(np.concatenate(([0.0], rng.uniform(0.0, 1.0, m - 1))))
        configs = rng.normal(size=(m, 3))
        ref = ReferencePath(knots, configs)
        for s in [0.0, 1.0, *knots, *rng.uniform(0.0, 1.0, 5)]:
            i = int(np.searchsorted(knots, s, side="right")) - 1
            if i >= m - 1:
                expected = configs[-1]
            else:
                w = (s - knots[i]) / (knots[i + 1] - knots[i])
                expected = configs[i] + w * (configs[i + 1] - configs[i])
            assert np.array_equal(ref.at(s), expected)


def test_recorder_arrays_hold_every_sample_across_growth():
    rng = np.random.default_rng(6)
    n, k = 3, 70
    rec = Recorder(n, ("box",), capacity=4)  # grows 4 → 8 → … → 128
    times = np.round(np.cumsum(rng.uniform(0.005, 0.02, k)), 9)
    q = rng.normal(size=(k, n))
    tcps = rng.normal(size=(k, 4, 4))
    errors = rng.uniform(0.0, 1e-9, (k, 2))
    clear = [float(v) if i % 3 else None for i, v in enumerate(rng.uniform(0.1, 1.0, k))]
    for i in range(k):
        clearances = None if clear[i] is None else {"box": (clear[i], 2)}
        active = {1: "speed max"} if i % 5 == 0 else None
        rec.add(
            times[i], 10 + i, q[i], tcps[i], None, errors=tuple(errors[i]), iterations=i % 4,
            relaxed=i % 7 == 0, active=active, clearances=clearances, dt=0.01,
        )  # fmt: skip
    out = rec.arrays()
    assert len(rec) == k and out.q.shape == (k, n)
    np.testing.assert_array_equal(out.times, times)
    np.testing.assert_array_equal(out.lines, 10 + np.arange(k))
    np.testing.assert_array_equal(out.q, q)
    np.testing.assert_array_equal(out.tcp, tcps)
    np.testing.assert_array_equal(out.pos_error, errors[:, 0])
    np.testing.assert_array_equal(out.ori_error, errors[:, 1])
    np.testing.assert_array_equal(out.iterations, np.arange(k) % 4)
    np.testing.assert_array_equal(out.relaxed, np.arange(k) % 7 == 0)
    np.testing.assert_array_equal(out.active[:, 1], np.arange(k) % 5 == 0)
    assert not out.active[:, [0, 2]].any()
    assert rec.active_time == {(1, "speed max"): pytest.approx(0.01 * len(range(0, k, 5)))}
    # unmeasured cycles repeat the last clearance (inf before the first measurement)
    last, expected = np.inf, []
    for c in clear:
        last = c if c is not None else last
        expected.append(last)
    np.testing.assert_array_equal(out.clearance["box"], expected)
    # derivatives: per-sample backward differences, rest before the first sample
    speed = np.zeros_like(q)
    accel = np.zeros_like(q)
    for i in range(1, k):
        h = times[i] - times[i - 1]
        speed[i] = (q[i] - q[i - 1]) / h
        accel[i] = (speed[i] - speed[i - 1]) / h
    np.testing.assert_allclose(out.speed, speed, rtol=1e-12, atol=0.0)
    np.testing.assert_allclose(out.accel, accel, rtol=1e-9, atol=1e-9)
    s2, a2 = finite_differences(out.times, out.q)
    np.testing.assert_array_equal(s2, out.speed)
    np.testing.assert_array_equal(a2, out.accel)


def test_recorder_computes_the_path_error_when_not_given():
    rec = Recorder(2, task_rows=(0, 1))  # planar task: x, y only
    actual = _pose(spatial.zyx_to_matrix(0.3, 0.0, 0.0), np.array([1.0, 2.0, 3.0]))
    desired = _pose(np.eye(3), np.array([1.0, 2.5, 9.0]))
    rec.add(0.0, 1, np.zeros(2), actual, desired)
    rec.add(0.01, 1, np.zeros(2), actual, None)
    np.testing.assert_allclose(rec.pos_error, [0.5, 0.0])  # z is not controlled
    np.testing.assert_array_equal(rec.ori_error, [0.0, 0.0])  # nor the orientation


@pytest.fixture(scope="module")
def koch11():
    return load_robot("koch11")


def test_box_search_equals_exhaustive_search(koch11):
    kin = Kinematics(koch11)
    seg = robot_segments(kin)
    rng = np.random.default_rng(7)
    for _ in range(60):
        q = koch11.home_q() + rng.normal(scale=0.4, size=koch11.n)
        frames = kin.link_frames(q)
        centre = kin.tcp(q)[:3, 3] + rng.normal(scale=2.5, size=3)
        box = BoxObstacle(
            "b", centre, rng.uniform(0.1, 4.0, 3), spatial.zyx_to_matrix(*rng.uniform(-3, 3, 3))
        )
        a_all, b_all = seg.world(kin, frames)
        dists = [
            closest_segment_box(a_all[i], b_all[i], box.center, box.rotation, box.half)[0]
            - seg.radius[i]
            for i in range(len(seg.radius))
        ]
        # ties (within distance.TIE of the least) go to the lowest index
        best = int(np.flatnonzero(np.array(dists) <= min(dists) + TIE)[0])
        cp = critical_points(kin, frames, [box])[0]
        assert cp.distance == pytest.approx(dists[best], rel=0, abs=1e-12)  # see below
        assert cp.link == int(seg.links[best])
        _, p, _, v = closest_segment_box(
            a_all[best], b_all[best], box.center, box.rotation, box.half
        )
        # the same to round-off: the search computes all segments in array operations,
        # whose SIMD kernels may round the last bit differently (seen on AVX2)
        np.testing.assert_allclose(cp.robot_point, p - seg.radius[best] * v, rtol=0, atol=1e-12)


def test_plane_search_equals_exhaustive_search(koch11):
    kin = Kinematics(koch11)
    seg = robot_segments(kin)
    rng = np.random.default_rng(8)
    for _ in range(30):
        frames = kin.link_frames(koch11.home_q() + rng.normal(scale=0.4, size=koch11.n))
        normal = rng.normal(size=3)
        plane = PlaneObstacle("f", rng.normal(size=3), normal / np.linalg.norm(normal))
        a_all, b_all = seg.world(kin, frames)
        ends = np.minimum(
            (a_all - plane.point) @ plane.normal, (b_all - plane.point) @ plane.normal
        )
        cp = critical_points(kin, frames, [plane])[0]
        assert cp.distance == pytest.approx(float(np.min(ends - seg.radius)), abs=1e-12)


def test_run_records_fk_of_its_joints_and_the_path_error(monkeypatch):
    """The recorded TCP is the FK of the recorded joints and the recorded path error is
    ``‖f(θ_k) ⊖ x_d(t_k)‖`` against the pose the interpolator asked for (captured)."""
    from pathlib import Path

    from irlc.runtime.ik.newton import InverseTransformation
    from irlc.runtime.run import run_file

    targets = []
    step = InverseTransformation.step

    def spy(self, q, q_prev, target, dt, options=None):
        targets.append(np.array(target))
        return step(self, q, q_prev, target, dt, options)

    monkeypatch.setattr(InverseTransformation, "step", spy)
    run = run_file(Path(__file__).resolve().parents[2] / "programs" / "square.irl")
    assert run.ok, run.error
    kin = Kinematics(run.model)
    rec = run.recorded
    ik = np.flatnonzero(rec.iterations > 0)
    assert len(ik) == len(targets) > 1000
    for k, target in zip(ik[::9], targets[::9], strict=True):
        tcp = kin.tcp(rec.q[k])
        np.testing.assert_allclose(rec.tcp[k], tcp, rtol=0.0, atol=1e-12)
        err = spatial.pose_error(tcp, target)
        assert rec.pos_error[k] == pytest.approx(np.linalg.norm(err[:3]), abs=1e-13)
        assert rec.ori_error[k] == pytest.approx(np.linalg.norm(err[3:]), abs=1e-13)
    assert 0.0 < rec.pos_error.max() < 1e-8
