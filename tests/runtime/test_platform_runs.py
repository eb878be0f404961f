"""The platform task at run time (issue 27): ``WITH PLATFORM := q`` and ``R_PLATFORM``.

Checked independently of the controller: the platform frame's position comes from the
robot's own forward kinematics (``Kinematics.link_frames``) of the joints in the run's
trace, the TCP's from the same FK; the platform must lie on the straight line from its
start to ``q`` and be the same fraction of its way as the TCP is of its path at every
sample (arc length for a LIN, the swept angle for a CIRCLE, the joint fraction for a PTP).
"""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import numpy as np
from irlc.robots import load_robot
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.run import run_file

PROGRAMS = Path(__file__).resolve().parents[2] / "programs"


def _program(tmp_path: Path, robot: str, body: str, cell: str | None = None) -> Path:
    head = f"PROGRAM p;\nROBOT r := {robot};\n"
    if cell is not None:
        shutil.copy(PROGRAMS / f"{cell}.toml", tmp_path / f"{cell}.toml")
        head += f"IMPORT DATALIST {cell};\n"
    path = tmp_path / "p.irl"
    path.write_text(head + "BEGIN\n" + body + "ENDPROGRAM\n")
    return path


def _track(tmp_path: Path, before: str, after: str):
    """A run of as6_track from ``ready`` to ``line_start`` with the carriage held, ``before``
    and ``after`` that (statements), which must succeed; the statements after are on
    lines 8, 9, … (``before`` adds its lines)."""
    body = before + "  R_PLATFORM := 'HOLD';\n  MOVE PTP ready;\n  MOVE LIN line_start;\n"
    run = run_file(_program(tmp_path, "as6_track", body + after, "track_cell"))
    assert run.status == "ok", run.error
    return run


def _fk(model, q: np.ndarray):
    """(platform points (link of the last platform joint, its origin), TCP positions)."""
    kin = Kinematics(model)
    link = model.platform.link
    frames = [kin.link_frames(row) for row in q]
    return np.array([f[link][:3, 3] for f in frames]), np.array([kin.tcp(row)[:3, 3] for row in q])


def _rows(run, line: int) -> np.ndarray:
    """The samples of ``line`` and the one before (where the statement starts)."""
    lines = run.trace[:, run.trace_columns.index("line")]
    idx = np.flatnonzero(lines == line)
    assert idx.size > 10 and idx[0] > 0
    return np.concatenate(([idx[0] - 1], idx))


def _line_fraction(points: np.ndarray) -> tuple[np.ndarray, float]:
    """How far along the straight line from the first to the last point each point is
    (0 … 1), and the largest distance of a point from that line (m)."""
    start, end = points[0], points[-1]
    d = end - start
    f = (points - start) @ d / (d @ d)
    off = points - start - np.outer(f, d)
    return f, float(np.max(np.linalg.norm(off, axis=1)))


def test_track_platform_carriage_and_tool_in_step():
    """programs/track_platform.irl: the carriage goes 0 → 1500 mm on a straight line while
    the tool draws 600 mm on the wall, the same fraction of the way at every sample; with
    R_PLATFORM := 'HOLD' the carriage does not move before or after."""
    run = run_file(PROGRAMS / "track_platform.irl")
    assert run.status == "ok", run.error
    model = load_robot("as6_track")
    rows = _rows(run, 17)
    platform, tcp = _fk(model, run.q[rows])
    np.testing.assert_allclose(platform[[0, -1], 1], [0.0, 1.5], atol=1e-9)
    np.testing.assert_allclose(tcp[[0, -1], 1], [0.45, 1.05], atol=1e-9)
    f_platform, off_platform = _line_fraction(platform)
    f_tcp, off_tcp = _line_fraction(tcp)
    assert off_platform < 1e-9 and off_tcp < 1e-8  # both straight
    np.testing.assert_allclose(f_platform, f_tcp, atol=1e-8)  # in step
    assert np.all(np.diff(f_tcp) >= -1e-12) and f_tcp[0] == 0.0 and f_tcp[-1] == 1.0
    # the trace's platform column is the robot's FK of its own joints
    column = run.trace[:, run.trace_columns.index("platform_y_mm")]
    all_platform, _ = _fk(model, run.q)
    np.testing.assert_allclose(column, all_platform[:, 1] * 1000.0, atol=1e-6)
    # HOLD: every other statement leaves the carriage exactly where it is
    lines = run.trace[:, run.trace_columns.index("line")]
    t = run.q[:, 0]
    assert np.all(t[lines < 17] == 0.0)
    assert np.all(t[lines == 18] == t[rows[-1]])
    report = run.report["platform"]
    assert report["coordinates"] == ["y"] and report["end_mm"] == [1500.0]
    (motion,) = report["motions"]
    assert motion["line"] == 17 and motion["target_mm"] == [1500.0]
    assert motion["start_mm"] == [0.0] and motion["max_error_mm"] < 1e-6


