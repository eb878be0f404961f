"""The Python side of the compiled drive loop (``pip install 'irlc[fast]'``: numba).

The numpy loop of :mod:`..simulate` is the reference and the default. With the compiled
engine, :class:`CompiledLoop` runs the same steps through the kernels: at the coupled
level the whole run is one call of :func:`.kernels.run_segment`, which refreshes
``M(q)``, ``C q̇ + G``, the transmission's rotor matrix and ``M⁻¹`` inside
(:mod:`..refresh`'s policy) from the packed public data (``Kinematics.chain_data``,
``Dynamics.data``, ``Transmission.data``); at the decoupled level
:func:`.kernels.run_segment` runs from one refresh of ``G(q)`` to the next and
numpy refreshes it. Results equal the numpy path to rounding (tested in
``tests/drives/test_compiled_loop.py``).

Covered: DC drives with the averaged power stage (``decoupled``, ``coupled``) on robots
whose joints are all driven, any transmission (plain ratios, linear couplings, screw
levers), friction, both refresh policies. Not covered (the numpy loop runs): ``pwm``
(:mod:`.pwm_loop`), stepper drives, joints without drive data (prescribed motion).

When it is used: :func:`irlc.runtime.engine.compiled_loop` — ``simulate_drives(...,
accel=True)`` always (compiling if needed, ≈ 10–20 s once per install; numba caches the
machine code), ``False`` never, ``None`` (default) as ``IRLC_ENGINE=numpy|compiled|auto``
says (numpy when unset), as for the IK cycle. ``irlc warmup`` compiles ahead of the first
run.
"""

from __future__ import annotations

import numpy as np
from irlc.runtime import accel_support
from irlc.runtime.model.kinematics import Kinematics

KERNELS = accel_support.Kernels("irlc.runtime.drives.compiled.kernels", "run_segment")
"""The drive kernels (loaded, and compiled when numba's cache lacks them, on first use)."""


def _read_only(a: np.ndarray) -> np.ndarray:
    a.flags.writeable = False
    return a


def axis_parameters(k, c, frc, band) -> np.ndarray:
    """The per-axis constants ``par`` (m, ``k.N_PAR``) of the averaged kernel (module ``k``):
    the DC chain ``c`` (``DcDrives``), the motor-side friction ``frc`` and the stick band."""
    par = np.zeros((len(c.kz), k.N_PAR))
    for idx, value in (
        (k.KZ, c.kz), (k.KE, c.ke), (k.KP, c.kp), (k.KI, c.ki), (k.ULIM, c.u_ref_max),
        (k.R, c.R), (k.L, c.L), (k.KS, c.ks), (k.U, c.U), (k.IMAX, c.i_max),
        (k.RUN_M, frc.running), (k.VISC_M, frc.viscous), (k.BAND, band),
    ):  # fmt: skip
        par[:, idx] = value
    return par


