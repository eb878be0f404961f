"""The public API of the README: compile_program, run_program, load_robot."""

from __future__ import annotations

from pathlib import Path

import irlc
import numpy as np
import pytest
from irlc.lang.diagnostics import CompileError
from irlc.runtime import units
from irlc.runtime.model.kinematics import Kinematics
from scipy.spatial.transform import Rotation

PROGRAMS = Path(__file__).resolve().parents[1] / "programs"


def test_load_robot_by_name():
    robot = irlc.load_robot("koch11")
    assert robot.n == 11
    assert robot.joint_kinds[9] == "prismatic"


def test_compile_program_returns_code_and_raises_with_positions(tmp_path):
    code = irlc.compile_program(PROGRAMS / "square.irl")
    assert code.robot == "koch11" and code.joint_count == 11
    bad = tmp_path / "bad.irl"
    bad.write_text("PROGRAM bad;\nROBOT r := koch11;\nBEGIN\n  x := 1;\nENDPROGRAM\n")
    with pytest.raises(CompileError) as info:
        irlc.compile_program(bad)
    first = info.value.diagnostics[0]
    assert (first.line, first.column) == (4, 3)


def test_run_program_on_a_small_program(tmp_path):
    prog = tmp_path / "p.irl"
    prog.write_text(
        "PROGRAM p;\nROBOT r := planar3;\nVAR MAIN_JOINT: k;\nBEGIN\n"
        "  k := (30, 40, 50);\n  MOVE PTP k;\nENDPROGRAM\n"
    )
    run = irlc.run_program(prog)
    assert run.status == "ok", run.error
    end = units.joints_from_si(run.q[-1], run.model.joint_kinds)
    assert np.allclose(end, (30, 40, 50), atol=1e-9)


def test_public_names_are_exported_and_listed():
    """``from irlc import CompileError`` (what compile_program raises, as the README says)
    and the other public names work, resolve to their home modules, and ``dir(irlc)``
    lists them without the package's helpers."""
    from irlc import CompileError as exported
    from irlc import IrlcError, RunFailure, RunResult, RunSetupError

    assert exported is CompileError
    public = {
        "compile_program", "run_program", "load_robot", "CompileError", "RunFailure",
        "RunResult", "RunSetupError", "RobotFileError", "UnknownRobotError",
        "DriveSetupError", "IrlcError", "RobotModel", "Code", "Diagnostic",
    }  # fmt: skip
    assert public <= set(irlc.__all__) and public <= set(dir(irlc))
    assert not {"importlib", "Any", "TYPE_CHECKING", "annotations"} & set(dir(irlc))
    for name in irlc.__all__:
        assert getattr(irlc, name).__module__.startswith("irlc."), name
    for error in (CompileError, RunFailure, RunSetupError, irlc.RobotFileError):
        assert issubclass(error, IrlcError)
    run = irlc.run_program(PROGRAMS / "square.irl", ipo=0.05, max_cycles=5)
    assert isinstance(run, RunResult) and isinstance(run.error, RunFailure)
    with pytest.raises(AttributeError, match="no_such_name"):
        irlc.no_such_name  # noqa: B018
    assert sorted(irlc.__all__) == sorted(irlc._HOME_OF)


def test_run_program_on_a_cell_gives_each_robot(tmp_path):
    """``run_program`` on a program of two robots: ``robots`` holds each robot's samples,
    placement and report entry; its TCP is its own forward kinematics placed by AT."""
    prog = tmp_path / "pair.irl"
    prog.write_text(
        "PROGRAM pair;\nROBOT left := planar3;\nROBOT right := planar3 AT (3000, 0, 0, 180, 0, 0);"
        "\nBEGIN\n  MOVE left PTP (10, 80, -70) AND right PTP (20, 70, -60);\nENDPROGRAM\n"
    )
    code = irlc.compile_program(prog)
    assert [r.var for r in code.robots] == ["left", "right"]
    run = irlc.run_program(prog)
    assert run.status == "ok" and run.is_cell and list(run.robots) == ["left", "right"]
    at = np.eye(4)
    at[:3, :3] = Rotation.from_euler("ZYX", [180, 0, 0], degrees=True).as_matrix()
    at[:3, 3] = (3.0, 0.0, 0.0)
    plain = irlc.load_robot("planar3")
    for name, end, placement in (("left", (10, 80, -70), np.eye(4)), ("right", (20, 70, -60), at)):
        robot = run.robots[name]
        assert robot.name == name and robot.report["name"] == name
        assert robot.joint_names == ("a1", "a2", "a3")
        assert robot.trace_columns[0] == f"{name}_a1_deg"
        assert np.allclose(robot.at, placement, atol=1e-12)
        assert np.allclose(np.degrees(robot.q[-1]), end, atol=1e-9)
        assert np.allclose(robot.tcp[-1], placement @ Kinematics(plain).tcp(robot.q[-1]))
        assert np.array_equal(robot.times, run.times)
    assert np.array_equal(run.q, np.hstack([run.robots["left"].q, run.robots["right"].q]))
