"""Digital outputs OUT[n] / PULSE and the I/O columns of the trace: events at the
statements' times, trace columns from the timelines, range checks at compile and run time."""

from __future__ import annotations

import csv

import pytest
from irlc.api import compile_program
from irlc.cli import main
from irlc.lang.diagnostics import CompileError
from irlc.runtime.run import run_code, run_file

DATALIST = """# the cell
[inputs]   # part present at 3 s
2 = [[0.0, false], [3.0, true]]
"""
# planar3 starts at its home: the TCP at (2000, 1000) mm; the LIN takes 1000/200 + 200/500 s
PROGRAM = """PROGRAM io;
ROBOT r := planar3;
IMPORT DATALIST cell;
VAR SIGNAL: gripper;
BEGIN
  R_SPEED := 200;
  R_ACC := 500;
  OUT[3] := TRUE;
  MOVE LIN POSE(1000, 1000, 0, 0, 0, 0);
  PULSE(OUT[1], 0.5);
  WRITELN(OUT[1], ' ', OUT[3], ' ', IN[2]);
  WAIT 0.2 SEC;
  WRITELN(OUT[1]);
  WAIT 0.4 SEC;
  WRITELN(OUT[1]);
  OUT[3] := FALSE;
  gripper := TRUE;
  PULSE(OUT[7], 2);
  MOVE LIN POSE(1000, 0, 0, 0, 0, 0);
  PULSE(OUT[8], 2);
  OUT[8] := FALSE;
ENDPROGRAM
"""
T_LIN = 1000 / 200 + 200 / 500  # 5.4 s


@pytest.fixture(scope="module")
def io_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("io")
    (folder / "cell.toml").write_text(DATALIST, encoding="utf-8")
    (folder / "io.irl").write_text(PROGRAM, encoding="utf-8")
    trace = folder / "io.csv"
    assert main([str(folder / "io.irl"), "-q", "--trace", str(trace)]) == 0
    rows = list(csv.DictReader(trace.open(encoding="utf-8")))
    return run_file(folder / "io.irl"), rows, folder


def test_events_at_the_statements_times(io_run):
    run, _, _ = io_run
    assert run.ok and run.output == ["TRUE TRUE TRUE", "TRUE", "FALSE"]
    events = [e for e in run.report["events"] if e["kind"] == "output"]
    got = [(e["line"], round(e["time_s"], 9), e["output"], e["value"]) for e in events]
    t2 = round(2 * T_LIN + 0.6, 9)  # after the second LIN (1000 mm again: 5.4 s)
    t0 = round(T_LIN, 9)
    assert got == [
        (8, 0.0, 3, True),
        (10, t0, 1, True),
        (10, round(t0 + 0.5, 9), 1, False),  # the pulse's end, sorted in by time
        (16, round(t0 + 0.6, 9), 3, False),
        (18, round(t0 + 0.6, 9), 7, True),
        (18, round(t0 + 2.6, 9), 7, False),
        (20, t2, 8, True),
        (21, t2, 8, False),  # the assignment dropped the pulse's end
    ]  # fmt: skip
    assert events[1]["pulse_s"] == 0.5
    times = [e["time_s"] for e in run.report["events"]]
    assert times == sorted(times)


def test_trace_columns_follow_the_timelines(io_run):
    _, rows, _ = io_run
    columns = ["in_2", "out_1", "out_3", "out_7", "out_8", "signal_gripper"]
    assert list(rows[0])[-6:] == columns

    def at(t: float) -> str:
        row = min(rows, key=lambda r: abs(float(r["t_s"]) - t))
        assert float(row["t_s"]) == pytest.approx(t, abs=1e-9)
        return "".join(row[c] for c in columns)

    assert at(0.0) == "001000"
    assert at(2.99) == "001000"
    assert at(3.0) == "101000"  # the data list's input switches at 3 s
    assert at(5.39) == "101000"
    assert at(5.4) == "111000"  # PULSE right after the LIN: in the LIN's last row
    assert at(5.89) == "111000"
    assert at(5.9) == "101000"  # 0.5 s later
    assert at(6.0) == "100101"  # OUT[3] off, gripper on, PULSE(OUT[7], 2)
    assert at(7.99) == "100101"
    assert at(8.0) == "100001"  # PULSE(OUT[7], 2) ended during the LIN


