"""Golden-test mechanics: reduction, tolerant comparison, readable diffs, --update, CLI."""

from __future__ import annotations

import json
import math

import pytest
from irlc import golden
from irlc.cli import main
from irlc.golden import compare, nice_bound, reduce_report, run_case, run_golden

from .tool_fixtures import make_run


def _report(**changes):
    report = make_run().report
    report.update(changes)
    return report


def _program(tmp_path, name="tiny", text="PROGRAM tiny;\nBEGIN\nENDPROGRAM\n"):
    p = tmp_path / f"{name}.irl"
    p.write_text(text)
    return p


def test_reduction_rounds_and_bounds():
    red = reduce_report(_report())
    assert red["status"] == "ok" and red["error_line"] is None
    assert red["samples"] == 301 and red["duration_s"] == 3.0
    assert red["joints"]["a1"]["max"] == round(30.0 * math.sin(1.5), 2)  # at t = 3 s
    assert red["joints"]["a3"]["end"] == round(150.0 * 0.932039085967226, 2)  # sin(1.2)
    assert red["max_path_error_mm_below"] == 0.001  # 2·1e-4 is below the 1 µm floor
    assert red["output"] == ["hello"] and red["ik_relaxed_cycles"] == 0


@pytest.mark.parametrize(
    ("value", "bound"),
    [(0.0, 1e-3), (0.3, 1.0), (0.26, 1.0), (0.24, 0.5), (4.9, 10.0), (1e-3, 2e-3)],
)
def test_nice_bound(value, bound):
    assert nice_bound(value) == pytest.approx(bound)
    assert nice_bound(value) >= 2 * value


def test_last_digit_noise_passes_real_changes_fail():
    base = reduce_report(_report())
    noisy = _report()
    noisy["joints"][0]["max"] += 0.004  # below the 0.01 quantum
    noisy["duration_s"] += 1e-12
    noisy["max_path_error_mm"] *= 0.5  # better accuracy is fine
    assert compare(base, reduce_report(noisy)) == []
    worse = _report(max_path_error_mm=0.0006, output=["hello", "extra"])  # > 1 µm bound / 2
    worse["joints"][1]["min"] -= 0.5
    paths = {m.path for m in compare(base, reduce_report(worse))}
    assert paths == {"joints.a2.min", "max_path_error_mm_below", "output"}


def test_user_tolerances_widen_a_key():
    base = reduce_report(_report())
    moved = _report()
    moved["joints"][1]["min"] -= 0.5
    assert compare(base, reduce_report(moved), {"joints.a2": 1.0}) == []
    assert compare(base, reduce_report(moved), {"joints.a1": 1.0}) != []


def test_case_passes_fails_and_updates(tmp_path):
    prog = _program(tmp_path)
    report = _report()
    calls = []

    def runner(path, options):
        calls.append(options)
        return json.loads(json.dumps(report))

    assert run_case(prog, runner=runner).status == "missing"
    assert run_case(prog, update=True, runner=runner).status == "updated"
    exp = json.loads((tmp_path / "tiny.expected.json").read_text())
    assert exp["joints"]["a4"]["max"] == 45.0
    assert (tmp_path / "tiny.expected.txt").read_text() == "hello\n"
    assert run_case(prog, runner=runner).status == "pass"

    exp["joints"]["a4"]["max"] = 44.0  # a modified expectation fails with a readable diff
    exp["options"] = {"ipo": 0.005}
    (tmp_path / "tiny.expected.json").write_text(json.dumps(exp))
    (tmp_path / "tiny.expected.txt").write_text("bye\n")
    res = run_case(prog, runner=runner)
    assert res.status == "fail" and calls[-1] == {"ipo": 0.005}
    assert [(m.path, m.expected, m.actual) for m in res.mismatches] == [
        ("joints.a4.max", 44.0, 45.0)
    ]
    assert "-bye" in res.output_diff and "+hello" in res.output_diff

    run_case(prog, update=True, runner=runner)  # keeps the user's options
    again = json.loads((tmp_path / "tiny.expected.json").read_text())
    assert again["options"] == {"ipo": 0.005} and again["joints"]["a4"]["max"] == 45.0
    assert run_case(prog, runner=runner).status == "pass"


