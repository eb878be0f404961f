"""A robot's own links: their smallest distance over a run, for the report of a program of one
robot (``self_clearance``, docs/interfaces.md).

The watched pairs are those of :mod:`irlc.runtime.model.clearance` (parts on links at least
two apart that are apart at the robot's home). Measured after the run on the samples the
report shows (with drives: the actual joints): the forward kinematics of all samples and
the distances of all their pairs batched (``Kinematics.link_frames_many``). It is reported,
not judged: a program of one robot keeps the verdict it had before cells
(:mod:`irlc.runtime.control.clearance_rule`); ``R_CLEARANCE`` > 0 judges the links during
the run.
"""

from __future__ import annotations

import numpy as np
from irlc.runtime import units
from irlc.runtime.model.clearance import PartSet, RobotParts, segment_distances
from irlc.runtime.model.kinematics import Kinematics

CHUNK = 2048  # samples measured at once (≈ 100 pairs each: a few MB of temporaries)


class SelfClearanceTally:
    """The least distance between the watched pairs of one robot's links over pieces of a
    run's samples (module doc), with the first sample at it."""

    def __init__(self, model):
        self.kin = Kinematics(model)
        self.parts = PartSet([RobotParts("", self.kin)])
        self.best: tuple[float, float, int, int, int] | None = None  # d, t, line, links

    def add(self, motion) -> None:
        """One piece of a :class:`~irlc.runtime.outputs.samples.Motion` (measured
        :data:`CHUNK` samples at a time: bounded memory on a long run)."""
        for start in range(0, len(motion.times), CHUNK):
            self._add(motion, slice(start, start + CHUNK))

    def _add(self, motion, rows: slice) -> None:
        parts = self.parts
        qs = motion.q[rows]
        n = len(qs)
        if not len(parts) or not n:
            return
        robot = parts.robots[0]
        a, b = robot.segments.world_many(self.kin, self.kin.link_frames_many(qs))
        i, j = parts.i, parts.j
        _, _, p, q = segment_distances(
            a[:, i].reshape(-1, 3), b[:, i].reshape(-1, 3), a[:, j].reshape(-1, 3),
            b[:, j].reshape(-1, 3),
        )  # fmt: skip
        d = np.linalg.norm(p - q, axis=1).reshape(n, -1) - (parts.radius[i] + parts.radius[j])
        k, pair = np.unravel_index(int(np.argmin(d)), d.shape)
        value = float(d[k, pair])
        if self.best is None or value < self.best[0]:
            links = int(parts.link[i[pair]]), int(parts.link[j[pair]])
            times, lines = motion.times[rows], motion.lines[rows]
            self.best = (value, float(times[k]), int(lines[k]), *links)

    def report(self, rnd) -> dict | None:
        """``{"min_distance_mm", "at_time_s", "line", "link_a", "link_b"}``; ``None`` for a
        robot without watched pairs."""
        if self.best is None:
            return None
        d, t, line, la, lb = self.best
        return {
            "min_distance_mm": rnd(d / units.MM),
            "at_time_s": rnd(t),
            "line": line,
            "link_a": la,
            "link_b": lb,
        }
