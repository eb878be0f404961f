"""docs/interfaces.md, "Cells of several robots", lists the keys and columns a cell's run writes:
the top-level keys (those of a program of one robot that stay at the top, and the cell's
own), a ``robots`` entry's keys, and the trace's columns (each robot's, prefixed, then the
clearance columns), in the documented order."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from irlc.cli import main

from tests.tool.test_docs_interfaces import column_pattern, documented, section, tables

ROOT = Path(__file__).resolve().parents[2]
MOVED = ("tool", "self_clearance", "motors", "ideal", "verdict", "drives_summary",
         "kinetic_energy", "mvr", "platform")  # fmt: skip


@pytest.fixture(scope="module")
def cell_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("cells")
    report, trace = folder / "r.json", folder / "t.csv"
    program = ROOT / "programs" / "two_robots.irl"
    assert main([str(program), "-q", "--report", str(report), "--trace", str(trace)]) == 0
    header = trace.read_text(encoding="utf-8").splitlines()[0].split(",")
    return json.loads(report.read_text(encoding="utf-8")), header


def test_the_cell_report_keys_are_the_documented_ones(cell_run):
    report, _ = cell_run
    single, _ = documented(tables(section("Report"))[0])
    cell, entry = tables(section("Cells of several robots"))[:2]
    cell_keys, _ = documented(cell)
    own = {"cycle_time_s", "clearance", "robots"}
    assert own <= cell_keys
    expected = (single - set(MOVED)) | own
    assert set(report) == expected - {"motors", "ideal", "verdict", "drives_summary"}
    order = [k for k in report if k not in own]
    assert order == [k for k in report if k in single], "the single robot's keys keep their order"
    assert list(report)[-3:] == ["cycle_time_s", "clearance", "robots"]
    entry_keys, _ = documented(entry)
    optional = {"motors", "ideal", "verdict", "drives_summary", "platform"}
    for robot in report["robots"]:
        assert set(robot) <= entry_keys and entry_keys - set(robot) <= optional | {"motors"}
    assert {"robot"} <= set(report["joints"][0])
    for pair in report["clearance"]["pairs"]:
        assert set(pair) == set(report["clearance"]) - {"required_mm", "pairs"}
    for row in report["statements"]:
        for part in row["robots"].values():
            assert set(part) == {"duration_s", "limit", "set_the_time"}


def test_the_cell_trace_columns_are_the_documented_ones_in_order(cell_run):
    report, header = cell_run
    single = tables(section("Trace"))[0]
    names = [r["name"] for r in report["robots"]]
    clearance = ["clearance_mm", "clearance_robot_a", "clearance_link_a", "clearance_robot_b",
                 "clearance_link_b"]  # fmt: skip
    documented = {k for ks, _ in tables(section("Cells of several robots"))[2] for k in ks}
    assert set(clearance) <= documented
    assert header[:2] == ["t_s", "line"]
    at = 2
    for name, entry in zip(names, report["robots"], strict=True):
        joints = entry["joint_names"]
        mine = [c for c in header if c.startswith(f"{name}_")]
        assert header[at : at + len(mine)] == mine  # one block per robot, in order
        rows = []
        for column in mine:
            own = column[len(name) + 1 :]
            found = [
                i
                for i, (ks, _) in enumerate(single)
                if any(column_pattern(k, joints).match(own) for k in ks)
            ]
            assert found, f"{column}: not a documented column of a program of one robot"
            rows.append(found[0])
        assert rows == sorted(rows)
        at += len(mine)
    assert header[at : at + 5] == clearance
