"""The summary's rows of issue 27 (kinetic energy, velocity ratio, platform) for a program of
one robot and per robot of a cell, read against the report the same run wrote."""

from __future__ import annotations

import json
import re

from irlc.cli import main
from irlc.summary import clearance_rows, measure_rows, render_summary
from rich.console import Console

from tests.tool.test_golden import CELL


def _text(report: dict) -> str:
    console = Console(record=True, width=200, no_color=True)
    render_summary(report, console)
    return console.export_text()


def test_one_row_each_where_present():
    report = {
        "kinetic_energy": {"max_j": 29.8926644, "max_at_time_s": 3.0, "integral_j_s": 95.6078174},
        "mvr": {"min": 0.0878773007, "min_at_time_s": 2.75, "max": 1.71038414,
                "max_at_time_s": 0.69},
        "platform": {"joints": ["a1", "a2"], "coordinates": ["x", "y"], "start_mm": [0.0, 0.0],
                     "end_mm": [0.0, 500.0], "motions": [{}, {}], "max_error_mm": 2.5e-7},
    }  # fmt: skip
    rows = dict(measure_rows(report))
    assert rows["kinetic energy"] == "max 29.89 J at t = 3.00 s, integral 95.61 J·s"
    assert rows["velocity ratio (MVR)"] == "min 0.08788 at t = 2.75 s, max 1.71 at t = 0.69 s (SI)"
    assert rows["platform"] == (
        "x 0 → 0, y 0 → 500 mm; 2 motions WITH PLATFORM, off their lines ≤ 2.5e-07 mm"
    )
    # null (a robot without inertials, nothing moved) or no platform: no row
    assert measure_rows({"kinetic_energy": None, "mvr": None}) == []
    one = {**report["platform"], "motions": [{}]}
    assert dict(measure_rows({"platform": one}))["platform"].endswith("off its line ≤ 2.5e-07 mm")
    assert "(no motion WITH PLATFORM)" in measure_rows({"platform": {**one, "motions": []}})[0][1]


def test_a_cell_summary_has_each_robot_s_rows(tmp_path, capsys):
    program = tmp_path / "pair.irl"
    program.write_text(CELL, encoding="utf-8")
    report_path = tmp_path / "r.json"
    assert main([str(program), "--report", str(report_path)]) == 0
    out = capsys.readouterr().out
    report = json.loads(report_path.read_text(encoding="utf-8"))
    assert "kinetic_energy" not in report  # a cell: per robot
    sections = out.split("right (planar3) at (3000, 0, 0, 180, 0, 0)")
    assert len(sections) == 2  # the right robot's section, after the left's
    left, right = report["robots"]
    for entry, text in ((left, sections[0]), (right, sections[1])):
        energy = entry["kinetic_energy"]
        assert f"max {energy['max_j']:.4g} J" in text
        assert f"integral {energy['integral_j_s']:.4g} J·s" in text
        assert f"min {entry['mvr']['min']:.4g} at t = " in text
    assert "left: joints" in sections[0] and "right: joints" in sections[1]
    assert _text(report).count("kinetic energy") == 2


def test_each_robot_s_drives_in_a_cell_summary(tmp_path, capsys):
    program = tmp_path / "six.irl"
    program.write_text(
        "PROGRAM six;\nROBOT a := as6;\nROBOT b := as6 AT (0, -2200, 0, 180, 0, 0);\nBEGIN\n"
        "  MOVE a PTP (90, 40, 0, 45, 90, 0) AND b PTP (90, 40, 0, 45, 90, 0);\nENDPROGRAM\n",
        encoding="utf-8",
    )
    assert main([str(program), "--drives", "decoupled"]) == 0
    out = capsys.readouterr().out
    rows = re.findall(r"│ drives +decoupled, step 1 ms, could follow", out)
    assert len(rows) == 2  # one per robot (the cell's own drives row is not at the top)
    # each robot says what judged its drive run, and the cell's path error row points there
    assert out.count("│ verdict criteria") == 2
    judged = r"│ path error +max .* \(actual motion; ideal .*\), not judged"
    assert len(re.findall(judged, out)) == 2
    # the cell's row: the actual motion, the set points' (ideal) beside it, judged per robot
    assert re.search(r"\(actual motion; ideal .*; judged per robot below\)", out)


def test_r_clearance_row_names_own_pairs_closer_at_home():
    pair = {"min_distance_mm": 7.9, "at_time_s": 5.72, "line": 21, "link_a": 5, "link_b": 7}
    other = {"min_distance_mm": 51.0, "at_time_s": 5.64, "line": 21, "link_a": 5, "link_b": 4}
    clearance = {
        "required_mm": 50.0,
        "pairs": [
            {**other, "robot_a": "ceiling", "robot_b": "floor"},
            {**pair, "robot_a": "floor", "robot_b": "floor"},
        ],
    }
    rows = dict(clearance_rows({"status": "ok", "clearance": clearance}))
    assert rows["R_CLEARANCE"] == (
        "50 mm kept (floor's own links 5, 7: closer at home, kept apart only)"
    )
    assert rows["clearance floor (own links)"].startswith("min 7.9 mm (links 5, 7)")
    failed = dict(clearance_rows({"status": "failed", "clearance": clearance}))
    assert failed["R_CLEARANCE"] == "50 mm kept"  # a failed run: no claim about home


def test_a_least_distance_at_the_start_names_no_line_0():
    own = {"min_distance_mm": 7.3, "at_time_s": 0.0, "line": 0, "link_a": 8, "link_b": 10}
    rows = dict(clearance_rows({"status": "ok", "self_clearance": own}))
    assert rows["own links"] == "min 7.3 mm (links 8, 10) at t = 0.00 s, the start configuration"