def test_without_hold_the_redundancy_moves_the_carriage(tmp_path):
    """The same moves with R_PLATFORM 'FREE' (the start value): the LINs before the platform
    motion move the carriage (the track is the arm's redundant joint) — what HOLD stops."""
    body = "  R_SPEED := 200;\n  MOVE PTP ready;\n  MOVE LIN above_start;\n  MOVE LIN line_start;\n"
    run = run_file(_program(tmp_path, "as6_track", body, "track_cell"))
    assert run.status == "ok", run.error
    assert np.ptp(run.q[:, 0]) > 1e-3


def test_mobile_platform_line_in_step_with_the_circle():
    """programs/mobile_platform.irl: the platform (x, y) goes (0, 0) → (0, 500) mm along a
    straight line while the tool draws a full circle (two CIRCLE halves); the platform's
    fraction of its line equals the circle's swept angle over 2π at every sample."""
    run = run_file(PROGRAMS / "mobile_platform.irl")
    assert run.status == "ok", run.error
    model = load_robot("mobile8")
    rows = np.concatenate((_rows(run, 16), _rows(run, 17)[1:]))
    platform, tcp = _fk(model, run.q[rows])
    np.testing.assert_allclose(platform[[0, -1], :2], [[0.0, 0.0], [0.0, 0.5]], atol=1e-9)
    f_platform, off = _line_fraction(platform[:, :2])
    assert off < 1e-9
    centre = np.array([1.0, 0.25, 0.8])
    rel = tcp - centre
    np.testing.assert_allclose(np.linalg.norm(rel, axis=1), 0.15, atol=1e-8)  # on the circle
    np.testing.assert_allclose(rel[:, 0], 0.0, atol=1e-8)  # in the wall's plane x = 1000
    # swept angle from the start (y = 100: −y side), through the top (z up), 0 … 2π
    angle = np.unwrap(np.arctan2(rel[:, 2], -rel[:, 1]))
    angle = angle - angle[0]
    np.testing.assert_allclose(angle[-1], 2 * math.pi, atol=1e-6)
    np.testing.assert_allclose(f_platform, angle / (2 * math.pi), atol=1e-7)
    assert run.output == ["platform at x = 0.0 mm, y = 500.0 mm"]


