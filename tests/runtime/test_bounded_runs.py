"""Runs stay bounded in time and memory (issue 11): each test reproduces one hang or
memory blow-up the adversarial run found, with the CPU time of the fixed run far below
what the unfixed one took (CPU time: the machine may be loaded)."""

from __future__ import annotations

import json
import random
import time
from pathlib import Path

import pytest
from irlc.cli import main
from irlc.lang.value_ranges import MAX_LIVE_ELEMENTS
from irlc.runtime.interpreter.io import MAX_EVENTS, MAX_OUTPUT_CHARS
from irlc.runtime.interpreter.state import UNSET
from irlc.runtime.outputs.digital_io import value_at
from irlc.runtime.values import ArrayValue, format_value, pose_from_zyx, text_bound


def run(tmp_path: Path, capsys, program: str, *extra: str) -> tuple[int, str, str, float]:
    """Run ``program`` (with ``-q`` unless ``extra`` says ``--json``); (exit code, stdout,
    stderr flattened, CPU seconds)."""
    prog = tmp_path / "p.irl"
    prog.write_text(program, "utf-8")
    start = time.process_time()
    code = main(["run", str(prog), *([] if "--json" in extra else ["-q"]), *extra])
    cpu = time.process_time() - start
    out = capsys.readouterr()
    assert "Traceback" not in out.err and "internal error" not in out.err, out.err
    return code, out.out, " ".join(out.err.split()), cpu


HEAD = "PROGRAM p;\nROBOT r := planar3;\n"


def test_a_recursion_with_large_locals_fails_before_it_fills_the_memory(tmp_path, capsys):
    # Each call allocated a million cells; 10,000 nested calls: no end (killed after 30 s).
    code, _, err, cpu = run(
        tmp_path, capsys,
        HEAD + "PROCEDURE q(INTEGER: n);\nVAR ARRAY [1..1000000] OF REAL: a;\nBEGIN\n"
        "  q(n + 1);\nENDPROC;\nBEGIN\n  q(0);\nENDPROGRAM\n",
    )  # fmt: skip
    assert code == 2, err
    assert "p.irl:6:3: error: run-time failure at t = 0.000 s: the call of 'q' would hold" in err
    assert f"(at most {MAX_LIVE_ELEMENTS}) — endless recursion?" in err
    assert cpu < 20


def test_storing_into_a_large_array_is_charged_to_the_loop_guard(tmp_path, capsys):
    # Every a[i] := … converted all million items again (0.1 s a store): a hang.
    code, _, err, cpu = run(
        tmp_path, capsys,
        HEAD + "VAR ARRAY [1..1000000] OF REAL: a; INTEGER: i;\nBEGIN\n"
        "  FOR i := 1 TO 1000000 DO a[i] := i; ENDFOR;\nENDPROGRAM\n",
        "--instruction-budget", "100000",
    )  # fmt: skip
    assert code == 2, err
    assert "p.irl:5:3: error: run-time failure at t = 0.000 s: more than 100000 instructions" in err
    assert "work on an array as its elements / 128" in err
    assert cpu < 20


def test_array_items_keep_their_type_without_a_conversion_per_store(tmp_path, capsys):
    # An INTEGER stored into an ARRAY OF REAL is a REAL; an array passed by value is a copy.
    code, out, err, _ = run(
        tmp_path, capsys,
        HEAD + "TYPE v = ARRAY [0..2] OF REAL;\nVAR v: a, b; INTEGER: i;\n"
        "PROCEDURE bump(v: c);\nBEGIN\n  c[0] := 99;\n  WRITELN(c);\nENDPROC;\nBEGIN\n"
        "  FOR i := 0 TO 2 DO a[i] := i * 2; ENDFOR;\n  b := a;\n  bump(b);\n"
        "  WRITELN(a, b[2]);\nENDPROGRAM\n",
        "--json",
    )  # fmt: skip
    assert code == 0, err
    assert json.loads(out)["output"] == ["(99.0, 2.0, 4.0)", "(0.0, 2.0, 4.0)4.0"]


@pytest.mark.parametrize(
    "body",
    [
        "WHILE TRUE DO OUT[1] := TRUE; ENDWHILE;",  # scanned every event: O(n²), > 60 s
        "WHILE TRUE DO OUT[1] := NOT OUT[1]; PULSE(OUT[2], 1); ENDWHILE;",  # read: O(n) each
    ],
)
def test_switching_outputs_in_a_loop_takes_linear_time(tmp_path, capsys, body):
    code, _, err, cpu = run(
        tmp_path, capsys, HEAD + f"BEGIN\n  {body}\nENDPROGRAM\n", "--instruction-budget", "200000"
    )
    assert code == 2 and "more than 200000 instructions without motion" in err, err
    assert cpu < 20