def test_compile_errors_are_golden_too(tmp_path):
    prog = _program(tmp_path, "bad")
    diag = {"status": "compile_error", "diagnostics": ["bad.irl:2:3: error: unknown name 'x'"]}
    run_case(prog, update=True, runner=lambda p, o: diag)
    assert run_case(prog, runner=lambda p, o: diag).status == "pass"
    other = {"status": "compile_error", "diagnostics": ["bad.irl:2:4: error: unknown name 'x'"]}
    assert run_case(prog, runner=lambda p, o: other).status == "fail"
    assert run_case(prog, runner=lambda p, o: _report()).status == "fail"


def test_cli_exit_codes_and_diff(tmp_path, monkeypatch, capsys):
    _program(tmp_path, "a")
    _program(tmp_path, "b")
    monkeypatch.setattr(golden, "default_runner", lambda p, o: _report())
    assert main(["test", str(tmp_path)]) == 1  # no expectations yet
    assert main(["test", str(tmp_path), "--update"]) == 0
    assert main(["test", str(tmp_path)]) == 0
    assert "2 passed" in capsys.readouterr().out
    exp = json.loads((tmp_path / "b.expected.json").read_text())
    exp["samples"] = 300
    (tmp_path / "b.expected.json").write_text(json.dumps(exp))
    assert main(["test", str(tmp_path)]) == 1
    out = capsys.readouterr().out
    assert "FAIL" in out and "samples" in out and "300" in out and "301" in out
    assert "1 passed, 1 failed" in out
    assert main(["test", str(tmp_path / "nope")]) == 3
    assert [r.status for r in run_golden(tmp_path, runner=lambda p, o: _report())] == [
        "pass",
        "fail",
    ]


def test_failure_table_never_cuts_the_key():
    """Regression (acceptance): on an 80-column log `obstacles.post.min_distance_mm` was
    shown as `obstacles.post.…`, hiding which quantity changed."""
    import io
    from pathlib import Path

    from irlc.golden import CaseResult, Mismatch, render_results
    from rich.console import Console

    key = "obstacles.a_long_obstacle_name.min_distance_mm"
    case = CaseResult(Path("cell.irl"), "fail", [Mismatch(key, 146.6, -77.8, "tolerance 0.1")])
    buf = io.StringIO()
    render_results([case], Console(file=buf, width=60, highlight=False, color_system=None))
    assert key in buf.getvalue(), buf.getvalue()


def test_reduced_report_names_its_units_and_older_expectations_still_pass():
    red = reduce_report(_report())
    assert red["units"] == {"length": "mm", "angle": "deg", "time": "s"}
    older = {k: v for k, v in red.items() if k != "units"}  # written before the key existed
    assert compare(older, red) == []
    wrong = {**red, "units": {"length": "m", "angle": "rad", "time": "s"}}
    assert [m.path for m in compare(wrong, red)] == ["units.length", "units.angle"]


def test_a_case_that_does_not_compile_or_fails_says_so_when_recorded_and_passing(tmp_path):
    """Regression (new-user walk): the tutorial copied square.irl without its data list;
    `--update` recorded a compile error and every later run said PASS, without a word."""
    prog = _program(tmp_path)
    head = "tiny.irl:5:17: error: data list 'cell.toml' not found"
    broken = {"status": "compile_error", "diagnostics": [head]}
    up = run_case(prog, update=True, runner=lambda p, o: broken)
    assert (up.status, up.message) == ("updated", f"recorded: it does not compile — {head}")
    again = run_case(prog, runner=lambda p, o: broken)
    assert (again.status, again.message) == ("pass", f"expected: it does not compile — {head}")
    failing = _report(status="failed", error={"message": "joint a2 beyond", "line": 3})
    assert run_case(prog, update=True, runner=lambda p, o: failing).message == (
        "recorded: the run fails — joint a2 beyond"
    )
    assert run_case(prog, runner=lambda p, o: failing).message == (
        "expected: the run fails — joint a2 beyond"
    )
    fine = _report()
    assert run_case(prog, update=True, runner=lambda p, o: fine).message == ""
    assert run_case(prog, runner=lambda p, o: fine).message == ""


def test_a_changed_output_is_counted_in_the_table_and_shown_by_the_diff():
    """Regression (probe): the table's output row showed raw JSON lists, wrapped and cut."""
    import io
    from pathlib import Path

    from irlc.golden import CaseResult, Mismatch, render_results
    from rich.console import Console

    want, got = [f"lap {i}: joints 0.0 90.0 -90.0" for i in range(4)], ["round 1"]
    case = CaseResult(
        Path("p.irl"), "fail", [Mismatch("output", want, got)], ["-lap 0", "+round 1"]
    )
    buf = io.StringIO()
    render_results([case], Console(file=buf, width=80, highlight=False, color_system=None))
    row = next(line for line in buf.getvalue().splitlines() if line.strip().startswith("output"))
    assert row.split() == ["output", "4", "lines", "1", "line", "the", "diff", "below"]
    assert "-lap 0" in buf.getvalue() and "+round 1" in buf.getvalue()