def test_ptp_lin_path_inc_and_a_held_tcp_with_platform_targets(tmp_path):
    """PTP to a POSE (the platform joints at the target's: a straight line in step with
    the PTP's joint fraction), a LIN through two points (the line split by arc length),
    MOVE_INC LIN, and a LIN to where the TCP is (the TCP holds, the platform moves)."""
    body = (
        "  R_SPEED := 200;\n  R_PLATFORM := 'HOLD';\n  MOVE PTP ready;\n"  # lines 5-7
        "  MOVE LIN line_start;\n"  # 8
        "  MOVE LIN line_start WITH PLATFORM := 300;\n"  # 9: the TCP holds
        "  MOVE LIN (-765, 650, 1030, 90, 0, -90), (-765, 850, 1030, 90, 0, -90)"
        " WITH PLATFORM := 900;\n"  # 10
        "  MOVE_INC LIN (100, 0, 0, 0, 0, 0) WITH PLATFORM := 1200;\n"  # 11
        "  MOVE PTP line_start WITH PLATFORM := 200;\n"  # 12
    )
    run = run_file(_program(tmp_path, "as6_track", body, "track_cell"))
    assert run.status == "ok", run.error
    model = load_robot("as6_track")
    # 9: the TCP stays at line_start within the path tolerance, the carriage 0 → 300
    platform, tcp = _fk(model, run.q[_rows(run, 9)])
    assert np.max(np.linalg.norm(tcp - tcp[0], axis=1)) < 5e-8
    np.testing.assert_allclose(platform[[0, -1], 1], [0.0, 0.3], atol=1e-9)
    # 10: two segments, one line 300 → 900: the fraction by the TCP's arc length
    platform, tcp = _fk(model, run.q[_rows(run, 10)])
    f_platform, off = _line_fraction(platform)
    assert off < 1e-9
    travelled = np.concatenate(([0.0], np.cumsum(np.linalg.norm(np.diff(tcp, axis=0), axis=1))))
    np.testing.assert_allclose(f_platform, travelled / travelled[-1], atol=1e-6)
    np.testing.assert_allclose(platform[-1, 1], 0.9, atol=1e-9)
    # 11: MOVE_INC LIN (tool frame: its x axis is the world's y)
    platform, tcp = _fk(model, run.q[_rows(run, 11)])
    f_platform, _ = _line_fraction(platform)
    f_tcp, _ = _line_fraction(tcp)
    np.testing.assert_allclose(f_platform, f_tcp, atol=1e-8)
    np.testing.assert_allclose([platform[-1, 1], tcp[-1, 1] - tcp[0, 1]], [1.2, 0.1], atol=1e-9)
    # 12: PTP — every joint moves on one line in joint space, the carriage with them
    rows = _rows(run, 12)
    q = run.q[rows]
    f_joints, off_joints = _line_fraction(q)
    assert off_joints < 1e-9
    platform, tcp = _fk(model, q)
    f_platform, _ = _line_fraction(platform)
    np.testing.assert_allclose(f_platform, f_joints, atol=1e-9)
    np.testing.assert_allclose(platform[-1, 1], 0.2, atol=1e-9)
    assert [m["line"] for m in run.report["platform"]["motions"]] == [9, 10, 11, 12]


def test_the_platform_joints_limits_time_the_motion(tmp_path):
    """A long carriage travel with a short tool line at a high path speed: the segment is
    timed by the track's speed limit (1000 mm/s), which the trace never exceeds."""
    after = "  R_SPEED := 2000;\n  R_ACC := 20000;\n"
    run = _track(
        tmp_path, "", after + "  MOVE LIN (-765, 750, 1030, 90, 0, -90) WITH PLATFORM := 1200;\n"
    )
    (row,) = [s for s in run.report["statements"] if s["line"] == 10]
    assert row["limit"] == "platform joint a1 (T) speed/acceleration"
    speed = run.trace[:, run.trace_columns.index("a1_speed_mm_s")]
    assert 990.0 < np.max(np.abs(speed)) <= 1000.0 + 1e-6


def test_hold_keeps_the_platform_still_through_lin_and_ptp(tmp_path):
    """R_PLATFORM := 'HOLD' on mobile8: a LIN and a PTP to a POSE leave the platform joints
    constant (the FREE run of the same LIN moves them)."""
    body = (
        "  R_PLATFORM := 'HOLD';\n  MOVE LIN c_right;\n  MOVE PTP c_top;\n"
        "  R_PLATFORM := 'free';\n  MOVE LIN c_left;\n"
    )
    run = run_file(_program(tmp_path, "mobile8", body, "mobile_platform_cell"))
    assert run.status == "ok", run.error
    lines = run.trace[:, run.trace_columns.index("line")]
    held = run.q[lines <= 7][:, :2]
    assert np.all(held == held[0])
    assert np.ptp(run.q[lines == 9][:, :2], axis=0).max() > 1e-3


