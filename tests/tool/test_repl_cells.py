"""The REPL with a cell of several robots: ROBOT entries, --robot NAME=ROBOT@AT, :robot NAME,
:where NAME, cooperation across entries, :trace/:plot/:program of the cell.

Poses are checked against the robot's own forward kinematics composed with its AT placement
(computed here with scipy's rotations, not with irlc's pose conversion), final joints against
``irlc run`` of the program ``:program`` prints."""

from __future__ import annotations

import json
import re
import subprocess
import sys

import numpy as np
import pytest
from irlc.repl import Session, block_depth, is_complete
from scipy.spatial.transform import Rotation

IRLC = [sys.executable, "-c", "from irlc.cli import entry; entry()"]
B_AT = (0.0, -1550.0, 0.0, 180.0, 0.0, 0.0)
NUMBER = r"-?\d+(?:\.\d+)?"


def _matrix(x, y, z, a, b, c) -> np.ndarray:
    """mm, deg ZYX (a about z, then b about y, then c about x) as a 4×4 in m."""
    t = np.eye(4)
    t[:3, :3] = Rotation.from_euler("ZYX", [a, b, c], degrees=True).as_matrix()
    t[:3, 3] = np.array([x, y, z]) / 1000.0
    return t


def _pose_of(line: str) -> np.ndarray:
    m = re.search(r"pose \(([^)]*)\)", line)
    assert m is not None, line
    return _matrix(*(float(v) for v in m.group(1).split(",")))


def _joints_of(line: str) -> list[float]:
    return [float(v) for v in re.findall(rf"a\d+=({NUMBER})", line)]


def _first(entry) -> str:
    """The first line of an entry's output (a diagnostic: its header)."""
    return entry.lines[0].splitlines()[0]


def _cell(tmp_path) -> Session:
    s = Session("as6", cwd=tmp_path)
    added = s.enter(f"ROBOT b := as6 AT ({', '.join(f'{v:g}' for v in B_AT)});", 1)
    assert added.failure == 0, added.lines
    return s


def test_the_for_suffix_of_a_cell_is_not_a_loop():
    assert is_complete("JOINTLIMIT lo, hi FOR holder;")
    assert is_complete("CYCLICSTART FOR welder")
    assert block_depth("FOR i := 1 TO 3 DO") == 1
    assert not is_complete("FOR i := 1 TO 3 DO\n  JOINTLIMIT lo, hi FOR holder;")


def test_where_shows_each_robots_fk_composed_with_its_placement(tmp_path):
    from irlc.robots import load_robot
    from irlc.runtime.model.kinematics import Kinematics

    s = _cell(tmp_path)
    j = (10.0, 20.0, 30.0, 40.0, 50.0, 60.0)
    moved = s.enter(f"MOVE b PTP ({', '.join(f'{v:g}' for v in j)});", 2)
    assert moved.failure == 0, moved.lines
    assert moved.lines[0].startswith("→ t = ") and moved.lines[1].startswith("  b: pose (")
    where = s.enter(":where b", 3).lines
    assert re.match(r"t = \d+\.\d{3} s  b: pose \(", where[0]) and "cell frame" in where[0]
    assert _joints_of(where[1]) == pytest.approx(j, abs=1e-3)
    # the robot's own FK (its file's base and tool, no placement), then AT before it
    own = Kinematics(load_robot("as6")).tcp(np.radians(j))
    expected = _matrix(*B_AT) @ own
    shown = _pose_of(where[0])
    assert np.abs(shown[:3, 3] - expected[:3, 3]).max() < 2e-6  # m: 3 decimals of mm
    assert np.abs(shown[:3, :3] - expected[:3, :3]).max() < 1e-4
    # robot r did not move: its home, unplaced
    every = s.enter(":where", 4).lines
    assert [line.split(":")[0].strip() for line in every[1::2]] == ["r", "b"]
    home = Kinematics(load_robot("as6")).tcp(load_robot("as6").home_q())
    assert np.abs(_pose_of(every[1])[:3, 3] - home[:3, 3]).max() < 2e-6
    # R_ACT_POSE of b reads the same pose (the frame MOVE b's poses are in)
    act = s.enter("WRITELN(b.R_ACT_POSE);", 5).lines[0]
    values = [float(v) for v in re.findall(NUMBER, act)]
    assert np.abs(_matrix(*values)[:3, 3] - expected[:3, 3]).max() < 2e-6


