"""Cells of several robots at run time (issue 26), checked against independent computations:
the robots' own forward kinematics of the trace's joints (not the solver's numbers), the
programmed lines, the group moves' common start and end, closed-form and sampled distances,
and positioned errors for bad input."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from irlc.lang import compile_source
from irlc.robots import load_robot
from irlc.runtime import values
from irlc.runtime.model import spatial
from irlc.runtime.model.clearance import PartSet, RobotParts
from irlc.runtime.model.distance import closest_segment_segment
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.run import run_code, run_file

PROGRAMS = Path(__file__).resolve().parents[2] / "programs"


def _run(text: str, name: str = "cell.irl", **options):
    result = compile_source(text, name, resolve_robot=load_robot)
    assert result.ok, [d.header() for d in result.diagnostics]
    return run_code(result.code, **options)


def _pose(*xyzabc) -> np.ndarray:
    return values.pose_to_matrix(values.pose_from_zyx(*xyzabc))


def _kin(run, name: str, tool: np.ndarray | None = None) -> Kinematics:
    """The robot's own kinematics in the cell (its placed model), not the solver's chain."""
    return Kinematics(run.robots[name].model, tool)


def _line_of(path: Path, text: str) -> int:
    lines = path.read_text(encoding="utf-8").splitlines()
    return next(i + 1 for i, line in enumerate(lines) if text in line)


def _on_segment(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, float]:
    """Each point's parameter along ``a → b`` and the largest distance off the line (m)."""
    u = b - a
    s = (points - a) @ u / (u @ u)
    off = np.linalg.norm(points - (a + s[:, None] * u), axis=1)
    return s, float(off.max())


# --------------------------------------------------------------------------- cooperation


@pytest.fixture(scope="module")
def cooperating():
    return run_file(PROGRAMS / "cooperating.irl")


def _seam(run):
    """seam_start, seam_end in the holder's tool frame, from the start joints' own FK."""
    h = _kin(run, "holder").tcp(np.radians([90, 45, 0, 45, 90, 0]))
    w = _kin(run, "welder").tcp(np.radians([90, 45, 0, 45, 90, 0]))
    grip = spatial.inverse(h) @ w
    return grip @ _pose(-300, 0, 0, 0, 0, 0), grip @ _pose(300, 0, 0, 45, 0, 45)


@pytest.mark.scenario
def test_the_welder_follows_the_seam_on_the_workpiece(cooperating):
    """The welder's tool in the holder's tool frame, from the two robots' own forward
    kinematics of the recorded joints, lies on the programmed seam (position on the line,
    orientation the slerp between the end poses), and reaches both ends."""
    run = cooperating
    assert run.ok, run.error
    holder, welder = run.robots["holder"], run.robots["welder"]
    kh, kw = _kin(run, "holder"), _kin(run, "welder")
    start, end = _seam(run)
    line = _line_of(PROGRAMS / "cooperating.irl", "MOVE welder LIN seam_end")
    rows = np.flatnonzero(holder.recorded.lines == line)
    assert rows.size > 1000
    rel = np.array([spatial.inverse(kh.tcp(holder.q[k])) @ kw.tcp(welder.q[k]) for k in rows])
    s, off = _on_segment(rel[:, :3, 3], start[:3, 3], end[:3, 3])
    assert off < 1e-7  # on the line (0.1 µm)
    assert np.all(np.diff(s) >= -1e-12) and s[0] < 0.01 and s[-1] == pytest.approx(1.0, abs=1e-9)
    turn = start[:3, :3].T @ end[:3, :3]
    angle = np.arccos((np.trace(turn) - 1) / 2)
    for k, r in zip(s[::50], rel[::50], strict=True):  # the orientation: slerp by the same s
        own = start[:3, :3].T @ r[:3, :3]
        got = np.arccos(np.clip((np.trace(own) - 1) / 2, -1, 1))
        assert got == pytest.approx(min(1.0, max(0.0, k)) * angle, abs=1e-6)
    assert np.allclose(rel[-1], end, atol=1e-7)
    # both robots' samples on one clock; the report names the statements of both
    assert np.array_equal(holder.times, welder.times)
    assert run.report["robots"][1]["max_path_error_mm"] < 1e-3


