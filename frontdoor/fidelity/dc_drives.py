"""Drive studies on the DC drive chains: the IRb-6 line-trajectory test (ch. 5, figs.
5.11–5.21 with the servo data of Tables 5.3–5.5, in irlc's irb6_track) and the
model-simplification tables (3.6/3.7 AS, 4.4/4.6 L-1, 5.7–5.10 IRb-6 on the track).

A **simplification** is judged as Szkodny does: the largest difference of the actual joint
trajectories of the simplified and the full model on the same command, in % of the
commanded range of the joint (:func:`irlc.runtime.drives.deviation_percent`). The full
model is ``coupled`` (the complete ``M(q)``, ``C q̇``, ``G(q)``) at the step-size rule's
step; the simplified ones are ``decoupled`` (constant inertia per motor, configuration-
dependent gravity) at the same step, and the full model at :data:`COARSE_STEP_FACTOR` ×
the step (the integration step's effect). The test motions are ``programs/fidelity/``'s
(the book's are not in the sources at hand); each run's command comes from irlc's kinematic
run of the program.
"""

from __future__ import annotations

import functools
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from irlc.fidelity.steppers import line_drive, motor_errors
from irlc.runtime.drives import StepSizeWarning, deviation_percent, simulate_drives
from irlc.runtime.run import run_file

PROGRAMS = Path(__file__).resolve().parents[2] / "programs" / "fidelity"
COARSE_STEP_FACTOR = 4
MOTIONS = {"as6": "as6_ptp.irl", "irb6_track": "irb6_track_line.irl"}


@functools.cache
def command(robot: str):
    """``(model, times, q)`` of the robot's test motion (kinematic run; the L-1's is the
    line of :mod:`.steppers`, on the robot without position limits, as the book ran it)."""
    if robot == "l1":
        model, run, _ = line_drive()
        return model, run.times, run.q
    run = run_file(PROGRAMS / MOTIONS[robot])
    if not run.ok:
        raise RuntimeError(f"{MOTIONS[robot]} fails: {run.error}")
    return run.model, run.times, run.q


@functools.cache
def drive_run(robot: str, level: str, factor: int = 1):
    """The drives on the robot's test motion at ``factor`` × the step-size rule's step of
    the coupled model (``factor`` > 1 breaks the rule on purpose: no warning)."""
    model, times, q = command(robot)
    step = None if factor == 1 and level == "coupled" else drive_run(robot, "coupled").step
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", StepSizeWarning)
        return simulate_drives(model, times, q, level=level, step=step and step * factor, hold=0.5)


@dataclass(frozen=True)
class Simplification:
    """Per joint, % of the commanded range: ``decoupled`` vs coupled at the same step,
    ``coarse`` the coupled model at :data:`COARSE_STEP_FACTOR` × the step vs the step."""

    robot: str
    step: float
    decoupled: np.ndarray
    coarse: np.ndarray


@functools.cache
def simplification(robot: str) -> Simplification:
    full = drive_run(robot, "coupled")
    decoupled = drive_run(robot, "decoupled")
    coarse = drive_run(robot, "coupled", COARSE_STEP_FACTOR)
    # the coarse run on the fine run's time grid (its samples are every FACTOR-th)
    fine_t = full.t
    coarse_q = np.array([np.interp(fine_t, coarse.t, coarse.q_actual[:, j])
                         for j in range(coarse.q_actual.shape[1])]).T  # fmt: skip
    span = np.ptp(full.q_cmd_interp, axis=0)
    step_dev = (
        100.0 * np.abs(full.q_actual - coarse_q).max(axis=0) / np.where(span > 0, span, np.inf)
    )
    return Simplification(robot, full.step, deviation_percent(full, decoupled), step_dev)


@functools.cache
def line_following_errors(level: str = "coupled") -> np.ndarray:
    """Largest motor-side following error per axis (rad) of the IRb-6 line test."""
    model, _, _ = command("irb6_track")
    return np.abs(motor_errors(model, drive_run("irb6_track", level))).max(axis=0)
