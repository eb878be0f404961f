"""The L-1's stepper drives as Szkodny simulated them: the line P→K of (4.23) / Table 4.5
and the step trajectory of figs. 4.7/4.8.

* **Line.** The book's procedure: the joint command of the line from the kinematics (no
  position limits: :func:`~irlc.fidelity.unlimited.without_position_limits`), then the
  drive models. Control errors per motor ``e_qs = Θs_cmd − Θs`` (rad, motor side): the
  largest over the line (4.23) and the error at rest after it, in steps of 1.8° (Table 4.5).
  The line is ``programs/fidelity/l1_line.irl`` (P, K are not in the sources at hand).
* **Step trajectory.** A step of the wrist joints' command (the step generator then issues
  full steps at its 2.5π rad/s); which motors lose steps (fall out of step) and when motor 6
  settles — with the robot file's wrist inertias and with them scaled up, since the L-1's
  wrist masses are not published (``WRIST_SCALES``).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from irlc.fidelity.unlimited import without_position_limits
from irlc.robots import load_robot
from irlc.robots.model import RobotModel
from irlc.runtime.drives import simulate_drives
from irlc.runtime.outputs.motor_coords import motor_angles
from irlc.runtime.run import run_file

PROGRAMS = Path(__file__).resolve().parents[2] / "programs" / "fidelity"
LINE_PROGRAM = PROGRAMS / "l1_line.irl"
LINE_START = (200.0, 300.0, 300.0, 90.0, 30.0, 0.0)  # P' (mm, deg): W6 on its 0° bound
STEP_ANGLE = 2 * math.pi / 200  # rad: 1.8°, one full step of a 50-tooth motor
STEP_COMMAND_DEG = (90.0, 90.0, 90.0)  # the wrist step W4, W5, W6 (not published)
STEP_DURATION = 3.0  # s simulated after the step (+ the drives' hold)
WRIST_SCALES = (1.0, 10.0, 30.0, 100.0)
SETTLED = 0.02  # rad: a motor is settled once its error stays below (≈ 2/3 step)


@dataclass(frozen=True)
class LineStudy:
    """``limited_error``: how the run fails with the position limits enforced (``None``
    when it does not); ``max_error`` / ``rest_error_steps`` / ``lost_steps`` per motor;
    ``duration``: the line's time, s."""

    limited_error: str | None
    limited_time: float | None
    max_error: np.ndarray
    rest_error_steps: np.ndarray
    lost_steps: tuple[int, ...]
    duration: float


@functools.cache
def line_drive(level: str = "decoupled"):
    """``(model, run, drive)``: the line on the L-1 without position limits (kinematic
    run) and the stepper drives on its command — the book's procedure."""
    book = without_position_limits(load_robot("l1"))
    run = run_file(LINE_PROGRAM, robot=book, seed_config=list(LINE_START))
    if not run.ok:
        raise RuntimeError(f"the L-1 line fails without position limits: {run.error}")
    return book, run, simulate_drives(book, run.times, run.q, level=level, hold=0.5)


def motor_errors(model: RobotModel, drive) -> np.ndarray:
    """``Θs_cmd − Θs`` per drive step and motor (rad)."""
    return motor_angles(model, drive.q_cmd_interp) - motor_angles(model, drive.q_actual)


@functools.cache
def line_study(level: str = "decoupled") -> LineStudy:
    """The line with the limits enforced (kinematic run), then as the book did it."""
    limited = run_file(LINE_PROGRAM, seed_config=list(LINE_START))
    book, run, drive = line_drive(level)
    errors = motor_errors(book, drive)
    return LineStudy(
        None if limited.ok else limited.error.message,
        None if limited.ok else limited.error.time_s,
        np.abs(errors).max(axis=0),
        errors[-1] / STEP_ANGLE,
        tuple(int(a.lost_steps or 0) for a in drive.axes),
        float(run.report["statements"][0]["duration_s"]),
    )


@dataclass(frozen=True)
class StepStudy:
    """Per motor 4–6: ``lost_steps``, ``settle_time`` (s after the step: the error stays
    below :data:`SETTLED` from then on; ``inf`` if it never does), ``max_error`` (rad)."""

    scale: float
    lost_steps: tuple[int, int, int]
    settle_time: tuple[float, float, float]
    max_error: tuple[float, float, float]


def scaled_wrist(model: RobotModel, scale: float) -> RobotModel:
    """The L-1 with the inertia tensors of its wrist links (4–6) times ``scale`` (masses
    kept: the gravity load stays, the inertia the step must accelerate grows)."""
    inertials = tuple(
        dataclasses.replace(i, inertia=i.inertia * scale) if i.link >= 4 else i
        for i in model.inertials
    )
    return dataclasses.replace(model, inertials=inertials)


@functools.cache
def step_drive(scale: float = 1.0, level: str = "coupled"):
    """``(model, drive)``: a step of :data:`STEP_COMMAND_DEG` on W4–W6 from the home
    configuration, the wrist inertias × ``scale``."""
    model = scaled_wrist(load_robot("l1"), scale)
    q0 = model.home_q()
    q1 = q0.copy()
    q1[3:] += np.radians(STEP_COMMAND_DEG)
    times = np.array([0.0, 1e-3, STEP_DURATION])
    return model, simulate_drives(model, times, np.array([q0, q1, q1]), level=level, hold=0.5)


@functools.cache
def step_study(scale: float = 1.0, level: str = "coupled") -> StepStudy:
    model, drive = step_drive(scale, level)
    errors = np.abs(motor_errors(model, drive))[:, 3:]
    settle = []
    for k in range(3):
        above = np.flatnonzero(errors[:, k] >= SETTLED)
        if not len(above):
            settle.append(0.0)
        elif above[-1] == len(errors) - 1:
            settle.append(math.inf)
        else:
            settle.append(float(drive.t[above[-1] + 1]))
    lost = tuple(abs(int(a.lost_steps or 0)) for a in drive.axes[3:])
    return StepStudy(scale, lost, tuple(settle), tuple(errors.max(axis=0)))


def step_travel_time() -> float:
    """|ΔΘs6| / 2.5π of the step command: when motor 6's generator has issued its steps."""
    model = load_robot("l1")
    q0 = model.home_q()
    q1 = q0.copy()
    q1[3:] += np.radians(STEP_COMMAND_DEG)
    rate = model.extra["drives"]["stepper"]["step_rate"]
    return abs(motor_angles(model, q1)[5] - motor_angles(model, q0)[5]) / rate