@pytest.mark.scenario
def test_the_joint_limit_sets_keep_holder_j5_and_welder_j4_inside(cooperating):
    """Fig. 3.4b/3.5: with the JOINTLIMIT sets holder J5 ≤ 100° and welder J4 ≥ 20° along
    the seam; the same program without them takes holder J5 above 100° and welder J4 below
    20° (the joints the book names)."""
    source = (PROGRAMS / "cooperating.irl").read_text(encoding="utf-8")
    first = _line_of(PROGRAMS / "cooperating.irl", "COOPERATE welder IN holder")

    def seam_joints(run):
        lines = run.robots["holder"].recorded.lines
        at = lines >= first
        return (
            np.degrees(run.robots["holder"].q[at, 4]),
            np.degrees(run.robots["welder"].q[at, 3]),
        )

    h5, w4 = seam_joints(cooperating)
    assert h5.max() <= 100 + 1e-6 and w4.min() >= 20 - 1e-6
    assert h5.max() > 99.9 and w4.min() < 20.1  # at the bounds: the limits bind
    free_text = "\n".join(
        line if not re.match(r"\s*JOINTLIMIT", line) else "" for line in source.splitlines()
    )
    free = _run(free_text, "cooperating.irl")
    assert free.ok, free.error
    h5, w4 = seam_joints(free)
    assert h5.max() > 105 and w4.min() < 10


@pytest.mark.scenario
def test_vertical_and_master_slave_and_a_third_robot():
    """WITH VERTICAL keeps the welder's tool z axis vertical (own FK); a holder motion inside
    COOPERATE carries the welder, its tool fixed in the holder's tool frame; a third robot
    moves as usual, and every robot is sampled on one clock (blends included)."""
    run = _run(VERTICAL)
    assert run.ok, run.error
    holder, welder = run.robots["holder"], run.robots["welder"]
    kh, kw = _kin(run, "holder"), _kin(run, "welder")
    for name in ("welder", "third"):  # one clock: the same times and lines (blends too)
        assert np.array_equal(run.robots[name].times, holder.times)
        assert np.array_equal(run.robots[name].recorded.lines, holder.recorded.lines)
    inside = (holder.recorded.lines >= 15) & (holder.recorded.lines <= 22)
    z = np.array([kw.tcp(q)[:3, 2] for q in welder.q[inside]])
    assert np.abs(z[:, :2]).max() < 1e-8  # vertical
    carry = np.flatnonzero(holder.recorded.lines == 19)  # MOVE holder LIN p
    rel = [spatial.inverse(kh.tcp(holder.q[k])) @ kw.tcp(welder.q[k]) for k in carry]
    assert np.abs(np.array(rel) - rel[0]).max() < 1e-7  # fixed on the workpiece
    assert (
        np.linalg.norm(kh.tcp(holder.q[carry[-1]])[:3, 3] - kh.tcp(holder.q[carry[0]])[:3, 3])
        > 0.049
    )
    third = run.robots["third"]
    moved = np.flatnonzero(holder.recorded.lines == 20)
    assert np.degrees(third.q[moved[-1], 1]) == pytest.approx(-30.0, abs=1e-9)
    still = holder.recorded.lines != 20
    assert np.allclose(third.q[still & (holder.times > third.times[moved[-1]])], third.q[moved[-1]])
    assert run.output == [run.output[0]] and len(run.output[0].split()) == 3


