"""The hot-path variants give the same numbers as the plain formulas they replace."""

from __future__ import annotations

import numpy as np
import pytest
from irlc.robots import load_robot
from irlc.runtime.ik.compact import CompactBasis
from irlc.runtime.ik.limits import JointBox, LimitViolationError
from irlc.runtime.ik.newton_step import NewtonStep
from irlc.runtime.ik.qp import QuadprogSolver
from irlc.runtime.ik.task_error import pose_error_list
from irlc.runtime.model import spatial
from irlc.runtime.model.kinematics import Kinematics

from .test_qp_compact import kkt_certificate, random_instance


@pytest.mark.parametrize("robot", ["koch11", "panda", "irb6_track", "mobile8", "irb6"])
def test_chain_and_tcp_jacobian_equal_the_public_ones(robot):
    model = load_robot(robot)
    kin = Kinematics(model)
    rng = np.random.default_rng(3)
    out = np.empty((6, model.n))
    for _ in range(20):
        q = rng.uniform(-1.0, 1.0, model.n)
        frames = kin.link_frames(q)
        tcp = kin.tcp_from_frames(frames)
        reference = kin.jacobian_at(frames, tcp[:3, 3])
        np.testing.assert_array_equal(kin.chain(q), frames)
        np.testing.assert_allclose(kin.tcp_jacobian(frames, tcp[:3, 3], out), reference, atol=0)


def test_tcp_jacobian_matches_finite_differences():
    model = load_robot("koch11")  # revolute and prismatic joints
    kin = Kinematics(model)
    q = model.home_q() + 0.1
    frames = kin.link_frames(q)
    tcp = kin.tcp_from_frames(frames)
    J = kin.tcp_jacobian(frames, tcp[:3, 3], np.empty((6, model.n)))
    h = 1e-6
    for j in range(model.n):
        dq = np.zeros(model.n)
        dq[j] = h
        t1, t0 = kin.tcp(q + dq), kin.tcp(q - dq)
        np.testing.assert_allclose((t1[:3, 3] - t0[:3, 3]) / (2 * h), J[:3, j], atol=1e-7)
        w = spatial.rotation_vector(t1[:3, :3] @ t0[:3, :3].T) / (2 * h)
        np.testing.assert_allclose(w, J[3:, j], atol=1e-7)


def test_pose_error_list_equals_spatial_pose_error():
    rng = np.random.default_rng(4)
    for angle in [0.0, 1e-8, 1e-3, 0.5, 2.0, np.pi - 1e-3, np.pi - 1e-5, np.pi]:
        for _ in range(10):
            axis = rng.normal(size=3)
            axis /= np.linalg.norm(axis)
            target = spatial.transform(
                spatial.axis_angle(rng.normal(size=3), 0.7), rng.normal(size=3)
            )
            tcp = target.copy()
            tcp[:3, :3] = spatial.axis_angle(axis, angle) @ target[:3, :3]
            tcp[:3, 3] += rng.normal(size=3) * 0.01
            tl = target.tolist()
            fast = pose_error_list(
                tcp, (tl[0][:3], tl[1][:3], tl[2][:3]), tl[0][3:] + tl[1][3:] + tl[2][3:], target
            )
            np.testing.assert_allclose(
                fast, spatial.pose_error(tcp, target), rtol=1e-12, atol=1e-15
            )


def _old_box(pos, spd, acc, q_start, q_prev, dt):
    """The box of docs/ik.md written out plainly (the cancellation-prone braking form)."""
    d = q_start - q_prev
    eps_hi, eps_lo = -dt * dt * acc[:, 0], dt * dt * acc[:, 1]
    brake_hi = -eps_hi + np.sqrt(eps_hi**2 + 2 * eps_hi * np.maximum(pos[:, 1] - q_start, 0))
    brake_lo = eps_lo - np.sqrt(eps_lo**2 + 2 * eps_lo * np.maximum(q_start - pos[:, 0], 0))
    lower = np.max([pos[:, 0] - q_start, dt * spd[:, 0], dt * dt * acc[:, 0] + d, brake_lo], 0)
    upper = np.min([pos[:, 1] - q_start, dt * spd[:, 1], dt * dt * acc[:, 1] + d, brake_hi], 0)
    return lower, upper


