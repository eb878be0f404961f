"""``R_PROFILE := 'SCURVE'`` end to end: durations against the closed form, the jerk from the
trace (finite differences of its accelerations), the jerk bounds' sources (robot file or
derived), the settings' checks, and the drives (lower peak currents and following errors
than the trapezoid on the same program)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from irlc.api import compile_program, load_robot
from irlc.lang.diagnostics import CompileError
from irlc.runtime.commands import MotionCommand, Settings
from irlc.runtime.plan.motion_values import motion_values
from irlc.runtime.plan.preinterp import PreInterpolator
from irlc.runtime.run import run_code

DT = 0.01  # the default IPO cycle (s)

PROGRAM = """PROGRAM scurve_run;
ROBOT r := {robot};
BEGIN
  R_PROFILE := '{profile}';
{body}
ENDPROGRAM
"""


def _run(tmp_path, body: str, profile: str, robot: str = "irb6", **options):
    source = PROGRAM.format(robot=robot, profile=profile, body=body)
    code = compile_program(tmp_path / "scurve_run.irl", source=source)
    run = run_code(code, **options)
    assert run.status == "ok", run.error
    return run


def _column(run, name: str) -> np.ndarray:
    return run.trace[:, run.trace_columns.index(name)]


def _trace_jerk(run, name: str) -> np.ndarray:
    """First differences of the trace's acceleration column over the IPO cycle."""
    t, acc = _column(run, "t_s"), _column(run, name)
    return np.diff(acc) / np.diff(t)


# irb6 A1: 44 deg/s, 120 deg/s²; 100 % of both; no jerk in the file, so the derived
# jerk is 120 · R_JERK / R_ACC = 120 · 2000 / 1000 = 240 deg/s³.
SINGLE_JOINT = """  R_SPEED_PTP := 100;  R_ACC_PTP := 100;  R_JERK := 2000;  R_ACC := 1000;
  MOVE PTP (120, 0, 0, -45, 0);"""  # A1 from its home 90 to 120: 30 deg


def test_single_joint_ptp_duration_and_jerk_from_the_trace(tmp_path):
    run = _run(tmp_path, SINGLE_JOINT, "SCURVE")
    # closed form: v = 44 is not reached (accelerating to it takes 2·√(44/240) s and
    # 44·2·√(44/240) = 37.7 > 30 deg), a = 120 neither (240·t₁ ≤ 120 with 2·240·t₁³ = 30):
    # four jerk phases, t₁ = (30/480)^(1/3), T = 4·t₁, rounded up to whole IPO cycles
    t1 = (30.0 / (2 * 240.0)) ** (1 / 3)
    assert 240.0 * t1 <= 120.0 and 44.0 * 2 * math.sqrt(44.0 / 240.0) > 30.0
    assert run.report["duration_s"] == pytest.approx(math.ceil(4 * t1 / DT) * DT, abs=1e-9)
    jerk = _trace_jerk(run, "a1_accel_deg_s2")
    # the trace's accelerations are backward differences; their differences are third
    # differences of positions sampled from a piecewise cubic: a weighted mean of the jerk
    assert np.abs(jerk).max() <= 240.0 * (1 + 1e-6)
    assert np.abs(jerk).max() >= 0.95 * 240.0  # and the bound is used
    assert run.report["joints"][0]["max_abs_jerk"] == pytest.approx(np.abs(jerk).max(), rel=1e-6)
    assert _column(run, "a1_deg")[-1] == pytest.approx(120.0, abs=1e-9)

    trapezoid = _run(tmp_path, SINGLE_JOINT, "TRAPEZOID")  # the same move, unlimited jerk
    # v²/a = 16.1 < 30 deg: cruise; T = 30/44 + 44/120
    expected = math.ceil((30 / 44 + 44 / 120) / DT) * DT
    assert trapezoid.report["duration_s"] == pytest.approx(expected, abs=1e-9)
    assert np.abs(_trace_jerk(trapezoid, "a1_accel_deg_s2")).max() > 10 * 240.0
    assert trapezoid.report["joints"][0]["max_abs_jerk"] > 10 * 240.0


