"""A cell of several robots at run time: the coordinator above the one-robot controllers.

:class:`CellController` implements the interpreter's
:class:`~irlc.runtime.commands.CellController` (the instructions' robot operand). It owns
one *unit* per robot — :class:`RobotUnit`, the robot's own
:class:`~irlc.runtime.control.executor.SimulatedController` (placed in the cell by ``AT``:
its model's base is the placement times the file's base) — and, while ``COOPERATE`` is on, a
:class:`~irlc.runtime.control.cooperation.Cooperation` for the pair. One statement at a
time:

* a motion of one robot is its unit's ``move`` (approximate positioning included); a
  worker's Cartesian motion inside ``COOPERATE`` the pair's; a group move, or a holder's
  motion inside ``COOPERATE`` (the worker follows), a lock-step :class:`~irlc.runtime.
  control.group.GroupMove`;
* ``RECONFIGURATION`` the robot's unit (a cooperating robot: the pair's self-motion with
  the other robot's joints as they are), ``WAIT`` robot 0's unit while the others hold.

**The samples** of a cell are every robot's, on one clock: each robot's controller's
recorder is its *channel*, and after every IPO cycle a unit records
(:class:`UnitObserver`, the cycle runner's observer) the cell brings the channels to the
same sample: the robots that do not move get a *hold* sample (their joints, their TCP with
their current tool, their obstacle clearances), a pair's sample becomes each robot's
(:meth:`Cooperation.emit`); a blend tried and undone drops the samples it had added. Then
the clearance of the sample — the closest watched pair of links, between robots and within
one (:mod:`irlc.runtime.model.clearance`) — is recorded (:class:`CellClearances`) and judged
(:class:`~irlc.runtime.control.clearance_rule.ClearanceRule`: a collision, or a distance
below ``R_CLEARANCE``, fails the run naming both robots and links, the time and the line).

**R_CLEARANCE** (the cell's setting) is kept by every unit's inverse transformation
(:mod:`irlc.runtime.ik.clearance`): its own pairs, and the other robots' links as moving
obstacles (:meth:`CellController.neighbours`: where they are, and — in a group move, for a
robot not yet stepped this cycle — where its last displacement takes it).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime import units, values
from irlc.runtime.commands import ModalOptions, MotionCommand, RobotMotion, Settings
from irlc.runtime.control.budget import RunBudget
from irlc.runtime.control.clearance_rule import CellClearances, ClearanceRule, Measured
from irlc.runtime.control.cooperation import Cooperation
from irlc.runtime.control.executor import ExecutionOptions, SimulatedController
from irlc.runtime.control.group import GroupMove, GroupStatement, Part
from irlc.runtime.errors import RunFailure
from irlc.runtime.ik.clearance import Neighbours
from irlc.runtime.model import spatial
from irlc.runtime.model.clearance import PartSet, RobotParts
from irlc.runtime.model.distance import critical_points
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.model.naming import JointNaming
from irlc.runtime.outputs.cycle_time import StatementSpan
from irlc.runtime.plan.preinterp import base_transform, tool_transform
from irlc.runtime.values import JointTuple, Pose


@dataclass(frozen=True)
class CellMember:
    """A robot of the cell for the run: its name in the program, its model placed in the
    cell (base = ``AT`` · the file's base), its start joints (SI) and its joint naming."""

    name: str
    model: RobotModel
    q0: np.ndarray
    naming: JointNaming
    at: np.ndarray  # 4×4 SI: the placement (AT)


class RobotUnit:
    """A robot moving on its own (module doc): its controller; its recorder is the
    robot's channel."""

    def __init__(self, index: int, member: CellMember, controller: SimulatedController):
        self.index, self.name, self.model = index, member.name, member.model
        self.at = member.at
        self.controller = controller
        self.robots = self.own_channels = (index,)
        self.pairs: list[Cooperation] = []  # every cooperation it was in (their statements)

    @property
    def channel(self):
        return self.controller.recorder

    def last_sample(self) -> int:
        return len(self.controller.recorder) - 1

    def begin(self, cell_samples: int, t: float) -> None:
        """(A robot's own state is kept in step by the cell.)"""

    def emit(self, k: int) -> None:
        """(It recorded its sample itself.)"""


class UnitObserver:
    """A unit's cycle runner's observer: every recorded cycle goes to the cell."""

    def __init__(self, cell: CellController, unit):
        self.cell, self.unit = cell, unit

    def cycle(self, runner) -> None:
        self.cell.recorded(self.unit, runner.state)


@dataclass(frozen=True)
class UnitStatement:
    """A statement one unit ran: the span its statement log holds at ``index`` (read when
    the report is made: a later blend may end it elsewhere)."""

    log: object  # the unit's StatementLog
    index: int
    robots: tuple[str, ...]

    @property
    def span(self) -> StatementSpan:
        return self.log.spans[self.index]


class CellController:
    """Several robots on one clock (module doc)."""

    def __init__(
        self,
        members: Sequence[CellMember],
        *,
        obstacles: dict | None = None,
        options: ExecutionOptions | None = None,
        progress: Callable[[float, int], None] | None = None,
    ):
        self.opts = opts = options or ExecutionOptions()
        self.obstacles = dict(obstacles or {})
        self.budget = RunBudget(opts)
        self.progress = progress
        self.robots: list[RobotUnit] = []
        for k, m in enumerate(members):
            ctl = SimulatedController(
                m.model,
                m.q0,
                obstacles=self.obstacles,
                options=opts,
                progress=progress,
                naming=m.naming,
                budget=self.budget,
            )
            unit = RobotUnit(k, m, ctl)
            self._attach(unit)
            self.robots.append(unit)
        self.parts = PartSet([RobotParts(u.name, Kinematics(u.model)) for u in self.robots])
        self.rule = ClearanceRule(self.parts, opts.allow_collisions)
        self.clearances = CellClearances()
        self.cooperations: dict[int, Cooperation] = {}  # worker → its pair
        self.moving: tuple[int, ...] = ()
        self.required = 0.0  # m: R_CLEARANCE of the statement
        self.required_max = 0.0  # m: the largest R_CLEARANCE of the run
        self.statements: list[UnitStatement | GroupStatement] = []
        self.tools = [np.array(u.model.tool) for u in self.robots]  # each robot's full tool
        self._kins: dict[tuple[int, bytes], Kinematics] = {}
        self._ends: dict[int, tuple[bytes, np.ndarray, np.ndarray]] = {}
        self._held: dict[int, tuple[bytes, bytes, np.ndarray, dict | None]] = {}
        self.measure(0, 0.0, 0, judge=False)  # the start (judged by the run's setup)

    def _attach(self, unit) -> None:
        cycles = unit.controller.cycles
        cycles.observer = UnitObserver(self, unit)
        cycles.neighbours = lambda: self.neighbours(unit)
        cycles.robot_name = unit.name

    # ------------------------------------------------------------------ protocol
    @property
    def time(self) -> float:
        return max(u.controller.state.t for u in self.robots)

    @property
    def samples(self) -> int:
        return len(self.clearances)

    def robot_naming(self, robot: int) -> JointNaming:
        """How messages name robot ``robot``'s joints."""
        return self.robots[robot].controller.naming

    def flush(self, reason: str = "") -> None:
        """Every unit's pending approximated motion ends with an exact stop."""
        for unit in (*self.robots, *self.cooperations.values()):
            self.moving = unit.robots
            try:
                unit.controller.flush(reason)
            finally:
                self.settle()

    def joints(self, robot: int) -> tuple[float, ...]:
        self.flush("a robot's joints are read")
        return self.robots[robot].controller.joints()

    def pose(
        self, settings: Sequence[Settings], options: Sequence[ModalOptions], robot: int
    ) -> Pose:
        self.flush("a robot's pose is read")
        q = self.robots[robot].controller.state.q
        return self._program_pose(robot, q, settings)

    def forward(self, joints: JointTuple, settings, options, robot: int) -> Pose:
        q = self.robots[robot].controller.pre.joints_si(joints)
        return self._program_pose(robot, q, settings)

    def _program_pose(self, robot: int, q: np.ndarray, settings) -> Pose:
        """Robot ``robot``'s TCP at ``q`` in the frame its poses are written in: the cell
        through its ``R_BASE``; a cooperating worker's, the holder's tool frame now."""
        unit = self.robots[robot]
        world = self._kin(robot, tool_transform(unit.model, settings[robot])).tcp(q)
        pair = self.cooperations.get(robot)
        if pair is not None:
            h = pair.holder
            holder = self._kin(h.index, tool_transform(h.model, settings[h.index]))
            world = spatial.inverse(holder.tcp(h.controller.state.q)) @ world
        return values.pose_from_matrix(spatial.inverse(base_transform(settings[robot])) @ world)

    def move_group(self, parts: Sequence[RobotMotion], settings, options) -> None:
        self._begin(settings)
        plan = [self._part(p, settings, options) for p in parts]
        plan += self._followers(plan, settings, options)
        if len(plan) == 1:
            p = plan[0]
            self._single(p, lambda: p.controller.move(p.cmd, p.settings, p.options))
        else:
            self._group(plan)

    def reconfigure(self, target: JointTuple, line: int, settings, options, robot: int) -> None:
        self._begin(settings)
        pair = self._pair_of(robot)
        if pair is None:
            unit = self.robots[robot]
            part = self._robot_part(unit, MotionCommand("PTP", (target,), line), settings, options)
            self._single(
                part,
                lambda: unit.controller.reconfigure(target, line, settings[robot], options[robot]),
            )
            return
        h, w = pair.holder, pair.worker
        now = {u.index: JointTuple("MAIN_JOINT", u.controller.joints()) for u in (h, w)}
        now[robot] = target
        k = pair.joined(now[h.index], now[w.index])
        opts = pair.options(options[h.index], options[w.index])
        part = Part(
            pair.robots,
            self.robots[robot].name,
            pair.controller,
            pair,
            MotionCommand("PTP", (k,), line),
            settings[w.index],
            opts,
        )
        self._single(part, lambda: pair.controller.reconfigure(k, line, settings[w.index], opts))

    def wait(self, seconds: float, line: int, settings, options) -> None:
        self._begin(settings)
        unit = self.robots[0]
        part = self._robot_part(unit, MotionCommand("PTP", (), line), settings, options)
        self._single(part, lambda: unit.controller.wait(seconds, line, settings[0], options[0]))

    def check_switch_on(self, option: str, line: int, settings, options, robot: int) -> None:
        self.flush(f"{option} at line {line}")
        pair = self._pair_of(robot)
        if pair is None:
            self.robots[robot].controller.check_switch_on(
                option, line, settings[robot], options[robot]
            )
            return
        h, w = pair.holder.index, pair.worker.index
        opts = pair.options(options[h], options[w])
        pair.controller.state.q = pair.layout.join(
            pair.holder.controller.state.q, pair.worker.controller.state.q
        )
        pair.controller.check_switch_on(option, line, settings[w], opts)

    def cooperate(
        self, worker: int, holder: int, vertical: bool, line: int, settings, options
    ) -> None:
        self.flush(f"COOPERATE at line {line}")
        for r in (worker, holder):
            if self._pair_of(r) is not None:
                name = self.robots[r].name
                raise RunFailure(
                    f"COOPERATE: robot {name} is already in a cooperation", line, self.time
                )
        w, h = self.robots[worker], self.robots[holder]
        if vertical:
            self._check_vertical(w, settings[worker], line)
        self._pair(w, h, vertical, tool_transform(h.model, settings[holder]))

    def _pair(self, w: RobotUnit, h: RobotUnit, vertical: bool, tool: np.ndarray) -> Cooperation:
        """The cooperation of ``w`` in ``h`` with the holder's full ``tool`` (a new one when
        the holder's R_TOOL changes inside the block: another workpiece frame)."""
        pair = Cooperation(w, h, vertical, tool, obstacles=self.obstacles, options=self.opts,
                           budget=self.budget, progress=self.progress)  # fmt: skip
        self._attach(pair)
        self.cooperations[w.index] = pair
        w.pairs.append(pair)
        h.pairs.append(pair)
        return pair

    def _check_vertical(self, worker: RobotUnit, settings: Settings, line: int) -> None:
        """``WITH VERTICAL`` holds the worker's tool z axis vertical: it must be so when the
        cooperation starts (the two rows keep it, they do not turn the tool there)."""
        kin = self._kin(worker.index, tool_transform(worker.model, settings))
        z = kin.tcp(worker.controller.state.q)[:3, 2]
        tilt = float(np.arccos(min(1.0, abs(float(z[2])))))
        if tilt > self.opts.tol_orientation:
            raise RunFailure(
                f"COOPERATE {worker.name} … WITH VERTICAL: its tool z axis is "
                f"{tilt / units.DEG:.4g} deg from vertical (the tolerance is "
                f"{self.opts.tol_orientation / units.DEG:g} deg); move it vertical first — the "
                "condition holds the axis, it does not turn it there",
                line,
                self.time,
            )

    def end_cooperation(self, worker: int, holder: int, line: int) -> None:
        self.flush(f"COOPERATEEND at line {line}")
        pair = self.cooperations.get(worker)
        if pair is None or pair.holder.index != holder:
            raise RunFailure("COOPERATEEND without its COOPERATE", line, self.time)
        del self.cooperations[worker]

    def log_event(self, kind: str, line: int, **data) -> None:
        event = {"kind": kind, "line": line, "time_s": round(self.time, 9)}
        event.update(data)
        self.robots[0].controller.recorder.events.append(event)

    def restart_cycle_budget(self) -> None:
        self.budget.restart()

    # ------------------------------------------------------------------ statements
    def _begin(self, settings: Sequence[Settings]) -> None:
        """A statement starts: the cell's R_CLEARANCE, each robot's tool."""
        self.required = settings[0].clearance * units.MM
        self.required_max = max(self.required_max, self.required)
        for u in self.robots:
            self.tools[u.index] = tool_transform(u.model, settings[u.index])
            u.controller.cycles.clearance = self.required

    def _pair_of(self, robot: int) -> Cooperation | None:
        for pair in self.cooperations.values():
            if robot in pair.robots:
                return pair
        return None

    def _robot_part(self, unit: RobotUnit, cmd: MotionCommand, settings, options) -> Part:
        return Part(
            unit.robots,
            unit.name,
            unit.controller,
            unit,
            cmd,
            settings[unit.index],
            options[unit.index],
        )

    def _part(self, motion: RobotMotion, settings, options) -> Part:
        """The unit a robot's part runs on: its own; a cooperating worker's Cartesian
        motion (or PTP to a pose) the pair's; a cooperating holder's own, with a follower."""
        r, cmd = motion.robot, motion.command
        pair = self._pair_of(r)
        unit = self.robots[r]
        joints = cmd.kind in ("PTP", "PTPINC") and not any(isinstance(t, Pose) for t in cmd.targets)
        if pair is None or (r == pair.worker.index and joints):
            return self._robot_part(unit, cmd, settings, options)
        h, w = pair.holder.index, pair.worker.index
        if r == w:
            tool = tool_transform(pair.holder.model, settings[h])
            if not np.array_equal(tool, pair.holder_tool):  # the workpiece frame moved
                pair = self._pair(pair.worker, pair.holder, pair.vertical, tool)
            opts = pair.options(options[h], options[w])
            return Part(
                pair.robots, unit.name, pair.controller, pair, pair.command(cmd), settings[w], opts
            )
        return self._robot_part(unit, cmd, settings, options)

    def _followers(self, parts: list[Part], settings, options) -> list[Part]:
        """Each cooperating holder's part followed by its worker (master–slave)."""
        out = []
        moved = {r for p in parts for r in p.robots}
        for p in parts:
            pair = self._pair_of(p.robots[0]) if len(p.robots) == 1 else None
            if pair is None or pair.holder.index != p.robots[0]:
                continue
            w = pair.worker
            if w.index in moved:
                raise RunFailure(
                    f"a group move cannot move both cooperating robots ({w.name} works in "
                    f"{pair.holder.name}): move {w.name} (both follow its path) or "
                    f"{pair.holder.name} ({w.name} follows)",
                    p.cmd.line,
                    self.time,
                )
            cmd = MotionCommand("LIN", (), p.cmd.line, call=p.cmd.call)
            out.append(
                Part(
                    w.robots,
                    w.name,
                    w.controller,
                    w,
                    cmd,
                    settings[w.index],
                    options[w.index],
                    follows=p,
                )
            )
        return out

    def _single(self, part: Part, run: Callable[[], None]) -> None:
        """One unit's statement (``run``), the other units flushed first."""
        unit = part.unit
        for other in (*self.robots, *self.cooperations.values()):
            if other is not unit:
                self.moving = other.robots
                try:
                    other.controller.flush("another robot moves")
                finally:
                    self.settle()
        self.moving = unit.robots
        unit.begin(self.samples, self.time)
        log = unit.controller.log
        before = len(log.spans)
        try:
            with part.failures():
                run()
        finally:
            self.settle()
            self.moving = ()
            if len(log.spans) > before:
                names = tuple(self.robots[r].name for r in unit.robots)
                self.statements.append(UnitStatement(log, len(log.spans) - 1, names))

    def _group(self, parts: list[Part]) -> None:
        """Several parts (or a holder and its follower) in lock-step."""
        self.flush("a group move starts")
        self.moving = tuple(r for p in parts for r in p.robots)
        for p in parts:
            p.unit.begin(self.samples, self.time)
        group = GroupMove(self, parts)
        try:
            group.run()
        finally:
            self.settle()
            self.moving = ()
            if group.statement is not None:
                self.statements.append(group.statement)

    # ------------------------------------------------------------------ samples
    def recorded(self, unit, state) -> None:
        """A unit recorded a cycle (its sample ``k``): the channels brought to ``k``
        (module doc), then — once every moving unit has it — the others' hold samples and
        the sample's clearance, judged."""
        k = unit.last_sample()
        for u in self.robots:  # samples a blend that was undone had added
            mine = u.index in unit.robots and u.index not in unit.own_channels
            if (mine or u.index not in self.moving) and len(u.channel) > k:
                u.channel.truncate(k)
        self.clearances.truncate(k)
        unit.emit(k)
        if any(len(self.robots[r].channel) <= k for r in self.moving):
            return  # a group move: the others' cycle is still to come
        rec = unit.controller.recorder  # the sample's line (a blend's tail keeps its own)
        line = int(rec.rows("lines", len(rec) - 1, len(rec))[0])
        for u in self.robots:
            if u.index not in self.moving:
                self.hold(u, state.t, line)
        self.measure(k, state.t, line)

    def settle(self) -> None:
        """Every channel and the clearances brought to the longest channel (after a
        statement, also one that failed in the middle of a cycle): hold samples, not judged."""
        for pair in self.cooperations.values():
            while pair.last_sample() >= len(pair.worker.channel):
                pair.emit(len(pair.worker.channel))
        longest = max(self.robots, key=lambda u: len(u.channel))
        n = len(longest.channel)
        for j in range(len(self.clearances), n):
            t = float(longest.channel.rows("times", j, j + 1)[0])
            line = int(longest.channel.rows("lines", j, j + 1)[0])
            for u in self.robots:
                if len(u.channel) <= j:
                    self.hold(u, t, line)
            self.measure(j, t, line, judge=False)

    def hold(self, unit: RobotUnit, t: float, line: int) -> None:
        """A sample of a robot standing still (its TCP with its current tool)."""
        st = unit.controller.state
        tool = self.tools[unit.index]
        key, tool_key = st.q.tobytes(), tool.tobytes()
        held = self._held.get(unit.index)
        if held is None or held[0] != key or held[1] != tool_key:
            kin = self._kin(unit.index, tool)
            frames = kin.link_frames(st.q)
            clear = None
            names = unit.channel.obstacle_names
            if names:
                cps = critical_points(kin, frames, tuple(self.obstacles[n] for n in names))
                clear = {cp.name: (cp.distance, cp.link) for cp in cps}
            held = (key, tool_key, kin.tcp_from_frames(frames), clear)
            self._held[unit.index] = held
        unit.channel.add(t, line, st.q, held[2], None, clearances=held[3])
        st.q_prev, st.t, st.line = st.q.copy(), t, line

    def measure(self, k: int, t: float, line: int, judge: bool = True) -> None:
        """The clearance of cell sample ``k`` recorded, and judged (module doc)."""
        ends = [self._ends_at(u, u.channel.rows("q", k, k + 1)[0]) for u in self.robots]
        a = np.concatenate([e[0] for e in ends])
        b = np.concatenate([e[1] for e in ends])
        m = Measured.at(self.parts, a, b)
        self.clearances.add(m, self.required)
        if judge:
            self.rule.judge(m, self.required, line, t)

    def tolerate_collisions(self) -> None:
        """The robots' links that are inside each other, or closer than R_CLEARANCE, now (a
        collision failed the last REPL entry) may come apart, not closer
        (:meth:`ClearanceRule.tolerate`)."""
        ends = [self._ends_at(u, u.controller.state.q) for u in self.robots]
        m = Measured.at(self.parts, *(np.concatenate(e) for e in zip(*ends, strict=True)))
        self.rule.tolerate(m, self.required)

    def start_failure(self, line: int) -> RunFailure | None:
        """The robots' links collide in the start configuration (t = 0, the program's
        first statement), unless collisions are allowed."""
        ends = [self._ends_at(u, u.controller.state.q) for u in self.robots]
        m = Measured.at(self.parts, *(np.concatenate(e) for e in zip(*ends, strict=True)))
        try:
            self.rule.judge(m, 0.0, line, 0.0)
        except RunFailure as failure:
            return failure
        return None

    def _ends_at(self, unit: RobotUnit, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The robot's parts' world ends at ``q`` (the last ones kept: a robot standing)."""
        key = q.tobytes()
        hit = self._ends.get(unit.index)
        if hit is None or hit[0] != key:
            parts = self.parts.robots[unit.index]
            a, b = parts.world(parts.kin.link_frames(q))
            hit = (key, a, b)
            self._ends[unit.index] = hit
        return hit[1], hit[2]

    def _kin(self, robot: int, tool: np.ndarray) -> Kinematics:
        key = (robot, tool.tobytes())
        kin = self._kins.get(key)
        if kin is None:
            kin = self._kins[key] = Kinematics(self.robots[robot].model, tool)
        return kin

    def neighbours(self, unit) -> Neighbours | None:
        """The parts of the robots ``unit`` does not move, for its clearance rows: where
        they are and, for a robot moving in the same group that has not made this cycle's
        step yet, its displacement over the cycle if it repeats its last one."""
        t_now = unit.controller.state.t
        others = [u for u in self.robots if u.index not in unit.robots]
        if not others:
            return None
        a, b, da, db, radius, names, links = [], [], [], [], [], [], []
        for u in others:
            st = u.controller.state
            ea, eb = self._ends_at(u, st.q)
            if u.index in self.moving and st.t <= t_now + 1e-12:
                parts = self.parts.robots[u.index]
                pa, pb = parts.world(parts.kin.link_frames(2.0 * st.q - st.q_prev))
                da.append(pa - ea)
                db.append(pb - eb)
            else:
                da.append(np.zeros_like(ea))
                db.append(np.zeros_like(eb))
            a.append(ea)
            b.append(eb)
            parts = self.parts.robots[u.index]
            radius.append(parts.radius)
            names += [u.name] * parts.size
            links.append(parts.links)
        return Neighbours(
            np.concatenate(a),
            np.concatenate(b),
            np.concatenate(da),
            np.concatenate(db),
            np.concatenate(radius),
            tuple(names),
            np.concatenate(links),
        )
