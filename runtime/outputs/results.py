"""Assemble a run's result: the report (``docs/interfaces.md`` keys) and the trace table.

Presentation only: everything is read from the run's :class:`~irlc.runtime.outputs.samples.Samples`
(set points and, with drives, the actual motion, each derived once by the pipeline stage
that owns it: :mod:`irlc.runtime.run`, :mod:`irlc.runtime.drives.stage`) and the other
parts of a :class:`RunData`; nothing is simulated or re-derived here. The samples are read
in consecutive pieces (:meth:`RunData.pieces`: one for a run kept in memory, the
recorder's spilled pieces for a streamed one): the report sums them up (:class:`_Tally`),
the trace is built piece by piece (:func:`trace_tables`), with the same values either way.

Everything user-facing is in program units (mm, deg, s; joints deg | mm) through
:mod:`units`. Numbers in the report are rounded to fixed precision (``ROUND``) so that the
same input gives the same bytes; non-finite values never appear (an infinite clearance —
no geometry — is reported as ``null``).

Trace columns (``docs/interfaces.md``): ``t_s, line, <j>_<unit> …, <j>_speed_<unit>_s …,
<j>_accel_<unit>_s2 …, x_mm, y_mm, z_mm, a_deg, b_deg, c_deg, path_error_mm``; with drives
``<j>_cmd_<unit> …, <j>_current_A …``; then the extras ``orientation_error_deg``,
``clearance_<obstacle>_mm`` per obstacle, ``kinetic_energy_j`` (robots with inertials) and
``mvr`` (:mod:`~irlc.runtime.outputs.measures`). Joint names are the program's (MAIN_JOINT
record; :mod:`naming`), the report's ``joints`` rows add the robot file's name as
``robot_name``; the pose is the world-frame TCP with ZYX angles. With drives the joint columns
are the *actual* joints and speeds/accelerations are their backward differences; the pose,
``path_error_mm``, ``orientation_error_deg`` and the clearances are those of the actual
motion against the commanded path (:mod:`irlc.runtime.outputs.actual_motion`), and the report's
``verdict`` (:mod:`irlc.runtime.outputs.verdict`) decides whether the run failed; the kinematic
figures are kept under ``ideal``.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterator
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from irlc.lang import trace_columns as tc
from irlc.runtime import units, values
from irlc.runtime.errors import RunFailure
from irlc.runtime.model.naming import JointNaming
from irlc.runtime.outputs import motor_coords, platform_coords
from irlc.runtime.outputs.cycle_time import source_lines, statement_rows
from irlc.runtime.outputs.digital_io import io_columns, signal_timelines
from irlc.runtime.outputs.measures import MeasureTally, MotionMeasures
from irlc.runtime.outputs.platform_coords import platform_report
from irlc.runtime.outputs.recorder import backward_jerk
from irlc.runtime.outputs.run_result import RunResult, TraceArrays
from irlc.runtime.outputs.samples import Samples
from irlc.runtime.outputs.self_clearance import SelfClearanceTally

if TYPE_CHECKING:
    from irlc.lang.irdata import Code
    from irlc.robots.model import RobotModel
    from irlc.runtime.control.executor import ExecutionOptions, SimulatedController
    from irlc.runtime.interpreter import ExecutionResult
    from irlc.runtime.outputs.verdict import Verdict

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
    the :class:`~irlc.runtime.outputs.samples.Samples` and, with drives, the verdict."""

    code: Code
    model: RobotModel
    controller: SimulatedController
    execution: ExecutionResult
    options: ExecutionOptions
    samples: Samples
    level: str = "ideal"  # the drive level asked for
    verdict: Verdict | None = None  # drives
    base_dir: Path | None = None  # the program's folder (statement texts)
    streamed: bool = False  # the samples are read from the recorder piece by piece

    def pieces(self) -> Iterator[Samples]:
        """The run's samples in consecutive pieces: ``samples`` whole, or (``streamed``)
        the recorder's :meth:`~irlc.runtime.outputs.recorder.Recorder.chunks` one by one."""
        if not self.streamed:
            yield self.samples
            return
        for rec in self.controller.recorder.chunks():
            yield Samples.of(rec)

    @cached_property
    def measures(self) -> MotionMeasures:
        """The kinetic energy and velocity ratio of the run's motion, shared by the report
        and the trace (each piece computed once: :class:`MotionMeasures` keeps the last)."""
        return MotionMeasures(self.model)

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
        if self.samples is not None and self.samples.drive is not None:
            out += list(self.samples.drive.notes) + self.verdict.warnings
        return out


