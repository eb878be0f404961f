"""A reader that stops reading (``irlc run prog.irl | head -2``) does not change the run's
exit status: the rest of the standard output is dropped and the run carries on (click and
rich would both exit 1, the status of a program that does not compile)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

LOOP = """PROGRAM w;
ROBOT r := planar3;
VAR INTEGER: i;
BEGIN
  FOR i := 1 TO {n} DO
    WRITELN('line ', i);
  ENDFOR;
  MOVE PTP (10, 20, 30);
ENDPROGRAM
"""


def _run_and_close(tmp_path: Path, n: int, *options: str) -> tuple[int, str]:
    """Run ``irlc run`` on a program writing ``n`` lines; read its first line, then close
    the pipe. Returns the exit status and stderr."""
    program = tmp_path / "w.irl"
    program.write_text(LOOP.format(n=n), encoding="utf-8")
    cmd = [sys.executable, "-c", "from irlc.cli import entry; entry()", "run", str(program)]
    cmd += options
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=tmp_path)
    assert proc.stdout is not None and proc.stderr is not None
    first = proc.stdout.readline()
    proc.stdout.close()  # the reader goes away, as `head -1` does
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=300) is not None
    assert first  # something was written before the pipe closed
    return proc.returncode, err


@pytest.mark.parametrize(("n", "status"), [(20_000, 0), (100_000, 2)])
def test_a_closed_pipe_keeps_the_runs_exit_status(tmp_path: Path, n: int, status: int) -> None:
    code, err = _run_and_close(tmp_path, n)  # 100,000 lines: the endless-loop guard, exit 2
    assert code == status, err
    assert "Traceback" not in err and "internal error" not in err
    if status == 2:
        assert "w.irl:6:" in err  # the run's own failure is still reported


def _irlc(tmp_path: Path, args: list[str], stdout, env: dict | None = None):
    import os

    program = tmp_path / "w.irl"
    program.write_text(LOOP.format(n=3), encoding="utf-8")
    cmd = [sys.executable, "-c", "from irlc.cli import entry; entry()", *args]
    return subprocess.run(
        cmd, stdout=stdout, stderr=subprocess.PIPE, cwd=tmp_path, timeout=300,
        env={**os.environ, **(env or {})},
    )  # fmt: skip


NEGATIVE_WAIT = (
    "PROGRAM p;\nROBOT r := planar3;\nVAR REAL: x;\nBEGIN\n  x := -1;\n  WAIT x SEC;\nENDPROGRAM\n"
)


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="no /dev/full")
@pytest.mark.parametrize("args", [["run", "w.irl"], ["fk", "planar3", "0", "0", "0"], ["robots"]])
def test_a_full_standard_output_is_exit_3_naming_it(tmp_path, args):
    # an internal error before: OSError [Errno 28] escaped from click.echo / rich
    with open("/dev/full", "w") as full:
        done = _irlc(tmp_path, args, full)
    err = done.stderr.decode()
    assert done.returncode == 3, err
    assert err == "irlc: error: cannot write the standard output: No space left on device\n"


def test_a_closed_standard_output_or_an_ascii_one_does_not_stop_the_run(tmp_path):
    # closed (>&-: Python's sys.stdout is None): "AttributeError: 'NoneType' object has no
    # attribute 'isatty'", exit 4; PYTHONIOENCODING=ascii: UnicodeEncodeError on "²", exit 4
    import os

    (tmp_path / "w.irl").write_text(LOOP.format(n=3), encoding="utf-8")
    closed = subprocess.run(
        [sys.executable, "-c", "from irlc.cli import entry; entry()", "run", "w.irl"],
        stderr=subprocess.PIPE, cwd=tmp_path, timeout=300, preexec_fn=lambda: os.close(1),
    )  # fmt: skip
    assert closed.returncode == 0, closed.stderr.decode()
    ascii_run = _irlc(tmp_path, ["robot", "koch11"], subprocess.PIPE, {"PYTHONIOENCODING": "ascii"})
    assert ascii_run.returncode == 0, ascii_run.stderr.decode()
    assert b"\\u2014" in ascii_run.stdout  # the dash escaped, not a failure


@pytest.mark.parametrize("columns", ["0", "5"])
def test_a_tiny_columns_is_raised_to_a_readable_width(tmp_path, columns):
    # COLUMNS=0: `irlc robots` printed nothing (exit 0); COLUMNS=5: a character a line
    done = _irlc(tmp_path, ["robots"], subprocess.PIPE, {"COLUMNS": columns})
    out = done.stdout.decode()
    assert done.returncode == 0 and "planar3" in out, out
    assert max(len(line) for line in out.splitlines()) == 40  # MIN_COLUMNS


NEGATIVE_WAIT = (
    "PROGRAM p;\nROBOT r := planar3;\nVAR REAL: x;\nBEGIN\n  x := -1;\n  WAIT x SEC;\nENDPROGRAM\n"
)


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="no /dev/full")
@pytest.mark.parametrize(
    ("program", "args", "status"),
    [
        ("PROGRAM p;\nBEGIN\n  x := ;\nENDPROGRAM\n", ["check"], 1),  # a compile error
        (NEGATIVE_WAIT, ["run", "-q"], 2),  # a run-time failure
        (None, ["run"], 3),  # no such file
        (None, ["run", "--frob"], 3),  # click's usage error
    ],
)
def test_a_full_standard_error_keeps_the_exit_status(tmp_path: Path, program, args, status):
    """Regression: with ``2>/dev/full`` the message could not be written, and the failed
    write turned exit 1 and 2 into 3, and 3 into 1."""
    path = tmp_path / "p.irl"
    if program is not None:
        path.write_text(program, encoding="utf-8")
    cmd = [sys.executable, "-c", "from irlc.cli import entry; entry()", *args, str(path)]
    with open("/dev/full", "w") as full:
        done = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=full, cwd=tmp_path, timeout=300)
    assert done.returncode == status
