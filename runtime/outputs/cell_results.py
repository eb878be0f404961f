"""Assemble a cell's result: the report (with ``robots``), the trace and the RunResult.

Presentation only, like :mod:`irlc.runtime.outputs.results`, whose builders make each
robot's part: a robot of the cell is reported as a program of that robot would be
(:func:`~irlc.runtime.outputs.results.build_report` on its samples — its channel of the
cell's samples, :mod:`irlc.runtime.control.cell` — its statements, its limit activity),
and the cell's report puts them together (``docs/interfaces.md``, "Cells"):

* ``robots``: one entry per robot, in the ``ROBOT`` records' order: ``name``, ``robot``,
  ``at``, ``joints``, ``start_joints``, ``end_joints``, ``max_path_error_mm``,
  ``max_orientation_error_deg``, ``obstacles``, ``ik``, ``approximations``,
  ``joint_names``, ``robot_joint_names``, ``tool``, ``statements`` (the statements that
  moved it), ``warnings``; with drives ``ideal``, ``verdict``, ``drives_summary``;
* the cell's own keys as a program's: ``joints`` lists every robot's joints named
  ``ROBOT_JOINT`` (``holder_a1``) with ``robot``, as the trace names its columns;
  ``max_path_error_mm`` … the largest over the robots; ``statements`` the cell's
  cycle-time table (a group move one row, with ``robots``: per robot its own time, its
  limit and whether it set the group's time); ``cycle_time_s``; ``clearance``: the smallest
  distance between links (robots' and within one) with its pair, time and line.

The trace: ``t_s``, ``line``, then each robot's columns of a program of that robot
(joints, speeds, accelerations, TCP, path error, drive columns, orientation error, obstacle
clearances, motors) prefixed by its name and ``_``, then ``clearance_mm`` and the pair
(``clearance_robot_a``, ``clearance_link_a``, ``clearance_robot_b``, ``clearance_link_b``:
robot numbers 0, 1, … in the ``ROBOT`` records' order, link numbers), then the I/O columns.
"""

from __future__ import annotations

import dataclasses
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from irlc.lang import trace_columns as tc
from irlc.runtime import units
from irlc.runtime.outputs import stop
from irlc.runtime.outputs.cycle_time import source_lines, statement_rows
from irlc.runtime.outputs.digital_io import io_columns, signal_timelines
from irlc.runtime.outputs.results import RunData, build_report, build_trace, rnd
from irlc.runtime.outputs.run_result import RobotResult, RunResult, TraceArrays
from irlc.runtime.outputs.samples import Samples


class RobotView:
    """What a robot's report reads of its controller (:class:`RunData`'s ``controller``):
    its channel of samples, the cell's obstacles, its statements and blends — its own and
    those of the cooperations it was in."""

    def __init__(self, unit):
        ctl = unit.controller
        self.recorder = unit.channel
        self.obstacles = ctl.obstacles
        self.dt_used = ctl.dt_used
        spans = list(ctl.log.spans)
        blends = list(ctl.blends)
        for pair in unit.pairs:
            spans += pair.controller.log.spans
            blends += [{**b, "robot": pair.worker.name} for b in pair.controller.blends]
        self.statements = sorted(spans, key=lambda s: (s.start, s.end))
        self.blends = blends