def assemble(run: RunData):
    """The :class:`~irlc.runtime.outputs.run_result.RunResult`: the report and the trace of
    ``run``'s
    samples (presentation only: nothing is simulated or derived again here). A streamed
    run's trace is not built here: :class:`StreamedTrace` makes it piece by piece when it
    is written (or whole, when asked for)."""
    report = build_report(run)
    error = run.error
    if run.streamed:
        source = StreamedTrace(run)
        columns = source.columns
    else:
        columns, table = trace_columns(run), next(trace_tables(run))
        traced = run.samples.traced
        source = TraceArrays(traced.times, traced.q, traced.tcp, table, run.samples.recorded)
    return RunResult(
        status="ok" if error is None else "failed",
        error=error,
        report=report,
        trace_columns=columns,
        model=run.model,
        obstacles=tuple(run.controller.obstacles.values()),
        output=list(run.execution.output),
        drive=run.samples.drive if run.samples is not None else None,
        code=run.code,
        joint_names=run.names,
        source=source,
    )


def trace_columns(run: RunData) -> list[str]:
    """The trace's columns (:func:`trace_header`, motors, then the I/O columns)."""
    names, model = run.names, run.model
    drives = run.samples is not None and run.samples.drive is not None
    energy = model.missing_inertia is None
    cols = trace_header(names, model.joint_kinds, drives, run.controller.obstacles, energy)
    return cols + _motor_header(model, names) + _io(run, np.zeros(0))[0]


def trace_tables(run: RunData) -> Iterator[np.ndarray]:
    """The trace table (program units) in consecutive pieces of rows, one per piece of
    :meth:`RunData.pieces` (one for a run kept in memory): :func:`build_trace`'s columns
    and the I/O columns (:func:`~irlc.runtime.outputs.digital_io.io_columns`), each row-local."""
    for samples in run.pieces():
        table = build_trace(run.model, samples, run.names, run.measures)[1]
        yield np.hstack((table, _io(run, table[:, 0])[1]))


def _io(run: RunData, times: np.ndarray):
    """The I/O columns' names and values at ``times``."""
    signals = signal_timelines(run.execution.events)
    return io_columns(times, run.code.inputs, run.execution.state.outputs, signals)


