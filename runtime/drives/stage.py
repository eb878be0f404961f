"""The drive step of a run: the recorded set points through the simulated drives.

``run_drives(samples, …)`` simulates the drives (:func:`irlc.runtime.drives.simulate_drives`)
on the commanded joints of the IPO samples, interpolates the actual joints to the sample
times once, measures the actual motion there once (TCP, path errors, clearances:
:mod:`irlc.runtime.outputs.actual_motion`), and judges it
(:mod:`irlc.runtime.outputs.verdict`); a verdict that fails stops the run where it failed
(:mod:`irlc.runtime.outputs.stop`). With one
trace row per drive step (``every_step``) the actual motion is also measured at the drive's
own times (the trace's rows). It returns the samples with the drive's part filled in and
the verdict; bad or missing drive data is a :class:`~irlc.runtime.errors.DriveSetupError`
(exit 3).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from irlc.runtime import engine_policy
from irlc.runtime.errors import DriveSetupError
from irlc.runtime.outputs import stop
from irlc.runtime.outputs.recorder import RecordedRun
from irlc.runtime.outputs.samples import Samples, commanded, measured

if TYPE_CHECKING:
    from irlc.robots.model import RobotModel
    from irlc.runtime.control.executor import ExecutionOptions
    from irlc.runtime.model.obstacles import Obstacle
    from irlc.runtime.outputs.verdict import Verdict


def run_drives(
    samples: Samples,
    model: RobotModel,
    level: str,
    every_step: bool,
    obstacles: dict[str, Obstacle],
    task_rows: tuple[int, ...],
    names: tuple[str, ...],
    opts: ExecutionOptions,
    until: float | None = None,
) -> tuple[Samples, Verdict]:
    """``(samples with the actual motion, verdict)`` (module doc). A verdict that fails
    before ``until`` (the kinematic run's failure time, if it failed) stops the run
    there: samples, drive rows and verdict end at the failure
    (:mod:`~irlc.runtime.outputs.stop`)."""
    from irlc.runtime.outputs.actual_motion import measure
    from irlc.runtime.outputs.verdict import judge

    rec = samples.recorded
    params = drive_data(model)
    steps = (rec.times[-1] - rec.times[0]) / opts.drive_step_s if opts.drive_step_s else 0.0
    accel = engine_policy.drive_kernels(opts.engine, steps)  # when the drive kernels pay
    drive = simulate(model, rec, level, every_step, params, accel)
    at_samples = measure(model, rec, rec.times, at_times(drive, rec.times), task_rows, obstacles)
    actual = measured(rec, at_samples)
    verdict = judge(model, names, rec, drive, actual, opts, params)
    steps = None
    if every_step:
        steps = measured(rec, measure(model, rec, drive.t, drive.q_actual, task_rows, obstacles))
    samples = Samples(rec, commanded(rec), actual, steps, drive)
    first = verdict.failure
    if first is not None and (until is None or first.time_s < until):
        return stopped(samples, verdict, model, names, opts, float(first.time_s), params)
    return samples, verdict


def stopped(
    samples: Samples,
    verdict: Verdict,
    model: RobotModel,
    names: tuple[str, ...],
    opts: ExecutionOptions,
    t_f: float,
    params=None,
) -> tuple[Samples, Verdict]:
    """A drive run stopped at ``t_f`` — its own first failure, or another's (a robot of
    the same cell, the clearance of the cell's actual motion): samples, drive rows and
    the verdict end there (:mod:`~irlc.runtime.outputs.stop`); the verdict is judged
    again on that part (the same failure, when it was this run's own)."""
    from irlc.runtime.outputs.verdict import following_bound, judge

    params = params if params is not None else drive_data(model)
    rec = samples.recorded
    drive = stop.drive_until(samples.drive, t_f, following_bound(model, params, rec.q[0]).bound)
    rec = stop.recorded_until(rec, t_f)
    actual = stop.motion_until(samples.actual, t_f)
    cut = judge(model, names, rec, drive, actual, opts, params)
    if cut.failure is None:  # stopped by another's failure, or between recorded rows
        cut = verdict
        cut.violations = [v for v in verdict.violations if v["time_s"] <= t_f + stop.SLACK]
        if cut.failure is not None and cut.failure.time_s > t_f + stop.SLACK:
            cut.failure = None
    steps = stop.motion_until(samples.steps, t_f)
    return Samples(rec, commanded(rec), actual, steps, drive), cut


def has_drive_data(model) -> bool:
    """Whether the robot file has drive data (``[drives]``; bad data still raises)."""
    from irlc.runtime.drives import drive_params

    try:
        return drive_params(model) is not None
    except ValueError as exc:
        raise DriveSetupError(f"robot {model.name}: bad drive data: {exc}") from None


def drive_data(model):
    """The robot's validated drive data (:func:`irlc.runtime.drives.drive_params`)."""
    try:
        from irlc.runtime.drives import drive_params
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
    return params


def simulate(model, rec: RecordedRun, level: str, every_step: bool, params=None, accel=None):
    """The drive simulation of the recorded set points (``record`` per drive step or per
    IPO sample; ``accel``: the compiled drive loop, :mod:`irlc.runtime.engine_policy`);
    its input errors are :class:`DriveSetupError`."""
    from irlc.runtime.drives import simulate_drives
    from irlc.runtime.outputs.verdict import following_bound

    params = params if params is not None else drive_data(model)
    try:
        return simulate_drives(
            model,
            rec.times,
            rec.q,
            level=level,
            params=params,
            tolerance=following_bound(model, params, rec.q[0]).bound,
            record="step" if every_step else "ipo",
            accel=accel,
        )
    except ValueError as exc:
        raise DriveSetupError(f"drive simulation: {exc}") from None


def at_times(drive, times: np.ndarray) -> np.ndarray:
    """The drive's actual joints at the IPO sample times (the drive run continues a little
    after the last sample so that settling is seen; the trace stops at the last sample)."""
    if len(drive.t) == len(times) and np.allclose(drive.t, times):
        return drive.q_actual
    return np.column_stack(
        [np.interp(times, drive.t, drive.q_actual[:, j]) for j in range(drive.q_actual.shape[1])]
    )
