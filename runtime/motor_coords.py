"""Motor coordinates for users: trace columns, the report's per-motor travel, fk/ik output.

Motor angles ``θs = m(q)`` come from the robot's motor map (:mod:`motor_maps`) and are
shown in **rad** (motor side; the unit is in every column and key name: ``a5_motor_rad``,
``travel_rad``), as Szkodny tabulates them (L-1: eq. 4.21). Only robots whose file has a
``[transmission]`` table show them (the others are direct drives: motor = joint).

The report's ``motors`` (per motor, over the run): start and end angle, the travel
``Σ|Δθs|`` over the samples, the largest speed, the speed limit of the drive data where
the transmission couples joints (:mod:`motor_limits`; ``null`` otherwise) and the book's
travel time ``travel / v_max`` (L-1: eq. 4.22) — the shortest time the motor needs.
:func:`add_statement_motors` gives the same per statement of the report's ``statements``
(``motor_travel_rad``, ``motor_travel_time_s``: Szkodny's per-move table).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime.motor_limits import motor_limits
from irlc.runtime.motor_maps import MotorMap

UNITS = {"angle": "rad", "speed": "rad/s", "time": "s"}


def has_motors(model: RobotModel) -> bool:
    """True when the robot file gives motor maps (a ``[transmission]`` table)."""
    return "transmission" in model.extra


def motor_angles(model: RobotModel, q: np.ndarray) -> np.ndarray:
    """``θs`` (rad) of joint configurations ``q`` (SI; one ``(n,)`` or many ``(k, n)``)."""
    q = np.asarray(q, dtype=float)
    out = MotorMap.from_model(model).motor_from_joints(q)
    return out if q.ndim == 2 else out[0]


def trace_columns(names) -> list[str]:
    """``NAME_motor_rad`` per joint (the program's names)."""
    return [f"{n}_motor_rad" for n in names]


def motor_report(model: RobotModel, names, times: np.ndarray, q: np.ndarray) -> dict[str, Any]:
    """The report's ``motors`` section of the motion ``q`` (SI, ``(k, n)``) at ``times``."""
    theta = motor_angles(model, q) if len(q) else np.zeros((0, model.n))
    limits = motor_limits(model)
    speed_limit = limits.speed if limits is not None else np.full(model.n, np.inf)
    step = np.abs(np.diff(theta, axis=0))
    travel = step.sum(axis=0) if len(theta) > 1 else np.zeros(model.n)
    dt = np.diff(np.asarray(times, dtype=float))
    with np.errstate(divide="ignore", invalid="ignore"):
        speed = step / dt[:, None] if len(dt) else np.zeros((0, model.n))
    speed = np.where(np.isfinite(speed), speed, 0.0)
    axes = []
    for j, name in enumerate(names):
        limit = float(speed_limit[j])
        finite = np.isfinite(limit)
        axes.append(
            {
                "joint": name,
                "robot_name": model.joint_names[j],
                "start_rad": float(theta[0, j]) if len(theta) else 0.0,
                "end_rad": float(theta[-1, j]) if len(theta) else 0.0,
                "travel_rad": float(travel[j]),
                "max_abs_speed_rad_s": float(speed[:, j].max()) if len(speed) else 0.0,
                "speed_limit_rad_s": limit if finite else None,
                "travel_time_s": float(travel[j]) / limit if finite else None,
            }
        )
    source = limits.source if limits is not None else None
    return {"units": dict(UNITS), "speed_limits_from": source, "axes": axes}


def add_statement_motors(rows: list[dict], model: RobotModel, times, q: np.ndarray, rnd) -> None:
    """Per statement row (``start_s``, ``duration_s``): ``motor_travel_rad`` (``Σ|Δθs|``
    per motor over the samples of the statement) and ``motor_travel_time_s`` (travel /
    speed limit, ``None`` for an unlimited motor); ``rnd`` rounds the numbers."""
    times = np.asarray(times, dtype=float)
    if not len(times):
        return
    theta = motor_angles(model, q)
    limits = motor_limits(model)
    speed = limits.speed if limits is not None else np.full(model.n, np.inf)
    for row in rows:
        start = row["start_s"] or 0.0
        end = start + (row["duration_s"] or 0.0)
        i0 = int(np.searchsorted(times, start - 1e-9))
        i1 = int(np.searchsorted(times, end + 1e-9, side="right"))
        span = theta[i0:i1]  # from the sample at the statement's start to its end
        travel = np.abs(np.diff(span, axis=0)).sum(axis=0) if len(span) > 1 else np.zeros(model.n)
        row["motor_travel_rad"] = [rnd(float(v)) for v in travel]
        row["motor_travel_time_s"] = [
            rnd(float(t / v)) if np.isfinite(v) else None
            for t, v in zip(travel, speed, strict=True)
        ]