def test_a_platform_target_the_arm_cannot_follow_fails_naming_the_platform_task(tmp_path):
    """mobile8: the TCP goes +300 mm in y while the platform is sent −300 mm: with the
    platform on its line the end is out of the arm's reach, with the platform free it is
    not — the failure names the platform task and how far off its line the TCP needs it,
    before anything moves."""
    body = "  MOVE LIN c_left;\n  MOVE LIN c_right WITH PLATFORM := (0, -300);\n"
    run = run_file(_program(tmp_path, "mobile8", body, "mobile_platform_cell"))
    err = run.report["error"]
    assert run.status == "failed" and err["line"] == 6 and err["cause"] == "platform"
    assert "the platform task cannot be met" in err["message"]
    assert err["platform_mm"] == [0.0, -300.0] and err["platform_off_line_mm"] > 300.0
    lines = run.trace[:, run.trace_columns.index("line")]
    assert not np.any(lines == 6)


def test_an_unreachable_tcp_target_names_the_tcp_task(tmp_path):
    """A TCP target out of reach for every platform position names the TCP task."""
    body = "  MOVE LIN (1000, 100, 2500, 0, 90, 0) WITH PLATFORM := (0, 100);\n"
    run = run_file(_program(tmp_path, "mobile8", body))
    err = run.report["error"]
    assert err["cause"] == "unreachable" and "the TCP task cannot be met" in err["message"]


def test_a_cycle_that_cannot_follow_names_both_deviations(tmp_path):
    """Both targets reachable, but the arm's joints slowed to 10 deg/s: the failing cycle
    reports the TCP's and the platform's deviation and the binding speed bound."""
    body = (
        "  lo := (-500, -500, -10, -10, -10, -10, -10, -10);\n"
        "  hi := (500, 500, 10, 10, 10, 10, 10, 10);\n"
        "  MOVE LIN c_left;\n"
        "  MOVE LIN c_right WITH PLATFORM := (0, 150) WITH JOINTSPEEDLIMIT lo, hi;\n"
    )
    path = _program(tmp_path, "mobile8", body, "mobile_platform_cell")
    text = path.read_text().replace(
        "BEGIN", "VAR MAIN_JOINT_SPEED_MIN: lo; MAIN_JOINT_SPEED_MAX: hi;\nBEGIN"
    )
    path.write_text(text)
    run = run_file(path)
    err = run.report["error"]
    assert run.status == "failed" and err["line"] == 9 and err["cause"] == "speed_limit"
    assert err["tcp_deviation_mm"] > 0.05 or err["platform_deviation_mm"] > 0.05
    assert "joints cannot follow in time" in err["message"]
    assert "speed max 10 deg/s" in err["constraint"]


def test_run_time_platform_errors_are_positioned(tmp_path):
    """A variable target beyond the platform's limits, one beyond an active JOINTLIMIT,
    and FREEZE of a platform joint with WITH PLATFORM: failures at the motion's line."""
    body = "  goal[1] := 6000; goal[2] := 0;\n  MOVE LIN c_left WITH PLATFORM := goal;\n"
    path = _program(tmp_path, "mobile8", body, "mobile_platform_cell")
    path.write_text(path.read_text().replace("BEGIN", "VAR ARRAY [1..2] OF REAL: goal;\nBEGIN"))
    err = run_file(path).report["error"]
    assert err["line"] == 7 and err["cause"] == "platform_limit"
    assert "needs joint a1 (X) at 6000 mm" in err["message"]
    body = (
        "  JOINTLIMIT (-100, -100, -180, -120, -150, -180, -120, -180),"
        " (100, 100, 180, 90, 150, 180, 120, 180);\n"
        "  MOVE LIN c_left WITH PLATFORM := (0, 200);\n  JOINTLIMITEND;\n"
    )
    err = run_file(_program(tmp_path, "mobile8", body, "mobile_platform_cell")).report["error"]
    assert err["line"] == 6 and err["cause"] == "platform_limit"
    assert "a2 (Y) at 200 mm, beyond the active position limit (max 100 mm)" in err["message"]
    body = "  FREEZESTART 2;\n  MOVE LIN c_left WITH PLATFORM := (0, 200);\n  FREEZEEND;\n"
    err = run_file(_program(tmp_path, "mobile8", body, "mobile_platform_cell")).report["error"]
    assert err["line"] == 6 and err["cause"] == "freeze" and "a2 (Y)" in err["message"]


