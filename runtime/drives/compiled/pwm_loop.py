"""The Python side of the compiled loop of the ``pwm`` drive level (``pip install
'irlc[fast]'``: numba).

The numpy loop of :mod:`..simulate` with :class:`..power_stage.PwmStage` is the reference
and the default. With the compiled engine, :class:`PwmLoop` runs the same PWM periods
through :func:`.pwm_kernels.run_pwm_segment` and returns to Python only to refresh
``M(q)``, ``C q̇ + G`` (the refresh of :class:`.loop.CompiledLoop`, which it extends).
Results equal the numpy path to rounding (``tests/drives/test_compiled_pwm.py``).

Covered: DC drives at ``pwm`` on robots whose joints are all driven, any transmission,
friction, both refresh policies. When it is used: :func:`irlc.runtime.engine.compiled_loop`
(``IRLC_ENGINE``; numpy by default). ``irlc warmup`` compiles ahead of the first run.
"""

from __future__ import annotations

import numpy as np
from irlc.runtime import accel_support
from irlc.runtime.drives.compiled import loop
from irlc.runtime.drives.compiled.loop import CompiledLoop

KERNELS = accel_support.Kernels("irlc.runtime.drives.compiled.pwm_kernels", "run_pwm_segment")
"""The PWM kernel (loaded, and compiled when numba's cache lacks it, on first use)."""


class PwmLoop(CompiledLoop):
    """The constant arrays of one ``pwm`` drive simulation for the kernel."""

    def __init__(self, sim, bank, static_j, running_j, sticky: bool, sliding: bool):
        super().__init__(sim, bank, static_j, running_j, sticky, sliding)  # the refresh
        kp = self.kp = KERNELS.load()
        c, frc = sim.p.chain, sim.p.friction
        par = np.zeros((len(sim.axes), kp.N_PAR))
        for idx, value in (
            (kp.KZ, c.kz), (kp.KE, c.ke), (kp.KP, c.kp), (kp.KI, c.ki), (kp.ULIM, c.u_ref_max),
            (kp.R, c.R), (kp.L, c.L), (kp.KS, c.ks), (kp.U, c.U), (kp.IMAX, c.i_max),
            (kp.KC, c.k), (kp.KIWZM, c.kiwzm),
            (kp.RUN_M, frc.running), (kp.VISC_M, frc.viscous), (kp.BAND, sim.band),
        ):  # fmt: skip
            par[:, idx] = value
        self.pwm_par = par
        self.pwm_ist = np.zeros(kp.N_IST, dtype=np.int64)
        self.pwm_fst = np.zeros(kp.N_FST)
        self.pwm_fst[kp.H] = sim.h
        self.pwm_ist[kp.STICKY], self.pwm_ist[kp.SLIDING] = int(sticky), int(sliding)

    @staticmethod
    def layout_module():
        """The averaged loop's module, for the ``ist``/``fst`` layout the PWM kernel shares
        (its ``run_segment`` never runs here: nothing of it compiles)."""
        return loop.KERNELS.module()

    @staticmethod
    def covers(sim) -> bool:
        """DC drives at ``pwm``, every joint driven (module docstring)."""
        return (
            sim.is_dc
            and sim.pwm
            and sim.driven.all()
            and np.array_equal(sim.axes, np.arange(sim.n))
        )

    def run(self, q, qd, theta_ref, refresh, rec, rec_i, rec_u, sat_rec, energy, copper):
        """All periods; ``q``, ``qd``, the records and the PWM bank's state (PI integral,
        current, controller output) are updated in place."""
        kp, bank = self.kp, self.bank
        ist, fst = self.pwm_ist, self.pwm_fst
        steps, (mm, hb, m_inv) = self._start(ist, fst, refresh)
        stage = bank.stage
        xv = np.array(bank.pi.x, dtype=float)
        xi, xc = np.array(stage.i, dtype=float), np.array(stage.u_c, dtype=float)
        theta_ref = np.ascontiguousarray(theta_ref)
        trans = self.trans
        s, fresh = 0, 0
        while True:
            ist[kp.START], ist[kp.FRESH], ist[kp.S0] = s, fresh, refresh.s0
            s = kp.run_pwm_segment(
                ist, fst, self.pwm_par, theta_ref,
                trans.linear, trans.rows, trans.angle, trans.lever,
                self.static_j, self.running_j,
                q, qd, xv, xi, xc, mm, hb, m_inv, refresh.q0, refresh.qd0,
                rec["q"], rec["qd"], rec["tau"], rec["f"], rec_i, rec_u, sat_rec,
                energy, copper,
            )  # fmt: skip
            if s >= steps:
                break
            self._refresh(q, qd, mm, hb, m_inv)
            refresh.mark(s, q, qd)
            fresh = 1
        bank.pi.x, stage.i, stage.u_c = xv, xi, xc