class StreamedTrace:
    """A streamed run's trace (kinematic runs only: no drives): :meth:`tables` builds it
    piece by piece from the recorder (:func:`trace_tables`), so writing it needs memory
    for one piece; the whole-run arrays (:class:`TraceArrays`' fields) are built on first
    use, for the tools that want them (plots, animation, the Python API)."""

    def __init__(self, run: RunData):
        self.run = run
        self.columns = trace_columns(run)

    def tables(self) -> Iterator[np.ndarray]:
        """The trace table in pieces of rows."""
        return trace_tables(self.run)

    @cached_property
    def recorded(self):
        """The recorder's samples joined
        (:meth:`~irlc.runtime.outputs.recorder.Recorder.arrays`)."""
        return self.run.controller.recorder.arrays()

    @property
    def times(self) -> np.ndarray:
        return self.recorded.times

    @property
    def q(self) -> np.ndarray:
        return self.recorded.q

    @property
    def tcp(self) -> np.ndarray:
        return self.recorded.tcp

    @cached_property
    def trace(self) -> np.ndarray:
        pieces = list(self.tables())
        return np.vstack(pieces) if pieces else np.zeros((0, len(self.columns)))


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
    ``ideal``. The samples are read once, piece by piece (:class:`_Tally`)."""
    model, controller, execution, opts = run.model, run.controller, run.execution, run.options
    names, code, error, verdict = run.names, run.code, run.error, run.verdict
    drive = run.samples.drive if run.samples is not None else None
    kinds = model.joint_kinds
    rows = statement_rows(  # cycle time per statement (cycle_time.py)
        controller.statements, source_lines(code.source, run.base_dir), rnd
    )
    tally = _Tally(model, controller.obstacles, rows, drive is not None)
    measures = MeasureTally(run.measures)  # kinetic energy, velocity ratio
    own = SelfClearanceTally(model)  # the robot's own links (self_clearance.py)
    for samples in run.pieces():
        tally.add(samples)
        measures.add(samples.shown)
        own.add(samples.shown)
    k = tally.k
    penetrations = tally.shown.penetrations()
    warnings = run.warnings + [
        "collisions allowed (--allow-collisions): the arm penetrates obstacle "
        f"{p['obstacle']} {p['depth_mm']:.4g} mm deep (link {p['link']}) at t = "
        f"{p['time_s']:.3f} s, line {p['line']}"
        for p in (penetrations if opts.allow_collisions else ())
    ]
    strictest, loosest = tally.path_tolerances(opts.tol_position)  # R_PATH_TOL may change
    activity = controller.recorder.active_time  # (joint, label) → s, built once here
    active_time = _active_time(activity, model.n)
    following = _following(drive, model)
    joints = []
    for j, name in enumerate(names):
        joints.append(
            {
                "name": name,
                "unit": units.joint_unit(kinds[j]),
                "robot_name": model.joint_names[j],
                "min": rnd(float(tally.q_min[j]) if k else 0.0),
                "max": rnd(float(tally.q_max[j]) if k else 0.0),
                "max_abs_speed": rnd(float(tally.top_speed[j]) if k else 0.0),
                "max_abs_accel": rnd(float(tally.top_accel[j]) if k else 0.0),
                "max_abs_jerk": rnd(float(tally.top_jerk[j]) if k else 0.0),
                "limit_active_s": rnd(active_time[j]),
                "limit_activity": {lab: rnd(t) for lab, t in sorted(_labels(activity, j).items())},
                "max_following_error": following[j],
            }
        )
    report: dict[str, Any] = {
        "status": "ok" if error is None else "failed",
        "error": _error_dict(error),
        "program": os.path.basename(code.source) if code.source else code.program,
        "robot": model.name,
        "units": {"length": "mm", "angle": "deg", "time": "s"},
        "ipo_s": rnd(controller.dt_used),
        "drives": run.level,
        "duration_s": rnd(tally.end_time if k else 0.0),
        "samples": k,
        "joints": joints,
        "start_joints": [rnd(float(v)) for v in (tally.q_first if k else [])],
        "end_joints": [rnd(float(v)) for v in (tally.q_last if k else [])],
        "max_path_error_mm": rnd(tally.shown.pos / units.MM if k else 0.0),
        "max_orientation_error_deg": rnd(tally.shown.ori / units.DEG if k else 0.0),
        "obstacles": tally.shown.obstacles(),
        "ik": {
            "cycles": tally.ik_cycles,
            "iterations_mean": rnd(
                float(tally.iterations) / tally.ik_iterated if tally.ik_iterated else 0.0, 6
            ),
            "iterations_max": tally.iterations_max,
            "relaxed_cycles": tally.relaxed,
            "min_manipulability": rnd(tally.manipulability) if tally.manip_seen else None,
        },
        "output": list(execution.output),
        "warnings": warnings,
        "collisions": {"allowed": opts.allow_collisions, "penetrations": penetrations},
        "events": [_clean(e) for e in sorted(execution.events, key=lambda e: e["time_s"])],
        "approximations": list(getattr(controller, "blends", ())),
        "tolerances": {
            "path_mm": rnd(strictest / units.MM),
            "path_mm_loosest": rnd(loosest / units.MM),
            "orientation_deg": rnd(opts.tol_orientation / units.DEG),
        },
        "joint_names": list(names),
        "robot_joint_names": list(model.joint_names),
        "program_name": code.program,
        "tool": tool_report(model, execution.state.settings.tool),
        "statements": rows,
        **measures.report(rnd),  # kinetic_energy, mvr
        "self_clearance": own.report(rnd),
    }
    if tally.motors is not None:  # per motor and statement: travel, travel time
        report["motors"] = _clean(tally.motors.report(names))
        tally.motors.add_statements(rnd)
    if model.platform is not None:  # where the platform was (platform_coords.py)
        motions = [m.entry() for m in controller.platform.record.motions]
        scale = units.joint_scale(kinds)  # (the tally's joints are in program units)
        first, last = (tally.q_first * scale, tally.q_last * scale) if k else (None, None)
        report["platform"] = platform_report(model, names, first, last, motions, rnd)
    if drive is not None:
        from irlc.runtime.drives import report_axes

        report["ideal"] = {  # the commanded (kinematic) motion, for comparison
            "max_path_error_mm": rnd(tally.ideal.pos / units.MM if k else 0.0),
            "max_orientation_error_deg": rnd(tally.ideal.ori / units.DEG if k else 0.0),
            "obstacles": tally.ideal.obstacles(),
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


class _Extrema:
    """The largest path errors (m, rad) and, per obstacle, the smallest clearance (m) and
    the time, line and robot link of the first sample at the smallest one, over pieces of
    a motion."""

    def __init__(self, obstacles):
        self.pos = self.ori = -math.inf
        # name → [finite min, argmin value, its time, its line, its link]
        self.clearance: dict[str, list] = {name: [None] * 5 for name in obstacles}

    def add(self, motion) -> None:
        """One piece of a :class:`~irlc.runtime.outputs.samples.Motion`."""
        times, links = motion.times, motion.clearance_link or {}
        self.pos = max(self.pos, float(motion.pos_error.max()))
        self.ori = max(self.ori, float(motion.ori_error.max()))
        for name, d in motion.clearance.items():
            best = self.clearance[name]
            finite = d[np.isfinite(d)]
            if finite.size and (best[0] is None or finite.min() < best[0]):
                best[0] = finite.min()
            i = int(np.argmin(d))
            if best[1] is None or d[i] < best[1]:  # the first sample at the minimum
                link = int(links[name][i]) if name in links else 0
                best[1:] = [d[i], times[i], int(motion.lines[i]), link]

    def obstacles(self) -> dict:
        """The report's ``obstacles`` section."""
        out = {}
        for name in sorted(self.clearance):
            low, _, at, line, link = self.clearance[name]
            out[name] = {
                "min_distance_mm": rnd(float(low) / units.MM) if low is not None else None,
                "at_time_s": rnd(float(at)) if low is not None else None,
                "line": line if low is not None else None,
                "link": link if low is not None else None,
            }
        return out

    def penetrations(self) -> list[dict]:
        """Per obstacle with a negative clearance its deepest penetration (collision.py)."""
        from irlc.runtime.control.collision import Collision

        out = []
        for name in sorted(self.clearance):
            low, _, at, line, link = self.clearance[name]
            if low is not None and low < 0.0:
                hit = Collision(name, link, -float(low), float(at), line)
                out.append(_clean(hit.as_dict()))
        return out


