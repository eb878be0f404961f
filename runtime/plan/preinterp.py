"""The pre-interpolator: one motion command → profiled segments (SI, world frame).

For each :class:`~irlc.runtime.commands.MotionCommand` it resolves

* **units**: program values (mm, deg, s; joints deg | mm) → SI, via :mod:`units` only;
* **frames**: program poses are in the ``R_BASE`` frame: ``T_world = R_BASE · T_prog``;
  the TCP is the robot's own tool (robot file) followed by ``R_TOOL``
  (:func:`tool_transform`); ``MOVE_INC LIN`` deltas are in the tool frame:
  ``T_target = T_now · Δ``;
* **limits**: program limits (modal JOINTLIMIT … blocks and WITH clauses, intersected
  with each other) ∩ the robot's own limits, which always apply. A position bound that
  excludes the current configuration is a :class:`~irlc.runtime.errors.RunFailure`
  naming joint, value and bound (never a clamp);
* **profile** (:mod:`profiles`; its bounds, motors and ``WITH TIME``: :mod:`segment_timing`),
  a trapezoid stretched to a whole number of IPO cycles:

  - PTP: straight line in joint space, synchronised; joint ``i`` may use
    ``R_SPEED_PTP % · θ̇max_i`` and ``R_ACC_PTP % · θ̈max_i`` (of the active limits);
    the slowest joint sets the time; where the transmission couples joints and the drive
    data give motor limits (:mod:`motor_limits`), every motor is one more axis of the
    profile (its travel ``|ΔΘs_m|`` at ``R_SPEED_PTP % · v_m``, ``R_ACC_PTP % · a_m``):
    the plan is never shorter than the slowest motor allows;
  - LIN: position (``R_SPEED``, ``R_ACC``) and orientation (``R_SPEED_ORI`` with the
    same ramp time, ``ω̇ = R_SPEED_ORI · R_ACC / R_SPEED``) share one ``s(t)``; the segment
    time is the larger of the two times (orientation only counts when the robot's task
    controls it: not for a planar arm whose task is x, y);
  - CIRCLE: the same on the arc length and the start → target orientation angle;
  - several LIN points / LIN PATH: consecutive segments, each profiled to stop at its
    point (approximate positioning superposes them in the executor: :mod:`blending`);
    ``WITH TIME`` is split over them in proportion to their minimum times;
  - ``WITH TIME t``: the profile is stretched to ``t``; shorter than the limits allow is
    a RunFailure;
  - ``R_PROFILE = 'SCURVE'``: the jerk-limited profile of :mod:`scurve` in place of the
    trapezoid, with the jerk bounds of :meth:`PreInterpolator.ptp_jerks` (PTP) and
    ``R_JERK`` (LIN, CIRCLE; orientation jerk ``R_SPEED_ORI · R_JERK / R_SPEED``, the same
    time constants as the position).

A PTP to a POSE gets its joints from :func:`solve_ptp_pose` (the search of
:mod:`~irlc.runtime.ik.reach` with the active position limits, frozen joints and the tool
of :class:`PlanState` as arguments); :meth:`PreInterpolator.joint_profile` is the joint
motion of PTP and of RECONFIGURATION's reference.

``WITH RECONFIGURATION`` gives a reference θ⁰(s), linear per segment from the
configuration at the start of the statement (or the previous point's) to each point's.

``WITH PLATFORM := q`` gives each segment the platform's own line ``x_platform(s)``
(:mod:`platform_path`: in step with the TCP, timed within the platform joints' limits); a
PTP to a POSE holds the platform joints at ``q``'s in its pose search, so they move on
the PTP's joint line (a straight platform line, in step).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from irlc.lang.irdata import geometry_problem
from irlc.lang.settings import LIMIT_OPTIONS, reconfiguration_counts
from irlc.robots.model import RobotModel
from irlc.runtime import units, values
from irlc.runtime.commands import ModalOptions, MotionCommand, Settings
from irlc.runtime.errors import RunFailure
from irlc.runtime.ik.limits import format_joint_value, intersect_limits
from irlc.runtime.ik.reach import LimitedModels, Reach, unreachable_failure
from irlc.runtime.model.limit_check import first_outside, limit_failure
from irlc.runtime.model.motor_limits import motor_limits
from irlc.runtime.model.naming import JointNaming
from irlc.runtime.plan.interpolator import (
    CartesianArc,
    CartesianLine,
    CircleError,
    Hold,
    JointLine,
    JointPeaks,
    ReferencePath,
    Segment,
)
from irlc.runtime.plan.motion_values import MotionValues
from irlc.runtime.plan.platform_path import (
    held_joints,
    platform_lines,
    platform_timing,
    target_failure,
)
from irlc.runtime.plan.profiles import (
    ProfileError,
    Trapezoid,
    cycles,
)
from irlc.runtime.plan.segment_timing import (
    Bounds,
    motor_bounds,
    segment_bounds,
    segment_profile,
    split_time,
    with_time,
)
from irlc.runtime.values import JointTuple, Pose

Limits3 = tuple[np.ndarray, np.ndarray, np.ndarray]


def check_coordinates(frame: np.ndarray, what: str, line: int | None) -> None:
    """:class:`RunFailure` unless the translation of ``frame`` (4×4, SI) is finite and
    inside the physical range of a coordinate (``irdata.geometry_problem``, ±1 km): beyond
    it a path length or a normalised speed overflows or underflows."""
    for axis, v in zip("xyz", frame[:3, 3], strict=True):
        if problem := geometry_problem("point", (v / units.MM,)):
            raise RunFailure(f"{what}: {axis} = {problem}", line)


def tool_transform(model: RobotModel, settings: Settings) -> np.ndarray:
    """TCP in the flange frame: the robot's own tool, then ``R_TOOL``."""
    return model.tool @ values.pose_to_matrix(settings.tool)


