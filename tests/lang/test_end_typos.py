"""END_IF; END_FOR; END_WHILE; ENDPROCEDURE; — the typo's hint at the typo's own line and
column, with the ';' as without it (with it the word parsed as a procedure call and the
error came later: at ENDPROGRAM, or "'BEGIN' is a reserved word")."""

from __future__ import annotations

import pytest
from irlc.lang import compile_source
from irlc.lang.parser import parse

from .invalid_cases import CASES


def _case(name: str) -> tuple[str, int, int]:
    return next((src, line, col) for n, src, line, col, _ in CASES if n == name)


@pytest.mark.parametrize(
    ("name", "word", "right"),
    [
        ("end_if_semicolon", "END_IF", "ENDIF"),
        ("end_if_no_semicolon", "END_IF", "ENDIF"),
        ("end_for_semicolon", "END_FOR", "ENDFOR"),
        ("end_while_semicolon", "END_WHILE", "ENDWHILE"),
        ("endprocedure_semicolon", "ENDPROCEDURE", "ENDPROC"),
        ("endfunction_semicolon", "ENDFUNCTION", "ENDFCT"),
        ("cooperate_end_typo", "COOPERATE_END", "COOPERATEEND"),
        ("cooperatend_typo", "COOPERATEND", "COOPERATEEND"),
        ("obstacle_end_typo", "OBSTACLE_END", "OBSTACLEEND"),
        ("jointspeedlimit_end_typo", "JOINTSPEEDLIMIT_END", "JOINTSPEEDLIMITEND"),
    ],
)
def test_end_typo_hint_at_its_own_line(name, word, right):
    source, line, column = _case(name)
    result = compile_source(source, "t.irl", resolve_robot=lambda n: None)
    assert result.code is None
    (d,) = result.diagnostics
    assert (d.span.line, d.span.column) == (line, column)
    assert source.splitlines()[line - 1][column - 1 :].startswith(word)
    assert d.message == f"'{word}' is not a keyword of this dialect"
    assert d.hint == f"write {right}"


def test_a_procedure_call_of_another_name_still_parses():
    src = "PROGRAM t;\nPROCEDURE endit;\nBEGIN\n  HALT;\nENDPROC;\nBEGIN\n  endit;\nENDPROGRAM\n"
    program, diagnostics = parse(src, "t.irl")
    assert program is not None and not diagnostics


@pytest.mark.parametrize(
    ("source", "line", "column", "word", "right"),
    [
        ("  CASE 1 OF\n    1: HALT;\n  END_CASE;", 6, 3, "END_CASE", "ENDCASE"),
        ("  HALT;\nEND_PROGRAM;", 5, 1, "END_PROGRAM", "ENDPROGRAM"),
    ],
)
def test_more_end_typos(source, line, column, word, right):
    """Also END_CASE; and END_PROGRAM at the end of the file (with or without ';')."""
    for tail in ("", "\n", "\n{ trailing comment }\n"):
        for text in (source, source.rstrip(";")):
            src = f"PROGRAM t;\nROBOT r := six;\nBEGIN\n{text}{tail}"
            if "ENDPROGRAM" not in right:
                src += "\nENDPROGRAM\n"
            _, diagnostics = parse(src, "t.irl")
            (d,) = diagnostics
            assert (d.span.line, d.span.column, d.hint) == (line, column, f"write {right}"), src
            assert d.message == f"'{word}' is not a keyword of this dialect"