VERTICAL = """PROGRAM vert;
ROBOT holder := as6;
ROBOT welder := as6 AT (0, -2200, 0, 180, 0, 0);
ROBOT third := panda AT (1500, -1100, 0, 180, 0, 0);
CONST
  MAIN_JOINT: h_start = (90, 40, -30, 50, 60, 20);
  MAIN_JOINT: w_v = (110.369, 50.074, -8.502, 66.869, 7.274, 63.554);
VAR
  POSE: grip, a, p;
BEGIN
  MOVE holder PTP h_start AND welder PTP w_v;
  grip := INV(holder.R_ACT_POSE) : welder.R_ACT_POSE;
  a := grip : (-100, 50, 0, 0, 0, 0);
  COOPERATE welder IN holder WITH VERTICAL;
    MOVE welder LIN a WITH SPEED := 50;
    p := welder.R_ACT_POSE;
    WRITELN(p.x, ' ', p.y, ' ', p.z);
    p := holder.R_ACT_POSE : (0, 0, -50, 0, 0, 0);
    MOVE holder LIN p WITH SPEED := 20;
    MOVE third PTP (0, -30, 0, -120, 0, 90, 45);
    RECONFIGURATION (85, 45, 0, 45, 90, 0) FOR holder;
    WAIT 0.2 SEC;
  COOPERATEEND;
  p := welder.R_ACT_POSE;
  MOVE welder LIN p : (0, 0, -40, 0, 0, 0) WITH SPEED := 50 WITH APPROX := 20;
  MOVE welder LIN p : (40, 0, -40, 0, 0, 0) WITH SPEED := 50 WITH APPROX := 20;
  MOVE welder LIN p WITH SPEED := 50;
ENDPROGRAM
"""


def test_vertical_is_checked_when_switched_on():
    text = VERTICAL.replace("w_v = (110.369, 50.074, -8.502, 66.869, 7.274, 63.554)",
                            "w_v = (90, 45, 0, 45, 90, 0)")  # fmt: skip
    run = _run(text.split("    MOVE welder LIN a")[0] + "  COOPERATEEND;\nENDPROGRAM\n")
    assert run.status == "failed" and run.error.line == 14
    assert "WITH VERTICAL: its tool z axis is 90 deg from vertical" in run.error.message


# --------------------------------------------------------------------------- group moves


@pytest.fixture(scope="module")
def two_robots():
    return run_file(PROGRAMS / "two_robots.irl")


@pytest.mark.scenario
def test_group_moves_start_together_and_end_together(two_robots):
    run = two_robots
    assert run.ok, run.error
    rows = [r for r in run.report["statements"] if len(r["robots"]) > 1]
    assert len(rows) == 2
    for row in rows:
        parts = row["robots"]
        slowest = max(parts.values(), key=lambda p: p["duration_s"])
        assert slowest["set_the_time"] and sum(p["set_the_time"] for p in parts.values()) == 1
        assert row["duration_s"] == pytest.approx(slowest["duration_s"], abs=1e-9)
        at = np.flatnonzero(run.robots["floor"].recorded.lines == row["line"])
        first_last = []
        for robot in run.robots.values():
            moving = np.flatnonzero(
                np.abs(np.diff(robot.q[at[0] - 1 : at[-1] + 1], axis=0)).max(axis=1) > 1e-12
            )
            first_last.append((moving[0], moving[-1]))
        assert len(set(first_last)) == 1  # the same first and last cycle of motion
        assert run.robots["floor"].times[at[-1]] - run.robots["floor"].times[
            at[0] - 1
        ] == pytest.approx(row["duration_s"], abs=1e-9)


def _least_between(run, a: str, b: str, rows) -> float:
    """The least distance between two robots' parts at the given samples, by the scalar
    segment routine over every pair (independent of the cell's batched query)."""
    pa, pb = RobotParts(a, _kin(run, a)), RobotParts(b, _kin(run, b))
    out = np.inf
    for k in rows:
        ea = pa.world(pa.kin.link_frames(run.robots[a].q[k]))
        eb = pb.world(pb.kin.link_frames(run.robots[b].q[k]))
        for i in range(pa.size):
            for j in range(pb.size):
                _, _, p, q = closest_segment_segment(ea[0][i], ea[1][i], eb[0][j], eb[1][j])
                out = min(out, np.linalg.norm(p - q) - pa.radius[i] - pb.radius[j])
    return float(out)


