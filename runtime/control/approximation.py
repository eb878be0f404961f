"""Approximate positioning in the simulated controller (``WITH APPROX`` / ``R_APPROX``):
which segment is pending, when it is blended into the next one or run to an exact stop,
and the report entry of each approximated point. The geometry (superposition, the
choice of the overlap) is :mod:`~irlc.runtime.plan.blending`; the cycles are the cycle
runner's (:mod:`~irlc.runtime.control.cycles`).

The controller uses :class:`ApproximatePositioning` through a small interface:

* :meth:`~ApproximatePositioning.distance` — a statement's blend distance (WITH APPROX,
  else R_APPROX);
* :meth:`~ApproximatePositioning.before_move` — a change of options, tool, base or IPO
  cycle ends the pending motion with an exact stop; LIN/CIRCLE → PTP: the joints the
  inverse transformation will give for the pending Cartesian tail are computed ahead
  (it is deterministic), so that the PTP is planned from their end and the two are
  superposed in joint space;
* :meth:`~ApproximatePositioning.start_point` — where the next motion starts (the
  pending segment's point);
* :meth:`~ApproximatePositioning.feed` runs a segment: blended with the pending one (if
  any), and itself left pending — its last cycles within ``min(APPROX, L/2)`` of its
  point — when its statement approximates; a blend the inverse transformation cannot
  follow is undone (:class:`BlendMark`: the controller state, the recorder and both
  segments' progress) and its distance bisected down to an exact stop;
* :meth:`~ApproximatePositioning.flush` ends the pending segment with an exact stop (the
  advance run stops: WAIT, WAIT FOR, input and R_ACT reads, options, the program's end);
* ``blends`` — the report's ``approximations``, one entry per approximated point.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from irlc.runtime.commands import MotionCommand
from irlc.runtime.control.cycles import CycleRunner
from irlc.runtime.control.segment_run import PendingSegment, RunMark, SegmentRun
from irlc.runtime.control.state import ControllerState
from irlc.runtime.control.statement_log import StatementLog
from irlc.runtime.errors import RunFailure
from irlc.runtime.outputs.recorder import Recorder
from irlc.runtime.plan.blending import (
    NO_OVERLAP,
    Overlap,
    blend_joints,
    blend_pose,
    choose_overlap,
    limit_distance,
    tail_cycles,
    within_joint_limits,
)
from irlc.runtime.plan.interpolator import Segment

_MIN_BLEND = 1e-4  # m: a blend shortened below this is an exact stop
_BISECTIONS = 5  # trials when a blend must be shortened (1/32 of the failed distance)


@dataclass(frozen=True)
class BlendMark:
    """What a tried blend changes, to undo it: the controller state, the recorder, the
    progress of the pending segment A and of the next segment B."""

    state: ControllerState
    recorder: tuple
    a: RunMark
    b: RunMark


class ApproximatePositioning:
    """The blender of the simulated controller (module docstring): it moves ``state``
    through ``cycles``, records in ``recorder`` and ends statement spans in ``log``."""

    def __init__(
        self,
        state: ControllerState,
        recorder: Recorder,
        cycles: CycleRunner,
        log: StatementLog,
    ):
        self.state, self.recorder, self.cycles, self.log = state, recorder, cycles, log
        self.blends: list[dict] = []  # one entry per approximated point (the report's)

    @property
    def pending(self) -> PendingSegment | None:
        return self.state.pending

    def flush(self, reason: str = "") -> None:
        """Ends the pending approximated motion with an exact stop at its point (the
        advance run stops: WAIT, WAIT FOR, an input read, R_ACT_POSE, a change of options,
        the end of the program); ``reason`` goes into the point's report entry."""
        st = self.state
        pending, st.pending = st.pending, None
        if pending is None:
            return
        self.cycles.run(pending.run, pending.run.seg.cycles)
        self.blends.append(pending.entry(None, pending.run.dt, reason or "exact stop"))
        self.log.end_at(pending.span, st.t, "exact")

    def before_move(self, cmd: MotionCommand, context: tuple) -> None:
        """Before a motion is planned: an exact stop when what a blend needs changed
        (``context``: options, tool, base, Δt); into a PTP from a Cartesian segment the
        pending tail's joints computed ahead (:meth:`_joint_chain`)."""
        pending = self.state.pending
        if pending is not None and pending.context != context:
            self.flush(self._pending_reason(cmd, context))
        pending = self.state.pending
        joint = cmd.kind in ("PTP", "PTPINC")
        if pending is not None and joint and not pending.run.seg.is_joint:
            try:  # LIN/CIRCLE → PTP: plan the PTP from the Cartesian segment's end joints
                self._joint_chain(pending)
            except RunFailure:  # it cannot be followed: run it (and fail) at its own line
                self.flush("the motion before cannot be followed")

    def start_point(self) -> tuple[np.ndarray | None, np.ndarray | None]:
        """``(joints, world TCP)`` where the next motion starts when a segment is pending
        (either may be ``None``: not known ahead); ``(None, None)`` when none is."""
        pending = self.state.pending
        if pending is None:
            return None, None
        seg = pending.run.seg
        if seg.is_joint:
            return seg.path.q1.copy(), None
        q = pending.chain[seg.cycles].copy() if pending.chain else None  # (_joint_chain)
        return q, seg.path.at(1.0).copy()

    def _pending_reason(self, cmd: MotionCommand, context) -> str:
        pending = self.state.pending
        old = pending.context if pending is not None else context
        if old[0] != context[0]:
            return f"the options changed before line {cmd.line} (exact stop)"
        return f"R_TOOL, R_BASE or R_IPO changed before line {cmd.line} (exact stop)"

    def feed(self, run: SegmentRun, approx: float, context, point: int) -> None:
        """Run segment ``run``: blended with the pending one if any, and itself left
        pending (its last cycles within ``APPROX`` of its point) when ``approx > 0``."""
        seg, st = run.seg, self.state
        length = self._seg_length(run)
        reserve = 0
        if approx > 0.0:
            d_own = limit_distance(approx, length, length)
            reserve = tail_cycles(self._remaining(run, d_own), d_own)
        pending, st.pending = st.pending, None
        if pending is not None:
            overlap = self._blend(pending, run, length, reserve)
            self.blends.append(pending.entry(overlap, run.dt, pending.limit_reason))
            self.log.end_at(pending.span, pending.handover)  # A's span ends where B starts
        if approx > 0.0:
            self.cycles.run(run, max(run.done, seg.cycles - reserve))
            span = len(self.log.spans)  # where its statement's span will be logged
            st.pending = PendingSegment(run, approx, length, context, point, span)
        else:
            self.cycles.run(run, seg.cycles)

    # ------------------------------------------------------------------ blending

    def _blend(self, pending: PendingSegment, run: SegmentRun, length: float, reserve: int):
        """Runs the pending segment's rest and the blend into ``run``. A blend the inverse
        transformation cannot follow within the limits and options (a RunFailure in its
        cycles) is undone and shortened: the longest distance that works is bisected
        between 0 (an exact stop) and the one that failed (``_BISECTIONS`` trials, each
        undone but the last, which is kept when it is the one to run), then run; a failure
        of the exact stop itself is the motion's own."""
        overlap_for = self._overlaps(pending, run, length, reserve)
        overlap = overlap_for(math.inf)
        failure = self._try_blend(pending, run, overlap, keep=True)
        if failure is None:
            return overlap
        pending.limit_reason = f"shortened: the longer blend failed ({failure.message})"
        good, bad = 0.0, overlap.used
        for i in range(_BISECTIONS):
            cap = 0.5 * (good + bad)
            trial = overlap_for(cap)
            last = i == _BISECTIONS - 1 and cap > _MIN_BLEND  # the one run below: keep it
            if trial.cycles and self._try_blend(pending, run, trial, keep=last) is not None:
                bad = cap
            else:
                good = cap
                if last and trial.cycles:
                    return trial
        while True:
            final = overlap_for(good if good > _MIN_BLEND else 0.0)
            if self._try_blend(pending, run, final, keep=True) is None:
                return final
            good = 0.5 * final.used  # not reproduced (never seen): keep halving

    def _try_blend(self, pending: PendingSegment, run: SegmentRun, overlap: Overlap, *, keep: bool):
        """Runs the rest of A and the blend; ``None`` if it worked (undone unless
        ``keep``), else the failure, undone. An exact stop's failure is raised."""
        mark = self._mark(pending.run, run)
        try:
            self.cycles.run(pending.run, pending.run.seg.cycles - overlap.cycles)
            pending.handover = self.state.t  # B's first cycle follows
            self._blend_cycles(pending, run, overlap.cycles)
        except RunFailure as exc:
            if overlap.cycles == 0:
                raise
            self._rewind(mark, pending.run, run)
            return exc
        else:
            if not keep:
                self._rewind(mark, pending.run, run)
            return None
        finally:
            self.recorder.release(mark.recorder)  # its samples may be spilled (recorder.py)

    def _mark(self, a_run: SegmentRun, b_run: SegmentRun) -> BlendMark:
        return BlendMark(self.state.snapshot(), self.recorder.mark(), a_run.mark(), b_run.mark())

    def _rewind(self, mark: BlendMark, a_run: SegmentRun, b_run: SegmentRun) -> None:
        self.state.restore(mark.state)
        self.recorder.rewind(mark.recorder)
        a_run.restore(mark.a)
        b_run.restore(mark.b)

    def _seg_length(self, run: SegmentRun) -> float:
        """Path length of the TCP (m): the chord for PTP."""
        seg = run.seg
        if seg.is_joint:
            tcp = run.solver.kin.tcp
            return float(np.linalg.norm(tcp(seg.path.q1)[:3, 3] - tcp(seg.path.q0)[:3, 3]))
        return float(getattr(seg.path, "length", 0.0))

    def _remaining(self, run: SegmentRun, d: float) -> list[float]:
        """TCP distance to the segment's end ``i`` cycles before it, ``i = 0, 1, …``,
        until it exceeds ``d``."""
        seg = run.seg
        end = self._seg_point(run, seg.cycles)
        out = []
        for i in range(seg.cycles + 1):
            dist = float(np.linalg.norm(self._seg_point(run, seg.cycles - i) - end))
            out.append(dist)
            if dist > d:
                break
        return out

    def _seg_point(self, run: SegmentRun, k: int) -> np.ndarray:
        """TCP position (m) of cycle ``k`` of the segment (``k = 0``: its start)."""
        seg = run.seg
        s = 0.0 if k <= 0 else seg.setpoint(k, run.dt)[0]
        x = seg.path.at(s)
        if seg.is_joint:
            return run.solver.kin.tcp(x)[:3, 3]
        return x[:3, 3]

    def _overlaps(
        self, pending: PendingSegment, run: SegmentRun, length: float, reserve: int
    ) -> Callable[[float], Overlap]:
        """The overlap of the pending segment A with the next segment B (blending.py) as a
        function of a cap on its distance (``inf``, or a shortened retry's). What every
        cap shares — A's remaining cycles and B's first ones as offsets from the corner,
        the speed cap — is computed once, for the uncapped distance ``d``; a capped
        distance uses the first rows of B's offsets, exactly those its own computation
        would stop at (:meth:`_Tails.upto`)."""
        a_run, seg_a, seg_b = pending.run, pending.run.seg, run.seg
        d_max = limit_distance(pending.approx, pending.length, length)
        m_a = seg_a.cycles - a_run.done
        m_b = max(0, seg_b.cycles - reserve)
        tails: list[_Tails] = []

        def overlap(cap: float = math.inf) -> Overlap:
            if d_max < pending.approx and not pending.limit_reason:
                pending.limit_reason = "shortened to half of a neighbouring segment"
            d = min(d_max, cap)
            pending.limit = d
            if d <= 0.0 or m_a <= 0 or m_b <= 0:
                if d_max <= 0.0:  # a shortened retry's cap of 0 keeps its own reason
                    pending.limit_reason = "a neighbouring segment has no TCP path length"
                return NO_OVERLAP
            if not tails:
                tails.append(self._tails(pending, run, m_a, m_b, d_max))
            if seg_b.is_joint:
                return self._joint_overlap(pending, run, tails[0], d)
            a, b, _, cap_speed = tails[0].upto(d)
            return choose_overlap(a, b, d, speed_cap=cap_speed, dt=run.dt)

        return overlap

    def _tails(self, pending: PendingSegment, run: SegmentRun, m_a: int, m_b: int, d: float):
        """A's last ``m_a`` cycles and B's first ones up to ``d`` (:class:`_Tails`): TCP
        offsets from the corner; into a PTP also the joint offsets from A's end joints
        ``θ₁`` (superposed in joint space, TCP by FK, B followed until 2 cycles beyond ``d``
        for the limits check); into a Cartesian segment the speed cap, the faster
        segment's peak TCP speed."""
        seg_a, seg_b, big_k = pending.run.seg, run.seg, pending.run.seg.cycles
        if seg_b.is_joint:
            q1 = self._a_joints(pending, big_k)
            qa = np.array([self._a_joints(pending, big_k - i) - q1 for i in range(m_a + 1)])
            tcp = run.solver.kin.tcp
            p1 = tcp(q1)[:3, 3]
            a = np.array([tcp(q1 + x)[:3, 3] - p1 for x in qa])
            qb_list, b_list = [0.0 * q1], [0.0 * p1]
            for j in range(1, m_b + 1):  # B's start, until 2 cycles beyond d (limits check)
                qb_list.append(seg_b.setpoint(j, run.dt)[1] - q1)
                b_list.append(tcp(q1 + qb_list[-1])[:3, 3] - p1)
                if len(b_list) > 3 and min(np.linalg.norm(x) for x in b_list[-3:]) > d:
                    break
            return _Tails(a, np.array(b_list), 3, joints=(q1, qa, np.array(qb_list)))
        corner = self._a_pose(pending, big_k)[:3, 3]
        a = np.array([self._a_pose(pending, big_k - i)[:3, 3] - corner for i in range(m_a + 1)])
        b_list = [0.0 * corner]
        for j in range(1, m_b + 1):  # B's start, until it is farther than d
            b_list.append(self._seg_point(run, j) - corner)
            if np.linalg.norm(b_list[-1]) > d:
                break
        if seg_a.is_joint:  # a PTP has no programmed path speed: its TCP's in this tail
            v_a = float(np.max(np.linalg.norm(np.diff(a, axis=0), axis=1), initial=0.0))
            v_a /= run.dt
        else:
            v_a = _peak_speed(seg_a, pending.run.dt)
        return _Tails(a, np.array(b_list), 1, speed_cap=max(v_a, _peak_speed(seg_b, run.dt)))

    def _joint_overlap(self, pending: PendingSegment, run: SegmentRun, tails: _Tails, d: float):
        """The overlap into a PTP segment: joints superposed, TCP distances by FK, the
        joint limits of both segments checked (:meth:`_joint_blend_ok`)."""
        a, b, (q1, qa, qb), _ = tails.upto(d)
        tcp = run.solver.kin.tcp
        p1 = tcp(q1)[:3, 3]
        far: dict[int, float] = {}

        def check(m: int) -> bool:
            j = np.arange(1, m + 1)
            blended = q1 + qa[m - j] + qb[j]
            dist = max(float(np.linalg.norm(tcp(q)[:3, 3] - p1)) for q in blended)
            far[m] = dist
            return dist <= d + 1e-12 and self._joint_blend_ok(pending, run, qa, qb, q1, m)

        overlap = choose_overlap(a, b, d, check, superposed=False)
        if overlap.cycles:
            overlap = dataclasses.replace(
                overlap, max_distance=max(overlap.max_distance, far[overlap.cycles])
            )
        return overlap

    def _blend_cycles(self, pending: PendingSegment, run: SegmentRun, m: int) -> None:
        """The ``m`` overlapping cycles of the pending segment's end and the next
        segment's start (blending.py); the samples carry the next statement's line. Into
        a PTP segment the joints are superposed and set directly; into a Cartesian one
        the poses (a PTP's by forward kinematics) are, followed by the inverse
        transformation."""
        a_run, st, cycles = pending.run, self.state, self.cycles
        seg_b, dt = run.seg, run.dt
        big_k = a_run.seg.cycles
        cycles.start(run)
        st.active_obstacles = run.obstacles
        k0 = len(self.recorder)
        if seg_b.is_joint:
            q1 = self._a_joints(pending, big_k)
            if pending.chain and m:
                self._check_chain(pending, big_k - m, seg_b.line)
            for j in range(1, m + 1):
                qa = self._a_joints(pending, big_k - m + j)
                _, qb = seg_b.setpoint(j, dt)
                cycles.joint_cycle(seg_b, blend_joints(qa, qb, q1), j, dt, run.solver, False)
            st.last_reference = None
        else:
            corner = self._a_pose(pending, big_k)
            opts, reference = run.cycle_opts, run.reference
            for j in range(1, m + 1):
                xa = self._a_pose(pending, big_k - m + j)
                s, xb = seg_b.setpoint(j, dt)
                if reference is not None:
                    opts.reference = reference.at(s)
                cycles.ik_cycle(seg_b, blend_pose(xa, xb, corner), dt, opts, run.solver)
            st.last_reference = opts.reference
        a_run.done, run.done = big_k, max(run.done, m)
        if m:
            tcp = self.recorder.rows("tcp", max(k0 - 1, 0), k0 + m)[:, :3, 3]
            speeds = np.linalg.norm(np.diff(tcp, axis=0), axis=1) / dt
            pending.min_speed = float(speeds.min()) if speeds.size else 0.0
            pending.start_time = float(self.recorder.rows("times", max(k0 - 1, 0), k0)[0])

    def _check_chain(self, pending: PendingSegment, k: int, line: int) -> None:
        """The joints computed ahead for a Cartesian segment are those it reached (the
        inverse transformation is deterministic); a difference would be a jump."""
        gap = float(np.max(np.abs(self.state.q - pending.chain[k])))
        if gap > 1e-9:
            self.recorder.warnings.append(
                f"line {line}: the blend into the PTP starts {gap:.3g} (rad | m) away from "
                "the joints computed ahead for the motion before it"
            )

    def _a_joints(self, pending: PendingSegment, k: int) -> np.ndarray:
        """Joints of the pending segment at its cycle ``k``: a PTP's setpoint, else the
        inverse transformation's (:meth:`_joint_chain`)."""
        seg = pending.run.seg
        if seg.is_joint:
            return seg.setpoint(k, pending.run.dt)[1] if k > 0 else seg.path.q0
        return pending.chain[k]

    def _a_pose(self, pending: PendingSegment, k: int) -> np.ndarray:
        """World TCP pose of the pending segment at its cycle ``k`` (a PTP's by FK)."""
        seg = pending.run.seg
        if seg.is_joint:
            return pending.run.solver.kin.tcp(self._a_joints(pending, k))
        return seg.setpoint(k, pending.run.dt)[1] if k > 0 else seg.path.at(0.0)

    def _joint_chain(self, pending: PendingSegment) -> None:
        """The joints the inverse transformation will give for the pending Cartesian
        segment's remaining cycles (it is deterministic: the same steps from the same
        state), so that a PTP can be planned from its end and blended in joint space."""
        run = pending.run
        seg, dt = run.seg, run.dt
        self.cycles.start(run)
        opts, reference = run.cycle_opts, run.reference
        saved = opts.reference
        q, q_prev = self.state.q.copy(), self.state.q_prev.copy()
        chain = {run.done: q}
        try:
            for k in range(run.done + 1, seg.cycles + 1):
                s, target = seg.setpoint(k, dt)
                if reference is not None:
                    opts.reference = reference.at(s)
                res = run.solver.ik.step(q, q_prev, target, dt, opts)
                q_prev, q = q, res.q
                chain[k] = q
        finally:
            opts.reference = saved
        pending.chain = chain

    def _joint_blend_ok(self, pending, run, qa, qb, q1, m: int) -> bool:
        """Joint blend ``m`` within the position, speed and acceleration limits of both
        segments (with one cycle either side, to include the switch in and out)."""
        la, lb = pending.run.seg.limits, run.seg.limits
        boxes = [np.column_stack((np.fmax(a[:, 0], b[:, 0]), np.fmin(a[:, 1], b[:, 1])))
                 for a, b in zip(la, lb, strict=True)]  # fmt: skip
        j = np.arange(1, m + 1)
        before = [q1 + qa[i] for i in (m + 1, m) if i < len(qa)]
        after = [q1 + qb[i] for i in (m + 1, m + 2) if i < len(qb)]
        seq = np.array([*before, *(q1 + qa[m - j] + qb[j]), *after])
        return within_joint_limits(seq, run.dt, *boxes)


