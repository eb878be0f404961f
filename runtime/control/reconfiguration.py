"""RECONFIGURATION k (self-motion) in the simulated controller.

The reference moves from the current configuration to ``k`` along a synchronised joint
profile (:meth:`~irlc.runtime.plan.preinterp.PreInterpolator.joint_profile`: PTP timing under
the active limits and ``R_SPEED_PTP``/``R_ACC_PTP``) while the TCP is held; after the
profile ends the reference stays at ``k`` and the statement ends at the first cycle with
``‖θ(t) − θ(t−Δt)‖ < ε_conf`` *and* ``‖θ(t−Δt) − θ(t−2Δt)‖ < ε_conf``
(``IKParams.eps_conf``; the second condition is our addition to seed 4.2.3, see
:func:`~irlc.runtime.ik.self_motion.reconfiguration_done`) or after ``reconf_settle_s``
seconds (a warning). The cycles themselves are the executor's
(:mod:`~irlc.runtime.control.executor`),
whose controller includes this class.
"""

from __future__ import annotations

import math

import numpy as np
from irlc.runtime import units
from irlc.runtime.commands import ModalOptions, MotionCommand, Settings
from irlc.runtime.ik.self_motion import reconfiguration_done
from irlc.runtime.plan.motion_values import motion_values
from irlc.runtime.values import JointTuple


class Reconfiguration:
    """The RECONFIGURATION statement of :class:`~irlc.runtime.control.executor.SimulatedController`
    (it provides ``flush``, ``pre``, ``recorder``, ``_solver``, ``_plan_state``,
    ``_cycle_options``, ``_within_budget``, ``_grant_cycles``, ``_ik_cycle``,
    ``_log_statement``, ``q``, ``q_prev``, ``_t``, ``opts``, ``ik_params``)."""

    def reconfigure(
        self, target: JointTuple, line: int, settings: Settings, options: ModalOptions
    ) -> None:
        self.flush(f"RECONFIGURATION at line {line}")
        self._line = line
        self.recorder.tol_position = settings.path_tol * units.MM  # R_PATH_TOL
        solver = self._solver(settings)
        # reference profile: a synchronised joint move from here to k (PTP timing)
        cmd = MotionCommand("PTP", (target,), line)
        motion = motion_values(cmd, settings, self.opts.ipo, self._t)
        self.dt_used = motion.ipo
        state = self._plan_state(settings, solver, motion)
        lims = self.pre.limits((None, None, None), options, line)
        self.pre.check_inside(self.q, lims[0], line, "the limits exclude the current state")
        k = self.pre.joints_si(target)
        self.pre.check_inside(k, lims[0], line, "RECONFIGURATION target")
        ref_seg = self.pre.joint_profile(cmd, motion, self.q, k, lims)
        hold = self.pre.hold("reconf", line, state, 0, lims)
        dt = state.dt
        cycle_opts = self._cycle_options(hold, options)
        cycle_opts.self_motion = True
        settle = max(1, math.ceil(self.opts.reconf_settle_s / dt))
        # the time budget for the longest it may take; the cycle budget for the reference's
        # cycles now, each settling cycle when it is simulated (it usually settles at once)
        what = "the RECONFIGURATION"
        self._within_budget((ref_seg.cycles + settle) * dt, line, what)
        self._grant_cycles(ref_seg.cycles, ref_seg.cycles * dt, line, what)
        t0, stop = self._t, "failed"
        try:
            self._reconf_cycles(ref_seg, k, hold, cycle_opts, solver, dt, settle, line)
            stop = "exact"
        finally:
            limit = ref_seg.limiting
            self._log_statement("RECONFIGURATION", line, t0, stop, limit, settings.override)

    def _reconf_cycles(self, ref_seg, k, hold, cycle_opts, solver, dt, settle, line) -> None:
        """The self-motion's cycles: follow the reference, then settle (module doc)."""
        k_cyc = 0
        while True:
            k_cyc += 1
            if k_cyc <= ref_seg.cycles:
                _, ref = ref_seg.setpoint(k_cyc, dt)
            else:
                self._grant_cycles(1, dt, line, "the RECONFIGURATION's settling")
                ref = k
            cycle_opts.reference = ref
            q_prev2 = self.q_prev  # θ(t − 2Δt) after this cycle: the two-cycle rule
            self._ik_cycle(hold, hold.path.pose, dt, cycle_opts, solver)
            self._last_reference = np.array(ref, dtype=float)
            if k_cyc > ref_seg.cycles and reconfiguration_done(
                self.q, self.q_prev, self.ik_params.eps_conf, q_prev2
            ):
                break
            if k_cyc > ref_seg.cycles + settle:
                self.recorder.warnings.append(
                    f"line {line}: RECONFIGURATION did not settle within "
                    f"{self.opts.reconf_settle_s:g} s after its reference arrived"
                )
                break