@pytest.mark.scenario
def test_the_clearance_binds_and_keeps_50_mm(two_robots):
    """two_robots.irl keeps 50 mm between the robots (R_CLEARANCE): the Panda's elbow swings
    away from the AS arm, its tool on its lines; without R_CLEARANCE they come to 32 mm."""
    run = two_robots
    line = _line_of(PROGRAMS / "two_robots.irl", "MOVE floor LIN f_b WITH SPEED := 100;")
    rows = np.flatnonzero(run.robots["floor"].recorded.lines == line)
    kept = _least_between(run, "ceiling", "floor", rows[::4])
    assert 50.0e-3 <= kept < 52.0e-3
    pair = run.report["clearance"]["pairs"][1]
    assert (pair["robot_a"], pair["robot_b"]) == ("ceiling", "floor")
    assert pair["min_distance_mm"] == pytest.approx(kept * 1e3, abs=0.2)
    assert run.report["max_path_error_mm"] < 1e-3
    free = _run((PROGRAMS / "two_robots.irl").read_text(encoding="utf-8").replace(
        "R_CLEARANCE := 50;", "R_CLEARANCE := 0;"), "two_robots.irl")  # fmt: skip
    assert free.ok
    assert _least_between(free, "ceiling", "floor", rows[::4]) < 35e-3


def test_the_trace_columns_of_a_cell(two_robots):
    cols = two_robots.trace_columns
    assert cols[:2] == ["t_s", "line"]
    assert cols[2:8] == [f"ceiling_a{i}_deg" for i in range(1, 7)]
    assert "floor_a7_deg" in cols and "floor_x_mm" in cols and "ceiling_path_error_mm" in cols
    assert cols[-5:] == ["clearance_mm", "clearance_robot_a", "clearance_link_a",
                         "clearance_robot_b", "clearance_link_b"]  # fmt: skip
    table = two_robots.trace
    assert table.shape == (two_robots.report["samples"], len(cols))
    k = int(np.argmin(table[:, cols.index("clearance_mm")]))
    assert table[k, cols.index("clearance_mm")] == pytest.approx(
        two_robots.report["clearance"]["min_distance_mm"], abs=1e-6
    )
    q = table[:, [cols.index(f"floor_a{i}_deg") for i in range(1, 8)]]
    assert np.allclose(np.radians(q), two_robots.robots["floor"].q)
    x = table[:, cols.index("floor_x_mm")] / 1000
    tcp = np.array([_kin(two_robots, "floor").tcp(v)[0, 3] for v in two_robots.robots["floor"].q])
    assert np.allclose(x, tcp, atol=1e-9)


# --------------------------------------------------------------------------- clearance


def test_clearance_in_closed_form_and_a_collision_at_the_start():
    """Two straight AS arms (all joints 0) 1 m apart: their first links' capsules (radius
    0.12 m) are 0.76 m apart; 0.2 m apart they are inside each other: the first statement
    fails at t = 0 naming both robots and links."""
    text = """PROGRAM c;
ROBOT a := as6;
ROBOT b := as6 AT (1000, 0, 0, 0, 0, 0);
BEGIN
  WAIT 0.05 SEC;
ENDPROGRAM
"""
    run = _run(text, seed_config=[0.0] * 12)
    assert run.ok
    col = run.trace[:, run.trace_columns.index("clearance_mm")]
    pair = run.trace[:, -4:]
    between = run.report["clearance"]["pairs"][1]
    assert between["min_distance_mm"] == pytest.approx(760.0, abs=1e-6)
    assert (between["link_a"], between["link_b"]) == (1, 1)
    assert np.all(col <= 760.0 + 1e-9) and np.all(pair[:, [0, 2]] >= 0)
    near = _run(text.replace("AT (1000,", "AT (200,"), seed_config=[0.0] * 12)
    assert near.status == "failed" and near.error.cause == "clearance"
    assert near.error.line == 5 and near.error.time_s == 0.0
    assert near.error.message.startswith("a link 1 and b link 1 collide: they are 40 mm inside")
    assert near.error.details["robot_a"] == "a" and near.error.details["link_b"] == 1


