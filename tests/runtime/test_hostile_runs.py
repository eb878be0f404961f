"""Hostile programs at run time (issue 11): exit 1/2/3 with a position, never 4.

Each test reproduces one crash the adversarial run found.
"""

from __future__ import annotations

from pathlib import Path

from irlc.lang.irdata import MAX_STRING

from irlc.cli import main


def run(tmp_path: Path, capsys, body: str, robot: str = "planar3", *extra: str):
    """Run a program whose main body is ``body``; (exit code, stdout, stderr flattened)."""
    prog = tmp_path / "p.irl"
    prog.write_text(f"PROGRAM p;\nROBOT r := {robot};\nBEGIN\n{body}\nENDPROGRAM\n", "utf-8")
    code = main(["run", str(prog), "-q", "--trace", str(tmp_path / "t.csv"), *extra])
    out = capsys.readouterr()
    assert "Traceback" not in out.err and "internal error" not in out.err, out.err
    return code, out.out, " ".join(out.err.split())


def test_zero_length_ptp_with_time_holds_for_that_time(tmp_path, capsys) -> None:
    # A hold profile (acceleration 0) divided 0/0 in Trapezoid.at: ZeroDivisionError.
    code, _, err = run(
        tmp_path, capsys, "  MOVE PTP R_ACT_JOINT;\n  MOVE PTP R_ACT_JOINT WITH TIME := 1;"
    )
    assert code == 0, err
    rows = (tmp_path / "t.csv").read_text().splitlines()
    assert rows[-1].split(",")[:2] == ["1", "5"]  # held at line 5 until t = 1 s


def test_string_doubling_stops_at_the_maximum_length(tmp_path, capsys) -> None:
    # Doubling 40 times ended in MemoryError: STRING holds at most MAX_STRING characters.
    prog = tmp_path / "p.irl"
    prog.write_text(
        "PROGRAM p;\nROBOT r := planar3;\nVAR STRING: s; INTEGER: i;\nBEGIN\n  s := 'ab';\n"
        "  FOR i := 1 TO 40 DO\n    s := s + s;\n  ENDFOR;\nENDPROGRAM\n",
        "utf-8",
    )
    code = main(["run", str(prog), "-q"])
    err = " ".join(capsys.readouterr().err.split())
    assert code == 2, err
    # 2·2^15 = 65,536 characters is the first length beyond 65,535, at line 7
    assert f"{prog}:7:1: error: run-time failure at t = 0.000 s" in err
    assert (
        f"string concatenation: a STRING of 65536 characters is too long (at most {MAX_STRING})"
        in err
    )
