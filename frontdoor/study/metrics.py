"""The columns of ``results.csv`` and one row from a run's report (program units).

Columns, in this order (docs/studies.md, docs/interfaces.md):

* ``variant`` (0-based, the study's order), then one column per varied key (its dotted
  path; a list value as JSON text);
* ``status`` — ``ok`` | ``failed`` (run failure) | ``compile_error`` | ``setup_error``
  (robot, data, option) | ``internal_error`` | ``crashed`` (the worker process died);
  ``exit_code`` as ``irlc run`` would give (0 … 4; empty when crashed);
  ``error``, ``error_line``, ``error_time_s``;
* ``duration_s``, ``samples``, ``max_path_error_mm``, ``max_orientation_error_deg``,
  ``ik_relaxed_cycles``; the links' kinetic energy, ``max_kinetic_energy_j`` and
  ``kinetic_energy_integral_j_s`` (empty for a robot without inertials), and the velocity
  ratio's ``min_mvr`` and ``max_mvr`` (the report's ``kinetic_energy`` and ``mvr``);
  ``min_clearance_<obstacle>_mm`` per obstacle of the program;
* ``active_bounds`` — the bounds that became active, ``a10 position max; a11 speed min``
  (joint order), and ``limit_active_s``, the report's per-joint active times summed over
  the joints (two joints on a bound for 1 s count 2 s);
* ``peak_speed_<j>_<u>_s`` and ``peak_accel_<j>_<u>_s2`` per joint (``u`` deg | mm);
* with drives (when some variant simulates them): ``drives_could_follow``,
  ``peak_current_<j>_A`` and ``max_following_error_<j>_<u>`` per joint.

A **cell** (several robots) has the cell report's numbers after the status: ``duration_s``,
``samples``, ``cycle_time_s``, the largest ``max_path_error_mm`` and
``max_orientation_error_deg`` over the robots, ``ik_relaxed_cycles`` (all robots),
``min_clearance_mm`` (the least distance between links, robots' and within one) and
``min_clearance_<A>-<B>_mm`` per pair of robots (``A-A``: robot A's own links), then per
robot ``<NAME>_max_path_error_mm`` … ``<NAME>_max_mvr`` (the one-robot run columns from
``max_path_error_mm`` on, of its entry in ``robots``); its joints are named as in the
trace, ``<NAME>_<j>`` (``peak_speed_holder_a1_deg_s``).

Values are the report's (rounded to 9 significant digits there), so the same variant gives
the same bytes on any worker.
"""

from __future__ import annotations

import json
import math
from typing import Any

from irlc.study.plan import Plan

STATUS_COLUMNS = ("status", "exit_code", "error", "error_line", "error_time_s")
TEXT_COLUMNS = ("status", "error", "active_bounds", "drives_could_follow")  # no metric
RUN_COLUMNS = (
    "duration_s",
    "samples",
    "max_path_error_mm",
    "max_orientation_error_deg",
    "ik_relaxed_cycles",
    "max_kinetic_energy_j",
    "kinetic_energy_integral_j_s",
    "min_mvr",
    "max_mvr",
)


CELL_COLUMNS = (
    "duration_s",
    "samples",
    "cycle_time_s",
    "max_path_error_mm",
    "max_orientation_error_deg",
    "ik_relaxed_cycles",
    "min_clearance_mm",
)
ROBOT_COLUMNS = RUN_COLUMNS[2:]  # a cell's per robot, prefixed by its name


def robot_pairs(names: tuple[str, ...]) -> list[tuple[str, str]]:
    """Every pair of a cell's robots, each robot with itself too (record order)."""
    return [(a, b) for i, a in enumerate(names) for b in names[i:]]


def columns(plan: Plan) -> list[str]:
    cols = ["variant", *plan.keys, *STATUS_COLUMNS]
    if plan.cell:
        cols += CELL_COLUMNS
        cols += [f"min_clearance_{a}-{b}_mm" for a, b in robot_pairs(plan.cell)]
        cols += [f"{name}_{c}" for name in plan.cell for c in ROBOT_COLUMNS]
    else:
        cols += RUN_COLUMNS
    cols += [f"min_clearance_{o}_mm" for o in plan.obstacles]
    cols += ["active_bounds", "limit_active_s"]
    cols += [f"peak_speed_{j}_{u}_s" for j, u in plan.joints]
    cols += [f"peak_accel_{j}_{u}_s2" for j, u in plan.joints]
    if plan.drives:
        cols += ["drives_could_follow"]
        cols += [f"peak_current_{j}_A" for j, _ in plan.joints]
        cols += [f"max_following_error_{j}_{u}" for j, u in plan.joints]
    return cols