def test_a_ptp_that_comes_closer_than_r_clearance_fails_naming_both():
    text = """PROGRAM c;
ROBOT a := as6;
ROBOT b := as6 AT (1100, 0, 0, 0, 0, 0);
BEGIN
  R_CLEARANCE := 100;
  MOVE a PTP (0, -60, 0, 0, 0, 0);
ENDPROGRAM
"""
    run = _run(text, seed_config=[0.0] * 12)
    assert run.status == "failed" and run.error.cause == "clearance" and run.error.line == 6
    assert "closer than R_CLEARANCE 100 mm" in run.error.message
    assert run.error.details["required_mm"] == 100.0
    d = run.trace[:, run.trace_columns.index("clearance_mm")]
    assert d[-2] >= 100.0 - 0.1 > d[-1]  # the failing sample is the trace's last


# --------------------------------------------------------------------------- bad input, API


def test_a_joint_tuple_of_the_wrong_length_for_its_robot_fails_at_its_line(tmp_path, capsys):
    from irlc.cli import main

    program = tmp_path / "bad.irl"
    program.write_text("""PROGRAM bad;
ROBOT arm := as6;
ROBOT hand := panda AT (0, -1500, 0, 90, 0, 0);
VAR MAIN_JOINT: k;
BEGIN
  k := (90, 30, 0, 30, 90, 0);
  MOVE arm PTP k;
  MOVE hand PTP k;
ENDPROGRAM
""", encoding="utf-8")  # fmt: skip
    assert main([str(program), "-q"]) == 2
    err = capsys.readouterr().err
    where = f"{program}:8:3: error: run-time failure at t = 0.000 s: "
    assert where + "MOVE PTP target for robot hand needs 7 values, got a MAIN_JOINT of 6" in err


def test_a_single_robot_placed_by_at_is_in_the_cell_frame():
    text = """PROGRAM p;
ROBOT r := planar3 AT (100, 200, 0, 90, 0, 0);
BEGIN
  MOVE PTP (10, 20, 30);
ENDPROGRAM
"""
    placed, plain = _run(text), _run(text.replace(" AT (100, 200, 0, 90, 0, 0)", ""))
    assert placed.ok and plain.ok and not placed.is_cell
    assert np.allclose(placed.q, plain.q)
    at = _pose(100, 200, 0, 90, 0, 0)
    assert np.allclose(placed.tcp, at @ plain.tcp, atol=1e-12)
    assert np.allclose(placed.robots["r"].at, at)


def test_the_python_api_gives_each_robot(two_robots):
    run = two_robots
    assert run.is_cell and list(run.robots) == ["ceiling", "floor"]
    floor = run.robots["floor"]
    assert floor.q.shape == (run.report["samples"], 7) and floor.tcp.shape[1:] == (4, 4)
    assert floor.joint_names == tuple(f"a{i}" for i in range(1, 8))
    assert floor.report["name"] == "floor" and floor.report["robot"] == "panda"
    assert floor.trace_columns[0] == "floor_a1_deg"
    assert run.q.shape == (run.report["samples"], 13) and run.tcp is None
    assert run.joint_names[0] == "ceiling_a1" and run.joint_names[-1] == "floor_a7"
    assert np.allclose(run.q[:, 6:], floor.q)


