"""The IPO cycles of a segment: the part of the simulated controller that moves the robot.

Every cycle advances :class:`~irlc.runtime.control.state.ControllerState` by ``Δt`` and
records one sample:

* a **joint cycle** (PTP) sets the joints to the profile's setpoint; its TCP and
  clearances come from the chain's forward kinematics and bodies;
* an **IK cycle** (LIN, CIRCLE, RECONFIGURATION) calls the inverse transformation with the
  segment's :class:`~irlc.runtime.ik.params.CycleOptions` (the active limits, θ⁰, FREEZE,
  the obstacles). The recorded TCP and path error are the IK result's own. A relaxed or
  unconverged cycle is noted (a warning per statement); beyond the path tolerance
  (``R_PATH_TOL``) or the orientation tolerance it is a :class:`RunFailure` with its
  cause (:mod:`~irlc.runtime.ik.cause`).

A cycle of a motion WITH PLATFORM also sets the platform task's target from the segment's
``s`` and fails when the platform leaves its line beyond the path tolerance, saying which
task could not be met (:mod:`~irlc.runtime.control.platform`).

A negative clearance is a collision, judged by the controller's
:class:`~irlc.runtime.control.collision.CollisionRule` (a run failure unless collisions are
allowed). A segment's θ⁰(s) starts from the previous cycle's
reference, so switching the criterion does not jerk the joints (:meth:`CycleRunner.start`).

Two hooks for what the controller adds around the cycles: ``clearance`` (m, the
statement's ``R_CLEARANCE``; > 0: the IK cycles keep it, :mod:`~irlc.runtime.ik.clearance`,
with ``neighbours`` the cell's other robots) and ``observer`` (told after every recorded
cycle: :class:`CycleObserver`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Protocol

import numpy as np
from irlc.runtime import units
from irlc.runtime.commands import ModalOptions
from irlc.runtime.control import ptp_activity
from irlc.runtime.control.collision import CollisionRule
from irlc.runtime.control.platform import PlatformRecord, platform_failure
from irlc.runtime.control.segment_run import SegmentRun, Solver
from irlc.runtime.control.state import ControllerState
from irlc.runtime.errors import RunFailure
from irlc.runtime.ik import cause
from irlc.runtime.ik.clearance import ClearanceSpec, Neighbours
from irlc.runtime.ik.params import CycleOptions
from irlc.runtime.ik.reach import Reach
from irlc.runtime.model.obstacles import Obstacle
from irlc.runtime.outputs.recorder import Recorder
from irlc.runtime.plan.interpolator import ReferencePath, Segment
from irlc.runtime.plan.preinterp import PreInterpolator

_NAN = float("nan")


class CycleObserver(Protocol):
    """Told after every cycle the runner recorded (its state and recorder hold it): the
    clearance rule between links, a cell's other robots (:mod:`~irlc.runtime.control.cell`)."""

    def cycle(self, runner: CycleRunner) -> None: ...