CELL = """PROGRAM pair;
ROBOT left := planar3;
ROBOT right := planar3 AT (3000, 0, 0, 180, 0, 0);
BEGIN
  R_SPEED := 500;
  MOVE left LIN POSE(1500, 1000, 0, 0, 0, 0);
  MOVE right PTP (20, 70, -60) AND left LIN POSE(1500, 500, 0, 0, 0, 0);
ENDPROGRAM
"""


def test_a_cell_s_golden_test_and_its_tolerance_keys(tmp_path, capsys):
    """A cell's expectation: every robot's joints (ROBOT_JOINT), the clearance overall and
    per pair of robots; tolerance keys for them (clearance, clearance.A-B, joints.ROBOT)."""
    _program(tmp_path, "pair", CELL)
    assert main(["test", str(tmp_path), "--update"]) == 0
    path = tmp_path / "pair.expected.json"
    exp = json.loads(path.read_text())
    assert set(exp["joints"]) == {f"{r}_a{j}" for r in ("left", "right") for j in (1, 2, 3)}
    assert exp["joints"]["right_a1"]["end"] == 20.0  # the PTP's target
    assert set(exp["clearance"]) == {"min_distance_mm", "left-left", "left-right", "right-right"}
    assert main(["test", str(tmp_path)]) == 0
    exp["clearance"]["min_distance_mm"] += 0.5
    exp["clearance"]["left-right"]["min_distance_mm"] -= 0.5
    exp["joints"]["right_a1"]["end"] += 0.3
    exp["joints"]["right_a2"]["max"] -= 0.3
    path.write_text(json.dumps(exp))
    capsys.readouterr()
    assert main(["test", str(tmp_path)]) == 1
    out = capsys.readouterr().out
    for key in ("clearance.min_distance_mm", "clearance.left-right.min_distance_mm",
                "joints.right_a1.end", "joints.right_a2.max"):  # fmt: skip
        assert key in out
    exp["tolerances"] = {"clearance.min_distance_mm": 0.6, "clearance.left-right": 0.6,
                         "joints.right": 0.4}  # fmt: skip
    path.write_text(json.dumps(exp))
    assert main(["test", str(tmp_path)]) == 0
    exp["tolerances"] = {"joints.right": 0.2}  # too narrow: fails again
    path.write_text(json.dumps(exp))
    assert main(["test", str(tmp_path)]) == 1
    for key, why in (("clearance.left-middle", "no pair of robots 'left-middle'"),
                     ("clearance.left-right.max", "has the fields min_distance_mm"),
                     ("joints.middle", "no joint 'middle'")):  # fmt: skip
        exp["tolerances"] = {key: 1.0}
        path.write_text(json.dumps(exp))
        capsys.readouterr()
        assert main(["test", str(tmp_path)]) == 1
        assert why in capsys.readouterr().out


def test_a_failing_case_says_why_the_run_failed_and_keeps_its_numbers_whole(tmp_path):
    """Regression (new-user walk, a cell): a case whose run now fails showed `status ok →
    failed` and `error_line 15` but not why, and on 80 columns its values were cut inside
    their digits (`-134.` / `76`, `faile` / `d`) while the note kept its whole width."""
    import io

    from irlc.golden import render_results
    from rich.console import Console

    prog = _program(tmp_path)
    run_case(prog, update=True, runner=lambda p, o: _report())
    failing = _report(status="failed", error={"message": "joint a2 beyond", "line": 3})
    res = run_case(prog, runner=lambda p, o: failing)
    assert (res.status, res.message) == ("fail", "now: the run fails — joint a2 beyond")
    assert run_case(prog, runner=lambda p, o: _report(samples=300)).message == ""
    buf = io.StringIO()
    render_results([res], Console(file=buf, width=80, highlight=False, color_system=None))
    text = buf.getvalue()
    assert "now: the run fails — joint a2 beyond" in text
    status = next(line for line in text.splitlines() if line.strip().startswith("status"))
    assert status.split() == ["status", "ok", "failed"]
    for m in res.mismatches:  # every number on one line, whole
        shown = m.actual if isinstance(m.actual, str) else json.dumps(m.actual)
        assert any(shown in line for line in text.splitlines()), (shown, text)