def test_the_output_of_a_run_is_bounded(tmp_path, capsys):
    # 83,000 lines of 32,768 characters: a MemoryError (exit 4) after a minute.
    code, _, err, cpu = run(
        tmp_path, capsys,
        HEAD + "VAR STRING: s; INTEGER: i;\nBEGIN\n  s := 'abcdefghijklmnop';\n"
        "  FOR i := 1 TO 11 DO s := s + s; ENDFOR;\n  WHILE TRUE DO WRITELN(s, i); ENDWHILE;\n"
        "ENDPROGRAM\n",
    )  # fmt: skip
    assert code == 2, err
    assert (
        "p.irl:7:3: error: run-time failure at t = 0.000 s: the program's output would exceed"
        f" {MAX_OUTPUT_CHARS} characters — endless loop?"
    ) in err
    assert cpu < 20


def test_a_huge_value_is_refused_before_its_text_is_built(tmp_path, capsys):
    # A million strings of 32,768 characters (64 GB of text) cost a few thousand stores.
    code, _, err, cpu = run(
        tmp_path, capsys,
        HEAD + "VAR ARRAY [1..1000] OF STRING: row;\n"
        "  ARRAY [1..1000] OF ARRAY [1..1000] OF STRING: a; STRING: s; INTEGER: i;\nBEGIN\n"
        "  s := 'abcdefghijklmnop';\n"
        "  FOR i := 1 TO 11 DO s := s + s; ENDFOR;\n  FOR i := 1 TO 1000 DO row[i] := s; ENDFOR;\n"
        "  FOR i := 1 TO 1000 DO a[i] := row; ENDFOR;\n  WRITELN(a);\nENDPROGRAM\n",
    )  # fmt: skip
    assert code == 2, err
    assert "p.irl:10:3: error: run-time failure" in err and "output would exceed" in err
    assert cpu < 20


@pytest.mark.parametrize("body", ["g := TRUE;", "PAUSE;", "OUT[3] := TRUE;"])
def test_events_of_a_run_are_bounded(tmp_path, capsys, monkeypatch, body):
    # Each event is a dict kept to the end; a loop of them under a raised budget (or
    # between motions) grew the memory without bound. 2,000 stands for MAX_EVENTS here.
    from irlc.runtime.interpreter import io

    assert MAX_EVENTS == 200_000
    monkeypatch.setattr(io, "MAX_EVENTS", 2_000)
    code, _, err, _ = run(
        tmp_path, capsys,
        HEAD + f"VAR SIGNAL: g;\nBEGIN\n  WHILE TRUE DO {body} ENDWHILE;\nENDPROGRAM\n",
    )  # fmt: skip
    assert code == 2, err
    assert "p.irl:5:3: error: run-time failure at t = 0.000 s: more than 2000 events" in err


def test_text_bound_is_an_upper_bound_of_the_text() -> None:
    rng = random.Random(7)
    for _ in range(300):
        items = [
            rng.choice([True, -(2**63), rng.uniform(-1e308, 1e308), -1.2345678901234567e-300,
                        "x" * rng.randrange(5), pose_from_zyx(*[rng.uniform(-1e300, 1e300)] * 6)])
            for _ in range(rng.randrange(1, 5))
        ]  # fmt: skip
        v = ArrayValue(1, tuple(items))
        assert len(format_value(v)) <= text_bound(v)


def test_value_at_is_the_last_switch_at_or_before_the_time() -> None:
    rng = random.Random(3)
    times = sorted(rng.choice([0.0, 0.5, 1.0, 1.5, 2.0]) for _ in range(40))
    timeline = [(t, rng.random() < 0.5) for t in times]
    for t in [-1.0, 0.0, 0.25, 0.5, 1.0 - 1e-12, 1.0, 1.7, 2.0, 3.0]:
        linear = [v for time_, v in timeline if time_ <= t + 1e-9]
        assert value_at(timeline, t) == (linear[-1] if linear else False)


def test_an_array_of_unset_items_shares_one_initial_value() -> None:
    from irlc.runtime.interpreter.datatypes import DataTypes

    a = DataTypes([], ["a1"]).initial("ARRAY[1..1000000]OFARRAY[0..1]OFREAL")
    assert len(a.items) == 1_000_000 and a.items[0] is a.items[-1]
    assert a.items[0].items == (UNSET, UNSET) and a.elem == "ARRAY[0..1]OFREAL"


def test_running_out_of_memory_is_an_environment_error(tmp_path, capsys, monkeypatch):
    # --drives pwm at --override 1 allocated (4186001, 10) arrays: MemoryError, exit 4.
    from irlc.runtime import run as run_module

    def exhausted(*args, **kwargs):
        raise MemoryError("Unable to allocate 319. MiB")

    monkeypatch.setattr(run_module, "run_file", exhausted)
    prog = tmp_path / "p.irl"
    prog.write_text(HEAD + "BEGIN\n  WAIT 1 SEC;\nENDPROGRAM\n", "utf-8")
    assert main(["run", str(prog), "-q"]) == 3
    err = capsys.readouterr().err
    assert err.startswith("irlc: error: out of memory: the command needs more memory") and (
        "internal error" not in err
    )