class CompiledLoop:
    """The constant arrays of one drive simulation (``simulate._Simulation``) for the
    kernel."""

    def __init__(self, sim, bank, static_j, running_j, sticky: bool, sliding: bool):
        k = self.layout_module()
        self.k, self.sim, self.bank = k, sim, bank
        self.par = axis_parameters(k, sim.p.chain, sim.p.friction, sim.band)
        self.trans = sim.trans.data  # the packed motor map (public, read-only)
        self.static_j, self.running_j = static_j, running_j
        self.ist = np.zeros(k.N_IST, dtype=np.int64)
        self.fst = np.array([sim.h, 0.0, 0.0])
        self.ist[k.STICKY], self.ist[k.SLIDING] = int(sticky), int(sliding)

    @staticmethod
    def layout_module():
        """The module of the kernel this loop runs and of the ``ist``/``fst`` layout (says
        on stderr that it compiles, when numba's cache lacks it)."""
        return KERNELS.load()

    def _refresh(self, q, qd, mm, hb, m_inv) -> None:
        """``D``, ``G(q)`` and ``D⁻¹`` of the decoupled level (``Mechanics.terms``; the
        coupled level refreshes inside the kernel, :meth:`_terms`)."""
        m_new, hb[:] = self.sim.mech.terms(q, qd)
        if m_new.ndim == 1:  # plain ratios: D diagonal
            mm[:] = np.diag(m_new)
            m_inv[:] = np.diag(1.0 / m_new)
        else:
            mm[:] = m_new
            m_inv[:] = np.linalg.inv(m_new)

    def _terms(self) -> tuple:
        """``(chain, dyn, J_m)`` for the refresh inside :func:`.kernels.run_segment`:
        the packed chain (``Kinematics.chain_data``: basis, joints, base), the packed
        inertial data (``Dynamics.data``, rotors of plain ratios on its diagonal) and the
        motor inertias of the rotor matrix ``Kᵀ diag(J_m) K``. Without inertial data
        (decoupled with ``load_inertia``; never refreshed inside) empty read-only arrays
        of the same kinds (one compiled specialisation)."""
        mech = self.sim.mech
        c = Kinematics(self.sim.model).chain_data
        if mech.dyn is not None:
            d = mech.dyn.data
            dyn = (d.axes, d.revolute, d.rotor, d.mass, d.com, d.inertia, d.gravity)
        else:
            dyn = tuple(_read_only(np.zeros(s)) for s in ((0, 3), 0, 0, 0, (0, 3), (0, 3, 3), 3))
        j_m = np.array(self.sim.p.chain.J_m, dtype=float)
        return (c.basis, c.joints, c.ends[0]), dyn, j_m

    @staticmethod
    def covers(sim) -> bool:
        """Is this simulation inside the kernel's scope (module docstring)?"""
        return (
            sim.is_dc
            and not sim.pwm
            and sim.driven.all()
            and np.array_equal(sim.axes, np.arange(sim.n))
        )

    def _start(self, ist, fst, refresh) -> tuple[int, tuple]:
        """The run's steps and refresh policy into the packed ``ist``/``fst`` (the layout of
        :mod:`.kernels`, which the PWM kernel shares) and zeroed ``(M, h, M⁻¹)``
        buffers for the kernel to fill."""
        k, n = self.k, self.sim.n
        steps = len(self.sim.t)
        ist[k.STEPS] = steps
        ist[k.EVERY] = 0 if refresh.every is None else refresh.every
        ist[k.MAX_STEPS] = refresh.max_steps
        fst[k.DQ], fst[k.DV] = refresh.dq, refresh.dv
        return steps, (np.zeros((n, n)), np.zeros(n), np.zeros((n, n)))

    def run(self, q, qd, theta_ref, refresh, rec, rec_i, rec_u, sat_rec, energy, copper):
        """All steps; ``q``, ``qd``, the records and the bank's state are updated in place."""
        k, sim, bank = self.k, self.sim, self.bank
        ist, fst = self.ist, self.fst
        steps, (mm, hb, m_inv) = self._start(ist, fst, refresh)
        xv = np.ascontiguousarray(bank.pi.x, dtype=float).copy()
        xiu = bank.loop.x.copy()
        xi, xu = np.ascontiguousarray(xiu[:, 0]), np.ascontiguousarray(xiu[:, 1])
        theta_ref = np.ascontiguousarray(theta_ref)
        mech = sim.mech
        inner = mech.coupled  # the refreshes run inside the kernel: one call
        ist[k.START], ist[k.FRESH], ist[k.S0], ist[k.COUNT] = 0, 0, refresh.s0, 0
        ist[k.INNER], ist[k.ROTOR] = int(inner), int(mech.rotor_extra is not None)
        args = (
            ist, fst, self.par, bank.fused, bank.limits, bank.loop.big, theta_ref,
            self.trans.linear, self.trans.rows, self.trans.angle, self.trans.lever,
            self.static_j, self.running_j,
            q, qd, xv, xi, xu, mm, hb, m_inv, refresh.q0, refresh.qd0,
            rec["q"], rec["qd"], rec["tau"], rec["f"], rec_i, rec_u, sat_rec, energy, copper,
            self._terms(),
        )  # fmt: skip
        while (s := k.run_segment(*args)) < steps:  # decoupled: G(q) refreshed in numpy
            self._refresh(q, qd, mm, hb, m_inv)
            refresh.mark(s, q, qd)
            ist[k.START], ist[k.FRESH], ist[k.S0] = s, 1, refresh.s0
        if inner:
            refresh.s0, refresh.count = int(ist[k.S0]), refresh.count + int(ist[k.COUNT])
        bank.loop.x[:, 0], bank.loop.x[:, 1] = xi, xu
        bank.pi.x = xv
