"""The book's kinematic equations against irlc: each function evaluates the book's formula
as printed (transcribed in the robot files' comments and the spec) at configurations drawn
inside the robot's limits and returns irlc's largest deviation from it.

IRb-6 (Szkodny ch. 5, redefined angles, deg): the limits (5.1b), the wrist point (5.3),
the key equation of the 5-axis arm (5.5), the closed-form inverse (5.6), motor 5 (5.22).
L-1 (ch. 4): the end pose of Table 4.1's chain, the motor angles (4.21). koch11 (seed
ch. 6): the zero-configuration TCP of the arm table.
"""

from __future__ import annotations

import functools
import itertools
import math
from dataclasses import dataclass

import numpy as np
from irlc.robots import load_robot
from irlc.runtime.ik import closed_form
from irlc.runtime.ik.pose import seed_problem
from irlc.runtime.model import spatial
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.model.reachability import check_vertical_plane
from irlc.runtime.model.sensitivity import sample_configurations
from irlc.runtime.outputs.motor_coords import motor_angles

SAMPLES = 200
K5 = 1.0  # the robot files' assumed k5 (not published)
K4 = 80.0  # the robot file's assumed k4 (not published)
BOOK_WINDOW = (-270.0, 90.0)  # θ5 − θ234/k5 in (5.1b)


def irb6_margin(t1, t2, t3, t4, t5, window=BOOK_WINDOW) -> float:
    """The smallest slack of (5.1b) at a point (deg; < 0 outside, 0 on a bound)::

    0 ≤ θ1 ≤ 340;  −40 ≤ θ2 ≤ 40;
    −40−θ2 ≤ θ3 ≤ 40 (−40 ≤ θ2 ≤ −15);  −40−θ2 ≤ θ3 ≤ 25−θ2 (−15 ≤ θ2 ≤ 0);
    −40 ≤ θ3 ≤ 25−θ2 (0 ≤ θ2 ≤ 40);  −90 ≤ θ2+θ3+θ4 ≤ 90;
    −270 + θ234/k5 ≤ θ5 ≤ 90 + θ234/k5
    """
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


GRID_T1 = (-0.5, 0.0, 170.0, 340.0, 340.5)
GRID_T2 = (-45.0, -40.0, -30.0, -15.0, -5.0, 0.0, 10.0, 25.0, 40.0, 45.0)
GRID_T3 = (-50.0, -40.0, -30.0, -10.0, 0.0, 10.0, 25.0, 40.0, 45.0, 60.0)
GRID_T4 = (*(float(v) for v in range(-150, 151, 15)), -115.0, 65.0, 66.0, 115.0, 130.0)
GRID_T5 = (*(float(v) for v in range(-380, 301, 20)), -271.0, -181.0, 91.0, 181.0, 269.0)


@dataclass(frozen=True)
class GridCheck:
    """irlc's limit check against (5.1b) on the grid: points ``checked`` (``on_bound``:
    within 1e-7° of a bound, either answer right, not counted), ``disagree``-ing, and the
    ``first`` disagreement ``(deg point, margin, irlc's message)``."""

    checked: int
    disagree: int
    on_bound: int
    first: tuple | None


def limits_grid(robot: str = "irb6", window=BOOK_WINDOW) -> GridCheck:
    """(5.1b) with the θ5 ``window`` against irlc's limit check (the pose search's seed
    check: the joint box and the robot file's coupled rows) over the grid (θ1 varied at
    θ2 = θ3 = 0)."""
    model = load_robot(robot)
    checked = disagree = on_bound = 0
    first = None
    for t2, t3, t4, t5 in itertools.product(GRID_T2, GRID_T3, GRID_T4, GRID_T5):
        for t1 in GRID_T1 if (t2, t3) == (0.0, 0.0) else (170.0,):
            margin = irb6_margin(t1, t2, t3, t4, t5, window)
            if abs(margin) < 1e-7:
                on_bound += 1
                continue
            checked += 1
            problem = seed_problem(model, np.radians([t1, t2, t3, t4, t5]))
            if (problem is None) != (margin > 0):
                disagree += 1
                first = first or ((t1, t2, t3, t4, t5), margin, problem)
    return GridCheck(checked, disagree, on_bound, first)


@functools.cache
def _irb6():
    model = load_robot("irb6")
    return model, Kinematics(model), sample_configurations(model, SAMPLES, seed=1)


def wrist_point_book(q_deg) -> np.ndarray:
    """(5.3) in the book's symbols and redefined angles (deg in, m out)::

    d_x = l2·S1·S2 − l3·S1·C23 − λ5·S1·C234
    d_y = −l2·C1·S2 + l3·C1·C23 + λ5·C1·C234
    d_z = λ1 + l2·C2 + l3·S23 + λ5·S234
    """
    t1, t2, t3, t4 = np.radians(q_deg[:4])
    l2, l3, lam1, lam5 = 0.45, 0.67, 0.70, 0.095
    s1, c1 = math.sin(t1), math.cos(t1)
    return np.array([
        l2 * s1 * math.sin(t2) - l3 * s1 * math.cos(t2 + t3) - lam5 * s1 * math.cos(t2 + t3 + t4),
        -l2 * c1 * math.sin(t2) + l3 * c1 * math.cos(t2 + t3) + lam5 * c1 * math.cos(t2 + t3 + t4),
        lam1 + l2 * math.cos(t2) + l3 * math.sin(t2 + t3) + lam5 * math.sin(t2 + t3 + t4),
    ])  # fmt: skip


