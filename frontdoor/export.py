"""Run data for tools (plots, animation, exports) and the ROS-like trajectory export.

:func:`run_data` turns what a run produced — a ``RunResult`` of :mod:`irlc.runtime.run`,
what :func:`irlc.report.load_run` read back from a report or trace, or a path to one —
into one :class:`RunData` with plain arrays in SI (rad | m, s). Columns of the trace are
found by their ``docs/interfaces.md`` names (``a1_deg``, ``a1_speed_deg_s``, ``a1_cmd_deg``,
``a1_current_A``, ``x_mm`` …) and converted with :mod:`irlc.runtime.units` only.

When the trace has no speed / acceleration columns they are the finite differences of
the positions, ``q̇ ≈ np.gradient(q, t)`` (central inside, one-sided at the ends).

:func:`write_trajectory` writes a JSON document shaped like ROS ``trajectory_msgs/
JointTrajectory``: ``joint_names`` — the robot file's own names (URDF names for a URDF
robot, e.g. ``panda_joint4``), so that the file drops into ROS tooling without renaming;
the program's names ``a1 … aN`` are beside them in ``program_joint_names`` — and
``points`` with ``positions``, ``velocities``,
``accelerations`` (rad | m, per second, per second²) and ``time_from_start``
``{sec, nanosec}``. Velocities and accelerations there are derivatives *at* the sample
times (:func:`sample_derivatives`), not the trace's backward differences.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from irlc.errors import UsageError
from irlc.files import atomic_write_bytes, atomic_write_text  # noqa: F401 (plots imports it here)
from irlc.runtime import units
from irlc.runtime.model.naming import default_names, joint_label

TRAJECTORY_FORMAT = "irlc-joint-trajectory 1"
_POSE_AXES = {"x", "y", "z", "a", "b", "c"}
DIGITS = 9  # decimals kept in exported SI numbers (1 nrad, 1 nm)


@dataclass
class RunData:
    """One run as arrays; ``k`` samples, ``n`` joints; SI unless named otherwise."""

    times: np.ndarray  # (k,) s
    joint_names: tuple[str, ...]  # program names (a1 … aN or MAIN_JOINT's)
    joint_kinds: tuple[str, ...]  # "revolute" | "prismatic"
    q: np.ndarray  # (k, n) rad | m
    qd: np.ndarray  # (k, n) /s
    qdd: np.ndarray  # (k, n) /s²
    lines: np.ndarray | None = None  # (k,) program line per sample
    tcp: np.ndarray | None = None  # (k, 3) m, world frame
    path_error_mm: np.ndarray | None = None  # (k,)
    q_cmd: np.ndarray | None = None  # (k, n) drive setpoints (with simulated drives)
    current: np.ndarray | None = None  # (k, n) A
    report: dict = field(default_factory=dict)
    model: Any = None  # RobotModel | None
    obstacles: tuple = ()
    label: str = ""
    robot_joint_names: tuple[str, ...] = ()  # the robot file's names (() when unknown)

    @property
    def k(self) -> int:
        return len(self.times)

    @property
    def n(self) -> int:
        return len(self.joint_names)

    def joint_label(self, j: int) -> str:
        """Joint ``j`` by the naming rule: ``a4 (panda_joint4)``."""
        robot = self.robot_joint_names[j] if len(self.robot_joint_names) == self.n else None
        return joint_label(self.joint_names[j], robot)

    def program_units(self, values: np.ndarray) -> np.ndarray:
        """SI joint values → deg | mm (per joint kind)."""
        return units.joints_from_si(values, self.joint_kinds)

    def unit(self, j: int, derivative: int = 0) -> str:
        """Readable unit of joint ``j``: ``deg``, ``deg/s``, ``mm/s²`` …"""
        return (
            units.joint_unit(self.joint_kinds[j], derivative)
            .replace("_s2", "/s²")
            .replace("_s", "/s")
        )


class RunDataError(UsageError, ValueError):
    """The run has no usable samples (e.g. a report without a trace): a usage error."""


# --------------------------------------------------------------------------- reading


def _get(obj: Any, *names: str, default: Any = None) -> Any:
    for name in names:
        if isinstance(obj, dict) and name in obj:
            return obj[name]
        if hasattr(obj, name):
            return getattr(obj, name)
    return default


def _trace_table(run: Any) -> dict[str, np.ndarray]:
    """The trace as ``column name → (k,) array`` (empty when the run has none)."""
    table = _get(run, "trace_table")
    if isinstance(table, dict):
        return {str(k): np.asarray(v, dtype=float) for k, v in table.items()}
    columns = _get(run, "trace_columns", "columns")
    data = _get(run, "trace_data", "trace")
    if columns is None and data is not None and hasattr(data, "columns"):
        columns, data = _get(data, "columns"), _get(data, "data", "values", "rows")
    if columns is None or data is None:
        return {}
    arr = np.asarray(data, dtype=float)
    if arr.ndim != 2 or arr.shape[1] != len(columns):
        return {}
    return {str(c): arr[:, i] for i, c in enumerate(columns)}


def _joint_names_kinds(run: Any, report: dict, model: Any, table) -> tuple[tuple, tuple]:
    rows = report.get("joints") or []
    if rows and all("name" in r for r in rows):
        names = tuple(str(r["name"]) for r in rows)
        kinds = tuple(units.PRISMATIC if r.get("unit") == "mm" else units.REVOLUTE for r in rows)
        return names, kinds
    if model is not None:
        names = tuple(_get(run, "joint_names", default=None) or default_names(model.n))
        return names, tuple(model.joint_kinds)
    names, kinds = [], []
    for col in table:
        for suffix, kind in (("_deg", units.REVOLUTE), ("_mm", units.PRISMATIC)):
            stem = col[: -len(suffix)]
            if col.endswith(suffix) and "_" not in stem and stem not in _POSE_AXES:
                names.append(stem)
                kinds.append(kind)
    return tuple(names), tuple(kinds)


def _robot_joint_names(report: dict, model: Any, n: int) -> tuple[str, ...]:
    """The robot file's joint names: from the report (``robot_joint_names``, or the
    ``robot_name`` of its joint rows), else from the model; ``()`` when unknown."""
    names = report.get("robot_joint_names")
    if not names:
        rows = report.get("joints") or []
        names = [r.get("robot_name") for r in rows] if rows else None
    if (not names or not all(names)) and model is not None:
        names = model.joint_names
    names = tuple(str(v) for v in names or ())
    return names if len(names) == n else ()


def _joint_columns(table, names, kinds, middle: str, derivative: int) -> np.ndarray | None:
    cols = []
    for name, kind in zip(names, kinds, strict=True):
        unit = units.joint_unit(kind, derivative) if derivative >= 0 else "A"
        key = f"{name}{middle}_{unit}"
        if key not in table:
            return None
        cols.append(table[key])
    return np.column_stack(cols) if cols else None


def _model_of(run: Any, report: dict) -> Any:
    model = _get(run, "model")
    if model is not None or not report.get("robot"):
        return model
    try:
        from irlc.robots import load_robot

        return load_robot(report["robot"])
    except Exception:
        return None


def _file_name(run: Any) -> str:
    """The name of the file a loaded run was read from (a trace names no program), or ''."""
    path = _get(run, "path", default=None)
    return Path(path).name if path else ""


def run_data(run: Any, label: str = "") -> RunData:
    """Normalise a run (RunResult, loaded run, report/trace path, or RunData)."""
    if isinstance(run, RunData):
        return run
    if isinstance(run, (str, Path)):
        from irlc.report import load_run  # the reader of report JSON / trace CSV

        run = load_run(Path(run))
    report = dict(_get(run, "report", default=None) or {})
    table = _trace_table(run)
    model = _model_of(run, report)
    names, kinds = _joint_names_kinds(run, report, model, table)
    times = _get(run, "times")
    times = np.asarray(times if times is not None else table.get("t_s", []), dtype=float)
    q = _get(run, "q")
    if q is not None:
        q = np.asarray(q, dtype=float)
    else:
        q_prog = _joint_columns(table, names, kinds, "", 0)
        q = None if q_prog is None else units.joints_to_si(q_prog, kinds)
    if q is None or q.ndim != 2 or len(q) == 0 or len(times) != len(q):
        where = _get(run, "path", default=None) or report.get("program") or "the run"
        raise RunDataError(
            f"{where}: no joint samples (a report holds none; use a trace CSV from --trace)"
        )
    if not names or len(names) != q.shape[1]:
        names = tuple(f"a{i + 1}" for i in range(q.shape[1]))
        kinds = tuple(model.joint_kinds) if model is not None else (units.REVOLUTE,) * q.shape[1]
    qd = _derivative(table, names, kinds, "_speed", 1, q, times)
    qdd = _derivative(table, names, kinds, "_accel", 2, qd, times)
    cmd = _joint_columns(table, names, kinds, "_cmd", 0)
    current = _joint_columns(table, names, kinds, "_current", -1)
    return RunData(
        times=times,
        joint_names=names,
        joint_kinds=kinds,
        q=q,
        qd=qd,
        qdd=qdd,
        lines=table["line"].astype(int) if "line" in table else _lines_of(run),
        tcp=_tcp_of(run, table, model, q),
        path_error_mm=table.get("path_error_mm"),
        q_cmd=None if cmd is None else units.joints_to_si(cmd, kinds),
        current=current,
        report=report,
        model=model,
        obstacles=tuple(_get(run, "obstacles", default=()) or ()),
        label=label or str(report.get("program", "")) or _file_name(run),
        robot_joint_names=_robot_joint_names(report, model, len(names)),
    )


def _derivative(table, names, kinds, middle, order, lower, times) -> np.ndarray:
    prog = _joint_columns(table, names, kinds, middle, order)
    if prog is not None:
        return units.joints_to_si(prog, kinds)
    if len(times) < 2:
        return np.zeros_like(lower)
    return np.gradient(lower, times, axis=0)


def _lines_of(run: Any) -> np.ndarray | None:
    lines = _get(run, "lines")
    return None if lines is None else np.asarray(lines, dtype=int)


def _tcp_of(run: Any, table, model, q: np.ndarray) -> np.ndarray | None:
    tcp = _get(run, "tcp")
    if tcp is not None:
        tcp = np.asarray(tcp, dtype=float)
        if tcp.ndim == 3:  # (k, 4, 4) transforms
            return tcp[:, :3, 3]
        if tcp.ndim == 2 and tcp.shape[1] >= 3:
            return tcp[:, :3]
    if all(c in table for c in ("x_mm", "y_mm", "z_mm")):
        return np.column_stack([table["x_mm"], table["y_mm"], table["z_mm"]]) * units.MM
    if model is not None:
        from irlc.runtime.model.kinematics import Kinematics

        kin = Kinematics(model)
        return np.array([kin.tcp(qi)[:3, 3] for qi in q])
    return None


# --------------------------------------------------------------------------- writing


def _round(values: np.ndarray) -> list[float]:
    return [float(v) + 0.0 for v in np.round(values, DIGITS)]  # + 0.0: no "-0.0"


def _time_from_start(t: float) -> dict[str, int]:
    ns = round(t * 1e9)
    return {"sec": ns // 1_000_000_000, "nanosec": ns % 1_000_000_000}


def sample_derivatives(q: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Velocity and acceleration *at* the sample times, from the positions ``q`` (k, n).

    q̇ₖ = np.gradient (central, second order; one-sided second order at the ends, so a
    run that starts and ends at rest has q̇ = 0 there); q̈ₖ = 2·(δ₊/h₊ − δ₋/h₋)/(h₊ + h₋)
    with δ± the position steps and h± the time steps (the 3-point second difference;
    the ends repeat their neighbour). The trace's speed columns are backward differences
    — the mean speed of the cycle *before* the sample, half a cycle late — which a
    trajectory follower interpolating positions and velocities must not be given."""
    k = len(t)
    if k < 2:
        return np.zeros_like(q), np.zeros_like(q)
    qd = np.gradient(q, t, axis=0, edge_order=2 if k >= 3 else 1)
    if k < 3:
        return qd, np.zeros_like(q)
    h = np.diff(t)[:, None]
    slope = np.diff(q, axis=0) / h
    qdd = np.empty_like(q)
    qdd[1:-1] = 2.0 * (slope[1:] - slope[:-1]) / (h[1:] + h[:-1])
    qdd[0], qdd[-1] = qdd[1], qdd[-2]
    return qd, qdd


