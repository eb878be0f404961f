"""Assemble a run's result: the report (``interfaces.md`` keys) and the trace table.

Everything user-facing is in program units (mm, deg, s; joints deg | mm) through
:mod:`units`. Numbers in the report are rounded to fixed precision (``ROUND``) so that the
same input gives the same bytes; non-finite values never appear (an infinite clearance —
no geometry — is reported as ``null``).

Trace columns (``interfaces.md``): ``t_s, line, <j>_<unit> …, <j>_speed_<unit>_s …,
<j>_accel_<unit>_s2 …, x_mm, y_mm, z_mm, a_deg, b_deg, c_deg, path_error_mm``; with drives
``<j>_cmd_<unit> …, <j>_current_A …``; then the extras ``orientation_error_deg`` and
``clearance_<obstacle>_mm`` per obstacle. Joint names are the program's (MAIN_JOINT
record; :mod:`naming`), the report's ``joints`` rows add the robot file's name as
``robot_name``; the pose is the world-frame TCP with ZYX angles. With drives the joint columns
are the *actual* joints and speeds/accelerations are their backward differences.
"""

from __future__ import annotations

import math
import os
from typing import Any

import numpy as np
from irlc.runtime import units
from irlc.runtime.errors import RunFailure
from irlc.runtime.naming import JointNaming
from irlc.runtime.recorder import RecordedRun, finite_differences

ROUND = 9  # significant digits of report numbers


def rnd(x: float | None, digits: int = ROUND) -> float | None:
    """``x`` rounded to ``digits`` significant digits; ``None`` for non-finite / None."""
    if x is None or not math.isfinite(x):
        return None
    if x == 0.0:
        return 0.0
    v = float(f"{x:.{digits}g}")
    return v + 0.0  # no negative zero


def assemble(code, model, controller, obstacles, execution, opts, drives: str, every_step: bool):
    from irlc.runtime.run import RunResult

    rec = controller.recorder.arrays()
    error = execution.error
    names = JointNaming.for_model(model, code.joint_names).program
    drive = None
    q_actual = rec.q
    if drives != "ideal" and len(rec.times) > 0:
        drive = simulate(model, rec, drives, every_step)
    warnings = list(controller.recorder.warnings) + list(execution.warnings)
    warnings += relaxed_warnings(controller.recorder)
    if drive is not None:
        warnings += list(drive.notes)
        if error is None:
            error = _drive_failure(model, names, rec, drive)
    report = build_report(
        code, model, rec, controller, error, names, opts, drives, drive, execution, warnings
    )
    if error is not None and error is not execution.error:  # a drive failure
        report["status"], report["error"] = "failed", _error_dict(error)
    columns, table = build_trace(model, rec, names, drive, every_step)
    if drive is not None and every_step:
        times = drive.t
        q_actual = drive.q_actual
        tcp = _tcp_of(model, q_actual, rec, times)
    elif drive is not None:
        q_actual = _at_times(drive, rec.times)
        times, tcp = rec.times, _tcp_of(model, q_actual, rec, rec.times)
    else:
        times, tcp = rec.times, rec.tcp
    return RunResult(
        status="ok" if error is None else "failed",
        error=error,
        report=report,
        times=times,
        q=q_actual,
        tcp=tcp,
        trace_columns=columns,
        trace=table,
        model=model,
        obstacles=tuple(obstacles.values()),
        output=list(execution.output),
        drive=drive,
        recorded=rec,
        code=code,
        joint_names=names,
    )


