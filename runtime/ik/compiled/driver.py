"""The Python side of the compiled IK cycle: :class:`CompiledCycle` runs
:meth:`InverseTransformation.step`'s numbers through :func:`.cycle.newton_cycle` on one
:class:`Workspace` — FK, task error, Jacobian, joint box, compact split, closed-form 1-D
QP, the compact QP's unconstrained minimiser when nothing binds, QP data — and calls
quadprog from Python only when a compact-QP constraint binds and for the relaxed QP.
Results equal the numpy path to rounding (``tests/ik/test_compiled_cycle.py``; each kernel
alone in ``tests/ik/test_compiled_kernels.py``).

Covered: every cycle option — the default criterion, CYCLIC / WITH RECONFIGURATION,
RECONFIGURATION (self-motion), position/speed/acceleration limits with braking, coupled
joint limits, any task rows, FREEZE (the step over the free joints, the frozen ones
stepping to their held values), reported and avoided obstacles (OBSTACLE: the criterion's
terms — any number of critical points — are computed once per cycle, at the first
iterate, from the kernel's frames by the compiled queries of :mod:`.distance`, and
passed in as arrays; the full ``H`` then goes through the general compact QP; the
reported clearances at the result come from the same queries). Not covered (the numpy
path runs): ``solver="daqp"``, ``max_iter < 1``. The kernels read only public packed
data: :attr:`Kinematics.chain_data`, the box constants' ``data`` (:class:`BoxData`), the
coupled rows' ``A`` / ``bound_d`` and the cycle's options.

**When it is used**: :func:`irlc.runtime.engine.compiled_cycle` decides (``IKParams.accel``
and ``IRLC_ENGINE``; numpy when unset — the choice never depends on numba's cache, so one
installation always gives the same bytes: :mod:`irlc.runtime.accel_support`). Compiling
takes ≈ 10–15 s, once: numba caches the machine code in ``__pycache__`` next to the kernel
modules (or in the user cache dir when that is read-only), and later processes load it in
≈ 0.3 s. ``irlc warmup`` (:mod:`irlc.runtime.warmup`) compiles ahead of the first run.
"""

from __future__ import annotations

import numpy as np
import quadprog
from irlc.runtime import accel_support
from irlc.runtime.ik.compiled import layout as L
from irlc.runtime.ik.failure import IKFailure, full_rank, require_finite
from irlc.runtime.ik.freeze import FreezeError
from irlc.runtime.ik.limits import BoxSnapshot
from irlc.runtime.model.distance import robot_segments

KERNELS = accel_support.Kernels("irlc.runtime.ik.compiled.cycle", "newton_cycle")
"""The cycle kernel (loaded, and compiled when numba's cache lacks it, on first use)."""
OBSTACLE_KERNELS = accel_support.Kernels(
    "irlc.runtime.ik.compiled.distance", "critical_points", "IK obstacle kernels"
)
"""The obstacle queries (compiled on the first cycle with obstacles, ≈ 8 s of CPU)."""
INERTIA_KERNELS = accel_support.Kernels(
    "irlc.runtime.ik.compiled.inertia", "inertia_metric", "IK inertia kernel"
)
"""ENERGY's metric (compiled on the first ENERGY cycle)."""


def cache_warm() -> bool:
    """True when numba's cache holds the cycle, the obstacle queries and ENERGY's kernel."""
    return KERNELS.cache_warm() and OBSTACLE_KERNELS.cache_warm() and INERTIA_KERNELS.cache_warm()


_NO_ROWS = np.zeros(0, dtype=np.int64)  # a cycle without active QP rows (shared, never written)
_NO_MULT = np.zeros(0)
_NO_ROWS.flags.writeable = _NO_MULT.flags.writeable = False


