"""With drives, the verdict comes from the actual motion (issue 9 §1).

A straight line on irb6_track at 60 mm/s: its drives (K_v = 30 1/s on the arm axes) lag the
setpoint by millimetres, while the kinematic (ideal) run follows the line to ~1e-6 mm.
Checked through the command line and the API, against an independent forward kinematics
of the trace's actual joints and an ideal run of the same program.
"""

from __future__ import annotations

import csv
import json
import shutil
from pathlib import Path

import numpy as np
import pytest
from irlc.cli import main
from irlc.robots.loader import load_toml
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.run import run_file
from irlc.runtime.units import joints_to_si

ROOT = Path(__file__).resolve().parents[2]
ROBOT = ROOT / "robots" / "irb6_track.toml"
LIN_LINE = 12  # the line of the first MOVE LIN below
PROGRAM = """{ a straight line in the work area, ends from irlc fk irb6_track }
PROGRAM verdict_line;
ROBOT r := irb6_track;
VAR
  POSE: start, goal;
BEGIN
  start := (-843.241, 976.759, 400, 135, 0, -90);
  goal := (-653.063, 934.597, 400, 135, 0, -90);
  {PATHTOL}
  MOVE PTP (400, 90, 0, 0, -45, 0);
  R_SPEED := 60;
  MOVE LIN goal WITH ACC := 250;
  {PATHTOL2}
  MOVE LIN start WITH ACC := 250;
  WAIT 0.3 SEC;
ENDPROGRAM
"""
LOOSE = ["--path-tolerance", "20", "--orientation-tolerance", "1"]

pytestmark = pytest.mark.scenario


def write(tmp_path: Path, name: str = "line", tol: str = "", tol2: str = "") -> Path:
    path = tmp_path / f"{name}.irl"
    path.write_text(PROGRAM.replace("{PATHTOL}", tol).replace("{PATHTOL2}", tol2))
    return path


def cli(tmp_path: Path, program: Path, *extra: str, capsys=None):
    report, trace = tmp_path / "r.json", tmp_path / "t.csv"
    args = ["run", str(program), "--drives", "decoupled", "--report", str(report)]
    code = main([*args, "--trace", str(trace), "-q", *extra])
    err = capsys.readouterr().err if capsys is not None else ""
    with trace.open(newline="") as f:
        rows = list(csv.DictReader(f))
    return code, json.loads(report.read_text()), rows, err


def test_leaving_the_path_fails_at_its_line_with_a_stated_tolerance(tmp_path, capsys):
    program = write(tmp_path)
    code, report, rows, err = cli(tmp_path, program, "--path-tolerance", "0.5", capsys=capsys)
    assert code == 2
    assert report["status"] == "failed"
    assert report["error"]["line"] == LIN_LINE
    assert f"line.irl:{LIN_LINE}:" in err and "--path-tolerance" in err and "R_PATH_TOL" in err
    first = report["verdict"]["violations"][0]
    assert first["criterion"] == "path_tolerance" and first["line"] == LIN_LINE
    assert first["limit"] == 0.5 and first["value"] > 0.5
    assert report["verdict"]["criteria"]["path_tolerance_from"] == "--path-tolerance"
    assert report["error"]["time_s"] == pytest.approx(first["time_s"])
    # the trace stops at the failure (issue 24 §3): its last row is the first one beyond
    # the tolerance, at the failure's time and line
    over = [r for r in rows if float(r["path_error_mm"]) > 0.5]
    assert len(over) == 1 and rows[-1] is over[0]
    assert float(over[0]["t_s"]) == pytest.approx(first["time_s"])
    assert int(float(over[0]["line"])) == LIN_LINE
    assert report["duration_s"] == pytest.approx(first["time_s"])
    assert report["verdict"]["could_follow"] is False
    assert report["drives_summary"]["could_follow"] is False
    assert report["max_path_error_mm"] > 0.5  # the drives' lag, up to the failure
    assert report["ideal"]["max_path_error_mm"] < 1e-3  # the commanded motion is on the path


