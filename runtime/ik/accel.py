"""Optional compiled accelerator of the IPO cycle (``pip install irlc[fast]``: numba).

The numpy path of :mod:`newton` is the reference and the default without numba. With
numba, :class:`AcceleratedCycle` runs the same cycle through the fused kernel
:func:`accel_kernels.newton_cycle` — FK, task error, Jacobian, joint box, compact split,
closed-form 1-D QP, QP data — and calls quadprog from Python only for the general QP
(``n − m > 1``) and the relaxed QP. Results equal the numpy path to rounding (tested in
``tests/ik/test_accel.py``).

Covered: every cycle option — the default criterion, CYCLIC / WITH RECONFIGURATION,
RECONFIGURATION (self-motion), position/speed/acceleration limits with braking, coupled
joint limits, any task rows, FREEZE (the step over the free joints, the frozen ones
stepping to their held values), reported and avoided obstacles (OBSTACLE: the criterion's
terms — any number of critical points — are computed in Python once per cycle, at the
first iterate, from the kernel's frames, and passed in as arrays; the full ``H`` then
goes through the general compact QP). Not covered (the numpy path runs):
``solver="daqp"``, ``max_iter < 1``. The kernels read only public packed data:
:attr:`Kinematics.chain_data`, the box constants' ``data`` (:class:`BoxData`), the
coupled rows' ``A`` / ``bound_d`` and the cycle's options.

**When it is used** (:func:`use_accel`): ``IKParams.accel`` ``True`` (always, compiling
if needed), ``False`` (never) or ``None`` (default: whenever numba is importable — the
choice depends on the installation only, so one installation always gives the same
bytes; see :mod:`irlc.runtime.accel_support`). ``IRLC_NO_ACCEL=1`` disables it whatever
the parameter says; ``IRLC_ACCEL=1`` / ``0`` overrides ``None``. Compiling takes
≈ 10–15 s, once: numba caches the machine code in ``__pycache__`` next to this module (or
in the user cache dir when that is read-only), and later processes load it in ≈ 0.3 s.
``python -m irlc.runtime.ik.accel`` compiles ahead of the first run.
"""

from __future__ import annotations

import time

import numpy as np
import quadprog
from irlc.runtime import accel_support

AVAILABLE = accel_support.AVAILABLE  # numba importable and not IRLC_NO_ACCEL=1
compile_seconds: float | None = None  # first kernel call of this process (compile or load)

_KERNELS = accel_support.Kernels("irlc.runtime.ik.accel_kernels", "newton_cycle")
_module = _KERNELS.load
cache_warm = _KERNELS.cache_warm


def use_accel(requested: bool | None) -> bool:
    """Decide whether a solver uses the accelerator (:func:`accel_support.decide`)."""
    return accel_support.decide(requested)


def warm_up() -> float:
    """Compile (or load from the cache) every kernel by running one tiny cycle; returns
    the seconds it took. Called on the first accelerated cycle of a process."""
    global compile_seconds
    if compile_seconds is not None:
        return compile_seconds
    t0 = time.perf_counter()
    from irlc.robots.model import Joint, Limits, RobotModel
    from irlc.runtime.ik.newton import InverseTransformation
    from irlc.runtime.ik.params import IKParams
    from irlc.runtime.kinematics import Kinematics

    link = np.eye(4)
    link[0, 3] = 1.0
    limits = Limits((-3.0, 3.0), (-3.0, 3.0), (-20.0, 20.0))
    axis = np.array([0.0, 0.0, 1.0])
    joints = tuple(
        Joint(f"J{i}", "revolute", link if i else np.eye(4), axis, limits) for i in range(3)
    )
    model = RobotModel(name="warmup", joints=joints, flange=link)
    compile_seconds = -1.0  # (the cycle below must not recurse into warm_up)
    ik = InverseTransformation(model, Kinematics(model), IKParams(task_rows=(0, 1), accel=True))
    q = np.array([0.1, 0.2, 0.3])
    target = ik.kin.tcp(q)
    target[0, 3] += 1e-3
    ik.step(q, q, target, 0.01)
    compile_seconds = time.perf_counter() - t0
    return compile_seconds


