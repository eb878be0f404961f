"""Obstacle avoidance (seed eq. 47–49) increases the real clearance, at two IPO cycles."""

from __future__ import annotations

import numpy as np
import pytest
from irlc.robots import load_robot
from irlc.runtime.ik import (
    CycleOptions,
    IKParams,
    InverseTransformation,
    ObstacleParams,
    solve_pose,
)
from irlc.runtime.ik.obstacle import activation_weight
from irlc.runtime.model import spatial
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.model.obstacles import BoxObstacle

from .ik_robots import XY, line_poses, run_path


def min_clearance(model, q0, start, end, dt, avoid):
    kin = Kinematics(model)
    ik = InverseTransformation(model, kin, IKParams(task_rows=XY))
    box = BoxObstacle("box", np.array([0.6, -0.15, 0.0]), np.array([0.4, 0.3, 0.4]))
    opts = CycleOptions(obstacles=[box], active_obstacles=frozenset({"box"} if avoid else ()))
    steps = round(3.0 / dt)  # the same 3 s motion whatever the cycle
    _, results = run_path(ik, q0, line_poses(start, end, steps), dt, opts)
    assert all(r.converged for r in results)  # the path itself is kept exactly
    return min(r.clearances["box"][0] for r in results)


@pytest.mark.parametrize("dt", [0.01, 0.004])
def test_obstacle_criterion_increases_clearance_planar4(dt):
    """planar4 with the 40 × 30 cm box at (60, −15) cm: the TCP runs along y = 0.15 m above
    the box; without avoidance link 2 cuts into the box, with it the arm stays outside."""
    model = load_robot("planar4")
    kin = Kinematics(model)
    seed = np.array([-0.3, 0.9, 0.9, -1.2])
    q0 = solve_pose(model, spatial.transform(None, (0.45, 0.15, 0.0)), seed, task_rows=XY).q
    start = kin.tcp(q0)
    end = start.copy()
    end[:2, 3] = (1.0, 0.15)
    without = min_clearance(model, q0, start, end, dt, avoid=False)
    with_avoidance = min_clearance(model, q0, start, end, dt, avoid=True)
    assert without < -0.05  # penetration without the criterion
    assert with_avoidance > 0.0  # clear of the box with it
    assert with_avoidance > without + 0.05


def test_activation_weight_is_smooth_and_zero_far_away():
    p = ObstacleParams(activation=0.5, ramp=0.5)
    assert activation_weight(0.6, p) == 0.0 and activation_weight(0.5, p) == 0.0
    assert activation_weight(0.25, p) == 1.0 and activation_weight(0.01, p) == 1.0
    r = np.linspace(0.2, 0.55, 200)
    w = np.array([activation_weight(x, p) for x in r])
    assert np.all(np.diff(w) <= 1e-15) and np.max(np.abs(np.diff(w))) < 0.05  # no jump


def test_far_obstacle_changes_nothing(koch11):
    kin = Kinematics(koch11)
    q0 = koch11.home_q()
    far = BoxObstacle("far", np.array([50.0, 50.0, 0.0]), np.ones(3))
    start = kin.tcp(q0)
    end = start.copy()
    end[:3, 3] += (-0.5, 0.0, 0.0)
    poses = line_poses(start, end, 60)
    a = InverseTransformation(koch11, kin, IKParams(obstacle=ObstacleParams(a_conf=1.0)))
    b = InverseTransformation(koch11, kin, IKParams(obstacle=ObstacleParams(a_conf=1.0)))
    qa, _ = run_path(a, q0, poses, 0.01)
    qb, rb = run_path(
        b, q0, poses, 0.01, CycleOptions(obstacles=[far], active_obstacles=frozenset({"far"}))
    )
    np.testing.assert_allclose(qa, qb, atol=1e-12)
    assert rb[-1].clearances["far"][0] > 40.0