class _Tally:
    """What the report reads of a run's samples, summed up over consecutive pieces
    (:meth:`RunData.pieces`): joint extrema in program units (the jerk the backward
    difference of the accelerations, the previous piece's last row carried), path-error
    and clearance extrema (shown and, with drives, ideal), the inverse transformation's
    counts and the motors' travel. Extrema and integer counts do not depend on how the
    samples are cut into pieces."""

    def __init__(self, model, obstacles, statement_rows: list[dict], drives: bool):
        self.scale = units.joint_scale(model.joint_kinds)
        self.k = self.ik_cycles = self.ik_iterated = self.iterations = 0
        self.iterations_max = self.relaxed = 0
        self.manipulability, self.manip_seen = math.inf, False
        self.q_min = self.q_max = self.q_first = self.q_last = None
        self.top_speed = self.top_accel = self.top_jerk = None
        self.end_time = 0.0
        self.path_tol = (math.inf, -math.inf)  # m: the strictest, loosest R_PATH_TOL on path
        self._carry: tuple | None = None  # (time, acceleration) of the last sample
        self.shown = _Extrema(obstacles)
        self.ideal = _Extrema(obstacles) if drives else None
        has_motors = motor_coords.has_motors(model)
        self.motors = motor_coords.MotorTally(model, statement_rows) if has_motors else None

    def add(self, samples: Samples) -> None:
        rec, shown = samples.recorded, samples.shown
        if not len(rec.times):
            return
        q, speed = shown.q / self.scale, np.abs(shown.speed / self.scale)
        accel = shown.accel / self.scale
        jerk = np.abs(backward_jerk(rec.times, accel, self._carry))
        self._carry = (rec.times[-1], accel[-1])
        accel = np.abs(accel)
        if self.k == 0:
            self.q_first = q[0]
            self.q_min, self.q_max = q.min(axis=0), q.max(axis=0)
            self.top_speed, self.top_accel = speed.max(axis=0), accel.max(axis=0)
            self.top_jerk = jerk.max(axis=0)
        else:
            self.q_min = np.minimum(self.q_min, q.min(axis=0))
            self.q_max = np.maximum(self.q_max, q.max(axis=0))
            self.top_speed = np.maximum(self.top_speed, speed.max(axis=0))
            self.top_accel = np.maximum(self.top_accel, accel.max(axis=0))
            self.top_jerk = np.maximum(self.top_jerk, jerk.max(axis=0))
        self.q_last, self.end_time, self.k = q[-1], float(rec.times[-1]), self.k + len(rec.times)
        self.shown.add(shown)
        if self.ideal is not None:
            self.ideal.add(samples.commanded)
        self._add_ik(rec)
        tol = None if rec.tol_position is None else rec.tol_position[rec.on_path]
        if tol is not None and tol.size:  # (on a Cartesian path: a PTP has no path to keep)
            lo, hi = self.path_tol
            self.path_tol = (min(lo, tol.min()), max(hi, tol.max()))
        if self.motors is not None:
            self.motors.add(rec.times, shown.q)

    def path_tolerances(self, start: float) -> tuple[float, float]:
        """The strictest and loosest R_PATH_TOL in effect on the commanded path (m): the
        samples of Cartesian motions; ``start`` (the option's value) when there were none."""
        lo, hi = self.path_tol
        return (float(lo), float(hi)) if lo <= hi else (start, start)

    def _add_ik(self, rec) -> None:
        """The inverse transformation's cycles (iterations > 0): count, iterations (sum,
        max), relaxed cycles, the smallest finite manipulability."""
        ik = rec.iterations > 0
        iters = rec.iterations[ik]
        self.ik_cycles += int(ik.sum())
        self.ik_iterated += iters.size
        self.iterations += int(iters.sum())
        self.iterations_max = max(self.iterations_max, int(iters.max()) if iters.size else 0)
        self.relaxed += int(rec.relaxed.sum())
        manip = rec.manipulability[ik]
        manip = manip[np.isfinite(manip)]
        if manip.size:
            self.manipulability = min(self.manipulability, float(manip.min()))
            self.manip_seen = True


