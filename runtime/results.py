"""Assemble a run's result: the report (``docs/interfaces.md`` keys) and the trace table.

Presentation only: everything is read from the run's :class:`~irlc.runtime.samples.Samples`
(set points and, with drives, the actual motion, each derived once by the pipeline stage
that owns it: :mod:`irlc.runtime.run`, :mod:`irlc.runtime.drive_stage`) and the other
parts of a :class:`RunData`; nothing is simulated or re-derived here.

Everything user-facing is in program units (mm, deg, s; joints deg | mm) through
:mod:`units`. Numbers in the report are rounded to fixed precision (``ROUND``) so that the
same input gives the same bytes; non-finite values never appear (an infinite clearance —
no geometry — is reported as ``null``).

Trace columns (``docs/interfaces.md``): ``t_s, line, <j>_<unit> …, <j>_speed_<unit>_s …,
<j>_accel_<unit>_s2 …, x_mm, y_mm, z_mm, a_deg, b_deg, c_deg, path_error_mm``; with drives
``<j>_cmd_<unit> …, <j>_current_A …``; then the extras ``orientation_error_deg`` and
``clearance_<obstacle>_mm`` per obstacle. Joint names are the program's (MAIN_JOINT
record; :mod:`naming`), the report's ``joints`` rows add the robot file's name as
``robot_name``; the pose is the world-frame TCP with ZYX angles. With drives the joint columns
are the *actual* joints and speeds/accelerations are their backward differences; the pose,
``path_error_mm``, ``orientation_error_deg`` and the clearances are those of the actual
motion against the commanded path (:mod:`irlc.runtime.actual_motion`), and the report's
``verdict`` (:mod:`irlc.runtime.verdict`) decides whether the run failed; the kinematic
figures are kept under ``ideal``.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from irlc.runtime import motor_coords, units
from irlc.runtime.cycle_time import source_lines, statement_rows
from irlc.runtime.digital_io import io_columns, signal_timelines
from irlc.runtime.errors import RunFailure
from irlc.runtime.naming import JointNaming
from irlc.runtime.recorder import backward_jerk
from irlc.runtime.samples import Samples

if TYPE_CHECKING:
    from irlc.lang.irdata import Code
    from irlc.robots.model import RobotModel
    from irlc.runtime.executor import ExecutionOptions, SimulatedController
    from irlc.runtime.interpreter import ExecutionResult
    from irlc.runtime.verdict import Verdict

ROUND = 9  # significant digits of report numbers


def rnd(x: float | None, digits: int = ROUND) -> float | None:
    """``x`` rounded to ``digits`` significant digits; ``None`` for non-finite / None;
    0 for round-off of a zero (:func:`units.shown`: no ``1.99e-32``)."""
    if x is None or not math.isfinite(x):
        return None
    x = units.shown(x)
    if x == 0.0:
        return 0.0
    v = float(f"{x:.{digits}g}")
    return v + 0.0  # no negative zero


@dataclass(frozen=True)
class RunData:
    """What a run produced, for presentation: the code, the robot, the controller (its
    statements, limit activity, blends, IPO cycle), the interpreter's result, the options,
    the :class:`~irlc.runtime.samples.Samples` and, with drives, the verdict."""

    code: Code
    model: RobotModel
    controller: SimulatedController
    execution: ExecutionResult
    options: ExecutionOptions
    samples: Samples
    level: str = "ideal"  # the drive level asked for
    verdict: Verdict | None = None  # drives
    base_dir: Path | None = None  # the program's folder (statement texts)

    @cached_property
    def names(self) -> tuple[str, ...]:
        """The joints' program names (:mod:`naming`)."""
        return JointNaming.for_model(self.model, self.code.joint_names).program

    @property
    def error(self) -> RunFailure | None:
        """The run's failure: the interpreter's, else the verdict's (drives)."""
        if self.execution.error is not None or self.verdict is None:
            return self.execution.error
        return self.verdict.failure

    @property
    def warnings(self) -> list[str]:
        """The recorder's, the interpreter's, the relaxed cycles', then the drive's notes
        and the verdict's."""
        recorder = self.controller.recorder
        out = list(recorder.warnings) + list(self.execution.warnings)
        out += relaxed_warnings(recorder)
        if self.samples.drive is not None:
            out += list(self.samples.drive.notes) + self.verdict.warnings
        return out


