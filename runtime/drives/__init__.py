"""Simulated joint drives: setpoint interpolation → position P → velocity
PI → current controller → power stage → DC motor (or stepper) → friction → transmission
→ manipulator dynamics. Entry point: :func:`simulate_drives`; schema: ``docs/drives.md``.
"""

from irlc.runtime.drives.params import DriveParamError, DriveParams, drive_params
from irlc.runtime.drives.result import (
    AxisSummary,
    DriveRun,
    deviation_percent,
    report_axes,
    trace_columns,
)
from irlc.runtime.drives.simulate import LEVELS, DriveInputError, simulate_drives
from irlc.runtime.drives.stepsize import StepSizeError, StepSizeWarning

__all__ = [
    "LEVELS",
    "AxisSummary",
    "DriveInputError",
    "DriveParamError",
    "DriveParams",
    "DriveRun",
    "StepSizeError",
    "StepSizeWarning",
    "deviation_percent",
    "drive_params",
    "report_axes",
    "simulate_drives",
    "trace_columns",
]