def test_without_a_stated_tolerance_the_path_is_reported_not_judged(tmp_path):
    """The kinematic 0.05 mm judges the set points; a drive run's path is judged only by a
    tolerance stated for it (issue 24 §2): here none, so the millimetres of servo lag are
    reported and the drives are judged by their following error."""
    code, report, _, _ = cli(tmp_path, write(tmp_path))
    assert code == 0 and report["status"] == "ok"
    crit = report["verdict"]["criteria"]
    assert crit["path_tolerance_mm"] is None and crit["path_tolerance_from"] is None
    assert crit["orientation_tolerance_deg"] is None
    assert report["max_path_error_mm"] > 1.0  # reported


def test_the_robots_path_accuracy_judges_when_the_user_states_none(tmp_path):
    """``[drives] path_accuracy`` (ISO 9283 AT_p) of the robot file: 2 mm fails the line,
    whose actual path leaves it by ≈ 6.7 mm; 10 mm passes it."""
    for accuracy, expect in ((0.002, 2), (0.01, 0)):
        text = ROBOT.read_text().replace("[drives]\n", f"[drives]\npath_accuracy = {accuracy}\n")
        robot = tmp_path / "accurate.toml"
        robot.write_text(text)
        code, report, _, _ = cli(tmp_path, write(tmp_path), "--robot", str(robot))
        assert code == expect, report["error"]
        crit = report["verdict"]["criteria"]
        assert crit["path_tolerance_mm"] == pytest.approx(accuracy * 1e3)
        assert crit["path_tolerance_from"] == "[drives] path_accuracy"
        if expect:
            assert report["verdict"]["violations"][0]["criterion"] == "path_tolerance"
            assert "path accuracy" in report["error"]["message"]


def test_the_same_run_passes_with_a_loose_path_tolerance(tmp_path):
    code, report, _, _ = cli(tmp_path, write(tmp_path), *LOOSE)
    assert code == 0 and report["status"] == "ok"
    verdict = report["verdict"]
    assert verdict["could_follow"] is True and verdict["violations"] == []
    assert verdict["criteria"]["path_tolerance_mm"] == 20.0
    assert verdict["criteria"]["orientation_tolerance_deg"] == 1.0
    assert report["drives_summary"]["could_follow"] is True
    assert 1.0 < report["max_path_error_mm"] <= 20.0


def test_r_path_tol_is_modal_in_the_program(tmp_path, capsys):
    loose = write(tmp_path, "modal", tol="R_PATH_TOL := 20;")
    code, report, _, _ = cli(tmp_path, loose, "--orientation-tolerance", "1")
    assert code == 0, report["error"]
    # the tolerance the program set on the path, not the option's unused start value
    assert report["tolerances"]["path_mm"] == report["tolerances"]["path_mm_loosest"] == 20
    # tightened again before the second line: that line fails, at its own statement
    tight = write(tmp_path, "modal2", tol="R_PATH_TOL := 20;", tol2="R_PATH_TOL := 0.5;")
    code, report, _, err = cli(tmp_path, tight, "--orientation-tolerance", "1", "--path-tolerance",
                               "30", capsys=capsys)  # fmt: skip
    assert code == 2
    assert report["error"]["line"] == LIN_LINE + 2
    assert report["verdict"]["criteria"]["path_tolerance_mm"] == 0.5
    assert (report["tolerances"]["path_mm"], report["tolerances"]["path_mm_loosest"]) == (0.5, 20)
    # the option cannot reach a statement whose R_PATH_TOL the program set: not advised
    flat = " ".join(err.split())
    assert "loosen R_PATH_TOL, which the program set to 0.5 mm" in flat
    assert "--path-tolerance" not in flat