def assemble(run: RunData):
    """The :class:`~irlc.runtime.run.RunResult`: the report and the trace of ``run``'s
    samples (presentation only: nothing is simulated or derived again here)."""
    from irlc.runtime.run import RunResult

    report = build_report(run)
    samples, execution, code = run.samples, run.execution, run.code
    columns, table = build_trace(run.model, samples, run.names)
    signals = signal_timelines(execution.events)
    io_names, io_table = io_columns(table[:, 0], code.inputs, execution.state.outputs, signals)
    columns, table = columns + io_names, np.hstack((table, io_table))
    traced = samples.traced
    error = run.error
    return RunResult(
        status="ok" if error is None else "failed",
        error=error,
        report=report,
        times=traced.times,
        q=traced.q,
        tcp=traced.tcp,
        trace_columns=columns,
        trace=table,
        model=run.model,
        obstacles=tuple(run.controller.obstacles.values()),
        output=list(execution.output),
        drive=samples.drive,
        recorded=samples.recorded,
        code=code,
        joint_names=run.names,
    )


# --------------------------------------------------------------------------- report


def relaxed_warnings(recorder) -> list[str]:
    out = []
    for span in recorder.relaxed_spans:
        text = (
            f"line {span.line}: {span.cycles} relaxed IK cycle(s) at t = {span.t_start:.3f}"
            + (f"–{span.t_end:.3f}" if span.cycles > 1 else "")
            + f" s, path deviation up to {span.max_deviation / units.MM:.3g} mm"
        )
        if span.max_orientation > 0.0:
            text += f" / {span.max_orientation / units.DEG:.3g} deg"
        if span.binding:
            text += f" (bound by {span.binding})"
        out.append(text)
    return out


