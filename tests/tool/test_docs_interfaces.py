"""docs/interfaces.md lists exactly the report keys and trace columns a run writes.

The tables of its "Report" and "Trace" sections are parsed (first column: the backticked
keys, ``NAME`` standing for a joint name, ``OBSTACLE`` for an obstacle name, ``NUM`` for an
input or output number and ``SIGNAL`` for a SIGNAL's name); a row
ending in ``<!-- pending: … -->`` documents planned work and may be absent. A run with drives
(so the drive keys and columns appear) must write every documented key and column, in the
documented order for the trace, and nothing undocumented — on koch11 (no motor maps) and on
the L-1 (motor maps: the ``motors`` key and ``NAME_motor_rad`` columns, which only robots
with a ``[transmission]`` table write).
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from irlc.cli import main

ROOT = Path(__file__).resolve().parents[2]
PENDING_ROW = re.compile(r"<!-- pending[^>]*--> \|\s*$")  # the whole row is planned work
DOC = ROOT / "docs" / "interfaces.md"
PROGRAM = """PROGRAM s;
ROBOT r := koch11;
BEGIN
  MOVE LIN (11400, 1000, 3500, 0, 0, 0);
  OUT[1] := TRUE;
  WRITELN('done');
ENDPROGRAM
"""
L1_PROGRAM = """PROGRAM s;
ROBOT r := l1;
BEGIN
  MOVE PTP (205, 300, 300, 90, 25, 95);
  OUT[1] := TRUE;
  WRITELN('done');
ENDPROGRAM
"""
MOTOR_MAPS_ONLY = {"motors", "NAME_motor_rad"}  # written for robots with motor maps only


def section(title: str) -> str:
    text = DOC.read_text(encoding="utf-8")
    start = text.index(f"\n## {title}")
    end = text.find("\n## ", start + 1)
    return text[start : end if end >= 0 else None]


def _rows(text: str) -> list[tuple[list[str], bool]]:
    """``(keys of the first column, pending)`` per table row of ``text``."""
    out = []
    for line in text.splitlines():
        cells = line.split(" | ")
        if not line.startswith("| `") or len(cells) < 2:
            continue
        keys = [k.strip() for chunk in re.findall(r"`([^`]+)`", cells[0]) for k in chunk.split(",")]
        out.append((keys, PENDING_ROW.search(line) is not None))
    return out


def tables(section: str) -> list[list[tuple[list[str], bool]]]:
    """The tables of a section, in order (a blank line ends a table)."""
    return [rows for block in section.split("\n\n") if (rows := _rows(block))]


def documented(rows) -> tuple[set[str], set[str]]:
    keys = {k for ks, pending in rows if not pending for k in ks}
    pending = {k for ks, p in rows if p for k in ks}
    return keys, pending


@pytest.fixture(scope="module", params=["koch11", "l1"])
def run_files(request, tmp_path_factory):
    folder = tmp_path_factory.mktemp("interfaces")
    program = folder / "s.irl"
    program.write_text(PROGRAM if request.param == "koch11" else L1_PROGRAM, encoding="utf-8")
    report, trace = folder / "r.json", folder / "t.csv"
    # drives lag the path by millimetres: the run states its tolerances (docs/drives.md)
    tolerances = ["--path-tolerance", "200", "--orientation-tolerance", "10"]
    argv = [str(program), "--drives", "decoupled", *tolerances, "-q", "--report", str(report)]
    assert main([*argv, "--trace", str(trace)]) == 0
    header = trace.read_text(encoding="utf-8").splitlines()[0].split(",")
    return json.loads(report.read_text(encoding="utf-8")), header


def _optional(report: dict) -> set[str]:
    """Documented keys this run need not write: the motor-map ones without motor maps."""
    return set() if report["robot"] == "l1" else MOTOR_MAPS_ONLY


def test_report_keys_are_the_documented_ones(run_files):
    report, _ = run_files
    top, per_joint = tables(section("Report"))[:2]
    keys, pending = documented(top)
    pending |= keys & _optional(report)
    keys -= _optional(report)
    assert keys <= set(report), f"documented but not written: {sorted(keys - set(report))}"
    extra = set(report) - keys - pending
    assert not extra, f"written but not in docs/interfaces.md: {sorted(extra)}"
    order = [k for ks, p in top if not p for k in ks if k in keys]
    assert [k for k in report if k in keys] == order, "report keys not in the documented order"
    keys, pending = documented(per_joint)
    joint = report["joints"][0]
    assert keys <= set(joint), f"documented but not written: {sorted(keys - set(joint))}"
    assert not set(joint) - keys - pending, sorted(set(joint) - keys - pending)


def column_pattern(doc_name: str, joints: list[str]) -> re.Pattern:
    name = "(?:" + "|".join(map(re.escape, joints)) + ")"
    text = re.escape(doc_name).replace("NAME", name).replace("OBSTACLE", r"\w+")
    text = text.replace("NUM", r"\d+").replace("SIGNAL", r"\w+")
    return re.compile(text + r"\Z")


def test_trace_columns_are_the_documented_ones_in_order(run_files):
    report, header = run_files
    rows = tables(section("Trace"))[0]
    joints = report["joint_names"]
    row_of = []  # the documented row each column matches
    for column in header:
        found = [
            i
            for i, (ks, _) in enumerate(rows)
            if any(column_pattern(k, joints).match(column) for k in ks)
        ]
        assert found, f"trace column {column!r} is not in docs/interfaces.md"
        row_of.append(found[0])
    assert row_of == sorted(row_of), "trace columns are not in the documented order"
    for i, (ks, pending) in enumerate(rows):
        optional = any(w in k for k in ks for w in ("OBSTACLE", "NUM", "SIGNAL"))
        optional = optional or bool(set(ks) & _optional(report))
        optional = optional or ks == ["partial"]  # failed runs only (test_partial_trace.py)
        if not pending and not optional:
            assert i in row_of, f"documented trace columns {ks} are not written"
