"""Fuzz the classes of hostile input issue 11 found (compiler and .ird reader).

Each strategy builds one class — long words before a syntax error, deep nesting, long
integer literals, strings with line breaks, corrupted .ird records with hostile numbers —
and the property is the contract: a diagnostic with a position in the text (or the code
compiles / reads back byte-identically), never an exception, in bounded time.
"""

from __future__ import annotations

import time

from hypothesis import given
from hypothesis import strategies as st
from irlc.lang import CompileError, read_code, write_code

from ..fuzz_budget import fuzz_settings
from .conftest import compile_text

HEAD = "PROGRAM p; ROBOT r := koch11; VAR REAL: x; BOOLEAN: b; STRING: s; BEGIN "


def _positioned(text: str, filename: str = "t.irl") -> None:
    """Compile; a failure has errors positioned inside the text (the fuzz contract)."""
    result = compile_text(text, filename)
    if result.ok:
        return
    n_lines = text.count("\n") + 1
    for d in result.errors:
        assert d.span is not None, d
        assert 1 <= d.span.line <= n_lines + 1 and d.span.column >= 1, d


@fuzz_settings(60)
@given(st.integers(1, 60_000), st.sampled_from([";", ":=", "x", ")", "1", "ENDPROGRAM"]))
def test_fuzz_long_words_before_errors(n: int, junk: str) -> None:
    text = "PROGRAM p; ROBOT r := koch11; VAR REAL: " + "x" * n + f"; BEGIN x := 1 {junk} x"
    start = time.perf_counter()
    _positioned(text)
    assert time.perf_counter() - start < 5.0


_NESTERS = {
    "sum": lambda n: "x := " + " + ".join(["x"] * n) + ";",
    "minus": lambda n: "x := " + "-" * n + "x;",
    "not": lambda n: "b := " + "NOT " * n + "b;",
    "sqrt": lambda n: "x := " + "SQRT(" * n + "x" + ")" * n + ";",
    "paren": lambda n: "x := " + "(" * n + "x" + ")" * n + ";",
    "if": lambda n: "IF b THEN " * n + "x := 1;" + " ENDIF;" * n,
    "while": lambda n: "WHILE b DO " * n + "x := 1;" + " ENDWHILE;" * n,
    "repeat": lambda n: "REPEAT " * n + "x := 1;" + " UNTIL b;" * n,
    "case": lambda n: "CASE 1 OF 1: " * n + "x := 1;" + " ENDCASE;" * n,
}


@fuzz_settings(60)
@given(st.sampled_from(sorted(_NESTERS)), st.integers(1, 3000))
def test_fuzz_nesting_of_any_depth(kind: str, depth: int) -> None:
    _positioned(HEAD + _NESTERS[kind](depth) + " ENDPROGRAM")


@fuzz_settings(60)
@given(st.integers(1, 20_000), st.sampled_from(["", "0", "-", ".5", "e3", "e999"]))
def test_fuzz_long_number_literals(digits: int, tail: str) -> None:
    lead = "-" if tail == "-" else ""
    _positioned(HEAD + f"x := {lead}" + "7" * digits + tail.lstrip("-") + "; ENDPROGRAM")


_LINE_BREAKS = "\n\r\x0b\x0c\x1c\x1d\x1e\x85\u2028\u2029"
_STRING_CHARS = st.characters(codec="utf-8", exclude_characters="'\n") | st.sampled_from(
    [*_LINE_BREAKS.replace("\n", ""), "\\", "''", "\\u000b", "E'"]
)


@fuzz_settings(100)
@given(st.lists(_STRING_CHARS, max_size=30).map("".join))
def test_fuzz_strings_survive_the_ird_round_trip(body: str) -> None:
    result = compile_text(HEAD + f"s := '{body}'; WRITELN(s); ENDPROGRAM")
    if not result.ok:
        return  # e.g. an unterminated string: the compiler's own fuzz covers positions
    ird = write_code(result.code)
    assert len(ird.splitlines()) == ird.count("\n")
    back = read_code(ird, "t.ird")
    assert write_code(back) == ird
    assert [v.data[0] for v in back.consts if v.type == "STRING"] == [body.replace("''", "'")]


SEED = compile_text(
    "PROGRAM t; ROBOT r := six; VAR INTEGER: i; STRING: s;\n"
    "PROCEDURE p(INTEGER: k); BEGIN i := k; ENDPROC;\n"
    "BEGIN\n  i := 3; s := 'a';\n  WHILE i > 0 DO i := i - 1; p(i); ENDWHILE;\n"
    "  WRITELN(s, 2.5);\n  CYCLICSTART;\n  CYCLICEND;\nENDPROGRAM\n"
).code
SEED_IRD = write_code(SEED) if SEED is not None else ""
_HOSTILE_TOKENS = [
    "9" * 5000, "-" + "9" * 30, "9223372036854775808", "1e308", "-1e308", "4.9e-324", "nan",
    "inf", "-0.0", "@1.5", "@-0.0", "@4.9e-324", "@" + "1" * 5000, "@²", "L" + "7" * 5000, "L²",
    "E'\\u2028'", "E'\\uzzzz'", "'\u2028'", "''", "'", "E'", ";", "@0", "@99999", "STRING",
    "INTEGER", "REAL", "POSE", "MAIN", "x" * 300,
]  # fmt: skip


@fuzz_settings(200)
@given(
    st.lists(
        st.tuples(st.integers(0, 3), st.integers(0, 10**6), st.sampled_from(_HOSTILE_TOKENS)),
        min_size=1,
        max_size=4,
    )
)
def test_fuzz_corrupted_ird_records(ops) -> None:
    lines = SEED_IRD.split("\n")
    for kind, where, token in ops:
        k = 1 + where % (len(lines) - 1)
        words = lines[k].split(" ")
        i = where % len(words)
        if kind == 0:
            words[i] = token
        elif kind == 1:
            words.insert(i, token)
        elif kind == 2 and len(words) > 1:
            del words[i]
        else:
            lines.insert(k, lines[where % len(lines)])
            continue
        lines[k] = " ".join(words)
    text = "\n".join(lines)
    try:
        read_code(text, "bad.ird")
    except CompileError as e:
        n = len(text.splitlines())
        for d in e.diagnostics:
            assert d.span is not None and 1 <= d.span.line <= n + 1, d
