"""The IRb-6's joint limits (5.1b) over a grid of all five joints, including θ5.

The book's inequalities are written out here literally (degrees, the redefined angles):

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

import itertools

import numpy as np
import pytest
from irlc.robots import load_robot
from irlc.runtime.ik.pose import seed_problem

K5 = 1.0  # the robot file's assumed k5 (its "theta5-theta234/k5" row, documented there)
EPS = 1e-7  # deg: grid points this close to a bound count as on it (either answer)


BOOK_WINDOW = (-270.0, 90.0)  # θ5 − θ234/k5, as (5.1b) prints it
SYMMETRIC_WINDOW = (-180.0, 180.0)  # irlc's earlier reading (robot irb6_symmetric5)


def book_margin(t1: float, t2: float, t3: float, t4: float, t5: float, window=BOOK_WINDOW) -> float:
    """The smallest slack of (5.1b) at the point (deg; < 0 outside, 0 on a bound)."""
    slack = [t1 - 0.0, 340.0 - t1, t2 + 40.0, 40.0 - t2]
    if -40.0 <= t2 <= -15.0:
        slack += [t3 - (-40.0 - t2), 40.0 - t3]
    elif -15.0 < t2 <= 0.0:
        slack += [t3 - (-40.0 - t2), 25.0 - t2 - t3]
    elif 0.0 < t2 <= 40.0:
        slack += [t3 + 40.0, 25.0 - t2 - t3]
    t234 = t2 + t3 + t4
    slack += [t234 + 90.0, 90.0 - t234]
    slack += [t5 - (window[0] + t234 / K5), window[1] + t234 / K5 - t5]
    return min(slack)


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


def agreement_on_grid(model, window) -> tuple[int, int, int, object]:
    """(checked, disagreeing, on a bound, first disagreement) of irlc's limit check and
    (5.1b) with the θ5 ``window`` over a grid of all five joints."""
    t1s = [-0.5, 0.0, 170.0, 340.0, 340.5]
    t2s = [-45.0, -40.0, -30.0, -15.0, -5.0, 0.0, 10.0, 25.0, 40.0, 45.0]
    t3s = [-50.0, -40.0, -30.0, -10.0, 0.0, 10.0, 25.0, 40.0, 45.0, 60.0]
    t4s = [float(v) for v in range(-150, 151, 15)] + [-115.0, 65.0, 66.0, 115.0, 130.0]
    t5s = [float(v) for v in range(-380, 301, 20)] + [-271.0, -181.0, 91.0, 181.0, 210.0, 269.0]
    checked = disagree = on_bound = 0
    first = None
    for t2, t3, t4, t5 in itertools.product(t2s, t3s, t4s, t5s):
        for t1 in t1s if (t2, t3) == (0.0, 0.0) else [170.0]:
            margin = book_margin(t1, t2, t3, t4, t5, window)
            if abs(margin) < EPS:
                on_bound += 1
                continue
            q = np.radians([t1, t2, t3, t4, t5])
            ours = seed_problem(model, q) is None
            checked += 1
            if ours != (margin > 0):
                disagree += 1
                first = first or ((t1, t2, t3, t4, t5), margin, seed_problem(model, q))
    return checked, disagree, on_bound, first


def test_limit_check_agrees_with_5_1b_on_a_grid(irb6):
    checked, disagree, on_bound, first = agreement_on_grid(irb6, BOOK_WINDOW)
    assert disagree == 0, first
    assert checked > 60_000 and on_bound > 1000


def test_symmetric_variant_agrees_with_its_reading_and_differs_from_the_book(irb6_symmetric5):
    checked, disagree, _, first = agreement_on_grid(irb6_symmetric5, SYMMETRIC_WINDOW)
    assert disagree == 0, first
    # and it is another robot: θ5 − θ234 = 135° is inside its window, outside the book's
    q = [90.0, 0.0, 0.0, 0.0, 135.0]
    assert book_margin(*q) < 0 < book_margin(*q, window=SYMMETRIC_WINDOW)
    assert seed_problem(irb6_symmetric5, np.radians(q)) is None
    assert seed_problem(load_robot("irb6"), np.radians(q)) is not None
    assert checked > 60_000


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
    from irlc.runtime.motor_maps import MotorMap

    rows = {c["name"]: c for c in irb6.extra["coupled_limits"]}
    motor5 = MotorMap.from_model(irb6).motor_jacobian(irb6.home_q())[4]
    assert np.allclose(rows["theta5-theta234/k5"]["coeffs"], motor5 / (-80.0 * K5))
