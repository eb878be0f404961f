"""Motor coordinates are visible: fk/ik ``--motors``, Z-Y-Z Euler angles (``--euler zyz``),
trace columns ``NAME_motor_rad`` and the report's per-motor travel and travel time.

Expected values come from the book's L-1 formulas (Szkodny): ``θs_i = 360π λ_i`` (i = 1..3),
``θs4 = −3.6 θ4``, ``θs5 = 7.2 (θ5 − 0.5 θ4)``, ``θs6 = 7.2 (θ6 − 2 θ5)``, and
``R = Rz(Φ)·Ry(Θ)·Rz(Ψ)`` written out with cosines and sines.
"""

from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest
from irlc.cli import main
from irlc.robots import load_robot
from irlc.runtime import units
from irlc.runtime.model import spatial
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.run import run_file

Q = ["120", "250", "400", "200", "-35", "300"]  # mm, deg


def book_motors(q_prog) -> list[float]:
    l1, l2, l3, t4, t5, t6 = (float(v) for v in q_prog)
    k = 360.0 * math.pi
    t4, t5, t6 = (math.radians(v) for v in (t4, t5, t6))
    return [k * l1 / 1e3, k * l2 / 1e3, k * l3 / 1e3, -3.6 * t4, 7.2 * (t5 - 0.5 * t4),
            7.2 * (t6 - 2.0 * t5)]  # fmt: skip


def zyz(phi, theta, psi) -> np.ndarray:
    cf, sf, ct, st, cp, sp = (f(a) for a in (phi, theta, psi) for f in (math.cos, math.sin))
    return np.array(
        [
            [cf * ct * cp - sf * sp, -cf * ct * sp - sf * cp, cf * st],
            [sf * ct * cp + cf * sp, -sf * ct * sp + cf * cp, sf * st],
            [-st * cp, st * sp, ct],
        ]
    )


def run(capsys, *args: str) -> tuple[int, str]:
    code = main(list(args))
    return code, capsys.readouterr().out


def test_fk_motors_json_reproduces_the_book_formulas(capsys):
    code, out = run(capsys, "fk", "l1", *Q, "--motors", "--json")
    assert code == 0
    data = json.loads(out)
    assert data["units"]["motor_angle"] == "rad"
    assert np.allclose(data["motor_angles_rad"], book_motors(Q), atol=5e-7)


def test_fk_motors_text(capsys):
    code, out = run(capsys, "fk", "l1", *Q, "--motors")
    assert code == 0
    assert "motor a6 (W6) [rad]" in out
    assert f"{book_motors(Q)[5]:.6f}" in out


def test_fk_without_options_prints_what_it_printed(capsys):
    code, out = run(capsys, "fk", "l1", *Q, "--json")
    assert code == 0
    assert "motor_angles_rad" not in json.loads(out) and "pose_zyz" not in json.loads(out)


@pytest.mark.parametrize("angles", [(30.0, 50.0, -120.0), (-170.0, 10.0, 45.0), (0.0, 90.0, 0.0)])
def test_zyz_round_trip_and_explicit_matrix(angles):
    r = spatial.zyz_to_matrix(*np.radians(angles))
    assert np.allclose(r, zyz(*np.radians(angles)), atol=1e-14)
    back = spatial.matrix_to_zyz(r)
    assert np.allclose(np.degrees(back), angles, atol=1e-9)


@pytest.mark.parametrize("theta", [0.0, 180.0])
def test_zyz_singular_keeps_the_rotation(theta):
    r = zyz(math.radians(40.0), math.radians(theta), math.radians(25.0))
    back = spatial.matrix_to_zyz(r)
    assert back[2] == 0.0
    assert np.allclose(spatial.zyz_to_matrix(*back), r, atol=1e-12)


def test_fk_euler_zyz_is_the_tcp_rotation(capsys):
    code, out = run(capsys, "fk", "l1", *Q, "--euler", "zyz", "--json")
    assert code == 0
    data = json.loads(out)
    model = load_robot("l1")
    t = Kinematics(model).tcp(units.joints_to_si([float(v) for v in Q], model.joint_kinds))
    phi, theta, psi = np.radians(data["pose_zyz"][3:])
    assert 0.0 <= theta <= math.pi
    assert np.allclose(zyz(phi, theta, psi), t[:3, :3], atol=1e-8)
    assert data["pose_zyz"][:3] == data["pose"][:3]


def test_ik_takes_zyz_and_prints_motors(capsys):
    model = load_robot("l1")
    q = [float(v) for v in Q]
    t = Kinematics(model).tcp(units.joints_to_si(q, model.joint_kinds))
    phi, theta, psi = spatial.matrix_to_zyz(t[:3, :3])
    pose = [*(t[:3, 3] * 1e3), *np.degrees([phi, theta, psi])]
    seed = ["125", "245", "395", "195", "-30", "295"]
    args = ["ik", "l1", *(f"{v:.10f}" for v in pose), "--euler", "zyz", "--motors", "--json"]
    code, out = run(capsys, *args, "--seed", *seed)
    assert code == 0, out
    data = json.loads(out)
    assert data["converged"]
    assert np.allclose(data["joints"], q, atol=1e-5)
    assert np.allclose(data["motor_angles_rad"], book_motors(q), atol=1e-5)
    assert np.allclose(data["pose"], units.pose_from_si(t), atol=1e-6)  # ZYX beside it


