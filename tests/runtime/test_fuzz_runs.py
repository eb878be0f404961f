"""Fuzz runs of hostile values (issue 11): a compiled planar3 program whose constants are
replaced by hostile numbers (huge, denormal, negative, zero) must end ``ok`` or with a
positioned run failure — never another exception — within its simulated-time budget.
Hostile statements (large arrays, loops of outputs, events and WRITE, built-ins on extreme
numbers) in any order end the same way, in bounded time and memory."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st
from irlc.lang import read_code, write_code
from irlc.lang.compiler import compile_source
from irlc.robots import RobotFileError, resolver
from irlc.runtime.run import RunSetupError, run_code

from ..fuzz_budget import fuzz_settings, warm_up_kernels

SOURCE = """PROGRAM f;
ROBOT r := planar3;
VAR POSE: p; REAL: t;
BEGIN
  R_SPEED := 500;
  R_ACC := 2000;
  t := 0.05;
  p := POSE(1500, 500, 0, 0, 0, 0);
  MOVE LIN p;
  WAIT t SEC;
  MOVE PTP (10, 20, 30) WITH TIME := 5;
  R_TOOL := POSE(10, 0, 0, 0, 0, 0);
  MOVE_INC LIN POSE(-10, 20, 0, 0, 0, 0);
  RECONFIGURATION (0, 60, -60);
  MOVE PTP R_ACT_JOINT;
ENDPROGRAM
"""
warm_up_kernels()  # at import: the kernels' one-time compile is no case's hang
IRD = write_code(compile_source(SOURCE, "f.irl", resolve_robot=resolver()).code)
CONSTS = [k for k, line in enumerate(IRD.split("\n")) if " CONST " in line]
HOSTILE = st.sampled_from(
    [0.0, -0.0, -1.0, 1e-320, 4.9e-324, 1e-300, 1e300, -1e308, 1e308, 1e6, 1e9, 200.0, -200.0]
)


@fuzz_settings(80)
@given(st.lists(st.tuples(st.integers(0, 10**6), st.integers(0, 5), HOSTILE), max_size=3))
def test_fuzz_hostile_values_in_motion(edits) -> None:
    lines = IRD.split("\n")
    for where, pos, value in edits:
        k = CONSTS[where % len(CONSTS)]
        words = lines[k].split(" ")
        numbers = [i for i, w in enumerate(words[4:], start=4) if w[:1] in "-0123456789"]
        if not numbers:
            continue
        i = numbers[pos % len(numbers)]
        words[i] = str(int(value)) if words[3] == "INTEGER" else repr(value)
        lines[k] = " ".join(words)
    code = read_code("\n".join(lines), "f.ird")
    try:
        run = run_code(code, max_time=60.0)
    except (RunSetupError, RobotFileError):
        return
    assert run.status in ("ok", "error") or run.error is not None
    if run.error is not None:
        assert run.error.line is not None, run.error


STATEMENTS = [
    "x := DIST(POSITION(1e300, 0, 0), POSITION(-1e300, 0, 0));",
    "x := DIST(p, POSITION(big, 0, 0));", "o := ORIQUAT(big, big, 0, 0);",
    "o := ORIVANG(POSITION(0, 0, tiny), 90);", "o := ORIQUAT(tiny, 0, 0, 0);",
    "o := ORIRS(big, tiny, 0);", "x := x * big;", "x := x / tiny;", "i := i * 2147483647;",
    "i := ROUND(x);", "i := i DIV j;", "i := i MOD j;", "j := 0;", "j := -1;",
    "i := -9223372036854775807 - 1;", "a[i] := x;", "a[1] := i;", "b := a;",
    "big_a[i MOD 1000000 + 1] := x;", "big_a[1] := 1;", "WRITELN(a);", "WRITELN(big_a);",
    "WRITELN(s, x, o, p);", "s := s + s;", "WHILE TRUE DO OUT[1] := NOT OUT[1]; ENDWHILE;",
    "WHILE TRUE DO PULSE(OUT[2], 0.5); g := TRUE; ENDWHILE;",
    "WHILE TRUE DO WRITELN(s); ENDWHILE;", "WHILE TRUE DO big_a[3] := x; ENDWHILE;", "rec(0);",
    "FOR k := 1 TO 1000000 DO a[k MOD 3 + 1] := k; ENDFOR;", "WAIT tiny SEC;", "WAIT x SEC;",
    "MOVE PTP (10, 20, 30);", "MOVE LIN POSE(x, 500, 0, 0, 0, 0);",
    "p := POSE(big, 0, 0, 0, 0, 0);", "R_TOOL := POSE(0, 0, 0, x, 0, 0);", "PAUSE;",
]  # fmt: skip
PROGRAM = """PROGRAM f;
ROBOT r := planar3;
VAR REAL: x, big, tiny; INTEGER: i, j, k; STRING: s; ORIENTATION: o; POSE: p; SIGNAL: g;
  ARRAY [1..3] OF REAL: a, b; ARRAY [1..1000000] OF REAL: big_a;
PROCEDURE rec(INTEGER: n);
VAR ARRAY [1..1000000] OF REAL: local;
BEGIN
  local[1] := n;
  rec(n + 1);
ENDPROC;
BEGIN
  x := 1500; big := 1e308; tiny := 4.9e-324; i := 2; j := 3; s := 'ab';
  p := POSE(1500, 500, 0, 0, 0, 0); a[1] := 1; a[2] := 2; a[3] := 3;
{}
ENDPROGRAM
"""


@fuzz_settings(30)
@given(st.lists(st.sampled_from(STATEMENTS), min_size=1, max_size=6))
def test_fuzz_hostile_statements(statements) -> None:
    body = "\n".join("  " + t for t in statements)
    result = compile_source(PROGRAM.format(body), "f.irl", resolve_robot=resolver())
    assert result.ok, [d.header() for d in result.errors]
    run = run_code(result.code, max_time=60.0, instruction_budget=100_000)
    assert run.status in ("ok", "failed"), run.status
    if run.error is not None:
        assert run.error.line is not None and run.error.line >= 1, run.error
