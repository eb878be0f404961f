"""``irlc study`` for cells: ``robot.NAME.…`` and ``robot.NAME.at`` keys, the cell's columns.

The cell is two planar3 arms (unit links, all axes along z) 2.5 m apart, each drawing a
200 mm line one after the other (< 1 s simulated, ≈ 0.3 s a run), so the numbers can be
checked against the arms' closed-form kinematics: TCP = AT + Σ 1 m·(cos, sin)(θ1 + … + θk),
and the capsules' (radius 50 mm) distance from the segments between the joints.
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest
from irlc.cli import main
from irlc.study import read_study
from irlc.study.expand import variants
from irlc.study.plan import build_plan

CELL = """PROGRAM c2;
ROBOT left := planar3;
ROBOT right := planar3 AT (0, 2500, 0, 0, 0, 0);
VAR
  POSE: p, q;
BEGIN
  R_SPEED := 800;
  R_ACC := 4000;
  p := left.R_ACT_POSE : (0, 200, 0, 0, 0, 0);
  MOVE left LIN p;
  q := right.R_ACT_POSE : (0, -200, 0, 0, 0, 0);
  MOVE right LIN q;
ENDPROGRAM
"""
ONE = """PROGRAM p1;
ROBOT r := planar3;
VAR
  POSE: p;
BEGIN
  R_SPEED := 800;
  p := r.R_ACT_POSE : (0, 200, 0, 0, 0, 0);
  MOVE LIN p;
