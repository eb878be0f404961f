"""The ROS-like trajectory export of a run (``--export-trajectory``).

:func:`write_trajectory` writes a JSON document shaped like ROS ``trajectory_msgs/
JointTrajectory``: ``joint_names`` — the robot file's own names (URDF names for a URDF
robot, e.g. ``panda_joint4``), so that the file drops into ROS tooling without renaming;
the program's names ``a1 … aN`` are beside them in ``program_joint_names`` — and
``points`` with ``positions``, ``velocities``,
``accelerations`` (rad | m, per second, per second²) and ``time_from_start``
``{sec, nanosec}``. Velocities and accelerations there are derivatives *at* the sample
times (:func:`sample_derivatives`), not the trace's backward differences. A cell's
document holds one trajectory per robot (:func:`cell_trajectory_document`).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
from irlc.files import atomic_write_text
from irlc.robot_runs import robot_runs
from irlc.run_data import RunData, run_data

TRAJECTORY_FORMAT = "irlc-joint-trajectory 1"
DIGITS = 9  # decimals kept in exported SI numbers (1 nrad, 1 nm)


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