class Workspace:
    """The cycle's arrays in two buffers (``fw`` float, ``iw`` int) and the layout ``lay``
    that :func:`.cycle.newton_cycle` cuts them with (slots: :mod:`.layout`, ``k``); the
    same views as attributes here.

    The step's (reduced) problem has its own region, sized for all ``n`` joints: under
    FREEZE (:meth:`use`) its views cover the free joints; otherwise the layout points them
    at the full arrays (``Vr`` is ``V``, …)."""

    def __init__(self, k, n: int, m: int, r: int):
        self.k, self.n, self.m, self.r = k, n, m, r
        nz, nc = max(n - m, 0), 2 * n + r
        floats = (
            (k.F_V, k.NV * n), (k.F_FRAMES, 16 * (n + 1)), (k.F_TCP, 16), (k.F_J6, 6 * n),
            (k.F_JT, m * n), (k.F_F, m), (k.F_H, n * n), (k.F_A, r * n), (k.F_BOUND_D, r),
            (k.F_BOUNDS, 2 * n), (k.F_CAND, 8 * n), (k.F_TARGET, 16), (k.F_VR, k.NV * n),
            (k.F_JR, m * n), (k.F_FR, m), (k.F_HR, n * n), (k.F_AR, r * n), (k.F_BOUND_R, r),
            (k.F_AUG, m * (n + 1)), (k.F_N, n * nz), (k.F_HT, nz * nz), (k.F_GT, nz),
            (k.F_CT, nz * nc), (k.F_BT, nc), (k.F_HREL, n * n), (k.F_GREL, n),
            (k.F_MULT, nc), (k.F_FTARGET, n), (k.F_FST, k.N_FST), (k.F_MA, n * n),
            (k.F_MC, n * n),
        )  # fmt: skip
        ints = (
            (k.I_ROWS, m), (k.I_FREE, n), (k.I_FZ, n), (k.I_PERM, n), (k.I_ACTIVE, nc),
            (k.I_IST, k.N_IST_ALL), (k.I_CODES, n),
        )  # fmt: skip
        self.lay = lay = np.zeros(k.N_LAY, dtype=np.int64)
        self._own = {}
        self.fw = np.zeros(self._offsets(floats))
        self.iw = np.zeros(self._offsets(ints), dtype=np.int64)
        lay[k.Z_N], lay[k.Z_M], lay[k.Z_R] = n, m, r
        f = self._f
        self.V, self.frames = f(k.F_V, k.NV, n), f(k.F_FRAMES, n + 1, 4, 4)
        self.tcp, self.J6, self.Jt = f(k.F_TCP, 4, 4), f(k.F_J6, 6, n), f(k.F_JT, m, n)
        self.F, self.H, self.A = f(k.F_F, m), f(k.F_H, n, n), f(k.F_A, r, n)
        self.MA, self.MC = f(k.F_MA, n, n), f(k.F_MC, n, n)  # ENERGY's metric (criteria)
        self.bound_d, self.bounds = f(k.F_BOUND_D, r), f(k.F_BOUNDS, 2, n)
        self.cand, self.target = f(k.F_CAND, 4, 2, n), f(k.F_TARGET, 4, 4)
        self.fst = f(k.F_FST, k.N_FST)
        self.rows, self.ist = self._i(k.I_ROWS, m), self._i(k.I_IST, k.N_IST_ALL)
        self.codes = self._i(k.I_CODES, n)
        self.frozen = False
        self.use(None)

    def _offsets(self, sizes) -> int:
        total = 0
        for slot, size in sizes:
            self.lay[slot] = self._own[slot] = total
            total += size
        return total

    def _f(self, slot: int, *shape: int) -> np.ndarray:
        o = int(self.lay[slot])
        return self.fw[o : o + int(np.prod(shape))].reshape(shape)

    def _i(self, slot: int, size: int) -> np.ndarray:
        o = int(self.lay[slot])
        return self.iw[o : o + size]

    def use(self, frozen) -> None:
        """Point the problem's views at the free joints of ``frozen`` (``FrozenJoints``)
        or, with None, at the full arrays."""
        k, lay, n, m, r = self.k, self.lay, self.n, self.m, self.r
        for slot in (k.F_VR, k.F_JR, k.F_FR, k.F_HR, k.F_AR, k.F_BOUND_R):
            lay[slot] = self._own[slot]
        if frozen is None:
            nf, nfz = n, 0
            pairs = ((k.F_VR, k.F_V), (k.F_JR, k.F_JT), (k.F_FR, k.F_F), (k.F_HR, k.F_H),
                     (k.F_AR, k.F_A), (k.F_BOUND_R, k.F_BOUND_D))  # fmt: skip
            for mine, full in pairs:
                lay[mine] = lay[full]
        else:
            nf, nfz = frozen.free.size, frozen.frozen.size
        lay[k.Z_NF], lay[k.Z_NFZ] = nf, nfz
        self.frozen = frozen is not None
        nz, nc = max(nf - m, 0), 2 * nf + r
        f = self._f
        self.Vr, self.Jr, self.Hr = f(k.F_VR, k.NV, nf), f(k.F_JR, m, nf), f(k.F_HR, nf, nf)
        self.Ht, self.gt = f(k.F_HT, nz, nz), f(k.F_GT, nz)
        self.Ct, self.bt = f(k.F_CT, nz, nc), f(k.F_BT, nc)
        self.Hrel, self.grel, self.mult = f(k.F_HREL, nf, nf), f(k.F_GREL, nf), f(k.F_MULT, nc)
        self.perm, self.active = self._i(k.I_PERM, nf), self._i(k.I_ACTIVE, nc)
        self.shape = (m, nf)
        if frozen is not None:
            self._i(k.I_FREE, nf)[:] = frozen.free
            self._i(k.I_FZ, nfz)[:] = frozen.frozen
            f(k.F_FTARGET, nfz)[:] = frozen.targets