ENDPROGRAM
"""
RADIUS_MM = 50.0  # planar3's capsules
ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    (tmp_path / "c2.irl").write_text(CELL)
    (tmp_path / "p1.irl").write_text(ONE)
    return tmp_path


def study_file(folder: Path, body: str, program: str = "c2.irl") -> Path:
    path = folder / "s.toml"
    path.write_text(f'program = "{program}"\n\n' + body)
    return path


def rows(path: Path) -> list[dict[str, str]]:
    with path.open(newline="") as f:
        return list(csv.DictReader(f))


def joints_rad(row: dict[str, str], robot: str) -> list[float]:
    return [math.radians(float(row[f"{robot}_a{k}_deg"])) for k in (1, 2, 3)]


def elbows(at_xy: tuple[float, float], q: list[float]) -> list[np.ndarray]:
    """The joint positions of a planar3 arm (mm): base, elbow 1, elbow 2, TCP."""
    points, angle = [np.array(at_xy, dtype=float)], 0.0
    for theta in q:
        angle += theta
        points.append(points[-1] + 1000.0 * np.array([math.cos(angle), math.sin(angle)]))
    return points


def segment_distance(a0, a1, b0, b1) -> float:
    """The distance of two segments of a plane that do not cross: the least of the four
    point-to-segment distances."""

    def point(p, s0, s1):
        d = s1 - s0
        t = min(1.0, max(0.0, float(np.dot(p - s0, d) / np.dot(d, d))))
        return float(np.linalg.norm(p - (s0 + t * d)))

    return min(point(a0, b0, b1), point(a1, b0, b1), point(b0, a0, a1), point(b1, a0, a1))


# --------------------------------------------------------------------------- running


def test_a_cell_study_moves_a_robot_and_reports_the_cells_numbers(folder, capsys):
    """Moving robot right's AT by dx shifts its TCP by exactly dx with the same joints;
    the clearance column is the capsules' least distance from the closed-form arms; the
    robot columns are the report's; --sort and --resume work with the cell's columns."""
    body = '[output]\ntraces = true\nreports = true\n\n[grid]\n"robot.right.at.x" = [0, 150]\n'
    path = study_file(folder, body)
    out = folder / "out"
    args = ["study", str(path), "--out", str(out), "-j", "1"]
    plot = []
    try:
        import matplotlib  # noqa: F401 (the plot extra)

        plot = ["--plot", str(folder / "clearance.png")]
    except ImportError:
        pass
    assert main([*args, "--sort=-min_clearance_left-right_mm", *plot]) == 0
    summary = " ".join(capsys.readouterr().out.split())
    assert "by min_clearance_left-right_mm, largest first" in summary
    if plot:
        assert (folder / "clearance.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    table = rows(out / "results.csv")
    assert [r["status"] for r in table] == ["ok", "ok"]
    traces = [rows(out / f"variants/variant_000000{i}.trace.csv") for i in (0, 1)]
    assert len(traces[0]) == len(traces[1]) == int(table[0]["samples"]) > 10
    for before, after in zip(*traces, strict=True):
        assert float(after["right_x_mm"]) - float(before["right_x_mm"]) == pytest.approx(
            150.0, abs=1e-9
        )
        for column in ("right_y_mm", "right_a1_deg", "right_a2_deg", "right_a3_deg",
                       "left_x_mm", "left_a2_deg"):  # fmt: skip
            assert float(after[column]) == pytest.approx(float(before[column]), abs=1e-9)
    for row, trace, dx in zip(table, traces, (0.0, 150.0), strict=True):
        report = json.loads((out / f"variants/variant_000000{row['variant']}.report.json")
                            .read_text())  # fmt: skip
        assert report["robots"][1]["at"] == [dx, 2500.0, 0.0, 0.0, 0.0, 0.0]
        least = math.inf
        for sample in trace:  # independent: the arms' closed form, then the capsules
            left = elbows((0.0, 0.0), joints_rad(sample, "left"))
            right = elbows((dx, 2500.0), joints_rad(sample, "right"))
            tcp = right[-1]
            assert float(sample["right_x_mm"]) == pytest.approx(tcp[0], abs=1e-6)
            assert float(sample["right_y_mm"]) == pytest.approx(tcp[1], abs=1e-6)
            for i in range(3):
                for j in range(3):
                    d = segment_distance(left[i], left[i + 1], right[j], right[j + 1])
                    least = min(least, d - 2 * RADIUS_MM)
        assert float(row["min_clearance_left-right_mm"]) == pytest.approx(least, abs=1e-4)
        pairs = {(p["robot_a"], p["robot_b"]): p for p in report["clearance"]["pairs"]}
        assert (
            float(row["min_clearance_right-right_mm"]) == pairs["right", "right"]["min_distance_mm"]
        )
        assert float(row["min_clearance_mm"]) == report["clearance"]["min_distance_mm"]
        assert float(row["cycle_time_s"]) == report["cycle_time_s"] > 0
        for entry in report["robots"]:
            name = entry["name"]
            assert float(row[f"{name}_max_path_error_mm"]) == entry["max_path_error_mm"]
            assert float(row[f"{name}_max_kinetic_energy_j"]) == entry["kinetic_energy"]["max_j"]
            assert float(row[f"{name}_min_mvr"]) == entry["mvr"]["min"]
        joints = {j["name"]: j for j in report["joints"]}
        assert float(row["peak_speed_right_a3_deg_s"]) == joints["right_a3"]["max_abs_speed"]
    # the right arm came 150 mm nearer the left one's x: its links are no farther away
    assert float(table[1]["min_clearance_left-right_mm"]) < float(
        table[0]["min_clearance_left-right_mm"]
    )
    # --resume: a lost row is run again, the file is the same bytes
    expected = (out / "results.csv").read_bytes()
    lines = expected.decode().splitlines(keepends=True)
    (out / "results.csv").write_text("".join(lines[:2]))
    assert main([*args, "--resume", "-q"]) == 0
    assert (out / "results.csv").read_bytes() == expected


def test_a_robot_files_value_changes_that_robot_only(folder):
    """robot.left.joints.2.position narrows left's J2 to [88, 180] deg: its J2 (87.2 deg
    at the end of the free run) stops at 88 deg, the redundancy keeps the path; the right
    arm, whose file did not change, moves exactly as before."""
    from irlc.study.worker import run_variant

    body = '[output]\ntraces = true\n\n[grid]\n"robot.left.joints.a2.position" = [[-180, 180], [88, 180]]\n'  # noqa: E501
    study = read_study(study_file(folder, body))
    plan = build_plan(study, folder / "variants")
    got = [run_variant(plan, i, values) for i, values in variants(study)]
    assert [r["status"] for r in got] == ["ok", "ok"]
    free, narrow = (rows(folder / f"variants/variant_000000{i}.trace.csv") for i in (0, 1))
    assert min(float(s["left_a2_deg"]) for s in free) < 87.5
    assert min(float(s["left_a2_deg"]) for s in narrow) == pytest.approx(88.0, abs=0.01)
    assert "left_a2 position min" in got[1]["active_bounds"]
    assert "right" not in got[1]["active_bounds"]
    assert float(got[1]["left_max_path_error_mm"]) < 0.05
    for a, b in zip(free, narrow, strict=True):
        assert a["right_a1_deg"] == b["right_a1_deg"] and a["right_x_mm"] == b["right_x_mm"]
    # the loader's model of the key's robot: J2's limits are the new ones (rad), J1's not
    from irlc.study.paths import target
    from irlc.study.robots import robot_key, robot_model, robot_named

    key = robot_key(plan.robots, target("robot.left.joints.a2.position")[1])
    assert (key.robot, key.parts, key.at) == ("left", ("joints", "2", "position"), False)
    left = robot_model(robot_named(plan.robots, "left"), [(list(key.parts), [-10, 120])])
    assert np.allclose(left.position_limits[1], np.radians([-10, 120]))
    assert np.allclose(left.position_limits[0], np.radians([-180, 180]))


DRIVES = """PROGRAM c3;
ROBOT holder := as6;
ROBOT welder := as6 AT (0, -2200, 0, 180, 0, 0);
CONST
  MAIN_JOINT: h1 = (100, 45, 0, 45, 90, 0);
  MAIN_JOINT: w1 = (80, 40, 0, 45, 90, 0);
