"""Hostile programs at run time (issue 11): exit 1/2/3 with a position, never 4.

Each test reproduces one crash the adversarial run found.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from irlc.cli import main
from irlc.lang.irdata import MAX_STRING


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
    assert f"{prog}:7:5: error: run-time failure at t = 0.000 s" in err
    assert (
        f"string concatenation: a STRING of 65536 characters is too long (at most {MAX_STRING})"
        in err
    )


RANGE = "is outside the physical range of a coordinate (within ±1e+06 mm)"
BUDGET = "the run's simulated-time budget of 86400 s"


@pytest.mark.parametrize(
    ("body", "line", "message"),
    [
        # OverflowError in cycles() / executor.wait (ceil of an infinite cycle count)
        ("WAIT 1e308 SEC;", 4, "the WAIT would take 1e+308 s and the run past its simulated"),
        # MemoryError after 40 s: one trace sample per IPO cycle of a 30-year wait
        ("WAIT 1e9 SEC;", 4, "the WAIT would take 1e+09 s and the run past its simulated"),
        # ZeroDivisionError in minimum_time: the normalised speed underflowed to 0
        ("MOVE LIN POSE(-1e308, 0, 0, 0, 0, 0);", 4, f"MOVE target: x = -1e+308 mm {RANGE}"),
        ("MOVE_INC LIN POSE(1e308, 0, 0, 0, 0, 0);", 4, "MOVE_INC LIN target: x = 1e+308 mm"),
        ("R_TOOL := POSE(1e300, 0, 0, 0, 0, 0);\nMOVE PTP (10, 10, 10);", 5, "R_TOOL: x = 1e+300"),
        (
            "R_BASE := POSE(0, 1e300, 0, 0, 0, 0);\nMOVE LIN POSE(1500, 500, 0, 0, 0, 0);",
            5,
            f"R_BASE: y = 1e+300 mm {RANGE}",
        ),
        # not finished after 60 s
        ("R_ACC := 1e-320;\nMOVE LIN POSE(1500, 500, 0, 0, 0, 0);", 5, BUDGET),
        (  # a denormal speed underflowed to 0 in SI: ZeroDivisionError (found by the fuzz)
            "R_SPEED := 5e-324;\nMOVE LIN POSE(1500, 500, 0, 0, 0, 0);",
            5,
            "the path speed, acceleration or orientation speed is too small to move",
        ),
        ("MOVE PTP (10, 10, 10) WITH SPEED_PTP := 1e-300;", 4, BUDGET),
        (
            "RECONFIGURATION (1e300, 0, 0);",
            4,
            "RECONFIGURATION target: joint a1 (J1) is at 1e+300 deg",
        ),
        # exited 0: a reconfiguration target outside the limits
        (
            "RECONFIGURATION (0, 200, -200);",
            4,
            "RECONFIGURATION target: joint a2 (J2) is at 200 deg, above the upper bound",
        ),
    ],
)
def test_hostile_motion_is_a_run_failure_at_its_line(tmp_path, capsys, body, line, message):
    code, _, err = run(tmp_path, capsys, body)
    assert code == 2, err
    assert f"p.irl:{line}:1: error: run-time failure at t = 0.000 s" in err
    assert message in err


def test_the_simulated_time_budget_is_settable(tmp_path, capsys) -> None:
    code, _, err = run(tmp_path, capsys, "WAIT 0.5 SEC;\nWAIT 1 SEC;", "planar3", "--max-time", "1")
    assert code == 2
    assert "p.irl:5:1: error: run-time failure at t = 0.500 s: the WAIT would take 1 s" in err
    assert "budget of 1 s" in err
    code, _, err = run(tmp_path, capsys, "WAIT 0.5 SEC;", "planar3", "--max-time", "1")
    assert code == 0, err
    code, _, err = run(tmp_path, capsys, "WAIT 0.5 SEC;", "planar3", "--max-time", "-1")
    assert code == 3 and "--max-time must be a positive number of seconds" in err


def _ird_with_lines(tmp_path, capsys, relabel) -> tuple[int, str]:
    prog = tmp_path / "w.irl"
    prog.write_text(
        "PROGRAM w;\nROBOT r := planar3;\nVAR REAL: t;\nBEGIN\n  t := -1;\n  WAIT t SEC;\n"
        "ENDPROGRAM\n",
        "utf-8",
    )
    ird = tmp_path / "w.ird"
    assert main(["compile", str(prog), "-o", str(ird)]) == 0
    prog.unlink()  # the run reports against the .ird itself
    ird.write_text(relabel(ird.read_text("utf-8")), "utf-8")
    code = main(["run", str(ird), "-q"])
    out = capsys.readouterr()
    assert "Traceback" not in out.err and "internal error" not in out.err, out.err
    return code, " ".join(out.err.split())


def test_a_failure_in_code_without_a_line_names_the_nearest_line(tmp_path, capsys) -> None:
    # A hand-made .ird whose failing instruction says L0: the failure named no line.
    code, err = _ird_with_lines(tmp_path, capsys, lambda t: t.replace(" L6 ", " L0 "))
    assert code == 2
    assert "w.ird:5:1: error: run-time failure at t = 0.000 s: WAIT -1.0 SEC: the time" in err


def test_a_failure_in_code_without_any_line_says_so(tmp_path, capsys) -> None:
    import re

    code, err = _ird_with_lines(tmp_path, capsys, lambda t: re.sub(r" L\d+ ", " L0 ", t))
    assert code == 2
    assert "(the code records no source line for it): WAIT -1.0 SEC" in err


def test_library_noise_does_not_reach_stderr(capsys, caplog) -> None:
    import logging
    import warnings

    import numpy as np
    from irlc.cli import quiet_libraries

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a warning that got through would raise here
        with quiet_libraries():
            assert np.isinf(np.float64(1e308) * np.float64(10.0))
            logging.getLogger("yourdfpy.urdf").warning("unknown tag <bogus>")
    assert "unknown tag" not in caplog.text + capsys.readouterr().err
    assert logging.getLogger("yourdfpy").level == logging.NOTSET  # restored
