"""Report JSON, trace CSV and the run command: keys and columns of interfaces.md,
same input → same bytes, atomic writes, exit codes."""

from __future__ import annotations

import json
import os

import numpy as np
import pytest
from irlc.cli import main
from irlc.report import NonFiniteError, load_run, trace_csv, write_report, write_trace
from irlc.runtime.run import run_code

from .conftest import Ird, planar_robot

REPORT_KEYS = [
    "status",
    "error",
    "program",
    "robot",
    "units",
    "ipo_s",
    "drives",
    "duration_s",
    "samples",
    "joints",
    "start_joints",
    "end_joints",
    "max_path_error_mm",
    "max_orientation_error_deg",
    "obstacles",
    "ik",
    "output",
    "warnings",
]
JOINT_KEYS = [
    "name",
    "unit",
    "min",
    "max",
    "max_abs_speed",
    "max_abs_accel",
    "limit_active_s",
    "max_following_error",
]
IK_KEYS = ["cycles", "iterations_mean", "iterations_max", "relaxed_cycles"]


def _program(fail: bool = False) -> Ird:
    p = Ird("planar3t", "RRR", names=("base", "elbow", "wrist"), program="demo")
    p.obstacle("post", "sphere", center=[1500, -300, 0], radius=50)
    p.move(10, "LIN", p.pose(1500, 1000, 0))
    p.move(11, "LIN", p.pose(1500, 500, 0))
    if fail:
        p.move(12, "LIN", p.pose(4000, 500, 0))
    return p


@pytest.fixture
def robot():
    return planar_robot(3, home_deg=(0.0, 90.0, -90.0))


def test_report_has_every_key_of_interfaces_md(robot):
    run = run_code(_program().code_object(), robot=robot)
    r = run.report
    assert list(r)[: len(REPORT_KEYS)] == REPORT_KEYS
    assert r["status"] == "ok" and r["error"] is None
    assert r["program"] == "demo.irl" and r["robot"] == robot.name
    assert r["units"] == {"length": "mm", "angle": "deg", "time": "s"}
    assert r["ipo_s"] == 0.01 and r["drives"] == "ideal"
    assert r["samples"] == len(run.times) and r["duration_s"] == pytest.approx(run.times[-1])
    for j, name in zip(r["joints"], ("base", "elbow", "wrist"), strict=True):
        assert list(j)[:2] == ["name", "unit"] and set(JOINT_KEYS) <= set(j)
        assert j["name"] == name and j["unit"] == "deg" and j["max_following_error"] is None
    assert set(IK_KEYS) <= set(r["ik"])
    assert r["obstacles"]["post"]["min_distance_mm"] > 0
    assert len(r["start_joints"]) == len(r["end_joints"]) == 3
    # numbers agree with the samples (program units)
    q_deg = np.degrees(run.q)
    assert r["joints"][1]["max"] == pytest.approx(q_deg[:, 1].max(), rel=1e-8)
    speed = np.abs(np.diff(q_deg[:, 0])) / 0.01
    assert r["joints"][0]["max_abs_speed"] == pytest.approx(speed.max(), rel=1e-8)


def test_trace_columns_follow_interfaces_md(robot):
    run = run_code(_program().code_object(), robot=robot)
    names = ("base", "elbow", "wrist")
    expected = [
        "t_s",
        "line",
        *(f"{n}_deg" for n in names),
        *(f"{n}_speed_deg_s" for n in names),
        *(f"{n}_accel_deg_s2" for n in names),
        "x_mm",
        "y_mm",
        "z_mm",
        "a_deg",
        "b_deg",
        "c_deg",
        "path_error_mm",
    ]
    assert run.trace_columns[: len(expected)] == expected
    assert run.trace.shape == (len(run.times), len(run.trace_columns))
    t = run.trace
    assert np.allclose(t[:, 2:5], np.degrees(run.q))
    assert np.allclose(t[:, run.trace_columns.index("x_mm")], run.tcp[:, 0, 3] * 1e3)
    assert set(t[:, 1]) == {0.0, 10.0, 11.0}


def test_same_input_same_bytes_and_readback(robot, tmp_path):
    files = []
    for k in range(2):
        run = run_code(_program().code_object(), robot=robot)
        files.append(
            (
                write_report(run.report, tmp_path / f"r{k}.json"),
                write_trace(run.trace_columns, run.trace, tmp_path / f"t{k}.csv"),
            )
        )
    assert files[0][0].read_bytes() == files[1][0].read_bytes()
    assert files[0][1].read_bytes() == files[1][1].read_bytes()
    back = load_run(files[0][1])
    assert back.trace_columns == run.trace_columns
    assert np.allclose(back.trace, run.trace, rtol=1e-9, atol=1e-9)
    rep = load_run(files[0][0])
    assert rep.report == json.loads(files[0][0].read_text())


