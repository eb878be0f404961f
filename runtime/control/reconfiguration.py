"""RECONFIGURATION k (self-motion) in the simulated controller.

The reference moves from the current configuration to ``k`` along a synchronised joint
profile (:meth:`~irlc.runtime.plan.preinterp.PreInterpolator.joint_profile`: PTP timing under
the active limits and ``R_SPEED_PTP``/``R_ACC_PTP``) while the TCP is held; after the
profile ends the reference stays at ``k`` and the statement ends at the first cycle with
``‖θ(t) − θ(t−Δt)‖ < ε_conf`` *and* ``‖θ(t−Δt) − θ(t−2Δt)‖ < ε_conf``
(``IKParams.eps_conf``; the second condition is our addition to seed 4.2.3, see
:func:`~irlc.runtime.ik.self_motion.reconfiguration_done`) or after ``settle_s``
seconds (a warning). The cycles are the cycle runner's (:mod:`~irlc.runtime.control.cycles`).
"""

from __future__ import annotations

import math

import numpy as np
from irlc.runtime.commands import ModalOptions, MotionCommand
from irlc.runtime.control.budget import RunBudget
from irlc.runtime.control.cycles import CycleRunner
from irlc.runtime.control.segment_run import Solver
from irlc.runtime.control.statement_log import StatementLog
from irlc.runtime.ik.self_motion import reconfiguration_done
from irlc.runtime.plan.interpolator import Segment
from irlc.runtime.plan.preinterp import PlanState, PreInterpolator
from irlc.runtime.values import JointTuple


class SelfMotion:
    """RECONFIGURATION of the simulated controller: plans the reference and runs the
    self-motion's cycles on ``cycles`` (module docstring), within ``budget``, logging
    the statement's span in ``log``."""

    def __init__(
        self,
        pre: PreInterpolator,
        cycles: CycleRunner,
        budget: RunBudget,
        log: StatementLog,
        *,
        eps_conf: float,
        settle_s: float,
    ):
        self.pre, self.cycles, self.budget, self.log = pre, cycles, budget, log
        self.eps_conf = eps_conf
        self.settle_s = settle_s

    def reconfigure(
        self,
        target: JointTuple,
        line: int,
        options: ModalOptions,
        solver: Solver,
        plan: PlanState,
    ) -> None:
        """Self-motion to ``target`` from ``plan`` (where the robot stands, with the
        statement's settings checked once: ``plan.motion``), the TCP held by ``solver``'s
        inverse transformation."""
        pre, st = self.pre, self.cycles.state
        lims = pre.limits((None, None, None), options, line)
        pre.check_inside(st.q, lims[0], line, "the limits exclude the current state")
        k = pre.joints_si(target)
        # reference profile: a synchronised joint move from here to k (PTP timing)
        cmd = MotionCommand("PTP", (target,), line)
        pre.check_inside(k, lims[0], line, "RECONFIGURATION target")
        dt = plan.dt
        ref_seg = pre.joint_profile(cmd, plan.motion, st.q, k, lims)
        hold = pre.hold("reconf", line, plan, 0, lims)
        cycle_opts = self.cycles.options_for(hold, options, plan.motion.criterion)
        cycle_opts.self_motion = True
        settle = max(1, math.ceil(self.settle_s / dt))
        # the time budget for the longest it may take; the cycle budget for the reference's
        # cycles now, each settling cycle when it is simulated (it usually settles at once)
        what = "the RECONFIGURATION"
        self.budget.check_time(st.t, (ref_seg.cycles + settle) * dt, line, what)
        self.budget.grant(ref_seg.cycles, ref_seg.cycles * dt, st.t, line, what)
        t0, stop = st.t, "failed"
        try:
            self._cycles(ref_seg, k, hold, cycle_opts, solver, dt, settle, line)
            stop = "exact"
        finally:
            limit = ref_seg.limiting
            self.log.add("RECONFIGURATION", line, t0, st.t, stop, limit, plan.motion.override)

    def _cycles(self, ref_seg: Segment, k, hold: Segment, cycle_opts, solver, dt, settle, line):
        """The self-motion's cycles: follow the reference, then settle (module doc)."""
        st, cycles = self.cycles.state, self.cycles
        k_cyc = 0
        while True:
            k_cyc += 1
            if k_cyc <= ref_seg.cycles:
                _, ref = ref_seg.setpoint(k_cyc, dt)
            else:
                what = "the RECONFIGURATION's settling"
                self.budget.grant(1, dt, st.t, line, what)
                ref = k
            cycle_opts.reference = ref
            q_prev2 = st.q_prev  # θ(t − 2Δt) after this cycle: the two-cycle rule
            cycles.ik_cycle(hold, hold.path.pose, dt, cycle_opts, solver)
            st.last_reference = np.array(ref, dtype=float)
            if k_cyc > ref_seg.cycles and reconfiguration_done(
                st.q, st.q_prev, self.eps_conf, q_prev2
            ):
                break
            if k_cyc > ref_seg.cycles + settle:
                cycles.recorder.warnings.append(
                    f"line {line}: RECONFIGURATION did not settle within "
                    f"{self.settle_s:g} s after its reference arrived"
                )
                break
