"""Motor-side limits decide the timing where the transmission couples joints (the L-1).

Every expected number is computed here from the book's maps (Szkodny, L-1):
``θs_i = k_i λ_i`` (i = 1..3, k = 360π rad/m), ``θs4 = k4 θ4``, ``θs5 = k5 (θ5 − 0.5 θ4)``,
``θs6 = k6 (θ6 − 2 θ5)``, ``k4 = −3.6``, ``k5 = k6 = 7.2``; steppers at 2.5π rad/s. The
travel time of a motor is ``|ΔΘs| / 2.5π`` and a plan is never shorter than the slowest.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest
from irlc.robots import load_robot
from irlc.runtime.ik import CycleOptions, IKParams, InverseTransformation
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.model.motor_limits import motor_limits
from irlc.runtime.run import run_file

V_STEP = 2.5 * math.pi  # rad/s, the L-1's commanded step rate (motor side)
K = 360.0 * math.pi  # rad/m
IPO = 0.01


def book_motors(q_prog) -> np.ndarray:
    """Motor angles (rad) of program joint values (mm, deg), from the book's formulas."""
    l1, l2, l3, t4, t5, t6 = q_prog
    l1, l2, l3 = (v / 1000.0 for v in (l1, l2, l3))
    t4, t5, t6 = (math.radians(v) for v in (t4, t5, t6))
    return np.array(
        [K * l1, K * l2, K * l3, -3.6 * t4, 7.2 * (t5 - 0.5 * t4), 7.2 * (t6 - 2.0 * t5)]
    )


def _program(tmp_path: Path, q0, q1, pct: float = 100.0) -> Path:
    prog = tmp_path / "motors.irl"
    fmt = ", ".join
    prog.write_text(
        "PROGRAM motors;\nROBOT r := l1;\nBEGIN\n"
        f"  R_SPEED_PTP := {pct:g};\n  R_ACC_PTP := {pct:g};\n"
        f"  MOVE PTP ({fmt(map(repr, q0))});\n  MOVE PTP ({fmt(map(repr, q1))});\nENDPROGRAM\n"
    )
    return prog


def _expected_duration(q0, q1, pct: float = 100.0) -> float:
    """The trapezoid of docs/runtime.md with the motors as more axes, in whole cycles."""
    model = load_robot("l1")
    scale = np.array([1e-3] * 3 + [math.pi / 180.0] * 3)
    dq = np.abs(np.subtract(q1, q0)) * scale
    dm = np.abs(book_motors(q1) - book_motors(q0))
    f = pct / 100.0
    vj = model.speed_limits[:, 1] * f
    aj = model.accel_limits[:, 1] * f
    moving = dq > 0
    v = min(np.min(vj[moving] / dq[moving]), np.min(V_STEP * f / dm[dm > 0]))
    a = np.min(aj[moving] / dq[moving])  # the steppers give no acceleration bound
    t = 1.0 / v + v / a if a >= v * v else 2.0 / math.sqrt(a)
    return math.ceil(t / IPO - 1e-9) * IPO


HOME = (200.0, 300.0, 300.0, 90.0, 30.0, 90.0)
WRIST = (200.0, 300.0, 300.0, 90.0, -15.0, 135.0)  # W5 −45°, W6 +45°


def test_wrist_move_is_planned_for_its_motors(tmp_path):
    """W5 −45°, W6 +45°: motor 6 turns 7.2·(45° + 90°) = 16.96 rad, ≥ 2.16 s at 2.5π rad/s
    (the joint limits alone allowed 0.85 s)."""
    dm = np.abs(book_motors(WRIST) - book_motors(HOME))
    assert dm[5] == pytest.approx(7.2 * math.radians(135.0))
    assert dm[5] / V_STEP == pytest.approx(2.16, abs=5e-3)
    run = run_file(_program(tmp_path, HOME, WRIST))
    assert run.ok, run.error
    assert run.report["duration_s"] >= dm.max() / V_STEP
    assert run.report["duration_s"] == pytest.approx(_expected_duration(HOME, WRIST), abs=1e-9)


def test_wrist_move_is_followed_by_the_steppers(tmp_path):
    run = run_file(_program(tmp_path, HOME, WRIST), drives="decoupled")
    assert run.ok, run.error
    assert run.report["duration_s"] >= 2.16


