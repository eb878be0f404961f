"""Held-out acceptance tests of the IRL compiler, written from ``language.md`` alone.

``valid/*.irl`` must pass ``irlc check`` (exit 0), ``irlc compile -o X.ird`` (exit 0) and
``irlc disasm X.ird`` (exit 0, non-empty listing).  A first-line comment
``{ args: --robot NAME }`` adds command-line options.

``invalid/*.irl`` must fail ``irlc check`` with exit 1 and no traceback.  Their first
line states what the user should see:

- ``{ expect: L:C[|L2:C2] fragment }`` — stderr starts with ``FILE:L:C: error:``,
  contains ``fragment`` (case-insensitive) in the message or its hint, and shows the
  source line with a caret under column ``C``.
- ``{ expect-datalist: NAME.toml fragment }`` — a data-list error: stderr names the
  data-list file and contains ``fragment`` (the offending key or value).

Column rule: the expected column is the first character of the token the error is
about (the unexpected token for syntax errors, the offending operand/name/argument for
semantic errors).  Where two positions are equally defensible — a missing ``;`` (end
of the previous token or the token that follows), a binary type error (left operand or
operator), a START never closed (the START or the end of its list) — the header lists
both, separated by ``|``, and either is accepted.  The line must always match exactly.

The CLI runs in-process (``irlc.cli.main``) to keep ~110 programs well under 30 s;
``test_real_executable`` checks that the installed ``irlc`` behaves the same.
"""

from __future__ import annotations

import contextlib
import io
import re
import subprocess
import sys
from pathlib import Path

import pytest
from irlc.cli import main

HERE = Path(__file__).parent
VALID = sorted((HERE / "valid").glob("*.irl"))
INVALID = sorted((HERE / "invalid").glob("*.irl"))

HEADER = re.compile(r"\{\s*expect:\s*(?P<spots>\d+:\d+(?:\|\d+:\d+)*)\s+(?P<frag>.*?)\s*\}")
DL_HEADER = re.compile(r"\{\s*expect-datalist:\s*(?P<file>\S+)\s+(?P<frag>.*?)\s*\}")
ARGS = re.compile(r"\{\s*args:\s*(?P<args>.*?)\s*\}")
# lark terminal names that must never leak into a user-facing message
LARK_NAMES = re.compile(
    r"\$END|__ANON|\b(?:SEMICOLON|LPAR|RPAR|LSQB|RSQB|COMMA|COLON|DOT|EQUAL|MORETHAN|LESSTHAN"
    r"|SIGNED_NUMBER|ESCAPED_STRING|CNAME|_NL|_WS|STAR|SLASH|PLUS|MINUS)\b"
)