class _Problem:
    """The step's problem over the free joints (all joints without FREEZE): its sizes and
    the buffers of the split, the QPs and the active set."""

    def __init__(self, cycle: AcceleratedCycle, frozen):
        k, n, m = cycle.k, cycle.n, cycle.m
        self.frozen = frozen  # FrozenJoints, or None
        if frozen is None:
            nf, self.V, self.J, self.F = n, cycle.V, cycle.Jt, cycle.F
            self.H, self.A, self.bound = cycle.H, cycle.A, None  # (bound: the cycle's own)
            self.free = self.fz = np.zeros(0, dtype=np.int64)
            self.targets = np.zeros(0)
        else:
            nf = frozen.free.size
            self.V, self.J, self.F = np.zeros((k.NV, nf)), np.empty((m, nf)), np.empty(m)
            self.H = np.empty((nf, nf))
            self.A = np.ascontiguousarray(cycle.A[:, frozen.free])
            self.bound = np.empty(cycle.A.shape[0])
            self.free = frozen.free.astype(np.int64)
            self.fz = frozen.frozen.astype(np.int64)
            self.targets = np.ascontiguousarray(frozen.targets, dtype=float)
        nz, r = max(nf - m, 0), self.A.shape[0]
        self.shape = (m, nf)
        self.perm = np.zeros(nf, dtype=np.int64)
        self.aug = np.empty((m, nf + 1))
        self.N = np.zeros((nf, nz))
        self.Ht, self.gt = np.empty((nz, nz)), np.empty(nz)
        self.Ct, self.bt = np.empty((nz, 2 * nf + r)), np.empty(2 * nf + r)
        self.Hrel, self.grel = np.empty((nf, nf)), np.empty(nf)
        self.Crel = np.ascontiguousarray(np.hstack((np.eye(nf), -np.eye(nf), self.A.T)))
        self.active = np.zeros(2 * nf + r, dtype=np.int64)
        self.mult = np.zeros(2 * nf + r)