def trajectory_document(run: Any) -> dict:
    """The JointTrajectory-like document of a run (see the module docstring); a cell's
    holds one per robot (:func:`cell_trajectory_document`)."""
    if getattr(run, "is_cell", False):
        return cell_trajectory_document(run)
    d = run_data(run)
    joints = _joint_trajectory(d)
    points = joints.pop("points")
    return {
        "format": TRAJECTORY_FORMAT,
        "header": _HEADER,
        "robot": d.report.get("robot", getattr(d.model, "name", "")),
        **_run_keys(d.report),
        **joints,
        "units": dict(_UNITS),
        "points": points,
    }


_HEADER = {"frame_id": "world", "stamp": {"sec": 0, "nanosec": 0}}
_UNITS = {"revolute": "rad", "prismatic": "m", "time": "s"}


def _run_keys(report: dict) -> dict:
    """The run's ``program``, ``status``, ``partial``, ``motion`` and ``drives``: a failed
    run's points stop where it stopped; with drives they are the simulated actual motion,
    not the setpoints."""
    status, drives = report.get("status"), report.get("drives", "ideal")
    return {
        "program": report.get("program", ""),
        "status": status,
        "partial": status == "failed",
        "motion": "commanded" if drives == "ideal" else "actual",
        "drives": drives,
    }