@pytest.mark.parametrize(
    "q1",
    [
        (250.0, 330.0, 280.0, 150.0, 60.0, 300.0),  # all axes
        (200.0, 300.0, 300.0, 180.0, 30.0, 90.0),  # W4 alone drags motors 4 and 5
        (258.5, 300.0, 300.0, 90.0, 30.0, 90.0),  # a1 alone: no coupling, joint = motor
    ],
)
def test_no_plan_shorter_than_the_slowest_motor(tmp_path, q1):
    """The book's rule ``T ≥ max_m |ΔΘs_m| / v_max`` and the exact trapezoid time."""
    run = run_file(_program(tmp_path, HOME, q1))
    assert run.ok, run.error
    slowest = np.abs(book_motors(q1) - book_motors(HOME)).max() / V_STEP
    assert run.report["duration_s"] >= slowest
    assert run.report["duration_s"] == pytest.approx(_expected_duration(HOME, q1), abs=1e-9)


def test_speed_percentage_scales_the_motor_limits(tmp_path):
    run = run_file(_program(tmp_path, HOME, WRIST, pct=50.0))
    assert run.ok, run.error
    assert run.report["duration_s"] == pytest.approx(
        _expected_duration(HOME, WRIST, 50.0), abs=1e-9
    )


def test_motor_limits_only_where_the_transmission_couples():
    assert motor_limits(load_robot("l1")) is not None
    for name in ("koch11", "planar3", "as6", "panda"):
        assert motor_limits(load_robot(name)) is None


# ------------------------------------------------------------------------------- IK rows


def _cycle(model, q_start, prev, step, accel=None):
    """One IK cycle towards ``fk(q_start + step)``, moving at ``prev`` per cycle before
    (``accel``: the compiled cycle or not, ``None``: if available)."""
    params = dataclasses.replace(IKParams.for_robot(model), accel=accel)
    ik = InverseTransformation(model, Kinematics(model), params)
    target = Kinematics(model).tcp(q_start + step)
    return ik, ik.step(q_start, q_start - prev, target, IPO, CycleOptions())


@pytest.mark.parametrize("accel", [False, None])
def test_ik_cycle_respects_the_motor_speeds(accel):
    """Moving W5 −0.2°, W6 +0.2° per 10 ms (motor 6: 7.2·0.6° = 0.075 rad per cycle,
    inside 2.5π·0.01 = 0.0785 rad), the target asks for W5 −0.4°, W6 +0.6°; the joint box
    (500 deg/s²: ±0.05° change per cycle) lets W5 −0.25°, W6 +0.25° through, which turns
    motor 6 by 7.2·0.75° = 0.094 rad. With the motor rows every motor's cycle travel stays
    within ``v Δt``; without them (the old solver) motor 6 overruns."""
    model = load_robot("l1")
    q = np.array([0.2, 0.3, 0.3, math.radians(90), math.radians(30), math.radians(90)])
    prev = np.array([0.0, 0.0, 0.0, 0.0, math.radians(-0.2), math.radians(0.2)])
    step = np.array([0.0, 0.0, 0.0, 0.0, math.radians(-0.4), math.radians(0.6)])
    assert abs(7.2 * (prev[5] - 2 * prev[4])) < V_STEP * IPO
    ik, res = _cycle(model, q, prev, step, accel)
    assert accel is None or not ik.accelerated  # False: the numpy cycle
    travel = book_motors(np.concatenate((res.q[:3] * 1e3, np.degrees(res.q[3:])))) - book_motors(
        np.concatenate((q[:3] * 1e3, np.degrees(q[3:])))
    )
    assert np.all(np.abs(travel) <= V_STEP * IPO * (1 + 1e-9))
    assert abs(travel[5]) == pytest.approx(V_STEP * IPO, rel=1e-6)  # motor 6 at its bound
    rows = ik.coupled
    assert rows.describe_row(rows.npos + 5) == "motor speed of a6 min -7.85398 rad/s"
    assert rows.describe_row(rows.npos + 11) == "motor speed of a6 max 7.85398 rad/s"
    # the same cycle without the motor rows
    bare = dataclasses.replace(model, extra={k: v for k, v in model.extra.items() if k != "drives"})
    _, old = _cycle(bare, q, prev, step)
    old_travel = 7.2 * ((old.q[5] - q[5]) - 2 * (old.q[4] - q[4]))
    assert abs(old_travel) > V_STEP * IPO * 1.1


