"""Habits of KRL and RAPID programmers (issue 24 §8): their spellings get a hint with irlc's
form, at the word's own line and column — and where the hint rewrites the statement, the
rewritten program compiles (an independent check that the hint is right).

On main these were "'PTP' is a reserved word" (with "choose another name"), "unexpected
name 'left'" after ``MoveL`` with no hint, "unexpected name 'mm'", "unexpected character
'$'", "malformed number '250mm'" with "put a space …" and so on.
"""

from __future__ import annotations

import re

import pytest
from irlc.lang import compile_source
from irlc.lang.signature import SimpleRobot

HEAD = "PROGRAM p;\nROBOT r := planar3;\nVAR POSE: left, right; MAIN_JOINT: k; REAL: x;\nBEGIN\n"
PLANAR3 = SimpleRobot("planar3", ("revolute",) * 3)


def _compile(body: str):
    return compile_source(
        HEAD + f"  {body}\nENDPROGRAM\n", "p.irl", resolve_robot=lambda n: PLANAR3
    )


def _only_error(body: str):
    result = _compile(body)
    assert result.code is None, body
    return result.errors[0]


# statement, the word the error is at, the message's words, the hint's irlc statement
REWRITTEN = [
    ("PTP left;", "PTP", "MOVE PTP left;"),
    ("LIN left;", "LIN", "MOVE LIN left;"),
    ("CIRC left, right;", "CIRC", "MOVE CIRCLE left, right;"),
    ("SLIN left;", "SLIN", "MOVE LIN left;"),
    ("LIN_REL left;", "LIN_REL", "MOVE_INC LIN left;"),
    ("PTP_REL k;", "PTP_REL", "MOVE_INC PTP k;"),
    (
        "MoveL left, v100, z10, tool0;",
        "MoveL",
        "MOVE LIN left WITH SPEED := 100 WITH APPROX := 10;",
    ),
    ("MoveJ left, v100, fine, tool0;", "MoveJ", "MOVE PTP left;"),
    ("MoveAbsJ k, v100, fine, tool0;", "MoveAbsJ", "MOVE PTP k;"),
    (
        "MoveC left, right, v200, z5, tool0\\WObj:=wobj0;",
        "MoveC",
        "MOVE CIRCLE left, right WITH SPEED := 200 WITH APPROX := 5;",
    ),
    ("WaitTime 1;", "WaitTime", "WAIT 1 SEC;"),
    ("WAIT SEC 1;", "SEC", "WAIT 1 SEC;"),
    ("TPWrite 'hi';", "TPWrite", "WRITELN('hi');"),
    ("$VEL.CP = 0.25;", "$VEL.CP", "R_SPEED := 250;"),
    ("$VEL.CP := 0.25;", "$VEL.CP", "R_SPEED := 250;"),
    ("$ACC.CP = 2;", "$ACC.CP", "R_ACC := 2000;"),
    ("$OV_PRO = 50;", "$OV_PRO", "R_OVERRIDE := 50;"),
    ("$OUT[3] = TRUE;", "$OUT", "OUT[3] := TRUE;"),
]


@pytest.mark.parametrize(("body", "word", "form"), REWRITTEN)
def test_a_foreign_statement_gets_irlcs_form_and_that_form_compiles(body, word, form):
    error = _only_error(body)
    line = (HEAD + f"  {body}\n").splitlines()[error.span.line - 1]
    assert error.span.line == 5
    assert line[error.span.column - 1 :].startswith(word), (error.span, word)
    assert f"write {form}" in error.hint, error.hint
    assert "reserved word" not in error.message and "choose another name" not in error.hint
    fixed = _compile(form)
    assert fixed.code is not None, [d.message for d in fixed.diagnostics]


@pytest.mark.parametrize(
    ("body", "word", "hint"),
    [
        ("MOVE LIN left WITH SPEED := 250 mm/s;", "mm", "write 250"),
        ("R_SPEED := 0.25 m/s;", "m", "0.25 m is 250 (mm)"),
        ("MOVE PTP k WITH TIME := 1500 ms;", "ms", "1500 ms is 1.5 (s)"),
        ("R_SPEED := 250mm;", "250mm", "write 250"),
        ("WAIT 2 s;", "s", "write WAIT 2 SEC"),
        ("WAIT 2;", ";", "WAIT t SEC"),
        ("MOVE PTP k WITH SPEED_PTP := 50 %;", "%", "plain numbers"),
        ("x = 5;", "=", "x := 5"),
        ("x == 5;", "=", "'==' is C's"),
        ("IF x == 5 THEN HALT; ENDIF;", "=", "'==' is C's"),
        ("IF x != 5 THEN HALT; ENDIF;", "!", "'<>'"),
        ("x += 1;", "+", "x := x + value"),
        ("IF x := 5 THEN HALT; ENDIF;", "=", "a comparison is written with '='"),
        ("$VEL_AXIS[1] = 20;", "$VEL_AXIS", "R_SPEED_PTP"),
        ("$FOO = 1;", "$FOO", "start with R_"),
        ("LOOP", "LOOP", "WHILE TRUE DO"),
        ("LIN left C_DIS;", "LIN", "WITH APPROX := mm"),
    ],
)
def test_a_foreign_spelling_gets_a_hint_at_its_place(body, word, hint):
    error = _only_error(body)
    line = (HEAD + f"  {body}\n").splitlines()[error.span.line - 1]
    assert line[error.span.column - 1 :].startswith(word), (error.span, error.message)
    assert error.hint is not None and hint in error.hint, error.hint


