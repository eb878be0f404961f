"""Corrupted ``.ird`` files found by the adversarial fuzz run of issue 11 (helper h7): each
used to hang, crash (exit 4) or fail half-way through a run without a position; now the
reader reports it at the record's line (``lang/irdata_checks.py``)."""

from __future__ import annotations

import os
import re
import time

import pytest
from irlc.cli import main
from irlc.lang import CompileError, read_code, write_code
from irlc.lang.file_access import read_source_text
from irlc.lang.irdata_checks import MAX_CELLS
from irlc.lang.irdata_reader import MAX_ERRORS

from .conftest import compile_text, ird_text
from .test_irdata_corrupt import corrupt, errors

SOURCE = """PROGRAM t;
ROBOT r := six;
TYPE
  RECORD REAL: x; REAL: y; ENDRECORD = pt;
VAR
  INTEGER: i;
  pt: p;
PROCEDURE q(INTEGER: n);
VAR REAL: tmp;
BEGIN
  tmp := n;
ENDPROC;
BEGIN
  i := 3;
  q(i);
  WRITELN('x', 2.5);
ENDPROGRAM
"""


@pytest.fixture(scope="module")
def ird() -> str:
    return ird_text(SOURCE)


def test_the_program_reads_back(ird: str) -> None:
    assert write_code(read_code(ird)) == ird


@pytest.mark.parametrize(
    ("record", "replacement", "message"),
    [
        (  # a run allocated 2**64 cells before the first instruction: a hang (exit -9)
            r"(\d+ GLOBAL 0) INTEGER (i.*)",
            r"\1 ARRAY[-9223372036854775808..9223372036854775807]OFREAL \2",
            "has more than 1,000,000 elements",
        ),
        (  # nested arrays: each within the limit, together 10**12 cells
            r"(\d+ GLOBAL 0) INTEGER (i.*)",
            r"\1 ARRAY[1..1000000]OFARRAY[1..1000000]OFREAL \2",
            f"cells (at most {MAX_CELLS:,})",
        ),
        (  # a record type containing itself: endless recursion at run start
            r"(\d+ TYPE 0 RECORD) x:REAL (y:REAL.*)",
            r"\1 x:RECORD#0 \2",
            "record type RECORD#0 contains itself",
        ),
        (r"(\d+ GLOBAL 1) RECORD#0 (p.*)", r"\1 RECORD#7 \2", "unknown record type 'RECORD#7'"),
        (r"(\d+ GLOBAL 0) INTEGER (i.*)", r"\1 FOO \2", "unknown type 'FOO'"),
        (  # constants of the wrong shape failed at run time "with no source line"
            r"(\d+ CONST 0) INTEGER 3(.*)",
            r"\1 RECORD#0 1.0 2.0\2",
            "a constant cannot be of type 'RECORD#0'",
        ),
        (r"(\d+ CONST 0) INTEGER 3(.*)", r"\1 POSE 1.0 2.0\2", "POSE: expected 6 numbers, got 2"),
        (r"(\d+ CONST 0) INTEGER 3(.*)", r"\1 CHAR 'ab'\2", "CHAR: expected one character"),
        (  # a 5,000-digit type word was echoed whole
            r"(\d+ CONST 0) INTEGER 3(.*)",
            r"\g<1> " + "1" * 5000 + r" 3\2",
            "CONST: expected a type, got '" + "1" * 32 + "'… (a word of 5000 characters)",
        ),
        (  # a file name with a NUL byte: ValueError when the run read the source (exit 4)
            r"(\d+ SOURCE) '.*'",
            "\\1 'a\x00b.irl'",
            "SOURCE: a file name cannot hold a NUL character",
        ),
        (  # ENAMETOOLONG from Path.is_file when the CLI looked for the source (exit 4)
            r"(\d+ SOURCE) '.*'",
            r"\1 '" + "s" * 300 + ".irl'",
            "SOURCE: a file name too long for a file system (304 characters)",
        ),
        (r"(\d+ JOINTS) a1 .*", r"\1 a1", "JOINTS: 1 name(s) for the ROBOT record's 6 joint(s)"),
        (r"(\d+ GLOBAL) 1 (RECORD#0 p.*)", r"\1 5 \2", "GLOBAL: expected index 1, got 5"),
        (r"(\d+ ROUTINE 1 q PROC) 1 1 (@.*)", r"\1 1 2 \2", "declares 1 parameter(s) and 2"),
        (r"(\d+ ROUTINE 1 q) PROC (.*)", r"\1 BOGUS \2", "expected MAIN, PROC or FUNC:TYPE"),
    ],
)
def test_a_bad_header_record_is_a_read_error_at_its_line(ird, record, replacement, message):
    text, line = corrupt(ird, record, replacement)
    found = errors(text)
    assert any(ln == line and message in msg for ln, _, msg in found), found