@pytest.mark.scenario
def test_every_robot_s_drives(cooperating):
    run = run_file(PROGRAMS / "cooperating.irl", drives="decoupled")
    assert run.ok, run.error
    for entry in run.report["robots"]:
        axes = entry["drives_summary"]["axes"]
        assert len(axes) == 6 and entry["drives_summary"]["could_follow"]
    assert run.robots["holder"].drive is not None
    assert np.array_equal(run.robots["holder"].times, run.robots["welder"].times)
    assert run.report["max_path_error_mm"] > 0.0  # the actual motion lags the set points


def test_cell_part_set_matches_the_run(two_robots):
    """The cell watches what PartSet says: its own pairs and all pairs between robots."""
    run = two_robots
    parts = PartSet([RobotParts(n, _kin(run, n)) for n in ("ceiling", "floor")])
    assert [tuple(g) for g in parts.groups] == [(0, 0), (0, 1), (1, 1)]
    assert len(run.report["clearance"]["pairs"]) == 3


def test_a_holder_tool_changed_inside_cooperate_moves_the_workpiece_frame():
    """After ``holder.R_TOOL := …`` inside the block the welder's poses are in the holder's
    new tool frame: its LIN ends there (own FK of both robots, the new tool)."""
    text = (PROGRAMS / "cooperating.irl").read_text(encoding="utf-8")
    seam = "    MOVE welder LIN seam_start WITH SPEED := 50;\n    MOVE welder LIN seam_end"
    text = text.replace(
        seam + " WITH SPEED := 50;\n",
        "    holder.R_TOOL := (0, 0, 80, 0, 0, 0);\n    seam_start := welder.R_ACT_POSE;\n"
        "    MOVE welder LIN seam_start : (50, 20, 0, 0, 0, 10) WITH SPEED := 50;\n",
    )  # fmt: skip
    run = _run(text, "cooperating.irl")
    assert run.ok, run.error
    holder, welder = run.robots["holder"], run.robots["welder"]
    tool = holder.model.tool @ _pose(0, 0, 80, 0, 0, 0)
    before = np.flatnonzero(holder.recorded.lines < 31)[-1]
    start = spatial.inverse(_kin(run, "holder", tool).tcp(holder.q[before])) @ _kin(
        run, "welder"
    ).tcp(welder.q[before])
    end = spatial.inverse(_kin(run, "holder", tool).tcp(holder.q[-1])) @ _kin(run, "welder").tcp(
        welder.q[-1]
    )
    assert np.allclose(end, start @ _pose(50, 20, 0, 0, 0, 10), atol=1e-7)


@pytest.mark.scenario
def test_r_clearance_keeps_a_single_robot_s_own_links(tmp_path):
    """square.irl's koch11 folds links 8 and 10 19 mm into each other (reported, not judged);
    with R_CLEARANCE := 10 they stay apart (their home distance, 7.3 mm, is below 10 mm: they
    keep 0, aimed 1 mm) and the TCP still follows the square."""
    import shutil

    for name in ("square.irl", "square_cell.toml"):
        shutil.copy(PROGRAMS / name, tmp_path / name)
    program = tmp_path / "square.irl"
    plain = run_file(program)
    assert plain.ok and plain.report["self_clearance"]["min_distance_mm"] < -18.0
    text = program.read_text(encoding="utf-8").replace(
        "  R_SPEED := 1000;", "  R_SPEED := 1000;  R_CLEARANCE := 10;"
    )
    program.write_text(text, encoding="utf-8")
    kept = run_file(program)
    assert kept.ok, kept.error
    own = kept.report["self_clearance"]
    assert 0.99 <= own["min_distance_mm"] < 1.5 and (own["link_a"], own["link_b"]) == (8, 10)
    assert kept.report["max_path_error_mm"] < 1e-3