@dataclass(frozen=True)
class _Tails:
    """What every trial overlap of one blend shares (:meth:`ApproximatePositioning.
    _overlaps`): ``a[i]`` A's TCP offset from the corner ``i`` cycles before its end,
    ``b[j]`` B's after its ``j``-th cycle (m, rows), collected until B is farther than the
    uncapped distance for ``last`` consecutive cycles (1 Cartesian, 3 into a PTP); into a
    PTP the joints ``(θ₁, θ_A − θ₁, θ_B − θ₁)``, else the blended speed cap (m/s)."""

    a: np.ndarray
    b: np.ndarray
    last: int
    joints: tuple | None = None
    speed_cap: float | None = None
    distances: np.ndarray = field(init=False, repr=False)  # |b[j]|, once

    def __post_init__(self) -> None:
        norms = np.array([np.linalg.norm(x) for x in self.b])
        object.__setattr__(self, "distances", norms)

    def upto(self, d: float) -> tuple[np.ndarray, np.ndarray, tuple | None, float | None]:
        """``(a, b, joints, speed_cap)`` with B's rows cut where a computation for the
        distance ``d`` (≤ the uncapped one) stops: after the first ``j`` (``j ≥ last``)
        whose ``last`` rows ending at ``j`` are all farther than ``d``."""
        far = self.distances > d
        n = len(self.b)
        for j in range(self.last, len(self.b)):
            if far[j - self.last + 1 : j + 1].all():
                n = j + 1
                break
        joints = self.joints
        if joints is not None:
            joints = (joints[0], joints[1], joints[2][:n])
        return self.a, self.b[:n], joints, self.speed_cap


def _peak_speed(seg: Segment, dt: float) -> float:
    """The largest TCP path speed of a Cartesian segment (m/s): its profile's largest
    ``Δs/Δt`` on the IPO grid times its path length (any profile shape)."""
    s = [seg.setpoint(k, dt)[0] for k in range(seg.cycles + 1)] if seg.cycles else [0.0]
    s[0] = 0.0
    steps = np.diff(np.array(s))
    return float(steps.max(initial=0.0)) / dt * float(getattr(seg.path, "length", 0.0))
