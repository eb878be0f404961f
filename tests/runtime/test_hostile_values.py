"""Hostile numbers in built-ins (issue 11): each test reproduces one failure the
adversarial run found — a result is right, or a positioned run failure, never exit 4."""

from __future__ import annotations

import json
from pathlib import Path

from irlc.cli import main


def run(tmp_path: Path, capsys, body: str) -> tuple[int, dict, str]:
    prog = tmp_path / "p.irl"
    prog.write_text(
        "PROGRAM p;\nROBOT r := planar3;\nVAR ORIENTATION: o; REAL: x;\nBEGIN\n"
        f"{body}\nENDPROGRAM\n",
        "utf-8",
    )
    code = main(["run", str(prog), "-q", "--report", str(tmp_path / "r.json")])
    err = capsys.readouterr().err
    assert "Traceback" not in err and "internal error" not in err, err
    return code, json.loads((tmp_path / "r.json").read_text("utf-8")), " ".join(err.split())


def test_dist_of_huge_coordinates_is_exact_or_a_failure(tmp_path, capsys) -> None:
    # (1e300 - -1e300) ** 2 raised OverflowError: exit 4.
    code, report, err = run(
        tmp_path, capsys,
        "  x := DIST(POSITION(1e300, 0, 0), POSITION(-1e300, 0, 0)); WRITELN(x);\n"
        "  x := DIST(POSITION(3e-300, 0, 0), POSITION(0, 4e-300, 0)); WRITELN(x);\n"
        "  x := DIST(POSITION(1e308, 0, 0), POSITION(-1e308, 0, 0));",
    )  # fmt: skip
    assert code == 2
    assert report["output"] == ["2e+300", "0.0"]  # 5e-300 is 0 to 6 decimals
    assert "p.irl:7:3: error: run-time failure at t = 0.000 s: DIST: the result is not a" in err


def test_orientations_from_huge_quaternions_and_axes(tmp_path, capsys) -> None:
    # ‖q‖² overflowed to inf: ORIQUAT(1e300, 1e300, 0, 0) became the zero quaternion;
    # ORIVANG's axis length raised OverflowError.
    code, report, err = run(
        tmp_path, capsys,
        "  o := ORIQUAT(1e300, 1e300, 0, 0); WRITELN(o);\n"
        "  o := ORIVANG(POSITION(0, 0, 1e300), 90); WRITELN(o);\n"
        "  o := ORIVANG(POSITION(0, 0, 1e-10), 90); WRITELN(o);",
    )  # fmt: skip
    assert code == 0, err
    # q = (1, 1, 0, 0)/√2: 90° about x; ORIVANG about z: yaw 90°
    assert report["output"] == [
        "ORIZYX(0.0, 0.0, 90.0)", "ORIZYX(90.0, 0.0, 0.0)", "ORIZYX(90.0, 0.0, 0.0)",
    ]  # fmt: skip


def test_an_overflowing_duration_is_never_shown_as_inf(tmp_path, capsys) -> None:
    # 'the motion would take inf s …' in the message and the report (found by the fuzz).
    code, report, err = run(
        tmp_path, capsys, "  MOVE LIN POSE(1500, 500, 0, 0, 0, 0) WITH SPEED := 1e-320;"
    )
    assert code == 2
    assert "p.irl:5:3: error: run-time failure at t = 0.000 s: the motion would take longer" in err
    assert "inf" not in err and "inf" not in json.dumps(report)


def test_a_subnormal_joint_move_under_the_s_curve_runs(tmp_path, capsys) -> None:
    # a 1e-320 deg PTP delta: bound / distance overflowed to inf, and the S-curve's own
    # check raised ProfileError (exit 4; found by the REPL fuzz on planar4)
    code, report, err = run(
        tmp_path, capsys,
        "  R_PROFILE := 'SCURVE';\n"
        "  MOVE PTP (0, 90, -90);\n"
        "  MOVE PTP (1e-320, 90, -90);\n"
        "  MOVE_INC PTP (4.9e-324, 4.9e-324, 0);\n"
        "  MOVE_INC PTP (1e-320, 0, 0) WITH TIME := 1;",
    )  # fmt: skip
    assert code == 0, err
    assert report["end_joints"] == [0, 90, -90]
