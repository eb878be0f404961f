"""The IPO-cycle inverse transformation: convergence, limits, options, failures."""

from __future__ import annotations

import math

import numpy as np
import pytest
from irlc.runtime import units
from irlc.runtime.ik import (
    CycleOptions,
    FreezeError,
    IKParams,
    InverseTransformation,
    LimitViolationError,
    reconfiguration_done,
    solve_pose,
)
from irlc.runtime.model import spatial
from irlc.runtime.model.kinematics import Kinematics

from .ik_robots import XY, line_poses, planar_arm, run_path, smooth, square_poses


# ------------------------------------------------------------------ convergence
def test_newton_reaches_random_reachable_targets_on_koch11(koch11):
    kin = Kinematics(koch11)
    ik = InverseTransformation(koch11, kin, IKParams(tol_position=1e-10, tol_orientation=1e-10))
    rng = np.random.default_rng(3)
    q0 = koch11.home_q()
    for _ in range(20):
        target = kin.tcp(q0 + rng.normal(scale=0.01, size=koch11.n))
        r = ik.step(q0, q0, target, dt=0.05)
        err = spatial.pose_error(kin.tcp(r.q), target)
        assert r.converged and not r.relaxed
        assert np.linalg.norm(err[:3]) < 1e-9 and np.linalg.norm(err[3:]) < 1e-9
        assert 1 <= r.iterations <= 4


def test_solve_pose_reaches_random_far_targets(koch11):
    kin = Kinematics(koch11)
    rng = np.random.default_rng(4)
    lim = koch11.position_limits
    home = koch11.home_q()
    solved = 0
    for _ in range(10):
        q_goal = np.clip(home + rng.normal(scale=0.3, size=koch11.n), lim[:, 0], lim[:, 1])
        target = kin.tcp(q_goal)
        sol = solve_pose(koch11, target, home, tol_position=1e-10, tol_orientation=1e-10)
        if sol.converged:
            solved += 1
            err = spatial.pose_error(kin.tcp(sol.q), target)
            assert np.linalg.norm(err[:3]) < 1e-9
            assert np.all(sol.q >= lim[:, 0]) and np.all(sol.q <= lim[:, 1])
        else:  # then it must say why, with finite numbers
            assert sol.message and np.isfinite(sol.position_error)
    assert solved >= 8


def test_solve_pose_unreachable_is_reported_without_nan(koch11):
    target = units.pose_to_si(60000, 0, 0, 0, 0, 0)  # 60 m away
    sol = solve_pose(koch11, target, koch11.home_q())
    assert not sol.converged
    assert np.all(np.isfinite(sol.q)) and np.isfinite(sol.position_error)
    assert "not reachable" in sol.message


def test_solve_pose_rejects_seed_outside_limits(koch11):
    seed = koch11.home_q()
    seed[3] = -0.5  # J4 min is 0 deg
    sol = solve_pose(koch11, np.eye(4), seed)
    assert not sol.converged and "J4" in sol.message and "outside" in sol.message


# ------------------------------------------------------------------ limits box
def finite_differences(qs, dt):
    v = np.diff(qs, axis=0) / dt
    a = np.diff(qs, axis=0, n=2) / dt**2
    return v, a


def test_position_speed_accel_limits_hold_along_a_demanding_path():
    model = planar_arm(3, speed=1.0, accel=8.0)
    kin = Kinematics(model)
    ik = InverseTransformation(model, kin, IKParams(task_rows=XY))
    q0 = np.array([0.3, 1.2, -1.0])
    pos = model.position_limits.copy()
    pos[2] = (-1.03, 0.4)  # a program limit on J3 that the motion runs into
    opts = CycleOptions(position=pos, speed=model.speed_limits, accel=model.accel_limits)
    start = kin.tcp(q0)
    end = start.copy()
    end[:3, 3] += (-0.9, 0.5, 0.0)
    dt = 0.01
    qs, results = run_path(ik, q0, line_poses(start, end, 50), dt, opts)
    v, a = finite_differences(qs, dt)
    tol = 1e-9
    assert np.all(qs >= pos[:, 0] - tol) and np.all(qs <= pos[:, 1] + tol)
    assert np.all(np.abs(v) <= 1.0 + tol / dt)
    assert np.all(np.abs(a) <= 8.0 + tol / dt**2)
    kinds = {what for r in results for what in r.active.values()}
    assert "position min" in kinds and "accel max" in kinds | {"accel min"}