@pytest.mark.parametrize(
    ("declaration", "hint"),
    [
        ("CONST side := 2000.0;", "declared with '='"),
        ("CONST REAL: side := 2000.0;", "declared with '='"),
        ("TYPE vec := ARRAY [1..3] OF REAL;", "declared with '='"),
        ("VAR REAL: y := 5;", "assign it after BEGIN"),
    ],
)
def test_assignment_and_declaration_signs(declaration, hint):
    source = f"PROGRAM p;\nROBOT r := planar3;\n{declaration}\nBEGIN\nENDPROGRAM\n"
    result = compile_source(source, "p.irl", resolve_robot=lambda n: PLANAR3)
    (error,) = result.errors
    assert error.span.line == 3 and hint in error.hint, error.hint
    right = re.sub(r":=", "=", declaration) if "VAR" not in declaration else "VAR REAL: y;"
    fixed = compile_source(
        source.replace(declaration, right), "p.irl", resolve_robot=lambda n: PLANAR3
    )
    assert fixed.code is not None, [d.message for d in fixed.diagnostics]


def test_a_name_of_the_program_is_not_taken_for_a_habit():
    """A program's own procedure named like a RAPID instruction is called as usual, and
    a real keyword misuse keeps its message."""
    source = (
        "PROGRAM p;\nROBOT r := planar3;\nPROCEDURE waittime(REAL: t);\nBEGIN\n  WAIT t SEC;\n"
        "ENDPROC;\nBEGIN\n  waittime(1);\nENDPROGRAM\n"
    )
    result = compile_source(source, "p.irl", resolve_robot=lambda n: PLANAR3)
    assert result.code is not None, [d.message for d in result.diagnostics]
    for body in ("x := PTP;", "x := 1 + LIN;", "VAR_x := FOR;"):
        error = _only_error(body)
        assert error.message.endswith("is a reserved word"), (body, error.message)


CELL_HEAD = (
    "PROGRAM p;\nROBOT a := planar3;\nROBOT b := planar3 AT (0, 3000, 0, 0, 0, 0);\n"
    "VAR POSE: left, right; MAIN_JOINT: k;\nBEGIN\n"
)


def _compile_cell(body: str):
    return compile_source(
        CELL_HEAD + f"  {body}\nENDPROGRAM\n", "p.irl", resolve_robot=lambda n: PLANAR3
    )


# In a cell only a motion kind may follow MOVE a: the lexer read LIN_REL as LIN and a name
# _REL ("unknown function '_REL'"), LINEAR as LIN and EAR ("unexpected name 'left'"), and
# the hints dropped the robot (write MOVE_INC LIN left: a cell's motion names its robot).
@pytest.mark.parametrize(
    ("body", "word", "form"),
    [
        ("MOVE a LIN_REL left;", "LIN_REL", "MOVE_INC a LIN left;"),
        ("MOVE a LIN_REL (0, 0, 10, 0, 0, 0);", "LIN_REL", "MOVE_INC a LIN (0, 0, 10, 0, 0, 0);"),
        ("MOVE_INC b PTP_REL k;", "PTP_REL", "MOVE_INC b PTP k;"),
        ("MOVE a SLIN left;", "SLIN", "MOVE a LIN left;"),
        ("MOVE a PTP k AND b SPTP k;", "SPTP", "MOVE b PTP k;"),
        ("MOVE a PTP k AND b LIN_REL left;", "LIN_REL", "MOVE_INC b LIN left;"),
        (
            "MOVE a MoveL left, v100, z10, tool0;",
            "MoveL",
            "MOVE a LIN left WITH SPEED := 100 WITH APPROX := 10;",
        ),
    ],
)
def test_a_foreign_motion_in_a_cell_names_its_robot_and_the_form_compiles(body, word, form):
    result = _compile_cell(body)
    assert result.code is None
    (error,) = result.errors
    line = (CELL_HEAD + f"  {body}\n").splitlines()[error.span.line - 1]
    assert error.span.line == 6
    assert line[error.span.column - 1 :].startswith(word), (error.span, word)
    assert error.span.end_column - error.span.column == len(word)
    assert error.message == f"'{word}' is not a statement of this dialect"
    assert f"write {form}" in error.hint, error.hint
    fixed = _compile_cell(form)
    assert fixed.code is not None, [d.message for d in fixed.diagnostics]


@pytest.mark.parametrize(
    ("word", "keyword"), [("LINEAR", "LIN"), ("PTPx", "PTP"), ("CIRCLEx", "CIRCLE")]
)
def test_a_word_glued_to_a_keyword_is_reported_as_the_word(word, keyword):
    result = _compile_cell(f"MOVE a {word} left, right;")
    (error,) = result.errors
    assert (error.span.line, error.span.column, error.span.end_column) == (6, 10, 10 + len(word))
    assert error.message == f"unknown word '{word}'"
    assert f"irlc read {keyword} and then '{word[len(keyword) :]}'" in error.hint


def test_vertical_on_a_motion_points_at_cooperate():
    result = _compile_cell("MOVE a PTP k WITH VERTICAL;")
    (error,) = result.errors
    assert error.message == "unexpected ';'; expected ':='"
    assert "COOPERATE welder IN holder WITH VERTICAL" in error.hint