def insert_after_units(text: str, records: list[str]) -> tuple[str, int]:
    """``records`` inserted after the UNITS record, the records renumbered and jump and
    entry targets moved with them; the file line of the first inserted record."""
    lines = text.splitlines()
    at = next(k for k, s in enumerate(lines) if s.endswith(" UNITS mm deg s")) + 1
    units_record = int(lines[at - 1].split()[0])
    shift = len(records)

    def moved(m: re.Match) -> str:
        n = int(m.group(1))
        return f"@{n + shift if n > units_record else n}"

    tail = []
    for s in lines[at:]:
        if s[:1].isdigit():
            number, rest = s.split(" ", 1)
            s = f"{int(number) + shift} {re.sub(r'@([0-9]+)', moved, rest)}"
        tail.append(s)
    new = [f"{units_record + k} {r}" for k, r in enumerate(records, 1)]
    return "\n".join(lines[:at] + new + tail) + "\n", at + 1


def test_a_bad_obstacle_or_input_record_is_a_read_error(ird: str) -> None:
    extra = ["OBSTACLE wall box center 0 0 0 size 1 2", "INPUT 1 2.0 TRUE 1.0 FALSE"]
    text, line = insert_after_units(ird, extra)
    found = errors(text)
    assert found == [
        (line, 17, "OBSTACLE 'wall': 'size' needs 3 number(s), got 2"),
        (line + 1, 3, "INPUT: event times must not decrease (2 then 1)"),
    ]


def test_an_unknown_move_clause_is_a_read_error(ird: str) -> None:
    text = ird.replace("UNITS mm deg s", "UNITS mm deg s")
    lines = text.splitlines()
    k = next(i for i, s in enumerate(lines) if " WRITELN " in s)
    number, line_op = lines[k].split(" ", 1)
    lines[k] = f"{number} {line_op.split()[0]} MOVE PTP 1 @999999999"
    found = errors("\n".join(lines) + "\n")
    assert (k + 1, len(lines[k]) - 10 + 1, "MOVE: unknown clause '@999999999'") in found


def test_a_long_word_is_not_echoed_whole(ird: str) -> None:
    text, line = corrupt(ird, r"(\d+ L\d+) PUSHC 0( .*)?", r"\1 PUSHC " + "SECRETx" * 10_000)
    [(ln, _, message)] = errors(text)
    assert ln == line and "(a word of 70000 characters)" in message and len(message) < 200


def test_errors_are_capped_with_a_count_of_the_rest(ird: str) -> None:
    text, _ = insert_after_units(ird, [f"OBSTACLE o{n} cone" for n in range(200)])
    with pytest.raises(CompileError) as e:
        read_code(text, "bad.ird")
    diags = e.value.diagnostics
    assert len(diags) == MAX_ERRORS
    assert diags[-1].notes == ("180 more error(s) in bad.ird not shown",)