def _tcp_of(model, q: np.ndarray, rec: RecordedRun, times: np.ndarray) -> np.ndarray:
    """World TCP of joints ``q`` (the drives' actual joints at ``times``) with the tool the
    program had then: the recorded sample's ``R_TOOL`` is ``f₀(θₖ)⁻¹ · TCPₖ`` (``f₀``: the
    forward kinematics with the robot file's tool, ``θₖ``, ``TCPₖ``: the recorded joints
    and TCP), and ``TCP(q) = f₀(q) · R_TOOLₖ`` with ``k`` the last sample at or before
    the time."""
    from irlc.runtime.kinematics import Kinematics

    if not len(q):
        return np.zeros((0, 4, 4))
    kin = Kinematics(model)
    tcp = np.array([kin.tcp(qi) for qi in q])
    if not len(rec.times):
        return tcp
    r_tool = np.array(
        [_rigid_inverse(kin.tcp(qk)) @ tk for qk, tk in zip(rec.q, rec.tcp, strict=True)]
    )
    idx = np.clip(np.searchsorted(rec.times, times, side="right") - 1, 0, len(rec.times) - 1)
    return tcp @ r_tool[idx]


def _rigid_inverse(t: np.ndarray) -> np.ndarray:
    """``T⁻¹ = [Rᵀ, −Rᵀp; 0, 1]`` of a rigid transform."""
    inv = np.eye(4)
    inv[:3, :3] = t[:3, :3].T
    inv[:3, 3] = -t[:3, :3].T @ t[:3, 3]
    return inv


# --------------------------------------------------------------------------- drives


class DriveSetupError(Exception):
    """Drives requested but not available (module missing, robot without drive data)."""


def simulate(model, rec: RecordedRun, level: str, every_step: bool):
    try:
        from irlc.runtime.drives import drive_params, simulate_drives
    except ImportError as exc:  # pragma: no cover - the drives package ships with irlc
        raise DriveSetupError(f"the drive simulation is not available: {exc}") from None
    try:
        params = drive_params(model)
    except ValueError as exc:
        raise DriveSetupError(f"robot {model.name}: bad drive data: {exc}") from None
    if params is None:
        raise DriveSetupError(
            f"robot {model.name} has no drive data ([drives] in its robot file); use --drives ideal"
        )
    try:
        return simulate_drives(
            model,
            rec.times,
            rec.q,
            level=level,
            params=params,
            record="step" if every_step else "ipo",
        )
    except ValueError as exc:
        raise DriveSetupError(f"drive simulation: {exc}") from None


