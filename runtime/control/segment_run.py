"""A segment being executed (:class:`SegmentRun`) and an approximated one waiting for the
next motion (:class:`PendingSegment`): the records the controller's parts hand each other.

A :class:`SegmentRun` is made by the controller with everything a cycle of it needs — the
segment, the solver (chain and inverse transformation) of the statement's tool, the IPO
cycle ``Δt`` and the per-cycle options — and keeps its progress (cycles done, started,
its reference path θ⁰(s)); :meth:`SegmentRun.mark` / :meth:`SegmentRun.restore` save and
restore that progress field by field (a blend that is tried and undone).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

from irlc.runtime import units
from irlc.runtime.ik.newton import InverseTransformation
from irlc.runtime.ik.params import CycleOptions
from irlc.runtime.ik.tasks.platform import PlatformTask
from irlc.runtime.model.chain import Chain
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.plan.blending import NO_OVERLAP, Overlap
from irlc.runtime.plan.interpolator import ReferencePath, Segment


@dataclass
class Solver:
    """The chain and inverse transformation of one tool (the controller keeps one per
    ``R_TOOL``, and one with the platform task for motions WITH PLATFORM: ``platform``, the
    task whose target the cycle runner sets)."""

    chain: Chain
    ik: InverseTransformation
    platform: PlatformTask | None = None

    @property
    def kin(self) -> Kinematics:
        return self.chain.kin


@dataclass(frozen=True)
class RunMark:
    """A :class:`SegmentRun`'s progress (what a cycle changes)."""

    done: int
    started: bool
    reference: ReferencePath | None
    cycle_reference: object  # CycleOptions.reference (θ⁰ of the last cycle) or None


class SegmentRun:
    """One segment being executed: its inputs (read-only) and its progress (``done``,
    ``started``, ``reference``; ``cycle_opts.reference`` changes every cycle)."""

    def __init__(
        self,
        seg: Segment,
        solver: Solver,
        dt: float,
        cycle_opts: CycleOptions | None,
        obstacles: frozenset[str],
    ):
        self.seg, self.solver, self.dt = seg, solver, dt
        self.cycle_opts = cycle_opts  # None for a joint (PTP) segment
        self.obstacles = obstacles  # the avoided ones (OBSTACLE … OBSTACLEEND)
        self.done = 0
        self.started = False
        self.reference: ReferencePath | None = None

    def mark(self) -> RunMark:
        opts = self.cycle_opts
        return RunMark(
            self.done, self.started, self.reference, None if opts is None else opts.reference
        )

    def restore(self, mark: RunMark) -> None:
        for f in dataclasses.fields(RunMark):
            if f.name == "cycle_reference":
                if self.cycle_opts is not None:
                    self.cycle_opts.reference = mark.cycle_reference
            else:
                setattr(self, f.name, getattr(mark, f.name))


@dataclass
class PendingSegment:
    """An approximated segment whose last cycles wait for the next motion."""

    run: SegmentRun
    approx: float  # m, requested
    length: float  # m, TCP path length (chord for PTP)
    context: tuple  # what must not change for a blend (options, tool, base, Δt)
    point: int  # 1-based point of its statement
    span: int  # the index of its statement's span in the statement log (cycle_time.py)
    limit: float = 0.0  # m, d = min(APPROX, L_A/2, L_B/2)
    limit_reason: str = ""
    min_speed: float = 0.0  # m/s, lowest TCP speed during the blend
    chain: dict = field(default_factory=dict)  # cycle → joints (Cartesian A before a PTP)
    start_time: float = 0.0  # s, the blend's first sample's predecessor
    handover: float = 0.0  # s, where the next motion starts (cycle_time.py spans)

    def entry(self, overlap: Overlap | None, dt: float, reason: str) -> dict:
        """The point's report entry (mm, s): ``overlap`` None is an exact stop."""
        o = overlap or NO_OVERLAP
        seg = self.run.seg
        return {
            "line": seg.line,
            "point": self.point,
            "kind": seg.kind,
            "approx_mm": _mm(self.approx),
            "limit_mm": _mm(self.limit if overlap is not None else 0.0),
            "used_mm": _mm(o.used),
            "max_distance_mm": _mm(o.max_distance),
            "start_s": round(self.start_time, 9) if o.cycles else None,
            "cycles": o.cycles,
            "saved_s": round(o.cycles * dt, 9),
            "min_speed_mm_s": _mm(self.min_speed) if o.cycles else 0.0,
            "blended": o.cycles > 0,
            "note": reason if (reason or not o.cycles) else "",
        }


def _mm(x: float) -> float:
    return round(x / units.MM, 6) + 0.0