def test_hand_written_code_with_the_wrong_dimension_fails_at_its_line(tmp_path):
    """IRDATA whose PLATFORM operand is one number for mobile8's two coordinates (the
    compiler refuses it; hand-written code reaches the runtime): a failure at its line."""
    from irlc.lang import compile_file, read_code, write_code
    from irlc.runtime.run import run_code

    path = _program(tmp_path, "mobile8", "  MOVE LIN c_left WITH PLATFORM := (0, 200);\n",
                    "mobile_platform_cell")  # fmt: skip
    text = write_code(compile_file(path, resolve_robot=load_robot).code)
    assert "MAKE ARRAY[1..2]OFREAL 2" in text
    code = read_code(text.replace("MAKE ARRAY[1..2]OFREAL 2", "ADD"))  # 0 + 200: one REAL
    err = run_code(code).report["error"]
    assert err["line"] == 5 and "robot mobile8's platform has 2 (x, y mm)" in err["message"]


def test_hold_on_a_robot_without_a_platform_warns_and_holds_nothing(tmp_path):
    from irlc.lang import compile_file

    path = _program(
        tmp_path, "planar3", "  R_PLATFORM := 'HOLD';\n  MOVE LIN (1500, 500, 0, 0, 0, 0);\n"
    )
    result = compile_file(path, resolve_robot=load_robot)
    (warning,) = result.warnings
    assert result.ok and warning.span.line == 4 and "has no platform to hold" in warning.message
    run = run_file(path)
    assert run.status == "ok" and "platform" not in run.report


def test_an_s_curve_platform_motion_keeps_the_tracks_jerk(tmp_path):
    """R_PROFILE := 'SCURVE': the platform's joints get a PTP's jerk bound (the track has
    none in its file: θ̈max·R_JERK/R_ACC = 2000·10000/1000 = 20000 mm/s³), also when the
    TCP holds; the trace's backward-difference jerk, acceleration and speed of the track
    stay within 20000 mm/s³, 2000 mm/s², 1000 mm/s."""
    after = (
        "  MOVE LIN line_start WITH PLATFORM := 300;\n  MOVE LIN line_end WITH PLATFORM := 1500;\n"
    )
    run = _track(tmp_path, "  R_PROFILE := 'SCURVE';\n", after)
    limits = {s["line"]: s["limit"] for s in run.report["statements"]}
    assert limits[9] == "platform joint a1 (T) speed/acceleration/jerk"
    track = run.report["joints"][0]
    assert track["max_abs_jerk"] <= 20000.0 * (1 + 1e-6)
    assert track["max_abs_accel"] <= 2000.0 * (1 + 1e-6)
    assert track["max_abs_speed"] <= 1000.0 * (1 + 1e-6)


def test_hold_blends_its_motions_and_stops_a_free_one_first(tmp_path):
    """Approximated motions under HOLD blend (the platform stays where the first stopped);
    a FREE motion before them ends with an exact stop, saying why."""
    body = (
        "  R_APPROX := 30;\n  MOVE LIN c_left;\n  R_PLATFORM := 'HOLD';\n"
        "  MOVE LIN c_top;\n  MOVE LIN c_right;\n  MOVE LIN c_bottom;\n"
        "  MOVE LIN c_left WITH APPROX := 0;\n"
    )
    run = run_file(_program(tmp_path, "mobile8", body, "mobile_platform_cell"))
    assert run.status == "ok", run.error
    points = {a["line"]: a for a in run.report["approximations"]}
    assert not points[6]["blended"] and "R_PLATFORM := 'HOLD'" in points[6]["note"]
    assert all(points[line]["blended"] for line in (8, 9, 10))
    lines = run.trace[:, run.trace_columns.index("line")]
    held = run.q[lines >= 8][:, :2]
    assert np.all(held == run.q[np.flatnonzero(lines == 6)[-1], :2])
