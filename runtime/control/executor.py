"""The simulated controller: executes motion commands cycle by cycle (kinematic run).

:class:`SimulatedController` implements :class:`~irlc.runtime.commands.Controller`. It
is a small coordinator of parts with explicit interfaces, each its own module:

* :class:`~irlc.runtime.control.state.ControllerState` — the joints, time, cycle count,
  last reference, pending segment …: what a cycle changes (snapshot / restore);
* :class:`~irlc.runtime.control.cycles.CycleRunner` — the IPO cycles of a segment: PTP
  segments set the joints directly (the profile respects the joint limits); Cartesian
  segments (LIN, CIRCLE) and RECONFIGURATION call the inverse transformation with the
  options of the cycle (the active limits, θ⁰ of WITH RECONFIGURATION or CYCLIC, FREEZE,
  the obstacles: every obstacle's clearance is measured, the OBSTACLE … OBSTACLEEND ones
  are avoided); the path deviation of a relaxed cycle is a warning, beyond ``R_PATH_TOL``
  (start value ``tol_position``, 0.05 mm) or ``tol_orientation`` (0.01°) a run failure;
* :class:`~irlc.runtime.control.approximation.ApproximatePositioning` — the blender
  (``APPROX``): pending segments, blends, exact stops, the report's ``approximations``;
* :class:`~irlc.runtime.control.reconfiguration.SelfMotion` — RECONFIGURATION k;
* :class:`~irlc.runtime.control.budget.RunBudget` — the time and cycle budgets;
* :class:`~irlc.runtime.control.statement_log.StatementLog` — the cycle time per statement;
* the solver of each tool: a :class:`~irlc.runtime.model.chain.SerialChain` and its
  :class:`~irlc.runtime.ik.newton.InverseTransformation`
  (:class:`~irlc.runtime.control.segment_run.Solver`), and for motions ``WITH PLATFORM``
  the same chain with the platform task;
* :class:`~irlc.runtime.control.platform.PlatformControl` — ``R_PLATFORM`` (HOLD: a
  FREEZE of the platform's joints), the platform motions' pre-check and record.

The coordinator plans each statement with the pre-interpolator and hands the segments,
as :class:`~irlc.runtime.control.segment_run.SegmentRun` records carrying their own
``Δt`` and cycle options, to the blender. Statements that stop the advance run call
:meth:`SimulatedController.flush`.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime import units, values
from irlc.runtime.commands import (
    WAIT_SAMPLED_CYCLES,
    ModalOptions,
    MotionCommand,
    Settings,
    setting_error,
)
from irlc.runtime.control.approximation import ApproximatePositioning
from irlc.runtime.control.budget import DEFAULT_MAX_CYCLES as DEFAULT_MAX_CYCLES
from irlc.runtime.control.budget import DRIVE_STEPS_PER_CYCLE as DRIVE_STEPS_PER_CYCLE
from irlc.runtime.control.budget import MOTION_MIN_CYCLES as MOTION_MIN_CYCLES
from irlc.runtime.control.budget import RunBudget
from irlc.runtime.control.clearance_rule import OwnClearance
from irlc.runtime.control.collision import CollisionRule
from irlc.runtime.control.cycles import CycleRunner, advance, located
from irlc.runtime.control.platform import PlatformControl, platform_chain
from irlc.runtime.control.reconfiguration import SelfMotion
from irlc.runtime.control.segment_run import SegmentRun, Solver
from irlc.runtime.control.state import ControllerState
from irlc.runtime.control.statement_log import StatementLog
from irlc.runtime.engine_policy import EngineChoice
from irlc.runtime.errors import RunFailure
from irlc.runtime.ik.freeze import FrozenJoints
from irlc.runtime.ik.newton import InverseTransformation
from irlc.runtime.ik.params import IKParams
from irlc.runtime.ik.reach import check_targets
from irlc.runtime.model import spatial
from irlc.runtime.model.chain import Chain, SerialChain
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.model.naming import JointNaming, naming_or_default
from irlc.runtime.model.obstacles import Obstacle
from irlc.runtime.outputs.cycle_time import KIND_WORDS, StatementSpan, motion_limit
from irlc.runtime.outputs.recorder import Recorder
from irlc.runtime.plan.interpolator import JointLine, ReferencePath, Segment
from irlc.runtime.plan.motion_values import MotionValues, motion_values
from irlc.runtime.plan.plan_start import ROUND_OFF, planning_start
from irlc.runtime.plan.preinterp import (
    PlanState,
    PreInterpolator,
    base_transform,
    tool_transform,
)
from irlc.runtime.values import JointTuple, Pose


@dataclass(frozen=True)
class PreparedMotion:
    """A motion statement's checked settings (``values``), the solver of its tool and what
    must not change for a blend into the next one (``context``)."""

    values: MotionValues
    solver: Solver
    context: tuple
    options: ModalOptions  # the statement's options under R_PLATFORM (platform.py)


@dataclass
class ExecutionOptions:
    """Run-time parameters of the controller (SI)."""

    ipo: float | None = None  # overrides R_IPO when set (``--ipo``)
    tol_position: float = 5e-5  # m: a path deviation beyond this fails the run
    tol_orientation: float = 0.01 * units.DEG  # rad
    reconf_settle_s: float = 10.0  # s after the reference arrived before giving up
    max_time_s: float = 86_400.0  # simulated-time budget of a run (``--max-time``): 24 h
    max_cycles: int = DEFAULT_MAX_CYCLES  # IPO cycles a run may simulate (``--max-cycles``)
    drive_step_s: float | None = None  # with drives: their step h (s), for the cycle budget
    progress_every: int = 200  # cycles between progress callbacks
    manipulability_every: int = 10  # cycles between manipulability samples (an SVD each)
    ik: IKParams | None = None
    allow_collisions: bool = False  # a penetration of an obstacle does not fail (collision.py)
    path_tolerance_stated: bool = False  # --path-tolerance was given (judges a drive run)
    orientation_tolerance_stated: bool = False  # --orientation-tolerance was given
    engine: EngineChoice | None = None  # when the kernels take over (engine_policy.py)


class SimulatedController:
    """Kinematic simulation of one robot (``drives = ideal``); records every IPO cycle.
    A coordinator of parts (module docstring)."""

    def __init__(
        self,
        model: RobotModel,
        start_q: np.ndarray,
        *,
        obstacles: dict[str, Obstacle] | None = None,
        options: ExecutionOptions | None = None,
        progress: Callable[[float, int], None] | None = None,
        naming: JointNaming | None = None,
        chain_of: Callable[[np.ndarray], Chain] | None = None,
        budget: RunBudget | None = None,
    ):
        """``chain_of(tool)``: the chain of a tool (default: the robot's
        :class:`~irlc.runtime.model.chain.SerialChain`; a cooperating pair's chain, the
        cell's); ``budget``: the run's budgets when several controllers share them (a
        cell)."""
        self.model = model
        self._chain_of = chain_of
        self._naming = naming_or_default(naming, model)  # joints in failure messages
        self.opts = opts = options or ExecutionOptions()
        self.ik_params = opts.ik or IKParams.for_robot(model)
        self.obstacles = dict(obstacles or {})
        self.recorder = Recorder(model.n, tuple(self.obstacles), self.ik_params.task_rows)
        self.recorder.tol_position = opts.tol_position
        self.pre = PreInterpolator(model, self.ik_params.task_rows, opts.tol_orientation)
        self.pre.max_duration = opts.max_time_s
        self.pre.naming = self._naming
        self.scale = units.joint_scale(model.joint_kinds)
        self.state = ControllerState.at(start_q)
        self.budget = budget or RunBudget(opts)
        self.log = StatementLog()
        self.cycles = CycleRunner(
            self.state,
            self.recorder,
            self.pre,
            self.obstacles,
            tol_orientation=opts.tol_orientation,
            progress=progress,
            progress_every=opts.progress_every,
            manipulability_every=opts.manipulability_every,
            collisions=CollisionRule(opts.allow_collisions),
        )
        self.own_clearance = OwnClearance(opts.allow_collisions)  # R_CLEARANCE, one robot
        self.cycles.observer = self.own_clearance
        self.blender = ApproximatePositioning(self.state, self.recorder, self.cycles, self.log)
        self.self_motion = SelfMotion(
            self.pre,
            self.cycles,
            self.budget,
            self.log,
            eps_conf=self.ik_params.eps_conf,
            settle_s=opts.reconf_settle_s,
        )
        self.platform = PlatformControl(model)  # R_PLATFORM, WITH PLATFORM (platform.py)
        self.cycles.platform_record = self.platform.record
        self._solvers: dict[bytes, Solver] = {}
        self.dt_used = opts.ipo if opts.ipo is not None else Settings().ipo
        self._start_tool = b""  # the tool (bytes) the start sample was stamped with
        self._programmed_end: tuple[bytes, np.ndarray] | None = None  # (tool, world TCP)
        self._record_initial()
        self.chain: Chain = self._solver(Settings()).chain  # the last motion's (prepare)

    # ------------------------------------------------------------------ protocol
    @property
    def collisions(self) -> CollisionRule:
        """The collision rule the cycles apply (run setup: the start configuration; the
        REPL: an obstacle the arm may back out of)."""
        return self.cycles.collisions

    @property
    def naming(self) -> JointNaming:
        """How failure messages name joints (the program's names; the REPL may set it
        when a session's MAIN_JOINT names change): passed to the pre-interpolator and
        every solver."""
        return self._naming

    @naming.setter
    def naming(self, value: JointNaming) -> None:
        self._naming = self.pre.naming = value
        for solver in self._solvers.values():
            solver.ik.naming = value

    @property
    def time(self) -> float:
        return self.state.t

    @property
    def q(self) -> np.ndarray:
        """The joints now (SI)."""
        return self.state.q

    @property
    def blends(self) -> list[dict]:
        """The report's ``approximations``: one entry per approximated point."""
        return self.blender.blends

    @property
    def statements(self) -> list[StatementSpan]:
        """The cycle time per statement (cycle_time.py)."""
        return self.log.spans

    def flush(self, reason: str = "") -> None:
        """Ends a pending approximated motion with an exact stop at its point (the advance
        run stops: :meth:`ApproximatePositioning.flush`)."""
        self.blender.flush(reason)

    def joints(self) -> tuple[float, ...]:
        self.flush("the robot's joints are read (CYCLICSTART, JOINTLIMIT, FREEZESTART)")
        return tuple(float(v) for v in self.state.q / self.scale)

    def pose(self, settings: Settings) -> Pose:
        self.flush("the robot's pose is read")
        return self._program_pose(self._tcp(self.state.q, settings), settings)

    def forward(self, joints: JointTuple, settings: Settings) -> Pose:
        q = self.pre.joints_si(joints)
        return self._program_pose(self._tcp(q, settings), settings)

    def move(self, cmd: MotionCommand, settings: Settings, options: ModalOptions) -> None:
        st = self.state
        motion = self.prepare(cmd, settings, options)
        options, solver, dt = motion.options, motion.solver, motion.values.ipo
        moves_platform = cmd.platform_target is not None
        # a motion WITH PLATFORM is not blended: exact stops (platform.py)
        approx = 0.0 if moves_platform else motion.values.approx * units.MM
        self.blender.before_move(cmd, motion.context)
        plan = self.plan_state(settings, solver, motion.values)
        t0, segments, stop = st.t, [], "failed"
        try:
            segments = self.pre.plan(cmd, settings, options, plan)
            self.admit(cmd, segments, plan, options, solver)
            if moves_platform:
                self.platform.record.begin(cmd, self.platform.platform, st.q)
            runs = self.segment_runs(
                segments, solver, dt, options, motion.values.criterion, settings
            )
            for point, run in enumerate(runs, 1):
                self.blender.feed(run, approx, motion.context, point)
            self.note_end(cmd, segments, plan, solver)
            own = st.pending is not None and st.pending.span == len(self.log.spans)
            stop = "approximated" if own else "exact"  # (a zero-length move blends nothing)
        except RunFailure as exc:  # the platform held by R_PLATFORM: say so (platform.py)
            held = motion.values.platform == "HOLD" and not moves_platform
            raise self.platform.explained(exc, held, self.naming) from None
        finally:
            limit = motion_limit([s.limiting for s in segments], cmd.time is not None)
            kind = KIND_WORDS.get(cmd.kind, cmd.kind)
            if self.log.spans:  # after a blend the span starts where the one before ends
                t0 = max(t0, self.log.spans[-1].end)
            self.log.add(kind, cmd.line, t0, st.t, stop, limit, settings.override, cmd.call)

    # the steps of a motion statement, public for a cell's group moves (control/cell.py)
    def prepare(
        self, cmd: MotionCommand, settings: Settings, options: ModalOptions
    ) -> PreparedMotion:
        """A motion's settings checked once (:func:`motion_values`), its solver (the
        settings' tool), the path tolerance and clearance of its cycles."""
        st = self.state
        st.line = cmd.line
        self.recorder.tol_position = settings.path_tol * units.MM  # R_PATH_TOL
        solver = self._solver(settings)
        motion = motion_values(cmd, settings, self.opts.ipo, st.t)  # each value checked once
        self.dt_used = motion.ipo
        self.cycles.clearance = motion.clearance * units.MM  # R_CLEARANCE
        self.chain = self.own_clearance.chain = solver.chain
        options = self._platform_options(cmd, motion, options)
        # what must not change between two motions for a blend
        context = (options, solver.kin.tool.tobytes(), base_transform(settings).tobytes(),
                   motion.ipo)  # fmt: skip
        return PreparedMotion(motion, solver, context, options)

    def admit(self, cmd: MotionCommand, segments: list[Segment], plan: PlanState,
              options: ModalOptions, solver: Solver) -> None:  # fmt: skip
        """Before anything moves: the time and cycle budgets, and the reachability of the
        end (and via) points of the Cartesian segments."""
        st = self.state
        cycles = sum(seg.cycles for seg in segments)
        self.budget.check_time(st.t, cycles * plan.dt, cmd.line, "the motion")
        self.budget.grant(cycles, cycles * plan.dt, st.t, cmd.line, "the motion", MOTION_MIN_CYCLES)
        cartesian = [seg for seg in segments if not seg.is_joint]
        if cartesian:  # reachability of the end (and via) points, before anything moves
            frozen = self.pre.frozen_si(options)
            reach = self.cycles.reach(cartesian[0].limits[0], frozen, solver)
            what = KIND_WORDS.get(cmd.kind, cmd.kind)
            if cmd.platform_target is not None:
                self.platform.check_targets(reach, cartesian, st.q, cmd.line, st.t, what)
            else:
                check_targets(reach, cartesian, st.q, cmd.line, st.t, what)

    def segment_runs(
        self,
        segments: list[Segment],
        solver: Solver,
        dt: float,
        options: ModalOptions,
        criterion: str = "DISTANCE",
        settings: Settings | None = None,
    ) -> list[SegmentRun]:
        """The segments as runs with their cycle options (Cartesian ones: under the
        statement's ``R_CRITERION``); a segment that moves the platform gets the solver
        with the platform task (of ``settings``' tool)."""
        avoided, cycles = frozenset(options.obstacles), self.cycles
        runs = []
        for seg in segments:
            opts = None if seg.is_joint else cycles.options_for(seg, options, criterion)
            own = solver
            if seg.platform is not None and settings is not None:
                own = self._platform_solver(settings)
            runs.append(SegmentRun(seg, own, dt, opts, avoided))
        return runs

    def note_end(self, cmd: MotionCommand, segments: list[Segment], plan, solver: Solver) -> None:
        """The next motion is planned from this motion's programmed end (plan_start.py)."""
        if segments:
            end = self._programmed_point(cmd, segments[-1], plan)
            self._programmed_end = None if end is None else (solver.kin.tool.tobytes(), end)

    def _programmed_point(self, cmd: MotionCommand, last: Segment, plan) -> np.ndarray | None:
        """The world TCP pose the motion's last point was programmed at: a Cartesian
        segment's end; a PTP to a POSE, that pose (its joints come from the pose solver,
        with its residual); ``None`` for a PTP to joints (the TCP is exact there)."""
        if not last.is_joint:
            return last.path.at(1.0).copy()
        target = cmd.targets[-1] if cmd.kind == "PTP" and cmd.targets else None
        if isinstance(target, Pose):
            return self.pre.world(target, plan, cmd.line)
        return None

    def wait(self, seconds: float, line: int, settings: Settings, options: ModalOptions) -> None:
        st = self.state
        if not (seconds >= 0.0 and math.isfinite(seconds)):
            raise RunFailure(f"WAIT needs a finite time ≥ 0 s, got {seconds!r}", line, st.t)
        self.flush(f"WAIT at line {line}")
        st.line = line
        dt = self._dt(settings)
        self.budget.check_time(st.t, seconds, line, "the WAIT")
        n = round(seconds / dt)
        if abs(n * dt - seconds) > 1e-9 * max(1.0, seconds):
            n = math.ceil(seconds / dt)
        if n == 0:
            return
        sampled = min(n, WAIT_SAMPLED_CYCLES)
        # the cycles recorded
        self.budget.grant(sampled + (n > sampled), n * dt, st.t, line, "the WAIT")
        st.q_prev = st.q.copy()  # standing still: q, and so the sample, do not change
        tcp = self._solver(settings).kin.tcp(st.q)
        rec = self.recorder
        t0 = st.t
        for _ in range(sampled):
            st.t = advance(st.t, dt)
            rec.add(st.t, line, st.q, tcp, None)
            self.cycles.tick()
        if n > sampled:  # the rest of a long WAIT: its last cycle stands for all of them
            st.t = round(t0 + n * dt, 9)
            rec.add(st.t, line, st.q, tcp, None)
            st.cycles += n - sampled - 1
            self.cycles.tick()
        self.log.add("WAIT", line, t0, st.t, None, "")

    def reconfigure(
        self, target: JointTuple, line: int, settings: Settings, options: ModalOptions
    ) -> None:
        """RECONFIGURATION k (:class:`~irlc.runtime.control.reconfiguration.SelfMotion`)."""
        self.flush(f"RECONFIGURATION at line {line}")
        motion = self.prepare(MotionCommand("PTP", (target,), line), settings, options)
        plan = self.plan_state(settings, motion.solver, motion.values)
        self.self_motion.reconfigure(target, line, motion.options, motion.solver, plan)

    def check_switch_on(
        self, option: str, line: int, settings: Settings, options: ModalOptions
    ) -> None:
        """Checks when OBSTACLE or FREEZESTART is switched on, so that the failure points
        at that statement (as JOINTLIMIT's "excludes the current state" does), not at the
        next motion: an avoided obstacle the arm is already inside cannot be avoided, and
        fewer free joints than task rows cannot follow any path."""
        self.flush(f"{option} at line {line}")
        if option == "OBSTACLE":
            self._check_not_inside(options.obstacles, line, settings)
        elif option == "FREEZE":
            frozen = FrozenJoints(self.model.n, self.pre.frozen_si(options))
            try:
                frozen.check_task(self.model, len(self.ik_params.task_rows), self.naming)
            except RunFailure as exc:
                raise located(exc, line, self.state.t) from None

    def _check_not_inside(self, names: tuple[str, ...], line: int, settings: Settings) -> None:
        solver, q = self._solver(settings), self.state.q
        clearances = self.cycles.clearances(solver, q, solver.kin.link_frames(q)) or {}
        for name in names:
            distance, link = clearances.get(name, (0.0, 0))
            if distance < 0.0:
                raise RunFailure(
                    f"OBSTACLE {name}: the arm is already inside it ({-distance / units.MM:.4g}"
                    f" mm deep, link {link}); it cannot be avoided",
                    line,
                    self.state.t,
                    f"obstacle {name}",
                    cause="obstacle",
                )

    def log_event(self, kind: str, line: int, **data) -> None:
        event = {"kind": kind, "line": line, "time_s": round(self.state.t, 9)}
        event.update(data)
        self.recorder.events.append(event)

    def restart_cycle_budget(self) -> None:
        """Count the cycle budget from here (the REPL: each entry has the whole budget)."""
        self.budget.restart()

    # ------------------------------------------------------------------ start sample
    def _record_initial(self) -> None:
        """The sample at t = 0 (with the clearances of the start configuration), with the
        default tool; :meth:`_solver` re-stamps it with the program's tool while it is the
        only sample (``R_TOOL`` set before the first motion holds from t = 0)."""
        self._stamp_start(self._solver(Settings()))

    def _stamp_start(self, solver: Solver) -> None:
        q = self.state.q
        frames = solver.kin.link_frames(q)
        tcp = solver.kin.tcp_from_frames(frames)
        clear = self.cycles.clearances(solver, q, frames)
        if len(self.recorder) == 0:
            self.recorder.add(self.state.t, 0, q, tcp, None, clearances=clear)
        else:
            self.recorder.restamp_first(tcp, clear)
        self._start_tool = solver.kin.tool.tobytes()

    # ------------------------------------------------------------------ helpers
    def _dt(self, settings: Settings) -> float:
        dt = self.opts.ipo if self.opts.ipo is not None else settings.ipo
        error = setting_error("ipo", dt)
        if error is not None:
            raise RunFailure(f"the IPO cycle {dt!r} s: {error}", self.state.line, self.state.t)
        self.dt_used = float(dt)
        return self.dt_used

    def _solver(self, settings: Settings) -> Solver:
        """The chain and inverse transformation of the settings' tool (one per tool); from
        the engine policy's switch on (engine_policy.py) the compiled cycle's."""
        switch = self.opts.engine.ik_from if self.opts.engine is not None else None
        if switch is not None and self.recorder.ik_cycles >= switch and not self.ik_params.accel:
            self.ik_params = dataclasses.replace(self.ik_params, accel=True)  # engine_policy
            self._solvers.clear()  # the next motion's solver runs the compiled cycle
        tool = tool_transform(self.model, settings)
        key = tool.tobytes()
        solver = self._solvers.get(key)
        if solver is None:
            if self._chain_of is not None:
                chain = self._chain_of(tool)
            else:
                kin = Kinematics(self.model, tool)
                chain = SerialChain(self.model, kin, task_rows=self.ik_params.task_rows)
            solver = Solver(chain, InverseTransformation(chain, None, self.ik_params, self.naming))
            self._solvers[key] = solver
        if len(self.recorder) == 1 and key != self._start_tool:
            self._stamp_start(solver)  # a tool set before the first motion holds from t = 0
        return solver

    def _platform_solver(self, settings: Settings) -> Solver:
        """The solver of the settings' tool with the platform task (one per tool)."""
        base = self._solver(settings)
        key = base.kin.tool.tobytes() + b"platform"
        solver = self._solvers.get(key)
        if solver is None:
            chain, task = platform_chain(base.chain, self.platform.platform)
            ik = InverseTransformation(chain, None, self.ik_params, self.naming)
            solver = Solver(chain, ik, task)
            self._solvers[key] = solver
        return solver

    def _platform_options(
        self, cmd: MotionCommand | None, motion: MotionValues, options: ModalOptions
    ) -> ModalOptions:
        """The options under R_PLATFORM (HOLD: the platform's joints frozen), after an
        exact stop where a platform motion or HOLD needs one (platform.py)."""
        pending = self.state.pending
        held = pending.context[0] if pending is not None else None
        state = self.state  # its joints read after any flush the platform part asks for
        return self.platform.options(cmd, motion, options, lambda: state.q, held, self.flush)

    def plan_state(self, settings: Settings, solver: Solver, motion: MotionValues) -> PlanState:
        """Where the next motion starts: here, or at the pending segment's point."""
        q, tcp = self.blender.start_point()
        q = self.state.q.copy() if q is None else q
        if tcp is None:
            tcp = self._start_pose(solver, q)
        return PlanState(q, tcp, motion, base_transform(settings), solver.kin.tool, self.state.t)

    def _start_pose(self, solver: Solver, q: np.ndarray) -> np.ndarray:
        """The TCP a motion from ``q`` is planned from: the last Cartesian point as
        programmed when the actual TCP is on it within the round-off bound (the same
        tool), else the actual TCP (:mod:`plan_start`)."""
        actual = solver.kin.tcp(q)
        last = self._programmed_end
        if last is None or last[0] != solver.kin.tool.tobytes():
            return actual
        rows = self.ik_params.task_rows
        p = self.ik_params
        tol_p = min(self.recorder.tol_position, ROUND_OFF * p.tol_position)
        tol_o = min(self.opts.tol_orientation, ROUND_OFF * p.tol_orientation)
        return planning_start(actual, last[1], rows, tol_p, tol_o)

    def _tcp(self, q: np.ndarray, settings: Settings) -> np.ndarray:
        return self._solver(settings).kin.tcp(q)

    @staticmethod
    def _program_pose(world: np.ndarray, settings: Settings) -> Pose:
        return values.pose_from_matrix(spatial.inverse(base_transform(settings)) @ world)


# re-exported for tests that build segments by hand, and the budgets' constants
__all__ = [
    "DEFAULT_MAX_CYCLES",
    "DRIVE_STEPS_PER_CYCLE",
    "MOTION_MIN_CYCLES",
    "ExecutionOptions",
    "JointLine",
    "ReferencePath",
    "SimulatedController",
]
