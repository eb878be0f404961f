"""The drive simulation: joint setpoints at IPO samples → what the robot actually does.

One fixed step ``h`` for all axes (vectorised across axes). Per step, DC drives::

    θ_ref → position P → velocity PI → [current controller + armature, exact over h]
          → τ_m = k_s ī → friction (Karnopp) → i·(τ_m − τ_f) → mechanics → q̈
    q̇ += h q̈,  q += h q̇          (semi-implicit Euler)

Levels (docs/drives.md): ``ideal`` (actual = setpoint), ``decoupled`` (constant diagonal
inertia + gravity), ``coupled`` (M, C, G), ``pwm`` (coupled + PWM with exact switching,
one step per PWM period). Stepper axes use :mod:`.stepper`; stepper drives have no PWM
stage (``pwm`` runs them as ``coupled``). Joints without drive data follow their setpoint
exactly (prescribed motion) at every level.

The run starts at rest at the first setpoint, with the currents (and PI integrals) that
hold the arm against gravity, and continues ``hold`` seconds after the last sample so
that settling is seen.
"""

from __future__ import annotations

import numpy as np
from irlc.lang.errors import IrlcError
from irlc.robots.model import RobotModel
from irlc.runtime.drives import friction as fr
from irlc.runtime.drives import setpoint, stepsize
from irlc.runtime.drives.cascade import DcBank
from irlc.runtime.drives.levels import LEVELS
from irlc.runtime.drives.mechanics import Mechanics
from irlc.runtime.drives.params import DcDrives, DriveParams, drive_params
from irlc.runtime.drives.refresh import Refresh
from irlc.runtime.drives.result import DriveRun, default_tolerance, summarise
from irlc.runtime.drives.stepper import StepperBank
from irlc.runtime.drives.transmission import Transmission
from irlc.runtime.engine import compiled_loop
from irlc.runtime.model.dynamics import Dynamics

STEP_CAP = 1e-3  # the largest default step (s) of the averaged levels


class DriveInputError(IrlcError, ValueError):
    """Bad arguments to :func:`simulate_drives` (shape, level, NaN, times)."""


def simulate_drives(
    model: RobotModel,
    times: np.ndarray,
    q_cmd: np.ndarray,
    *,
    level: str,
    step: float | None = None,
    params: DriveParams | None = None,
    tolerance: float | np.ndarray | None = None,
    interpolation: str | None = None,
    hold: float = 0.5,
    record: str = "step",
    dynamics_every: int | None = None,
    accel: bool | None = None,
) -> DriveRun:
    """Simulate the robot's drives following ``q_cmd`` (``(k, n)`` SI at ``times``).

    ``params`` defaults to the robot file's ``[drives]``; ``tolerance`` (SI, scalar or per
    joint) bounds the following error for ``could_follow``; ``interpolation`` is
    ``"linear"`` or ``"trapezoid"`` (default: trapezoid when the file has a
    ``[drives.slave]``); ``hold`` (s) extends the run past the last sample;
    ``record="ipo"`` decimates the arrays to the IPO times; ``dynamics_every`` refreshes
    ``M(q)``, ``C q̇ + G`` every that many steps (default ``None``: adaptive, when the
    configuration or speed has changed by more than :mod:`.refresh`'s bounds);
    ``accel`` runs the loop through the optional compiled kernels (:mod:`.compiled`,
    chosen by :func:`irlc.runtime.engine.compiled_loop`: ``True``
    always, ``False`` never, ``None`` as ``IRLC_ENGINE`` says; numpy is the reference).
    """
    times, q_cmd = _check_inputs(model, times, q_cmd, level, record)
    if not (np.isfinite(hold) and hold >= 0.0):
        raise DriveInputError(f"hold must be a non-negative time in s, got {hold!r}")
    if params is None:
        params = drive_params(model)
    tol = (
        default_tolerance(model)
        if tolerance is None
        else np.broadcast_to(np.asarray(tolerance, dtype=float), (model.n,)).copy()
    )
    if not np.all(np.isfinite(tol) & (tol > 0.0)):
        raise DriveInputError(f"tolerance must be positive, got {tolerance!r}")
    if level == "ideal" or params is None:
        run = _ideal(model, times, q_cmd, tol, level)
        if params is None and level != "ideal":
            run.notes.append(f"robot {model.name} has no [drives]: all axes run ideal")
        return run
    sim = _Simulation(model, params, level, times, q_cmd, step, interpolation, hold, dynamics_every)
    run = sim.run(tol, accel)
    return _decimate(run, times) if record == "ipo" else run