class CompiledCycle:
    """Buffers of one :class:`InverseTransformation` for the compiled cycle."""

    def __init__(self, ik):
        self.run = KERNELS.load().newton_cycle
        self.k = k = L
        self.ik = ik
        self.n, self.m = n, m = ik.n, ik.rows.size
        self.chain = ik.kin.chain_data  # packed, read-only (re-read per cycle: R_TOOL)
        coupled = ik.coupled
        r = 0 if coupled is None else coupled.A.shape[0]
        ws = self.ws = Workspace(k, n, m, r)
        ws.rows[:] = ik.rows
        if coupled is not None:
            ws.A[:] = coupled.A
        self.V, self.ist, self.fst = ws.V, ws.ist, ws.fst
        self.frames, self.tcp, self.Jt, self.cand = ws.frames, ws.tcp, ws.Jt, ws.cand
        self.weights = ik.criteria.distance.w  # the diagonal criterion's: W, or MVR's ŵ
        self.conf_weights = ik.criteria.distance.conf.w  # a_conf·W (as WeightedDisplacement)
        self.V[k.W] = self.weights
        self._mode = (False, False)  # (V[W] is a_conf·W, V[WC] is a_conf·W)
        self._energy: tuple | None = None  # ENERGY's packed inputs (inertia.inertia_metric)
        self._reference_key: bytes | None = None  # θ⁰ whose Ĝ(θ⁰) is in _reference_metric
        self._reference_metric = np.zeros((n, n))
        self._no_terms = (np.zeros(0), np.zeros((0, 3)), np.zeros((0, 3, n)), np.zeros((0, n, n)))
        self.terms = self._no_terms
        self._packed: dict[tuple, tuple] = {}  # ids of obstacles → (obstacles, rows)
        self._term_bufs: dict[int, tuple] = {}  # obstacle count → criterion buffers, views
        self._box_key = None
        self._frozen = None  # the FrozenJoints the workspace's problem is cut for
        self._crel: dict[int, np.ndarray] = {}
        self._basis_key: tuple | None = None  # (basis version, problem shape) last synced
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

    def _use(self, frozen) -> None:
        """Cut the workspace's problem for this cycle's FREEZE set (only when it changes)."""
        if frozen is not self._frozen:
            self._frozen = frozen
            self.ws.use(frozen)

    def _crel_for(self) -> np.ndarray:
        """``[I, −I, A_freeᵀ]``: the relaxed QP's constraint columns (cached per size)."""
        ws = self.ws
        nf = ws.shape[1]
        key = nf if self._frozen is None else (nf, tuple(self._frozen.free.tolist()))
        crel = self._crel.get(key)
        if crel is None:
            a = ws.A if self._frozen is None else ws.A[:, self._frozen.free]
            crel = np.ascontiguousarray(np.hstack((np.eye(nf), -np.eye(nf), a.T)))
            self._crel[key] = crel
        return crel

    def _sync_basis(self) -> None:
        """The compact basis's columns into the workspace (when the basis or the
        problem's shape changed since the last sync: ``CompactBasis.version``)."""
        b = self.ik.stepper.basis
        ws = self.ws
        key = (b.version, ws.shape)
        if key == self._basis_key:
            return
        self._basis_key = key
        valid = b.columns is not None and b.shape == ws.shape
        self.ist[self.k.BASIS_VALID] = int(valid)
        if valid:
            ws.perm[:] = b.columns

    def _criteria(self, opts, active: list, q_start) -> None:
        """The cost's form before the cycle: ``GENERAL`` (full ``H``: FREEZE, or more than
        one criterion), ``FULL_METRIC`` (ENERGY: the matrices ``MA``, ``MC``) or the
        diagonal weights ``V[W]`` / ``V[WC]`` (DISTANCE: ``W``, MVR: ``ŵ``) — as
        ``InverseTransformation._criteria`` (:class:`~irlc.runtime.ik.criteria.CycleCriteria`)
        / ``_single_diagonal`` choose them; with avoided obstacles the choice waits for
        their terms (:meth:`_obstacle_terms`)."""
        k, ist = self.k, self.ist
        ist[k.NEED_TERMS] = int(bool(active))
        self.terms = self._no_terms
        diag = self.ik.criteria.diagonal(opts.criterion)  # None: ENERGY (a full metric)
        ist[k.FULL_METRIC] = int(diag is None)
        if diag is None:
            self._energy_metric(opts, bool(active), q_start)
            ist[k.GENERAL] = 1
            return
        if diag.w is not self.weights:  # another diagonal criterion: its weights
            self.weights, self.conf_weights = diag.w, diag.conf.w
            self._mode = (None, None)
        self._weights(False, False)
        ist[k.GENERAL] = int(self._frozen is not None)

    def _weights(self, conf_w: bool, conf_wc: bool) -> None:
        """``V[W]`` = a_conf·W or W, ``V[WC]`` = a_conf·W or 0 (written when they change)."""
        if self._mode != (conf_w, conf_wc):
            k, V = self.k, self.V
            V[k.W] = self.conf_weights if conf_w else self.weights
            V[k.WC] = self.conf_weights if conf_wc else 0.0
            self._mode = (conf_w, conf_wc)

    def _energy_metric(self, opts, avoided: bool, q_start) -> None:
        """ENERGY's ``MA``, ``MC`` (:mod:`~irlc.runtime.ik.criteria`): without θ⁰ ``MA =
        s·Ĝ(θ_s)`` (``s`` = a_conf beside avoided obstacles, else 1), ``MC = 0``; with θ⁰
        ``MA = Ĝ(θ⁰)`` (kept while θ⁰ is) and ``MC = a_conf·Ĝ(θ_s)`` or 0 — the
        compiled :func:`.inertia.inertia_metric`."""
        ws, a_conf = self.ws, self.ik.params.obstacle.a_conf
        if opts.reference is None:
            self._inertia(q_start, a_conf if avoided else 1.0, ws.MA)
            ws.MC[:] = 0.0
            return
        reference = np.asarray(opts.reference, dtype=float)
        key = reference.tobytes()
        if key != self._reference_key:
            self._inertia(reference, 1.0, self._reference_metric)
            self._reference_key = key
        ws.MA[:] = self._reference_metric
        if avoided:
            self._inertia(q_start, a_conf, ws.MC)
        else:
            ws.MC[:] = 0.0

    def _inertia(self, q, scale: float, out) -> None:
        """``out = scale·Ĝ(q)`` (:func:`.inertia.inertia_metric` on the packed chain and
        inertials; the packed inputs made on the first ENERGY cycle)."""
        metric = self.ik.criteria.inertia  # raises EnergyNeedsInertia, as numpy does
        if metric.dynamics is None:  # several robots' links (a cooperating chain): numpy
            out[:] = scale * metric(np.asarray(q, dtype=float))
            return
        if self._energy is None:
            n, d = self.n, metric.dynamics.data
            dyn = (d.axes, d.revolute, d.rotor, d.mass, d.com, d.inertia, d.gravity)
            buf = (np.empty((n + 1, 4, 4)), np.empty((4, 4)), np.zeros(n), np.empty(n))
            kernel = INERTIA_KERNELS.load().inertia_metric
            self._energy = (kernel, dyn, buf, metric.weight_sum)
        kernel, dyn, buf, weight_sum = self._energy
        c = self.ik.kin.chain_data
        kernel((c.basis, c.joints, c.ends[0]), dyn, q, weight_sum, scale, buf, out)

    def _obstacle_terms(self, opts, active: list) -> None:
        """At the first iterate: the obstacle criterion's terms (the compiled
        :func:`.distance.obstacle_terms` at the kernel's frames, as
        :func:`obstacle.obstacle_terms` gives them) as arrays, and the cost's form."""
        k, ist, ik = self.k, self.ist, self.ik
        d = OBSTACLE_KERNELS.load()
        bufs = self._term_bufs.get(len(active))
        if bufs is None:  # (params, cps, ow, opush, ojac, ojtj), then the first-cnt views
            m, n = len(active), self.n
            arrays = (d.pack_params(ik.params.obstacle), np.empty((m, d.N_CP)), np.empty(m),
                      np.empty((m, 3)), np.empty((m, 3, n)), np.empty((m, n, n)))  # fmt: skip
            views = [self._no_terms] + [tuple(a[:c] for a in arrays[2:]) for c in range(1, m + 1)]
            bufs = self._term_bufs[m] = (arrays, views)
        arrays, views = bufs
        seg = robot_segments(ik.kin)
        rows = self._packed_rows(active)[1]
        cnt = d.obstacle_terms(self.frames, self.tcp, self.chain.joints, seg.links, seg.a_local,
                               seg.b_local, seg.radius, seg.fallback, rows, *arrays)  # fmt: skip
        self.terms = views[cnt]
        if ist[k.FULL_METRIC]:  # ENERGY: MA, MC made before the cycle (_energy_metric)
            ist[k.GENERAL] = 1
        elif opts.reference is not None:  # [CYCLIC, a_conf·W, terms…]: a full H
            self._weights(False, True)
            ist[k.GENERAL] = 1
        else:  # [a_conf·W, terms…]: diagonal when no obstacle is near
            self._weights(True, False)
            ist[k.GENERAL] = int(cnt > 0 or self._frozen is not None)
        ist[k.NEED_TERMS] = 0

    def _packed_rows(self, obstacles) -> tuple:
        """``(obstacles, rows, names, out)``: the packed rows of ``obstacles``
        (:func:`.distance.pack_obstacles`), their names and an output buffer of
        their critical points, kept while the same shapes come back (cycle after cycle)."""
        key = tuple(map(id, obstacles))
        hit = self._packed.get(key)
        if hit is None:  # (the shapes are kept with their rows: their ids stay theirs)
            d = OBSTACLE_KERNELS.load()
            hit = (tuple(obstacles), d.pack_obstacles(obstacles),
                   [o.name for o in obstacles], np.empty((len(obstacles), d.N_CP)))  # fmt: skip
            self._packed[key] = hit
        return hit

    def clearances(self, obstacles) -> dict[str, tuple[float, int]]:
        """``{name: (distance, link)}`` of the reported ``obstacles`` at the cycle's result
        (the kernel's last frames; ``InverseTransformation._clearances``)."""
        d = OBSTACLE_KERNELS.load()
        seg = robot_segments(self.ik.kin)
        _, rows, names, out = self._packed_rows(obstacles)
        d.critical_points(self.frames, self.tcp, seg.links, seg.a_local, seg.b_local,
                          seg.radius, seg.fallback, rows, out)  # fmt: skip
        dist, link = d.D_DIST, d.D_LINK
        rows_out = out.tolist()
        return {name: (rows_out[i][dist], int(rows_out[i][link])) for i, name in enumerate(names)}

    # ------------------------------------------------------------------ the cycle
    def step(self, q_start, q_prev, target, dt, opts, frozen=None, active=()):
        """The numbers of ``InverseTransformation.step``; ``frozen``: the cycle's
        ``FrozenJoints`` (or None), ``active``: the avoided obstacles. The kernel tests
        the inputs' finiteness first (``S_NOT_FINITE``: :func:`.failure.require_finite`
        raises, as the numpy path's first test). Returns ``(theta, limits,
        outcome_active, outcome_mult, codes, iterations, pe, oe, relaxed, singular)``
        (``codes``: as ``limits.active_codes``; Python numbers from one ``tolist`` of the
        state arrays); :meth:`snapshot` and :meth:`jacobian` copy the reused buffers only
        when the caller keeps them."""
        k, ik, ws = self.k, self.ik, self.ws
        lim = ik.limits
        position = lim[0] if opts.position is None else opts.position
        speed = lim[1] if opts.speed is None else opts.speed
        accel = lim[2] if opts.accel is None else opts.accel
        c = self._box_constants(position, speed, accel, dt)
        if ik.coupled is not None:
            ik.coupled.prepare(q_start, dt, accel, q_prev)
            ws.bound_d[:] = ik.coupled.bound_d
            if ik.coupled.varying:  # motor rows of a non-linear map: K(q_start)
                ws.A[:] = ik.coupled.A
                self._crel.clear()  # the relaxed QP's constraint columns carry A
        self._use(frozen)
        if frozen is not None and frozen.free.size < self.m:  # (numpy's order: limits first)
            ik.box.prepare(ik.model, q_start, q_prev, dt, position, speed, accel)
            frozen.check_task(ik.model, self.m, ik.naming)
        V, ist = self.V, self.ist
        V[k.Q_START] = q_start
        V[k.Q_PREV] = q_prev
        ws.target[:] = target
        if opts.reference is not None:
            V[k.REF] = opts.reference
        ist[k.HAS_REF] = opts.reference is not None
        ist[k.SELF_MOTION] = bool(opts.self_motion)
        ist[k.BOX_READY] = 0
        ist[k.PHASE] = k.P_START
        self._opts, self._active = opts, active
        self._criteria(opts, active, q_start)
        chain = self.chain = ik.kin.chain_data
        self._sync_basis()
        run, fw, iw, lay = self.run, ws.fw, ws.iw, ws.lay
        while True:
            status = run(chain.basis, chain.joints, chain.ends, self.boxc, *self.terms, fw, iw,
                         lay)  # fmt: skip
            if status == k.S_DONE:
                break
            self._resume(status, q_start, q_prev, target, dt, position, speed, accel)
        self.bounds = ws.bounds  # the last cycle's box on Δθ (live; with ``cand``: observers)
        il = ist.tolist()
        nact = il[k.N_ACTIVE]
        if nact:
            rows, mult = ws.active[:nact].copy(), ws.mult[:nact].copy()
        else:
            rows, mult = _NO_ROWS, _NO_MULT
        pe, oe = self.fst[k.PE : k.OE + 1].tolist()
        return (
            V[k.THETA].copy(),
            c.limits,
            rows,
            mult,
            ws.codes.astype(np.int8) if il[k.ANY_CODE] else None,
            il[k.K],
            pe,
            oe,
            il[k.RELAXED] != 0,
            il[k.SINGULAR] != 0,
        )

    def _resume(self, status, q_start, q_prev, target, dt, position, speed, accel) -> None:
        """What the kernel asked Python for (a quadprog call, a basis, obstacle terms, the
        box's error path, the exact finiteness test of the inputs) or the failure it
        found."""
        k, ik, ist = self.k, self.ik, self.ist
        if status == k.S_NEED_QP:
            self._hard_qp()
        elif status == k.S_NEED_RELAXED:
            self._relaxed_qp()
        elif status == k.S_NEED_BASIS:
            self._choose_basis()
        elif status == k.S_NEED_TERMS:
            self._obstacle_terms(self._opts, self._active)
        elif status == k.S_BOX_CHECK:
            box = ik.box
            box.prepare(ik.model, q_start, q_prev, dt, position, speed, accel)  # raises
            self.ws.bounds[:] = box.bounds
            self.cand[:] = box.cand
            ist[k.BOX_READY] = 1
            ist[k.PHASE] = k.P_START_CHECKED
        elif status == k.S_NOT_FINITE:
            require_finite("start configuration", q_start)  # raises, as the numpy path
            require_finite("target pose", target)
            ist[k.PHASE] = k.P_START_CHECKED  # (finite: ‖q‖² overflowed)
        elif status == k.S_FROZEN_FAR:
            raise IKFailure(
                "frozen joints are away from their held values by more than the "
                "joint box allows in one cycle"
            )
        else:  # S_BAD_STEP
            raise IKFailure(
                f"inverse transformation produced a non-finite step: {self.V[k.DTHETA].copy()}"
            )

    def snapshot(self, limits):
        """The cycle's box for reports (copies the reused bounds and candidates)."""
        bounds = self.ws.bounds.copy()
        return BoxSnapshot(bounds[0], bounds[1], self.cand.copy(), limits)

    def jacobian(self):
        """A copy of the last Jacobian (its free columns under FREEZE), or None when the
        cycle computed none."""
        if not self.ist[self.k.HAVE_J]:
            return None
        frozen = self._frozen
        return self.Jt.copy() if frozen is None else self.Jt[:, frozen.free]

    # ------------------------------------------------------------------ Python parts
    def _hard_qp(self) -> None:
        """General compact QP: quadprog on the kernel's data; infeasible → relaxed."""
        k, ist, ws = self.k, self.ist, self.ws
        try:
            z, _, _, _, lagr, iact = quadprog.solve_qp(ws.Ht, ws.gt, ws.Ct, ws.bt, 0)
        except ValueError:
            ist[k.PHASE] = k.P_RELAX
            return
        rows = iact[iact > 0] - 1
        self._set_active(rows, lagr[rows] / self.fst[k.SCALE])
        ws.Vr[k.Z, : z.shape[0]] = z
        ist[k.PHASE] = k.P_APPLY_Z

    def _relaxed_qp(self) -> None:
        k, ist, ws = self.k, self.ist, self.ws
        try:
            z, _, _, _, lagr, iact = quadprog.solve_qp(ws.Hrel, ws.grel, self._crel_for(), ws.bt, 0)
        except ValueError as exc:
            if self.ws.r == 0:
                raise FloatingPointError(f"relaxed QP failed ({exc})") from None
            raise IKFailure(
                "the joint box and the coupled joint limits leave no admissible step "
                "(the coupled combination moves too fast to stop before its bound)"
            ) from None
        rows = iact[iact > 0] - 1
        factor = self.fst[k.SCALE]
        self._set_active(rows, lagr[rows] * factor)
        ws.Vr[k.DTHETA] = z
        ist[k.RELAXED] = 1
        ist[k.SINGULAR] |= ist[k.LAST_SINGULAR]
        if self._frozen is not None and ist[k.LAST_SINGULAR]:
            self._check_freeze(self._frozen)
        ist[k.PHASE] = k.P_APPLY

    def _check_freeze(self, frozen) -> None:
        """``InverseTransformation._solve``: a singular free problem while the whole J
        has full rank means FREEZE made the task impossible."""
        ik, m = self.ik, self.m
        if m <= frozen.free.size and full_rank(self.Jt, m):
            raise FreezeError(frozen.describe_impossible(ik.model, m, ik.naming))

    def _set_active(self, rows, mult) -> None:
        cnt = rows.shape[0]
        ws = self.ws
        ws.active[:cnt] = rows
        ws.mult[:cnt] = mult
        self.ist[self.k.N_ACTIVE] = cnt

    def _choose_basis(self) -> None:
        """QR with column pivoting of the current J (``CompactBasis.choose``)."""
        k, ist, fst = self.k, self.ist, self.fst
        basis = self.ik.stepper.basis
        ok = basis.choose(self.ws.Jr)
        self._sync_basis()
        if not ok:
            ist[k.LAST_SINGULAR] = 1
            ist[k.PHASE] = k.P_RELAX
            return
        stage = 0 if ist[k.BASIS_REASON] == 0 else 1
        ist[k.BASIS_STAGE] = stage
        fst[k.COND_LIMIT] = fst[k.COND_MAX] if stage == 0 else fst[k.SINGULAR_COND]
        ist[k.PHASE] = k.P_SPLIT