def wrist_point_deviation() -> float:
    """(5.3): largest |irlc's flange origin − the book's closed form| over the samples, mm."""
    _, kin, qs = _irb6()
    worst = 0.0
    for q in qs:
        ours = kin.flange_from_frames(kin.link_frames(q))[:3, 3]
        worst = max(worst, float(np.abs(ours - wrist_point_book(np.degrees(q))).max()))
    return worst * 1e3


def key_equation() -> tuple[float, float, bool]:
    """(5.5): (largest |c_x·d_y − c_y·d_x| over reachable poses in m, the same for irlc's
    plane check, whether a pose turned 1° out of the plane is called unreachable)."""
    model, kin, qs = _irb6()
    worst_book = worst_ours = 0.0
    for q in qs:
        flange = kin.flange_from_frames(kin.link_frames(q))
        c, d = flange[:3, 2], flange[:3, 3]
        worst_book = max(worst_book, abs(c[0] * d[1] - c[1] * d[0]))
        worst_ours = max(worst_ours, abs(check_vertical_plane(model, kin.tcp(q)).residual))
    off = kin.tcp(qs[1]) @ spatial.transform(spatial.rot_x(math.radians(1.0)))
    return worst_book, worst_ours, not check_vertical_plane(model, off).reachable


def closed_form_round_trip() -> tuple[float, int]:
    """(5.6): (largest joint error in deg of the branch that reproduces the sampled
    configuration, number of samples without such a branch)."""
    model, kin, qs = _irb6()
    worst, missing = 0.0, 0
    for q in qs:
        found = closed_form.branches(model, kin.tcp(q)) or []
        errors = [float(np.abs(np.degrees(b.q - q)).max()) for b in found]
        if not errors or min(errors) > 1e-3:
            missing += 1
            continue
        worst = max(worst, min(errors))
    return worst, missing


def motor5_deviation() -> float:
    """(5.22): largest |irlc's θs5 − (k4·θ234 − k4·k5·θ5)| over the samples, rad."""
    model, _, qs = _irb6()
    theta = motor_angles(model, qs)
    book = K4 * (qs[:, 1] + qs[:, 2] + qs[:, 3]) - K4 * K5 * qs[:, 4]
    return float(np.abs(theta[:, 4] - book).max())


L1_K = 360.0 * math.pi  # rad/m, k1 = k2 = k3


def l1_motor_deviation() -> float:
    """(4.21): largest |irlc's θs − the book's maps| over sampled L-1 configurations, rad::

    θs_i = k_i λ_i (i = 1..3), θs4 = k4 θ4, θs5 = k5 (θ5 − 0.5 θ4), θs6 = k6 (θ6 − 2 θ5)
    """
    model = load_robot("l1")
    qs = sample_configurations(model, SAMPLES, seed=2)
    lam, t4, t5, t6 = qs[:, :3], qs[:, 3], qs[:, 4], qs[:, 5]
    book = np.column_stack([L1_K * lam, -3.6 * t4, 7.2 * (t5 - 0.5 * t4), 7.2 * (t6 - 2.0 * t5)])
    return float(np.abs(motor_angles(model, qs) - book).max())


def l1_end_pose_deviation() -> float:
    """Table 4.1's closed form X = Trans(λ2, λ3+λ4−l1, λ1)·Rot(x,−90°)·Rot(z,θ4)·Rot(y,−θ5)·
    Rot(z,θ6)·Trans(0,0,λ6+λ7) (λ4 = 0.055, l1 = 0.051, λ6+λ7 = 0.1535 m) against irlc's
    TCP: largest element difference (mm for the position, rotation entries × 1000)."""
    model = load_robot("l1")
    kin = Kinematics(model)
    worst = 0.0
    for q in sample_configurations(model, SAMPLES, seed=3):
        l1, l2, l3, t4, t5, t6 = q  # the user angles (Table 4.1's offset +90° is in the DH row)
        x = (
            spatial.transform(None, (l2, l3 + 0.055 - 0.051, l1))
            @ spatial.transform(spatial.rot_x(-math.pi / 2))
            @ spatial.transform(spatial.rot_z(t4))
            @ spatial.transform(spatial.rot_y(-t5))
            @ spatial.transform(spatial.rot_z(t6))
            @ spatial.transform(None, (0.0, 0.0, 0.1535))
        )
        worst = max(worst, float(np.abs(kin.tcp(q) - x).max()))
    return worst * 1e3


def koch11_zero_tcp() -> np.ndarray:
    """The TCP at the zero configuration, mm (the book: (1.2, 1.0, −0.1) m)."""
    model = load_robot("koch11")
    return Kinematics(model).tcp(np.zeros(model.n))[:3, 3] * 1e3