def _check_inputs(model, times, q_cmd, level, record):
    times = np.asarray(times, dtype=float)
    q_cmd = np.asarray(q_cmd, dtype=float)
    if level not in LEVELS:
        raise DriveInputError(f"unknown drive level {level!r}; expected one of {', '.join(LEVELS)}")
    if record not in ("step", "ipo"):
        raise DriveInputError(f"record must be 'step' or 'ipo', got {record!r}")
    if times.ndim != 1 or times.size < 1 or q_cmd.shape != (times.size, model.n):
        raise DriveInputError(
            f"expected times (k,) and q_cmd (k, {model.n}); got {times.shape} and {q_cmd.shape}"
        )
    if not (np.all(np.isfinite(times)) and np.all(np.isfinite(q_cmd))):
        raise DriveInputError("times and setpoints must be finite (no NaN)")
    if np.any(np.diff(times) <= 0.0):
        raise DriveInputError("times must be strictly increasing")
    return times, q_cmd


def _ideal(model, times, q_cmd, tol, level) -> DriveRun:
    """Actual = setpoint; torques by inverse dynamics when the robot has inertial data."""
    n, k = model.n, len(times)
    qd = np.gradient(q_cmd, times, axis=0) if k > 1 else np.zeros_like(q_cmd)
    qdd = np.gradient(qd, times, axis=0) if k > 1 else np.zeros_like(q_cmd)
    torque = np.zeros((k, n))
    notes = ["ideal: actual = setpoint; currents are not simulated"]
    if model.inertials:
        dyn = Dynamics(model)
        for s in range(k):
            torque[s] = dyn.rnea(q_cmd[s], qd[s], qdd[s])
    zeros = np.zeros((k, n))
    run = DriveRun(
        level,
        float(np.median(np.diff(times))) if k > 1 else 0.0,
        times.copy(),
        q_cmd.copy(),
        q_cmd.copy(),
        qd,
        zeros,
        torque,
        zeros.copy(),
        zeros.copy(),
        np.zeros(n, dtype=bool),
        [],
        notes,
    )
    run.axes = summarise(
        run, model, times, q_cmd, np.zeros((k, n), bool), tol, ["ideal"] * n, {}, np.zeros(n, int)
    )
    return run


def drive_step(model: RobotModel, params: DriveParams, level: str, q0: np.ndarray) -> float:
    """The step (s) :func:`simulate_drives` takes by default for a run that starts at ``q0``
    (it depends on the drives and, coupled, on the inertia at the start): for a run's
    cycle budget before the run (:mod:`irlc.runtime.control.executor`)."""
    if level == "ideal":
        raise DriveInputError("the ideal level has no drive step")
    sim = _Simulation.__new__(_Simulation)
    sim._start_at(model, params, level, np.asarray(q0, dtype=float), None)
    return sim.h