@pytest.mark.parametrize("tool_mm", [0.0, 100.0])
def test_report_path_error_is_fk_of_the_actual_joints_against_the_commanded_path(tmp_path, tool_mm):
    """Also with ``R_TOOL`` set in the program: the actual TCP carries the program's tool."""
    program = write(tmp_path, tol=f"R_TOOL := (0, 0, {tool_mm:g}, 0, 0, 0);" if tool_mm else "")
    tool = np.array([0.0, 0.0, tool_mm / 1000.0, 1.0])  # in the robot file's TCP frame
    tol = {"path_tolerance": 20.0, "orientation_tolerance": 1.0}
    run = run_file(program, drives="decoupled", **tol)
    ideal = run_file(program, drives="ideal")
    assert run.ok and ideal.ok
    cols = run.trace_columns
    model = load_toml(ROBOT)
    kinds = model.joint_kinds
    names = run.report["joint_names"]
    joint_cols = [cols.index(f"{n}_{'mm' if k == 'prismatic' else 'deg'}") for n, k in
                  zip(names, kinds, strict=True)]  # fmt: skip
    kin = Kinematics(model)  # independent FK of the trace's actual joints (robot file's tool)
    actual = np.array(
        [(kin.tcp(joints_to_si(row[joint_cols], kinds)) @ tool)[:3] for row in run.trace]
    )
    # the commanded path: each LIN is a straight segment, from the ideal run's TCP where the
    # line starts to where it ends; the path error is the distance to the nearest of those
    # run so far
    # (contour error); the lag is the distance to the set point of the same instant
    assert np.allclose(ideal.trace[:, 0], run.trace[:, 0])
    xyz = [cols.index(c) for c in ("x_mm", "y_mm", "z_mm")]
    commanded = ideal.trace[:, xyz]
    lines = [np.flatnonzero(run.trace[:, 1] == line) for line in (LIN_LINE, LIN_LINE + 2)]
    segments = [(commanded[rows[0] - 1], commanded[rows[-1]]) for rows in lines]
    error = np.zeros(len(run.trace))
    lag = np.zeros(len(run.trace))
    for i, rows in enumerate(lines):  # the path so far: this line and the ones before it
        p = actual[rows] * 1000.0
        error[rows] = np.min([_distance_to_segment(p, a, b) for a, b in segments[: i + 1]], 0)
        lag[rows] = np.linalg.norm(p - commanded[rows], axis=1)
    assert error.max() > 0.5  # the drives leave the line by more than the default tolerance
    # the set point of the same instant lies on the line: its distance (the lag, a timing
    # error) bounds the path error, which is smaller where the TCP lags along the line
    assert np.all(error <= lag + 1e-9) and lag.max() > error.max() + 1.0
    # the way back ends at `start` as printed (3 decimals), 1.6e-4 mm beside where the way
    # out began: which of the two nearly equal lines is nearest differs by up to that much
    assert run.report["max_path_error_mm"] == pytest.approx(error.max(), abs=5e-4)
    assert np.allclose(run.trace[:, cols.index("path_error_mm")], error, atol=5e-4)
    # pose columns: the actual TCP (from the first motion on: R_TOOL is set at line 9)
    assert np.allclose(run.trace[1:, xyz], actual[1:] * 1000.0, atol=1e-6)


