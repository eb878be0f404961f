"""One naming rule for joints in every output (issue 9 §3): program names ``a1 … aN``
first, the robot file's name in parentheses where it differs (``a5 (A3)`` on mobile8,
``a4 (panda_joint4)`` on panda), a ``robot_name`` key in JSON, program names in the trace
columns, and the robot's own names in the ROS-like trajectory export."""

from __future__ import annotations

import json
import re

import pytest
from irlc.animate import animation_data
from irlc.cli import main
from irlc.plots import axis_label
from irlc.repl import Session
from irlc.robots import load_robot
from irlc.run_data import run_data
from irlc.runtime.run import run_file

PROGRAMS = {
    "mobile8": "MOVE PTP (100, 0, 0, -30, 60, 0, -30, 0);",
    "panda": "MOVE PTP (0, -30, 0, -120, 0, 90, 45);",
}
# robot file names, written out here (not read through irlc.runtime.model.naming)
ROBOT_NAMES = {
    "mobile8": ["X", "Y", "A1", "A2", "A3", "A4", "A5", "A6"],
    "panda": [f"panda_joint{i}" for i in range(1, 8)],
}


def _program(tmp_path, robot: str, body: str, head: str = ""):
    path = tmp_path / f"{robot}_names.irl"
    path.write_text(f"PROGRAM names;\nROBOT r := {robot};\nBEGIN\n{head}  {body}\nENDPROGRAM\n")
    return path


def _labels(robot: str) -> list[str]:
    return [f"a{i} ({name})" for i, name in enumerate(ROBOT_NAMES[robot], 1)]


@pytest.mark.parametrize("robot", ["mobile8", "panda"])
def test_summary_report_trace_and_export_use_one_rule(tmp_path, capsys, robot):
    prog = _program(tmp_path, robot, PROGRAMS[robot])
    report, trace, traj = tmp_path / "r.json", tmp_path / "t.csv", tmp_path / "x.json"
    code = main(
        [str(prog), "--report", str(report), "--trace", str(trace),
         "--export-trajectory", str(traj)]
    )  # fmt: skip
    out = capsys.readouterr().out
    assert code == 0, out
    for label in _labels(robot):  # every joint of the summary, robot name beside it
        assert re.search(rf"│ {re.escape(label)} \[(deg|mm)\]\s+│", out), (label, out)
    rep = json.loads(report.read_text())
    assert [j["name"] for j in rep["joints"]] == [f"a{i + 1}" for i in range(len(rep["joints"]))]
    assert [j["robot_name"] for j in rep["joints"]] == ROBOT_NAMES[robot]
    assert rep["robot_joint_names"] == ROBOT_NAMES[robot]
    assert rep["joint_names"] == [j["name"] for j in rep["joints"]]
    header = trace.read_text().splitlines()[0].split(",")
    assert header[2 : 2 + len(rep["joints"])][-1] == f"a{len(rep['joints'])}_deg"
    doc = json.loads(traj.read_text())
    assert doc["joint_names"] == ROBOT_NAMES[robot]  # ROS tooling: the robot's own names
    assert doc["program_joint_names"] == rep["joint_names"]


@pytest.mark.parametrize("robot", ["mobile8", "panda"])
def test_fk_robot_and_repl_use_the_summary_names(capsys, robot):
    model = load_robot(robot)
    home = [str(v) for v in model.home_q() * 0.0]
    assert main(["fk", robot, *home]) == 0
    fk_out = capsys.readouterr().out
    assert main(["robot", robot]) == 0
    robot_out = capsys.readouterr().out
    session = Session(robot)
    robot_lines = "\n".join(session._meta_robot("").lines)
    limit_lines = "\n".join(session.limits())
    for i, (label, name) in enumerate(zip(_labels(robot), ROBOT_NAMES[robot], strict=True), 1):
        assert label in fk_out and label in robot_lines and label in limit_lines
        assert re.search(rf"^\s*a{i}\s+{re.escape(name)}\s", robot_out, re.M), robot_out