@dataclass
class RobotRun:
    """One robot's part of a cell's run: its unit, its samples, with drives its verdict."""

    unit: Any
    samples: Samples
    verdict: Any = None
    cut_at: float | None = None  # a drive failure (of any robot) ends the run here
    undriven: str | None = None  # why its drives were not simulated (no drive data)

    @classmethod
    def kinematic(cls, unit) -> RobotRun:
        return cls(unit, Samples.of(unit.channel.arrays()))

    def drive(self, level: str, every_step: bool, obstacles, opts, until) -> None:
        """The robot's drives simulated on its set points (:func:`run_drives`)."""
        from irlc.runtime.drives.stage import run_drives

        ctl = self.unit.controller
        self.samples, self.verdict = run_drives(self.samples, self.unit.model, level, every_step,
                                                obstacles, ctl.recorder.task_rows,
                                                ctl.naming.program, opts, until)  # fmt: skip

    def cut(self, t_end: float, opts) -> None:
        """Its samples up to ``t_end`` (a drive run failed there: its own drives, another
        robot's, or the cell's actual clearance): with drives its drive rows and verdict
        too (:func:`~irlc.runtime.drives.stage.stopped`)."""
        from irlc.runtime.drives.stage import stopped

        self.cut_at = t_end
        samples = self.samples
        if not len(samples.recorded.times) or samples.recorded.times[-1] <= t_end:
            return
        if samples.drive is None or self.verdict is None:
            self.samples = stop.samples_until(samples, t_end)
            return
        names = tuple(self.unit.controller.naming.program)
        self.samples, self.verdict = stopped(samples, self.verdict, self.unit.model, names,
                                             opts, t_end)  # fmt: skip


@dataclass(frozen=True)
class CellRunData:
    """What a cell's run produced, for presentation."""

    code: Any
    cell: Any  # CellController
    execution: Any
    options: Any
    robots: list[RobotRun]
    level: str = "ideal"
    base_dir: Path | None = None
    actual: Any = None  # ActualClearance: with drives, the actual motion's clearance

    @property
    def clearances(self):
        """The clearance the report and trace show: the actual motion's with drives
        (:mod:`~irlc.runtime.outputs.actual_clearance`), else the set points'."""
        return self.cell.clearances if self.actual is None else self.actual.clearances

    @property
    def error(self):
        return self.execution.error

    @property
    def t_end(self) -> float | None:
        """Where a drive failure cut the run (``None``: not cut)."""
        return self.robots[0].cut_at if self.robots else None


def assemble_cell(run: CellRunData) -> RunResult:
    """The cell's :class:`RunResult` (module doc)."""
    reports = [build_report(_robot_data(run, k)) for k in range(len(run.robots))]
    entries = [_robot_entry(run, k, reports[k]) for k in range(len(run.robots))]
    report = _cell_report(run, reports, entries)
    blocks = [_robot_block(run, k) for k in range(len(run.robots))]
    times = run.robots[0].samples.traced.times
    lines = run.robots[0].samples.traced.lines
    clearance_cols, clearance = _clearance_columns(run, len(times))
    io_names, io_values = _io(run, times)
    columns = ["t_s", "line"] + [c for cols, _ in blocks for c in cols] + clearance_cols + io_names
    parts = [times[:, None], lines[:, None].astype(float)] + [t for _, t in blocks]
    parts += [clearance, io_values]
    table = np.hstack(parts) if len(times) else np.zeros((0, len(columns)))
    robots = {}
    for k, rr in enumerate(run.robots):
        unit, traced = rr.unit, rr.samples.traced
        robots[unit.name] = RobotResult(
            name=unit.name, model=unit.model, at=unit.at,
            joint_names=tuple(unit.controller.naming.program), times=traced.times, q=traced.q,
            tcp=traced.tcp, report=entries[k], trace_columns=blocks[k][0],
            recorded=rr.samples.recorded, drive=rr.samples.drive,
        )  # fmt: skip
    q_all = np.hstack([rr.samples.traced.q for rr in run.robots])
    source = TraceArrays(times, q_all, None, table, run.robots[0].samples.recorded)
    return RunResult(
        status=report["status"],
        error=run.error,
        report=report,
        trace_columns=columns,
        model=run.robots[0].unit.model,
        obstacles=tuple(run.cell.obstacles.values()),
        output=list(run.execution.output),
        code=run.code,
        joint_names=tuple(j["name"] for j in report["joints"]),
        source=source,
        cell=robots,
    )