class _Simulation:
    def __init__(
        self, model, params: DriveParams, level, times, q_cmd, step, interpolation, hold, every
    ):
        self._start_at(model, params, level, q_cmd[0], step)
        self.refresh = self._refresh_interval(every)
        self.t = times[0] + self.h * np.arange(
            int(np.ceil((times[-1] + hold - times[0]) / self.h)) + 1
        )
        self._setpoints(times, q_cmd, interpolation)
        self.band = fr.band(self.h, params.friction.static, self.motor_inertia)

    def _start_at(self, model, params: DriveParams, level, q0, step) -> None:
        """The axes, transmission and mechanics at the start configuration ``q0``, their
        time constants and the step ``h`` (all the time grid needs)."""
        self.model, self.p, self.level = model, params, level
        self.n = model.n
        self.notes: list[str] = []
        self.axes = np.array(params.axes, dtype=int)
        self.driven = np.zeros(self.n, dtype=bool)
        self.driven[self.axes] = True
        self.trans = Transmission(model, params)
        self.notes += self.trans.notes
        self.ratio = self.trans.local_ratio(q0)  # local ratio at the start
        chain = params.chain
        self.is_dc = isinstance(chain, DcDrives)
        self.pwm = level == "pwm" and self.is_dc
        if level == "pwm" and not self.is_dc:
            self.notes.append("stepper drives have no PWM stage: pwm runs as coupled")
        load = None
        if params.load_inertia is not None:
            load = np.zeros(self.n)
            load[self.axes] = params.load_inertia
        if self.trans.diagonal:
            rotor, extra = self.trans.reflected(chain.J_m, self.n), None
        else:
            rotor = np.zeros(self.n)
            fixed = self.trans.rotor_matrix(chain.J_m, q0)
            extra = (
                (lambda q: fixed)
                if self.trans.matrix is not None
                else (lambda q: self.trans.rotor_matrix(chain.J_m, q))
            )
        kmat = None if self.trans.diagonal else self.trans.jacobian(q0)
        self.mech = Mechanics(model, level, rotor, q0, load, extra, kmat)
        self.motor_inertia = self.mech.diag[self.axes] / self.ratio**2
        self.tau = stepsize.fastest_time_constant(chain, self.motor_inertia)
        names = [model.joints[j].name for j in self.axes]
        if self.mech.coupled and self.is_dc:
            mass = self.mech.mass_matrix(q0)
            tau_c = stepsize.coupled_time_constant(chain, mass, self.trans.jacobian(q0))
            self.tau = np.append(self.tau, tau_c)
            names.append("coupled velocity loops")
        self.h = self._choose_step(step, chain, names)

    # ------------------------------------------------------------------ set-up
    def _choose_step(self, step, chain, names) -> float:
        if self.pwm:
            period = 1.0 / chain.pwm_frequency
            if step is not None and not np.isclose(step, period, rtol=1e-9):
                raise stepsize.StepSizeError(
                    f"the pwm level steps one PWM period ({period * 1e6:.4g} µs) and solves the "
                    f"switching instants exactly; a step of {step * 1e6:.4g} µs does not apply"
                )
            stepsize.check_step(period, self.tau, names)
            return period
        if step is None:
            h = stepsize.default_step(float(self.tau.min()), STEP_CAP)
            if not self.is_dc:
                interval = float((chain.step_angle / chain.step_rate).min())
                h = min(h, interval)
            return h
        if not step > 0.0:
            raise DriveInputError(f"drive step must be positive, got {step!r}")
        stepsize.check_step(step, self.tau, names)
        if not self.is_dc:
            stepsize.check_generator(step, chain.step_angle / chain.step_rate)
        return float(step)

    def _refresh_interval(self, every: int | None) -> int | None:
        """Steps between refreshes of ``M(q)`` and ``C q̇ + G`` (decoupled: ``G``);
        ``None``: adaptive (:mod:`.refresh`)."""
        if every is None:
            return None
        if not isinstance(every, int) or isinstance(every, bool) or every < 1:
            raise DriveInputError(f"dynamics_every must be a positive integer, got {every!r}")
        if every * self.h > 10e-3:
            raise DriveInputError(
                f"dynamics_every = {every} holds M(q) for {every * self.h * 1e3:.3g} ms; "
                "at most 10 ms is allowed"
            )
        return every

    def _setpoints(self, times, q_cmd, interpolation):
        slave = self.p.slave
        mode = interpolation or ("trapezoid" if slave is not None else "linear")
        if mode not in ("linear", "trapezoid"):
            raise DriveInputError(f"interpolation must be linear or trapezoid, got {mode!r}")
        lin = setpoint.linear(times, q_cmd, self.t)
        self.violations = np.zeros(self.n, dtype=int)
        if mode == "trapezoid":
            if slave is None:
                raise DriveInputError(
                    "trapezoid interpolation needs [drives.slave] (T_pr, "
                    "v_max, a_max) in the robot file"
                )
            ref = lin.copy()
            ref[:, self.axes] = setpoint.trapezoid(times, q_cmd, self.t, slave.T_pr)[:, self.axes]
            self.violations[self.axes] = setpoint.slave_violations(
                ref[:, self.axes], self.h, self.ratio, slave.v_max, slave.a_max
            )
            if self.violations.any():
                self.notes.append(
                    "setpoints exceed the slave controller's v_max/a_max on "
                    "some axes (see setpoint_violations)"
                )
        else:
            ref = lin
        self.q_ref = ref
        self.qd_ref = np.gradient(ref, self.h, axis=0)
        self.qdd_ref = np.gradient(self.qd_ref, self.h, axis=0)

    # ------------------------------------------------------------------ loop
    def run(self, tol, accel: bool | None = None) -> DriveRun:
        n, h, axes, ratio, k = self.n, self.h, self.axes, self.ratio, len(self.t)
        frc = self.p.friction
        x = np.zeros(2 * n)  # the state [q; q̇], updated in place
        q, qd = x[:n], x[n:]
        q[:] = self.q_ref[0]
        bank = self._bank(q)
        m_ax = len(axes)
        rec_x = np.zeros((k, 2 * n))
        rec = {name: np.zeros((k, n)) for name in ("tau", "f")}
        rec_iu = np.zeros((k, 2 * m_ax))  # [ī, ū] per step
        rec_i, rec_u = rec_iu[:, :m_ax], rec_iu[:, m_ax:]
        sat_rec = np.zeros((k, m_ax), dtype=bool)
        energy, copper = np.zeros(m_ax), np.zeros(m_ax)
        prescribed = ~self.driven
        any_prescribed = bool(prescribed.any())
        all_driven = not any_prescribed and np.array_equal(axes, np.arange(n))
        sticky = bool(np.any(frc.static > 0.0))
        sliding = sticky or bool(np.any(frc.running > 0.0) or np.any(frc.viscous > 0.0))
        static_j, running_j = np.zeros(n), np.zeros(n)
        static_j[axes] = np.abs(ratio) * frc.static
        running_j[axes] = np.abs(ratio) * frc.running
        drive, slide = np.zeros(n), np.zeros(n)
        stuck = np.zeros(n, dtype=bool)
        trans = self.trans
        diagonal = trans.diagonal
        theta_ref = trans.to_motor(self.q_ref)
        kmat = trans.jacobian(q)
        moving_map = not diagonal and trans.matrix is None  # K(q) changes with q
        mech = self.mech
        refresh = Refresh(self.refresh, h, n)
        compiled = None if accel is False else compiled_loop(self, accel)
        if compiled is not None:
            rec["q"], rec["qd"] = np.zeros((k, n)), np.zeros((k, n))
            rec_i, rec_u = np.zeros((k, m_ax)), np.zeros((k, m_ax))
            loop = compiled(self, bank, static_j, running_j, sticky, sliding)
            loop.run(q, qd, theta_ref, refresh, rec, rec_i, rec_u, sat_rec, energy, copper)
            return self._result(tol, rec, rec_i, rec_u, sat_rec, energy, copper, bank, q)
        fused = self.is_dc and not self.pwm  # DcBank.fused_step applies
        was_fused = np.zeros(k, dtype=bool)
        ks, r_arm = (self.p.chain.ks, self.p.chain.R) if fused else (None, None)
        # motor-side torques [τ_m; τ_f sliding] → joint side in one product with K
        motor_side = np.zeros((2, m_ax))
        running, viscous, band = frc.running, frc.viscous, self.band
        viscous_any = bool(np.any(viscous != 0.0))
        qdd_ref = self.qdd_ref
        limited_step = bank.limited_step if fused else bank.step
        for s in range(k):
            if diagonal:
                if all_driven:
                    theta, omega = q * ratio, qd * ratio
                else:
                    theta, omega = q[axes] * ratio, qd[axes] * ratio
            else:
                if moving_map:
                    theta, kmat = trans.motor_and_jacobian(q)
                else:
                    theta = trans.to_motor(q)
                omega = kmat @ qd
            out = bank.fused_step(theta_ref[s], theta, omega) if fused else None
            if out is not None:
                rec_iu[s] = out[2 * m_ax : 4 * m_ax]
                was_fused[s] = True
                np.multiply(ks, out[2 * m_ax : 3 * m_ax], out=motor_side[0])
            else:
                tau_m, i_m, u_m, sat, e_in, loss = limited_step(
                    theta_ref[s], theta, omega, self.t[s]
                )
                energy += e_in
                copper += loss
                rec_i[s], rec_u[s], sat_rec[s] = i_m, u_m, sat
                motor_side[0] = tau_m
            if sliding:
                np.multiply(running, np.sign(omega), out=motor_side[1])
                if viscous_any:
                    motor_side[1] += viscous * omega
            if diagonal:
                drive[axes] = ratio * motor_side[0]
                if sliding:
                    slide[axes] = ratio * motor_side[1]
            else:
                joint_side = motor_side @ kmat
                drive, slide = joint_side[0], joint_side[1]
            if sticky:
                if all_driven:
                    np.less(np.abs(omega), band, out=stuck)
                else:
                    stuck[axes] = np.abs(omega) < band
            if refresh.due_state(s, x):
                m, hb = mech.terms(q, qd)
                m_inv = mech.inverse(m)
                refresh.mark_state(s, x)
            if any_prescribed:
                qdd, fric, held = mech.accel(
                    m, hb, drive, slide, stuck, static_j, running_j, prescribed, qdd_ref[s], m_inv
                )
                rec["tau"][s] = np.where(prescribed, mech.required(m, hb, qdd), drive)
            else:
                qdd, fric, held = mech.accel_driven(
                    m, hb, drive, slide, stuck, static_j, running_j, m_inv
                )
                rec["tau"][s] = drive
            rec_x[s] = x
            rec["f"][s] = fric
            qd += h * qdd
            if sticky:
                qd[held] = 0.0
            q += h * qd
            if any_prescribed and s + 1 < k:
                q[prescribed] = self.q_ref[s + 1, prescribed]
                qd[prescribed] = self.qd_ref[s + 1, prescribed]
        if fused and was_fused.any():  # Σ ū ī h and Σ R ī² h of the fused steps
            i_f, u_f = rec_i[was_fused], rec_u[was_fused]
            energy += (u_f * i_f).sum(axis=0) * h
            copper += r_arm * (i_f * i_f).sum(axis=0) * h
        rec["q"], rec["qd"] = rec_x[:, :n].copy(), rec_x[:, n:].copy()
        rec_i, rec_u = rec_i.copy(), rec_u.copy()
        return self._result(tol, rec, rec_i, rec_u, sat_rec, energy, copper, bank, q)

    def _bank(self, q0):
        """The drives of the driven axes, at rest at ``q0`` holding the arm against gravity."""
        chain = self.p.chain
        if not self.is_dc:
            return StepperBank(chain, self.trans.to_motor(q0), self.h)
        _, g = self.mech.terms(q0, np.zeros(self.n))
        # motor torques with Kᵀ τ_m = G on the driven joints (least squares if a subset)
        hold = np.linalg.lstsq(self.trans.jacobian(q0).T, g, rcond=None)[0]
        return DcBank(chain, self.h, self.pwm, hold)

    def _result(self, tol, rec, rec_i, rec_u, sat_rec, energy, copper, bank, q) -> DriveRun:
        n, axes = self.n, self.axes
        k = len(self.t)
        current, voltage = np.zeros((k, n)), np.zeros((k, n))
        current[:, axes], voltage[:, axes] = rec_i, rec_u
        saturated = np.zeros((k, n), dtype=bool)
        saturated[:, axes] = sat_rec
        e_full, c_full = np.zeros(n), np.zeros(n)
        e_full[axes], c_full[axes] = energy, copper
        run = DriveRun(
            self.level,
            self.h,
            self.t,
            rec["q"],
            self.q_ref,
            rec["qd"],
            current,
            rec["tau"],
            voltage,
            rec["f"],
            self.driven.copy(),
            [],
            self.notes,
            e_full,
            c_full,
        )
        lost = {}
        if not self.is_dc:
            lost = dict(
                zip(axes.tolist(), bank.lost_steps(self.trans.to_motor(q)).tolist(), strict=True)
            )
        dt = np.diff(self.t, prepend=self.t[0])
        run.saturation_cum = np.cumsum(np.where(saturated, dt[:, None], 0.0), axis=0)
        drives = [self.p.type if self.driven[j] else "ideal" for j in range(n)]
        run.axes = summarise(
            run, self.model, self.t, self.q_ref, saturated, tol, drives, lost, self.violations
        )
        if not self.driven.all():
            names = ", ".join(self.model.joints[j].name for j in np.flatnonzero(~self.driven))
            self.notes.append(f"joints without drive data run ideal: {names}")
        return run


def _decimate(run: DriveRun, times: np.ndarray) -> DriveRun:
    """Keep the rows nearest to the IPO times (and the hold tail at the IPO spacing)."""
    dt = np.median(np.diff(times)) if len(times) > 1 else run.step
    tail = np.arange(times[-1] + dt, run.t[-1] + 1e-12, dt)
    want = np.concatenate([times, tail])
    idx = np.unique(np.clip(np.rint((want - run.t[0]) / run.step).astype(int), 0, len(run.t) - 1))
    for name in (
        "t",
        "q_actual",
        "q_cmd_interp",
        "qd_actual",
        "current",
        "torque",
        "voltage",
        "friction",
        "saturation_cum",
    ):
        if getattr(run, name) is not None:
            setattr(run, name, getattr(run, name)[idx])
    return run
