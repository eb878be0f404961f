"""Fuzz REPL lines (issue 11): a session survives any line — each entry ends with a status
of 0, 1, 2 or 3 (never 4, never an exception), a failing entry says where
(``<stdin>:LINE:COL: error: …``), and the next entry still runs."""

from __future__ import annotations

import re

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ..fuzz_budget import fuzz_settings, warm_up_kernels

LINES = [
    "VAR REAL: x;", "x := 1;", "x := x * 1e300;", "x := x / 0;", "WAIT 1e308 SEC;",
    "WAIT 0.02 SEC;", "WAIT -1 SEC;", "MOVE PTP (10, 20, 30);", "MOVE PTP (0, 200, 0);",
    "MOVE LIN POSE(1e308, 0, 0, 0, 0, 0);", "MOVE LIN POSE(1500, 500, 0, 0, 0, 0);",
    "MOVE_INC LIN POSE(1e308, 0, 0, 0, 0, 0);", "R_TOOL := POSE(1e300, 0, 0, 0, 0, 0);",
    "R_TOOL := POSE(0, 0, 0, 0, 0, 0);", "R_SPEED := 1e-320;", "R_SPEED := 500;",
    "R_IPO := 0;", "RECONFIGURATION (1e300, 0, 0);", "IF TRUE THEN", "ENDIF;", "ENDPROGRAM",
    "IMPORT DATALIST nosuch;", "IMPORT DATALIST " + "d" * 300 + ";", ":robot nosuch",
    ":where", ":options", ":limits", ":program", ":nosuch", "PROCEDURE q; BEGIN q; ENDPROC",
    "q;", "VAR STRING: s;", "s := 'ab';", "s := s + s + s + s + s + s + s + s;",
    "x := " + "9" * 5000 + ";", "x := " + "-" * 600 + "x;", "{ unclosed", "'", "(*",
    "\u2028", "\x00", "POSE: p := (1, 2, 3, 4, 5, 6);", "JOINTLIMIT (0,0,0), (1,1,1);",
    ":robot /nonexistent.toml", ":trace", ":teach", ":teach R_SPEED", ":teach a b c",
    "ROBOT r := x;",
    "POSE: a, b := (1, 2, 3, 4, 5, 6);", "JOINTLIMITEND;", "VAR ARRAY [1..1000000] OF REAL: big;",
    "big[1] := 1;", "WRITELN(big);", "x := DIST(POSITION(1e300, 0, 0), POSITION(-1e300, 0, 0));",
    "WHILE TRUE DO OUT[1] := TRUE; ENDWHILE;",
]  # fmt: skip
POSITIONED = re.compile(r"^<stdin>:\d+:\d+: error: ", re.M)


@pytest.fixture(scope="module")
def session_class():
    pytest.importorskip("irlc.runtime.control.executor")
    from irlc.repl import Session

    warm_up_kernels()  # the kernels' one-time compile is no case's hang

    return Session


@fuzz_settings(100)
@given(st.lists(st.sampled_from(LINES) | st.text(max_size=12), min_size=1, max_size=6))
def test_fuzz_repl_lines(session_class, lines: list[str]) -> None:
    session = session_class("planar3")
    for k, line in enumerate(lines, start=1):
        entry = session.enter(line, k)
        assert entry.failure in (0, 1, 2, 3), (line, entry.lines)
        if entry.failure:
            assert POSITIONED.search("\n".join(entry.lines)), (line, entry.lines)
    assert session.enter("WRITELN(1 + 1);").lines[-1] == "2"