def test_robot_selects_the_robot_that_limits_options_and_teach_show(tmp_path):
    s = _cell(tmp_path)
    listing = s.enter(":robot", 2).lines
    assert listing[0].startswith("robot as6: 6 joints")
    assert "cell of 2 robots" in listing[-3]
    assert listing[-2].split()[:2] == ["r", "as6"] and listing[-1].split()[:3] == ["*", "b", "as6"]
    assert s.enter(":robot r", 3).lines[0] == "current robot: r"
    assert s.enter("JOINTLIMIT (0, -80, -80, -80, 10, -80), (300, 80, 80, 80, 300, 80) FOR b;", 4)
    assert s.enter(":limits", 5).lines[0] == "robot r (as6):"
    assert all(line.rstrip().endswith("-  [deg]") for line in s.enter(":limits", 5).lines[2:])
    limited = s.enter(":limits b", 6).lines
    assert limited[0] == "robot b (as6):" and "0..300  [deg]" in limited[2]
    assert s.enter(":options", 7).lines[1] == "no modal options active"
    assert s.enter(":options b", 8).lines[1].startswith("JOINTLIMIT min (0, -80")
    s.enter(":robot b", 9)
    taught = s.enter(":teach spot", 10)
    assert taught.failure == 0, taught.lines
    assert "MOVE b LIN spot;" in taught.lines[1] and "MOVE b PTP spot_joints;" in taught.lines[1]
    text = (tmp_path / "taught.toml").read_text()
    assert "spot_joints = [90, 30, 0, 30, 90, 0]" in text


def test_mistakes_are_positioned_and_list_the_robots(tmp_path):
    s = _cell(tmp_path)
    no_name = s.enter("MOVE PTP (0, 0, 0, 0, 0, 0);", 7)
    assert no_name.failure == 1
    assert _first(no_name) == "<stdin>:7:1: error: MOVE PTP in a cell names its robot (r, b)"
    unknown = s.enter("MOVE c PTP (0, 0, 0, 0, 0, 0);", 8)
    assert _first(unknown) == "<stdin>:8:6: error: unknown robot 'c'"
    assert "hint: robots of this program: r, b" in unknown.lines[-1]
    for entry, line in ((":robot c", 9), (":where c", 10), (":limits c", 11)):
        out = s.enter(entry, line)
        assert out.failure == 1
        assert out.lines == [
            f"<stdin>:{line}:1: error: unknown robot 'c'; the session's robots: r, b"
        ]
    twice = s.enter("ROBOT b := panda;", 12)
    assert twice.failure == 1
    assert _first(twice) == "<stdin>:12:7: error: 'b' is already defined (earlier in the session)"
    same = s.enter("VAR REAL: y,\n  y;", 14)  # a line the user typed: as they count it
    assert _first(same) == "<stdin>:15:3: error: 'y' is already defined (line 14)"
    bad_at = s.enter("ROBOT c := as6 AT 5;", 13)
    assert _first(bad_at) == "<stdin>:13:19: error: AT of robot c: expected POSE, got INTEGER"
    assert s.robot_names() == ["r", "b"]  # refused entries leave the cell as it was


def test_a_robot_after_statements_that_name_no_robot_is_refused(tmp_path):
    s = Session("as6", cwd=tmp_path)
    assert s.enter("MOVE PTP (80, 30, 0, 30, 90, 0);", 1).failure == 0
    refused = s.enter("ROBOT b := as6 AT (0, -1550, 0, 180, 0, 0);", 2)
    assert refused.failure == 1
    assert refused.lines[0].startswith("<stdin>:2:1: error: with this robot the statements")
    assert "MOVE PTP in a cell names its robot (r, b)" in refused.lines[0]
    assert s.cell is None and s.enter(":reset", 3).failure == 0
    assert s.enter("ROBOT b := as6 AT (0, -1550, 0, 180, 0, 0);", 4).failure == 0
    default = Session(cwd=tmp_path)  # the default robot: replaced by the first ROBOT
    first = default.enter("ROBOT a := as6;", 1)
    assert first.lines == ["robot a: as6, the session's robot (in place of the default koch11)"]
    assert default.cell is None and default.model.name == "as6"


