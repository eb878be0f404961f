"""Compile time grows linearly with the program's length (issue 11: a 1 MB program took
17–19 s to check; parse + check should stay near 10,000 lines/s).

The guards are deterministic where they can be: no cycle collection runs during a compile
(full collections over the growing heap were the superlinear part), and the number of Python
function calls for 4N lines is 4× that for N lines (a quadratic loop in Python shows up as
a 16× ratio). One generous CPU-time ratio also catches quadratic work inside C calls.
"""

from __future__ import annotations

import cProfile
import gc
import pstats
import time

import pytest
from irlc.lang import compiler

from .conftest import compile_text

HEAD = """PROGRAM speed;
ROBOT r := koch11;
VAR REAL: x, y; INTEGER: i; POSE: p; STRING: s;
PROCEDURE corner(POSE: c);
BEGIN
  MOVE LIN c;
ENDPROC;
BEGIN
  x := 0; y := 0;
"""

BLOCK = """  x := x + {i} * 0.5 - y / 3;
  IF x > 1000 THEN
    x := 0;
  ELSIF x < -1000 THEN
    x := 1;
  ELSE
    y := y + SIN(x) * COS(y);
  ENDIF;
  WHILE y > {i} DO
    y := y - 1;
  ENDWHILE;
  FOR i := 1 TO {i} DO
    s := 'lap';
  ENDFOR;
  p := POSE(11500, {i}, 3500, 0, 0, 0);
  MOVE LIN p WITH SPEED := 500;
  corner(p);
  WRITELN('step ', i, ' ', x);
"""
BLOCK_LINES = BLOCK.count("\n")


def program(blocks: int) -> str:
    return HEAD + "".join(BLOCK.format(i=i + 1) for i in range(blocks)) + "ENDPROGRAM\n"


def test_the_program_compiles() -> None:
    result = compile_text(program(3))
    assert result.ok, [d.header() for d in result.errors]


def test_no_cycle_collection_runs_during_a_compile(monkeypatch: pytest.MonkeyPatch) -> None:
    """From the parser's start to the code generator's end (after it, the restarted
    collector may run at once: that is one pass, not one per 25 % of heap growth)."""
    collections: list[int] = []
    marks: dict[str, int] = {}

    def count(phase: str, info: dict) -> None:
        if phase == "start":
            collections.append(info["generation"])

    real_parse, real_generate = compiler.parse, compiler.generate

    def parse(*args):
        marks["parse"] = len(collections)
        return real_parse(*args)

    def generate(*args):
        code = real_generate(*args)
        marks["generated"] = len(collections)
        return code

    monkeypatch.setattr(compiler, "parse", parse)
    monkeypatch.setattr(compiler, "generate", generate)
    text = program(200)  # 3,600 lines: hundreds of thousands of allocations
    gc.callbacks.append(count)
    try:
        result = compile_text(text)
    finally:
        gc.callbacks.remove(count)
    assert result.ok
    assert marks["generated"] == marks["parse"], collections
    assert gc.isenabled()


def test_a_paused_collector_stays_paused_after_a_compile() -> None:
    gc.disable()
    try:
        assert compile_text(program(2)).ok
        assert not gc.isenabled()
    finally:
        gc.enable()


def _calls(text: str) -> int:
    profile = cProfile.Profile()
    profile.enable()
    result = compile_text(text)
    profile.disable()
    assert result.ok
    return pstats.Stats(profile).total_calls  # type: ignore[attr-defined]


def test_function_calls_grow_linearly_with_the_program() -> None:
    compile_text(program(2))  # lark's tables are built once per process
    small, large = _calls(program(50)), _calls(program(200))
    # (large - small) is the work of 150 blocks, small ≈ that of 50 blocks plus a constant
    assert 2.9 < large / small < 4.1, (small, large)


@pytest.mark.scenario
def test_compile_time_grows_linearly_with_the_program() -> None:
    compile_text(program(2))
    n = 300  # 5,400 lines; 4n: 21,600 lines (≈ 440 kB)

    def cpu(blocks: int) -> float:
        text = program(blocks)
        best = float("inf")
        for _ in range(2):
            t0 = time.process_time()
            assert compile_text(text).ok
            best = min(best, time.process_time() - t0)
        return best

    small, large = cpu(n), cpu(4 * n)
    assert large / small < 8.0, (small, large)  # linear: ≈ 4; quadratic: ≈ 16
