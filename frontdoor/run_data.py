"""Run data for tools (plots, animation, exports): one run as plain arrays.

:func:`run_data` turns what a run produced — a ``RunResult`` of :mod:`irlc.runtime.run`,
what :func:`irlc.report.load_run` read back from a report or trace, or a path to one —
into one :class:`RunData` with plain arrays in SI (rad | m, s). Columns of the trace are
found by their ``docs/interfaces.md`` names (``a1_deg``, ``a1_speed_deg_s``, ``a1_cmd_deg``,
``a1_current_A``, ``x_mm`` …) and converted with :mod:`irlc.runtime.units` only.

When the trace has no speed / acceleration columns they are the finite differences of
the positions, ``q̇ ≈ np.gradient(q, t)`` (central inside, one-sided at the ends).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from irlc.errors import UsageError
from irlc.runtime import units
from irlc.runtime.model.naming import default_names, joint_label

_POSE_AXES = {"x", "y", "z", "a", "b", "c"}


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