def _robot_data(run: CellRunData, k: int) -> RunData:
    """Robot ``k``'s part as a program of that robot (for :func:`build_report`)."""
    rr = run.robots[k]
    code_robot = run.code.robots[k]
    code = dataclasses.replace(
        run.code, robot_var=code_robot.var, robot=code_robot.robot,
        joint_kinds=code_robot.joint_kinds, joint_names=code_robot.joint_names,
    )  # fmt: skip
    state = run.execution.state
    tool = state.robots[k].tool if len(state.robots) > k else state.settings.tool
    settings = dataclasses.replace(state.settings, tool=tool)
    execution = dataclasses.replace(
        run.execution, warnings=[], state=dataclasses.replace(state, settings=settings)
    )
    error = run.error if rr.verdict is None else None
    warnings = [rr.undriven] if rr.undriven else []
    execution = dataclasses.replace(execution, error=error, warnings=warnings)
    level = "ideal" if rr.undriven else run.level
    return RunData(code, rr.unit.model, RobotView(rr.unit), execution, run.options, rr.samples,
                   level, rr.verdict, run.base_dir)  # fmt: skip


_ROBOT_KEYS = ("joints", "start_joints", "end_joints", "max_path_error_mm",
               "max_orientation_error_deg", "obstacles", "ik", "approximations", "joint_names",
               "robot_joint_names", "tool", "statements", "motors", "collisions", "ideal",
               "verdict", "drives_summary", "kinetic_energy", "mvr", "platform")  # fmt: skip


def _robot_entry(run: CellRunData, k: int, report: dict) -> dict:
    """Robot ``k``'s entry of ``robots`` (module doc)."""
    unit = run.robots[k].unit
    at = run.code.robots[k].at or (0.0,) * 6  # as the program wrote it (mm, ZYX deg)
    entry: dict[str, Any] = {
        "name": unit.name,
        "robot": report["robot"],
        "at": [rnd(float(v)) for v in at],
    }
    entry.update({key: report[key] for key in _ROBOT_KEYS if key in report})
    entry["warnings"] = [w for w in report["warnings"]]
    return entry


def _cell_report(run: CellRunData, reports: list[dict], entries: list[dict]) -> dict:
    """The cell's report (module doc)."""
    first = reports[0]
    error = run.error
    joints = []
    for e in entries:
        for j in e["joints"]:
            joints.append({**j, "name": tc.prefixed(e["name"], j["name"]), "robot": e["name"]})
    rows = _statements(run)
    warnings = list(run.execution.warnings)
    for e in entries:
        warnings += [f"{e['name']}: {w}" for w in e["warnings"]]
    collisions = {
        "allowed": run.options.allow_collisions,
        "penetrations": [{**p, "robot": e["name"]} for e in entries
                         for p in e["collisions"]["penetrations"]],
    }  # fmt: skip
    out: dict[str, Any] = {
        "status": "ok" if error is None else "failed",
        "error": None if error is None else _error(error),
        "program": os.path.basename(run.code.source) if run.code.source else run.code.program,
        "robot": ", ".join(f"{e['name']} ({e['robot']})" for e in entries),
        "units": first["units"],
        "ipo_s": first["ipo_s"],
        "drives": run.level,
        "duration_s": first["duration_s"],
        "samples": first["samples"],
        "joints": joints,
        "start_joints": [v for e in entries for v in e["start_joints"]],
        "end_joints": [v for e in entries for v in e["end_joints"]],
        "max_path_error_mm": max(e["max_path_error_mm"] or 0.0 for e in entries),
        "max_orientation_error_deg": max(e["max_orientation_error_deg"] or 0.0 for e in entries),
        "obstacles": _obstacles(entries),
        "ik": _ik(entries),
        "output": list(run.execution.output),
        "warnings": warnings,
        "collisions": collisions,
        "events": [_clean_event(e) for e in sorted(run.execution.events, key=_time)],
        "approximations": [{**a, "robot": a.get("robot", e["name"])} for e in entries
                           for a in e["approximations"]],
        "tolerances": first["tolerances"],
        "joint_names": [j["name"] for j in joints],
        "robot_joint_names": [j["robot_name"] for j in joints],
        "program_name": run.code.program,
        "statements": rows,
        "cycle_time_s": rnd(sum(r["duration_s"] or 0.0 for r in rows)),
        "clearance": _clearance_report(run, run.clearances),
        "robots": entries,
    }  # fmt: skip
    inside = out["clearance"]
    if run.actual is not None and (inside["min_distance_mm"] or 0.0) < 0.0:
        out["warnings"].append(  # (allowed: else the run failed at it)
            "collisions allowed (--allow-collisions): the actual motion (simulated drives) "
            f"brings {inside['robot_a']} link {inside['link_a']} and {inside['robot_b']} link "
            f"{inside['link_b']} {-inside['min_distance_mm']:.4g} mm inside each other at "
            f"t = {inside['at_time_s']:.3f} s, line {inside['line']}"
        )
    if run.actual is not None:  # the set points' figures, for comparison (as a robot's)
        ideal = [e["ideal"] for e in entries if e.get("ideal")]
        out["ideal"] = {
            "max_path_error_mm": max((i["max_path_error_mm"] or 0.0 for i in ideal), default=0.0),
            "max_orientation_error_deg": max((i["max_orientation_error_deg"] or 0.0
                                              for i in ideal), default=0.0),
            "obstacles": _obstacles([{**e, "obstacles": e["ideal"]["obstacles"]}
                                     for e in entries if e.get("ideal")]),
            "clearance": _clearance_report(run, run.cell.clearances),
        }  # fmt: skip
        out["robots"] = out.pop("robots")  # (the last key)
    return out


