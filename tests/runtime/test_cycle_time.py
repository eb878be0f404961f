"""Cycle time per statement (report ``statements``): one row per statement that takes
simulated time, durations from the closed form of the trapezoid, summing to the run's
duration — also in loops and when the run fails."""

from __future__ import annotations

import itertools
import json

import pytest
from irlc.cli import main
from irlc.runtime.run import run_file

# planar3 starts at its home (0, 90, -90): the TCP at (2000, 1000) mm
PROGRAM = """PROGRAM cy;
ROBOT r := planar3;
VAR INTEGER: i;
BEGIN
  R_SPEED := 200;
  R_ACC := 500;
  MOVE LIN POSE(1000, 1000, 0, 0, 0, 0);  { first: the comment is not shown }
  WAIT 0.5 SEC;
  MOVE LIN POSE(1000, 0, 0, 0, 0, 0) WITH TIME := 6;
  FOR i := 1 TO 2 DO
    MOVE PTP (0, 90, -90);
    MOVE PTP (10, 90, -90);
  ENDFOR;
  {TAIL}
ENDPROGRAM
"""


def _run(tmp_path, tail: str = ""):
    path = tmp_path / "cy.irl"
    path.write_text(PROGRAM.replace("{TAIL}", tail), encoding="utf-8")
    return run_file(path)


def test_rows_and_closed_form_durations(tmp_path):
    run = _run(tmp_path)
    assert run.ok, run.error
    rows = run.report["statements"]
    assert [(r["line"], r["kind"]) for r in rows] == [
        (7, "MOVE LIN"), (8, "WAIT"), (9, "MOVE LIN"),
        (11, "MOVE PTP"), (12, "MOVE PTP"), (11, "MOVE PTP"), (12, "MOVE PTP"),
    ]  # fmt: skip
    assert rows[0]["statement"] == "MOVE LIN POSE(1000, 1000, 0, 0, 0, 0);"
    assert rows[0]["duration_s"] == pytest.approx(1000 / 200 + 200 / 500)  # L/v + v/a
    assert rows[0]["limit"] == "path speed/acceleration" and rows[0]["stop"] == "exact"
    assert rows[1]["duration_s"] == pytest.approx(0.5) and rows[1]["stop"] is None
    assert rows[2]["duration_s"] == pytest.approx(6.0) and rows[2]["limit"] == "WITH TIME"
    # PTP of joint a1 by 10°: R_SPEED_PTP = R_ACC_PTP = 50 % of 90°/s, 500°/s²; short move
    # (a triangle): T = 2·sqrt(Δ/a), rounded up to whole 10 ms cycles
    t_ptp = 2 * (10 / 250) ** 0.5
    assert rows[4]["duration_s"] == pytest.approx(t_ptp, abs=0.0101)
    assert rows[4]["limit"] == "joint a1 (J1) speed/acceleration"
    # the spans tile the run
    for a, b in itertools.pairwise(rows):
        assert b["start_s"] == pytest.approx(a["start_s"] + a["duration_s"], abs=1e-9)
    total = sum(r["duration_s"] for r in rows)
    assert total == pytest.approx(run.report["duration_s"], abs=1e-9)


def test_failed_run_still_sums(tmp_path):
    run = _run(tmp_path, "MOVE LIN POSE(5000, 0, 0, 0, 0, 0);")  # out of reach
    assert not run.ok
    rows = run.report["statements"]
    assert rows[-1]["stop"] == "failed" and rows[-1]["line"] == 14
    total = sum(r["duration_s"] for r in rows)
    assert total == pytest.approx(run.report["duration_s"], abs=1e-9)