def base_transform(settings: Settings) -> np.ndarray:
    """``R_BASE``: the program's base frame in the world (4×4, SI)."""
    return values.pose_to_matrix(settings.base)


@dataclass
class PlanState:
    """What the pre-interpolator needs to know about the robot right now (SI)."""

    q: np.ndarray  # commanded configuration
    tcp: np.ndarray  # its world TCP pose (with the current tool)
    motion: MotionValues  # the motion's settings, checked and scaled (motion_values.py)
    base: np.ndarray  # R_BASE in the world (4×4)
    tool: np.ndarray  # the TCP in the flange frame (4×4): tool_transform(model, settings)
    time: float = 0.0  # s, the simulated time (of a failure while planning)

    @property
    def dt(self) -> float:
        """The IPO cycle (s)."""
        return self.motion.ipo


def solve_ptp_pose(reach: Reach, target: np.ndarray, seed: np.ndarray, line: int,
                   time: float) -> np.ndarray:  # fmt: skip
    """PTP to a POSE: the joints for ``target`` (world, 4×4) from ``seed``, within the
    context ``reach`` (its active position limits, frozen joints held, tool and task: the
    search of :mod:`ik.reach`). The PTP needs the exact pose, so the result must converge:
    a stalled search is restarted (:meth:`Reach.search`), an unreachable pose is a
    :class:`RunFailure` at ``line`` and ``time``."""
    sol = reach.solve(target, seed)
    if not sol.converged:  # stalled: the restarts of the pre-check's search
        sol = reach.search(target, seed)
    if not sol.converged:
        raise unreachable_failure(reach, target, seed, sol, line, time, "MOVE PTP")
    return sol.q


