"""The motion pipeline on small planar arms, checked against independent computations:
closed-form planar forward kinematics, the ideal straight-line / arc path with its own
trapezoid time law, and finite differences of the recorded joints."""

from __future__ import annotations

import math

import numpy as np
import pytest
from irlc.runtime.run import run_code

from .conftest import DEG, Ird, planar_robot

TOL_PATH_MM = 0.01


def planar_fk(q: np.ndarray, link: float = 1.0) -> np.ndarray:
    """TCP (x, y) of a planar arm with equal links: Σ link·(cos, sin)(θ1 + … + θi)."""
    phi = np.cumsum(q, axis=-1)
    return link * np.stack([np.cos(phi).sum(-1), np.sin(phi).sum(-1)], axis=-1)


def ideal_s(t: np.ndarray, length: float, v: float, a: float, dt: float) -> np.ndarray:
    """Unit trapezoid for a move of ``length`` under (v, a), stretched to whole cycles
    keeping ``a`` (written out here, independently of runtime.profiles)."""
    vn, an = v / length, a / length
    T = 1 / vn + vn / an if vn * vn <= an else 2 / math.sqrt(an)
    T = math.ceil(T / dt - 1e-9) * dt
    vc = 0.5 * (an * T - math.sqrt(an * an * T * T - 4 * an))
    ta = vc / an
    return np.where(
        t <= ta,
        0.5 * an * t * t,
        np.where(t >= T - ta, 1 - 0.5 * an * (T - t) ** 2, 0.5 * an * ta * ta + vc * (t - ta)),
    )


def test_lin_follows_the_ideal_path_and_time_law(planar3):
    p = Ird("planar3t", "RRR")
    pts = [(2000.0, 1000.0), (1600.0, 400.0), (2200.0, 900.0)]
    p.sys(3, "R_SPEED", 400.0)
    p.sys(4, "R_ACC", 800.0)
    for i, (x, y) in enumerate(pts[1:]):
        p.move(10 + i, "LIN", p.pose(x, y, 0))
    run = run_code(p.code_object(), robot=planar3)
    assert run.status == "ok", run.error
    dt = 0.01
    xy = planar_fk(run.q) * 1e3  # mm
    assert np.allclose(xy[0], pts[0], atol=1e-6)
    t0 = 0.0
    for i in range(2):
        rows = run.lines == 10 + i
        t = run.times[rows] - t0
        a, b = np.array(pts[i]), np.array(pts[i + 1])
        length = float(np.linalg.norm(b - a))
        ideal = a + ideal_s(t, length, 400.0, 800.0, dt)[:, None] * (b - a)
        err = np.linalg.norm(xy[rows] - ideal, axis=1)
        assert err.max() <= TOL_PATH_MM
        assert np.allclose(xy[rows][-1], b, atol=TOL_PATH_MM)
        t0 = run.times[rows][-1]
    # the recorded path error agrees with the independent one
    assert run.report["max_path_error_mm"] <= TOL_PATH_MM
    # TCP speed never above R_SPEED (finite differences of the FK of the joints)
    speed = np.linalg.norm(np.diff(xy, axis=0), axis=1) / dt
    assert speed.max() <= 400.0 * (1 + 1e-6)


def test_circle_passes_via_and_stays_on_the_circle(planar3):
    p = Ird("planar3t", "RRR")
    # start at (2000, 1000) (home); circle through (1500, 1500) to (1000, 1000): centre
    # (1500, 1000), radius 500
    p.move(10, "CIRCLE", p.pose(1500, 1500, 0), p.pose(1000, 1000, 0))
    run = run_code(p.code_object(), robot=planar3)
    assert run.status == "ok", run.error
    xy = planar_fk(run.q) * 1e3
    r = np.linalg.norm(xy - (1500.0, 1000.0), axis=1)
    assert np.abs(r - 500.0).max() <= TOL_PATH_MM
    assert np.allclose(xy[-1], (1000.0, 1000.0), atol=TOL_PATH_MM)
    assert np.min(np.linalg.norm(xy - (1500.0, 1500.0), axis=1)) < 5.0  # passes the via