class CycleRunner:
    """Runs cycles on ``state`` and records them in ``recorder`` (module docstring).
    ``obstacles``: every obstacle of the code (clearances are measured for all of them);
    ``progress(t, line)`` is called every ``progress_every`` cycles; the manipulability
    is sampled every ``manipulability_every`` IK cycles (it costs an SVD)."""

    def __init__(
        self,
        state: ControllerState,
        recorder: Recorder,
        pre: PreInterpolator,
        obstacles: dict[str, Obstacle],
        *,
        tol_orientation: float,
        progress: Callable[[float, int], None] | None = None,
        progress_every: int = 200,
        manipulability_every: int = 10,
        collisions: CollisionRule | None = None,
    ):
        self.state, self.recorder, self.pre, self.obstacles = state, recorder, pre, obstacles
        self.collisions = collisions or CollisionRule()  # the rule on every cycle
        self.tol_orientation = tol_orientation
        self.progress, self.progress_every = progress, progress_every
        self.manip_every = max(1, manipulability_every)
        self.platform_record = PlatformRecord()  # the platform's deviations (WITH PLATFORM)
        self.clearance = 0.0  # m: R_CLEARANCE of the statement (the controller sets it)
        self.neighbours: Callable[[], Neighbours | None] | None = None  # a cell's others
        self.robot_name = ""  # a cell's robot (messages of the clearance rows)
        self.observer: CycleObserver | None = None

    # ------------------------------------------------------------------ segments
    def options_for(
        self, seg: Segment, options: ModalOptions, criterion: str = "DISTANCE"
    ) -> CycleOptions:
        """The per-cycle options of a Cartesian segment under the modal ``options`` and
        the motion's ``R_CRITERION``."""
        pos, spd, acc = seg.limits
        reference = None
        if options.cyclic_reference is not None:
            reference = self.pre.joints_si(options.cyclic_reference)
        for name in options.obstacles:
            if name not in self.obstacles:
                raise RunFailure(f"unknown obstacle {name!r}", seg.line, self.state.t)
        return CycleOptions(
            position=pos,
            speed=spd,
            accel=acc,
            reference=reference,
            frozen=self.pre.frozen_si(options),
            obstacles=tuple(self.obstacles.values()),
            active_obstacles=frozenset(options.obstacles),
            criterion=criterion,
            clearance=self._clearance_spec(),
        )

    def _clearance_spec(self) -> ClearanceSpec | None:
        """``R_CLEARANCE`` for the IK cycles (``None``: 0, not kept)."""
        if self.clearance <= 0.0:
            return None
        return ClearanceSpec(self.clearance, self.neighbours, self.robot_name)

    def run(self, run: SegmentRun, upto: int) -> None:
        """Cycles ``run.done + 1 … upto`` of the segment on its own."""
        if upto <= run.done:
            return
        self.start(run)
        seg, dt, st = run.seg, run.dt, self.state
        st.active_obstacles = run.obstacles
        if seg.is_joint:
            for k in range(run.done + 1, upto + 1):
                _, q = seg.setpoint(k, dt)
                self.joint_cycle(seg, q, k, dt, run.solver)
            st.last_reference = None
        else:
            opts, reference = run.cycle_opts, run.reference
            line, task = seg.platform, run.solver.platform  # WITH PLATFORM: x_platform(s)
            for k in range(run.done + 1, upto + 1):
                s, target = seg.setpoint(k, dt)
                if reference is not None:
                    opts.reference = reference.at(s)
                if line is not None and task is not None:
                    task.target = line.at(s)
                self.ik_cycle(seg, target, dt, opts, run.solver)
            st.last_reference = opts.reference
        run.done = upto

    def start(self, run: SegmentRun) -> None:
        """The segment's θ⁰(s), from the reference in effect when it starts."""
        if run.started:
            return
        run.started = True
        st = self.state
        st.segment_start = st.q.copy()  # for the cause of a failure (ik.cause)
        if not run.seg.is_joint:
            run.reference = self._blended_reference(run.seg.reference, run.cycle_opts.reference)

    def _blended_reference(self, path: ReferencePath | None, constant: np.ndarray | None):
        """The segment's θ⁰(s), starting from the previous cycle's reference (or the
        current configuration when none was active) so that switching the criterion (e.g.
        CYCLIC again after a WITH RECONFIGURATION statement) does not jerk the joints."""
        st = self.state
        start = st.last_reference if st.last_reference is not None else st.q
        if path is not None:
            configs = path.configs.copy()
            configs[0] = start
            return ReferencePath(path.knots, configs)
        if constant is None or np.allclose(start, constant, rtol=0.0, atol=1e-12):
            return None
        return ReferencePath(np.array([0.0, 1.0]), np.array([start, constant]))

    # ------------------------------------------------------------------ cycles
    def ik_cycle(self, seg: Segment, target, dt, opts: CycleOptions, solver: Solver) -> None:
        """One IPO cycle of the inverse transformation towards ``target``."""
        st = self.state
        t = advance(st.t, dt)
        sample_manip = st.cycles % self.manip_every == 0
        opts.jacobian = sample_manip
        try:
            res = solver.ik.step(st.q, st.q_prev, target, dt, opts)
        except RunFailure as exc:
            raise located(exc, seg.line, t) from None
        except FloatingPointError as exc:
            raise RunFailure(f"inverse transformation failed: {exc}", seg.line, t) from None
        st.q_prev, st.q = st.q, res.q
        st.t = t
        # the IK's last FK is at q: no second FK;
        # the path error is the IK's own task error at q (f(θ) ⊖ x_d, controlled rows)
        pos_err, ori_err = res.position_error, res.orientation_error
        rec = self.recorder
        rec.ik_cycles += 1
        rec.add(
            t,
            seg.line,
            st.q,
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
            self.check_collisions(res.clearances, opts.active_obstacles, seg.line, t)
        if res.relaxed or not res.converged:
            rec.note_relaxed(seg.line, t, dt, pos_err, ori_err, res.binding)
        off = 0.0  # the platform's distance from its line (WITH PLATFORM: the last task)
        platform = getattr(seg, "platform", None)  # (a hand-made segment may have none)
        if platform is not None and res.task_errors:
            off = res.task_errors[-1]
            self.platform_record.error(off)
        if pos_err > rec.tol_position or ori_err > self.tol_orientation or off > rec.tol_position:
            if platform is not None and solver.platform is not None:
                deviation = {"tcp": pos_err, "tcp_angle": ori_err, "platform": off}
                reach = self.reach(seg.limits[0], opts.frozen, solver)
                where = ("the path cannot be followed", seg.line, t)
                raise platform_failure(
                    self.pre.model.platform, reach, target, solver.platform.target,
                    st.q_prev, where, deviation, res.binding,
                )  # fmt: skip
            raise self._deviation_failure(seg, t, pos_err, ori_err, res, opts, solver)
        self.tick()

    def joint_cycle(
        self, seg: Segment, q, k: int, dt: float, solver: Solver, profiled: bool = True
    ) -> None:
        """One IPO cycle setting the joints to ``q`` (cycle ``k`` of a PTP segment; not
        ``profiled``: a blend's superposed joints, whose limit activity is not known)."""
        st = self.state
        st.q_prev, st.q = st.q, np.array(q, dtype=float)
        st.t = advance(st.t, dt)
        frames = solver.kin.link_frames(st.q)
        tcp = solver.kin.tcp_from_frames(frames)
        active = ptp_activity.at_bounds(seg, k, dt) if profiled else None
        clearances = self.clearances(solver, st.q, frames)
        self.recorder.add(
            st.t, seg.line, st.q, tcp, None, active=active, clearances=clearances, dt=dt
        )
        self.check_collisions(clearances, st.active_obstacles, seg.line, st.t)
        self.tick()

    def tick(self) -> None:
        st = self.state
        st.cycles += 1
        if self.observer is not None:
            self.observer.cycle(self)
        if self.progress is not None and st.cycles % self.progress_every == 0:
            self.progress(st.t, st.line)

    # ------------------------------------------------------------------ obstacles
    def clearances(
        self, solver: Solver, q: np.ndarray, frames: np.ndarray
    ) -> dict[str, tuple[float, int]] | None:
        """Every obstacle's clearance at ``q`` (``frames``: the task chain's), or ``None``
        without obstacles."""
        if not self.obstacles:
            return None
        bodies = solver.chain.bodies
        cps = bodies.critical_points(bodies.world(q, frames), tuple(self.obstacles.values()))
        return {cp.name: (cp.distance, cp.link) for cp in cps}

    def check_collisions(self, clearances, active, line: int, t: float) -> None:
        """The collision rule on the cycle's clearances (:mod:`collision`: a penetration
        of any obstacle fails the run unless collisions are allowed)."""
        self.collisions.check(clearances, active, line, t)

    # ------------------------------------------------------------------ failures
    def reach(self, position: np.ndarray, frozen: dict[int, float], solver: Solver) -> Reach:
        """The pose search's context: active position limits, frozen joints, tool."""
        return self.pre.reach(position, frozen, solver.kin.tool, self.recorder.tol_position)

    def _deviation_failure(self, seg, t, pos_err, ori_err, res, opts, solver) -> RunFailure:
        """The deviation beyond tolerance, with its cause (:mod:`ik.cause`) for a path
        segment; a held TCP (RECONFIGURATION) reports the binding bound."""
        what = (
            f"the path cannot be followed: TCP deviation {pos_err / units.MM:.4g} mm, "
            f"{ori_err / units.DEG:.4g} deg "
            f"(tolerance {self.recorder.tol_position / units.MM:g} mm, "
            f"{self.tol_orientation / units.DEG:g} deg)"
        )
        if res.binding:
            what += f"; bound by {res.binding}"
        if hasattr(getattr(seg, "path", None), "length"):
            reach = self.reach(seg.limits[0], opts.frozen, solver)
            q0 = self.state.segment_start
            try:
                k = seg.override  # its R_OVERRIDE/100: the suggested speeds are programmed
                return cause.classify(what, res, seg, q0, reach, solver.kin, seg.line, t, k)
            except (ValueError, np.linalg.LinAlgError, FloatingPointError) as exc:
                what += f"; the cause could not be determined ({exc})"  # (numerics)
        if res.singular or (math.isfinite(res.sigma_min) and res.sigma_min < 1e-6):
            what += f"; near a singular configuration (σ_min = {res.sigma_min:.3g})"
            return RunFailure(what, seg.line, t, res.binding or None, cause="singular")
        return RunFailure(what, seg.line, t, res.binding or None, cause.of_bound(res.binding))


def advance(t: float, dt: float) -> float:
    """The next sample time, rounded to 1 ns so that time stamps do not drift."""
    return round(t + dt, 9)


def located(exc: RunFailure, line: int, t: float) -> RunFailure:
    """The same failure with the statement line and the simulated time filled in."""
    if exc.line is None:
        exc.line = line
    if exc.time_s is None:
        exc.time_s = t
    return exc
