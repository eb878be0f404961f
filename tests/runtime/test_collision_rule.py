"""A collision never passes (issue 24 §1, runtime/control/collision.py).

planar3 (unit links, capsules of radius 50 mm) moves its TCP along y = 1 m from
(2000, 1000) to (500, 1000) through a ball of radius 100 mm at (800, 1000): link 3 runs
into it. The depth each failure or report names is checked against the closed-form
distance of the ball's centre to the link segments of an independent forward kinematics
of the trace's joints, ``depth = 100 mm + 50 mm − min_i dist(c, p_{i−1} p_i)``.
"""

from __future__ import annotations

import itertools
import json

import numpy as np
import pytest
from irlc.cli import main
from irlc.runtime.run import run_file

CELL = """
[poses]
start = [2000, 1000, 0, 0, 0, 0]
goal = [500, 1000, 0, 0, 0, 0]

[joints]
home = [0, 90, -90]
inside = [0, 90, 90]

[obstacles.ball]
kind = "sphere"
center = [{X}, 1000, 0]
radius = 100
"""
PROGRAM = """PROGRAM through;
ROBOT r := planar3;
IMPORT DATALIST cell;
BEGIN
  R_SPEED := 500;
  {AVOID}
  MOVE LIN goal;
  {AVOIDEND}
  WRITELN('arrived');
ENDPROGRAM
"""
LIN_LINE = 7
BALL = np.array([0.8, 1.0])
REACH = 0.1 + 0.05  # m: the ball's radius + the links'


def write(tmp_path, program: str = PROGRAM, x: float = 800.0, avoid: str = ""):
    (tmp_path / "cell.toml").write_text(CELL.replace("{X}", f"{x:g}"))
    path = tmp_path / "through.irl"
    end = avoid.replace("OBSTACLE", "OBSTACLEEND")
    path.write_text(program.replace("{AVOID}", avoid).replace("{AVOIDEND}", end))
    return path


def depth_closed_form(q_deg: np.ndarray, centre: np.ndarray = BALL) -> tuple[float, int]:
    """``(depth m, link)`` of the ball by planar forward kinematics, links 1…3."""
    angles = np.cumsum(np.radians(q_deg))
    points = np.vstack([[0.0, 0.0], np.cumsum(np.c_[np.cos(angles), np.sin(angles)], 0)])
    dist = []
    for a, b in itertools.pairwise(points):
        s = np.clip((centre - a) @ (b - a) / ((b - a) @ (b - a)), 0.0, 1.0)
        dist.append(np.linalg.norm(centre - a - s * (b - a)))
    i = int(np.argmin(dist))
    return REACH - dist[i], i + 1


def joints(run) -> np.ndarray:
    cols = [run.trace_columns.index(f"a{j}_deg") for j in (1, 2, 3)]
    return run.trace[:, cols]


def test_a_lin_through_an_obstacle_fails_at_its_line_naming_obstacle_link_depth(tmp_path):
    run = run_file(write(tmp_path))
    assert run.status == "failed"
    err = run.error
    assert err.line == LIN_LINE and err.cause == "obstacle"
    depth, link = depth_closed_form(joints(run)[-1])  # the failing cycle is the last row
    assert depth > 0.0
    assert err.details["obstacle"] == "ball" and err.details["link"] == link
    assert err.details["depth_mm"] == pytest.approx(depth * 1e3, abs=1e-6)
    assert err.time_s == pytest.approx(run.trace[-1, 0])
    assert f"link {link} is {depth * 1e3:.4g} mm inside it" in err.message
    assert "switch OBSTACLE ball on" in err.message and "--allow-collisions" in err.message
    # every row before the failing one is clear (it fails at the first penetration)
    assert all(depth_closed_form(q)[0] < 0.0 for q in joints(run)[:-1])
    assert run.output == []  # the WRITELN after the motion never ran
    report = run.report
    assert report["collisions"] == {
        "allowed": False,
        "penetrations": [
            {"obstacle": "ball", "link": link, "depth_mm": pytest.approx(depth * 1e3, abs=1e-6),
             "time_s": pytest.approx(err.time_s), "line": LIN_LINE}
        ],
    }  # fmt: skip
    assert report["obstacles"]["ball"]["link"] == link


def test_exit_code_and_message_on_the_command_line(tmp_path, capsys):
    program = write(tmp_path)
    assert main(["run", str(program), "-q"]) == 2
    err = " ".join(capsys.readouterr().err.split())
    assert f"through.irl:{LIN_LINE}:" in err and "collides with obstacle ball: link" in err


def test_allow_collisions_opts_out_and_says_so(tmp_path, capsys):
    program = write(tmp_path)
    run = run_file(program, allow_collisions=True)
    assert run.ok and run.output == ["arrived"]
    q = joints(run)
    depths = np.array([depth_closed_form(row)[0] for row in q])
    k = int(np.argmax(depths))
    assert depths[k] > 0.05  # 50 mm and more: the link passes right through the ball
    (hit,) = run.report["collisions"]["penetrations"]
    assert run.report["collisions"]["allowed"] is True
    assert hit["depth_mm"] == pytest.approx(depths[k] * 1e3, abs=1e-6)
    assert hit["time_s"] == pytest.approx(run.trace[k, 0]) and hit["line"] == LIN_LINE
    assert run.report["obstacles"]["ball"]["min_distance_mm"] == pytest.approx(-hit["depth_mm"])
    assert any("collisions allowed (--allow-collisions)" in w for w in run.report["warnings"])
    # the command line: exit 0, the summary says collisions were allowed and where
    report = tmp_path / "r.json"
    assert main(["run", str(program), "--allow-collisions", "--report", str(report)]) == 0
    shown = " ".join(capsys.readouterr().out.replace("│", " ").split())
    assert "collisions allowed (--allow-collisions): ball" in shown
    assert json.loads(report.read_text())["collisions"]["allowed"] is True