def test_trace_and_report_motor_columns(tmp_path):
    q0, q1 = (200.0, 300.0, 300.0, 90.0, 30.0, 90.0), (210.0, 300.0, 300.0, 90.0, -15.0, 135.0)
    prog = tmp_path / "wrist.irl"
    prog.write_text(
        "PROGRAM wrist;\nROBOT r := l1;\nBEGIN\n"
        f"  MOVE PTP ({', '.join(map(repr, q0))});\n  MOVE PTP ({', '.join(map(repr, q1))});\n"
        "ENDPROGRAM\n"
    )
    run_ = run_file(prog)
    assert run_.ok, run_.error
    names = [f"a{i}_motor_rad" for i in range(1, 7)]
    cols = run_.trace_columns
    assert cols[-6:] == names  # after the clearances, nothing renamed
    table = np.asarray(run_.trace)
    assert np.allclose(table[0, -6:], book_motors(q0), atol=1e-6)
    assert np.allclose(table[-1, -6:], book_motors(q1), atol=1e-6)
    motors = run_.report["motors"]
    assert motors["units"] == {"angle": "rad", "speed": "rad/s", "time": "s"}
    travel = np.abs(np.subtract(book_motors(q1), book_motors(q0)))  # straight, monotone
    for axis, expected in zip(motors["axes"], travel, strict=True):
        assert axis["travel_rad"] == pytest.approx(expected, rel=1e-8, abs=1e-9)
        assert axis["speed_limit_rad_s"] == pytest.approx(2.5 * math.pi)
        assert axis["travel_time_s"] == pytest.approx(expected / (2.5 * math.pi), abs=1e-8)
        assert axis["max_abs_speed_rad_s"] <= 2.5 * math.pi * 0.5 * (1 + 1e-9)  # 50 % PTP
    trace = tmp_path / "t.csv"
    assert main(["run", str(prog), "--trace", str(trace)]) == 0
    with trace.open() as f:
        header = next(csv.reader(f))
    assert header[-6:] == names


def test_robots_without_motor_maps_have_no_motor_columns(tmp_path):
    prog = tmp_path / "p3.irl"
    prog.write_text(
        "PROGRAM p3;\nROBOT r := planar3;\nBEGIN\n  MOVE PTP (0, 90, -90);\nENDPROGRAM\n"
    )
    run_ = run_file(prog)
    assert run_.ok
    assert not any(c.endswith("_motor_rad") for c in run_.trace_columns)
    assert "motors" not in run_.report


def test_robot_command_names_the_motor_limits(capsys):
    code, out = run(capsys, "robot", "l1")
    assert code == 0
    assert "motor limits [rad/s] ([drives.stepper] step_rate): 7.85398" in " ".join(out.split())
    code, out = run(capsys, "robot", "planar3")
    assert "motor limits" not in out


def test_summary_prints_the_motor_travel_times(tmp_path, capsys):
    prog = tmp_path / "w.irl"
    prog.write_text(
        "PROGRAM w;\nROBOT r := l1;\nBEGIN\n  MOVE PTP (200, 300, 300, 90, 30, 90);\n"
        "  MOVE PTP (200, 300, 300, 90, -15, 135);\nENDPROGRAM\n"
    )
    assert main(["run", str(prog)]) == 0
    out = capsys.readouterr().out
    assert "motors (rad, rad/s, s)" in out
    row = next(line for line in out.splitlines() if "a6 (W6)" in line and "20.7345" in line)
    assert f"{7.2 * math.radians(135.0) / (2.5 * math.pi):.4f}" in row  # 2.1600 s


def test_motors_of_a_robot_without_motor_maps_is_a_usage_error(capsys):
    code = main(["fk", "planar3", "0", "90", "-90", "--motors"])
    err = capsys.readouterr().err
    assert code == 3
    assert "no motor maps" in err and "Traceback" not in err


def test_statements_give_each_moves_motor_travel_and_time(tmp_path):
    """Two PTPs after the start: each statement's travel is the book's |ΔΘs| of its own
    move and its travel time |ΔΘs| / 2.5π (eq. 4.22), independently of the other move."""
    q0, q1 = (200.0, 300.0, 300.0, 90.0, 30.0, 90.0), (200.0, 300.0, 300.0, 90.0, -15.0, 135.0)
    q2 = (230.0, 300.0, 300.0, 120.0, -15.0, 135.0)
    prog = tmp_path / "two.irl"
    body = "".join(f"  MOVE PTP ({', '.join(map(repr, q))});\n" for q in (q0, q1, q2))
    prog.write_text(f"PROGRAM two;\nROBOT r := l1;\nBEGIN\n{body}ENDPROGRAM\n")
    run_ = run_file(prog)
    assert run_.ok, run_.error
    rows = run_.report["statements"]
    for row, (a, b) in zip(rows[1:], ((q0, q1), (q1, q2)), strict=True):
        travel = np.abs(np.subtract(book_motors(b), book_motors(a)))
        assert np.allclose(row["motor_travel_rad"], travel, rtol=1e-8, atol=1e-9)
        assert np.allclose(row["motor_travel_time_s"], travel / (2.5 * math.pi), atol=1e-8)
        assert row["duration_s"] >= travel.max() / (2.5 * math.pi)