def test_plots_and_animation_label_joints_by_the_rule(tmp_path):
    run = run_file(_program(tmp_path, "panda", PROGRAMS["panda"]))
    assert run.status == "ok", run.error
    d = run_data(run)
    assert axis_label(d, 3, 0) == "a4 (panda_joint4) [deg]"
    data = animation_data(run)
    assert data["joint_labels"] == _labels("panda")
    assert data["units"] == {"length": "mm", "angle": "deg", "time": "s"}


def test_summary_and_report_show_the_active_tool(tmp_path, capsys):
    prog = _program(
        tmp_path, "panda", PROGRAMS["panda"], head="  R_TOOL := POSE(0, 0, 150, 0, 0, 0);\n"
    )
    report = tmp_path / "r.json"
    assert main([str(prog), "--report", str(report)]) == 0
    out = capsys.readouterr().out
    tool = json.loads(report.read_text())["tool"]
    # panda.toml's tool is 103.4 mm along z, turned -45 deg about z; R_TOOL adds 150 mm on z
    assert tool["robot_file"] == pytest.approx([0, 0, 103.4, -45, 0, 0], abs=1e-9)
    assert tool["r_tool"] == pytest.approx([0, 0, 150, 0, 0, 0], abs=1e-9)
    assert tool["active"] == pytest.approx([0, 0, 253.4, -45, 0, 0], abs=1e-9)
    assert "(0, 0, 253.4, -45, 0, 0) mm, deg" in out
    assert "R_TOOL (0, 0, 150, 0, 0, 0)" in out


def test_drive_axes_in_the_report_follow_the_rule(tmp_path):
    run = run_file(_program(tmp_path, "koch11", "WAIT 0.05 SEC;"), drives="decoupled")
    assert run.status == "ok", run.error
    axes = run.report["drives_summary"]["axes"]
    assert [a["joint"] for a in axes] == [f"a{i}" for i in range(1, 12)]
    assert [a["robot_name"] for a in axes] == [f"J{i}" for i in range(1, 12)]


def test_repl_options_show_the_composed_tool_and_frozen_joints_by_name(tmp_path):
    s = Session("mobile8")
    for text in ("R_TOOL := POSE(0, 0, 150, 0, 0, 0);", "FREEZESTART 3;"):
        assert s.enter(text).failure == 0, text
    lines = s.enter(":options").lines
    # mobile8.toml's tool turns 90 deg about y; R_TOOL's 150 mm on its z is then along x
    assert "R_TOOL (0, 0, 150, 0, 0, 0) after the robot file's tool (0, 0, 0, 0, 90, 0)" in (
        "\n".join(lines)
    )
    assert any(line.startswith("FREEZE a3=") for line in lines), lines
    moved = s.enter("MOVE_INC PTP (10, 0, 0, 0, 0, 0, 0, 0)")
    assert moved.failure == 0, moved.lines
    trace = tmp_path / "t.csv"
    assert s.enter(f":trace {trace}").failure == 0
    rows = [r.split(",") for r in trace.read_text().splitlines()]
    col = rows[0].index("x_mm")
    # the start sample already has the program's tool: a 10 mm platform move, no 150 mm jump
    assert abs(float(rows[2][col]) - float(rows[1][col])) < 10.0


def test_a_very_long_joint_name_folds_and_keeps_the_numbers(tmp_path, capsys):
    """Regression (adversarial probe): a joint name of ~100 characters pushed min, max, end
    … out of the summary's joints table."""
    name = "s" + "x" * 110
    program = tmp_path / "ln.irl"
    program.write_text(
        f"PROGRAM ln;\nROBOT r := planar3;\nTYPE RECORD REAL: {name}, b2, c3; ENDRECORD = "
        "MAIN_JOINT;\nBEGIN\n  MOVE PTP (10, 80, -80);\nENDPROGRAM\n",
        encoding="utf-8",
    )
    assert main(["run", str(program)]) == 0
    out = capsys.readouterr().out
    rows = [line for line in out.splitlines() if line.count("│") >= 7 and "0.00" in line]
    first = next(line for line in rows if name[:30] in line)  # the name's first piece
    cells = [c.strip() for c in first.split("│")]
    assert cells[2:5] == ["0.00", "10.00", "10.00"]  # min, max, end of a1: 0 → 10 deg
    assert "".join(line.split("│")[1].strip() for line in out.splitlines()
                   if line.count("│") >= 7).count(name) == 1  # fmt: skip
