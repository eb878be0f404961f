"""The IRb-6's joint limits (5.1b) over a grid of all five joints, including θ5.

The book's inequalities, written out literally in irlc.fidelity.kinematics_rows.irb6_margin
(degrees, the redefined angles; the same function gives docs/fidelity.md's (5.1b) row):

    0 ≤ θ1 ≤ 340;  −40 ≤ θ2 ≤ 40;
    −40−θ2 ≤ θ3 ≤ 40        (−40 ≤ θ2 ≤ −15)
    −40−θ2 ≤ θ3 ≤ 25−θ2     (−15 ≤ θ2 ≤ 0)
    −40 ≤ θ3 ≤ 25−θ2        (0 ≤ θ2 ≤ 40)
    −90 ≤ θ2+θ3+θ4 ≤ 90;
    −270 + θ234/k5 ≤ θ5 ≤ 90 + θ234/k5        (θ234 = θ2+θ3+θ4; k5 = 1, assumed)

and compared with irlc's limit check (the seed check of the pose search: the joint box
and the coupled rows of the robot file). No box on θ4 or θ5 beyond these. The variant
robot ``irb6_symmetric5`` keeps irlc's earlier reading of the θ5 row, −180 … 180 around
θ234/k5, and is checked against that reading the same way.
"""

from __future__ import annotations

import numpy as np
import pytest
from irlc.fidelity.kinematics_rows import BOOK_WINDOW, irb6_margin, limits_grid
from irlc.robots import load_robot
from irlc.runtime.ik.seed import seed_problem

K5 = 1.0  # the robot file's assumed k5 (its "theta5-theta234/k5" row, documented there)
SYMMETRIC_WINDOW = (-180.0, 180.0)  # irlc's earlier reading (robot irb6_symmetric5)
book_margin = irb6_margin  # (5.1b) written out literally (irlc.fidelity.kinematics_rows)


@pytest.fixture(scope="module")
def irb6():
    return load_robot("irb6")


@pytest.fixture(scope="module")
def irb6_symmetric5():
    return load_robot("irb6_symmetric5")


def test_robot_file_states_the_assumed_k5(irb6):
    rows = {c["name"]: c for c in irb6.extra["coupled_limits"]}
    row = rows["theta5-theta234/k5"]
    assert "assumed" in row and "k5" in row["assumed"]
    assert np.allclose(row["coeffs"], [0, -1 / K5, -1 / K5, -1 / K5, 1])


def test_limit_check_agrees_with_5_1b_on_a_grid():
    grid = limits_grid("irb6", BOOK_WINDOW)
    assert grid.disagree == 0, grid.first
    assert grid.checked > 60_000 and grid.on_bound > 1000


def test_symmetric_variant_agrees_with_its_reading_and_differs_from_the_book(irb6_symmetric5):
    grid = limits_grid("irb6_symmetric5", SYMMETRIC_WINDOW)
    assert grid.disagree == 0, grid.first
    # and it is another robot: θ5 − θ234 = 135° is inside its window, outside the book's
    q = [90.0, 0.0, 0.0, 0.0, 135.0]
    assert book_margin(*q) < 0 < book_margin(*q, window=SYMMETRIC_WINDOW)
    assert seed_problem(irb6_symmetric5, np.radians(q)) is None
    assert seed_problem(load_robot("irb6"), np.radians(q)) is not None
    assert grid.checked > 60_000


def test_what_the_old_boxes_rejected_is_allowed(irb6):
    """θ4 > 65° with −90 ≤ θ234 ≤ 90, and |θ5| > 180° inside the moving window."""
    for deg in ([90, -30, 0, 100, 0], [90, 0, 0, 80, 160], [90, 0, 0, -80, -340]):
        assert book_margin(*deg) > 0
        assert seed_problem(irb6, np.radians(deg)) is None, deg
    # and the window moves: θ5 = 160° needs θ234 ≥ 70°
    assert seed_problem(irb6, np.radians([90, 0, 0, 60, 160])) is not None


def test_theta5_window_is_motor_5_within_plus_minus_180_deg_times_k4_k5(irb6):
    """The row and the motor map (5.22) carry the same k5: θs5 = −k4·k5·(θ5 − θ234/k5),
    so the window row is the motor-5 row of the map divided by −k4·k5 (k4 = 80)."""
    from irlc.runtime.model.motor_maps import MotorMap

    rows = {c["name"]: c for c in irb6.extra["coupled_limits"]}
    motor5 = MotorMap.from_model(irb6).motor_jacobian(irb6.home_q())[4]
    assert np.allclose(rows["theta5-theta234/k5"]["coeffs"], motor5 / (-80.0 * K5))
