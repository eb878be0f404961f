"""Hostile compiler input (issue 11): every bad program is a positioned error in bounded time.

Each test reproduces one crash or hang the adversarial run found; the fuzz tests in
``test_fuzz.py`` keep the classes fixed.
"""

from __future__ import annotations

import sys
import time

import pytest
from irlc.lang import read_code, write_code
from irlc.lang.irdata import MAX_STRING

from .conftest import compile_text, fake_resolver


def _only_error(text: str):
    result = compile_text(text, "t.irl")
    assert not result.ok
    return result.errors[0]


def test_syntax_error_after_a_long_word_is_reported_in_linear_time() -> None:
    # _previous_token retried its pattern at every position of the 40,000-letter name (9 s).
    text = (
        "PROGRAM p; ROBOT r := koch11; VAR REAL: "
        + "x" * 40000
        + "; BEGIN x := 1 x := 2 ENDPROGRAM"
    )
    start = time.perf_counter()
    err = _only_error(text)
    assert time.perf_counter() - start < 2.0
    assert err.span is not None and err.span.line == 1
    assert "unexpected name 'x'" in err.message


_HEAD = "PROGRAM p; ROBOT r := koch11; VAR REAL: x; BOOLEAN: b; BEGIN "


def _nested(kind: str, n: int) -> str:
    bodies = {
        "sum": "x := " + " + ".join(["x"] * n) + ";",
        "minus": "x := " + "-" * n + "x;",
        "not": "b := " + "NOT " * n + "b;",
        "and": "b := " + " AND ".join(["b"] * n) + ";",
        "sqrt": "x := " + "SQRT(" * n + "x" + ")" * n + ";",
        "if": "IF b THEN " * n + "x := 1;" + " ENDIF;" * n,
        "while": "WHILE b DO " * n + "x := 1;" + " ENDWHILE;" * n,
        "case": "CASE 1 OF 1: " * n + "x := 1;" + " ENDCASE;" * n,
    }
    return _HEAD + bodies[kind] + " ENDPROGRAM"


@pytest.mark.parametrize("kind", ["sum", "minus", "not", "and", "sqrt", "if", "while", "case"])
def test_nesting_beyond_the_bound_is_a_positioned_error(kind: str) -> None:
    # 600 levels ended in RecursionError in the checker (~495 was the limit).
    err = _only_error(_nested(kind, 600))
    assert "nested more than 200 levels deep" in err.message
    assert err.span is not None and err.span.line == 1 and err.span.column > len(_HEAD)


@pytest.mark.parametrize("kind", ["sum", "minus", "if", "while"])
def test_nesting_within_the_bound_compiles_with_room_to_spare(kind: str) -> None:
    # The bound leaves the recursive passes (checker, code generator) a wide margin.
    limit = sys.getrecursionlimit()
    sys.setrecursionlimit(700)
    try:
        assert compile_text(_nested(kind, 190), "t.irl").ok
    finally:
        sys.setrecursionlimit(limit)


def test_deep_parentheses_add_no_level() -> None:
    assert compile_text(_HEAD + "x := " + "(" * 1000 + "x" + ")" * 1000 + "; ENDPROGRAM").ok


@pytest.mark.parametrize("digits", [41, 4301, 100_000])
def test_a_long_integer_literal_is_an_overflow_at_its_position(digits: int) -> None:
    # int() refuses more than 4,300 digits: the literal was a ValueError in number().
    text = _HEAD + "x := " + "9" * digits + "; ENDPROGRAM"
    err = _only_error(text)
    assert err.message == f"INTEGER overflow (a {digits}-digit number is outside the 64-bit range)"
    assert (err.span.line, err.span.column) == (1, len(_HEAD) + 6)


def test_leading_zeros_do_not_count_towards_the_integer_range() -> None:
    assert compile_text(_HEAD + "x := " + "0" * 5000 + "7; ENDPROGRAM").ok


def test_a_string_literal_longer_than_the_maximum_is_an_error() -> None:
    text = "PROGRAM p; ROBOT r := koch11; VAR STRING: s; BEGIN s := '"
    err = _only_error(text + "a" * (MAX_STRING + 1) + "'; ENDPROGRAM")
    assert err.message == f"a STRING of {MAX_STRING + 1} characters is too long (at most 65535)"
    assert (err.span.line, err.span.column) == (1, len(text))
    assert compile_text(text + "a" * MAX_STRING + "'; ENDPROGRAM").ok


LINE_BREAKS = ["\u2028", "\u2029", "\x85", "\x0b", "\x0c", "\x1c", "\x1d", "\x1e", "\r"]


@pytest.mark.parametrize("ch", LINE_BREAKS, ids=[f"U+{ord(c):04X}" for c in LINE_BREAKS])
def test_strings_with_line_breaks_survive_the_ird_round_trip(ch: str) -> None:
    # The reader splits lines with str.splitlines(): the writer escapes these (E'…').
    text = f"a{ch}b\\u000b''c\\\\"  # also a backslash and a literal '\\u000b' to keep
    src = (
        "PROGRAM p; ROBOT r := koch11; VAR STRING: s; CHAR: c; BEGIN "
        f"s := '{text}'; c := '{ch}'; WRITELN(s, c); ENDPROGRAM"
    )
    result = compile_text(src)
    assert result.ok, [d.header() for d in result.diagnostics]
    ird = write_code(result.code)
    assert len(ird.splitlines()) == ird.count("\n")  # no line break inside a record
    back = read_code(ird, "t.ird")
    assert write_code(back) == ird
    strings = [v.data[0] for v in back.consts if v.type in ("STRING", "CHAR")]
    assert strings == [text.replace("''", "'"), ch]


def test_strings_without_line_breaks_are_written_as_before() -> None:
    result = compile_text(
        "PROGRAM p; ROBOT r := koch11; VAR STRING: s; BEGIN s := 'a\\b''c'; ENDPROGRAM"
    )
    assert "CONST 0 STRING 'a\\b''c'\n" in write_code(result.code)


def test_a_byte_order_mark_is_accepted(tmp_path) -> None:
    from irlc.lang import compile_file

    path = tmp_path / "bom.irl"
    path.write_bytes(b"\xef\xbb\xbfPROGRAM p;\nROBOT r := koch11;\nBEGIN\nENDPROGRAM\n")
    result = compile_file(path, resolve_robot=fake_resolver)
    assert result.ok, [d.header() for d in result.diagnostics]


def test_a_byte_that_is_not_utf8_is_reported_at_its_line_and_column(tmp_path) -> None:
    # It was "cannot read the program: 'utf-8' codec can't decode byte 0x80 in position 52".
    from irlc.lang import compile_file

    path = tmp_path / "bad.irl"
    path.write_bytes(
        b"PROGRAM p;\nROBOT r := koch11;\nBEGIN\n  WRITELN('\xc3\xa9\x80');\nENDPROGRAM\n"
    )
    (err,) = compile_file(path, resolve_robot=fake_resolver).errors
    assert (err.file, err.line, err.column) == (str(path), 4, 13)
    assert err.message == "the program is not UTF-8 text (byte 0x80)"