def _distance_to_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Closed form: the distance of each row of ``p`` to the segment ``a b``."""
    s = np.clip((p - a) @ (b - a) / ((b - a) @ (b - a)), 0.0, 1.0)
    return np.linalg.norm(p - a - np.outer(s, b - a), axis=1)


def test_ratings_beyond_the_drive_data_are_warnings(tmp_path, capsys):
    text = ROBOT.read_text()
    assert "[drives.dc]\n" in text and "[drives]\n" in text
    text = text.replace("[drives.dc]\n", "[drives.dc]\ni_peak = 2.0\n")
    text = text.replace("[drives]\n", "[drives]\ntorque_max = 5.0\n")
    robot = tmp_path / "rated.toml"
    robot.write_text(text)
    program = write(tmp_path)
    code, report, _, _ = cli(tmp_path, program, *LOOSE, "--robot", str(robot), capsys=capsys)
    assert code == 0  # warnings, not failures
    crit = report["verdict"]["criteria"]
    assert [r["value"] for r in crit["current_peak_A"]] == [2.0] * 6
    assert all(r["value"] == 5.0 for r in crit["torque_rating"])
    axes = {a["joint"]: a for a in report["drives_summary"]["axes"]}
    over_i = [n for n, a in axes.items() if a["peak_current_A"] > 2.0]
    assert over_i
    warned = [w for w in report["warnings"] if "above the motor's peak rating 2 A" in w]
    assert len(warned) == len(over_i)
    assert any("beyond the gear's rating 5" in w for w in report["warnings"])
    # the summary shows them, with the actual figures labelled and the criteria listed
    capsys.readouterr()
    assert main(["run", str(program), "--drives", "decoupled", *LOOSE, "--robot", str(robot)]) == 0
    shown = " ".join(capsys.readouterr().out.replace("│", " ").split())
    assert "actual motion; ideal" in shown and "verdict criteria" in shown
    assert "peak rating" in shown and "gear's" in shown
    # without ratings in the robot file: no criteria, no such warnings
    _, plain, _, _ = cli(tmp_path, program, *LOOSE)
    assert plain["verdict"]["criteria"]["current_peak_A"] is None
    assert not any("rating" in w for w in plain["warnings"])


def test_following_error_bound_from_the_drive_data(tmp_path):
    text = ROBOT.read_text().replace("[drives]\n", "[drives]\nfollowing_error_max = 1e-4\n")
    robot = tmp_path / "tight.toml"
    robot.write_text(text)
    code, report, _, _ = cli(tmp_path, write(tmp_path), *LOOSE, "--robot", str(robot))
    assert code == 2
    bounds = report["verdict"]["criteria"]["following_error_bound"]
    assert bounds[0]["unit"] == "mm" and bounds[0]["bound"] == pytest.approx(0.1)
    assert bounds[1]["unit"] == "deg" and bounds[1]["bound"] == pytest.approx(np.degrees(1e-4))
    assert report["verdict"]["violations"][0]["criterion"] == "following_error"
    # one violation per joint that could not follow (only the first was listed before)
    following = [v for v in report["verdict"]["violations"] if v["criterion"] == "following_error"]
    unable = {a["joint"] for a in report["drives_summary"]["axes"] if not a["could_follow"]}
    assert len(unable) > 1 and sorted(v["joint"] for v in following) == sorted(unable)
    assert all(v["value"] > v["limit"] for v in following)
    times = [v["time_s"] for v in report["verdict"]["violations"]]
    assert times == sorted(times)


def test_r_path_tol_must_be_positive(tmp_path):
    program = write(tmp_path, "zero", tol="R_PATH_TOL := R_SPEED - R_SPEED;")
    run = run_file(program)
    assert not run.ok and run.error.line == 9
    assert "R_PATH_TOL := 0.0: the value must be in [1e-05, ∞) mm" in run.error.message


def test_bad_tolerance_option_is_a_usage_error(tmp_path, capsys):
    program = write(tmp_path)
    assert main(["run", str(program), "--path-tolerance", "0", "-q"]) == 3
    assert "--path-tolerance must be a positive number" in capsys.readouterr().err
    # below round-off: a deviation of 2e-13 mm failed the run, blamed on the speed, and the
    # advice (a lower R_SPEED) never fixed it
    assert main(["run", str(program), "--path-tolerance", "1e-13", "-q"]) == 3
    err = " ".join(capsys.readouterr().err.split())
    assert "--path-tolerance 1e-13: the value must be in [1e-05, ∞) mm" in err


# ----------------------------------------------------------------- the criteria, in isolation


def _axis(j: int, error: float = 0.0, follow: bool = True):
    from irlc.runtime.drives import AxisSummary

    return AxisSummary(j, f"a{j + 1}", "revolute", "dc", error, 0.0, 0.0, 0.0, 1.0, 1.0, follow)


def _verdict(q, clear_ideal, clear_actual, following, axes, **options):
    from types import SimpleNamespace

    from irlc.runtime.control.executor import ExecutionOptions
    from irlc.runtime.drives import drive_params
    from irlc.runtime.outputs.verdict import judge

    from .drive_models import dc_drives, planar

    model = planar(2, drives=dc_drives(2))
    times = np.array([0.0, 0.01, 0.02])
    rec = SimpleNamespace(
        times=times,
        lines=np.array([0, 5, 6]),
        tol_position=np.full(3, 5e-5),
        clearance={"box": np.array(clear_ideal)},
    )
    none = np.zeros(3)
    actual = SimpleNamespace(
        times=times,
        lines=rec.lines,
        q=np.array(q),
        pos_error=none,
        ori_error=none,
        on_path=none.astype(bool),
        clearance={"box": np.array(clear_actual)},
        clearance_link={"box": np.array([2, 2, 2])},
    )
    rec.q = actual.q
    drive = SimpleNamespace(following_error=np.array(following), axes=axes, t=times)
    params = drive_params(model)
    opts = ExecutionOptions(**options)
    return judge(model, ("a1", "a2"), rec, drive, actual, opts, params)


def test_actual_collision_and_limit_overshoot_fail_first_in_time():
    q = [[0.0, 0.0], [0.0, 0.0], [3.01, 0.0]]  # a1 beyond +3 rad at the last sample
    v = _verdict(q, [0.1, 0.1, 0.1], [0.1, -0.002, 0.1], np.zeros((3, 2)), [_axis(0), _axis(1)])
    assert [x["criterion"] for x in v.violations] == ["collision", "position_limit"]
    assert v.failure.line == 5 and v.failure.time_s == 0.01
    assert "actual motion (simulated drives) collides with obstacle box" in v.failure.message
    assert "link 2 is 2 mm inside it" in v.failure.message
    assert v.violations[0]["obstacle"] == "box" and v.violations[0]["link"] == 2
    assert v.failure.cause == "obstacle" and v.failure.details["depth_mm"] == pytest.approx(2.0)
    assert v.violations[1]["joint"] == "a1" and v.violations[1]["line"] == 6
    assert v.violations[1]["value"] == pytest.approx(np.degrees(3.01))
    assert not v.could_follow
    # a penetration of the actual motion fails whether or not the commanded one had it
    # (issue 24 §1; the kinematic run fails there first) …
    v = _verdict(np.zeros((3, 2)), [0.1, -0.001, 0.1], [0.1, -0.002, 0.1], np.zeros((3, 2)),
                 [_axis(0), _axis(1)])  # fmt: skip
    assert [x["criterion"] for x in v.violations] == ["collision"]
    assert "the arm collides" in v.failure.message  # (the set points collide too)
    # … unless collisions are allowed
    v = _verdict(np.zeros((3, 2)), [0.1, -0.001, 0.1], [0.1, -0.002, 0.1], np.zeros((3, 2)),
                 [_axis(0), _axis(1)], allow_collisions=True)  # fmt: skip
    assert v.could_follow and v.violations == [] and v.criteria["collisions"] == "allowed"


def test_following_error_beyond_the_bound_between_recorded_rows_still_fails():
    # the bound: the position loop's range u_ref_max / (kz · ratio), joint side
    from .drive_models import DC_AXIS

    bound = np.degrees(DC_AXIS.get("u_ref_max", 5.0) / (DC_AXIS["kz"] * 30.0))
    # the recorded rows stay within it, the drive summary (every step) saw more on a2
    err = np.radians([[0.0, 0.0], [0.0, 0.8 * bound], [0.0, 0.2 * bound]])
    v = _verdict(np.zeros((3, 2)), [1.0] * 3, [1.0] * 3, err,
                 [_axis(0), _axis(1, np.radians(1.2 * bound), follow=False)])  # fmt: skip
    (row,) = v.violations
    assert row["criterion"] == "following_error" and row["joint"] == "a2"
    assert row["value"] == pytest.approx(1.2 * bound) and row["limit"] == pytest.approx(bound)
    assert row["time_s"] == 0.01 and row["line"] == 5
    assert "the position loop's range u_ref_max/kz" in v.failure.message


TURN = """PROGRAM turn;
ROBOT r := koch11;
IMPORT DATALIST square_cell;
BEGIN
  R_SPEED_ORI := 50;
  MOVE PTP konf_0;
  MOVE LIN (11500, 1000, 3500, 0, 40, 0);