def test_writes_are_atomic_and_refuse_nan(tmp_path):
    target = tmp_path / "t.csv"
    target.write_text("old\n")
    table = np.array([[0.0, 1.0], [0.01, float("nan")]])
    with pytest.raises(NonFiniteError):
        write_trace(["t_s", "x_mm"], table, target)
    assert target.read_text() == "old\n"  # untouched
    assert os.listdir(tmp_path) == ["t.csv"]  # no temporary file left
    with pytest.raises(NonFiniteError):
        write_report({"status": "ok", "x": float("inf")}, tmp_path / "r.json")
    assert trace_csv(["t_s", "line"], np.array([[-0.0, 3.0]])) == "t_s,line\n0,3\n"


def test_failed_run_keeps_partial_outputs(robot):
    run = run_code(_program(fail=True).code_object(), robot=robot)
    assert run.status == "failed" and run.report["status"] == "failed"
    err = run.report["error"]
    assert err["line"] == 12 and err["time_s"] > 0 and err["message"]
    assert len(run.trace) == run.report["samples"] > 10
    assert np.all(np.isfinite(run.trace))


# ------------------------------------------------------------------------ CLI


def _cli(args, capsys):
    code = main([str(a) for a in args])
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.fixture
def ird_files(tmp_path):
    ok = _program().write(tmp_path)
    bad = _program(fail=True)
    bad.program = "bad"
    return ok, bad.write(tmp_path), tmp_path


def test_cli_exit_codes_and_outputs(ird_files, capsys, monkeypatch):
    ok, bad, folder = ird_files
    robot = planar_robot(3, home_deg=(0.0, 90.0, -90.0))
    import irlc.runtime.run as run_mod

    real = run_mod.resolve_model
    monkeypatch.setattr(
        run_mod, "resolve_model", lambda code, r, b, *rest: real(code, robot, b, *rest)
    )
    code, out, err = _cli(
        ["run", ok, "--json", "--report", folder / "r.json", "--trace", folder / "t.csv"], capsys
    )
    assert code == 0, err
    report = json.loads(out)
    assert report["status"] == "ok"
    assert json.loads((folder / "r.json").read_text()) == report
    assert (folder / "t.csv").read_text().startswith("t_s,line,base_deg,")
    # bare form, failure: exit 2, report written and flagged failed, message with line
    code, out, err = _cli([bad, "--quiet", "--report", folder / "b.json"], capsys)
    assert code == 2
    assert "bad.irl:12:" in err or "bad.ird:12:" in err
    assert json.loads((folder / "b.json").read_text())["status"] == "failed"
    # usage errors: exit 3
    assert _cli(["run", folder / "missing.ird"], capsys)[0] == 3
    assert _cli(["run", ok, "--seed-config", "1 2 x"], capsys)[0] == 3
    assert _cli(["run", ok, "--seed-config", "1 2"], capsys)[0] == 3  # wrong count
    assert _cli(["run", ok, "--drives", "coupled"], capsys)[0] == 3  # no drive data
    # seed config as repeated values (negative numbers too)
    code, out, _ = _cli(
        ["run", ok, "--json", "--seed-config", "0", "--seed-config", "90", "--seed-config", "-90"],
        capsys,
    )
    assert code == 0 and json.loads(out)["start_joints"] == [0.0, 90.0, -90.0]


def test_cli_compile_error_exit_1(tmp_path, capsys):
    src = tmp_path / "broken.irl"
    src.write_text("PROGRAM broken;\nROBOT r := koch11;\nBEGIN\n  MOVE LIN ;\nENDPROGRAM\n")
    code, _, err = _cli(["run", src], capsys)
    assert code == 1
    assert "broken.irl:4:" in err


def test_cli_unknown_robot_exit_3(tmp_path, capsys):
    p = _program()
    p.robot = "no_such_robot"
    path = p.write(tmp_path)
    code, _, err = _cli(["run", path], capsys)
    assert code == 3 and "no_such_robot" in err


def test_compare_reads_a_previous_report(ird_files, capsys, monkeypatch):
    ok, _, folder = ird_files
    robot = planar_robot(3, home_deg=(0.0, 90.0, -90.0))
    import irlc.runtime.run as run_mod

    real = run_mod.resolve_model
    monkeypatch.setattr(
        run_mod, "resolve_model", lambda code, r, b, *rest: real(code, robot, b, *rest)
    )
    assert _cli(["run", ok, "-q", "--report", folder / "a.json"], capsys)[0] == 0
    code, out, _ = _cli(["run", ok, "--compare", folder / "a.json"], capsys)
    assert code == 0 and "compared with" in out
    assert _cli(["run", ok, "--compare", folder / "nope.json"], capsys)[0] == 3