def test_stretched_multi_joint_ptp_keeps_the_jerk_and_synchronises(tmp_path):
    body = """  R_JERK := 3000;
  MOVE PTP (110, 10, -10, -30, 40) WITH TIME := 4;"""
    run = _run(tmp_path, body, "SCURVE")
    assert run.report["duration_s"] == pytest.approx(4.0, abs=1e-9)
    model = load_robot("irb6")
    accel = np.degrees(np.minimum(model.accel_limits[:, 1], -model.accel_limits[:, 0]))
    bound = 0.5 * accel * 3000.0 / 1000.0  # R_ACC_PTP 50 %, derived jerk (R_ACC 1000)
    start = np.array([90.0, 0.0, 0.0, -45.0, 0.0])
    end = np.array([110.0, 10.0, -10.0, -30.0, 40.0])
    q = np.column_stack([_column(run, f"a{i + 1}_deg") for i in range(5)])
    for i in range(5):
        jerk = _trace_jerk(run, f"a{i + 1}_accel_deg_s2")
        assert np.abs(jerk).max() <= bound[i] * (1 + 1e-6), i
    # synchronised: every joint is the same fraction of its way at every sample
    frac = (q - start) / (end - start)
    assert np.ptp(frac, axis=1).max() <= 1e-9
    assert np.allclose(q[-1], end, atol=1e-9)


def _tcp_jerk(run) -> np.ndarray:
    """|third differences| of the trace's TCP position over Δt³ (mm/s³)."""
    p = np.column_stack([_column(run, c) for c in ("x_mm", "y_mm", "z_mm")])
    return np.linalg.norm(np.diff(p, 3, axis=0), axis=1) / DT**3


def test_lin_path_jerk_from_the_trace(tmp_path):
    body = """  R_SPEED := 200;  R_ACC := 1000;  R_JERK := 5000;
  MOVE_INC LIN (0, 200, 0, 0, 0, 0);"""  # 200 mm along the tool's y axis
    run = _run(tmp_path, body, "SCURVE", robot="panda")
    p = np.column_stack([_column(run, c) for c in ("x_mm", "y_mm", "z_mm")])
    assert np.linalg.norm(p[-1] - p[0]) == pytest.approx(200.0, abs=1e-3)
    jerk = _tcp_jerk(run)
    # the IK follows the line to far below the 0.05 mm tolerance; its residual, differenced
    # three times, adds at most 8·(residual)/Δt³ — bounded here by 2 % of the jerk
    assert jerk.max() <= 5000.0 * 1.02
    assert jerk.max() >= 0.9 * 5000.0
    trapezoid = _run(tmp_path, body, "TRAPEZOID", robot="panda")
    assert _tcp_jerk(trapezoid).max() > 10 * 5000.0
    assert run.report["duration_s"] > trapezoid.report["duration_s"]


def test_ptp_jerk_bounds_come_from_the_robot_file_where_it_has_them():
    cmd = MotionCommand("PTP", (), 1)
    settings = Settings(jerk=4000.0, acc=500.0)
    panda = load_robot("panda")
    pre = PreInterpolator(panda)
    accel = np.minimum(panda.accel_limits[:, 1], -panda.accel_limits[:, 0])
    # Franka's published jerk limits (rad/s³), whatever R_JERK says
    expected = [7500, 3750, 5000, 6250, 7500, 10000, 10000]
    assert np.allclose(pre.ptp_jerks(motion_values(cmd, settings), accel), expected, rtol=1e-12)
    irb6 = load_robot("irb6")
    pre = PreInterpolator(irb6)
    accel = np.minimum(irb6.accel_limits[:, 1], -irb6.accel_limits[:, 0])
    assert np.isnan(irb6.jerk_limits).all()  # none published: derived, ramp time 500/4000 s
    assert np.allclose(pre.ptp_jerks(motion_values(cmd, settings), accel), accel * 8.0, rtol=1e-12)


def test_profile_setting_is_checked_and_reads_back_in_upper_case(tmp_path):
    body = "  WRITELN(R_PROFILE, ' ', R_JERK);\n  R_PROFILE := 'Trapezoid';  WRITELN(R_PROFILE);"
    run = _run(tmp_path, body, "scurve")
    assert run.output == ["SCURVE 10000.0", "TRAPEZOID"]
    with pytest.raises(CompileError) as info:
        _run(tmp_path, "  R_JERK := 0;", "SCURVE")
    assert "R_JERK := 0: the value must be in (0, 10000000] mm/s³" in str(info.value)
    with pytest.raises(CompileError) as info:
        _run(tmp_path, "", "SMOOTH")
    assert "R_PROFILE := 'SMOOTH': the value must be one of 'TRAPEZOID', 'SCURVE'" in str(
        info.value
    )
    with pytest.raises(CompileError) as info:
        _run(tmp_path, "  R_PROFILE := 5;", "SCURVE")
    assert "R_PROFILE" in str(info.value)
    # a value the compiler cannot see is checked when it is assigned, at its line
    code = compile_program(
        tmp_path / "p.irl",
        source="PROGRAM p;\nROBOT r := irb6;\nVAR STRING: s;\nBEGIN\n  s := 'FAST';\n"
        "  R_PROFILE := s;\nENDPROGRAM\n",
    )
    run = run_code(code)
    assert run.status == "failed" and run.error.line == 6
    assert "R_PROFILE := 'FAST': the value must be one of 'TRAPEZOID', 'SCURVE'" in str(run.error)