def _error(error) -> dict:
    out = error.as_dict()
    if out.get("time_s") is not None:
        out["time_s"] = rnd(float(out["time_s"]))
    return {k: (rnd(v) if isinstance(v, float) else v) for k, v in out.items()}


def _time(event: dict) -> float:
    return event["time_s"]


def _clean_event(e: dict) -> dict:
    return {k: (rnd(v) if isinstance(v, float) else v) for k, v in e.items()}


def _obstacles(entries: list[dict]) -> dict:
    """Per obstacle the robot that came closest (its entry's figures and ``robot``)."""
    out: dict[str, dict] = {}
    for e in entries:
        for name, o in e["obstacles"].items():
            best = out.get(name)
            d = o["min_distance_mm"]
            if best is None or (d is not None and (best["min_distance_mm"] is None
                                                   or d < best["min_distance_mm"])):  # fmt: skip
                out[name] = {**o, "robot": e["name"]}
    return dict(sorted(out.items()))


def _ik(entries: list[dict]) -> dict:
    """The robots' inverse transformations summed (a cooperating pair's cycle, which
    moves both, counts for each), the smallest manipulability."""
    iks = [e["ik"] for e in entries]
    cycles = sum(i["cycles"] for i in iks)
    mean = sum(i["cycles"] * i["iterations_mean"] for i in iks) / cycles if cycles else 0.0
    manip = [i["min_manipulability"] for i in iks if i["min_manipulability"] is not None]
    return {
        "cycles": cycles,
        "iterations_mean": rnd(mean, 6),
        "iterations_max": max(i["iterations_max"] for i in iks),
        "relaxed_cycles": sum(i["relaxed_cycles"] for i in iks),
        "min_manipulability": min(manip) if manip else None,
    }