def build_report(run: RunData) -> dict:
    """The report (``docs/interfaces.md``). With drives the joints, path errors and
    clearances are the actual motion's (:attr:`Samples.shown`); the ideal ones are under
    ``ideal``."""
    model, controller, execution, opts = run.model, run.controller, run.execution, run.options
    rec, shown, drive = run.samples.recorded, run.samples.shown, run.samples.drive
    names, code, error, verdict = run.names, run.code, run.error, run.verdict
    kinds = model.joint_kinds
    scale = units.joint_scale(kinds)
    k = len(rec.times)
    q = shown.q / scale if k else np.zeros((0, model.n))
    speed, accel = shown.speed / scale, shown.accel / scale
    jerk = backward_jerk(rec.times, accel) if k else np.zeros((0, model.n))  # program units
    pos_err, ori_err, clearance = shown.pos_error, shown.ori_error, shown.clearance
    activity = controller.recorder.active_time  # (joint, label) → s, built once here
    active_time = _active_time(activity, model.n)
    following = _following(drive, model)
    joints = []
    for j, name in enumerate(names):
        col = q[:, j] if k else np.zeros(1)
        joints.append(
            {
                "name": name,
                "unit": units.joint_unit(kinds[j]),
                "robot_name": model.joint_names[j],
                "min": rnd(float(col.min())),
                "max": rnd(float(col.max())),
                "max_abs_speed": rnd(float(np.abs(speed[:, j]).max()) if k else 0.0),
                "max_abs_accel": rnd(float(np.abs(accel[:, j]).max()) if k else 0.0),
                "max_abs_jerk": rnd(float(np.abs(jerk[:, j]).max()) if k else 0.0),
                "limit_active_s": rnd(active_time[j]),
                "limit_activity": {lab: rnd(t) for lab, t in sorted(_labels(activity, j).items())},
                "max_following_error": following[j],
            }
        )
    ik_mask = rec.iterations > 0
    iters = rec.iterations[ik_mask]
    manip = rec.manipulability[ik_mask]
    manip = manip[np.isfinite(manip)]
    report: dict[str, Any] = {
        "status": "ok" if error is None else "failed",
        "error": _error_dict(error),
        "program": os.path.basename(code.source) if code.source else code.program,
        "robot": model.name,
        "units": {"length": "mm", "angle": "deg", "time": "s"},
        "ipo_s": rnd(controller.dt_used),
        "drives": run.level,
        "duration_s": rnd(float(rec.times[-1]) if k else 0.0),
        "samples": k,
        "joints": joints,
        "start_joints": [rnd(float(v)) for v in (q[0] if k else [])],
        "end_joints": [rnd(float(v)) for v in (q[-1] if k else [])],
        "max_path_error_mm": rnd(float(pos_err.max()) / units.MM if k else 0.0),
        "max_orientation_error_deg": rnd(float(ori_err.max()) / units.DEG if k else 0.0),
        "obstacles": _obstacles(rec.times, clearance),
        "ik": {
            "cycles": int(ik_mask.sum()),
            "iterations_mean": rnd(float(iters.mean()) if iters.size else 0.0, 6),
            "iterations_max": int(iters.max()) if iters.size else 0,
            "relaxed_cycles": int(rec.relaxed.sum()),
            "min_manipulability": rnd(float(manip.min())) if manip.size else None,
        },
        "output": list(execution.output),
        "warnings": run.warnings,
        "events": [_clean(e) for e in sorted(execution.events, key=lambda e: e["time_s"])],
        "approximations": list(getattr(controller, "blends", ())),
        "tolerances": {
            "path_mm": rnd(opts.tol_position / units.MM),
            "orientation_deg": rnd(opts.tol_orientation / units.DEG),
        },
        "joint_names": list(names),
        "robot_joint_names": list(model.joint_names),
        "program_name": code.program,
        "tool": tool_report(model, execution.state.settings.tool),
        "statements": statement_rows(  # cycle time per statement (cycle_time.py)
            controller.statements, source_lines(code.source, run.base_dir), rnd
        ),
    }
    if motor_coords.has_motors(model):  # per motor and statement: travel, travel time
        moved = shown.q if k else np.zeros((0, model.n))
        report["motors"] = _clean(motor_coords.motor_report(model, names, rec.times, moved))
        motor_coords.add_statement_motors(report["statements"], model, rec.times, moved, rnd)
    if drive is not None:
        from irlc.runtime.drives import report_axes

        report["ideal"] = {  # the commanded (kinematic) motion, for comparison
            "max_path_error_mm": rnd(float(rec.pos_error.max()) / units.MM if k else 0.0),
            "max_orientation_error_deg": rnd(float(rec.ori_error.max()) / units.DEG if k else 0.0),
            "obstacles": _obstacles(rec.times, rec.clearance),
        }
        could_follow = verdict.could_follow if verdict is not None else drive.could_follow
        report["verdict"] = _clean(verdict.as_dict()) if verdict is not None else None
        report["drives_summary"] = {
            "level": drive.level,
            "step_s": rnd(drive.step),
            "could_follow": bool(could_follow),
            "axes": [
                _clean({**row, "joint": names[a.joint], "robot_name": row["joint"]})
                for a, row in zip(drive.axes, report_axes(drive, model), strict=True)
            ],
        }
    return report


def tool_report(model, r_tool) -> dict:
    """The tool at the end of the run (mm, deg ZYX): the robot file's, the program's
    ``R_TOOL``, and the active one ``tool_file · R_TOOL`` the TCP is computed with."""
    file_tool = model.tool
    program = units.pose_value_to_si(r_tool)

    def pose(t: np.ndarray) -> list[float | None]:
        return [rnd(v, 9) for v in units.pose_from_si(t)]

    return {
        "robot_file": pose(file_tool),
        "r_tool": pose(program),
        "active": pose(file_tool @ program),
    }


def _labels(activity: dict, j: int) -> dict[str, float]:
    out: dict[str, float] = {}
    for (jj, label), t in activity.items():
        if jj == j:
            out[label] = out.get(label, 0.0) + t
    return out


def _active_time(active_time: dict, n: int) -> list[float]:
    out = [0.0] * n
    for (j, _), t in active_time.items():
        out[j] += t
    return out


