"""Optional compiled loop of the ``pwm`` drive level (``pip install irlc[fast]``: numba).

The numpy loop of :mod:`.simulate` with :class:`.power_stage.PwmStage` is the reference and
the default. With numba, :class:`PwmLoop` runs the same PWM periods through
:func:`.accel_pwm_kernels.run_pwm_segment` and returns to Python only to refresh
``M(q)``, ``C q̇ + G`` (the refresh of :class:`.accel.AcceleratedLoop`, which it extends).
Results equal the numpy path to rounding (``tests/drives/test_accel_pwm.py``).

Covered: DC drives at ``pwm`` on robots whose joints are all driven, any transmission,
friction, both refresh policies. When it is used: :func:`.accel.use_accel` (``IRLC_ENGINE``;
numpy by default). ``python -m irlc.runtime.drives.accel_pwm`` (or ``irlc warmup``)
compiles ahead of the first run.
"""

from __future__ import annotations

import time

import numpy as np
from irlc.runtime import accel_support
from irlc.runtime.drives import accel

compile_seconds: float | None = None  # warm_up() of this process (compile or load)

_KERNELS = accel_support.Kernels("irlc.runtime.drives.accel_pwm_kernels", "run_pwm_segment")
cache_warm = _KERNELS.cache_warm


class PwmLoop(accel.AcceleratedLoop):
    """The constant arrays of one ``pwm`` :class:`~.simulate._Simulation` for the kernel."""

    def __init__(self, sim, bank, static_j, running_j, sticky: bool, sliding: bool):
        if accel.compile_seconds is None:  # the drive kernels (the refresh's), as on any
            accel.warm_up()  # accelerated drive run: compiled once, then loaded
        super().__init__(sim, bank, static_j, running_j, sticky, sliding)  # the refresh
        kp = self.kp = _KERNELS.load()
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


def warm_up() -> float:
    """Compile (or load from the cache) the PWM kernel by running a tiny ``pwm`` simulation
    on the irb6_track (screw levers, friction: every branch's types); returns the seconds."""
    global compile_seconds
    if compile_seconds is not None:
        return compile_seconds
    t0 = time.perf_counter()
    from irlc.robots import load_robot
    from irlc.runtime.drives.simulate import simulate_drives

    model = load_robot("irb6_track")
    q0 = np.asarray(model.home_q(), dtype=float)
    times = np.array([0.0, 0.005])
    simulate_drives(model, times, np.stack([q0, q0]), level="pwm", hold=0.0, accel=True)
    compile_seconds = time.perf_counter() - t0
    return compile_seconds


if __name__ == "__main__":  # python -m irlc.runtime.drives.accel_pwm: fill numba's cache once
    if not accel.AVAILABLE:
        raise SystemExit("numba is not installed (pip install 'irlc[fast]') or IRLC_ENGINE=numpy")
    warm = cache_warm()
    seconds = warm_up()
    print(f"irlc PWM drive accelerator: {'loaded' if warm else 'compiled'} in {seconds:.2f} s")