class PreInterpolator:
    """Turns motion commands into segments for one robot."""

    def __init__(
        self,
        model: RobotModel,
        task_rows: Sequence[int] = (0, 1, 2, 3, 4, 5),
        tol_orientation: float = 0.01 * units.DEG,
    ):
        self.model = model
        self.naming = JointNaming.for_model(model)  # the controller sets the program's
        self.task_rows = tuple(task_rows)
        # a task without orientation rows (a planar arm's x, y) does not time orientation
        self.timed_orientation = any(r >= 3 for r in task_rows)
        self.kinds = model.joint_kinds
        self.scale = units.joint_scale(self.kinds)
        self.tol_orientation = tol_orientation  # rad: a PTP's POSE counts as reached within
        self.max_duration = math.inf  # s: the run's simulated-time budget (the controller's)
        self.motors = motor_limits(model)  # None: the joint limits say it all
        self.limited = LimitedModels(model)  # the pose searches' narrowed models, per run

    # ------------------------------------------------------------------ units
    def joints_si(self, values: Sequence[float] | JointTuple) -> np.ndarray:
        vals = values.values if isinstance(values, JointTuple) else values
        if len(vals) != self.model.n:
            raise RunFailure(
                f"a joint tuple has {len(vals)} values but robot {self.model.name} has "
                f"{self.model.n} joints"
            )
        return np.asarray(vals, dtype=float) * self.scale

    def frozen_si(self, options: ModalOptions) -> dict[int, float]:
        return {j: float(v) * float(self.scale[j]) for j, v in sorted(options.frozen.items())}

    # ------------------------------------------------------------------ limits
    def limits(self, cmd_limits: Sequence, options: ModalOptions, line: int) -> Limits3:
        """Robot limits ∩ modal program limits ∩ this statement's WITH limits."""
        progs = []
        for modal, clause in zip(
            tuple(getattr(options, o.field) for o in LIMIT_OPTIONS),
            cmd_limits,
            strict=True,
        ):
            bound = None
            for pair in (modal, clause):
                if pair is None:
                    continue
                lo, hi = self.joints_si(pair[0]), self.joints_si(pair[1])
                if bound is None:
                    bound = np.column_stack((lo, hi))
                else:
                    bound[:, 0] = np.fmax(bound[:, 0], lo)
                    bound[:, 1] = np.fmin(bound[:, 1], hi)
            progs.append(bound)
        try:
            return intersect_limits(self.model, *progs, naming=self.naming)
        except ValueError as exc:
            raise RunFailure(f"the active joint limits are contradictory: {exc}", line) from None

    def check_inside(self, q: np.ndarray, position: np.ndarray, line: int, what: str) -> None:
        """RunFailure if ``q`` is outside the position limits (naming joint, value, bound):
        the one check and message of :mod:`~irlc.runtime.model.limit_check` (SI, its tolerance)."""
        out = first_outside(q, position[:, 0], position[:, 1])
        if out is None:
            return
        j = out.joint
        raise limit_failure(
            what,
            out,
            self.naming.label(j),
            format_joint_value(self.model, j, out.value, 0),
            format_joint_value(self.model, j, out.bound, 0),
            line,
            cause="limits" if what.startswith("the limits") else "position_limit",
        )

    # ------------------------------------------------------------------ planning
    def plan(
        self, cmd: MotionCommand, settings: Settings, options: ModalOptions, state: PlanState
    ) -> list[Segment]:
        lims = self.limits(tuple(getattr(cmd, o.field) for o in LIMIT_OPTIONS), options, cmd.line)
        self.check_inside(state.q, lims[0], cmd.line, "the limits exclude the current state")
        check_coordinates(values.pose_to_matrix(settings.tool), "R_TOOL", cmd.line)
        check_coordinates(state.base, "R_BASE", cmd.line)
        kind = cmd.kind
        if cmd.platform_target is not None:
            self._check_platform(cmd, options, lims)
        try:
            if kind in ("PTP", "PTPINC"):
                segments = self._plan_ptp(cmd, options, state, lims)
            elif kind in ("LIN", "LINPATH", "LININC"):
                segments = self._plan_lin(cmd, state, lims)
            elif kind == "CIRCLE":
                segments = self._plan_circle(cmd, state, lims)
            else:
                raise RunFailure(f"unknown motion kind {kind!r}", cmd.line)
        except ProfileError as exc:  # bounds no profile can be planned with: at the line
            raise RunFailure(f"the motion cannot be planned: {exc}", cmd.line) from None
        for seg in segments:
            seg.override = state.motion.k
        return segments

    def _check_platform(self, cmd: MotionCommand, options: ModalOptions, lims: Limits3) -> None:
        """``WITH PLATFORM``: the robot has a platform, the target fits it and its active
        limits, no FREEZE holds its joints, a PTP goes to a POSE (:mod:`platform_path`)."""
        target = cmd.platform_target
        assert target is not None
        platform = self.model.platform
        failure = target_failure(platform, self.model.name, target, lims[0], self.naming, cmd.line)
        if failure is not None:
            raise failure
        held_joints(platform, self.frozen_si(options), self.naming, cmd.line)
        if cmd.kind == "PTPINC" or any(not isinstance(t, Pose) for t in cmd.targets):
            raise RunFailure(
                f"WITH PLATFORM needs a POSE target (a {cmd.kind} to joints fixes the platform)",
                cmd.line,
            )

    def hold(
        self,
        kind: str,
        line: int,
        state: PlanState,
        n_cycles: int,
        lims: Limits3,
        reference: np.ndarray | None = None,
    ) -> Segment:
        """A segment holding the TCP (WAIT: ``n_cycles``; RECONFIGURATION: open-ended)."""
        ref = None
        if reference is not None:
            ref = ReferencePath(np.array([0.0]), reference[None, :])
        profile = Trapezoid(n_cycles * state.dt, 0.0, 0.0)
        return Segment(kind, line, Hold(state.tcp.copy()), profile, n_cycles, lims, ref)

    # PTP ------------------------------------------------------------------
    def _plan_ptp(self, cmd, options, state: PlanState, lims: Limits3) -> list[Segment]:
        out = []
        q0 = state.q
        frozen = self.frozen_si(options)
        platform = self.model.platform
        if cmd.platform_target is not None:  # the pose search holds the platform at it
            at = platform.joints_for(np.asarray(cmd.platform_target) * units.MM)
            frozen.update({j: float(at[j]) for j in platform.joints})
        for target in cmd.targets:
            q1 = self._ptp_target(cmd, target, q0, frozen, lims, state)
            self.check_inside(q1, lims[0], cmd.line, "PTP target")
            for j, v in frozen.items():
                if abs(q1[j] - v) > 1e-9 * (1.0 + abs(v)):
                    name = self.naming.label(j)
                    raise RunFailure(
                        f"PTP target moves the frozen joint {name} "
                        f"(held at {format_joint_value(self.model, j, v, 0)}, target "
                        f"{format_joint_value(self.model, j, q1[j], 0)})",
                        cmd.line,
                    )
            seg = self.joint_profile(cmd, state.motion, q0, q1, lims, len(cmd.targets))
            if cmd.platform_target is not None:  # a straight line too: θ_a moves linearly
                seg.platform = platform_lines(platform, q0, cmd.platform_target, [1.0])[0]
            out.append(seg)
            q0 = q1
        return out

    def _ptp_target(self, cmd, target, q0, frozen, lims, state) -> np.ndarray:
        if cmd.kind == "PTPINC":
            return q0 + self.joints_si(target)
        if isinstance(target, JointTuple):
            return self.joints_si(target)
        if isinstance(target, Pose):
            world = self.world(target, state, cmd.line)
            reach = self.reach(lims[0], frozen, state.tool, state.motion.path_tol * units.MM)
            return solve_ptp_pose(reach, world, q0, cmd.line, state.time)
        raise RunFailure(f"MOVE PTP: unsupported target {type(target).__name__}", cmd.line)

    def ptp_jerks(self, motion: MotionValues, accel: np.ndarray, line: int = 0) -> np.ndarray:
        """Per-joint jerk bounds of an S-curve PTP (SI, before ``R_ACC_PTP``): the robot
        file's ``jerk`` where it gives one, else ``θ̈max_i · R_JERK / R_ACC`` — the joint
        builds up its (active) acceleration bound ``accel`` in the time ``R_ACC / R_JERK``
        the path takes for its own."""
        r_acc, r_jerk = motion.acc, motion.jerk
        known = self.model.jerk_limits * motion.k  # × R_ACC_PTP: k³ in all
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            jerks = np.where(np.isnan(known), accel * r_jerk / r_acc, known)
        for j in np.flatnonzero(~(np.isfinite(jerks) & (jerks > 0.0))):
            raise RunFailure(  # a subnormal R_JERK, or an R_ACC so small the jerk overflows
                f"the motion cannot be planned: joint {self.naming.label(int(j))}'s jerk "
                f"bound θ̈max·R_JERK/R_ACC is {float(jerks[j]):.3g} in SI units (R_JERK "
                f"{r_jerk:.3g} mm/s³, R_ACC {r_acc:.3g} mm/s²): an S-curve needs a positive, "
                "finite jerk",
                line,
            )
        return jerks

    def joint_profile(
        self, cmd: MotionCommand, motion: MotionValues, q0, q1, lims: Limits3, npts: int = 1
    ) -> Segment:
        """The synchronised joint motion ``q0 → q1`` (SI) of a PTP (or of RECONFIGURATION's
        reference): joint ``i`` may use ``R_SPEED_PTP % · θ̇max_i`` and ``R_ACC_PTP % ·
        θ̈max_i`` of the active limits ``lims``, the slowest joint sets the time (module
        doc); ``npts`` is the number of points of the statement (``WITH TIME`` needs one)."""
        _, spd, acc = lims
        delta = q1 - q0
        dt = motion.ipo
        pct_v = motion.speed_ptp / 100.0
        pct_a = motion.acc_ptp / 100.0
        vmax = np.where(delta >= 0.0, spd[:, 1], -spd[:, 0]) * pct_v
        accel = np.minimum(acc[:, 1], -acc[:, 0])
        amax = accel * pct_a
        jmax = self.ptp_jerks(motion, accel, cmd.line) * pct_a if motion.scurve else None
        for j in np.flatnonzero(np.abs(delta) > 0.0):
            if not (vmax[j] > 0.0 and amax[j] > 0.0):
                name = self.naming.label(j)
                raise RunFailure(
                    f"PTP: joint {name} must move but its active speed/acceleration limits "
                    "do not allow motion in that direction",
                    cmd.line,
                )
        b = segment_bounds(np.abs(delta), vmax, amax, jmax)
        if self.motors is not None:
            b = motor_bounds(
                b, self.motors, self.motors.ptp_rates(q0, q1), pct_v, pct_a, self.model.n
            )
        slowest = b.slowest
        limiting = ""
        if slowest >= 0:
            jerk = "/jerk" if b.jerk is not None else ""
            n = self.model.n
            axis = self.naming.label(slowest % n)
            limiting = f"joint {axis} speed/acceleration{jerk}"
            if slowest >= n:
                limiting = f"motor of {axis} speed/acceleration"
                slowest -= n
        duration = with_time(motion, npts, cmd.line)
        profile = segment_profile(b, duration, dt, cmd.line, self.max_duration, limiting)
        seg = Segment(
            "ptp",
            cmd.line,
            JointLine(q0.copy(), q1.copy()),
            profile,
            cycles(profile.duration, dt),
            lims,
            None,
            limiting,
            slowest,
        )
        moving = profile.duration > 0.0
        seg.peaks = JointPeaks(
            np.abs(delta) * (profile.cruise if moving else 0.0),
            np.abs(delta) * (profile.accel if moving else 0.0),
        )
        return seg

    def _path_motor_rates(self, path, q, lims, state: PlanState, line):
        """``(D_m, q_end)`` of a Cartesian path (:meth:`MotorLimits.path_rates`, solved
        with the PTP pose solver); ``(None, q)`` where a point of the path has no solution
        (the IK's motor rows still bound every cycle; the run reports it)."""
        reach = self.reach(lims[0], {}, state.tool, state.motion.path_tol * units.MM)
        try:
            return self.motors.path_rates(
                path.at, q, lambda pose, seed: solve_ptp_pose(reach, pose, seed, line, state.time)
            )
        except RunFailure:
            return None, q

    # LIN ------------------------------------------------------------------
    def _plan_lin(self, cmd, state: PlanState, lims) -> list[Segment]:
        if cmd.kind == "LININC":
            poses = [state.tcp @ values.pose_to_matrix(t) for t in cmd.targets]
            for p in poses:
                check_coordinates(p, "MOVE_INC LIN target", cmd.line)
        else:
            poses = [self.world(t, state, cmd.line) for t in cmd.targets]
        paths, start = [], state.tcp
        for p in poses:
            paths.append(CartesianLine(start.copy(), p))
            start = p
        return self._cartesian_segments(cmd, state, lims, paths, "lin")

    def _plan_circle(self, cmd, state: PlanState, lims) -> list[Segment]:
        if len(cmd.targets) != 2:
            raise RunFailure("MOVE CIRCLE needs a via point and a target", cmd.line)
        via, target = (self.world(t, state, cmd.line) for t in cmd.targets)
        try:
            arc = CartesianArc(state.tcp.copy(), via[:3, 3].copy(), target)
        except CircleError as exc:
            raise RunFailure(f"MOVE CIRCLE: {exc}", cmd.line) from None
        return self._cartesian_segments(cmd, state, lims, [arc], "circle")

    def _cartesian_segments(self, cmd, state, lims, paths, kind) -> list[Segment]:
        motion = state.motion
        speed = motion.speed * units.MM
        acc = motion.acc * units.MM
        w = motion.speed_ori * units.DEG
        if not (speed > 0.0 and acc > 0.0 and w > 0.0):  # a denormal setting underflowed in SI
            raise RunFailure(
                "the path speed, acceleration or orientation speed is too small to move "
                "(it underflows to zero in SI units)",
                cmd.line,
            )
        w_acc = w * acc / speed
        jerks = None
        if motion.scurve:
            jerk = motion.jerk * units.MM
            jerks = [jerk, w * jerk / speed]
            if not all(0.0 < b < math.inf for b in jerks):
                raise RunFailure(
                    "the path jerk (R_JERK, and R_SPEED_ORI·R_JERK/R_SPEED for the orientation)"
                    " is too small to plan an S-curve with (it underflows to zero in SI units)",
                    cmd.line,
                )
        bounds = []
        q = state.q
        for path in paths:
            angle = path.angle if self.timed_orientation else 0.0
            b = segment_bounds([path.length, angle], [speed, w], [acc, w_acc], jerks)
            if self.motors is not None and b.slowest >= 0:
                rates, q = self._path_motor_rates(path, q, lims, state, cmd.line)
                if rates is not None:
                    k = motion.k
                    b = motor_bounds(b, self.motors, rates, k, k * k, axes=2)
            bounds.append(b)
        whats = [self._path_limiting(b, jerks is not None) for b in bounds]
        lines: list = [None] * len(paths)
        if cmd.platform_target is not None:  # the platform's own line, in step (platform_path)
            platform = self.model.platform
            lines = platform_lines(platform, state.q, cmd.platform_target,
                                   [p.length for p in paths])  # fmt: skip
            platform_jerks = None
            if motion.scurve:  # each joint's jerk bound as a PTP's (× k² more: k³ in all)
                accel = np.minimum(lims[2][:, 1], -lims[2][:, 0])
                all_jerks = self.ptp_jerks(motion, accel, cmd.line) * motion.k**2
                platform_jerks = all_jerks[list(platform.joints)]
            bounds, whats = platform_timing(
                bounds, whats, lines, platform, lims, motion.k, self.naming, platform_jerks
            )
        times = split_time(motion, [b.t_min for b in bounds], whats, cmd.line)
        refs = self._references(cmd, state.q, paths)
        out = []
        for path, b, t, ref, what, pl in zip(paths, bounds, times, refs, whats, lines,
                                             strict=True):  # fmt: skip
            if b.slowest < 0:  # zero-length segment: nothing to interpolate
                continue
            profile = segment_profile(b, t, state.dt, cmd.line, self.max_duration, what)
            out.append(
                Segment(
                    kind,
                    cmd.line,
                    path,
                    profile,
                    cycles(profile.duration, state.dt),
                    lims,
                    ref,
                    what,
                    with_time_s=motion.written_time,
                    platform=pl,
                )
            )
        return out

    def _path_limiting(self, b: Bounds, jerk: bool) -> str:
        """What sets a path segment's time: the path speed, the orientation speed or a
        motor (``""`` for a zero-length segment)."""
        if b.slowest < 0:
            return ""
        if b.slowest >= 2:  # a motor (_motor_bounds)
            return f"motor of {self.naming.label(b.slowest - 2)} speed/acceleration"
        if jerk:
            return ("path speed/acceleration/jerk", "orientation speed")[b.slowest]
        return ("path speed/acceleration", "orientation speed")[b.slowest]

    def _references(self, cmd, q_start, paths) -> list[ReferencePath | None]:
        """Per-segment θ⁰(s) for WITH RECONFIGURATION (``None`` without it)."""
        if not cmd.reconfiguration:
            return [None] * len(paths)
        configs = [self.joints_si(k) for k in cmd.reconfiguration]
        if len(configs) not in reconfiguration_counts(cmd.kind, len(cmd.targets)):
            raise RunFailure(
                f"WITH RECONFIGURATION gives {len(configs)} configurations for "
                f"{len(cmd.targets)} points",
                cmd.line,
            )
        if isinstance(paths[0], CartesianArc):
            knots = np.array([0.0, paths[0].via_fraction, 1.0])
            return [ReferencePath(knots, np.array([q_start, configs[0], configs[-1]]))]
        if len(configs) == 1 and len(paths) > 1:  # one for the whole LIN: spread by arc length
            lengths = np.array([max(p.length, 1e-12) for p in paths])
            frac = np.cumsum(lengths) / lengths.sum()
            configs = [q_start + f * (configs[0] - q_start) for f in frac]
        out, prev = [], q_start
        for k in configs:
            out.append(ReferencePath(np.array([0.0, 1.0]), np.array([prev, k])))
            prev = k
        return out

    # helpers --------------------------------------------------------------
    def reach(self, position: np.ndarray, frozen: dict[int, float], tool: np.ndarray,
              tol_position: float) -> Reach:  # fmt: skip
        """The pose search's context (:class:`~irlc.runtime.ik.reach.Reach`): the active
        position limits, frozen joints, the tool, this robot's task and naming, and the
        tolerances a pose counts as reached within (``R_PATH_TOL``, SI)."""
        return Reach(self.model, position, dict(frozen), tool, self.task_rows, self.naming,
                     tol_position, self.tol_orientation, self.limited)  # fmt: skip

    def world(self, pose: Pose, state: PlanState, line: int | None = None) -> np.ndarray:
        """A program POSE in the world (``R_BASE · pose``, SI), its coordinates checked."""
        if not isinstance(pose, Pose):
            raise RunFailure(f"expected a POSE target, got {type(pose).__name__}")
        check_coordinates(values.pose_to_matrix(pose), "MOVE target", line)
        world = state.base @ values.pose_to_matrix(pose)
        check_coordinates(world, "MOVE target in the world (with R_BASE)", line)
        return world
