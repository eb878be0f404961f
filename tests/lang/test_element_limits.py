"""How many elements a type and a scope's variables hold (issue 11): a nested array of a
million arrays of a million reals compiled and then filled the memory at run time. Every
type holds at most ``MAX_ELEMENTS`` elements, the variables of one scope at most
``MAX_SCOPE_ELEMENTS``; beyond, a positioned compile error."""

from __future__ import annotations

import pytest
from irlc.lang import types as T
from irlc.lang.value_ranges import MAX_ELEMENTS, MAX_SCOPE_ELEMENTS

from .conftest import compile_text

HEAD = "PROGRAM p;\nROBOT r := planar3;\n"
BODY = "BEGIN\nENDPROGRAM\n"


def _errors(decls: str) -> list[tuple[int, int, str]]:
    result = compile_text(HEAD + decls + BODY)
    return [(e.span.line, e.span.column, e.message) for e in result.errors]


@pytest.mark.parametrize(
    ("decl", "column", "count"),
    [
        ("VAR ARRAY [1..1000000] OF ARRAY [1..1000000] OF REAL: a;\n", 5, 10**12),
        ("VAR ARRAY [1..2] OF ARRAY [1..500001] OF REAL: a;\n", 5, 1_000_002),
        ("TYPE big = ARRAY [1..600000] OF REAL;\n  RECORD big: a, b; ENDRECORD = two;\n", 3,
         1_200_000),
    ],
)  # fmt: skip
def test_a_type_of_too_many_elements_is_an_error_at_its_declaration(decl, column, count) -> None:
    line = 3 + decl.count("\n") - 1
    what = "this RECORD" if "RECORD" in decl else "this array"
    assert _errors(decl) == [
        (line, column, f"{what} would hold {count} elements (at most {MAX_ELEMENTS})")
    ]


def _at(line: str, word: str) -> int:
    """The 1-based column of ``word`` (last occurrence) in ``line``."""
    return line.rindex(word) + 1


def test_the_variables_of_a_scope_hold_at_most_the_scope_limit() -> None:
    big = "ARRAY [1..1000000] OF REAL"
    most = f"(at most {MAX_SCOPE_ELEMENTS})"
    decl = f"VAR {big}: a; {big}: b; INTEGER: i;"
    assert _errors(decl + "\n") == [
        (3, _at(decl, "i;"), f"the program's variables would hold 2000001 elements {most}")
    ]
    locs = f"VAR {big}: w; INTEGER: i;"  # a VAR parameter holds no elements of its own
    assert _errors(f"PROCEDURE q({big}: x; VAR {big}: y);\n{locs}\nBEGIN\nENDPROC;\n") == [
        (4, _at(locs, "i;"), f"the variables of 'q' would hold 2000001 elements {most}")
    ]
    params = f"PROCEDURE q({big}: x; {big}: y; INTEGER: i);"
    assert _errors(params + "\nBEGIN\nENDPROC;\n") == [
        (3, _at(params, "i)"), f"the parameters of 'q' would hold 2000001 elements {most}")
    ]


def test_the_largest_array_and_scope_compile() -> None:
    big = "ARRAY [1..1000000] OF REAL"
    assert _errors(f"VAR {big}: a; ARRAY [1..999999] OF REAL: b; INTEGER: i;\n") == []
    assert _errors(f"PROCEDURE q({big}: x; VAR {big}: y);\nVAR {big}: w;\nBEGIN\nENDPROC;\n") == []


def test_elements_counts_nested_arrays_and_records() -> None:
    inner = T.Array("ARRAY", 0, 9, T.REAL)
    rec = T.Record("r", 0, (("a", inner), ("b", T.POSE)))
    assert T.elements(T.Array("ARRAY", 1, 3, rec)) == 3 * (10 + 1)
    assert T.elements(T.Record("e", 1, ())) == 1  # an empty record still takes a cell