def cell(value: Any) -> str:
    """The CSV text of a value: ``repr`` of a float (exact, shortest), JSON of a list."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value + 0.0) if math.isfinite(value) else ""
    if isinstance(value, list | tuple):
        return json.dumps(list(value))
    return " | ".join(str(value).splitlines())  # one line per row


def parameter_cells(plan: Plan, index: int, values: tuple) -> dict[str, str]:
    return {"variant": str(index), **{k: cell(v) for k, v in zip(plan.keys, values, strict=True)}}


def report_cells(plan: Plan, report: dict) -> dict[str, str]:
    """The metrics of a finished run (ok or failed) from its report."""
    error = report.get("error") or {}
    row: dict[str, Any] = {
        "status": report["status"],
        "exit_code": 0 if report["status"] == "ok" else 2,
        "error": error.get("message"),
        "error_line": error.get("line"),
        "error_time_s": error.get("time_s"),
        **_run_values(report),
    }
    if plan.cell:
        row.update(_cell_values(plan, report))
    obstacles = report.get("obstacles") or {}
    for o in plan.obstacles:
        row[f"min_clearance_{o}_mm"] = (obstacles.get(o) or {}).get("min_distance_mm")
    joints = report.get("joints") or []
    bounds = [
        f"{j['name']} {label}" for j in joints for label in sorted(j.get("limit_activity") or {})
    ]
    row["active_bounds"] = "; ".join(bounds)
    row["limit_active_s"] = _round(sum(j.get("limit_active_s") or 0.0 for j in joints))
    for (name, unit), j in zip(plan.joints, joints, strict=False):
        row[f"peak_speed_{name}_{unit}_s"] = j.get("max_abs_speed")
        row[f"peak_accel_{name}_{unit}_s2"] = j.get("max_abs_accel")
    drives = _drives_summary(plan, report)
    if plan.drives and drives:
        row["drives_could_follow"] = drives.get("could_follow")
        for (name, _), axis in zip(plan.joints, drives.get("axes") or [], strict=False):
            row[f"peak_current_{name}_A"] = axis.get("peak_current_A")
        for (name, unit), j in zip(plan.joints, joints, strict=False):
            row[f"max_following_error_{name}_{unit}"] = j.get("max_following_error")
    return {k: cell(v) for k, v in row.items()}


def _run_values(report: dict) -> dict[str, Any]:
    """The run columns of a report — a program's, or a cell robot's entry in ``robots``."""
    return {
        "duration_s": report.get("duration_s"),
        "samples": report.get("samples"),
        "max_path_error_mm": report.get("max_path_error_mm"),
        "max_orientation_error_deg": report.get("max_orientation_error_deg"),
        "ik_relaxed_cycles": (report.get("ik") or {}).get("relaxed_cycles"),
        "max_kinetic_energy_j": (report.get("kinetic_energy") or {}).get("max_j"),
        "kinetic_energy_integral_j_s": (report.get("kinetic_energy") or {}).get("integral_j_s"),
        "min_mvr": (report.get("mvr") or {}).get("min"),
        "max_mvr": (report.get("mvr") or {}).get("max"),
    }


def _cell_values(plan: Plan, report: dict) -> dict[str, Any]:
    """A cell's own columns (module doc): cycle time, clearances, each robot's numbers."""
    clearance = report.get("clearance") or {}
    row: dict[str, Any] = {
        "cycle_time_s": report.get("cycle_time_s"),
        "min_clearance_mm": clearance.get("min_distance_mm"),
    }
    least = {}
    for pair in clearance.get("pairs") or []:
        least[frozenset((pair.get("robot_a"), pair.get("robot_b")))] = pair["min_distance_mm"]
    for a, b in robot_pairs(plan.cell):
        row[f"min_clearance_{a}-{b}_mm"] = least.get(frozenset((a, b)))
    entries = {e.get("name"): e for e in report.get("robots") or []}
    for name in plan.cell:
        values = _run_values(entries.get(name) or {})
        row.update({f"{name}_{c}": values[c] for c in ROBOT_COLUMNS})
    return row


def _drives_summary(plan: Plan, report: dict) -> dict | None:
    """The drives' summary: a program's; a cell's robots' together (all could follow,
    their axes one robot after the other)."""
    if not plan.cell:
        return report.get("drives_summary")
    summaries = [e.get("drives_summary") for e in report.get("robots") or []]
    if not summaries or any(s is None for s in summaries):
        return None
    return {
        "could_follow": all(s.get("could_follow") for s in summaries),
        "axes": [axis for s in summaries for axis in s.get("axes") or []],
    }


def error_cells(status: str, exit_code: int | None, message: str, line: int | None) -> dict:
    """A variant that did not run to a report (compile, setup, internal error, crash)."""
    return {
        "status": status,
        "exit_code": cell(exit_code),
        "error": cell(message),
        "error_line": cell(line),
    }


def _round(x: float) -> float:
    from irlc.runtime.outputs.results import rnd

    return rnd(x) or 0.0
