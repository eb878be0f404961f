"""``irlc run --compare``: what the comparison says when the two runs are not alike."""

from __future__ import annotations

import json

from irlc.cli import main

PROGRAM = """PROGRAM p;
ROBOT r := {robot};
BEGIN
  MOVE PTP {target};
ENDPROGRAM
"""


def _run(tmp_path, capsys, robot: str, target: str, *args: str) -> tuple[int, str]:
    prog = tmp_path / f"{robot}.irl"
    prog.write_text(PROGRAM.format(robot=robot, target=target), encoding="utf-8")
    code = main(["run", str(prog), *args])
    return code, capsys.readouterr().out


def _notes(out: str) -> list[str]:
    return [line for line in out.splitlines() if line.startswith("note: ")]


def test_another_robots_report_is_named_and_unmatched_joints_listed(tmp_path, capsys):
    report = tmp_path / "three.json"
    code, _ = _run(tmp_path, capsys, "planar3", "(10, 80, -80)", "-q", "--report",
                   str(report))  # fmt: skip
    assert code == 0
    theirs = json.loads(report.read_text())
    code, out = _run(tmp_path, capsys, "planar4", "(10, 80, -80, 5)", "--compare",
                     str(report))  # fmt: skip
    assert code == 0
    assert f"compared with {report}" in out.splitlines()  # on a line of its own, whole
    their_joints = {j["name"] for j in theirs["joints"]}
    only_here = [n for n in ("a1", "a2", "a3", "a4") if n not in their_joints]
    assert only_here == ["a4"]
    assert _notes(out) == [
        "note: that run is of robot 'planar3', this one of 'planar4': joints are matched by name",
        f"note: not in that run (shown as —): {', '.join(only_here)}",
    ]
    a4_rows = [line.split("│") for line in out.splitlines() if line.lstrip().startswith("a4 ")]
    assert len(a4_rows) == 3 and all(row[2].strip() == "—" for row in a4_rows)


def test_a_trace_with_more_joints_and_a_failed_report_are_noted(tmp_path, capsys):
    trace = tmp_path / "four.csv"
    report = tmp_path / "four.json"
    code, _ = _run(tmp_path, capsys, "planar4", "(10, 80, -80, 5)", "-q",
                   "--trace", str(trace))  # fmt: skip
    assert code == 0
    code, out = _run(tmp_path, capsys, "planar3", "(10, 80, -80)", "--compare",
                     str(trace))  # fmt: skip
    assert code == 0
    assert _notes(out) == [
        "note: a trace names no robot, and this one's joints differ from this run's: it may "
        "be another robot's; joints are matched by name",
        "note: only in that run (not shown): a4",
    ]
    from irlc.report import load_run
    from irlc.run_data import run_data

    assert run_data(load_run(trace)).label == "four.csv"  # the figures' legend names it
    failed = {"status": "failed", "robot": "planar3", "duration_s": 1.0, "joints": []}
    report.write_text(json.dumps(failed), encoding="utf-8")
    code, out = _run(tmp_path, capsys, "planar3", "(10, 80, -80)", "--compare",
                     str(report))  # fmt: skip
    assert code == 0
    assert _notes(out) == ["note: that run's status is 'failed': its numbers stop where it stopped"]


def test_alike_runs_get_no_note(tmp_path, capsys):
    report = tmp_path / "same.json"
    args = ("planar3", "(10, 80, -80)")
    assert _run(tmp_path, capsys, *args, "-q", "--report", str(report))[0] == 0
    code, out = _run(tmp_path, capsys, *args, "--compare", str(report))
    assert code == 0 and _notes(out) == []
    rows = [line.split("│") for line in out.splitlines() if line.lstrip().startswith("a2 max")]
    assert len(rows) == 1 and float(rows[0][1]) == float(rows[0][2])  # the same run


def test_the_summary_ends_with_the_files_written(tmp_path, capsys):
    """Regression (new-user walk): `compile` said `wrote FILE`, `run` wrote its report,
    trace and export without a word."""
    report, trace, export = (tmp_path / n for n in ("r.json", "t.csv", "e.json"))
    args = ("--report", str(report), "--trace", str(trace), "--export-trajectory", str(export))
    code, out = _run(tmp_path, capsys, "planar3", "(10, 80, -80)", *args)
    assert code == 0 and all(p.is_file() for p in (report, trace, export))
    assert out.splitlines()[-1] == f"wrote report {report}, trace {trace}, trajectory {export}"
    code, out = _run(tmp_path, capsys, "planar3", "(10, 80, -80)", "-q", *args)
    assert code == 0 and out == ""  # quiet: nothing