def test_a_refused_robot_of_an_ird_is_reported_at_its_robot_record(tmp_path, capsys) -> None:
    (tmp_path / "arm.toml").write_text("not read")
    sub = tmp_path / "sub"
    sub.mkdir()
    text = write_code(compile_text(SOURCE).code).replace("ROBOT r six", "ROBOT r '../arm.toml'")
    ird = sub / "t.ird"
    ird.write_text(text)
    line = next(k for k, s in enumerate(text.splitlines(), 1) if " ROBOT r " in s)
    assert main(["run", str(ird), "-q"]) == 3
    err = capsys.readouterr().err
    assert f"{ird}:{line}:11: cannot use robot '../arm.toml' (the code's ROBOT record)" in err
    assert "outside the folders a program may read from" in err


def test_disasm_of_a_non_utf8_file_names_the_line_and_shows_no_code(tmp_path, capsys) -> None:
    bad = tmp_path / "b.ird"
    bad.write_bytes(b"IRDATA 1\n1 PROGRAM t\n2 SOURCE '\xff'\n")
    assert main(["disasm", str(bad)]) == 3
    assert "byte 0xff on line 3" in capsys.readouterr().err
    bad.write_bytes(b"IRDATA 1\n1 PROGRAM t\n2 FOO SECRET_TEXT_OF_THE_FILE\n3 CODE\n")
    assert main(["disasm", str(bad)]) == 1
    err = capsys.readouterr().err
    assert f"{bad}:3:3: error: unknown header record 'FOO'" in err  # the line, not its text
    assert "SECRET_TEXT_OF_THE_FILE" not in err


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
def test_a_source_that_is_a_fifo_is_not_read(tmp_path) -> None:
    fifo = tmp_path / "p.irl"
    os.mkfifo(fifo)
    start = time.monotonic()
    assert read_source_text(fifo) is None  # opening a FIFO to read blocked for ever
    assert time.monotonic() - start < 2.0


def test_disasm_shows_only_an_irl_source_with_its_lines_as_the_compiler_counts_them(
    tmp_path, capsys
) -> None:
    # SOURCE '/etc/passwd' interleaved that file's lines; U+2028 or a form feed in a
    # comment shifted every shown line after it by one (str.splitlines)
    src = tmp_path / "p.irl"
    src.write_text(
        "PROGRAM p;\r\nROBOT r := planar3;\r\n{ a\u2028b \x0c c }\r\nBEGIN\r\n"
        "  WRITELN('x');\r\nENDPROGRAM\r\n",
        encoding="utf-8",
    )
    assert main(["compile", str(src), "-o", str(tmp_path / "p.ird")]) == 0
    capsys.readouterr()
    assert main(["disasm", str(tmp_path / "p.ird")]) == 0
    assert ";    5 |   WRITELN('x');" in capsys.readouterr().out.splitlines()
    other = tmp_path / "notes.txt"
    other.write_text("SECRET_LINE\n" * 9, encoding="utf-8")
    ird = (tmp_path / "p.ird").read_text(encoding="utf-8")
    (tmp_path / "q.ird").write_text(re.sub(r"SOURCE '[^']*'", f"SOURCE '{other}'", ird))
    assert main(["disasm", str(tmp_path / "q.ird")]) == 0
    out = capsys.readouterr().out
    assert "SECRET_LINE" not in out and "(source file not found" in out


@pytest.mark.parametrize(
    ("instruction", "message"),
    [
        ("OPTON CYCLIC 5", "OPTON CYCLIC: expected no operands, got 1"),
        ("OPTOFF OBSTACLE okno -inf", "OPTOFF OBSTACLE: expected one obstacle name, got 2"),
        ("OPTON FREEZE 7", "OPTON FREEZE: expected joint numbers in 1..6"),
    ],
)
def test_modal_option_operands_are_checked(ird: str, instruction: str, message: str) -> None:
    lines = ird.splitlines()
    k = next(i for i, s in enumerate(lines) if " WRITELN " in s)
    number, line_op = lines[k].split(" ", 1)
    lines[k] = f"{number} {line_op.split()[0]} {instruction}"
    found = errors("\n".join(lines) + "\n")
    assert any(ln == k + 1 and message in m for ln, _, m in found), found
