"""Coupled joint limits (IRb-6: −40° ≤ θ2+θ3 ≤ 25°, −90° ≤ θ2+θ3+θ4 ≤ 90°) in the IK."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from irlc.robots import load_robot
from irlc.runtime.ik import CycleOptions, IKParams, InverseTransformation, solve_pose
from irlc.runtime.ik.coupled import CoupledLimitError
from irlc.runtime.model.coupled_limits import as_inequalities, coupled_limits, violations
from irlc.runtime.model.kinematics import Kinematics

from .ik_robots import line_poses

DEG = math.pi / 180.0


@pytest.fixture(scope="module")
def irb6():
    return load_robot("irb6")


def without_coupled(model):
    extra = {k: v for k, v in model.extra.items() if k != "coupled_limits"}
    return dataclasses.replace(model, extra=extra)


def slack(model, q) -> np.ndarray:
    """``Aq − b`` (≥ 0 inside), computed from the robot file's rows independently of the IK."""
    A, b = as_inequalities(coupled_limits(model), model.n)
    return A @ q - b


def test_solve_pose_no_longer_returns_theta23_80_deg(irb6):
    """A pose whose only solution near the seed has θ2+θ3 = 80° (limit 25°): without the
    coupled rows the solver returns it (the old behaviour), with them it is reported as not
    reachable and the returned configuration respects the limit."""
    q_bad = np.radians([90.0, 40.0, 40.0, -45.0, 0.0])
    target = Kinematics(irb6).tcp(q_bad)
    seed = irb6.home_q()
    old = solve_pose(without_coupled(irb6), target, seed)
    assert old.converged
    assert math.degrees(old.q[1] + old.q[2]) == pytest.approx(80.0, abs=1e-6)
    new = solve_pose(irb6, target, seed)
    assert not new.converged
    assert "theta2+theta3 max 25 deg" in new.message
    assert np.all(slack(irb6, new.q) >= -1e-9)
    assert math.degrees(new.q[1] + new.q[2]) <= 25.0 + 1e-7


def test_solve_pose_inside_coupled_limits_converges(irb6):
    q_goal = np.radians([100.0, 10.0, 10.0, -30.0, 20.0])
    target = Kinematics(irb6).tcp(q_goal)
    sol = solve_pose(irb6, target, irb6.home_q())
    assert sol.converged
    assert np.all(slack(irb6, sol.q) >= -1e-9)
    assert sol.position_error < 1e-7


def test_seed_violating_a_coupled_limit_is_reported(irb6):
    seed = np.radians([90.0, 20.0, 10.0, -30.0, 0.0])  # θ2+θ3 = 30° > 25°
    sol = solve_pose(irb6, Kinematics(irb6).tcp(irb6.home_q()), seed)
    assert not sol.converged
    assert "coupled limit theta2+theta3" in sol.message and "by 5.000 deg" in sol.message


def test_cycle_start_violating_a_coupled_limit_raises(irb6):
    kin = Kinematics(irb6)
    ik = InverseTransformation(irb6, kin, IKParams.for_robot(irb6))
    q = np.radians([90.0, 20.0, 10.0, -30.0, 0.0])
    with pytest.raises(CoupledLimitError, match=r"theta2\+theta3.*by 5\.000 deg") as info:
        ik.step(q, q, kin.tcp(q), 0.01)
    assert info.value.violation.side == "upper"


@pytest.mark.parametrize("task_rows", [(0, 1, 2), (0, 1, 2, 3, 4, 5)])
def test_cycle_path_never_crosses_the_coupled_bound(irb6, task_rows):
    """A straight TCP line whose joint-space continuation needs θ2+θ3 up to 40°: cycle by
    cycle the configuration stays inside both coupled rows (checked on the configurations
    themselves), touches the 25° bound, and the finite-difference speeds and accelerations
    of the joints stay within the robot's limits (the braking row keeps the accelerations
    admissible when the combination runs into its bound)."""
    kin = Kinematics(irb6)
    q0 = np.radians([90.0, 5.0, 5.0, -30.0, 0.0])
    q1 = np.radians([90.0, 20.0, 20.0, -40.0, 0.0])  # θ2+θ3 = 40°: beyond the limit
    poses = line_poses(kin.tcp(q0), kin.tcp(q1), 250)
    free, _ = _run(without_coupled(irb6), poses, q0, task_rows)
    assert np.degrees(free[:, 1] + free[:, 2]).max() > 35.0  # the path does want to cross
    qs, bindings = _run(irb6, poses, q0, task_rows)
    dt = 0.01
    s = np.array([slack(irb6, x) for x in qs])
    assert s.min() >= -1e-9  # never crosses (tolerance: rounding)
    assert not any(violations(coupled_limits(irb6), x, 1e-9) for x in qs)
    assert np.degrees(qs[:, 1] + qs[:, 2]).max() == pytest.approx(25.0, abs=1e-3)
    assert any(b.startswith("coupled limit theta2+theta3 max") for b in bindings)
    v = np.diff(qs, axis=0) / dt
    a = np.diff(v, axis=0) / dt
    assert np.all(np.abs(v) <= irb6.speed_limits[:, 1] * (1 + 1e-9) + 1e-9)
    assert np.all(np.abs(a) <= irb6.accel_limits[:, 1] * (1 + 1e-6) + 1e-6)


def _run(model, poses, q0, task_rows, dt=0.01):
    kin = Kinematics(model)
    ik = InverseTransformation(model, kin, IKParams.for_robot(model, task_rows=task_rows))
    q_prev, q = q0.copy(), q0.copy()
    qs, bindings = [q0.copy()], []
    for target in poses:
        r = ik.step(q, q_prev, target, dt)
        q_prev, q = q, r.q
        qs.append(q.copy())
        bindings.append(r.binding)
    return np.array(qs), bindings


def test_robot_without_coupled_limits_builds_no_rows():
    model = load_robot("koch11")
    ik = InverseTransformation(model, Kinematics(model))
    assert ik.coupled is None
    q = model.home_q()
    r = ik.step(q, q, Kinematics(model).tcp(q), 0.01, CycleOptions())
    assert r.converged
