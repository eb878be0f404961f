"""A run as one :class:`~irlc.run_data.RunData` per robot: what the tools draw and export
for a cell (plots, animation, trajectory export, MCAP; docs/interfaces.md, "Cells of
several robots").

A cell's trace holds each robot's columns prefixed by its name (``holder_a1_deg``); a
robot's part of it — its columns with the prefix taken off, beside ``t_s`` and ``line`` —
is the trace of a program of that robot, and its ``robots`` entry of the report is that
program's report. :func:`robot_runs` gives, per robot in the ``ROBOT`` clauses' order, its
name, placement (``AT``, 4×4 SI), model (placed: its base is the placement times the
file's base), its samples (the :class:`~irlc.runtime.outputs.run_result.RobotResult`) and
a :class:`RunData` read from that part, so every tool of a program of one robot reads a
robot of a cell the same way. A program of one robot is one :class:`RobotRun`.

:func:`robot_parts` splits any trace (this run's, or a loaded ``--compare`` trace) by the
robots' names: a column belongs to the robot whose ``NAME_`` is its longest matching
prefix.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from irlc.run_data import RunData, run_data

CELL_KEYS = ("program", "status", "drives", "ipo_s", "units", "error", "events")


@dataclass(frozen=True)
class RobotRun:
    """One robot of a run: ``name`` in the program, placement ``at`` (4×4, SI), ``data``
    (its samples, trace columns and report entry as a program of that robot's) and
    ``result`` (:class:`~irlc.runtime.outputs.run_result.RobotResult`: ``tcp`` (k, 4, 4),
    ``recorded``, ``model``)."""

    name: str
    at: np.ndarray
    data: RunData
    result: Any

    @property
    def model(self):
        return self.result.model


def robot_runs(run: Any) -> list[RobotRun]:
    """Each robot of ``run`` (a :class:`~irlc.runtime.outputs.run_result.RunResult`)."""
    if not run.is_cell:
        ((name, result),) = run.robots.items()
        return [RobotRun(name, result.at, run_data(run), result)]
    names = list(run.robots)
    parts = robot_parts(run.trace_columns, names)
    trace = np.asarray(run.trace, dtype=float)
    index = {c: i for i, c in enumerate(run.trace_columns)}
    common = {c: trace[:, index[c]] for c in ("t_s", "line") if c in index}
    out = []
    for name, result in run.robots.items():
        table = {**common, **{own: trace[:, i] for i, own in parts[name]}}
        report = {**result.report, **{k: run.report.get(k) for k in CELL_KEYS}}
        report["robot"] = result.report.get("robot")
        view = {
            "report": report, "trace_table": table, "model": result.model,
            "times": result.times, "q": result.q, "tcp": result.tcp,
            "lines": run.lines, "obstacles": run.obstacles,
        }  # fmt: skip
        out.append(RobotRun(name, result.at, run_data(view, label=name), result))
    return out


def robot_parts(columns: Sequence[str], names: Sequence[str]) -> dict[str, list[tuple[int, str]]]:
    """Per robot name, its columns of a cell's trace: ``(index, column without NAME_)``; a
    column is the robot's whose ``NAME_`` is its longest matching prefix (``a_b_a1_deg`` is
    robot ``a_b``'s, not ``a``'s)."""
    out: dict[str, list[tuple[int, str]]] = {n: [] for n in names}
    by_length = sorted(names, key=len, reverse=True)
    for i, column in enumerate(columns):
        owner = next((n for n in by_length if column.startswith(f"{n}_")), None)
        if owner is not None:
            out[owner].append((i, column[len(owner) + 1 :]))
    return out


def compared_robot(compare: Any, name: str, names: Sequence[str]) -> dict | None:
    """Robot ``name``'s part of a loaded ``--compare`` trace of a cell (a view
    :func:`~irlc.run_data.run_data` reads), or ``None`` when that trace has no columns of it."""
    columns = getattr(compare, "trace_columns", None) or []
    trace = getattr(compare, "trace", None)
    if trace is None or not columns:
        return None
    mine = robot_parts(columns, names)[name]
    if not mine:
        return None
    table = {own: trace[:, i] for i, own in mine}
    for c in ("t_s", "line"):
        if c in columns:
            table[c] = trace[:, columns.index(c)]
    return {"trace_table": table, "report": {}, "path": getattr(compare, "path", None)}