def _joint_trajectory(d: RunData) -> dict:
    """``joint_names`` (the robot file's), ``program_joint_names``, ``joint_kinds`` and the
    ``points`` of one robot's samples."""
    t0 = float(d.times[0])
    qd, qdd = sample_derivatives(d.q, d.times)
    points = [
        {
            "positions": _round(d.q[i]),
            "velocities": _round(qd[i]),
            "accelerations": _round(qdd[i]),
            "time_from_start": _time_from_start(float(d.times[i]) - t0),
        }
        for i in range(d.k)
    ]
    return {
        "joint_names": list(d.robot_joint_names or d.joint_names),
        "program_joint_names": list(d.joint_names),
        "joint_kinds": list(d.joint_kinds),
        "points": points,
    }


def cell_trajectory_document(run: Any) -> dict:
    """A cell's trajectories: the run's keys, then ``robots``, per robot in the ``ROBOT``
    clauses' order its ``name``, ``robot``, ``at`` (its placement as the program writes
    it: mm, deg ZYX), ``placement`` (the same as a ROS transform from ``world`` to its
    base's placement: ``translation`` m, ``rotation`` quaternion ``x y z w``), ``header``
    and its own joint trajectory (its robot file's joint names, SI)."""
    from irlc.robot_runs import robot_runs
    from irlc.runtime.model import spatial

    robots = []
    for r in robot_runs(run):
        w, x, y, z = spatial.matrix_to_quat(r.at[:3, :3])
        placement = {
            "frame_id": "world",
            "translation": _round(r.at[:3, 3]),
            "rotation": _round(np.array([x, y, z, w])),
        }
        robots.append({
            "name": r.name,
            "robot": r.data.report.get("robot", r.model.name),
            "at": list(r.data.report.get("at") or [0.0] * 6),
            "placement": placement,
            "header": _HEADER,
            **_joint_trajectory(r.data),
        })  # fmt: skip
    units = {**_UNITS, "at": "mm, deg (x, y, z, a, b, c: ZYX, as the program's AT)"}
    return {
        "format": TRAJECTORY_FORMAT,
        "robot": run.report.get("robot", ""),
        **_run_keys(run.report),
        "units": units,
        "robots": robots,
    }


def write_trajectory(run: Any, path: str | Path) -> Path:
    """Write the run's joint trajectory as JSON (atomic, deterministic); returns the path."""
    path = Path(path)
    text = json.dumps(trajectory_document(run), indent=1, separators=(",", ": "))
    atomic_write_text(path, text + "\n")
    return path