def run_cli(*argv: str) -> tuple[int, str, str]:
    """Run ``irlc ARGV`` in-process; return (exit code, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        rc = main(list(argv))
    return rc, out.getvalue(), err.getvalue()


def extra_args(path: Path) -> list[str]:
    m = ARGS.search("\n".join(path.read_text().splitlines()[:2]))
    return m.group("args").split() if m else []


def assert_no_crash(stderr: str) -> None:
    assert "Traceback" not in stderr
    assert "internal error" not in stderr.lower()


@pytest.mark.parametrize("path", VALID, ids=lambda p: p.stem)
def test_valid_program_compiles_and_disassembles(path: Path, tmp_path: Path) -> None:
    args = extra_args(path)
    rc, _, err = run_cli("check", str(path), *args)
    assert_no_crash(err)
    assert rc == 0, err
    ird = tmp_path / "out.ird"
    rc, _, err = run_cli("compile", str(path), "-o", str(ird), *args)
    assert rc == 0, err
    assert ird.stat().st_size > 0
    rc, listing, err = run_cli("disasm", str(ird))
    assert rc == 0, err
    assert listing.strip()


def parse_expectation(path: Path) -> tuple[list[tuple[int, int]], str]:
    m = HEADER.match(path.read_text())
    assert m, f"{path.name}: missing expect header"
    spots = [tuple(map(int, s.split(":"))) for s in m.group("spots").split("|")]
    return spots, m.group("frag")  # type: ignore[return-value]


def caret_column(stderr_lines: list[str], source_line: str) -> int | None:
    """Column (1-based) the caret points at, measured against the echoed source line."""
    for i, line in enumerate(stderr_lines[:-1]):
        text = source_line.strip()
        if text and text in line and re.fullmatch(r"\s*\^[\^~]*\s*", stderr_lines[i + 1]):
            prefix = line.index(text) - (len(source_line) - len(source_line.lstrip()))
            return stderr_lines[i + 1].index("^") - prefix + 1
    return None


@pytest.mark.parametrize(
    "path", [p for p in INVALID if HEADER.match(p.read_text())], ids=lambda p: p.stem
)
def test_invalid_program_reports_position(path: Path) -> None:
    spots, fragment = parse_expectation(path)
    rc, _, err = run_cli("check", str(path), *extra_args(path))
    assert_no_crash(err)
    assert rc == 1, err
    first = err.splitlines()[0]
    m = re.match(rf"{re.escape(str(path))}:(\d+):(\d+): error: ", first)
    assert m, f"bad first line: {first!r}"
    where = (int(m.group(1)), int(m.group(2)))
    assert where in spots, f"reported {where}, expected one of {spots}: {err}"
    assert fragment.lower() in err.lower(), err
    source_line = path.read_text().splitlines()[where[0] - 1]
    assert caret_column(err.splitlines(), source_line) == where[1], err
    assert not LARK_NAMES.search(err), err


@pytest.mark.parametrize(
    "path", [p for p in INVALID if DL_HEADER.match(p.read_text())], ids=lambda p: p.stem
)
def test_invalid_datalist_names_file_and_key(path: Path) -> None:
    m = DL_HEADER.match(path.read_text())
    assert m
    rc, _, err = run_cli("check", str(path))
    assert_no_crash(err)
    assert rc == 1, err
    assert "error:" in err
    assert m.group("file") in err, err
    assert m.group("frag").lower() in err.lower(), err


def test_every_invalid_program_has_a_header() -> None:
    for p in INVALID:
        text = p.read_text()
        assert HEADER.match(text) or DL_HEADER.match(text), p.name


def test_corpus_size() -> None:
    assert len(VALID) >= 30
    assert len(INVALID) >= 40


# ---- diagnostic quality -----------------------------------------------------------


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "prog.irl"
    path.write_text(text)
    return path


def test_messages_echo_declared_spelling(tmp_path: Path) -> None:
    """A name used in another case is reported with its declared spelling."""
    path = write(
        tmp_path,
        "PROGRAM t;\nROBOT r := planar3;\nPROCEDURE Corner(REAL: x);\nBEGIN\nENDPROC;\n"
        "BEGIN\n  CORNER(1, 2);\nENDPROGRAM\n",
    )
    rc, _, err = run_cli("check", str(path))
    assert rc == 1
    assert "Corner" in err.splitlines()[0], err


def test_duplicate_declaration_names_first_spelling(tmp_path: Path) -> None:
    path = write(
        tmp_path,
        "PROGRAM t;\nROBOT r := planar3;\nVAR\n  POSE: Poz_A;\n  REAL: poz_a;\nBEGIN\nENDPROGRAM\n",
    )
    rc, _, err = run_cli("check", str(path))
    assert rc == 1
    assert "Poz_A" in err and "line 4" in err, err


def test_cyclicend_colon_has_hint() -> None:
    rc, _, err = run_cli("check", str(HERE / "invalid" / "e08_cyclicend_colon.irl"))
    assert rc == 1
    assert "hint:" in err, err


def test_unknown_obstacle_lists_known_names() -> None:
    rc, _, err = run_cli("check", str(HERE / "invalid" / "e47_unknown_obstacle.irl"))
    assert rc == 1
    for known in ("okno", "kula", "sciana_1"):
        assert known in err, err


def test_robot_conflict_warns() -> None:
    rc, _, err = run_cli(
        "check", str(HERE / "valid" / "v40_robot_both_differ.irl"), "--robot", "planar3"
    )
    assert rc == 0, err
    assert "warning:" in err and "planar3" in err and "koch11" in err, err


def test_real_executable() -> None:
    """The installed console script gives the same result as the in-process runs."""
    irlc = Path(sys.executable).parent / "irlc"
    bad = HERE / "invalid" / "e26_add_pose_real.irl"
    proc = subprocess.run([str(irlc), "check", str(bad)], capture_output=True, text=True)
    assert proc.returncode == 1
    assert proc.stderr.startswith(f"{bad}:7:")
    good = HERE / "valid" / "v05_seed_example.irl"
    proc = subprocess.run([str(irlc), "check", str(good)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