BEGIN
  MOVE holder PTP h1;
  MOVE welder PTP w1;
ENDPROGRAM
"""


def test_a_cell_with_drives_has_every_robots_drive_columns(folder):
    """With drives each robot's axes are its columns (its report entry's summary), and
    the cell could follow when every robot could."""
    from irlc.study.worker import run_variant

    (folder / "c3.irl").write_text(DRIVES)
    body = '[output]\nreports = true\n\n[grid]\n"run.drives" = ["decoupled"]\n'
    study = read_study(study_file(folder, body, "c3.irl"))
    plan = build_plan(study, folder / "variants")
    (row,) = [run_variant(plan, i, values) for i, values in variants(study)]
    assert row["status"] == "ok", row["error"]
    report = json.loads((folder / "variants/variant_0000000.report.json").read_text())
    follow = [e["drives_summary"]["could_follow"] for e in report["robots"]]
    assert row["drives_could_follow"] == ("true" if all(follow) else "false")
    for entry in report["robots"]:
        axes = entry["drives_summary"]["axes"]
        assert len(axes) == 6
        for k, axis in enumerate(axes, start=1):
            assert float(row[f"peak_current_{entry['name']}_a{k}_A"]) == axis["peak_current_A"]
    # joint 2 moved 15 deg (holder) and 10 deg (welder): their columns differ
    assert row["peak_current_holder_a2_A"] != row["peak_current_welder_a2_A"]


def test_one_robot_may_vary_its_placement_and_name_itself(folder):
    """A one-robot program: robot.at.y moves it (its TCP by exactly dy), robot.r.… (its
    name) is robot.…, and the columns are the one-robot columns."""
    from irlc.study.metrics import columns
    from irlc.study.worker import run_variant

    body = '[output]\ntraces = true\n\n[grid]\n"robot.at.y" = [0, 40]\n"robot.r.joints.a1.weight" = [2]\n'  # noqa: E501
    study = read_study(study_file(folder, body, "p1.irl"))
    plan = build_plan(study, folder / "variants")
    cols = columns(plan)
    assert "peak_speed_a1_deg_s" in cols and "cycle_time_s" not in cols
    got = [run_variant(plan, i, values) for i, values in variants(study)]
    assert [r["status"] for r in got] == ["ok", "ok"]
    a, b = (rows(folder / f"variants/variant_000000{i}.trace.csv") for i in (0, 1))
    for s, t in zip(a, b, strict=True):
        assert float(t["y_mm"]) - float(s["y_mm"]) == pytest.approx(40.0, abs=1e-9)
        assert float(t["a3_deg"]) == pytest.approx(float(s["a3_deg"]), abs=1e-9)
    # the weight is the file's joint 1 weight, as robot.joints.1.weight would set it
    from irlc.study.paths import target
    from irlc.study.robots import robot_key

    named = robot_key(plan.robots, target("robot.r.joints.a1.weight")[1])
    plain = robot_key(plan.robots, target("robot.joints.1.weight")[1])
    assert named == plain and named.parts == ("joints", "1", "weight")


def test_the_run_takes_its_own_robots_by_name(folder):
    """run_code(robots=…): an unknown robot or a placement that is not one is a usage
    error naming the robots; the report places the robot where the run did."""
    from irlc.api import compile_program
    from irlc.runtime.run import RobotOverride, RunSetupError, run_code

    code = compile_program(folder / "c2.irl")
    with pytest.raises(RunSetupError, match=r"no robot middle \(its robots: left, right\)"):
        run_code(code, robots={"middle": RobotOverride(at=(0, 0, 0, 0, 0, 0))})
    with pytest.raises(RunSetupError, match="robot right: a placement is x, y, z, a, b, c: 6"):
        run_code(code, robots={"right": RobotOverride(at=(0, 0, 0, 0, 0))})
    with pytest.raises(RunSetupError, match="finite"):
        run_code(code, robots={"right": RobotOverride(at=(0, math.nan, 0, 0, 0, 0))})
    run = run_code(code, robots={"RIGHT": RobotOverride(at=(0, 2600, 0, 0, 0, 90))})
    assert run.report["robots"][1]["at"] == [0.0, 2600.0, 0.0, 0.0, 0.0, 90.0]
    assert np.allclose(run.robots["right"].at[:3, 3], [0.0, 2.6, 0.0])
    assert code.other_robots[0].at == (0.0, 2500.0, 0.0, 0.0, 0.0, 0.0)  # not changed


# --------------------------------------------------------------------------- checks

BAD = [
    # (the study file's body, the marker of the offending line, words of the message)
    ('[grid]\n"robot.middle.at.x" = [0]\n', "middle", "not a robot of the program"),
    ('[grid]\n"robot.joints.1.weight" = [1]\n', "joints", "NAME one of its robots (left, right)"),
    (
        '[grid]\n"robot.right.at" = [[0, 2500, 0, 0, 0]]\n',
        "robot.right.at",
        "a placement is x, y, z, a, b, c: 6 numbers, got 5",
    ),
    ('[grid]\n"robot.right.at.q" = [0]\n', "at.q", "x, y, z, a, b, c or 1 … 6"),
    ('[grid]\n"robot.right" = [0]\n', "robot.right", "vary robot.right.at"),
    ('[grid]\n"robot.right.at.y" = [2e9]\n', "at.y", "outside the physical range"),
    ('[grid]\n"robot.right.at.c" = ["x"]\n', "at.c", "expected a finite number"),
    ('[grid]\n"robot.left.joints.a2.weight" = [-2]\n', "weight", "positive"),
    (
        '[grid]\n"run.seed_config" = [[0, 90, -90]]\n',
        "seed_config",
        "the cell's robots have 6 joints (left: 3, right: 3)",
    ),
    (
        'robot = "planar4"\n[grid]\n"robot.right.at.y" = [0]\n',
        "planar4",
        "robot: the program is a cell of 2 robots (left, right)",
    ),
]


@pytest.mark.parametrize(("body", "marker", "words"), BAD)
def test_bad_cell_keys_are_the_study_files_errors(folder, capsys, body, marker, words):
    path = study_file(folder, body)
    line = next(i for i, t in enumerate(path.read_text().splitlines(), 1) if marker in t)
    assert main(["study", str(path), "--out", str(folder / "out"), "-q"]) == 3
    err = " ".join(capsys.readouterr().err.split())
    assert f"s.toml:{line}:" in err and words in err, err
    assert "Traceback" not in err and "nan" not in err
    assert not (folder / "out" / "results.csv").exists()  # nothing ran


def test_the_example_cell_study_is_valid():
    """programs/studies/two_robots_floor.toml (docs/studies.md, "Cells") reads, compiles
    and passes the checks; running it (15 two_robots runs) is left to the docs' command."""
    from irlc.study.metrics import columns

    study = read_study(ROOT / "programs" / "studies" / "two_robots_floor.toml")
    plan = build_plan(study)
    assert plan.cell == ("ceiling", "floor") and len(list(variants(study))) == 15
    cols = columns(plan)
    for column in ("min_clearance_ceiling-floor_mm", "floor_max_path_error_mm",
                   "cycle_time_s", "peak_speed_floor_a1_deg_s"):  # fmt: skip
        assert column in cols


def test_a_cell_study_with_drives_needs_drive_data_of_one_robot_only(tmp_path):
    """two_robots.irl's Panda has no drive data: with run.drives the study is accepted
    (the Panda runs ideal beside the AS arm's drives, docs/drives.md)."""
    program = (ROOT / "programs" / "two_robots.irl").as_posix()
    path = tmp_path / "drives.toml"
    body = '[run]\ndrives = "decoupled"\n[grid]\n"robot.floor.at.x" = [0, 100]\n'
    path.write_text(f'program = "{program}"\n{body}', encoding="utf-8")
    plan = build_plan(read_study(path))
    assert plan.drives and plan.cell == ("ceiling", "floor")