def tool_report(model, r_tool) -> dict:
    """The tool at the end of the run (mm, deg ZYX): the robot file's, the program's
    ``R_TOOL``, and the active one ``tool_file · R_TOOL`` the TCP is computed with."""
    file_tool = model.tool
    program = values.pose_to_matrix(r_tool)

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


def trace_header(names, kinds, drives: bool, obstacles, energy: bool = True) -> list[str]:
    """The trace's columns before the motors' and the I/O's (names: ``irlc.lang.trace_columns``;
    ``energy``: the robot's inertials give the kinetic energy)."""
    joints = list(zip(names, kinds, strict=True))
    cols = ["t_s", "line"]
    cols += [tc.position(n, k) for n, k in joints]
    cols += [tc.speed(n, k) for n, k in joints]
    cols += [tc.accel(n, k) for n, k in joints]
    cols += [*tc.POSE, "path_error_mm"]
    if drives:
        cols += [tc.command(n, k) for n, k in joints]
        cols += [tc.current(n) for n in names]
    cols += ["orientation_error_deg"]
    cols += [tc.clearance(name) for name in sorted(obstacles)]
    cols += [tc.KINETIC_ENERGY, tc.MVR] if energy else [tc.MVR]
    return cols


def _motor_header(model, names) -> list[str]:
    """``NAME_motor_rad`` after the clearances, for robots with motor maps; then
    ``platform_C_mm`` for a robot with a platform."""
    motors = motor_coords.trace_columns(names) if motor_coords.has_motors(model) else []
    return motors + platform_coords.trace_columns(model)


def build_trace(model, samples: Samples, names, measures: MotionMeasures | None = None):
    """``(columns, table)`` in program units: one row per time of :attr:`Samples.traced`
    (IPO samples, or the drive steps of a drive run traced per step); ``measures``: the
    run's :class:`MotionMeasures` (default: a new one)."""
    kinds = model.joint_kinds
    scale = units.joint_scale(kinds)
    drive, motion = samples.drive, samples.traced
    measures = measures or MotionMeasures(model)
    cols = trace_header(
        names, kinds, drive is not None, samples.recorded.clearance, measures.energy
    )
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
    parts.append(measures.table(motion))
    if motor_coords.has_motors(model) and k:
        parts.append(motor_coords.motor_angles(model, q))  # of the joints in this row
    if model.platform is not None and k:
        parts.append(platform_coords.coordinates(model, q))
    table = np.hstack(parts) if k else np.zeros((0, len(cols)))
    return cols, table
