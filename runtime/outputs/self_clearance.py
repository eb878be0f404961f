"""A robot's own links: their smallest distance over a run, for the report of a program of one
robot (``self_clearance``, docs/interfaces.md).

The watched pairs are those of :mod:`irlc.runtime.model.clearance` (parts on links at least
two apart that are apart at the robot's home). Measured after the run on the samples the
report shows (with drives: the actual joints), one forward kinematics per sample and all
pairs of all samples in one batched distance query. It is reported, not judged: a program
of one robot keeps the verdict it had before cells (:mod:`irlc.runtime.control.
clearance_rule`); ``R_CLEARANCE`` > 0 judges the links during the run.
"""

from __future__ import annotations

import numpy as np
from irlc.runtime import units
from irlc.runtime.model.clearance import PartSet, RobotParts, segment_distances
from irlc.runtime.model.kinematics import Kinematics


class SelfClearanceTally:
    """The least distance between the watched pairs of one robot's links over pieces of a
    run's samples (module doc), with the first sample at it."""

    def __init__(self, model):
        self.kin = Kinematics(model)
        self.parts = PartSet([RobotParts("", self.kin)])
        self.best: tuple[float, float, int, int, int] | None = None  # d, t, line, links

    def add(self, motion) -> None:
        """One piece of a :class:`~irlc.runtime.outputs.samples.Motion`."""
        parts, n = self.parts, len(motion.times)
        if not len(parts) or not n:
            return
        robot = parts.robots[0]
        ends = [robot.world(self.kin.link_frames(q)) for q in motion.q]
        a = np.stack([e[0] for e in ends])  # (samples, parts, 3)
        b = np.stack([e[1] for e in ends])
        i, j = parts.i, parts.j
        _, _, p, q = segment_distances(
            a[:, i].reshape(-1, 3), b[:, i].reshape(-1, 3), a[:, j].reshape(-1, 3),
            b[:, j].reshape(-1, 3),
        )  # fmt: skip
        diff = p - q
        d = np.sqrt(np.einsum("ij,ij->i", diff, diff)).reshape(n, -1)
        d -= parts.radius[i] + parts.radius[j]
        k, pair = np.unravel_index(int(np.argmin(d)), d.shape)
        value = float(d[k, pair])
        if self.best is None or value < self.best[0]:
            links = int(parts.link[i[pair]]), int(parts.link[j[pair]])
            self.best = (value, float(motion.times[k]), int(motion.lines[k]), *links)

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