def test_cooperation_spans_entries_and_a_robot_waits_for_its_end(tmp_path):
    s = Session("as6", cwd=tmp_path)
    assert s.enter("ROBOT b := as6 AT (0, -2200, 0, 180, 0, 0);", 1).failure == 0
    script = [
        "MOVE r PTP (90, 45, 0, 45, 90, 0) AND b PTP (90, 45, 0, 45, 90, 0);",
        "POSE: grip := INV(r.R_ACT_POSE) : b.R_ACT_POSE;",
        "COOPERATE b IN r;",
    ]
    for k, entry in enumerate(script, 2):
        assert s.enter(entry, k).failure == 0, (entry, s.enter(":where", 99).lines)
    assert "r's tool frame" in s.enter(":where b", 5).lines[0]
    refused = s.enter("ROBOT c := as6 AT (3000, 0, 0, 0, 0, 0);", 6)
    assert refused.lines == [
        "<stdin>:6:1: error: COOPERATE b IN r is open: end it (COOPERATEEND;) first"
    ]
    seam = s.enter("MOVE b LIN grip : (-100, 0, 0, 0, 0, 0) WITH SPEED := 50;", 7)
    assert seam.failure == 0, seam.lines
    assert [line.split(":")[0].strip() for line in seam.lines[1::2]] == ["r", "b"]  # both moved
    assert s.enter("COOPERATEEND;", 8).failure == 0
    assert "cell frame" in s.enter(":where b", 9).lines[0]
    again = s.enter("COOPERATEEND;", 10)  # none open: the compiler says so
    assert _first(again).startswith("<stdin>:10:1: error: COOPERATEEND without an earlier")


SESSION = """\
ROBOT holder := as6;
ROBOT welder := as6 AT (0, -2200, 0, 180, 0, 0);
CONST MAIN_JOINT: h_start = (90, 45, 0, 45, 90, 0);
CONST MAIN_JOINT: w_start = (90, 45, 0, 45, 90, 0);
POSE: grip, seam_end;
MOVE holder PTP h_start AND welder PTP w_start;
grip := INV(FK(holder, h_start)) : FK(welder, w_start);
seam_end := grip : (200, 0, 0, 0, 0, 30);
JOINTLIMIT (0, -90, -90, -90, 60, -90), (330, 90, 90, 90, 100, 90) FOR holder;
COOPERATE welder IN holder;
  MOVE welder LIN seam_end WITH SPEED := 50;
COOPERATEEND;
JOINTLIMITEND FOR holder;
R_CLEARANCE := 20;
MOVE welder PTP w_start WITH SPEED_PTP := 20;
:where
:trace cell.csv
:plot figures
:program
"""


@pytest.mark.scenario
def test_a_scripted_cell_session_is_reproduced_by_its_program(tmp_path):
    res = subprocess.run([*IRLC, "repl"], input=SESSION, capture_output=True, text=True,
                         timeout=300, cwd=tmp_path)  # fmt: skip
    assert res.returncode == 0, res.stdout + res.stderr
    out = res.stdout.splitlines()
    where = out.index(next(line for line in out if re.match(r"t = \d", line)))
    shown = {out[k].split(":")[0].strip(): _joints_of(out[k + 1]) for k in (where + 1, where + 3)}
    # the trace: every robot's columns prefixed by its name, and the clearance
    header = (tmp_path / "cell.csv").read_text().splitlines()[0].split(",")
    assert {"holder_a1_deg", "welder_a6_deg", "welder_x_mm", "clearance_mm"} <= set(header)
    last = (tmp_path / "cell.csv").read_text().splitlines()[-1].split(",")
    for robot, joints in shown.items():
        traced = [float(last[header.index(f"{robot}_a{i}_deg")]) for i in range(1, 7)]
        assert traced == pytest.approx(joints, abs=1e-3)
    figures = {p.name for p in (tmp_path / "figures").iterdir()}
    assert {"tcp_path_3d.png", "clearance.png", "holder_joint_positions_1-6.png"} <= figures
    program = "\n".join(out[out.index("PROGRAM repl;") :]) + "\n"
    assert "ROBOT welder := as6 AT (0, -2200, 0, 180, 0, 0);" in program
    (tmp_path / "session.irl").write_text(program)
    run = subprocess.run([*IRLC, "run", "session.irl", "-q", "--report", "r.json"],
                         capture_output=True, text=True, timeout=300, cwd=tmp_path)  # fmt: skip
    assert run.returncode == 0, run.stdout + run.stderr
    report = json.loads((tmp_path / "r.json").read_text())
    for entry in report["robots"]:
        assert entry["end_joints"] == pytest.approx(shown[entry["name"]], abs=2e-3)