def test_ptp_is_synchronised_and_within_percent_limits(planar3):
    p = Ird("planar3t", "RRR")
    p.sys(3, "R_SPEED_PTP", 50.0)
    p.sys(4, "R_ACC_PTP", 40.0)
    p.move(10, "PTP", p.joints(30.0, 45.0, -10.0))
    run = run_code(p.code_object(), robot=planar3)
    assert run.status == "ok", run.error
    q = run.q / DEG
    start, end = np.array([0.0, 90.0, -90.0]), np.array([30.0, 45.0, -10.0])
    assert np.allclose(q[-1], end, atol=1e-9)
    # synchronised: every joint is the same fraction of the way at every sample
    frac = (q - start) / (end - start)
    assert np.allclose(frac, frac[:, :1], atol=1e-9)
    v = np.abs(np.diff(q, axis=0)) / 0.01
    acc = np.abs(np.diff(q, n=2, axis=0)) / 0.01**2
    assert v.max() <= 0.5 * 90.0 * (1 + 1e-9)
    assert acc.max() <= 0.4 * 500.0 * (1 + 1e-6)
    # the slowest joint (80 deg to go) reaches about its bound: time-optimal
    assert v[:, 2].max() >= 0.5 * 90.0 * 0.95


def test_with_time_stretches_and_rejects_infeasible(planar3):
    p = Ird("planar3t", "RRR")
    p.move(10, "LIN", p.pose(1500, 1000, 0), clauses=[("TIME", p.const("REAL", 4.0))])
    run = run_code(p.code_object(), robot=planar3)
    assert run.status == "ok"
    assert run.report["duration_s"] == pytest.approx(4.0)
    p = Ird("planar3t", "RRR")
    p.move(12, "LIN", p.pose(1500, 1000, 0), clauses=[("TIME", p.const("REAL", 0.1))])
    run = run_code(p.code_object(), robot=planar3)
    assert run.status == "failed"
    assert run.error.line == 12
    assert "WITH TIME" in run.error.message


def _laps(cyclic: bool, laps: int = 3):
    p = Ird("planar3t", "RRR")
    p.sys(2, "R_SPEED", 800.0)
    p.sys(3, "R_ACC", 2000.0)
    corners = [p.pose(1000, 1000, 0), p.pose(1000, 0, 0), p.pose(2000, 0, 0), p.pose(2000, 1000, 0)]
    p.move(5, "LIN", corners[0])
    if cyclic:
        p.op(6, "OPTON", "CYCLIC")
    for lap in range(laps):
        for i, c in enumerate(corners[1:] + corners[:1]):
            p.move(10 + 10 * lap + i, "LIN", c)
    if cyclic:
        p.op(99, "OPTOFF", "CYCLIC")
    return p


def _lap_end_configurations(run, laps: int) -> np.ndarray:
    return np.array([run.q[run.lines == 13 + 10 * lap][-1] for lap in range(laps)])


def test_cyclic_returns_to_the_start_configuration_and_default_drifts(planar3):
    laps = 2
    free = run_code(_laps(False, laps).code_object(), robot=planar3)
    cyc = run_code(_laps(True, laps).code_object(), robot=planar3)
    assert free.status == cyc.status == "ok"
    start = cyc.q[cyc.lines == 5][-1]  # the configuration at CYCLICSTART
    assert np.allclose(start, free.q[free.lines == 5][-1])
    ends_cyc = _lap_end_configurations(cyc, laps)
    assert np.abs(ends_cyc - start).max() < 1e-6  # rad
    ends_free = _lap_end_configurations(free, laps)
    drift = np.abs(ends_free - start).max(axis=1)
    assert drift[0] > 1.0 * DEG
    assert np.all(np.diff(drift) > 0.0)  # keeps drifting lap after lap
    # both follow the same TCP path
    assert max(free.report["max_path_error_mm"], cyc.report["max_path_error_mm"]) <= TOL_PATH_MM


def test_freeze_holds_joints_and_the_rest_follow():
    robot = planar_robot(4, link=0.6, home_deg=(30.0, 30.0, 30.0, 30.0))
    p = Ird("planar4t", "RRRR")
    p.op(5, "OPTON", "FREEZE", 1)
    p.move(10, "LIN", p.pose(1000, 1200, 0))
    p.move(11, "LIN", p.pose(900, 800, 0))
    p.op(12, "OPTOFF", "FREEZE")
    run = run_code(p.code_object(), robot=robot)
    assert run.status == "ok", run.error
    assert np.ptp(run.q[:, 0]) == 0.0
    assert np.ptp(run.q[:, 1:], axis=0).min() > 1.0 * DEG
    assert run.report["max_path_error_mm"] <= TOL_PATH_MM


