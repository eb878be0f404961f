"""The public API of the README: compile_program, run_program, load_robot."""

from __future__ import annotations

from pathlib import Path

import irlc
import numpy as np
import pytest
from irlc.lang.diagnostics import CompileError
from irlc.runtime import units

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