def test_signed_box_equals_the_plain_formulas():
    model = load_robot("koch11")
    rng = np.random.default_rng(5)
    pos, spd, acc = model.position_limits, model.speed_limits, model.accel_limits
    box = JointBox(model.n)
    dt = 0.01
    for _ in range(200):
        q = pos[:, 0] + (pos[:, 1] - pos[:, 0]) * rng.uniform(0.0, 1.0, model.n)
        d = rng.uniform(-0.3, 0.3, model.n) * dt * spd[:, 1]
        lower, upper = _old_box(pos, spd, acc, q, q - d, dt)
        try:
            box.prepare(model, q, q - d, dt, pos, spd, acc)
        except LimitViolationError:  # the state is excluded: the plain box is empty too
            assert np.any(lower > upper + 1e-9)
            continue
        np.testing.assert_allclose(box.lower_d, lower, rtol=1e-9, atol=1e-15)
        np.testing.assert_allclose(box.upper_d, upper, rtol=1e-9, atol=1e-15)


def test_infinite_acceleration_limit_leaves_the_position_bound():
    """Regression: −ε + √(ε² + 2εR) evaluated to 0 for ε ≈ 1e26 (infinite accel), which
    froze every joint; the stable form gives the position bound R."""
    model = load_robot("panda")
    box = JointBox(model.n)
    pos = model.position_limits
    inf = np.tile([-np.inf, np.inf], (model.n, 1))
    q = 0.5 * (pos[:, 0] + pos[:, 1])
    box.prepare(model, q, q, 0.01, pos, inf, inf)
    np.testing.assert_allclose(box.upper_d, pos[:, 1] - q, rtol=1e-15)
    np.testing.assert_allclose(box.lower_d, pos[:, 0] - q, rtol=1e-15)


def _instances(n, m, count, seed):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        J, H, g, F, lower, upper = random_instance(rng, n, m, np.full(n, 1.0))
        w = np.diag(H).copy()
        yield J, w, g * 20.0, F, lower, upper


@pytest.mark.parametrize("n,m", [(7, 6), (11, 6), (5, 2)])
def test_diagonal_hard_step_equals_the_general_one(n, m):
    """hard_diagonal (scalar closed form for n − m = 1, quadprog otherwise) = hard with
    the full H: same step, same active rows and multipliers, same infeasibility."""
    fast = NewtonStep(QuadprogSolver(), basis=CompactBasis())
    plain = NewtonStep(QuadprogSolver(), basis=CompactBasis())
    active = infeasible = 0
    for J, w, g, F, lower, upper in _instances(n, m, 60, n):
        a = fast.hard_diagonal(J, F, w, g, np.array([lower, upper]))
        b = plain.hard(J, F, np.diag(w), g, lower, upper)
        assert (a is None) == (b is None)
        if a is None:
            infeasible += 1
            continue
        np.testing.assert_allclose(a.dtheta, b.dtheta, atol=1e-10)
        assert kkt_certificate(np.diag(w), g, J, a.dtheta, lower, upper)
        assert sorted(a.active.tolist()) == sorted(b.active.tolist())
        np.testing.assert_allclose(np.sort(a.multipliers), np.sort(b.multipliers), rtol=1e-7)
        active += a.active.size
    assert active > 0