class AcceleratedCycle:
    """Buffers of one :class:`InverseTransformation` for the compiled cycle."""

    def __init__(self, ik):
        k = _module()
        self.k = k
        self.ik = ik
        self.n, self.m = n, m = ik.n, ik.rows.size
        self.chain = ik.kin.chain_data  # packed, read-only (re-read per cycle: R_TOOL)
        self.rows = np.ascontiguousarray(ik.rows, dtype=np.int64)
        coupled = ik.coupled
        self.A = np.zeros((0, n)) if coupled is None else np.ascontiguousarray(coupled.A)
        self.bound_d = np.zeros(0)
        self.V = np.zeros((k.NV, n))
        self.weights = np.asarray(ik.weights, dtype=float)
        self.conf_weights = ik.params.obstacle.a_conf * self.weights  # (as WeightedDisplacement)
        self.V[k.W] = self.weights
        self.frames = np.empty((n + 1, 4, 4))
        self.tcp = np.empty((4, 4))
        self.J6 = np.empty((6, n))
        self.Jt = np.empty((m, n))
        self.F = np.empty(m)
        self.H = np.zeros((n, n))
        self._no_terms = (np.zeros(0), np.zeros((0, 3)), np.zeros((0, 3, n)), np.zeros((0, n, n)))
        self.terms = self._no_terms
        self.ist = np.zeros(k.N_IST, dtype=np.int64)
        self.fst = np.zeros(k.N_FST)
        self.cand = np.empty((4, 2, n))
        self._box_key = None
        self._full = _Problem(self, None)
        self._problems: dict[tuple, _Problem] = {}
        self.problem = self._full
        p = ik.params
        ist, fst = self.ist, self.fst
        ist[k.MAX_ITER] = p.max_iter
        ist[k.SCALAR] = int(p.scalar_qp)
        ist[k.WARM] = int(p.warm_start)
        ist[k.NPOS] = int(np.sum(ik.rows < 3))
        fst[k.TOL_P], fst[k.TOL_O] = p.tol_position, p.tol_orientation
        fst[k.COND_MAX], fst[k.SINGULAR_COND] = p.cond_max, p.singular_cond
        fst[k.RELAX_W] = p.relax_weight

    # ------------------------------------------------------------------ setup
    def _box_constants(self, position, speed, accel, dt):
        c = self.ik.box.constants(position, speed, accel, dt)
        if self._box_key is not c:
            self._box_key = c
            data = c.data  # packed, read-only
            self.boxc = data.signed
            self.ist[self.k.ACCEL_BOUNDED] = int(data.accel_bounded)
            self.fst[self.k.DTOL] = data.dtol
        return c

    def _problem_for(self, frozen) -> _Problem:
        """The reduced problem of a FREEZE set (cached per set), or the full one."""
        if not frozen:
            return self._full
        key = (tuple(frozen.frozen.tolist()), tuple(frozen.targets.tolist()))
        prob = self._problems.get(key)
        if prob is None:
            prob = self._problems[key] = _Problem(self, frozen)
        return prob

    def _sync_basis(self) -> None:
        b = self.ik.stepper.basis
        prob = self.problem
        valid = b.columns is not None and b.shape == prob.shape
        self.ist[self.k.BASIS_VALID] = int(valid)
        if valid:
            prob.perm[:] = b.columns

    def _criteria(self, opts, active: list) -> None:
        """The cost's form before the cycle: ``GENERAL`` (full ``H``: FREEZE, or more than
        one criterion) and the diagonal weights ``V[W]`` / ``V[WC]`` — as
        ``InverseTransformation._criteria`` / ``_single_diagonal`` choose them; with
        avoided obstacles the choice waits for their terms (:meth:`_obstacle_terms`)."""
        k, V, ist = self.k, self.V, self.ist
        ist[k.NEED_TERMS] = int(bool(active))
        self.terms = self._no_terms
        V[k.W] = self.weights
        V[k.WC] = 0.0
        ist[k.GENERAL] = int(self.problem.frozen is not None)

    def _obstacle_terms(self, opts, active: list) -> None:
        """At the first iterate: the obstacle criterion's terms (:func:`obstacle_terms`,
        at the kernel's frames) as arrays, and the cost's form with them."""
        from irlc.runtime.ik.obstacle import obstacle_terms

        k, V, ist, ik = self.k, self.V, self.ist, self.ik
        terms = obstacle_terms(ik.kin, self.frames, active, ik.params.obstacle)
        if terms:
            self.terms = (
                np.array([t.weight for t in terms]),
                np.array([t.push for t in terms]),
                np.array([t.jac for t in terms]),
                np.array([t.jtj for t in terms]),
            )
        if opts.reference is not None:  # [CYCLIC, a_conf·W, terms…]: a full H
            V[k.WC] = self.conf_weights
            ist[k.GENERAL] = 1
        else:  # [a_conf·W, terms…]: diagonal when no obstacle is near
            V[k.W] = self.conf_weights
            ist[k.GENERAL] = int(bool(terms) or self.problem.frozen is not None)
        ist[k.NEED_TERMS] = 0

    # ------------------------------------------------------------------ the cycle
    def step(self, q_start, q_prev, target, dt, opts, frozen=None, active=()):
        """The numbers of ``InverseTransformation.step``; ``frozen``: the cycle's
        ``FrozenJoints`` (or None), ``active``: the avoided obstacles. Returns
        ``(theta, bounds, limits, outcome_active, outcome_mult)``; :meth:`snapshot` and
        :meth:`jacobian` copy the reused buffers only when the caller keeps them."""
        if compile_seconds is None:
            warm_up()
        from irlc.runtime.ik.newton import IKFailure

        k, ik = self.k, self.ik
        lim = ik.limits
        position = lim[0] if opts.position is None else opts.position
        speed = lim[1] if opts.speed is None else opts.speed
        accel = lim[2] if opts.accel is None else opts.accel
        c = self._box_constants(position, speed, accel, dt)
        if ik.coupled is not None:
            ik.coupled.prepare(q_start, dt, accel)
            self.bound_d = ik.coupled.bound_d
        prob = self.problem = self._problem_for(frozen)
        if frozen is not None and frozen.free.size < self.m:  # (numpy's order: limits first)
            ik.box.prepare(ik.model, q_start, q_prev, dt, position, speed, accel)
            frozen.check_task(ik.model, self.m, ik.naming)
        V, ist, fst = self.V, self.ist, self.fst
        V[k.Q_START] = q_start
        V[k.Q_PREV] = q_prev
        if opts.reference is not None:
            V[k.REF] = opts.reference
        ist[k.HAS_REF] = opts.reference is not None
        ist[k.SELF_MOTION] = bool(opts.self_motion)
        ist[k.BOX_READY] = 0
        ist[k.PHASE] = k.P_START
        self._criteria(opts, active)
        chain = self.chain = ik.kin.chain_data
        self._sync_basis()
        bounds = np.empty((2, self.n))
        cand = self.cand
        target = np.ascontiguousarray(target, dtype=float)
        bound_r = self.bound_d if prob.bound is None else prob.bound
        run = k.newton_cycle
        while True:
            status = run(
                chain.basis, chain.joints, chain.ends, target, self.boxc, cand, bounds, V,
                self.frames, self.tcp, self.J6, self.Jt, self.F, self.rows, self.A,
                self.bound_d, self.H, *self.terms, prob.free, prob.fz, prob.targets,
                prob.V, prob.J, prob.F, prob.H, prob.A, bound_r, prob.perm, prob.aug, prob.N,
                prob.Ht, prob.gt, prob.Ct, prob.bt, prob.Hrel, prob.grel, prob.active,
                prob.mult, ist, fst,
            )  # fmt: skip
            if status == k.S_DONE:
                break
            if status == k.S_NEED_QP:
                self._hard_qp()
            elif status == k.S_NEED_RELAXED:
                self._relaxed_qp()
            elif status == k.S_NEED_BASIS:
                self._choose_basis()
            elif status == k.S_NEED_TERMS:
                self._obstacle_terms(opts, active)
            elif status == k.S_BOX_CHECK:
                box = ik.box
                box.prepare(ik.model, q_start, q_prev, dt, position, speed, accel)  # raises
                bounds = box.bounds.copy()
                cand[:] = box.cand
                ist[k.BOX_READY] = 1
                ist[k.PHASE] = k.P_START
            elif status == k.S_FROZEN_FAR:
                raise IKFailure(
                    "frozen joints are away from their held values by more than the "
                    "joint box allows in one cycle"
                )
            else:  # S_BAD_STEP
                raise IKFailure(
                    f"inverse transformation produced a non-finite step: {V[k.DTHETA].copy()}"
                )
        nact = int(ist[k.N_ACTIVE])
        self.bounds = bounds  # the last cycle's box on Δθ (with ``cand``: for observers)
        return (
            V[k.THETA].copy(),
            bounds,  # fresh this cycle
            c.limits,
            prob.active[:nact].copy(),
            prob.mult[:nact].copy(),
        )

    def snapshot(self, bounds, limits):
        """The cycle's box for reports (copies the reused candidate buffer)."""
        from irlc.runtime.ik.limits import BoxSnapshot

        return BoxSnapshot(bounds[0], bounds[1], self.cand.copy(), limits)

    def jacobian(self):
        """A copy of the last Jacobian (its free columns under FREEZE), or None when the
        cycle computed none."""
        if not self.ist[self.k.HAVE_J]:
            return None
        frozen = self.problem.frozen
        return self.Jt.copy() if frozen is None else self.Jt[:, frozen.free]

    # ------------------------------------------------------------------ Python parts
    def _hard_qp(self) -> None:
        """General compact QP: quadprog on the kernel's data; infeasible → relaxed."""
        k, ist, prob = self.k, self.ist, self.problem
        try:
            z, _, _, _, lagr, iact = quadprog.solve_qp(prob.Ht, prob.gt, prob.Ct, prob.bt, 0)
        except ValueError:
            ist[k.PHASE] = k.P_RELAX
            return
        rows = iact[iact > 0] - 1
        self._set_active(rows, lagr[rows] / self.fst[k.SCALE])
        prob.V[k.Z, : z.shape[0]] = z
        ist[k.PHASE] = k.P_APPLY_Z

    def _relaxed_qp(self) -> None:
        k, ist, prob = self.k, self.ist, self.problem
        from irlc.runtime.ik.newton import IKFailure

        try:
            z, _, _, _, lagr, iact = quadprog.solve_qp(prob.Hrel, prob.grel, prob.Crel, prob.bt, 0)
        except ValueError as exc:
            if self.A.shape[0] == 0:
                raise FloatingPointError(f"relaxed QP failed ({exc})") from None
            raise IKFailure(
                "the joint box and the coupled joint limits leave no admissible step "
                "(the coupled combination moves too fast to stop before its bound)"
            ) from None
        rows = iact[iact > 0] - 1
        factor = self.fst[k.SCALE]
        self._set_active(rows, lagr[rows] * factor)
        prob.V[k.DTHETA] = z
        ist[k.RELAXED] = 1
        ist[k.SINGULAR] |= ist[k.LAST_SINGULAR]
        if prob.frozen is not None and ist[k.LAST_SINGULAR]:
            self._check_freeze(prob.frozen)
        ist[k.PHASE] = k.P_APPLY

    def _check_freeze(self, frozen) -> None:
        """``InverseTransformation._solve``: a singular free problem while the whole J
        has full rank means FREEZE made the task impossible."""
        from irlc.runtime.ik.freeze import FreezeError
        from irlc.runtime.ik.newton import _full_rank

        ik, m = self.ik, self.m
        if m <= frozen.free.size and _full_rank(self.Jt, m):
            raise FreezeError(frozen.describe_impossible(ik.model, m, ik.naming))

    def _set_active(self, rows, mult) -> None:
        cnt = rows.shape[0]
        prob = self.problem
        prob.active[:cnt] = rows
        prob.mult[:cnt] = mult
        self.ist[self.k.N_ACTIVE] = cnt

    def _choose_basis(self) -> None:
        """QR with column pivoting of the current J (``CompactBasis.choose``)."""
        k, ist, fst = self.k, self.ist, self.fst
        basis = self.ik.stepper.basis
        ok = basis.choose(self.problem.J)
        self._sync_basis()
        if not ok:
            ist[k.LAST_SINGULAR] = 1
            ist[k.PHASE] = k.P_RELAX
            return
        stage = 0 if ist[k.BASIS_REASON] == 0 else 1
        ist[k.BASIS_STAGE] = stage
        fst[k.COND_LIMIT] = fst[k.COND_MAX] if stage == 0 else fst[k.SINGULAR_COND]
        ist[k.PHASE] = k.P_SPLIT


if __name__ == "__main__":  # python -m irlc.runtime.ik.accel: fill numba's cache once
    if not AVAILABLE:
        raise SystemExit("numba is not installed (pip install 'irlc[fast]') or IRLC_NO_ACCEL=1")
    warm = cache_warm()
    seconds = warm_up()
    print(f"irlc IK accelerator: {'loaded' if warm else 'compiled'} in {seconds:.2f} s")
