"""The clearance between links of a cell's actual motion: a drive run judged like its set points.

During a cell's run the controller measures and judges the clearance of every sample's
set points (:class:`~irlc.runtime.control.cell.CellController`,
:class:`~irlc.runtime.control.clearance_rule.ClearanceRule`). With ``--drives`` every robot's
drives are simulated afterwards on its own set points (:mod:`irlc.runtime.drives.stage`),
and the drives lag: two robots whose set points stay apart may come together. So after the
drive stage the same watched pairs (:class:`~irlc.runtime.model.clearance.PartSet`: between
robots, and each robot's own pairs as the set-point rule watches them) are measured again
from the robots' **actual** joints at every IPO sample — one batched query per sample, as
for the set points — and judged by the same rule (:meth:`ClearanceRule.judge` with
``actual=True``):

* a penetration fails the run (cause ``clearance``, both robots and links, the depth, the
  time and the line, "the actual motion (simulated drives)"), unless collisions are
  allowed (``--allow-collisions``: then reported, not judged);
* with ``R_CLEARANCE := d`` > 0 (the value in effect at the sample, as the set points had
  it) a pair closer than it keeps (:meth:`PartSet.keep`) by more than
  :data:`~irlc.runtime.control.clearance_rule.KEEP_TOLERANCE` (0.1 mm) fails it. *Decision:*
  ``R_CLEARANCE`` is a distance the program states between physical links, not a bound on
  the solver's numerics (the kinematic path tolerance, which a drive run does not apply to
  servo lag, is one): the actual links must keep it as the set points do, with the same
  tolerance. A program whose drives lag into the margin keeps more (``R_CLEARANCE``) or
  moves slower.

The first failure in time of this rule and of every robot's drive verdict ends the run for
all robots (:mod:`irlc.runtime.cell_run`); the failure is a violation (criterion
``clearance``) of the verdicts of both robots involved. With drives the report's
``clearance`` and the trace's ``clearance_mm`` columns are the actual motion's (this
record); the set points' are under ``ideal`` (:mod:`irlc.runtime.outputs.cell_results`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from irlc.runtime import units
from irlc.runtime.control.clearance_rule import (
    KEEP_TOLERANCE,
    CellClearances,
    ClearanceRule,
    Measured,
)
from irlc.runtime.errors import RunFailure
from irlc.runtime.model.clearance import PartSet
from irlc.runtime.outputs import stop
from irlc.runtime.outputs.samples import Motion


@dataclass
class ActualClearance:
    """The clearance of every sample of the actual motion (:class:`CellClearances`, SI),
    the sample times and lines, and the rule's first failure (``None``: none before the
    kinematic run's own failure)."""

    clearances: CellClearances
    times: np.ndarray
    lines: np.ndarray
    failure: RunFailure | None = None
    criteria: dict = field(default_factory=dict)

    def cut(self, t_end: float) -> None:
        """The samples up to ``t_end`` (the run stopped there); a later failure is gone."""
        k = stop.rows_until(self.times, t_end)
        self.clearances.truncate(k)
        self.times, self.lines = self.times[:k], self.lines[:k]
        if self.failure is not None and self.failure.time_s > t_end + stop.SLACK:
            self.failure = None

    def violation(self) -> dict | None:
        """The failure as a verdict's violation row (criterion ``clearance``)."""
        f = self.failure
        if f is None:
            return None
        d = f.details
        return {
            "criterion": "clearance",
            "line": f.line,
            "time_s": float(f.time_s),
            "value": d["distance_mm"],
            "limit": d["required_mm"],
            "unit": "mm",
            "message": f.message,
            **{key: d[key] for key in ("robot_a", "link_a", "robot_b", "link_b")},
        }


def measure(
    parts: PartSet,
    motions: Sequence[Motion],
    required: Sequence[float],
    allow: bool,
    until: float | None = None,
) -> ActualClearance:
    """The watched pairs of ``parts`` at the robots' actual ``motions`` (one per robot, in
    the part set's order, at the cell's IPO samples; the samples all robots have), judged
    (module doc) with ``required`` the R_CLEARANCE (m) of each set-point sample and
    ``allow`` collisions; failures at or after ``until`` (the kinematic run's own failure)
    do not count."""
    k = min(len(m.times) for m in motions)
    times, lines = motions[0].times[:k], motions[0].lines[:k]
    rule = ClearanceRule(parts, allow)
    record = CellClearances()
    out = ActualClearance(record, times, lines, criteria=_criteria(required[:k]))
    if not len(parts) or not k:
        return out
    ends = [r.segments.world_many(r.kin, r.kin.link_frames_many(m.q[:k]))
            for r, m in zip(parts.robots, motions, strict=True)]  # fmt: skip
    a = np.concatenate([e[0] for e in ends], axis=1)
    b = np.concatenate([e[1] for e in ends], axis=1)
    for i in range(k):
        m = Measured.at(parts, a[i], b[i])
        record.add(m, required[i])
        t = float(times[i])
        if out.failure is None and (until is None or t < until):
            try:
                rule.judge(m, required[i], int(lines[i]), t, actual=True)
            except RunFailure as failure:
                failure.time_s = round(t, 9)
                out.failure = failure
    return out


def _criteria(required: Sequence[float]) -> dict:
    """What judged the actual clearance: the largest R_CLEARANCE (mm; 0: only a collision
    fails) and the tolerance below it (mm)."""
    return {
        "clearance_required_mm": max(required, default=0.0) / units.MM,
        "clearance_tolerance_mm": KEEP_TOLERANCE / units.MM,
    }
