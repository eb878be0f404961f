"""The endless-loop guard end to end: ``irlc run`` on IRL loops without motion fails with
exit 2 at the loop's line within a fraction of a second of interpretation (default budget
500 000 instructions; waiting, like motion, restarts the count), and
``--instruction-budget`` / ``instruction_budget=`` change it. A loop of WAITs is bounded by
the cycle and time budgets, not taken for an endless loop."""

from __future__ import annotations

import re
import time
from pathlib import Path

import pytest
from irlc.cli import main
from irlc.runtime.interpreter import DEFAULT_INSTRUCTION_BUDGET
from irlc.runtime.run import RunSetupError, run_file

LOOPS = {  # body (from line 6), the lines the failure may name (inside the loop)
    "empty": ("  WHILE TRUE DO\n  ENDWHILE;", (6, 7)),
    "assignment": ("  WHILE TRUE DO\n    i := i + 1;\n    i := i - 1;\n  ENDWHILE;", (6, 9)),
    "wait_zero": ("  WHILE TRUE DO\n    WAIT 0 SEC;\n  ENDWHILE;", (6, 8)),
    "repeat": ("  REPEAT\n    i := i + 1;\n  UNTIL i < 0;", (6, 8)),
}


def _program(tmp_path: Path, body: str) -> Path:
    prog = tmp_path / "loop.irl"
    prog.write_text(
        f"PROGRAM loop;\nROBOT r := planar3;\nVAR INTEGER: i;\nBEGIN\n  i := 0;\n{body}\n"
        "ENDPROGRAM\n"
    )
    return prog


@pytest.mark.parametrize("name", sorted(LOOPS))
def test_cli_reports_an_endless_loop_at_its_line(tmp_path, capsys, name):
    body, (first, last) = LOOPS[name]
    prog = _program(tmp_path, body)
    start = time.perf_counter()
    code = main(["run", "-q", str(prog)])
    elapsed = time.perf_counter() - start
    err = " ".join(capsys.readouterr().err.split())
    assert code == 2, err
    assert "Traceback" not in err
    m = re.search(r"loop\.irl:(\d+):(\d+): error: run-time failure at t = [\d.]+ s: more than "
                  r"500000 instructions without motion", err)  # fmt: skip
    assert m and first <= int(m.group(1)) <= last, err
    text = prog.read_text().splitlines()[int(m.group(1)) - 1]  # the column: its statement's
    assert int(m.group(2)) == len(text) - len(text.lstrip()) + 1, err
    assert "endless loop?" in err and "--instruction-budget N" in err
    assert elapsed < 30  # was ~40 s at 50 M instructions; ~1-2 s now (shared machine: loose)


def test_budget_option_and_api(tmp_path, capsys):
    prog = _program(tmp_path, LOOPS["empty"][0])
    assert main(["run", "-q", "--instruction-budget", "1000", str(prog)]) == 2
    assert "more than 1000 instructions" in " ".join(capsys.readouterr().err.split())
    run = run_file(prog, instruction_budget=5000)
    assert run.status == "failed" and "more than 5000 instructions" in run.error.message
    assert run.error.line == 6
    assert main(["run", "-q", "--instruction-budget", "0", str(prog)]) == 3
    assert "--instruction-budget must be a positive integer" in capsys.readouterr().err
    with pytest.raises(RunSetupError):
        run_file(prog, instruction_budget=-1)


def test_a_long_computation_passes_with_a_raised_budget(tmp_path):
    """300 000 iterations of ~8 instructions: over the default, fine when raised."""
    body = "  WHILE i < 300000 DO\n    i := i + 1;\n  ENDWHILE;\n  WRITELN(i);"
    prog = _program(tmp_path, body)
    assert run_file(prog).status == "failed"
    run = run_file(prog, instruction_budget=10 * DEFAULT_INSTRUCTION_BUDGET)
    assert run.status == "ok" and run.output == ["300000"]


def test_public_api_takes_the_budget(tmp_path):
    from irlc import run_program

    prog = _program(tmp_path, LOOPS["empty"][0])
    run = run_program(prog, instruction_budget=2000)
    assert run.status == "failed" and "more than 2000 instructions" in run.error.message


def test_golden_options_take_the_budget(tmp_path):
    import json

    from irlc import golden

    prog = _program(tmp_path, LOOPS["empty"][0])
    expected = tmp_path / "loop.expected.json"
    expected.write_text(json.dumps({"options": {"instruction_budget": 1000}}))
    options = golden.load_expectation(expected)["options"]
    report = golden.default_runner(prog, options)
    assert report["status"] == "failed"
    assert "more than 1000 instructions" in json.dumps(report)


