"""A run's samples: the set points it commanded and, with drives, its actual motion.

Every output of a run (the report, the trace, the verdict, the result's arrays) reads one
:class:`Samples` object, in which each quantity is derived **once**:

* ``recorded``: the recorder's IPO samples (SI;
  :class:`~irlc.runtime.outputs.recorder.RecordedRun`),
  the commanded joints ``θ_k`` with their backward differences ``θ̇_k``, ``θ̈_k``;
* ``commanded``: the same as a :class:`Motion`;
* ``actual`` (drives): the drive's actual joints ``θ̂`` at the IPO sample times (interpolated
  once), their TCP, path errors and clearances (one forward kinematics per sample,
  :mod:`irlc.runtime.outputs.actual_motion`) and their backward differences;
* ``steps`` (drives, one trace row per drive step): the same at the drive's own times;
* ``drive``: the drive simulation's result (:class:`~irlc.runtime.drives.DriveRun`).

:attr:`Samples.shown` is what the report's joints, path errors and clearances are (the actual
motion with drives, else the commanded one); :attr:`Samples.traced` the rows of the trace.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from irlc.runtime.outputs.recorder import RecordedRun, finite_differences

if TYPE_CHECKING:
    from irlc.runtime.drives import DriveRun
    from irlc.runtime.outputs.actual_motion import ActualMotion


@dataclass(frozen=True)
class Motion:
    """Joints at ``times`` and what the outputs read of them (SI)."""

    times: np.ndarray  # (m,) s
    lines: np.ndarray  # (m,) program line
    q: np.ndarray  # (m, n)
    speed: np.ndarray  # (m, n) backward differences
    accel: np.ndarray  # (m, n)
    tcp: np.ndarray  # (m, 4, 4) world
    pos_error: np.ndarray  # (m,) m
    ori_error: np.ndarray  # (m,) rad
    on_path: np.ndarray  # (m,) bool: a Cartesian path is commanded
    clearance: dict[str, np.ndarray]  # obstacle → (m,) m
    clearance_link: dict[str, np.ndarray] | None = None  # obstacle → (m,) the nearest link


def commanded(rec: RecordedRun) -> Motion:
    """The recorded set points as a :class:`Motion` (derivatives: the recorder's)."""
    on_path = rec.on_path if rec.on_path is not None else np.zeros(len(rec.times), dtype=bool)
    return Motion(rec.times, rec.lines, rec.q, rec.speed, rec.accel, rec.tcp, rec.pos_error,
                  rec.ori_error, on_path, rec.clearance, rec.clearance_link)  # fmt: skip


def measured(rec: RecordedRun, actual: ActualMotion) -> Motion:
    """The actual motion (:class:`~irlc.runtime.outputs.actual_motion.ActualMotion`) as a
    :class:`Motion`: lines of the IPO sample at or before each time, derivatives once."""
    speed, accel = finite_differences(actual.times, actual.q)
    clearance = {
        name: actual.clearance.get(name, v[actual.sample]) for name, v in rec.clearance.items()
    }
    links = actual.clearance_link or {}
    return Motion(actual.times, rec.lines[actual.sample], actual.q, speed, accel, actual.tcp,
                  actual.pos_error, actual.ori_error, actual.on_path, clearance,
                  links)  # fmt: skip


@dataclass(frozen=True)
class Samples:
    """One run's samples (module doc)."""

    recorded: RecordedRun
    commanded: Motion
    actual: Motion | None = None  # drives: at the IPO sample times
    steps: Motion | None = None  # drives, a trace row per drive step: at the drive's times
    drive: DriveRun | None = None  # the drive simulation (None: ideal)

    @classmethod
    def of(cls, rec: RecordedRun) -> Samples:
        """The set points of a kinematic run (no drives)."""
        return cls(rec, commanded(rec))

    @property
    def shown(self) -> Motion:
        """The report's motion: the actual one with drives, else the commanded one."""
        return self.actual if self.actual is not None else self.commanded

    @property
    def traced(self) -> Motion:
        """The trace's rows: per drive step, per IPO sample (actual), or commanded."""
        if self.steps is not None:
            return self.steps
        return self.shown
