"""What issue 26's front end compiles but this runtime does not do yet fails clearly rather
than being ignored: a positive R_CLEARANCE fails the run at its line (0, the start value,
runs); a robot placed with AT off the origin is refused before the run (cells: tests/lang/
test_cells.py). The runtime of cells replaces these tests."""

from __future__ import annotations

from irlc.lang import compile_source
from irlc.robots import load_robot
from irlc.runtime.run import run_code


def _run(value: str):
    text = (
        "PROGRAM c;\nROBOT r := planar3;\nBEGIN\n"
        f"  R_CLEARANCE := {value};\n  WAIT 0.1 SEC;\nENDPROGRAM\n"
    )
    result = compile_source(text, "c.irl", resolve_robot=load_robot)
    assert result.ok, [d.header() for d in result.diagnostics]
    return run_code(result.code)


def test_a_positive_clearance_fails_at_its_line_until_the_runtime_keeps_it() -> None:
    run = _run("50")
    assert run.status == "failed" and run.error.line == 4
    assert run.error.message == "R_CLEARANCE := 50: this runtime cannot keep a clearance yet"


def test_no_clearance_runs() -> None:
    assert _run("0").status == "ok"


def test_a_placed_robot_is_refused_until_the_runtime_places_robots() -> None:
    import pytest
    from irlc.runtime.run import RunSetupError

    text = "PROGRAM c;\nROBOT r := planar3 AT (100, 0, 0, 0, 0, 0);\nBEGIN\nENDPROGRAM\n"
    result = compile_source(text, "c.irl", resolve_robot=load_robot)
    with pytest.raises(RunSetupError, match="robot r is placed with AT, which this runtime"):
        run_code(result.code)
    placed_at_origin = text.replace("AT (100,", "AT (0,")
    assert run_code(compile_source(placed_at_origin, "c.irl", resolve_robot=load_robot).code).ok
