"""Compile-time warnings where approximate positioning ends with an exact stop
(lang/approx_lint.py), and the APPROX hint for other languages' words."""

from __future__ import annotations

import pytest

from .conftest import compile_text

HEAD = "PROGRAM t;\nROBOT r := six;\nVAR\n  POSE: p;\n  BOOLEAN: b;\nBEGIN\n"
P = "  p := POSE(400, 0, 500, 0, 0, 180);\n"  # line 7


def _warnings(body: str) -> list[tuple[int, str]]:
    result = compile_text(HEAD + P + body + "ENDPROGRAM\n")
    assert result.ok, [d.header() for d in result.diagnostics]
    return [(d.span.line, d.message) for d in result.warnings]


@pytest.mark.parametrize(
    ("statement", "why"),
    [
        ("WAIT 0.5 SEC;", "WAIT"),
        ("WAIT FOR b;", "WAIT FOR"),
        ("PAUSE;", "PAUSE"),
        ("IF IN[1] THEN\n    b := TRUE;\n  ENDIF;", "reading an input"),
        ("p := R_ACT_POSE;", "reading R_ACT_POSE"),
        ("CYCLICSTART;\n  CYCLICEND;", "switching CYCLIC on"),
        ("R_TOOL := POSE(0, 0, 10, 0, 0, 0);", "changing R_TOOL"),
    ],
)
def test_advance_run_stops_after_an_approximated_motion(statement, why):
    body = f"  MOVE LIN p WITH APPROX := 20;\n  {statement}\n  MOVE LIN p;\n"
    ((line, message),) = _warnings(body)
    assert line == 9 and message.startswith(why)
    assert "the approximated motion on line 8 ends with an exact stop" in message


@pytest.mark.parametrize(
    "body",
    [
        "  MOVE LIN p WITH APPROX := 0;\n  WAIT 0.5 SEC;\n  MOVE LIN p;\n",  # exact stop
        "  MOVE LIN p WITH APPROX := 20;\n  R_SPEED := 100;\n  b := TRUE;\n  MOVE LIN p;\n",
        "  MOVE LIN p WITH APPROX := 20;\n  MOVE PTP p;\n",  # LIN → PTP is blended
        "  MOVE LIN p;\n  WAIT 0.5 SEC;\n",  # not approximated
        "  R_APPROX := 10;\n  MOVE LIN p;\n  R_APPROX := 0;\n  MOVE LIN p;\n  WAIT 1 SEC;\n",
        "  R_APPROX := 10;\n  MOVE LIN p;\n",  # modal: the last point is simply exact
    ],
)
def test_no_warning_where_nothing_is_lost(body):
    assert _warnings(body) == []


def test_modal_r_approx_and_the_last_explicit_approx():
    body = "  R_APPROX := 5 + 5;\n  MOVE LIN p;\n  WAIT 1 SEC;\n  MOVE LIN p WITH APPROX := 3;\n"
    warnings = _warnings(body)
    assert [line for line, _ in warnings] == [10, 11]
    assert warnings[1][1] == "WITH APPROX has no effect: the program ends after this motion"


@pytest.mark.parametrize(
    ("statement", "column"),
    [
        ("MOVE LIN p C_DIS;", 14),
        ("MOVE LIN p WITH ZONE := 5;", 19),
        ("MOVE LIN p, z50;", 15),
        ("MOVE PTP p C_PTP;", 14),
        ("MOVE LIN p WITH C_VEL := 5;", 19),
        ("MOVE LIN p, fine;", 15),
        ("C_DIS := 5;", 3),
    ],
)
def test_other_languages_approximation_words_get_the_hint(statement, column):
    result = compile_text(HEAD + P + f"  {statement}\nENDPROGRAM\n")
    (error,) = result.errors
    assert (error.span.line, error.span.column) == (8, column)
    assert error.hint.startswith("approximate positioning is written WITH APPROX := mm")


def test_approx_range_is_checked_at_compile_time():
    result = compile_text(HEAD + P + "  MOVE LIN p WITH APPROX := -1;\nENDPROGRAM\n")
    (error,) = result.errors
    assert error.message == "WITH APPROX := -1: the value must be in [0, 100000] mm"
