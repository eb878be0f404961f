"""A cell's motion of several units in lock-step: group moves and master–slave motion.

``MOVE holder LIN h1 AND welder PTP w1;``: the parts start together and end together, as
ABB's MultiMove synchronized moves do. Each part is planned by its own controller as if
alone (:meth:`SimulatedController.prepare`, ``plan_state``, the pre-interpolator); the
slowest part — the most IPO cycles ``N`` — sets the group's duration, and every other part
is planned again with ``WITH TIME := N·Δt`` (its profile stretched: the same path at a
lower speed, every segment in proportion to its own shortest time). A part that does not
move (already at its target) holds. Then the parts run cycle by cycle in lock-step: cycle
``c`` of every part, then ``c + 1`` … (:meth:`CycleRunner.run` one cycle at a time), so that
the clearance between the robots and each robot's inverse transformation see the others
where they are (:mod:`irlc.runtime.control.cell`). Approximate positioning does not span a
group move: each part ends with an exact stop (the report says so).

A holder moving inside ``COOPERATE`` is a group of its own motion and a *follower*: the
worker's inverse transformation tracking :class:`~irlc.runtime.control.cooperation.
FollowPath` for the holder's ``N`` cycles, stepped right after the holder's.

Each part logs its span in its own controller's statement log (the robot's statements);
the group's row of the cell's table (:class:`GroupStatement`) says per robot how long its
part alone would have taken and which part set the time.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field

from irlc.runtime.commands import ModalOptions, MotionCommand, Settings
from irlc.runtime.control.executor import PreparedMotion, SimulatedController
from irlc.runtime.control.segment_run import SegmentRun
from irlc.runtime.errors import RunFailure
from irlc.runtime.model import spatial
from irlc.runtime.outputs.cycle_time import KIND_WORDS, motion_limit
from irlc.runtime.plan.interpolator import Segment
from irlc.runtime.plan.preinterp import PlanState
from irlc.runtime.plan.profiles import Trapezoid


@dataclass
class Part:
    """One unit's share of a lock-step motion: the ``robots`` it moves, the robot the
    program named (``name``), the ``controller`` whose cycles run it, its command (a
    follower has none: it tracks ``follows``, the part of the holder it follows)."""

    robots: tuple[int, ...]
    name: str
    controller: SimulatedController
    unit: object
    cmd: MotionCommand
    settings: Settings
    options: ModalOptions
    follows: Part | None = None
    prepared: PreparedMotion | None = None
    plan: PlanState | None = None
    segments: list[Segment] = field(default_factory=list)
    own_cycles: int = 0  # the cycles of the part planned alone

    @property
    def who(self) -> str:
        """Whose motion this is, in a failure's message: ``robot welder``; a cooperating
        pair's ``welder in holder``; a follower is its robot."""
        name = getattr(self.unit, "name", self.name)
        return f"robot {self.name}" if len(self.robots) == 1 or self.follows else name

    @contextmanager
    def failures(self) -> Iterator[None]:
        """A :class:`RunFailure` inside names this part (:meth:`RunFailure.of_robot`)."""
        try:
            yield
        except RunFailure as failure:
            raise failure.of_robot(self.who) from None

    @property
    def kind(self) -> str:
        return "follows" if self.follows is not None else KIND_WORDS.get(self.cmd.kind, "MOVE")


@dataclass(frozen=True)
class GroupStatement:
    """A group move's row of the cell's cycle-time table: its span and, per robot, the
    time its part alone takes (s), what set it, and whether it set the group's time."""

    line: int
    kind: str
    start: float
    end: float
    stop: str
    limit: str
    override: float | None
    call: tuple[str, int] | None
    robots: dict[str, dict]