def _drive_failure(model, names, rec: RecordedRun, drive) -> RunFailure | None:
    """A drive that could not follow (following error beyond its tolerance, lost steps)
    fails the run (exit 2) at the time and line of its largest following error."""
    bad = [a for a in drive.axes if not a.could_follow]
    if not bad:
        return None
    worst = max(bad, key=lambda a: a.max_following_error / units.joint_scale([a.kind])[0])
    j = worst.joint
    err = np.abs(drive.following_error[:, j])
    t = float(drive.t[int(np.argmax(err))])
    idx = int(np.clip(np.searchsorted(rec.times, t, side="right") - 1, 0, len(rec.times) - 1))
    unit = units.joint_unit(worst.kind)
    scale = units.joint_scale([worst.kind])[0]
    what = (
        f"{worst.lost_steps} lost steps"
        if worst.lost_steps
        else (f"following error {worst.max_following_error / scale:.4g} {unit}")
    )
    others = ", ".join(names[a.joint] for a in bad if a.joint != j)
    return RunFailure(
        f"the drive of joint {names[j]} could not follow its setpoint ({what})"
        + (f"; also {others}" if others else ""),
        int(rec.lines[idx]),
        round(t, 9),
        f"drive {names[j]}",
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


def build_report(
    code,
    model,
    rec: RecordedRun,
    controller,
    error: RunFailure | None,
    names,
    opts,
    drives,
    drive,
    execution,
    warnings,
) -> dict:
    kinds = model.joint_kinds
    scale = units.joint_scale(kinds)
    k = len(rec.times)
    q = rec.q / scale if k else np.zeros((0, model.n))
    speed, accel = rec.speed / scale, rec.accel / scale
    if drive is not None:  # actual joints at the IPO samples
        q_act = _at_times(drive, rec.times)
        q = q_act / scale
        sp, ac = finite_differences(rec.times, q_act)
        speed, accel = sp / scale, ac / scale
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
        "drives": drives,
        "duration_s": rnd(float(rec.times[-1]) if k else 0.0),
        "samples": k,
        "joints": joints,
        "start_joints": [rnd(float(v)) for v in (q[0] if k else [])],
        "end_joints": [rnd(float(v)) for v in (q[-1] if k else [])],
        "max_path_error_mm": rnd(float(rec.pos_error.max()) / units.MM if k else 0.0),
        "max_orientation_error_deg": rnd(float(rec.ori_error.max()) / units.DEG if k else 0.0),
        "obstacles": _obstacles(rec),
        "ik": {
            "cycles": int(ik_mask.sum()),
            "iterations_mean": rnd(float(iters.mean()) if iters.size else 0.0, 6),
            "iterations_max": int(iters.max()) if iters.size else 0,
            "relaxed_cycles": int(rec.relaxed.sum()),
            "min_manipulability": rnd(float(manip.min())) if manip.size else None,
        },
        "output": list(execution.output),
        "warnings": warnings,
        "events": [_clean(e) for e in execution.events],
        "tolerances": {
            "path_mm": rnd(opts.tol_position / units.MM),
            "orientation_deg": rnd(opts.tol_orientation / units.DEG),
        },
        "joint_names": list(names),
        "robot_joint_names": list(model.joint_names),
        "program_name": code.program,
        "tool": tool_report(model, execution.state.settings.tool),
    }
    if drive is not None:
        from irlc.runtime.drives import report_axes

        report["drives_summary"] = {
            "level": drive.level,
            "step_s": rnd(drive.step),
            "could_follow": bool(drive.could_follow),
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


def _at_times(drive, times: np.ndarray) -> np.ndarray:
    """The drive's actual joints at the IPO sample times (the drive run continues a little
    after the last sample so that settling is seen; the trace stops at the last sample)."""
    if len(drive.t) == len(times) and np.allclose(drive.t, times):
        return drive.q_actual
    return _interp_rows(drive.t, drive.q_actual, times)


def _interp_rows(t_src, rows, t_dst) -> np.ndarray:
    return np.column_stack([np.interp(t_dst, t_src, rows[:, j]) for j in range(rows.shape[1])])


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


def _obstacles(rec: RecordedRun) -> dict:
    out = {}
    for name in sorted(rec.clearance):
        d = rec.clearance[name]
        finite = d[np.isfinite(d)]
        idx = int(np.argmin(d)) if finite.size else None
        out[name] = {
            "min_distance_mm": rnd(float(finite.min()) / units.MM) if finite.size else None,
            "at_time_s": rnd(float(rec.times[idx])) if idx is not None else None,
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


def build_trace(model, rec: RecordedRun, names, drive, every_step: bool):
    """``(columns, table)`` in program units; one row per IPO sample (per drive step with
    ``every_step``)."""
    kinds = model.joint_kinds
    scale = units.joint_scale(kinds)
    cols = trace_header(names, kinds, drive is not None, rec.clearance)
    times, lines, q, tcp = rec.times, rec.lines, rec.q, rec.tcp
    pos_err, ori_err = rec.pos_error, rec.ori_error
    clearance = rec.clearance
    if drive is not None:
        if every_step:
            times = drive.t
            idx = np.clip(
                np.searchsorted(rec.times, times, side="right") - 1, 0, len(rec.times) - 1
            )
            lines, pos_err, ori_err = rec.lines[idx], rec.pos_error[idx], rec.ori_error[idx]
            clearance = {k: v[idx] for k, v in rec.clearance.items()}
        q = drive.q_actual if every_step else _at_times(drive, times)
        tcp = _tcp_of(model, q, rec, times)
    speed, accel = finite_differences(times, q)
    k = len(times)
    poses = np.array([units.pose_from_si(t) for t in tcp]) if k else np.zeros((0, 6))
    parts = [
        times[:, None],
        lines[:, None].astype(float),
        q / scale,
        speed / scale,
        accel / scale,
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
    table = np.hstack(parts) if k else np.zeros((0, len(cols)))
    return cols, table
