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
