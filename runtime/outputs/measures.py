"""The kinetic energy and the velocity ratio of a run's motion: the trace's
``kinetic_energy_j`` and ``mvr`` columns and the report's ``kinetic_energy`` and ``mvr``.

For every sample of a :class:`~irlc.runtime.outputs.samples.Motion` (the IPO samples, the
actual motion with drives, or a drive run's steps), from its joints ``θ_k``, its joint
speeds ``θ̇_k`` (the backward differences every output uses: the mean speed over the
sample's interval, as the criteria of ``R_CRITERION`` use it) and its TCP:

* ``kinetic_energy_j``: the links' kinetic energy ``½ θ̇ᵀ M(θ) θ̇`` (J), from the robot
  file's ``[[inertials]]`` (:class:`~irlc.runtime.model.link_velocities.LinkVelocities`;
  motor rotor inertia not included). A robot whose inertials cannot give it
  (:attr:`RobotModel.missing_inertia`) has no such column and ``kinetic_energy: null``;
* ``mvr``: the manipulator velocity ratio ``‖J θ̇‖/‖θ̇‖`` on the controlled task rows, SI
  (m and rad, unweighted: :func:`~irlc.runtime.ik.mvr.velocity_ratio`), 0 where the
  joints stand still (every ``|θ̇_j| < 1e-6`` rad/s or m/s: no motion, no ratio).

The report (:class:`MeasureTally`, over pieces of samples): the largest kinetic energy
and when, its integral over the run ``Σ_k E_k (t_k − t_{k−1})`` (J·s; ``E_k`` belongs to
the interval it is the mean speed of), and the smallest and largest ``mvr`` over the
samples whose joints move, and when.
"""

from __future__ import annotations

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime.ik.mvr import velocity_ratio
from irlc.runtime.model.chain import task_rows_for
from irlc.runtime.model.link_velocities import LinkVelocities
from irlc.runtime.outputs.samples import Motion

STILL = 1e-6  # rad/s (m/s): joints slower than this stand still (no velocity ratio)


class MotionMeasures:
    """The two measures of one robot's motion (module doc)."""

    def __init__(self, model: RobotModel):
        self.links = LinkVelocities(model)
        self.energy = model.missing_inertia is None
        self.rows = list(task_rows_for(model))
        self._last: tuple[Motion, tuple] | None = None  # the report's piece, for the trace

    def of(self, motion: Motion) -> tuple[np.ndarray | None, np.ndarray]:
        """``(E, mvr)`` per sample (``E`` None without inertials); the last motion's are
        kept, so the report and the trace of a run in memory compute them once."""
        if self._last is not None and self._last[0] is motion:
            return self._last[1]
        out = self._of(motion)
        self._last = (motion, out)
        return out

    def _of(self, motion: Motion) -> tuple[np.ndarray | None, np.ndarray]:
        if not len(motion.times):
            return (np.zeros(0) if self.energy else None), np.zeros(0)
        energy, twist = self.links.energy_and_twist(motion.q, motion.speed, motion.tcp)
        ratio = velocity_ratio(twist[:, self.rows], motion.speed)
        ratio[np.abs(motion.speed).max(axis=1) < STILL] = 0.0
        return (energy if self.energy else None), ratio

    def table(self, motion: Motion) -> np.ndarray:
        """The trace's columns of ``motion`` (:attr:`columns`), ``(k, 1 | 2)``."""
        energy, ratio = self.of(motion)
        return np.column_stack([energy, ratio] if energy is not None else [ratio])


class MeasureTally:
    """The report's ``kinetic_energy`` and ``mvr`` over consecutive pieces of a motion."""

    def __init__(self, measures: MotionMeasures):
        self.measures = measures
        self.e_max, self.e_at, self.integral = 0.0, 0.0, 0.0
        self.low = self.high = None  # (mvr, time)
        self._last_time: float | None = None

    def add(self, motion: Motion) -> None:
        times = motion.times
        if not len(times):
            return
        energy, ratio = self.measures.of(motion)
        if energy is not None:
            start = times[0] if self._last_time is None else self._last_time
            dt = np.diff(np.r_[start, times])
            self.integral += float(np.dot(energy, dt))
            i = int(np.argmax(energy))
            if energy[i] > self.e_max:
                self.e_max, self.e_at = float(energy[i]), float(times[i])
        self._last_time = float(times[-1])
        moving = np.flatnonzero(np.abs(motion.speed).max(axis=1) >= STILL)
        if moving.size:
            lo, hi = moving[np.argmin(ratio[moving])], moving[np.argmax(ratio[moving])]
            if self.low is None or ratio[lo] < self.low[0]:
                self.low = (float(ratio[lo]), float(times[lo]))
            if self.high is None or ratio[hi] > self.high[0]:
                self.high = (float(ratio[hi]), float(times[hi]))

    def report(self, rnd) -> dict:
        """``{"kinetic_energy": …, "mvr": …}`` (``rnd``: the report's rounding)."""
        energy = None
        if self.measures.energy:
            energy = {
                "max_j": rnd(self.e_max),
                "max_at_time_s": rnd(self.e_at),
                "integral_j_s": rnd(self.integral),
            }
        ratio = None
        if self.low is not None and self.high is not None:
            ratio = {
                "min": rnd(self.low[0]),
                "min_at_time_s": rnd(self.low[1]),
                "max": rnd(self.high[0]),
                "max_at_time_s": rnd(self.high[1]),
            }
        return {"kinetic_energy": energy, "mvr": ratio if ratio else None}