def _statements(run: CellRunData) -> list[dict]:
    """The cell's cycle-time table (a group move one row, with ``robots``)."""
    from irlc.runtime.control.group import GroupStatement
    from irlc.runtime.outputs.cycle_time import StatementSpan

    spans, robots = [], []
    for s in run.cell.statements:
        if isinstance(s, GroupStatement):
            spans.append(StatementSpan(s.line, s.kind, s.start, s.end, s.stop, s.limit,
                                       s.override, s.call))  # fmt: skip
            robots.append(s.robots)
        else:
            span = s.span
            spans.append(span)
            own = {"duration_s": round(span.duration, 9), "limit": span.limit or None,
                   "set_the_time": True}  # fmt: skip
            robots.append({name: dict(own) for name in s.robots})
    if run.t_end is not None:
        kept = stop.statements_until(spans, run.t_end)
        robots = robots[: len(kept)]
        spans = kept
    rows = statement_rows(spans, source_lines(run.code.source, run.base_dir), rnd)
    for row, who in zip(rows, robots, strict=True):
        row["robots"] = {
            name: {**info, "duration_s": rnd(info["duration_s"])} for name, info in who.items()
        }
    return rows


def _clearance_report(run: CellRunData, clearances) -> dict:
    """The smallest clearance between links over the run (of ``clearances``: the actual
    motion's or the set points', :class:`CellClearances`) — its pair, time and line — the
    largest R_CLEARANCE in effect, and the same per pair of robots (``pairs``: between two
    robots, and each robot with itself)."""
    cell = run.cell
    rec = run.robots[0].samples.recorded
    n = len(rec.times)
    names = [r.unit.name for r in run.robots]
    d = np.array(clearances.distance[:n])
    out = _least(d, rec, lambda k: clearances.pair[k], names)
    out["required_mm"] = rnd(max(cell.clearances.required[:n], default=0.0) / units.MM)
    parts = cell.parts
    pairs = []
    for g in range(len(parts.groups)):
        dg = np.array([m[0][g] for m in clearances.groups[:n]])

        def pair_of(k: int, g: int = g) -> tuple[int, int, int, int]:
            p = int(clearances.groups[k][1][g])
            i, j = int(parts.i[p]), int(parts.j[p])
            return int(parts.robot[i]), int(parts.link[i]), int(parts.robot[j]), int(parts.link[j])

        pairs.append(_least(dg, rec, pair_of, names))
    out["pairs"] = pairs
    return out


def _least(d: np.ndarray, rec, pair_of, names) -> dict:
    """The least of per-sample distances ``d`` (m): mm, time, line, the pair's robots and
    links (``pair_of(sample)``); ``null``s without a finite one."""
    keys = ("min_distance_mm", "at_time_s", "line", "robot_a", "link_a", "robot_b", "link_b")
    finite = np.isfinite(d)
    if not finite.any():
        return dict.fromkeys(keys)
    k = int(np.argmin(np.where(finite, d, np.inf)))
    ra, la, rb, lb = pair_of(k)
    values = (rnd(float(d[k]) / units.MM), rnd(float(rec.times[k])), int(rec.lines[k]),
              names[ra], la, names[rb], lb)  # fmt: skip
    return dict(zip(keys, values, strict=True))


def _clearance_columns(run: CellRunData, rows: int) -> tuple[list[str], np.ndarray]:
    """``clearance_mm`` and the pair's robot and link numbers, per trace row (with drives
    the actual motion's, as the joint columns are)."""
    clearances = run.clearances
    d = np.array(clearances.distance[:rows], dtype=float) / units.MM
    pair = np.array(clearances.pair[:rows], dtype=float).reshape(-1, 4)
    d = np.where(np.isfinite(d), d, 0.0)
    return list(tc.CELL_CLEARANCE), np.column_stack([d, pair]) if rows else np.zeros((0, 5))


def _robot_block(run: CellRunData, k: int) -> tuple[list[str], np.ndarray]:
    """Robot ``k``'s trace columns (a program's, without ``t_s`` and ``line``), prefixed."""
    rr = run.robots[k]
    unit = rr.unit
    cols, table = build_trace(unit.model, rr.samples, tuple(unit.controller.naming.program))
    return [tc.prefixed(unit.name, c) for c in cols[2:]], table[:, 2:]


def _io(run: CellRunData, times: np.ndarray):
    signals = signal_timelines(run.execution.events)
    return io_columns(times, run.code.inputs, run.execution.state.outputs, signals)