def test_ird_round_trip_runs_the_same(io_run):
    run, _, folder = io_run
    from irlc.lang.irdata import read_code, write_code

    code = read_code(write_code(run.code), "io.ird")
    again = run_code(code, base_dir=folder)
    assert again.report["events"] == run.report["events"]
    assert again.trace_columns == run.trace_columns


def _errors(tmp_path, body: str, decls: str = "") -> list[tuple[int, int, str]]:
    src = f"PROGRAM e;\nROBOT r := planar3;\n{decls}BEGIN\n{body}\nENDPROGRAM\n"
    with pytest.raises(CompileError) as exc:
        compile_program(tmp_path / "e.irl", source=src)
    return [(d.span.line, d.span.column, d.message) for d in exc.value.diagnostics if d.is_error]


def test_compile_time_checks(tmp_path):
    errors = _errors(
        tmp_path,
        "OUT[0] := TRUE;\nOUT[4097] := FALSE;\nOUT[1] := 3;\nPULSE(OUT[1], 0);\n"
        "PULSE(1, 2);\nb := OUT[5000];",
        "VAR BOOLEAN: b;\n",
    )
    assert errors == [
        (5, 5, "output numbers are 1..4096, got 0"),
        (6, 5, "output numbers are 1..4096, got 4097"),
        (7, 11, "cannot assign to 'OUT[…]': expected BOOLEAN, got INTEGER"),
        (8, 15, "PULSE: the duration must be in (0, 86400] s, got 0"),
        (9, 1, "PULSE needs an output and a duration: PULSE(OUT[n], seconds)"),
        (10, 10, "output numbers are 1..4096, got 5000"),
    ]


def test_run_time_checks(tmp_path):
    path = tmp_path / "r.irl"
    for stmt, message in (
        ("OUT[i] := TRUE;", "output numbers are 1..4096, got 0"),
        ("PULSE(OUT[1], d);", "PULSE: the duration must be in (0, 86400] s, got -1.0"),
    ):
        path.write_text(
            "PROGRAM r;\nROBOT r := planar3;\nVAR INTEGER: i; REAL: d;\nBEGIN\n"
            f"i := 0; d := -1;\n{stmt}\nENDPROGRAM\n",
            encoding="utf-8",
        )
        run = run_file(path)
        assert not run.ok and run.error.line == 6 and run.error.message == message


def test_a_declared_out_is_the_programs_own(tmp_path):
    path = tmp_path / "own.irl"
    path.write_text(
        "PROGRAM own;\nROBOT r := planar3;\nVAR ARRAY [0..2] OF INTEGER: out;\nBEGIN\n"
        "OUT[0] := 5;\nWRITELN(OUT[0]);\nENDPROGRAM\n",
        encoding="utf-8",
    )
    run = run_file(path)
    assert run.ok and run.output == ["5"]
    assert not any(c.startswith("out_") for c in run.trace_columns)


def test_wait_for_the_end_of_a_pulse(tmp_path):
    path = tmp_path / "wf.irl"
    path.write_text(
        "PROGRAM wf;\nROBOT r := planar3;\nBEGIN\n  PULSE(OUT[1], 0.25);\n"
        "  WAIT FOR NOT OUT[1];\n  WRITELN(OUT[1]);\nENDPROGRAM\n",
        encoding="utf-8",
    )
    run = run_file(path)
    assert run.ok and run.output == ["FALSE"]
    assert run.report["duration_s"] == pytest.approx(0.25)
    assert [r["kind"] for r in run.report["statements"]] == ["WAIT"]
