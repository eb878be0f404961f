"""Hand-corrupted IRDATA: the reader reports the real problem once, at its record.

One bad record must not shift the indices of the records after it (a bad CONST would make
every later PUSHC look out of range; a dropped instruction would move jump targets onto
the wrong instructions), and must never end in a Python exception.
"""

from __future__ import annotations

import re

import pytest
from irlc.lang import CompileError, read_code, write_code

from .conftest import ird_text

SOURCE = """PROGRAM t;
ROBOT r := six;
VAR INTEGER: i;
BEGIN
  i := 3;
  WHILE i > 0 DO
    i := i - 1;
    WRITELN('x', 2.5);
  ENDWHILE;
  CYCLICSTART;
  CYCLICEND;
ENDPROGRAM
"""


@pytest.fixture(scope="module")
def ird() -> str:
    return ird_text(SOURCE)


def corrupt(text: str, record: str, replacement: str) -> tuple[str, int]:
    """Replace the record matching ``record`` (a regex over the whole line); its file line."""
    lines = text.splitlines()
    hits = [k for k, line in enumerate(lines) if re.fullmatch(record, line)]
    assert len(hits) == 1, (record, hits)
    lines[hits[0]] = re.sub(record, replacement, lines[hits[0]])
    return "\n".join(lines) + "\n", hits[0] + 1


def errors(text: str) -> list[tuple[int, int, str]]:
    with pytest.raises(CompileError) as e:
        read_code(text, "bad.ird")
    return [(d.line, d.column, d.message) for d in e.value.diagnostics]


def test_the_uncorrupted_code_reads_back(ird: str) -> None:
    assert write_code(read_code(ird)) == ird


@pytest.mark.parametrize(
    ("record", "replacement", "column", "message"),
    [
        # a bad CONST in the middle: the later PUSHC indices must stay right
        (r"(\d+ CONST 1 INTEGER) 0", r"\1 zero", 11, "INTEGER: expected numbers"),
        (r"(\d+ CONST 1 INTEGER) 0", r"\1", 11, "INTEGER: expected one integer"),
        (r"(\d+ CONST 1 INTEGER) 0", r"\1 0.5", 11, "INTEGER: expected one integer"),
        (
            r"(\d+ CONST 1 INTEGER) 0",
            r"\1 9223372036854775808",
            19,
            "INTEGER: INTEGER overflow (9223372036854775808 is outside the 64-bit range)",
        ),
        (  # int() refuses more than 4,300 digits: this was a ValueError (issue 11)
            r"(\d+ CONST 1 INTEGER) 0",
            r"\1 " + "9" * 5000,
            19,
            "INTEGER: INTEGER overflow (a 5000-digit number is outside the 64-bit range)",
        ),
        (  # an integer too large for a float: this was an OverflowError
            r"(\d+ CONST 4 REAL) 2.5",
            r"\1 " + "9" * 400,
            12,
            "REAL: expected numbers",
        ),
        (  # STRING holds at most 65,535 characters (issue 11)
            r"(\d+ CONST 3 STRING) 'x'",
            r"\1 '" + "x" * 65536 + "'",
            18,
            "STRING: a STRING of 65536 characters is too long (at most 65535)",
        ),
        (r"(\d+ CONST) 1 (INTEGER 0)", r"\1 7 \2", 9, "CONST: expected index 1, got 7"),
        (r"(\d+ CONST) 1 (INTEGER 0)", r"\1 one \2", 9, "CONST: expected an index, got 'one'"),
        (r"(\d+ CONST) 1 INTEGER 0", r"\1 1", 9, "CONST: expected at least 2 operands"),
        # a bad instruction before a loop: the jump targets after it stay right
        (r"(\d+ L6 JF) @\d+", r"\1 @x28", 10, "JF: expected a jump target '@<record>', got '@x28'"),
        (r"(\d+ L5 PUSHC) 0 ; 3", r"\1 zero", 13, "PUSHC: expected an integer, got 'zero'"),
        (
            r"(\d+ L5 PUSHC) 0 ; 3",
            r"\1 " + "1" * 5000,
            13,
            "PUSHC: INTEGER overflow (a 5000-digit number is outside the 64-bit range)",
        ),
        (
            r"(\d+) L7 SUB",
            r"\1 L" + "7" * 5000 + " SUB",
            4,
            "expected a source line 'L<n>' and an opcode",
        ),
        (
            r"(\d+ L6 JF) @\d+",
            r"\1 @" + "2" * 5000,
            10,
            "JF: expected a jump target '@<record>', got '@"
            + "2" * 31
            + "'… (a word of 5001 characters)",  # a long word is not echoed whole
        ),
        (
            r"(\d+ L6 JF) @\d+",
            "\\1 @\u00b2",
            10,
            "JF: expected a jump target '@<record>', got '@²'",
        ),
        (r"(\d+ L7) SUB", r"\1 SUBB", 7, "unknown opcode 'SUBB'"),
        (r"(\d+ L7 SUB)", r"\1 1", 7, "SUB: expected 0 operand(s), got 1"),
        # bad table indices in the header: a placeholder, no Python exception
        (r"(\d+ GLOBAL) 0 (INTEGER i)", r"\1 zero \2", 11, "GLOBAL: expected an index, got 'zero'"),
        (
            r"(\d+ ROUTINE) 0 (t MAIN 0 0 @\d+)",
            r"\1 main \2",
            12,
            "ROUTINE: expected an index, got 'main'",
        ),
        *(  # float-looking entries were ValueErrors in int() (issue 11)
            (
                r"(\d+ ROUTINE 0 t MAIN 0 0) @\d+",
                rf"\1 {entry}",
                25,
                f"ROUTINE: expected an entry @record, got {shown}",
            )
            for entry, shown in (
                *((e, repr(e)) for e in ("@1.5", "@-0.0", "@4.9e-324")),
                ("@" + "1" * 5000, "'@" + "1" * 31 + "'… (a word of 5001 characters)"),
            )
        ),
        (
            r"(\d+ GLOBAL) 0 (INTEGER i)",
            r"\1 " + "8" * 5000 + r" \2",
            11,
            "GLOBAL: INTEGER overflow (a 5000-digit number is outside the 64-bit range)",
        ),
    ],
)
def test_one_bad_record_gives_one_error_at_it(
    ird: str, record: str, replacement: str, column: int, message: str
) -> None:
    text, line = corrupt(ird, record, replacement)
    assert errors(text) == [(line, column, message)]


def test_a_jump_outside_the_code_is_reported_at_the_jump(ird: str) -> None:
    text, line = corrupt(ird, r"(\d+ L9 JMP) @\d+", r"\1 @3")
    assert errors(text) == [(line, 11, "jump target @3 is not an instruction record")]


def test_two_bad_records_give_two_errors(ird: str) -> None:
    text, const_line = corrupt(ird, r"(\d+ CONST 0 INTEGER) 3", r"\1 three")
    text, jump_line = corrupt(text, r"(\d+ L6 JF) @\d+", r"\1 28")
    assert [(line, msg.split(":")[0]) for line, _, msg in errors(text)] == [
        (const_line, "INTEGER"),
        (jump_line, "JF"),
    ]