# The drives: irb6_track, the arm out and back at 12 % speed (the held-out drive programs'
# speed, within the drives' capacity), decoupled drives. The path tolerance is stated
# (the drives lag by v/K_v along the path, millimetres at these speeds).
DRIVE_BODY = """  MOVE PTP (400, 90, 0, 0, -45, 0);
  MOVE PTP (400, 100, 10, 5, -60, 45) WITH SPEED_PTP := 12;
  MOVE PTP (400, 90, 0, 0, -45, 0) WITH SPEED_PTP := 12;
  WAIT 0.6 SEC;"""
PATH_TOLERANCE_MM = 20.0


def _axes(run) -> dict[str, tuple[float, float]]:
    """joint → (max following error in its unit, peak current A) from the report."""
    out = {}
    for axis in run.report["drives_summary"]["axes"]:
        error = next(v for k, v in axis.items() if k.startswith("max_following_error"))
        out[axis["joint"]] = (error, axis["peak_current_A"])
    return out


def test_scurve_lowers_peak_currents_and_following_errors_with_drives(tmp_path):
    runs = {
        p: _run(
            tmp_path,
            DRIVE_BODY,
            p,
            robot="irb6_track",
            drives="decoupled",
            path_tolerance=PATH_TOLERANCE_MM,
        )
        for p in ("TRAPEZOID", "SCURVE")
    }
    trap, scur = (_axes(runs[p]) for p in ("TRAPEZOID", "SCURVE"))
    moving = [j for j, (err, _) in trap.items() if err > 1e-6]
    assert len(moving) == 5  # the arm's five joints (the track stands)
    for j in moving:
        assert scur[j][0] <= trap[j][0] * (1 + 1e-3), (j, scur[j], trap[j])
        assert scur[j][1] <= trap[j][1] * (1 + 1e-3), (j, scur[j], trap[j])
    # measured: 25.8 A → 23.6 A summed over the joints, A1's peak 1.48 → 1.15 A, A5's
    # 3.08 → 1.89 A (the trapezoid's acceleration steps excite the loops)
    assert sum(scur[j][1] for j in moving) <= 0.95 * sum(trap[j][1] for j in moving)
    assert sum(scur[j][0] for j in moving) < sum(trap[j][0] for j in moving)


def test_limit_activity_marks_only_the_held_acceleration(tmp_path):
    # A1 60 deg at 44 deg/s, 120 deg/s², jerk 120 · 10000/1000 = 1200 deg/s³: the
    # acceleration is held for t₂ = 44/120 − 120/1200 = 0.267 s at each end (the trapezoid
    # holds it for its whole ramp, 44/120 = 0.367 s)
    body = """  R_SPEED_PTP := 100;  R_ACC_PTP := 100;  R_JERK := 10000;
  MOVE PTP (150, 0, 0, -45, 0);"""
    for profile, held in (("SCURVE", 44 / 120 - 0.1), ("TRAPEZOID", 44 / 120)):
        activity = _run(tmp_path, body, profile).report["joints"][0]["limit_activity"]
        for side in ("accel max", "accel min"):
            assert activity[side] == pytest.approx(held, abs=2 * DT), (profile, activity)


PROGRAMS = Path(__file__).resolve().parents[2] / "programs"


@pytest.mark.parametrize("name", ["combined", "mobile8_freeze"])
def test_scurve_with_the_redundancy_options(tmp_path, name):
    """The golden programs (JOINTLIMIT family, CYCLIC, RECONFIGURATION, OBSTACLE, FREEZE)
    with R_PROFILE := 'SCURVE' first: they run within every bound and tolerance, a little
    slower than with the trapezoid (their golden duration)."""
    runs = {}
    for profile in ("SCURVE", "TRAPEZOID"):
        source = (PROGRAMS / f"{name}.irl").read_text(encoding="utf-8")
        source = source.replace("BEGIN\n", f"BEGIN\n  R_PROFILE := '{profile}';\n", 1)
        runs[profile] = run_code(compile_program(PROGRAMS / f"{name}.irl", source=source))
        assert runs[profile].status == "ok", runs[profile].error
    golden = json.loads((PROGRAMS / f"{name}.expected.json").read_text(encoding="utf-8"))
    assert runs["TRAPEZOID"].report["duration_s"] == pytest.approx(golden["duration_s"])
    assert runs["SCURVE"].report["duration_s"] > golden["duration_s"]
    # the same last point (the joints may differ: the self-motion depends on the timing)
    end = [r.tcp[-1] for r in runs.values()]
    assert np.allclose(end[0], end[1], atol=1e-6)