def _following(drive, model) -> list[float | None]:
    if drive is None:
        return [None] * model.n
    scale = units.joint_scale(model.joint_kinds)
    return [rnd(a.max_following_error / scale[a.joint]) for a in drive.axes]


def _obstacles(times: np.ndarray, clearance: dict[str, np.ndarray]) -> dict:
    out = {}
    for name in sorted(clearance):
        d = clearance[name]
        finite = d[np.isfinite(d)]
        idx = int(np.argmin(d)) if finite.size else None
        out[name] = {
            "min_distance_mm": rnd(float(finite.min()) / units.MM) if finite.size else None,
            "at_time_s": rnd(float(times[idx])) if idx is not None else None,
        }
    return out


def _error_dict(error: RunFailure | None) -> dict | None:
    if error is None:
        return None
    out = error.as_dict()
    if out.get("time_s") is not None:
        out["time_s"] = rnd(float(out["time_s"]))
    return out


def _clean(obj):
    """JSON-safe copy: floats rounded, non-finite → None, tuples → lists."""
    if isinstance(obj, dict):
        return {str(k): _clean(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_clean(v) for v in obj]
    if isinstance(obj, bool | int | str) or obj is None:
        return obj
    if isinstance(obj, float | np.floating):
        return rnd(float(obj))
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    return str(obj)


# --------------------------------------------------------------------------- trace


def trace_header(names, kinds, drives: bool, obstacles) -> list[str]:
    cols = ["t_s", "line"]
    cols += [f"{n}_{units.joint_unit(k)}" for n, k in zip(names, kinds, strict=True)]
    cols += [f"{n}_speed_{units.joint_unit(k, 1)}" for n, k in zip(names, kinds, strict=True)]
    cols += [f"{n}_accel_{units.joint_unit(k, 2)}" for n, k in zip(names, kinds, strict=True)]
    cols += ["x_mm", "y_mm", "z_mm", "a_deg", "b_deg", "c_deg", "path_error_mm"]
    if drives:
        cols += [f"{n}_cmd_{units.joint_unit(k)}" for n, k in zip(names, kinds, strict=True)]
        cols += [f"{n}_current_A" for n in names]
    cols += ["orientation_error_deg"]
    cols += [f"clearance_{name}_mm" for name in sorted(obstacles)]
    return cols


def _motor_header(model, names) -> list[str]:
    """``NAME_motor_rad`` after the clearances, for robots with motor maps."""
    return motor_coords.trace_columns(names) if motor_coords.has_motors(model) else []


def build_trace(model, samples: Samples, names):
    """``(columns, table)`` in program units: one row per time of :attr:`Samples.traced`
    (IPO samples, or the drive steps of a drive run traced per step)."""
    kinds = model.joint_kinds
    scale = units.joint_scale(kinds)
    drive, motion = samples.drive, samples.traced
    cols = trace_header(names, kinds, drive is not None, samples.recorded.clearance)
    cols += _motor_header(model, names)
    times, lines, q, tcp = motion.times, motion.lines, motion.q, motion.tcp
    pos_err, ori_err, clearance = motion.pos_error, motion.ori_error, motion.clearance
    k = len(times)
    poses = np.array([units.pose_from_si(t) for t in tcp]) if k else np.zeros((0, 6))
    parts = [
        times[:, None],
        lines[:, None].astype(float),
        q / scale,
        motion.speed / scale,
        motion.accel / scale,
        poses,
        (pos_err / units.MM)[:, None],
    ]
    if drive is not None:
        from irlc.runtime.drives import trace_columns

        extra = trace_columns(drive, model, times)
        parts.append(
            np.column_stack(
                [extra[f"{j.name}_cmd_{units.joint_unit(j.kind)}"] for j in model.joints]
            )
        )
        parts.append(np.column_stack([extra[f"{j.name}_current_A"] for j in model.joints]))
    parts.append((ori_err / units.DEG)[:, None])
    for name in sorted(clearance):
        parts.append((clearance[name] / units.MM)[:, None])
    if motor_coords.has_motors(model) and k:
        parts.append(motor_coords.motor_angles(model, q))  # of the joints in this row
    table = np.hstack(parts) if k else np.zeros((0, len(cols)))
    return cols, table