def test_braking_bound_keeps_the_acceleration_box_nonempty():
    """A joint running fast towards a position limit brakes in time (never an empty box)."""
    model = planar_arm(3, speed=2.0, accel=5.0)
    kin = Kinematics(model)
    ik = InverseTransformation(model, kin, IKParams(task_rows=XY))
    pos = model.position_limits.copy()
    pos[0] = (-math.pi, 0.35)
    opts = CycleOptions(position=pos)
    q0 = np.array([0.0, 0.5, 0.5])
    # the TCP circles about the base: joint 1 must turn and runs into its limit
    dt = 0.01
    poses = []
    base = kin.tcp(q0)
    for i in range(1, 120):
        ang = 0.8 * smooth(i / 119)
        poses.append(spatial.transform(spatial.rot_z(ang), (0, 0, 0)) @ base)
    qs, results = run_path(ik, q0, poses, dt, opts)
    _v, a = finite_differences(qs, dt)
    assert np.all(qs[:, 0] <= 0.35 + 1e-9)
    assert np.all(np.abs(a) <= 5.0 + 1e-6)
    assert any(0 in r.active for r in results)


def test_limit_excluding_the_state_is_an_error_naming_joint_value_and_bound(koch11):
    kin = Kinematics(koch11)
    ik = InverseTransformation(koch11, kin)
    q = koch11.home_q()
    pos = koch11.position_limits.copy()
    pos[10, 1] = 20 * units.DEG  # J11 is at 21.119 deg
    with pytest.raises(LimitViolationError) as info:
        ik.step(q, q, kin.tcp(q), 0.01, CycleOptions(position=pos))
    assert info.value.violation.joint == 10
    assert "a11 (J11) position max 20 deg" in info.value.message
    assert "21.119 deg" in info.value.message


def test_speed_limit_below_current_speed_is_an_error(koch11):
    kin = Kinematics(koch11)
    ik = InverseTransformation(koch11, kin)
    q = koch11.home_q()
    q_prev = q.copy()
    q_prev[0] -= 0.01  # J1 moved 0.01 rad in 10 ms: 57 deg/s > 50 deg/s
    speed = koch11.speed_limits.copy()
    speed[0] = (-50 * units.DEG, 50 * units.DEG)  # the book's set 6.2
    with pytest.raises(LimitViolationError, match=r"a1 \(J1\) speed max 50 deg/s"):
        ik.step(q, q_prev, kin.tcp(q), 0.01, CycleOptions(speed=speed))


# ------------------------------------------------------------------ CYCLIC
def test_cyclic_returns_to_start_and_default_drifts_on_planar3_square():
    model = planar_arm(3, speed=10.0, accel=1000.0)
    kin = Kinematics(model)
    q0 = np.array([0.2, 1.4, 1.2])
    center = kin.tcp(q0)[:2, 3] - np.array([0.25, 0.25])
    poses = square_poses(center, 0.5, 60)
    laps = 3
    default = InverseTransformation(model, kin, IKParams(task_rows=XY))
    qs_d, _ = run_path(default, q0, poses * laps, 0.01)
    cyclic = InverseTransformation(model, kin, IKParams(task_rows=XY))
    qs_c, res_c = run_path(cyclic, q0, poses * laps, 0.01, CycleOptions(reference=q0))
    drift = np.abs(qs_d[len(poses) :: len(poses)] - q0).max(axis=1)
    assert drift[0] > 1e-3  # weighted minimum-norm control does not close the loop
    assert drift[-1] > drift[0]  # ... and drifts further lap after lap
    np.testing.assert_allclose(qs_c[-1], q0, atol=1e-8)
    assert all(r.converged for r in res_c)