class GroupMove:
    """The lock-step run of ``parts`` (module doc); ``cell`` keeps the robots' samples in
    step (:meth:`~irlc.runtime.control.cell.CellController.recorded`)."""

    def __init__(self, cell, parts: list[Part]):
        self.cell = cell
        self.parts = parts
        self.statement: GroupStatement | None = None  # the row, also of a failed run

    def run(self) -> None:
        cell, parts = self.cell, self.parts
        leaders = [p for p in parts if p.follows is None]
        t0, stop, n, dt = cell.time, "failed", 0, 0.0
        try:
            for p in leaders:
                with p.failures():
                    self._plan(p)
            dts = {p.plan.dt for p in leaders}
            if len(dts) > 1:  # (R_IPO is the cell's: a hand-written .ird only)
                raise RunFailure("the parts of a group move have different IPO cycles")
            dt = dts.pop()
            n = max(p.own_cycles for p in leaders)
            for p in leaders:
                if 0 < p.own_cycles < n:
                    with p.failures():
                        self._stretch(p, n)
            for p in parts:
                if p.follows is not None:
                    with p.failures():
                        self._follow(p, n, dt)
            for p in leaders:
                with p.failures():
                    p.controller.admit(p.cmd, p.segments, p.plan, p.options, p.prepared.solver)
            # a part already at its target holds: its robot's samples are the cell's holds
            cell.moving = tuple(
                r for p in parts if p.follows is not None or p.own_cycles for r in p.robots
            )
            self._cycles(n, dt)
            stop = "exact"
        finally:
            t1 = cell.time
            limits = {
                id(p): motion_limit([s.limiting for s in p.segments], p.cmd.time is not None)
                for p in parts
            }
            slowest = max(leaders, key=lambda p: p.own_cycles)
            for p in parts:
                p.controller.log.add(
                    p.kind, p.cmd.line, t0, t1, stop, limits[id(p)], p.settings.override, p.cmd.call
                )
                if stop == "exact" and p.follows is None:
                    p.controller.note_end(p.cmd, p.segments, p.plan, p.prepared.solver)
            robots = {
                p.name: {
                    "duration_s": round(p.own_cycles * dt, 9) if p.follows is None else None,
                    "limit": limits[id(p)] if p.follows is None else f"follows {p.follows.name}",
                    "set_the_time": p is slowest,
                }
                for p in parts
            }
            first = parts[0].cmd
            kind = " AND ".join(f"{p.name} {p.kind}" for p in parts)
            self.statement = GroupStatement(
                first.line,
                kind,
                t0,
                t1,
                stop,
                limits[id(slowest)],
                parts[0].settings.override,
                first.call,
                robots,
            )

    def _plan(self, p: Part) -> None:
        """The part planned alone, from where its robot stands."""
        ctl = p.controller
        p.prepared = ctl.prepare(p.cmd, p.settings, p.options)
        p.plan = ctl.plan_state(p.settings, p.prepared.solver, p.prepared.values)
        p.segments = ctl.pre.plan(p.cmd, p.settings, p.options, p.plan)
        p.own_cycles = sum(s.cycles for s in p.segments)

    def _stretch(self, p: Part, n: int) -> None:
        """The part planned again to take ``n`` cycles (``WITH TIME := n·Δt``; the
        profile is rounded up to whole cycles, so a hair less is asked when ``n·Δt``
        rounds up to one more)."""
        ctl, dt = p.controller, p.plan.dt
        for time in (n * dt, (n - 1e-6) * dt):
            plan = dataclasses.replace(p.plan, motion=dataclasses.replace(p.plan.motion, time=time))
            segments = ctl.pre.plan(p.cmd, p.settings, p.options, plan)
            if sum(s.cycles for s in segments) == n:
                p.plan, p.segments = plan, segments
                return
        raise RunFailure(f"the group move's part of robot {p.name} cannot take {n} cycles")

    def _follow(self, p: Part, n: int, dt: float) -> None:
        """The follower's one segment: its TCP held in the holder's tool frame."""
        from irlc.runtime.control.cooperation import FollowPath

        ctl, lead = p.controller, p.follows
        p.prepared = ctl.prepare(p.cmd, p.settings, p.options)
        holder_kin = lead.prepared.solver.kin
        holder_state = lead.controller.state
        grip = spatial.inverse(holder_kin.tcp(holder_state.q)) @ p.prepared.solver.kin.tcp(
            ctl.state.q
        )
        limits = ctl.pre.limits((None, None, None), p.options, p.cmd.line)
        path = FollowPath(holder_kin, holder_state, grip)
        p.segments = [Segment("follow", p.cmd.line, path, Trapezoid(n * dt, 0.0, 0.0), n, limits)]
        p.plan = ctl.plan_state(p.settings, p.prepared.solver, p.prepared.values)

    def _cycles(self, n: int, dt: float) -> None:
        """``n`` cycles, each part's cycle ``c`` before any part's ``c + 1`` (a follower
        after the holder it follows)."""
        steps = []
        for p in self.parts:
            with p.failures():
                runs = p.controller.segment_runs(p.segments, p.prepared.solver, dt, p.options)
            steps.append((p, p.controller.cycles, _cycle_steps(runs)))
        running = None  # the part whose cycle runs: a failure names it (one try in all)
        try:
            for _ in range(n):
                for part, cycles, it in steps:
                    step = next(it, None)
                    if step is not None:
                        running = part
                        cycles.run(*step)
        except RunFailure as failure:
            raise (failure if running is None else failure.of_robot(running.who)) from None


def _cycle_steps(runs: list[SegmentRun]) -> Iterator[tuple[SegmentRun, int]]:
    """``(run, k)`` for every cycle of the runs in order."""
    for run in runs:
        for k in range(1, run.seg.cycles + 1):
            yield run, k