@pytest.mark.parametrize("accel", [False, None])
def test_ik_cycle_brakes_a_motor_that_runs_too_fast(accel):
    """Entering a cycle with motor 6 at 0.176 rad per cycle (more than v·Δt: e.g. after a
    blend), the QP is not empty: the motor row admits the fastest braking the joint box
    allows, |K₆d| − Σ|K₆j|a_jΔt² = 0.176 − 7.2·(1 + 2)·500°/s²·1e-4 s² ≈ 0.157 rad."""
    model = load_robot("l1")
    q = np.array([0.2, 0.3, 0.3, math.radians(90), math.radians(30), math.radians(90)])
    prev = np.array([0.0, 0.0, 0.0, 0.0, math.radians(-0.4), math.radians(0.6)])
    _, res = _cycle(model, q, prev, prev, accel)
    d6 = 7.2 * ((res.q[5] - q[5]) - 2 * (res.q[4] - q[4]))
    braked = 7.2 * math.radians(1.4) - 7.2 * 3 * math.radians(500.0) * IPO**2
    assert abs(d6) <= braked * (1 + 1e-9)
    assert abs(d6) < 7.2 * math.radians(1.4)


def test_lin_is_timed_for_its_motors(tmp_path):
    """A 50 mm LIN along y0 moves λ2 only (the L-1's Cartesian axes): motor 2 turns
    360π·0.05 = 56.55 rad, ≥ 7.2 s at 2.5π rad/s. The path speed R_SPEED = 100 mm/s would
    take 0.5 s (and failed on the joint speed bound); the plan is the trapezoid with
    ``v = 2.5π / 56.55`` and ``a = R_ACC / 50 mm`` per unit path."""
    prog = tmp_path / "lin.irl"
    prog.write_text(
        "PROGRAM linmove;\nROBOT r := l1;\nVAR POSE: p;\nBEGIN\n  R_ACC := 40;\n"
        "  MOVE PTP (200, 300, 300, 90, 30, 90);\n"
        "  p := POSE(350, 436.9349, 276.75, 180, 0, 60);\n  MOVE LIN p;\nENDPROGRAM\n"
    )
    tcp = Kinematics(load_robot("l1")).tcp(
        np.array([0.2, 0.3, 0.3, math.radians(90), math.radians(30), math.radians(90)])
    )
    assert np.allclose(tcp[:3, 3] * 1e3, [300.0, 436.9349, 276.75], atol=1e-4)
    run = run_file(prog)
    assert run.ok, run.error
    travel = K * 0.05
    v, a = V_STEP / travel, 40.0 / 50.0
    expected = math.ceil((1.0 / v + v / a) / IPO - 1e-9) * IPO
    assert run.report["duration_s"] == pytest.approx(expected, abs=1e-9)
    assert run.report["statements"][-1]["limit"] == "motor of a2 (L2) speed/acceleration"
    a2 = run.report["motors"]["axes"][1]
    assert a2["travel_rad"] == pytest.approx(travel, rel=1e-6)
    assert a2["max_abs_speed_rad_s"] <= V_STEP * (1 + 1e-6)


@pytest.mark.parametrize("accel", [False, None])
def test_ik_cycle_respects_a_non_linear_motor_map(accel):
    """IRb-6: motor 3 drives a screw on the lever of θ2+θ3 (a non-linear, coupled map),
    47.9369 rad/s (slave controller). Moving θ2 and θ3 together with motor 3 at 99 % of
    its limit, a target further along lets the joint box speed both joints up: without the
    rows motor 3 overruns ``v Δt``, with them (``K(q_start)``, rows updated per cycle) it
    stays there — checked with the map itself, not its linearisation."""
    from irlc.runtime.model.motor_maps import MotorMap

    model = load_robot("irb6")
    mm = MotorMap.from_model(model)
    v_dt = 47.9369 * IPO
    q = np.radians([100.0, 10.0, 5.0, -30.0, 20.0])
    k3 = mm.motor_jacobian(q)[2]
    prev = np.zeros(5)
    prev[1] = prev[2] = 0.99 * v_dt / (k3[1] + k3[2])
    a = np.minimum(-model.accel_limits[:, 0], model.accel_limits[:, 1])
    assert (k3[1] * a[1] + k3[2] * a[2]) * IPO**2 > 0.02 * v_dt  # the box could overrun it
    ik, res = _cycle(model, q, prev, 4 * prev, accel)
    assert ik.coupled.varying
    travel = mm.motor_from_joint(res.q) - mm.motor_from_joint(q)
    assert abs(travel[2]) <= v_dt * (1 + 1e-3)
    bare = dataclasses.replace(model, extra={k: v for k, v in model.extra.items() if k != "drives"})
    _, old = _cycle(bare, q, prev, 4 * prev, accel)
    old_travel = mm.motor_from_joint(old.q) - mm.motor_from_joint(q)
    assert abs(old_travel[2]) > v_dt * 1.005