def test_freezing_too_many_joints_fails_with_the_line():
    robot = planar_robot(3, home_deg=(0.0, 90.0, -90.0))
    p = Ird("planar3t", "RRR")
    p.op(5, "OPTON", "FREEZE", 1, 2)
    p.move(10, "LIN", p.pose(1200, 900, 0))
    run = run_code(p.code_object(), robot=robot)
    assert run.status == "failed"
    assert run.error.line == 5  # the FREEZESTART itself, not the next motion
    assert "FREEZE" in run.error.message
    assert run.times[-1] == 0.0  # nothing moved


def test_reconfiguration_keeps_the_tcp_and_reaches_the_target(planar3):
    # home (0, 90, -90) reaches (2, 1) m; k is another configuration reaching (2, 1):
    # choose θ1 + θ2 + θ3 = a and solve the two-link problem for the wrist point
    target = np.array([2.0, 1.0])
    a = 0.5  # choose θ1 + θ2 + θ3 = φ3 and solve the 2-link problem for the wrist point
    wrist = target - np.array([math.cos(a), math.sin(a)])
    d = np.linalg.norm(wrist)
    q2 = math.acos((d * d - 2.0) / 2.0)
    q1 = math.atan2(wrist[1], wrist[0]) - math.atan2(math.sin(q2), 1 + math.cos(q2))
    k = np.array([q1, q2, a - q1 - q2])
    assert np.allclose(planar_fk(k), target)
    p = Ird("planar3t", "RRR")
    p.push(10, p.joints(*np.degrees(k))).op(10, "RECONF")
    run = run_code(p.code_object(), robot=planar3)
    assert run.status == "ok", run.error
    xy = planar_fk(run.q)
    assert np.abs(xy - target).max() * 1e3 <= TOL_PATH_MM
    dist = np.linalg.norm(run.q - k, axis=1)
    assert dist[-1] < 1e-3 * dist[0]
    assert dist[-1] < 1e-3


def test_unreachable_target_fails_with_line_and_partial_trace(planar3):
    p = Ird("planar3t", "RRR")
    p.move(10, "LIN", p.pose(1500, 1000, 0))
    p.move(11, "LIN", p.pose(4000, 1000, 0))  # beyond the 3 m reach
    run = run_code(p.code_object(), robot=planar3)
    assert run.status == "failed"
    assert run.report["status"] == "failed"
    assert run.error.line == 11
    assert run.report["error"]["line"] == 11
    # checked before it moves: at the end of line 10, nothing of line 11 recorded
    assert run.error.time_s == pytest.approx(run.times[run.lines == 10][-1])
    assert run.error.cause == "unreachable" and "not reachable" in run.error.message
    assert run.report["error"]["cause"] == "unreachable"
    # the closest point of the 3 m disc is 4123 − 3000 = 1123 mm away
    assert run.report["error"]["distance_mm"] >= 1123.1 - 1e-6
    assert set(run.lines) == {0, 10}  # recorded up to the failure
    assert np.all(np.isfinite(run.trace))


def test_singular_configuration_fails_cleanly():
    # a 2R arm starting fully stretched (a singular configuration) cannot start moving
    # radially inwards: the first millimetres need an unbounded elbow speed
    robot = planar_robot(2)
    p = Ird("planar2t", "RR")
    p.move(10, "LIN", p.pose(1500, 0, 0))
    run = run_code(p.code_object(), robot=robot, seed_config=(0.0, 0.0))
    assert run.status == "failed"
    assert run.error.line == 10
    assert run.error.time_s <= 0.1
    assert "deviation" in run.error.message
    assert np.all(np.isfinite(run.trace))


def test_limits_excluding_the_current_state_fail_naming_the_joint(planar3):
    p = Ird("planar3t", "RRR")
    lo, hi = (
        p.joints(-10, -10, -10, type_="MAIN_JOINT_MIN"),
        p.joints(10, 80, 10, type_="MAIN_JOINT_MAX"),
    )
    p.move(10, "LIN", p.pose(1500, 1000, 0), clauses=[("JOINTLIMIT", lo, hi)])
    run = run_code(p.code_object(), robot=planar3)
    assert run.status == "failed"
    assert run.error.line == 10
    assert "a2" in run.error.message and "90" in run.error.message