# The cycle budget (--max-cycles): what a run computes grows with its IPO cycles of motion;
# a 600 s LIN on koch11 took 22 s of CPU, `--ipo 0.00001` made the square 1.3 M cycles.
MOVES = (
    HEAD + "BEGIN\n  MOVE PTP (10, 20, 30) WITH TIME := 5;\n"
    "  MOVE PTP (0, 20, 30) WITH TIME := 5;\nENDPROGRAM\n"
)
WAITS = (
    HEAD + "BEGIN\n  MOVE PTP (10, 20, 30) WITH TIME := 5;\n  WAIT 0.5 SEC;\n"
    "  WAIT 30 SEC;\n  MOVE PTP (0, 20, 30) WITH TIME := 5;\nENDPROGRAM\n"
)


@pytest.mark.parametrize("program, cycles", [(MOVES, 1000), (WAITS, 1000 + 50 + 1001)])
def test_the_cycle_budget_is_the_cycles_the_run_records(tmp_path, capsys, program, cycles):
    # motion cycles, and the cycles a WAIT records (30 s: its first 1,000 and its last)
    code, out, err, _ = run(tmp_path, capsys, program, "--json")
    assert code == 0, err
    assert json.loads(out)["samples"] - 1 == cycles  # the samples after the start one
    code, _, err, _ = run(tmp_path, capsys, program, "--max-cycles", str(cycles))
    assert code == 0, err
    code, _, err, _ = run(tmp_path, capsys, program, "--max-cycles", str(cycles - 1))
    assert code == 2
    t = "5.000" if program is MOVES else "35.500"
    assert (
        f"error: run-time failure at t = {t} s: the motion would take 500 IPO cycles and the"
        f" run past its budget of {cycles - 1} simulated cycles ({cycles - 500} so far, at t"
        f" = {t} s; raise it with --max-cycles)"
    ) in err


def test_a_wait_is_charged_the_cycles_it_records(tmp_path, capsys):
    code, _, err, _ = run(tmp_path, capsys, WAITS, "--max-cycles", "1549")
    assert code == 2
    assert "p.irl:6:3: error: run-time failure at t = 5.500 s: the WAIT would take 1001 IPO" in err


def test_a_motion_statement_is_charged_at_least_five_cycles(tmp_path, capsys):
    # planning and the target's reachability check cost even when nothing moves: 50,000
    # motions that do not move, each between two that do, would otherwise each restart the
    # loop guard's count
    from irlc.runtime.control.executor import MOTION_MIN_CYCLES

    assert MOTION_MIN_CYCLES == 5
    prog = HEAD + "BEGIN\n  MOVE PTP R_ACT_JOINT;\n  MOVE PTP R_ACT_JOINT;\nENDPROGRAM\n"
    code, _, err, _ = run(tmp_path, capsys, prog, "--max-cycles", "9")
    assert code == 2 and "p.irl:5:3:" in err, err
    assert (
        "the motion would take 5 cycles of the budget (0 IPO cycles; a motion statement counts"
        " at least 5) and the run past its budget of 9 simulated cycles (5 so far"
    ) in " ".join(err.split())
    code, _, err, _ = run(tmp_path, capsys, prog, "--max-cycles", "10")
    assert code == 0, err


def test_a_loop_of_one_cycle_motions_meets_the_budget_five_times_sooner(tmp_path, capsys):
    # one-cycle LINs (10 ms each): the 21st of them is the first past 100 cycles
    prog = (
        "PROGRAM p;\nROBOT r := koch11;\nBEGIN\n  WHILE TRUE DO\n"
        "    MOVE_INC LIN (0.001, 0, 0, 0, 0, 0); MOVE_INC LIN (-0.001, 0, 0, 0, 0, 0);\n"
        "  ENDWHILE;\nENDPROGRAM\n"
    )
    code, _, err, _ = run(tmp_path, capsys, prog, "--max-cycles", "100")
    assert code == 2, err
    text = " ".join(err.split())
    assert "p.irl:5:5: error: run-time failure at t = 0.200 s: the motion would take 5" in text
    assert "(1 IPO cycle; a motion statement counts at least 5)" in text
    assert "(100 so far, at t = 0.200 s;" in text