ENDPROGRAM
"""


def test_a_turn_on_the_spot_is_matched_by_orientation(tmp_path):
    """An orientation-only LIN (koch11, 40° about y on the spot): the nearest commanded
    pose is chosen by orientation too, so the drives' lag along the turn is not an
    orientation error. Checked against an independent FK: the contour orientation error
    never exceeds the angle to the set point of the same instant, and is a fraction of it."""
    from irlc.runtime.model.spatial import zyx_to_matrix

    program = tmp_path / "turn.irl"
    program.write_text(TURN)
    shutil.copy(ROOT / "programs" / "square_cell.toml", tmp_path)
    run = run_file(program, drives="decoupled", path_tolerance=50.0, orientation_tolerance=10.0)
    ideal = run_file(program, drives="ideal")
    assert run.ok and ideal.ok and np.allclose(ideal.trace[:, 0], run.trace[:, 0])
    cols = run.trace_columns
    model = load_toml(ROOT / "robots" / "koch11.toml")
    kinds = model.joint_kinds
    joint_cols = [cols.index(f"{n}_{units_of(k)}") for n, k in
                  zip(run.report["joint_names"], kinds, strict=True)]  # fmt: skip
    kin = Kinematics(model)
    abc = [cols.index(c) for c in ("a_deg", "b_deg", "c_deg")]
    turning = run.trace[:, 1] == 7
    lag = []
    for row, cmd in zip(run.trace[turning], ideal.trace[turning], strict=True):
        actual = kin.tcp(joints_to_si(row[joint_cols], kinds))[:3, :3]
        commanded = zyx_to_matrix(*np.radians(cmd[abc]))
        cos = (np.trace(actual @ commanded.T) - 1.0) / 2.0
        lag.append(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))
    contour = run.trace[turning, cols.index("orientation_error_deg")]
    assert max(lag) > 1.0  # the drives lag the turn by degrees
    assert np.all(contour <= np.array(lag) + 1e-6)
    assert contour.max() < 0.5 * max(lag)
    assert run.report["max_orientation_error_deg"] == pytest.approx(contour.max(), abs=1e-6)


def units_of(kind: str) -> str:
    return "mm" if kind == "prismatic" else "deg"


@pytest.mark.parametrize("ipo", [0.01, 0.001, 0.0001])
def test_the_nearest_point_search_covers_the_window_in_at_most_its_sample_cap(ipo):
    # a straight commanded line at `ipo`: the search looks 2 s back and 0.5 s ahead, over
    # at most WINDOW_MAX_SEGMENTS segments (it was every sample of the window: quadratic in
    # a run's length at a small IPO cycle, 3 minutes of CPU for 2.5 s at 0.1 ms), and the
    # nearest point it finds is exact (a point beside the line: its distance)
    from types import SimpleNamespace

    from irlc.runtime.outputs import actual_motion as am

    times = np.arange(0.0, 3.0 + ipo / 2, ipo)
    desired = np.tile(np.eye(4), (len(times), 1, 1))
    desired[:, 0, 3] = times  # along x at 1 m/s
    path = am._CommandedPath(
        SimpleNamespace(times=times, desired=desired, on_path=np.ones(len(times), bool))
    )
    searched: list[int] = []
    nearest = path._nearest
    path._nearest = lambda seg, *a: searched.append(seg.size) or nearest(seg, *a)
    tcp = np.eye(4)
    tcp[:3, 3] = (2.0 - 0.1, 0.003, 0.0)  # 0.1 s behind t = 2 s, 3 mm beside the line
    pos, _ = path.contour_error(2.0, tcp, np.arange(3), np.array([], int))
    assert pos == pytest.approx(0.003, abs=1e-12)
    assert 0 < searched[0] <= am.WINDOW_MAX_SEGMENTS
    assert searched[0] == min(round(2.5 / ipo), am.WINDOW_MAX_SEGMENTS)
