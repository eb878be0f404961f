"""OBSTACLE and FREEZESTART fail at their own statement when they cannot hold from the start
(regression: the failure used to point at the next motion, or never came when none followed).

Independent facts: the planar 3R arm at (0°, 90°, −90°) has link 1 on the x axis from (0, 0)
to (1, 0) m, so a sphere of radius 0.1 m at (0.5, 0, 0) contains it (clearance −0.15 m with
the 0.05 m link capsules), and a 2-row task (x, y) cannot be followed with 1 free joint.
"""

from __future__ import annotations

import pytest
from irlc.runtime.run import run_code

from .conftest import Ird


def _program(obstacle_x_mm: float, wait_first: bool) -> Ird:
    p = Ird("planar3t", "RRR")
    p.obstacle("ball", "sphere", center=(obstacle_x_mm, 0.0, 0.0), radius=100.0)
    p.op(4, "OPTON", "OBSTACLE", "ball")
    if wait_first:
        p.push(5, p.const("REAL", 0.5)).op(5, "WAIT")
    p.move(6, "LIN", p.pose(1800, 900, 0))
    p.op(7, "OPTOFF", "OBSTACLE", "ball")
    return p


def test_obstacle_the_arm_is_inside_fails_at_the_obstacle_statement(planar3):
    """With collisions allowed (else the start inside the ball fails first, below), an
    OBSTACLE switched on inside its obstacle still fails at its own statement."""
    for wait_first in (False, True):
        code = _program(500.0, wait_first).code_object()
        run = run_code(code, robot=planar3, allow_collisions=True)
        assert run.status == "failed"
        assert run.error.line == 4, run.error
        assert "already inside" in run.error.message and "ball" in run.error.message
        assert run.times[-1] == 0.0  # nothing ran after the OBSTACLE statement
        # by default the start configuration inside the ball is a collision (issue 24),
        # at the first statement, t = 0: 150 mm deep (ball 100 mm + link capsule 50 mm)
        run = run_code(code, robot=planar3)
        assert run.error.line == 4 and run.error.time_s == 0.0
        assert "starts inside obstacle ball" in run.error.message
        assert run.error.details == {"obstacle": "ball", "link": 1, "depth_mm": pytest.approx(150)}


def test_obstacle_clear_of_the_arm_switches_on_normally(planar3):
    run = run_code(_program(-1500.0, True).code_object(), robot=planar3)
    assert run.status == "ok", run.error
    assert run.report["obstacles"]["ball"]["min_distance_mm"] > 0.0


def test_too_many_frozen_joints_fail_at_freezestart_even_without_motion(planar3):
    p = Ird("planar3t", "RRR")
    p.op(5, "OPTON", "FREEZE", 1, 2)
    p.push(6, p.const("REAL", 0.2)).op(6, "WAIT")
    p.op(7, "OPTOFF", "FREEZE")
    run = run_code(p.code_object(), robot=planar3)
    assert run.status == "failed"
    assert run.error.line == 5
    assert "2 free joints" not in run.error.message and "1 free joints" in run.error.message