def test_an_avoided_obstacle_on_the_tcp_path_fails_all_the_same(tmp_path):
    """OBSTACLE stays avoidance: it cannot move the TCP off its path, which here runs
    through the ball, so the arm collides with OBSTACLE on — a failure that says so."""
    run = run_file(write(tmp_path, avoid="OBSTACLE ball;"))
    assert run.status == "failed" and run.error.line == LIN_LINE
    assert "OBSTACLE is on but cannot keep the arm out" in run.error.message
    depth, link = depth_closed_form(joints(run)[-1])
    assert run.error.details["depth_mm"] == pytest.approx(depth * 1e3, abs=1e-6)
    assert run.error.details["link"] == link


def test_a_ptp_into_an_obstacle_fails(tmp_path):
    program = PROGRAM.replace("MOVE LIN goal;", "MOVE PTP inside;")
    run = run_file(write(tmp_path, program))
    assert run.status == "failed" and run.error.line == LIN_LINE
    depth, link = depth_closed_form(joints(run)[-1])
    assert depth > 0.0 and run.error.details["link"] == link
    assert run.error.details["depth_mm"] == pytest.approx(depth * 1e3, abs=1e-6)


def test_a_program_that_starts_inside_an_obstacle_fails_at_its_first_statement(tmp_path, capsys):
    """The ball over the start configuration: link 3 starts inside it (t = 0), even for a
    program that only waits."""
    program = write(tmp_path, PROGRAM.replace("MOVE LIN goal;", "WAIT 1 SEC;"), x=1800.0)
    run = run_file(program)
    assert run.status == "failed" and run.error.time_s == 0.0
    assert run.error.line == 5  # R_SPEED := 500, the first statement
    depth, link = depth_closed_form(np.array([0.0, 90.0, -90.0]), np.array([1.8, 1.0]))
    assert run.error.details["depth_mm"] == pytest.approx(depth * 1e3, abs=1e-6)
    assert run.error.details["link"] == link == 3 and depth == pytest.approx(0.15)
    assert "starts inside obstacle ball" in run.error.message
    assert "the robot's home" in run.error.message
    assert run.report["samples"] == 1 and run.output == []
    # --seed-config names itself as the start
    run = run_file(program, seed_config=[0, 90, -90])
    assert "(--seed-config)" in run.error.message
    # allowed: the program runs
    run = run_file(program, allow_collisions=True)
    assert run.ok and run.report["duration_s"] == pytest.approx(1.0)


GOLDEN = {"format": "irlc-golden 1", "status": "ok"}


def test_a_golden_test_counts_a_collision_as_a_failure(tmp_path, capsys):
    from irlc.golden import run_case

    program = write(tmp_path)
    assert run_case(program, update=True).status == "updated"
    expected = json.loads(program.with_suffix(".expected.json").read_text())
    assert expected["status"] == "failed" and expected["error_line"] == LIN_LINE
    # an expectation recorded before the rule (the run passed) now fails
    expected.update(status="ok", error_line=None)
    program.with_suffix(".expected.json").write_text(json.dumps(expected))
    assert run_case(program).status == "fail"
    # the run option allow_collisions opts out
    expected["options"] = {"allow_collisions": True}
    program.with_suffix(".expected.json").write_text(json.dumps(expected))
    assert run_case(program, update=True).status == "updated"
    assert json.loads(program.with_suffix(".expected.json").read_text())["status"] == "ok"


def test_a_study_row_of_a_collision_is_failed_unless_the_run_allows_collisions(tmp_path):
    from irlc.cli import main as irlc

    program = write(tmp_path)
    study = tmp_path / "s.toml"
    study.write_text(
        f'program = "{program.name}"\n\n[grid]\n"run.allow_collisions" = [false, true]\n'
    )
    assert irlc(["study", str(study), "--out", str(tmp_path / "out")]) == 0
    import csv

    with (tmp_path / "out" / "results.csv").open(newline="") as f:
        rows = list(csv.DictReader(f))
    assert [(r["run.allow_collisions"], r["status"]) for r in rows] == [
        ("false", "failed"),
        ("true", "ok"),
    ]
    assert float(rows[1]["min_clearance_ball_mm"]) < -50.0


def test_the_repl_may_back_out_of_a_collision_but_not_go_deeper(tmp_path):
    from irlc.repl import Session

    (tmp_path / "cell.toml").write_text(CELL.replace("{X}", "800"))
    session = Session("planar3", datalist_path=[str(tmp_path)], cwd=tmp_path)
    assert session.enter("IMPORT DATALIST cell;").failure == 0
    entry = session.enter("MOVE LIN goal;")
    assert entry.failure == 2 and "collides with obstacle ball" in " ".join(entry.lines)
    inside = session.controller.recorder.last_clearances()["ball"][0]
    assert inside < 0.0
    assert session.enter("MOVE LIN goal;").failure == 2  # deeper in: still a collision
    # backing out (to the joints it came from) is allowed; a LIN back may still swing
    # the elbow deeper in its first cycles
    assert session.enter("MOVE PTP home;").failure == 0
    assert session.controller.recorder.last_clearances()["ball"][0] > 0.0