def test_setup_errors_of_a_cell_are_usage_errors():
    from irlc.runtime.run import RunSetupError

    text = (PROGRAMS / "two_robots.irl").read_text(encoding="utf-8")
    code = compile_source(text, "two_robots.irl", resolve_robot=load_robot).code
    with pytest.raises(RunSetupError, match=r"--seed-config has 6 values but the cell's robots "
                       r"have 13 joints \(ceiling: 6, floor: 7\)"):  # fmt: skip
        run_code(code, seed_config=[0.0] * 6)
    with pytest.raises(RunSetupError, match="robot floor's joint a4 \\(panda_joint4\\) = 0 deg"):
        run_code(code, seed_config=[90.0, 30, 0, 30, 90, 0, 0, 0, 0, 0, 0, 90, 45])
    with pytest.raises(RunSetupError, match="--robot cannot be used with a cell"):
        run_code(code, robot="as6")
    with pytest.raises(RunSetupError, match="--trace-every-step cannot be used with a cell"):
        run_code(code, trace_every_step=True, drives="decoupled")


def test_blends_in_a_cell_keep_every_robot_on_one_clock():
    """A robot's motions blend (a tried and shortened blend too); another robot's motion
    first ends the pending one exactly ("another robot moves"); every robot has every
    sample, with the same times and lines."""
    run = _run("""PROGRAM approx;
ROBOT a := as6;
ROBOT b := as6 AT (0, -2200, 0, 180, 0, 0);
CONST MAIN_JOINT: h = (90, 40, -30, 50, 60, 20);
VAR POSE: p, q;
BEGIN
  R_SPEED := 50;
  R_ACC := 300;
  MOVE a PTP h AND b PTP h;
  p := a.R_ACT_POSE;
  q := b.R_ACT_POSE;
  MOVE a LIN p : (0, 0, -50, 0, 0, 0) WITH APPROX := 20;
  MOVE b LIN q : (0, 0, -50, 0, 0, 0) WITH APPROX := 20;
  MOVE a LIN p WITH APPROX := 20;
  MOVE a LIN p : (0, 30, 0, 0, 0, 0);
ENDPROGRAM
""")
    assert run.ok, run.error
    a, b = run.robots["a"], run.robots["b"]
    assert np.array_equal(a.times, b.times) and np.array_equal(a.recorded.lines, b.recorded.lines)
    assert np.all(np.diff(a.times) > 0)
    notes = {(x["robot"], x["line"]): x for x in run.report["approximations"]}
    assert notes[("a", 12)]["note"] == notes[("b", 13)]["note"] == "another robot moves"
    assert notes[("a", 14)]["blended"]
    held = a.recorded.lines == 13  # robot a holds while b moves
    assert np.ptp(a.q[held], axis=0).max() == 0.0


NAMED = """PROGRAM named;
ROBOT holder := as6;
ROBOT welder := as6 AT (0, -2200, 0, 180, 0, 0);
CONST
  MAIN_JOINT: start = (90, 40, 20, 45, 70, 10);
BEGIN
  R_SPEED := 50; R_ACC := 200;
  MOVE holder PTP start AND welder PTP start;
  MOVE holder LIN holder.R_ACT_POSE : (0, 0, -20, 0, 0, 0) AND welder LIN POSE(0, 5000, 0, 0, 0, 0);
  COOPERATE welder IN holder;
    MOVE holder LIN holder.R_ACT_POSE : (0, 0, -50, 0, 0, 0);
  COOPERATEEND;
ENDPROGRAM
"""


def test_a_robots_failure_in_a_cell_names_the_robot():
    """Which robot of a group move cannot reach its target; which robot (the welder,
    following the holder's motion: master–slave) cannot follow — its joint a3 is its own."""
    run = _run(NAMED)
    error = run.report["error"]
    assert error["line"] == 9
    assert error["message"].startswith("robot welder: MOVE LIN: target not reachable")
    follows = _run(NAMED.replace("AND welder LIN POSE(0, 5000, 0, 0, 0, 0)", ""))
    error = follows.report["error"]
    assert error["line"] == 11
    assert error["message"].startswith("robot welder: the path cannot be followed")
    assert "bound by a3 (J3) accel min" in error["message"]