def test_cli_help_states_the_defaults():
    from click.testing import CliRunner
    from irlc.cli.app import cli
    from irlc.runtime.control.executor import DEFAULT_MAX_CYCLES
    from irlc.runtime.interpreter.machine import STILL_MOTION_COST

    text = " ".join(CliRunner().invoke(cli, ["run", "--help"]).output.split())
    assert f"[default: {DEFAULT_INSTRUCTION_BUDGET}]" in text
    assert "instructions without motion or waiting" in text
    assert f"a motion that does not move counts as {STILL_MOTION_COST}" in text
    assert f"(default {DEFAULT_MAX_CYCLES}, about 8 min" in text


def test_one_long_wait_is_not_an_endless_loop(tmp_path):
    """A 20-minute WAIT, 120 000 IPO cycles (it records at most WAIT_SAMPLED_CYCLES of
    them), is a program, not a loop."""
    prog = _program(tmp_path, "  WAIT 1200 SEC;")
    run = run_file(prog)
    assert run.ok, run.error
    assert run.report["duration_s"] == pytest.approx(1200.0)


def _loop_with_motion(tmp_path: Path, passes: int) -> Path:
    """Per pass two motions, each followed by ≈ 60 × 10 instructions without motion."""
    inner = "    FOR i := 1 TO 60 DO j := j + 1; ENDFOR;"
    prog = tmp_path / "loop.irl"
    prog.write_text(
        "PROGRAM loop;\nROBOT r := planar3;\nVAR INTEGER: i, j, k;\nBEGIN\n  j := 0;\n"
        f"  FOR k := 1 TO {passes} DO\n    MOVE PTP (10, 20, 30);\n{inner}\n"
        f"    MOVE PTP (0, 20, 30);\n{inner}\n  ENDFOR;\nENDPROGRAM\n"
    )
    return prog


def test_a_run_executes_at_most_run_budgets_guards_in_all(tmp_path, capsys):
    """Motion restarts the guard's count; a loop with a short motion in each pass was
    bounded only by the cycle budget (≈ 400,000 instructions a pass: hours)."""
    from irlc.runtime.interpreter.machine import RUN_BUDGETS

    for passes, code in ((2, 0), (40, 2)):
        prog = _loop_with_motion(tmp_path, passes)
        status = main(["run", "-q", "--instruction-budget", "1000", str(prog)])
        err = " ".join(capsys.readouterr().err.split())
        assert status == code, err
    assert f"more than {RUN_BUDGETS * 1000} instructions in the run ({RUN_BUDGETS} times" in err
    assert "the endless-loop guard's 1000) — an endless loop with motion?" in err


def test_a_wait_loop_does_not_spend_the_instruction_budget(tmp_path):
    """Waiting advances simulated time: a loop of WAITs is a program (on main 600 waits
    of 1 s stopped at t = 200 s as "endless loop?"). It records every cycle, so the cycle
    budget bounds it — its message names the WAIT and --max-cycles —, and with the budget
    raised it runs to its end."""
    prog = _program(tmp_path, "  FOR i := 1 TO 600 DO WAIT 1 SEC; ENDFOR;")
    run = run_file(prog)
    assert run.status == "failed"
    assert "instructions" not in run.error.message and "--max-cycles" in run.error.message
    assert run.report["duration_s"] > 450.0
    run = run_file(prog, max_cycles=70_000)
    assert run.ok, run.error
    assert run.report["duration_s"] == pytest.approx(600.0)


@pytest.mark.parametrize(
    ("body", "budget"),
    [
        ("  WHILE TRUE DO\n    WAIT 0.5 SEC;\n  ENDWHILE;", "cycles"),
        ("  WHILE TRUE DO\n    WAIT 3600 SEC;\n  ENDWHILE;", "simulated-time budget"),
    ],
)
def test_an_endless_wait_loop_ends_at_a_budget_at_its_wait(tmp_path, capsys, body, budget):
    prog = _program(tmp_path, body)
    start = time.perf_counter()
    assert main(["run", "-q", str(prog)]) == 2
    err = " ".join(capsys.readouterr().err.split())
    assert time.perf_counter() - start < 60.0
    assert "loop.irl:7:" in err and budget in err, err