def test_summary_and_gantt(tmp_path, capsys):
    path = tmp_path / "cy.irl"
    path.write_text(PROGRAM.replace("{TAIL}", ""), encoding="utf-8")
    pytest.importorskip("matplotlib")
    report = tmp_path / "r.json"
    assert main([str(path), "--plot", str(tmp_path / "figs"), "--report", str(report)]) == 0
    out = capsys.readouterr().out
    assert "cycle time per statement" in out and "WITH TIME" in out
    duration = json.loads(report.read_text(encoding="utf-8"))["duration_s"]
    assert f"sum {duration:.3f}" in " ".join(out.replace("│", " ").split())
    png = (tmp_path / "figs" / "cycle_time.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 5000


def test_without_the_source_the_kind_is_shown(tmp_path):
    from irlc.api import compile_program
    from irlc.runtime.run import run_code

    path = tmp_path / "cy.irl"
    path.write_text(PROGRAM.replace("{TAIL}", ""), encoding="utf-8")
    code = compile_program(path)
    path.unlink()
    rows = run_code(code, base_dir=tmp_path).report["statements"]
    assert [r["statement"] for r in rows[:3]] == ["MOVE LIN", "WAIT", "MOVE LIN"]


def test_summary_of_a_loop_sums_per_line(tmp_path):
    import io

    from irlc.summary import render_summary
    from rich.console import Console

    path = tmp_path / "loop.irl"
    path.write_text(PROGRAM.replace("TO 2 DO", "TO 10 DO").replace("{TAIL}", ""), "utf-8")
    run = run_file(path)
    assert run.ok and len(run.report["statements"]) == 23
    per_line = {}
    for r in run.report["statements"]:
        per_line[r["line"]] = per_line.get(r["line"], 0.0) + r["duration_s"]
    buf = io.StringIO()
    render_summary(run.report, Console(file=buf, width=200, no_color=True))
    text = " ".join(buf.getvalue().replace("│", " ").split())
    assert "cycle time per statement, summed (s), 23 runs" in text
    share = 100 * per_line[12] / run.report["duration_s"]
    assert f"12 MOVE PTP (10, 90, -90); 10 {per_line[12]:.3f} {share:.1f} %" in text
    assert f"sum {run.report['duration_s']:.3f}" in text


SHARED = """PROGRAM sh;
ROBOT r := planar3;
VAR POSE: p1, p2;  INTEGER: i;
PROCEDURE corner(POSE: p);
BEGIN
  MOVE LIN p;
ENDPROC;
BEGIN
  p1 := (1500, 1000, 0, 0, 0, 0);  p2 := (1000, 1500, 0, 0, 0, 0);
  MOVE LIN p1;  MOVE LIN p2;  WAIT 0.25 SEC;  MOVE LIN p1;  { three moves, one line }
  corner(p2);
  corner(p1);
  FOR i := 1 TO 2 DO MOVE LIN p2; WRITELN('MOVE LIN x; WAIT'); MOVE LIN p1; ENDFOR;
  IF i > 0 THEN MOVE LIN p2; ELSE MOVE LIN p1; ENDIF;
ENDPROGRAM
"""


def test_a_shared_line_shows_each_move_and_a_routine_its_call_site(tmp_path, capsys):
    """Statements sharing a line are shown one each (not the whole line for every one); a
    routine's motion names the routine and the line it was called at. A line with control
    flow and several moves of one kind is shown whole (which one ran is not known)."""
    path = tmp_path / "sh.irl"
    path.write_text(SHARED, encoding="utf-8")
    run = run_file(path)
    assert run.ok, run.error
    rows = [(r["line"], r["statement"], r["routine"], r["called_at"]) for r in
            run.report["statements"]]  # fmt: skip
    loop = "FOR i := 1 TO 2 DO MOVE LIN p2; WRITELN('MOVE LIN x; WAIT'); MOVE LIN p1; ENDFOR;"
    branch = "IF i > 0 THEN MOVE LIN p2; ELSE MOVE LIN p1; ENDIF;"
    assert rows == [
        (10, "MOVE LIN p1;", None, None),
        (10, "MOVE LIN p2;", None, None),
        (10, "WAIT 0.25 SEC;", None, None),
        (10, "MOVE LIN p1;", None, None),
        (6, "MOVE LIN p;", "corner", 11),
        (6, "MOVE LIN p;", "corner", 12),
        *[(13, loop, None, None)] * 4,
        (14, branch, None, None),
    ]
    assert main([str(path)]) == 0
    out = " ".join(capsys.readouterr().out.replace("│", " ").split())
    assert "6 MOVE LIN p; (corner, called at line 11)" in out
    assert "6 MOVE LIN p; (corner, called at line 12)" in out
    assert "10 MOVE LIN p2; 1.500" in out  # the second move of line 10 starts at 1.5 s


def test_with_time_after_a_blend_is_its_own_time(tmp_path):
    """APPROX 300 on a 500 mm side is shrunk to 250 mm and the blend to 0.5 s of the
    0.75 s tail: the next statement's span starts where it starts (not where the tail
    did), so its WITH TIME := 3 shows 3 s, and the spans still tile the run."""
    path = tmp_path / "bl.irl"
    path.write_text(
        "PROGRAM bl;\nROBOT r := planar3;\nBEGIN\n  MOVE LIN (1500, 1000, 0, 0, 0, 0);\n"
        "  MOVE LIN (1500, 1500, 0, 0, 0, 0) WITH APPROX := 300;\n"
        "  MOVE LIN (1000, 1500, 0, 0, 0, 0) WITH TIME := 3;\nENDPROGRAM\n",
        encoding="utf-8",
    )
    run = run_file(path)
    assert run.ok, run.error
    rows = run.report["statements"]
    (blend,) = run.report["approximations"]
    assert blend["blended"] and blend["saved_s"] == pytest.approx(0.5)
    assert rows[2]["limit"] == "WITH TIME" and rows[2]["duration_s"] == pytest.approx(3.0)
    # the approximated side: its 1.5 s (L/v + v/a) less the 0.5 s its blend saved
    assert rows[1]["duration_s"] == pytest.approx(1.5 - 0.5)
    for a, b in itertools.pairwise(rows):
        assert b["start_s"] == pytest.approx(a["start_s"] + a["duration_s"], abs=1e-9)
    assert sum(r["duration_s"] for r in rows) == pytest.approx(run.report["duration_s"])


@pytest.mark.parametrize("after", ["", "  WAIT 1 SEC;\n", "  MOVE LIN (1000, 1000, 0, 0, 0, 0);\n"])
def test_an_approximated_zero_length_move_keeps_the_spans_tiling(tmp_path, after):
    """A zero-length move after an approximated one moves nothing and blends nothing: the
    approximated move's tail (run at the exact stop that follows, or blended into the next
    motion) stays in the spans — on main the program's end or a WAIT lost it (the
    statement times summed to 1.19 s of a 1.5 s run)."""
    path = tmp_path / "z.irl"
    path.write_text(
        "PROGRAM z;\nROBOT r := planar3;\nBEGIN\n"
        "  MOVE LIN (1500, 1000, 0, 0, 0, 0) WITH APPROX := 50;\n"
        "  MOVE LIN (1500, 1000, 0, 0, 0, 0) WITH APPROX := 50;\n" + after + "ENDPROGRAM\n",
        encoding="utf-8",
    )
    run = run_file(path)
    assert run.ok, run.error
    rows = run.report["statements"]
    assert rows[1]["duration_s"] == 0.0 and rows[1]["stop"] == "exact"
    for a, b in itertools.pairwise(rows):
        assert b["start_s"] == pytest.approx(a["start_s"] + a["duration_s"], abs=1e-9)
    assert sum(r["duration_s"] for r in rows) == pytest.approx(run.report["duration_s"])
    if not after:  # the first side alone: L/v + v/a = 500/500 + 500/1000
        assert rows[0]["duration_s"] == pytest.approx(1.5) and rows[0]["stop"] == "exact"