def test_scalar_qp_infeasible_and_zero_column_cases():
    J = np.array([[1.0, 1.0]])  # n − m = 1, N = [−1; 1]
    step = NewtonStep(QuadprogSolver(), basis=CompactBasis())
    w = np.array([1.0, 2.0])
    bounds = np.array([[-0.1, -0.1], [0.1, 0.1]])
    assert step.hard_diagonal(J, np.array([1.0]), w, np.zeros(2), bounds) is None  # |Δθ|·2 ≥ 1
    out = step.hard_diagonal(J, np.array([-0.1]), w, np.zeros(2), bounds)
    np.testing.assert_allclose(J @ out.dtheta, [0.1], atol=1e-15)
    J0 = np.array([[1.0, 0.0, 1.0], [0.0, 1.0, 0.0]])  # joint 1 not in the null space
    step0 = NewtonStep(QuadprogSolver(), basis=CompactBasis())
    w3 = np.ones(3)
    b3 = np.array([-np.ones(3), np.ones(3)])
    a = step0.hard_diagonal(J0, np.array([0.2, 0.3]), w3, np.zeros(3), b3)
    b = NewtonStep(QuadprogSolver()).hard(J0, np.array([0.2, 0.3]), np.eye(3), np.zeros(3), *b3)
    np.testing.assert_allclose(a.dtheta, b.dtheta, atol=1e-12)


def test_kept_basis_gives_the_same_step_as_a_fresh_pivoted_one():
    """The basis chosen at an earlier J is kept (cheap LU) while it is well conditioned;
    the step equals the one with a freshly pivoted basis to rounding."""
    rng = np.random.default_rng(8)
    kept = NewtonStep(QuadprogSolver(), basis=CompactBasis())
    J0 = rng.normal(size=(6, 7))
    kept.hard_diagonal(
        J0, np.zeros(6), np.ones(7), np.zeros(7), np.array([-np.ones(7), np.ones(7)])
    )
    different = 0
    for J, w, g, F, lower, upper in _instances(7, 6, 40, 11):
        fresh = NewtonStep(QuadprogSolver(), basis=CompactBasis())
        a = kept.hard_diagonal(J, F, w, g, np.array([lower, upper]))
        b = fresh.hard_diagonal(J, F, w, g, np.array([lower, upper]))
        assert (a is None) == (b is None)
        different += set(kept.basis.columns[:6]) != set(fresh.basis.columns[:6])
        if a is not None:
            scale = 1.0 + np.max(np.abs(b.dtheta))
            assert np.max(np.abs(a.dtheta - b.dtheta)) <= 1e-12 * scale
    assert kept.basis.rechosen < 40  # kept most of the time
    assert different > 0  # and the kept basic columns differ from the fresh choice


def test_relaxed_diagonal_equals_relaxed():
    step = NewtonStep(QuadprogSolver(), basis=CompactBasis())
    for J, w, g, F, _, _ in _instances(7, 6, 30, 21):
        tight = 0.05 * np.ones(7)
        a = step.relaxed_diagonal(J, F * 10, w, g, np.array([-tight, tight]))
        b = step.relaxed(J, F * 10, np.diag(w), g, -tight, tight)
        np.testing.assert_allclose(a.dtheta, b.dtheta, atol=1e-9)
        assert sorted(a.active.tolist()) == sorted(b.active.tolist())
        np.testing.assert_allclose(np.sort(a.multipliers), np.sort(b.multipliers), rtol=1e-5)


def test_tcp_jacobian_with_negative_axes():
    import dataclasses

    from .ik_robots import planar_arm

    base = planar_arm(4)
    joints = tuple(
        dataclasses.replace(j, axis=-j.axis) if i % 2 else j for i, j in enumerate(base.joints)
    )
    model = dataclasses.replace(base, joints=joints)
    kin = Kinematics(model)
    assert kin._signed_axes
    q = np.array([0.3, -0.2, 0.5, 0.1])
    frames = kin.link_frames(q)
    tcp = kin.tcp_from_frames(frames)
    out = kin.tcp_jacobian(frames, tcp[:3, 3], np.empty((6, 4)))
    np.testing.assert_allclose(out, kin.jacobian_at(frames, tcp[:3, 3]), atol=0)
