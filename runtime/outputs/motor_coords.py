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
from irlc.lang import trace_columns as tc
from irlc.robots.model import RobotModel
from irlc.runtime.model.motor_limits import motor_limits
from irlc.runtime.model.motor_maps import MotorMap

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
    return [tc.motor(n) for n in names]


def motor_report(model: RobotModel, names, times: np.ndarray, q: np.ndarray) -> dict[str, Any]:
    """The report's ``motors`` section of the motion ``q`` (SI, ``(k, n)``) at ``times``."""
    tally = MotorTally(model, [])
    tally.add(times, q)
    return tally.report(names)


def add_statement_motors(rows: list[dict], model: RobotModel, times, q: np.ndarray, rnd) -> None:
    """Per statement row (``start_s``, ``duration_s``): ``motor_travel_rad`` (``Σ|Δθs|``
    per motor over the samples of the statement) and ``motor_travel_time_s`` (travel /
    speed limit, ``None`` for an unlimited motor); ``rnd`` rounds the numbers."""
    if not len(times):
        return
    tally = MotorTally(model, rows)
    tally.add(times, q)
    tally.add_statements(rnd)


class MotorTally:
    """:func:`motor_report` and :func:`add_statement_motors` of a motion given in
    consecutive pieces (a streamed run, :meth:`Recorder.chunks`): each piece is joined to
    the previous piece's last sample, and the travels are summed on in sample order, so
    they are those of the whole motion (to the last bit for two motors or more, whose sums
    numpy forms row by row; a single motor's may differ in the last bit)."""

    def __init__(self, model: RobotModel, rows: list[dict]):
        self.model, self.rows = model, rows
        self._windows = []  # a statement's samples: those within [start, end] ± 1 ns
        for row in rows:
            start = row["start_s"] or 0.0
            self._windows.append((start - 1e-9, start + (row["duration_s"] or 0.0) + 1e-9))
        self._row_travel: list[np.ndarray | None] = [None] * len(rows)
        self._travel: np.ndarray | None = None
        self._max_speed: np.ndarray | None = None
        self._first: np.ndarray | None = None
        self._last: tuple[np.ndarray, np.ndarray] | None = None  # (times, θs) of one sample

    def add(self, times: np.ndarray, q: np.ndarray) -> None:
        """The next piece of the motion: ``q`` (SI, ``(k, n)``) at ``times``."""
        times = np.asarray(times, dtype=float)
        if not len(times):
            return
        theta = motor_angles(self.model, q)
        if self._last is None:
            self._first = theta[0]
        else:
            times, theta = np.r_[self._last[0], times], np.vstack([self._last[1], theta])
        self._last = (times[-1:], theta[-1:])
        step = np.abs(np.diff(theta, axis=0))
        if len(step):
            self._travel = _summed(self._travel, step)
            with np.errstate(divide="ignore", invalid="ignore"):
                speed = step / np.diff(times)[:, None]
            top = np.where(np.isfinite(speed), speed, 0.0).max(axis=0)
            self._max_speed = top if self._max_speed is None else np.maximum(self._max_speed, top)
        for i, (lo, hi) in enumerate(self._windows):
            if hi < times[0] or lo > times[-1]:
                continue
            i0 = int(np.searchsorted(times, lo))
            i1 = int(np.searchsorted(times, hi, side="right"))
            if i1 - i0 > 1:
                self._row_travel[i] = _summed(
                    self._row_travel[i], np.abs(np.diff(theta[i0:i1], axis=0))
                )

    def report(self, names) -> dict[str, Any]:
        """The ``motors`` section (:func:`motor_report`)."""
        n = self.model.n
        limits = motor_limits(self.model)
        speed_limit = limits.speed if limits is not None else np.full(n, np.inf)
        travel = self._travel if self._travel is not None else np.zeros(n)
        top = self._max_speed if self._max_speed is not None else np.zeros(n)
        axes = []
        for j, name in enumerate(names):
            limit = float(speed_limit[j])
            finite = np.isfinite(limit)
            axes.append(
                {
                    "joint": name,
                    "robot_name": self.model.joint_names[j],
                    "start_rad": float(self._first[j]) if self._first is not None else 0.0,
                    "end_rad": float(self._last[1][0, j]) if self._last is not None else 0.0,
                    "travel_rad": float(travel[j]),
                    "max_abs_speed_rad_s": float(top[j]),
                    "speed_limit_rad_s": limit if finite else None,
                    "travel_time_s": float(travel[j]) / limit if finite else None,
                }
            )
        source = limits.source if limits is not None else None
        return {"units": dict(UNITS), "speed_limits_from": source, "axes": axes}

    def add_statements(self, rnd) -> None:
        """Write the rows' ``motor_travel_rad`` / ``motor_travel_time_s``
        (:func:`add_statement_motors`); nothing when no sample was added."""
        if self._last is None:
            return
        limits = motor_limits(self.model)
        speed = limits.speed if limits is not None else np.full(self.model.n, np.inf)
        for row, travel in zip(self.rows, self._row_travel, strict=True):
            travel = travel if travel is not None else np.zeros(self.model.n)
            row["motor_travel_rad"] = [rnd(float(v)) for v in travel]
            row["motor_travel_time_s"] = [
                rnd(float(t / v)) if np.isfinite(v) else None
                for t, v in zip(travel, speed, strict=True)
            ]


def _summed(total: np.ndarray | None, steps: np.ndarray) -> np.ndarray:
    """``total + Σ steps`` per column, added on row by row in order (the whole motion's
    ``steps.sum(axis=0)`` when the pieces are joined)."""
    if total is None:
        return steps.sum(axis=0)
    return np.add.reduce(np.vstack([total[None], steps]), axis=0)
