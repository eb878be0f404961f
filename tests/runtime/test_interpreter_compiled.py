"""Interpreter on code from the real compiler (IRL source → IRDATA text → read back → run)."""

from __future__ import annotations

import math

import pytest
from irlc.lang.irdata import read_code, write_code
from irlc.robots import load_robot
from irlc.runtime.interpreter import Interpreter

from .test_interpreter_fakes import FakeController

compiler = pytest.importorskip("irlc.lang.compiler")

LANGUAGE = """PROGRAM snip;
ROBOT r := planar3;
TYPE
  RECORD INTEGER: n; REAL: v; ENDRECORD = ITEM;
VAR
  INTEGER: i, s;  REAL: x;  ARRAY [1..3] OF REAL: a;  ITEM: it;  POSE: p, q;

PROCEDURE swap(VAR INTEGER: u; VAR INTEGER: w);
VAR INTEGER: t;
BEGIN
  t := u; u := w; w := t;
ENDPROC;

FUNCTION fact(INTEGER: n): INTEGER;
BEGIN
  IF n <= 1 THEN RETURN 1; ENDIF;
  RETURN n * fact(n - 1);
ENDFCT;

BEGIN
  s := 0;
  FOR i := 1 TO 10 DO s := s + i; ENDFOR;
  WRITELN('sum ', s, ' fact ', fact(6));
  i := 3; x := 7 / 2;
  swap(i, s);
  WRITELN(i, ' ', s, ' ', x, ' ', 7 DIV 2, ' ', -7 MOD 3);
  a[1] := 1; a[2] := 2.5; a[3] := a[1] + a[2];
  WRITELN(a[3]);
  it.n := 4; it.v := SQRT(2);
  WRITELN(it.n, ' ', it.v);
  CASE s OF 1: WRITELN('one'); 2, 3: WRITELN('two or three'); ELSE WRITELN('other'); ENDCASE;
  p := (100, 0, 0, 90, 0, 0);
  q := (10, 0, 0, 0, 0, 0);
  WRITELN(p : q, ' ', INV(p));
  REPEAT i := i - 1; UNTIL i <= 0;
  WRITELN(i);
ENDPROGRAM
"""


def compile_text(text: str, filename: str):
    result = compiler.compile_source(text, filename, resolve_robot=load_robot)
    assert result.code is not None, result.diagnostics
    return read_code(write_code(result.code), "snip.ird")  # the runtime runs the text form


def test_compiled_program_runs_like_pascal():
    out = Interpreter(compile_text(LANGUAGE, "snip.irl"), FakeController()).run().output
    # independent values: Σ1..10, 6!, √2 to 6 decimals; p : q moves 10 mm along p's x = world y
    assert out == [
        f"sum {sum(range(1, 11))} fact {math.factorial(6)}",
        "55 3 3.5 3 -1",
        "3.5",
        f"4 {round(math.sqrt(2), 6)}",
        "two or three",
        "(100.0, 10.0, 0.0, 90.0, 0.0, 0.0) (0.0, 100.0, 0.0, -90.0, 0.0, 0.0)",
        "0",
    ]


IO = """PROGRAM io;
ROBOT r := planar3;
IMPORT DATALIST cell;
VAR SIGNAL: gripper; MAIN_JOINT: k; MAIN_JOINT_MIN: jmin; MAIN_JOINT_MAX: jmax;
BEGIN
  k := (10, 20, 30);
  MOVE PTP k WITH SPEED_PTP := 20;
  WAIT FOR IN[2];
  gripper := TRUE;
  WRITELN('gripped');
  jmin := (-90, -90, -90); jmax := (90, 90, 25);
  JOINTLIMIT jmin, jmax;
  JOINTLIMITEND;
ENDPROGRAM
"""


def test_compiled_io_and_limit_check(tmp_path):
    (tmp_path / "cell.toml").write_text("[inputs]\n2 = [[0.0, false], [3.5, true]]\n")
    code = compile_text(IO, str(tmp_path / "io.irl"))
    ctl = FakeController()
    result = Interpreter(code, ctl).run(check=False)
    assert ctl.moves[0][0].speed_ptp == 20.0
    assert ctl.t == 3.5  # 1 s fake PTP, then WAIT FOR until the input rises at 3.5 s
    assert result.output == ["gripped"]
    assert result.events == [
        {"kind": "signal", "line": 9, "time_s": 3.5, "name": "gripper", "value": True}
    ]
    assert result.error.message == (
        "JOINTLIMIT excludes the current state: joint a3 is at 30.0 deg,"
        " above the upper bound 25.0 deg"
    )
    assert (result.error.line, result.error.time_s) == (12, 3.5)
