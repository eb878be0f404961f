"""Fuzz the header tables of ``.ird`` code and *run* what reads (issue 11, helper h7): a
hostile type, constant, obstacle, input or slot record is a read error at its line or a
run that ends with a result — never an exception, a hang, or an unpositioned failure
before the first instruction (the classes the CLI harness found: a 2**64-cell array,
a record type containing itself, constants of the wrong shape)."""

from __future__ import annotations

import re

from hypothesis import given
from hypothesis import strategies as st
from irlc.lang import CompileError, compile_source, read_code, write_code
from irlc.lang.errors import IrlcError
from irlc.robots import resolver
from irlc.runtime.run import run_code

from ..fuzz_budget import fuzz_settings

SOURCE = """PROGRAM t;
ROBOT r := planar3;
TYPE
  RECORD REAL: x; INTEGER: n; ENDRECORD = pt;
VAR
  INTEGER: i;
  pt: p;
  ARRAY[1..3] OF REAL: a;
PROCEDURE q(INTEGER: k);
VAR REAL: tmp;
BEGIN
  tmp := k;
ENDPROC;
BEGIN
  i := 2;
  p.x := 1.5;
  a[2] := p.x;
  q(i);
  MOVE PTP (0, 90, -90);
  WRITELN('x', a[2]);
ENDPROGRAM
"""
SEED = write_code(compile_source(SOURCE, "t.irl", resolve_robot=resolver()).code)
HEADER_OPS = ("CONST", "GLOBAL", "TYPE", "PARAM", "LOCAL", "ROUTINE", "JOINTS", "ROBOT")
HOSTILE = [
    "ARRAY[1..1000000000]OFREAL", "ARRAY[-9223372036854775808..9223372036854775807]OFREAL",
    "ARRAY[1..1000000]OFARRAY[1..1000000]OFREAL", "ARRAY[3..1]OFREAL", "ARRAY[1..2]OFSIGNAL",
    "RECORD#0", "RECORD#1", "RECORD#-1", "RECORD#99999999999", "SIGNAL", "POSE", "ORIENTATION",
    "MAIN_JOINT", "STRING", "CHAR", "BOOLEAN", "FOO", "x:RECORD#0", "n", "0", "1", "2", "-1",
    "1e308", "nan", "@1", "'a'", "''", "E'\\u0000'", "0.0 0.0 0.0 0.0", "1.0 2.0", "FUNC:POSE",
    "FUNC:RECORD#5", "PROC", "MAIN", "a1", "RRR", "RRRR", "3", "99",
]  # fmt: skip


def _header_records(text: str) -> list[int]:
    lines = text.split("\n")
    return [k for k, s in enumerate(lines) if re.match(rf"\d+ ({'|'.join(HEADER_OPS)}) ", s)]


HEADER = _header_records(SEED)


@fuzz_settings(150)
@given(
    st.lists(
        st.tuples(st.sampled_from(HEADER), st.integers(2, 8), st.sampled_from(HOSTILE)),
        min_size=1,
        max_size=3,
    )
)
def test_fuzz_hostile_header_records_read_or_run_to_an_end(edits) -> None:
    lines = SEED.split("\n")
    for k, where, token in edits:
        words = lines[k].split(" ")
        words[min(where, len(words) - 1)] = token
        lines[k] = " ".join(words)
    text = "\n".join(lines)
    try:
        code = read_code(text, "bad.ird")
    except CompileError as e:
        assert all(d.span is not None and d.span.line >= 1 for d in e.diagnostics)
        assert all(len(d.message) < 300 for d in e.diagnostics)
        return
    try:
        result = run_code(code, instruction_budget=20_000, max_time=60.0)
    except IrlcError as e:  # a setup error (the robot of a changed ROBOT record): positioned
        assert "bad.ird:" in str(e) or "the code records no position" in str(e), str(e)
        return
    assert result.status in ("ok", "failed")
