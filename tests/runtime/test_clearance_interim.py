"""R_CLEARANCE (issue 26) compiles; until the runtime keeps a clearance, a positive one
fails the run at its line rather than being ignored (0, the start value, runs)."""

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