def test_a_small_ipo_cycle_meets_the_default_cycle_budget_at_once(tmp_path, capsys):
    from irlc.runtime.control.executor import DEFAULT_MAX_CYCLES

    code, _, err, cpu = run(tmp_path, capsys, MOVES, "--ipo", "0.00001")
    assert code == 2, err
    assert "at t = 0.000 s: the motion would take 500000 IPO cycles" in err
    assert f"budget of {DEFAULT_MAX_CYCLES} simulated cycles" in err
    assert cpu < 10  # not 500,000 cycles simulated first


def test_the_cycle_budget_takes_whole_positive_numbers(tmp_path, capsys):
    from irlc.runtime.run import check_run_option

    for bad in ("0", "-5"):
        code, _, err, _ = run(tmp_path, capsys, MOVES, "--max-cycles", bad)
        assert code == 3 and f"--max-cycles must be a positive integer, got {bad}" in err
    assert check_run_option("max_cycles", 10) is None
    assert check_run_option("max_cycles", 2.5) == ("max_cycles must be a positive integer, got 2.5")


def test_motions_that_do_not_move_are_charged_to_the_loop_guard(tmp_path, capsys):
    # 100,000 MOVE PTP R_ACT_JOINT cost 0.3 ms each to plan: 32 s before the guard fired.
    code, _, err, cpu = run(
        tmp_path, capsys,
        HEAD + "VAR INTEGER: i;\nBEGIN\n  FOR i := 1 TO 100000 DO MOVE PTP R_ACT_JOINT; ENDFOR;\n"
        "ENDPROGRAM\n",
    )  # fmt: skip
    assert code == 2, err
    assert "more than 500000 instructions without motion" in err
    assert "a motion that does not move counts as 250" in err
    assert cpu < 10


def test_a_reconfiguration_charges_its_settling_cycles_as_they_run(tmp_path, capsys):
    # 10 s of settling at 1 ms would be 10,000 cycles; it settles after a few
    prog = HEAD + "BEGIN\n  RECONFIGURATION (0, 60, -60);\nENDPROGRAM\n"
    code, out, err, _ = run(tmp_path, capsys, prog, "--json", "--ipo", "0.001")
    assert code == 0, err
    cycles = json.loads(out)["samples"] - 1
    code, _, err, _ = run(tmp_path, capsys, prog, "--ipo", "0.001", "--max-cycles", str(cycles))
    assert code == 0, err
    code, _, err, _ = run(tmp_path, capsys, prog, "--ipo", "0.001", "--max-cycles", str(cycles - 1))
    assert code == 2 and "the RECONFIGURATION" in err and "--max-cycles" in err, err


def test_golden_options_and_the_api_take_the_budgets(tmp_path):
    from irlc import golden, run_program

    prog = tmp_path / "p.irl"
    prog.write_text(MOVES, "utf-8")
    expected = tmp_path / "p.expected.json"
    expected.write_text(json.dumps({"options": {"max_cycles": 700, "max_time": 100}}))
    report = golden.default_runner(prog, golden.load_expectation(expected)["options"])
    assert report["status"] == "failed" and "budget of 700 simulated cycles" in json.dumps(report)
    run = run_program(prog, max_time=7.5)
    assert run.status == "failed" and "simulated-time budget of 7.5 s" in run.error.message


def test_with_drives_the_cycle_budget_counts_their_steps(tmp_path, capsys):
    """The drives step through all of the run's time (a long WAIT's too) at their own
    step, 10 steps to a cycle of the budget; the run fails before either stage simulates."""
    import math

    from irlc.runtime.control.executor import DRIVE_STEPS_PER_CYCLE

    head = "PROGRAM p;\nROBOT r := irb6;\nBEGIN\n"
    code, out, err, _ = run(tmp_path, capsys, head + "  WAIT 2 SEC;\nENDPROGRAM\n", "--json",
                            "--drives", "decoupled")  # fmt: skip
    assert code == 0, err
    h = json.loads(out)["drives_summary"]["step_s"]  # the step the drive stage took
    wait = head + "  WAIT 30 SEC;\nENDPROGRAM\n"  # 1001 recorded cycles
    code, _, err, _ = run(tmp_path, capsys, wait, "--max-cycles", "2000")
    assert code == 0, err
    code, _, err, cpu = run(tmp_path, capsys, wait, "--max-cycles", "2000", "--drives", "decoupled")
    assert code == 2
    steps = math.ceil(30 / h - 1e-3)  # step_s is rounded to 9 digits in the report
    charged = math.ceil(steps / DRIVE_STEPS_PER_CYCLE)
    assert (
        f"p.irl:4:3: error: run-time failure at t = 0.000 s: the WAIT would take {charged}"
        f" cycles of the budget ({steps} drive steps of {h * 1e3:.3g} ms,"
        f" {DRIVE_STEPS_PER_CYCLE} to a cycle) and"
        " the run past its budget of 2000 simulated cycles"
    ) in err
    assert cpu < 20  # not 90,000 drive steps first