# ------------------------------------------------------------------ FREEZE
def test_freeze_keeps_frozen_joints_exactly_constant(koch11):
    kin = Kinematics(koch11)
    ik = InverseTransformation(koch11, kin)
    q0 = koch11.home_q()
    start = kin.tcp(q0)
    end = start.copy()
    end[:3, 3] += (-1.0, 0.0, 0.0)
    opts = CycleOptions(frozen={1: q0[1], 2: q0[2]})
    qs, results = run_path(ik, q0, line_poses(start, end, 200), 0.01, opts)
    assert np.all(qs[:, 1] == q0[1]) and np.all(qs[:, 2] == q0[2])
    assert all(r.converged for r in results)
    assert np.abs(qs[-1] - q0).max() > 0.01  # the other joints did move


def test_freeze_by_removal_equals_equality_rows(koch11):
    """Removing frozen joints gives the same step as the seed's Φ rows e_iᵀΔθ = 0."""
    from irlc.runtime.ik.compact import CompactBasis
    from irlc.runtime.ik.freeze import FrozenJoints
    from irlc.runtime.ik.newton_step import NewtonStep
    from irlc.runtime.ik.qp import QuadprogSolver

    kin = Kinematics(koch11)
    q0 = koch11.home_q()
    target = kin.tcp(q0)
    target[:3, 3] += (-0.01, 0.004, 0.002)
    ik = InverseTransformation(koch11, kin)
    # speed and acceleration boxes wide: only the position box remains
    wide = dict(speed=koch11.speed_limits * 1e3, accel=koch11.accel_limits * 1e6)
    opts = CycleOptions(frozen={1: q0[1], 2: q0[2]}, **wide)
    r = ik.step(q0, q0, target, 0.01, opts)
    # the same first Newton step with the Φ rows appended to J (full 8×11 system)
    frozen = FrozenJoints(koch11.n, opts.frozen)
    frames = kin.link_frames(q0)
    tcp = kin.tcp_from_frames(frames)
    J = np.vstack((kin.jacobian_at(frames, tcp[:3, 3]), frozen.phi_jacobian()))
    F = np.concatenate((spatial.pose_error(tcp, target), frozen.phi(q0)))
    W = np.diag(koch11.weights)
    lim = koch11.position_limits
    step = NewtonStep(QuadprogSolver(), basis=CompactBasis()).hard(
        J, F, W, np.zeros(koch11.n), lim[:, 0] - q0, lim[:, 1] - q0
    )
    one = InverseTransformation(koch11, kin, IKParams(max_iter=1, warm_start=False))
    r1 = one.step(q0, q0, target, 0.01, opts)
    np.testing.assert_allclose(r1.q - q0, step.dtheta, atol=1e-12)
    assert r.converged


def test_freezing_too_many_joints_is_a_clear_failure(koch11):
    kin = Kinematics(koch11)
    ik = InverseTransformation(koch11, kin)
    q0 = koch11.home_q()
    frozen = {j: q0[j] for j in range(6)}  # 5 free joints for a 6-row task
    names = ", ".join(rf"a{i} \(J{i}\)" for i in range(1, 7))
    with pytest.raises(FreezeError, match=f"FREEZE of joints {names}"):
        ik.step(q0, q0, kin.tcp(q0), 0.01, CycleOptions(frozen=frozen))


