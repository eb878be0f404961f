"""The simulated controller: executes motion commands cycle by cycle (kinematic run).

:class:`SimulatedController` implements :class:`~irlc.runtime.commands.Controller`.
For each command the pre-interpolator (:mod:`preinterp`) makes segments; every IPO cycle
``Δt`` the interpolator gives the desired setpoint, and

* PTP segments set the joints directly (the profile respects the joint limits);
* Cartesian segments (LIN, CIRCLE) and RECONFIGURATION call the inverse transformation
  (:class:`~irlc.runtime.ik.newton.InverseTransformation`) with the options of this
  cycle: the active limits, the reference θ⁰ (WITH RECONFIGURATION of the statement,
  else CYCLIC), FREEZE, and the obstacles (every obstacle's clearance is measured,
  the OBSTACLE … OBSTACLEEND ones are avoided).

**Path deviation.** When the hard problem is infeasible the inverse transformation
returns a relaxed cycle. Its TCP error is recorded with time and line (a warning); if it
exceeds the path tolerance ``R_PATH_TOL`` (start value ``tol_position``, 0.05 mm) or
``tol_orientation`` (default 0.01°) the run fails (:class:`RunFailure`, exit 2) naming
the line, the time and the binding constraint. Never a silent zero step: an unconverged
cycle is treated the same way.

**Approximate positioning** (``APPROX``): the controller includes
:class:`~irlc.runtime.control.approximation.ApproximatePositioning` (pending segments, blends,
exact stops, the report's ``approximations`` = :attr:`SimulatedController.blends`); the
geometry is :mod:`~irlc.runtime.plan.blending`. Statements that stop the advance run call
:meth:`SimulatedController.flush`.

**RECONFIGURATION k** (self-motion): :class:`~irlc.runtime.control.reconfiguration.Reconfiguration`,
which the controller includes as it includes approximate positioning.
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
from irlc.runtime.control import ptp_activity
from irlc.runtime.control.approximation import ApproximatePositioning, PendingSegment, SegmentRun
from irlc.runtime.control.reconfiguration import Reconfiguration
from irlc.runtime.engine_policy import EngineChoice
from irlc.runtime.errors import RunFailure
from irlc.runtime.ik import cause
from irlc.runtime.ik.freeze import FrozenJoints
from irlc.runtime.ik.newton import InverseTransformation
from irlc.runtime.ik.params import CycleOptions, IKParams
from irlc.runtime.ik.reach import Reach, check_targets
from irlc.runtime.model import spatial
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.model.naming import JointNaming, naming_or_default
from irlc.runtime.model.obstacles import Obstacle
from irlc.runtime.outputs.cycle_time import KIND_WORDS, StatementSpan, motion_limit
from irlc.runtime.outputs.recorder import Recorder
from irlc.runtime.plan.interpolator import JointLine, ReferencePath, Segment
from irlc.runtime.plan.plan_start import ROUND_OFF, planning_start
from irlc.runtime.plan.preinterp import (
    PlanState,
    PreInterpolator,
    base_transform,
    tool_transform,
)
from irlc.runtime.values import JointTuple, Pose

# The cycle budget: the IPO cycles a run may simulate — those of motion (MOVE, RECONFIGURATION;
# a motion statement counts at least MOTION_MIN_CYCLES) and those a WAIT records (a long WAIT
# records its first WAIT_SAMPLED_CYCLES and its last) — ≈ 8 min of robot time at the default
# 10 ms. What a run computes and records grows with its cycles (an IK cycle costs 0.1–2 ms of
# CPU), not with its simulated time: a small R_IPO, a long slow motion or a loop of motions
# or waits is bounded here; a long WAIT's time by max_time_s.
DEFAULT_MAX_CYCLES = 50_000
# Planning a motion statement and checking that its target is reachable cost about four IK
# cycles (a loop of one-cycle LINs on koch11: ≈ 2 ms of CPU a statement against ≈ 0.4 ms an
# IK cycle), so a statement counts at least five: such a loop meets the default budget
# after 10,000 statements, not 50,000 (24 s of CPU instead of 100 on a slow, loaded machine).
MOTION_MIN_CYCLES = 5
# With drives (``--drives`` other than ideal) the drive simulation steps through the run's
# time at its own step h (≤ 1 ms; 125 µs at the pwm level), each step costing about a fifth
# of a koch11 IK cycle (70–140 µs of CPU against 350 µs) and keeping ≈ 2 kB until the run
# ends: DRIVE_STEPS_PER_CYCLE drive steps count as one cycle (250,000 steps by default,
# ≈ 0.5 GB on koch11).
DRIVE_STEPS_PER_CYCLE = 5


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
    engine: EngineChoice | None = None  # when the kernels take over (engine_policy.py)


@dataclass
class _Solver:
    kin: Kinematics
    ik: InverseTransformation


class SimulatedController(ApproximatePositioning, Reconfiguration):
    """Kinematic simulation of one robot (``drives = ideal``); records every IPO cycle."""

    def __init__(
        self,
        model: RobotModel,
        start_q: np.ndarray,
        *,
        obstacles: dict[str, Obstacle] | None = None,
        options: ExecutionOptions | None = None,
        progress: Callable[[float, int], None] | None = None,
        naming: JointNaming | None = None,
    ):
        self.model = model
        self._naming = naming_or_default(naming, model)  # joints in failure messages
        self.opts = options or ExecutionOptions()
        self.ik_params = self.opts.ik or IKParams.for_robot(model)
        self.obstacles = dict(obstacles or {})
        self.recorder = Recorder(model.n, tuple(self.obstacles), self.ik_params.task_rows)
        self.pre = PreInterpolator(model, self.ik_params.task_rows, self.opts.tol_orientation)
        self.pre.max_duration = self.opts.max_time_s
        self.pre.naming = self._naming
        self.progress = progress
        self.scale = units.joint_scale(model.joint_kinds)
        self._solvers: dict[bytes, _Solver] = {}
        self._t = 0.0
        self.q = np.array(start_q, dtype=float)
        self.q_prev = self.q.copy()
        self._cycles = 0
        self._granted_cycles = 0  # cycles the cycle budget granted so far (_grant_cycles)
        self._line = 0
        self._manip_every = max(1, self.opts.manipulability_every)
        self._collision_warned: set[str] = set()
        self._last_reference: np.ndarray | None = None  # θ⁰ of the last IK cycle
        self._segment_start = self.q.copy()
        self._active_obstacles: frozenset[str] = frozenset()
        self.dt_used = self.opts.ipo if self.opts.ipo is not None else Settings().ipo
        self.recorder.tol_position = self.opts.tol_position
        self._start_tool = b""  # the tool (bytes) the start sample was stamped with
        self._programmed_end: tuple[bytes, np.ndarray] | None = None  # (tool, world TCP)
        self._pending: PendingSegment | None = None  # an approximated segment's unrun tail
        self.blends: list[dict] = []  # one entry per approximated point (the report's)
        self.statements: list[StatementSpan] = []  # cycle time per statement (cycle_time.py)
        self._record_initial()

    # ------------------------------------------------------------------ protocol
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
        return self._t

    def joints(self) -> tuple[float, ...]:
        self.flush("the robot's joints are read (CYCLICSTART, JOINTLIMIT, FREEZESTART)")
        return tuple(float(v) for v in self.q / self.scale)

    def pose(self, settings: Settings) -> Pose:
        self.flush("the robot's pose is read")
        return self._program_pose(self._tcp(self.q, settings), settings)

    def forward(self, joints: JointTuple, settings: Settings) -> Pose:
        q = self.pre.joints_si(joints)
        return self._program_pose(self._tcp(q, settings), settings)

    def move(self, cmd: MotionCommand, settings: Settings, options: ModalOptions) -> None:
        self._line = cmd.line
        self.recorder.tol_position = settings.path_tol * units.MM  # R_PATH_TOL
        solver = self._solver(settings)
        approx = self._approx(cmd, settings)
        context = (options, solver.kin.tool.tobytes(), base_transform(settings).tobytes(),
                   self._dt(settings))  # fmt: skip
        if self._pending is not None and self._pending.context != context:
            self.flush(self._pending_reason(cmd, context))
        joint = cmd.kind in ("PTP", "PTPINC")
        if self._pending is not None and joint and not self._pending.run.seg.is_joint:
            try:  # LIN/CIRCLE → PTP: plan the PTP from the Cartesian segment's end joints
                self._joint_chain(self._pending)
            except RunFailure:  # it cannot be followed: run it (and fail) at its own line
                self.flush("the motion before cannot be followed")
        state = self._plan_state(settings, solver)
        t0, segments, stop = self._t, [], "failed"
        try:
            segments = self.pre.plan(cmd, settings, options, state)
            cycles = sum(seg.cycles for seg in segments)
            self._within_budget(cycles * state.dt, cmd.line, "the motion")
            self._grant_cycles(cycles, cycles * state.dt, cmd.line, "the motion", MOTION_MIN_CYCLES)
            cartesian = [seg for seg in segments if not seg.is_joint]
            if cartesian:  # reachability of the end (and via) points, before anything moves
                reach = self._reach(cartesian[0].limits[0], options, solver)
                what = KIND_WORDS.get(cmd.kind, cmd.kind)
                check_targets(reach, cartesian, self.q, cmd.line, self._t, what)
            for point, seg in enumerate(segments, start=1):
                run = SegmentRun(self, seg, options, solver, settings)
                self._feed(run, approx, context, point)
            if segments:  # the next motion is planned from this point (plan_start.py)
                end = self._programmed_point(cmd, segments[-1], state)
                self._programmed_end = None if end is None else (solver.kin.tool.tobytes(), end)
            own = self._pending is not None and self._pending.span == len(self.statements)
            stop = "approximated" if own else "exact"  # (a zero-length move blends nothing)
        finally:
            self._log_motion(cmd, segments, t0, stop, settings.override)

    def _programmed_point(self, cmd: MotionCommand, last: Segment, state) -> np.ndarray | None:
        """The world TCP pose the motion's last point was programmed at: a Cartesian
        segment's end; a PTP to a POSE, that pose (its joints come from the pose solver,
        with its residual); ``None`` for a PTP to joints (the TCP is exact there)."""
        if not last.is_joint:
            return last.path.at(1.0).copy()
        target = cmd.targets[-1] if cmd.kind == "PTP" and cmd.targets else None
        if isinstance(target, Pose):
            return self.pre.world(target, state, cmd.line)
        return None

    def _log_motion(self, cmd: MotionCommand, segments, t0: float, stop: str, override) -> None:
        """The motion's span of the cycle-time table, with what set its time."""
        limit = motion_limit([s.limiting for s in segments], cmd.time is not None)
        kind = KIND_WORDS.get(cmd.kind, cmd.kind)
        if self.statements:  # after a blend the span starts where the one before ends
            t0 = max(t0, self.statements[-1].end)
        self._log_statement(kind, cmd.line, t0, stop, limit, override, cmd.call)

    def wait(self, seconds: float, line: int, settings: Settings, options: ModalOptions) -> None:
        if not (seconds >= 0.0 and math.isfinite(seconds)):
            raise RunFailure(f"WAIT needs a finite time ≥ 0 s, got {seconds!r}", line, self._t)
        self.flush(f"WAIT at line {line}")
        self._line = line
        dt = self._dt(settings)
        self._within_budget(seconds, line, "the WAIT")
        n = round(seconds / dt)
        if abs(n * dt - seconds) > 1e-9 * max(1.0, seconds):
            n = math.ceil(seconds / dt)
        if n == 0:
            return
        sampled = min(n, WAIT_SAMPLED_CYCLES)
        self._grant_cycles(sampled + (n > sampled), n * dt, line, "the WAIT")  # those recorded
        self.q_prev = self.q.copy()  # standing still: q, and so the sample, do not change
        tcp = self._solver(settings).kin.tcp(self.q)
        rec = self.recorder
        t0 = self._t
        for _ in range(sampled):
            self._t = _advance(self._t, dt)
            rec.add(self._t, line, self.q, tcp, None)
            self._tick()
        if n > sampled:  # the rest of a long WAIT: its last cycle stands for all of them
            self._t = round(t0 + n * dt, 9)
            rec.add(self._t, line, self.q, tcp, None)
            self._cycles += n - sampled - 1
            self._tick()
        self._log_statement("WAIT", line, t0, None, "")

    def _log_statement(
        self, kind, line: int, t0: float, stop, limit: str, override=None, call=None
    ) -> None:
        """One span of the cycle-time table (``statements`` of the report)."""
        span = StatementSpan(line, kind, t0, self._t, stop, limit, override, call)
        self.statements.append(span)

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
                raise _located(exc, line, self._t) from None

    def _check_not_inside(self, names: tuple[str, ...], line: int, settings: Settings) -> None:
        solver = self._solver(settings)
        clearances = self._clearances(solver, solver.kin.link_frames(self.q)) or {}
        for name in names:
            distance, link = clearances.get(name, (0.0, 0))
            if distance < 0.0:
                raise RunFailure(
                    f"OBSTACLE {name}: the arm is already inside it ({-distance / units.MM:.4g}"
                    f" mm deep, link {link}); it cannot be avoided",
                    line,
                    self._t,
                    f"obstacle {name}",
                    cause="obstacle",
                )

    def log_event(self, kind: str, line: int, **data) -> None:
        event = {"kind": kind, "line": line, "time_s": round(self._t, 9)}
        event.update(data)
        self.recorder.events.append(event)

    # ------------------------------------------------------------------ cycles
    def _run_cycles(self, run: SegmentRun, upto: int) -> None:
        """Cycles ``run.done + 1 … upto`` of the segment on its own."""
        if upto <= run.done:
            return
        self._start(run)
        seg, dt = run.seg, run.dt
        self._active_obstacles = run.obstacles
        if seg.is_joint:
            for k in range(run.done + 1, upto + 1):
                s, q = seg.setpoint(k, dt)
                self._joint_cycle(seg, q, k, s, dt, run.solver)
            self._last_reference = None
        else:
            opts, reference = run.cycle_opts, run.reference
            for k in range(run.done + 1, upto + 1):
                s, target = seg.setpoint(k, dt)
                if reference is not None:
                    opts.reference = reference.at(s)
                self._ik_cycle(seg, target, dt, opts, run.solver)
            self._last_reference = opts.reference
        run.done = upto

    def _start(self, run: SegmentRun) -> None:
        """The segment's θ⁰(s), from the reference in effect when it starts."""
        if run.started:
            return
        run.started = True
        self._segment_start = self.q.copy()  # for the cause of a failure (ik.cause)
        if not run.seg.is_joint:
            run.reference = self._blended_reference(run.seg.reference, run.cycle_opts.reference)

    def _blended_reference(self, path: ReferencePath | None, constant: np.ndarray | None):
        """The segment's θ⁰(s), starting from the previous cycle's reference (or the
        current configuration when none was active) so that switching the criterion (e.g.
        CYCLIC again after a WITH RECONFIGURATION statement) does not jerk the joints."""
        start = self._last_reference if self._last_reference is not None else self.q
        if path is not None:
            configs = path.configs.copy()
            configs[0] = start
            return ReferencePath(path.knots, configs)
        if constant is None or np.allclose(start, constant, rtol=0.0, atol=1e-12):
            return None
        return ReferencePath(np.array([0.0, 1.0]), np.array([start, constant]))

    def _cycle_options(self, seg: Segment, options: ModalOptions) -> CycleOptions:
        pos, spd, acc = seg.limits
        reference = None
        if options.cyclic_reference is not None:
            reference = self.pre.joints_si(options.cyclic_reference)
        for name in options.obstacles:
            if name not in self.obstacles:
                raise RunFailure(f"unknown obstacle {name!r}", seg.line, self._t)
        return CycleOptions(
            position=pos,
            speed=spd,
            accel=acc,
            reference=reference,
            frozen=self.pre.frozen_si(options),
            obstacles=tuple(self.obstacles.values()),
            active_obstacles=frozenset(options.obstacles),
        )

    def _ik_cycle(self, seg: Segment, target, dt, opts: CycleOptions, solver: _Solver) -> None:
        t = _advance(self._t, dt)
        sample_manip = self._cycles % self._manip_every == 0
        opts.jacobian = sample_manip
        try:
            res = solver.ik.step(self.q, self.q_prev, target, dt, opts)
        except RunFailure as exc:
            raise _located(exc, seg.line, t) from None
        except FloatingPointError as exc:
            raise RunFailure(f"inverse transformation failed: {exc}", seg.line, t) from None
        self.q_prev, self.q = self.q, res.q
        self._t = t
        # the IK's last FK is at q: no second FK;
        # the path error is the IK's own task error at q (f(θ) ⊖ x_d, controlled rows)
        pos_err, ori_err = res.position_error, res.orientation_error
        rec = self.recorder
        rec.ik_cycles += 1
        rec.add(
            t,
            seg.line,
            self.q,
            res.tcp,
            target,
            errors=(pos_err, ori_err),
            iterations=res.iterations,
            relaxed=res.relaxed,
            active_codes=res.active_codes,
            clearances=res.clearances,
            dt=dt,
            manipulability=res.manipulability if sample_manip else _NAN,
        )
        if res.clearances:
            self._check_collisions(res.clearances, opts.active_obstacles, seg.line, t)
        if res.relaxed or not res.converged:
            rec.note_relaxed(seg.line, t, dt, pos_err, ori_err, res.binding)
        if pos_err > rec.tol_position or ori_err > self.opts.tol_orientation:
            raise self._deviation_failure(seg, t, pos_err, ori_err, res, opts, solver)
        self._tick()

    def _joint_cycle(
        self, seg: Segment, q, k: int, s: float, dt: float, solver, profiled: bool = True
    ) -> None:
        self.q_prev, self.q = self.q, np.array(q, dtype=float)
        self._t = _advance(self._t, dt)
        frames = solver.kin.link_frames(self.q)
        tcp = solver.kin.tcp_from_frames(frames)
        active = ptp_activity.at_bounds(seg, k, dt) if profiled else None
        clearances = self._clearances(solver, frames)
        self.recorder.add(
            self._t, seg.line, self.q, tcp, None, active=active, clearances=clearances, dt=dt
        )
        self._check_collisions(clearances, self._active_obstacles, seg.line, self._t)
        self._tick()

    def _check_collisions(self, clearances, active, line: int, t: float) -> None:
        """A negative clearance is a collision: a failure for an avoided (active) obstacle,
        a warning (once per obstacle) for the others."""
        if not clearances:
            return
        for name, (distance, link) in clearances.items():
            if distance >= 0.0:
                continue
            depth = f"{-distance / units.MM:.4g} mm deep, link {link}"
            if name in active:
                raise RunFailure(
                    f"the arm collides with obstacle {name} ({depth})",
                    line,
                    t,
                    f"obstacle {name}",
                    cause="obstacle",
                )
            if name not in self._collision_warned:
                self._collision_warned.add(name)
                self.recorder.warnings.append(
                    f"line {line}: the arm touches obstacle {name} at t = {t:.3f} s ({depth}); "
                    "it is not avoided (no OBSTACLE statement active)"
                )

    def _record_initial(self) -> None:
        """The sample at t = 0 (with the clearances of the start configuration), with the
        default tool; :meth:`_solver` re-stamps it with the program's tool while it is the
        only sample (``R_TOOL`` set before the first motion holds from t = 0)."""
        self._stamp_start(self._solver(Settings()))

    def _stamp_start(self, solver: _Solver) -> None:
        frames = solver.kin.link_frames(self.q)
        tcp = solver.kin.tcp_from_frames(frames)
        clear = self._clearances(solver, frames)
        if len(self.recorder) == 0:
            self.recorder.add(self._t, 0, self.q, tcp, None, clearances=clear)
        else:
            self.recorder.restamp_first(tcp, clear)
        self._start_tool = solver.kin.tool.tobytes()

    def _clearances(self, solver: _Solver, frames) -> dict[str, tuple[float, int]] | None:
        if not self.obstacles:
            return None
        from irlc.runtime.model.distance import critical_points

        cps = critical_points(solver.kin, frames, tuple(self.obstacles.values()))
        return {cp.name: (cp.distance, cp.link) for cp in cps}

    def _within_budget(self, seconds: float, line: int, what: str) -> None:
        """:class:`RunFailure` (line, time) when ``seconds`` more would take the run past
        its simulated-time budget (``ExecutionOptions.max_time_s``); checked before any
        cycle of the statement is simulated (so a WAIT 1e9 SEC fails at once)."""
        budget = self.opts.max_time_s
        if self._t + seconds > budget:
            raise RunFailure(
                f"{what} would take {units.seconds_text(seconds)} and the run past its"
                " simulated-time budget "
                f"of {budget:g} s (at t = {self._t:.3f} s; raise it with --max-time)",
                line,
                self._t,
            )

    def _grant_cycles(
        self, cycles: int, seconds: float, line: int, what: str, minimum: int = 0
    ) -> None:
        """Count a statement's ``cycles`` recorded IPO cycles (over ``seconds`` of robot
        time), at least ``minimum``, against the cycle budget (``ExecutionOptions.max_cycles``,
        :data:`DEFAULT_MAX_CYCLES`) before they are simulated; :class:`RunFailure` if they
        would exceed it. With drives (``drive_step_s``) the drive steps of ``seconds``
        count instead when they are more, DRIVE_STEPS_PER_CYCLE to a cycle: the drives
        simulate every step of the run's time, a long WAIT's too. Granted cycles count
        until :meth:`restart_cycle_budget`."""
        h, charged = self.opts.drive_step_s, max(cycles, minimum)
        if h:
            charged = max(charged, math.ceil(seconds / (DRIVE_STEPS_PER_CYCLE * h) - 1e-9))
        limit = self.opts.max_cycles
        if self._granted_cycles + charged <= limit:
            self._granted_cycles += charged
            return
        cost = f"{cycles} IPO cycle{'s' if cycles != 1 else ''}"
        if charged > max(cycles, minimum):
            cost = (
                f"{charged} cycles of the budget ({math.ceil(seconds / h - 1e-9)} drive steps"
                f" of {h * 1e3:.3g} ms, {DRIVE_STEPS_PER_CYCLE} to a cycle)"
            )
        elif charged > cycles:
            cost = (
                f"{charged} cycles of the budget ({cost}; a motion statement counts at least"
                f" {minimum})"
            )
        raise RunFailure(
            f"{what} would take {cost} and the run past its budget of {limit} simulated"
            f" cycles ({self._granted_cycles} so far, at t = {self._t:.3f} s; raise it with"
            " --max-cycles)",
            line,
            self._t,
        )

    def restart_cycle_budget(self) -> None:
        """Count the cycle budget from here (the REPL: each entry has the whole budget)."""
        self._granted_cycles = 0

    def _tick(self) -> None:
        self._cycles += 1
        if self.progress is not None and self._cycles % self.opts.progress_every == 0:
            self.progress(self._t, self._line)

    def _deviation_failure(self, seg, t, pos_err, ori_err, res, opts, solver) -> RunFailure:
        """The deviation beyond tolerance, with its cause (:mod:`ik.cause`) for a path
        segment; a held TCP (RECONFIGURATION) reports the binding bound."""
        what = (
            f"the path cannot be followed: TCP deviation {pos_err / units.MM:.4g} mm, "
            f"{ori_err / units.DEG:.4g} deg "
            f"(tolerance {self.recorder.tol_position / units.MM:g} mm, "
            f"{self.opts.tol_orientation / units.DEG:g} deg)"
        )
        if res.binding:
            what += f"; bound by {res.binding}"
        if hasattr(getattr(seg, "path", None), "length"):
            reach = self._reach(seg.limits[0], None, solver, opts.frozen)
            q0 = self._segment_start
            try:
                k = seg.info.get("override", 1.0)  # its R_OVERRIDE/100 (SegmentRun)
                return cause.classify(what, res, seg, q0, reach, solver.kin, seg.line, t, k)
            except (ValueError, np.linalg.LinAlgError, FloatingPointError) as exc:
                what += f"; the cause could not be determined ({exc})"  # (numerics)
        if res.singular or (math.isfinite(res.sigma_min) and res.sigma_min < 1e-6):
            what += f"; near a singular configuration (σ_min = {res.sigma_min:.3g})"
            return RunFailure(what, seg.line, t, res.binding or None, cause="singular")
        return RunFailure(what, seg.line, t, res.binding or None, cause.of_bound(res.binding))

    # ------------------------------------------------------------------ helpers
    def _dt(self, settings: Settings) -> float:
        dt = self.opts.ipo if self.opts.ipo is not None else settings.ipo
        error = setting_error("ipo", dt)
        if error is not None:
            raise RunFailure(f"the IPO cycle {dt!r} s: {error}", self._line, self._t)
        self.dt_used = float(dt)
        return self.dt_used

    def _solver(self, settings: Settings) -> _Solver:
        switch = self.opts.engine.ik_from if self.opts.engine is not None else None
        if switch is not None and self.recorder.ik_cycles >= switch and not self.ik_params.accel:
            self.ik_params = dataclasses.replace(self.ik_params, accel=True)  # engine_policy
            self._solvers.clear()  # the next motion's solver runs the compiled cycle
        tool = tool_transform(self.model, settings)
        key = tool.tobytes()
        solver = self._solvers.get(key)
        if solver is None:
            kin = Kinematics(self.model, tool)
            ik = InverseTransformation(self.model, kin, self.ik_params, self.naming)
            solver = _Solver(kin, ik)
            self._solvers[key] = solver
        if len(self.recorder) == 1 and key != self._start_tool:
            self._stamp_start(solver)  # a tool set before the first motion holds from t = 0
        return solver

    def _plan_state(self, settings: Settings, solver: _Solver) -> PlanState:
        """Where the next motion starts: here, or at the pending segment's point."""
        q, tcp = self.q.copy(), None
        pending = self._pending
        if pending is not None:
            seg = pending.run.seg
            if seg.is_joint:
                q = seg.path.q1.copy()
            else:
                tcp = seg.path.at(1.0).copy()
                if pending.chain:  # LIN/CIRCLE → PTP: its end joints (_joint_chain)
                    q = pending.chain[seg.cycles].copy()
        if tcp is None:
            tcp = self._start_pose(solver, q)
        dt, base = self._dt(settings), base_transform(settings)
        return PlanState(q, tcp, dt, base, solver.kin.tool, self._t)

    def _start_pose(self, solver: _Solver, q: np.ndarray) -> np.ndarray:
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

    def _reach(
        self, position: np.ndarray, options: ModalOptions | None, solver: _Solver, frozen=None
    ) -> Reach:
        """The pose search's context: active position limits, frozen joints, tool."""
        frozen = self.pre.frozen_si(options) if frozen is None else frozen
        return self.pre.reach(position, frozen, solver.kin.tool, self.recorder.tol_position)


_NAN = float("nan")


def _advance(t: float, dt: float) -> float:
    """The next sample time, rounded to 1 ns so that time stamps do not drift."""
    return round(t + dt, 9)


def _located(exc: RunFailure, line: int, t: float) -> RunFailure:
    """The same failure with the statement line and the simulated time filled in."""
    if exc.line is None:
        exc.line = line
    if exc.time_s is None:
        exc.time_s = t
    return exc


# re-exported for tests that build segments by hand
__all__ = ["ExecutionOptions", "JointLine", "ReferencePath", "SimulatedController"]