def test_robot_option_names_and_places_the_robots(tmp_path):
    res = subprocess.run(
        [*IRLC, "repl", "--robot", "a=as6", "--robot", "b=as6@0,-1550,0,180,0,0"],
        input=":where\n:robot\n", capture_output=True, text=True, timeout=120, cwd=tmp_path,
    )  # fmt: skip
    assert res.returncode == 0, res.stderr
    lines = res.stdout.splitlines()
    assert lines[0] == "t = 0.000 s" and lines[1].startswith("  a: pose (0, -751.666, 1458.423")
    assert lines[3].startswith("  b: pose (0, -798.334, 1458.423, 0, 0, -60)")
    assert " * a            as6          AT (0, 0, 0, 0, 0, 0)  [mm, deg ZYX]" in lines  # the first
    assert "   b            as6          AT (0, -1550, 0, 180, 0, 0)  [mm, deg ZYX]" in lines
    for args, message in (
        (["--robot", "b=as6@1,2,3"], "the placement after @ is x,y,z,a,b,c"),
        # (was "'a' is already defined (line 2)": a line of a program the user never wrote)
        (
            ["--robot", "a=as6", "--robot", "A=panda"],
            "--robot A=panda: the name A is already given by --robot a=as6",
        ),
        (
            ["--robot", "as6", "--robot", "r=panda"],
            "--robot r=panda: the name r is already given by --robot as6",
        ),
    ):
        bad = subprocess.run([*IRLC, "repl", *args], input="", capture_output=True, text=True,
                             timeout=120, cwd=tmp_path)  # fmt: skip
        assert bad.returncode == 3 and message in bad.stderr and "Traceback" not in bad.stderr
        assert "(line " not in bad.stderr


def test_reset_puts_every_robot_home_and_keeps_the_cell(tmp_path):
    s = _cell(tmp_path)
    assert s.enter("MOVE r PTP (80, 30, 0, 30, 90, 0) AND b PTP (0, 30, 0, 30, 90, 0);", 2)
    assert s.enter(":reset", 3).lines == ["reset: r, b at home, no declarations"]
    every = s.enter(":where", 4).lines
    assert every[0] == "t = 0.000 s"
    assert _joints_of(every[2]) == _joints_of(every[4]) == [90, 30, 0, 30, 90, 0]
    assert s.enter(":program", 5).lines[1:4] == [
        "ROBOT r := as6;",
        "ROBOT b := as6 AT (0, -1550, 0, 180, 0, 0);",
        "BEGIN",
    ]


def test_robots_inside_each_other_may_be_jogged_apart_not_deeper(tmp_path):
    """After a collision between the robots failed an entry, the next entry may move them
    apart (as after a collision stop) but not deeper; once apart the rule is whole again."""
    s = Session("as6", cwd=tmp_path)
    assert s.enter("ROBOT b := as6 AT (0, -1500, 0, 180, 0, 0);", 1).failure == 0
    hit = s.enter("MOVE r PTP (90, 45, 0, 45, 90, 0) AND b PTP (90, 45, 0, 45, 90, 0);", 2)
    assert hit.failure == 2 and "r link 6 and b link 6 collide" in _first(hit), hit.lines
    depth = float(re.search(r"they are ([\d.]+) mm inside", _first(hit)).group(1))
    deeper = s.enter("MOVE r PTP (90, 60, 0, 45, 90, 0);", 3)
    assert deeper.failure == 2, deeper.lines
    assert float(re.search(r"they are ([\d.]+) mm inside", _first(deeper)).group(1)) > depth
    assert s.enter("MOVE r PTP (90, 20, 0, 45, 90, 0);", 4).failure == 0  # backs out
    again = s.enter("MOVE r PTP (90, 30, 0, 30, 90, 0);", 5)  # into b again
    assert again.failure == 2 and "collide" in _first(again), again.lines


def test_robots_closer_than_r_clearance_may_be_jogged_apart_not_closer(tmp_path):
    s = Session("as6", cwd=tmp_path)
    assert s.enter("ROBOT b := as6 AT (0, -1700, 0, 180, 0, 0);", 1).failure == 0
    assert s.enter("R_CLEARANCE := 150;", 2).failure == 0
    close = s.enter("MOVE r PTP (90, 45, 0, 45, 90, 0);", 3)  # a PTP is not steered
    assert close.failure == 2 and "closer than R_CLEARANCE 150 mm" in _first(close), close.lines
    assert s.enter("MOVE r PTP (90, 50, 0, 45, 90, 0);", 4).failure == 2  # closer still
    assert s.enter("MOVE r PTP (90, 0, 0, 45, 90, 0);", 5).failure == 0  # apart


def test_robots_placed_inside_each_other_are_warned_of():
    """Two robots on one base: a program stops at its first statement; the session says
    so when the robots are listed and, piped, when it starts."""
    done = subprocess.run(
        [*IRLC, "repl", "--robot", "as6", "--robot", "b=as6@0,0,0,0,0,0"],
        input=":robot\n", capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    warning = "warning: r link 1 and b link 1 collide: they are 240 mm inside each other"
    assert done.stdout.startswith(warning), done.stdout[:300]
    assert done.stdout.count(warning) == 2  # at the start, and under :robot's listing
    apart = subprocess.run(
        [*IRLC, "repl", "--robot", "as6", "--robot", "b=as6@0,-2200,0,180,0,0"],
        input=":robot\n", capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert "warning" not in apart.stdout