# ------------------------------------------------------------------ RECONFIGURATION
def test_reconfiguration_keeps_tcp_while_joints_approach_target():
    model = planar_arm(3, speed=2.0, accel=50.0)
    kin = Kinematics(model)
    ik = InverseTransformation(model, kin, IKParams(task_rows=XY))
    q0 = np.array([0.2, 1.0, 1.0])
    hold = kin.tcp(q0)
    # a configuration with the same TCP position and the hand turned by −0.8 rad
    turned = hold @ spatial.transform(spatial.rot_z(-0.8))
    sol = solve_pose(model, turned, q0, task_rows=(0, 1, 5))
    assert sol.converged
    goal = sol.q
    assert np.linalg.norm(goal - q0) > 0.3
    opts = CycleOptions(reference=goal, self_motion=True)
    q_prev2, q_prev, q = q0.copy(), q0.copy(), q0.copy()
    single_rule_stops = 0
    finished = False
    for _ in range(2000):
        r = ik.step(q, q_prev, hold, 0.01, opts)
        q_prev2, q_prev, q = q_prev, q, r.q
        assert np.linalg.norm(kin.tcp(q)[:2, 3] - hold[:2, 3]) < 1e-9
        single_rule_stops += reconfiguration_done(q, q_prev, 1e-9)
        if reconfiguration_done(q, q_prev, 1e-9, q_prev2):
            finished = True
            break
    assert finished
    d0, d1 = np.linalg.norm(q0 - goal), np.linalg.norm(q - goal)
    assert d1 < 1e-6 * d0
    # the seed's one-cycle rule would have stopped at the reversal after the overshoot
    assert single_rule_stops >= 2


# ------------------------------------------------------------------ infeasible cycles
def test_abrupt_target_gives_relaxed_cycle_with_deviation(koch11):
    kin = Kinematics(koch11)
    ik = InverseTransformation(koch11, kin)
    q0 = koch11.home_q()
    target = kin.tcp(q0)
    target[:3, 3] += (0.5, 0.0, 0.0)  # 0.5 m in one 10 ms cycle from rest
    r = ik.step(q0, q0, target, 0.01)
    assert r.relaxed and not r.converged
    assert 0.0 < r.position_error <= 0.5
    assert r.binding  # names the limit that stopped it, e.g. "J… accel max …"
    assert np.all(np.isfinite(r.q))


def test_executor_turns_a_relaxed_cycle_beyond_tolerance_into_a_run_failure(koch11):
    """The path deviation is judged by the executor (one mechanism): the same cycle as
    above fails the run with the IK's own deviation, the line and the binding limit."""
    from types import SimpleNamespace

    from irlc.runtime.commands import Settings
    from irlc.runtime.control.executor import SimulatedController
    from irlc.runtime.errors import RunFailure
    from irlc.runtime.ik.params import CycleOptions

    kin = Kinematics(koch11)
    q0 = koch11.home_q()
    target = kin.tcp(q0)
    target[:3, 3] += (0.5, 0.0, 0.0)
    expected = InverseTransformation(koch11, kin).step(q0, q0, target, 0.01)
    ctl = SimulatedController(koch11, q0)
    solver = ctl._solver(Settings())
    with pytest.raises(RunFailure) as info:
        ctl.cycles.ik_cycle(SimpleNamespace(line=7), target, 0.01, CycleOptions(), solver)
    err = info.value
    assert err.line == 7 and err.time_s == pytest.approx(0.01)
    assert f"TCP deviation {expected.position_error / units.MM:.4g} mm" in err.message
    assert err.constraint == expected.binding != ""
    span = ctl.recorder.relaxed_spans[-1]
    assert span.line == 7 and span.max_deviation == expected.position_error


def test_unreachable_far_target_never_nan(koch11):
    kin = Kinematics(koch11)
    ik = InverseTransformation(koch11, kin)
    q_prev = q = koch11.home_q()
    target = units.pose_to_si(80000, 5000, -3000, 30, 10, 0)
    for _ in range(50):
        r = ik.step(q, q_prev, target, 0.01)
        q_prev, q = q, r.q
        assert np.all(np.isfinite(q)) and np.isfinite(r.position_error)
        assert r.relaxed
    assert np.all(q >= koch11.position_limits[:, 0] - 1e-9)
    assert np.all(q <= koch11.position_limits[:, 1] + 1e-9)


def test_non_finite_target_is_a_clear_failure(koch11):
    from irlc.runtime.ik import IKFailure

    kin = Kinematics(koch11)
    ik = InverseTransformation(koch11, kin)
    q = koch11.home_q()
    target = kin.tcp(q)
    target[0, 3] = np.nan
    with pytest.raises(IKFailure, match="non-finite target"):
        ik.step(q, q, target, 0.01)
