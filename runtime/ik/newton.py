"""The inverse transformation of one IPO cycle: Newton–Raphson with the compact QP.

For the desired TCP pose ``x`` and ``θ_s`` the configuration at the start of the cycle::

    F(θ) = [ f(θ) ⊖ x ]_task          (rows selected by ``IKParams.task_rows``)
    k = 0, 1, …:   Δθ = argmin  gᵀΔθ + ½ΔθᵀHΔθ
                         s.t.   J(θ_k)Δθ = −F(θ_k),   lower_k ≤ Δθ ≤ upper_k
                   θ_{k+1} = θ_k + Δθ
    until ‖F_position‖ < tol_position and ‖F_orientation‖ < tol_orientation

* ``f(θ) ⊖ x`` is :func:`spatial.pose_error` (position error; world rotation vector of
  ``R·R_dᵀ``), so its Jacobian is the geometric Jacobian of the TCP.
* ``(g, H)`` is the sum of the active criteria (``R_CRITERION`` with θ⁰ and the
  obstacles: :mod:`criteria`; :mod:`weighted`, :mod:`cyclic`, :mod:`energy`, :mod:`mvr`,
  :mod:`self_motion`, :mod:`obstacle`); the box is :mod:`limits`; FREEZE removes the
  frozen joints from the variables (:mod:`freeze`).
* Each step is the compact QP of :mod:`compact`, or the relaxed QP of
  :mod:`newton_step` when the hard one has no solution; once relaxed, the cycle stays
  relaxed and iterates until the step vanishes. The remaining TCP error is the path
  deviation, reported with the binding constraint (the active bound with the largest
  multiplier, in program units).
* At least one step is taken per cycle even when ``F`` is already small, so the
  criteria (CYCLIC, obstacles, RECONFIGURATION) act while the TCP stands still.
* RECONFIGURATION (``options.self_motion``): ``F := 0`` in the first iteration.
* Never a silent zero step, never NaN: non-finite input or output raises
  :class:`IKFailure`; limits that exclude the state raise ``LimitViolationError``.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime.engine import compiled_cycle
from irlc.runtime.ik.clearance import ClearanceRows, ClearanceSpec, InequalityRows
from irlc.runtime.ik.compact import CompactBasis
from irlc.runtime.ik.coupled import CoupledRows
from irlc.runtime.ik.criteria import CycleCriteria
from irlc.runtime.ik.failure import IKFailure as IKFailure
from irlc.runtime.ik.failure import full_rank as _full_rank
from irlc.runtime.ik.failure import require_finite as _require_finite
from irlc.runtime.ik.freeze import FreezeError, FrozenJoints
from irlc.runtime.ik.limits import JointBox
from irlc.runtime.ik.newton_step import NewtonStep, StepOutcome
from irlc.runtime.ik.obstacle import obstacle_terms
from irlc.runtime.ik.params import CycleOptions, IKParams
from irlc.runtime.ik.qp import make_solver
from irlc.runtime.ik.result import CycleResult
from irlc.runtime.ik.state import IterationState
from irlc.runtime.ik.task_error import pose_error_list
from irlc.runtime.model.chain import Chain, ChainPoint, JointLimits, SerialChain
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.model.naming import JointNaming


class InverseTransformation:
    """Per-chain solver state (arrays, compact basis) reused from cycle to cycle.

    ``InverseTransformation(chain, params=…)`` solves a :class:`~irlc.runtime.model.chain.
    Chain`; ``InverseTransformation(model, kinematics, params)`` one robot: its
    :class:`~irlc.runtime.model.chain.SerialChain` with ``kinematics`` (default: the
    robot file's tool) and ``params.task_rows``. The chain's task rows win over
    ``params.task_rows`` (``self.params`` carries the chain's)."""

    def __init__(
        self,
        model: RobotModel | Chain,
        kinematics: Kinematics | None = None,
        params: IKParams | None = None,
        naming: JointNaming | None = None,
    ):
        if isinstance(model, Chain):
            chain = model
            params = dataclasses.replace(params or IKParams(), task_rows=chain.task_rows)
        else:
            params = params or IKParams.for_robot(model)
            chain = SerialChain(model, kinematics, task_rows=params.task_rows)
        self.chain = chain
        self.model = model = chain.model
        self.kin = chain.kin
        self.params = params
        self.n = n = model.n
        self.rows = np.array(chain.task_rows, dtype=int)
        npos = int(np.sum(self.rows < 3))  # rows are sorted: position rows come first
        self.pos_rows, self.ori_rows = slice(0, npos), slice(npos, self.rows.size)
        self._row_list = [int(r) for r in self.rows]
        self._all_rows = self.rows.size == 6
        self.tasks = chain.tasks  # extra equality rows, stacked under the pose rows
        self.m = chain.rows
        self.weights = chain.weights
        self.box = JointBox(n)
        self.naming = naming
        basis = CompactBasis(self.params.cond_max, self.params.singular_cond)
        self.stepper = NewtonStep(make_solver(self.params.solver), self.params.relax_weight, basis)
        self.stepper.scalar_qp = self.params.scalar_qp
        self.coupled = CoupledRows.for_model(model)
        if self.coupled is not None:
            self.coupled.naming = naming
        self._g = np.zeros(n)
        self._H = np.zeros((n, n))
        self._J6 = self.kin.jacobian_out()  # (fills without a copy)
        self._tcp = np.empty((4, 4))
        self._bounds = np.empty((2, n))
        self._lower, self._upper = self._bounds
        self._frozen_cache: tuple[tuple, FrozenJoints] | None = None
        self._no_frozen = FrozenJoints(n, {})
        self.limits = chain.limits
        self._default = CycleOptions()
        self.criteria = CycleCriteria(
            model, self.weights, self.params.obstacle.a_conf, chain.robot_columns()
        )
        self._weighted = self.criteria.distance.displacement
        self._weighted_only = self.criteria.distance.only
        self._state = IterationState(np.zeros(n), np.zeros(n), np.zeros(n))
        self._bodies_are_task_frames = chain.bodies.task_frames_are_world
        self._clearance: ClearanceRows | None = None  # R_CLEARANCE's rows (built on first use)
        self._soft_rows = 0  # the clearance rows at the end of this cycle's rows
        # None: this module's numpy path (engine.py); a chain with extra rows runs there
        self._accel = compiled_cycle(self) if chain.compiled else None

    @property
    def naming(self) -> JointNaming | None:
        """The joint names of failure messages (the program's; ``None``: ``a1 … aN``)."""
        return self.box.naming

    @naming.setter
    def naming(self, value: JointNaming | None) -> None:
        self.box.naming = value
        if getattr(self, "coupled", None) is not None:
            self.coupled.naming = value

    limits: JointLimits
    """The chain's own (position, speed, accel) limits, ``(n, 2)`` SI each — what a
    cycle uses where its options give none."""

    @property
    def accelerated(self) -> bool:
        """True when covered cycles run through the compiled kernel (:mod:`accel`)."""
        return self._accel is not None

    # ------------------------------------------------------------------ public
    def step(
        self,
        q_start: np.ndarray,
        q_prev: np.ndarray,
        target: np.ndarray,
        dt: float,
        options: CycleOptions | None = None,
    ) -> CycleResult:
        """Joint configuration at the end of one IPO cycle of length ``dt`` (s).

        ``q_start``: configuration at the start of the cycle; ``q_prev``: one cycle
        earlier (equal to ``q_start`` from rest); ``target``: desired TCP pose (4×4,
        world, m). Raises ``LimitViolationError``, ``CoupledLimitError``, ``FreezeError``
        or :class:`IKFailure`; a relaxed cycle's path deviation is the caller's to judge
        (the executor fails the run beyond its tolerance).
        """
        opts = options or self._default
        compiled = self._accel is not None and opts.clearance is None  # (rows: numpy)
        if compiled and opts.obstacles and not self._bodies_are_task_frames:
            compiled = False  # the kernel measures distances on the task chain's frames
        if compiled and self.coupled is None and not opts.frozen:
            # the kernel runs the same finiteness test first (nothing before it reads q)
            return self._step_accel(q_start, q_prev, target, dt, opts)
        tl = target.tolist()
        if not (_finite(q_start) and math.isfinite(sum(tl[0]) + sum(tl[1]) + sum(tl[2]))):
            _require_finite("start configuration", q_start)
            _require_finite("target pose", target)
        if compiled:
            return self._step_accel(q_start, q_prev, target, dt, opts)
        lim = self.limits
        acc = lim[2] if opts.accel is None else opts.accel
        box = self.box
        box.prepare(
            self.model,
            q_start,
            q_prev,
            dt,
            lim[0] if opts.position is None else opts.position,
            lim[1] if opts.speed is None else opts.speed,
            acc,
        )
        coupled = self.coupled
        if coupled is not None:
            coupled.prepare(q_start, dt, acc, q_prev)
        self._soft_rows = 0
        if opts.clearance is not None:  # R_CLEARANCE: rows beside the coupled ones
            coupled = self._inequalities(opts.clearance, q_start)
        if opts.frozen:
            frozen = self.frozen_joints(opts.frozen)
            frozen.check_task(self.model, self.m, self.naming)
        else:
            frozen = self._no_frozen

        p = self.params
        kin = self.kin
        if p.warm_start and not opts.self_motion:
            # first iterate: repeat the previous displacement (kept inside this box)
            d = box.displacement  # q_start − q_prev (prepare's own array, fresh per cycle)
            np.maximum(d, box.lower_d, out=d)
            np.minimum(d, box.upper_d, out=d)
            if frozen:
                d[frozen.frozen] = 0.0
            theta = np.add(q_start, d)
        else:
            theta = np.array(q_start, dtype=float)
        state = self._state
        state.theta, state.start = theta, q_start
        sigma = state.sigma
        criteria: list = []
        diagonal = None  # (criterion, w) when the cost is one diagonal criterion
        relaxed = singular = False
        outcome: StepOutcome | None = None
        J = None
        iterations = 0
        rd, pd = (tl[0][:3], tl[1][:3], tl[2][:3]), (tl[0][3], tl[1][3], tl[2][3])
        tcp, end, J6 = self._tcp, kin.end, self._J6
        tol_p, tol_o = p.tol_position, p.tol_orientation
        tasks, extra, task_errors, met = self.tasks, (), (), True
        for k in range(p.max_iter + 1):
            frames = kin.chain(theta)
            np.dot(frames[-1], end, out=tcp)
            e = pose_error_list(tcp, rd, pd, target)
            if self._all_rows:
                e0, e1, e2, e3, e4, e5 = e
                pe = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
                oe = math.sqrt(e3 * e3 + e4 * e4 + e5 * e5)
            else:
                e = [e[r] for r in self._row_list]
                pe, oe = self._errors(e)
            if tasks:
                point = ChainPoint(self.chain, theta, frames)
                extra = [np.asarray(t.residual(point), dtype=float) for t in tasks]
                task_errors = tuple(float(np.linalg.norm(r)) for r in extra)
                met = self._tasks_met(task_errors)
            if k == 0:
                plain = opts.reference is None and not opts.active_obstacles
                if plain and opts.criterion == "DISTANCE":
                    criteria = self._weighted_only
                    diagonal = None if frozen else self._weighted
                else:
                    criteria = self._criteria(opts, theta, frames, q_start)
                    diagonal = _single_diagonal(criteria, frozen)
            elif (
                (pe < tol_p and oe < tol_o and met)
                or k == p.max_iter
                or (relaxed and _tiny(outcome.dtheta, theta))
            ):
                break
            J = kin.tcp_jacobian(frames, tcp[:3, 3], J6)
            if not self._all_rows:
                J = J.take(self.rows, axis=0)
            if tasks:  # the extra rows under the pose rows (seed ch. 4.2: F = [f − x; Φ])
                e = [*e, *np.concatenate(extra).tolist()]
                J = np.vstack((J, *(t.jacobian(point) for t in tasks)))
            F = np.zeros(len(e)) if (k == 0 and opts.self_motion) else np.array(e)
            np.subtract(theta, q_start, out=sigma)
            state.iteration = k
            ineq = None if coupled is None else coupled.at(sigma)
            if diagonal is not None:
                outcome = self._solve_diagonal(J, F, diagonal, state, relaxed, ineq)
                dtheta = outcome.dtheta
            else:
                g, H = self._cost(criteria, state)
                box.at(sigma, self._lower, self._upper)
                outcome, dtheta = self._solve(J, F, g, H, frozen, theta, relaxed, ineq)
            relaxed = relaxed or outcome.relaxed
            singular = singular or outcome.singular
            if not math.isfinite(dtheta.dot(dtheta)):
                raise IKFailure(f"inverse transformation produced a non-finite step: {dtheta}")
            theta += dtheta
            iterations = k + 1
        else:  # no break: the last step was not followed by FK (max_iter = 0)
            frames = kin.chain(theta)
            np.dot(frames[-1], end, out=tcp)
        converged = pe < tol_p and oe < tol_o and met
        clearances = self._clearances(theta, frames, opts) if opts.obstacles else {}
        codes = box.active_codes(theta - q_start)
        qp_active = None if outcome is None else outcome.active
        # the box (for ``binding``) and J (for manipulability) are copied only when a
        # report can ask for them: otherwise ``binding`` is "" and nobody reads σ
        bound = codes is not None or relaxed or not converged
        bound = bound or (qp_active is not None and qp_active.size > 0)
        if J is not None and (opts.jacobian or not converged):
            J = J[:, frozen.free] if frozen else (J if J is not J6 else J.copy())
        else:
            J = None
        return CycleResult(
            theta,
            iterations,
            pe,
            oe,
            converged,
            relaxed,
            singular,
            clearances,
            active_codes=codes,
            box=box.snapshot() if bound else None,
            model=self.model,
            free=frozen.free,
            qp_active=qp_active,
            qp_multipliers=None if outcome is None else outcome.multipliers,
            jacobian=J,
            coupled=coupled,
            tcp=tcp.copy(),
            naming=self.naming,
            task_errors=task_errors,
        )

    # ------------------------------------------------------------------ pieces
    def _inequalities(self, spec: ClearanceSpec, q_start: np.ndarray):
        """The coupled rows and the clearance rows of this cycle (:mod:`clearance`) as one
        set (``None`` when there are none)."""
        rows = self._clearance
        if rows is None:
            rows = self._clearance = ClearanceRows(self.chain)
        rows.prepare(spec, q_start)
        self._soft_rows = len(rows)
        both = InequalityRows((self.coupled, rows))
        return both if len(both) else None

    @staticmethod
    def avoided(opts: CycleOptions) -> list:
        """The obstacles avoided (not just reported) this cycle."""
        names = opts.active_obstacles
        return [o for o in opts.obstacles if o.name in names] if names else []

    def _step_accel(self, q_start, q_prev, target, dt, opts: CycleOptions) -> CycleResult:
        """:meth:`step` through the compiled kernel (same numbers, see :mod:`accel`)."""
        acc = self._accel
        frozen = self.frozen_joints(opts.frozen) if opts.frozen else None
        theta, limits, active, mult, codes, iterations, pe, oe, relaxed, singular = acc.step(
            q_start, q_prev, target, dt, opts, frozen, self.avoided(opts)
        )
        p = self.params
        converged = pe < p.tol_position and oe < p.tol_orientation
        clearances = acc.clearances(opts.obstacles) if opts.obstacles else {}
        # as in the numpy path: keep the box and J only when a report can need them
        box = acc.snapshot(limits) if codes is not None or active.size else None
        J = acc.jacobian() if opts.jacobian or not converged else None
        return CycleResult(
            theta,
            iterations,
            pe,
            oe,
            converged,
            relaxed,
            singular,
            clearances,
            active_codes=codes,
            box=box,
            model=self.model,
            free=(frozen or self._no_frozen).free,
            qp_active=active,
            qp_multipliers=mult,
            jacobian=J,
            coupled=self.coupled,
            tcp=acc.tcp.copy(),
            naming=self.naming,
        )

    def _tasks_met(self, errors: tuple[float, ...]) -> bool:
        """Every extra task's rows below its tolerance (``tol_position`` for position
        rows, ``tol_orientation`` for orientation rows)."""
        p = self.params
        return all(
            err < (p.tol_position if t.kind == "position" else p.tol_orientation)
            for t, err in zip(self.tasks, errors, strict=True)
        )

    def _errors(self, e: list) -> tuple[float, float]:
        """Norms of the position and orientation parts of the task error."""
        pos, ori = e[self.pos_rows], e[self.ori_rows]
        return math.sqrt(sum(x * x for x in pos)), math.sqrt(sum(x * x for x in ori))

    def frozen_joints(self, frozen: dict[int, float]) -> FrozenJoints:
        """The :class:`FrozenJoints` of a FREEZE map (cached while it stays the same)."""
        key = tuple(sorted(frozen.items()))
        if self._frozen_cache is None or self._frozen_cache[0] != key:
            self._frozen_cache = (key, FrozenJoints(self.n, frozen))
        return self._frozen_cache[1]

    def _criteria(self, opts: CycleOptions, theta, frames, q_start) -> list:
        active = self.avoided(opts)
        out = self.criteria.terms(opts, q_start, bool(active))
        if active:
            bodies = self.chain.bodies
            world = bodies.world(theta, frames)
            out.extend(obstacle_terms(bodies, world, active, self.params.obstacle))
        return out

    def _cost(self, criteria, state) -> tuple[np.ndarray, np.ndarray]:
        g, H = self._g, self._H
        g.fill(0.0)
        H.fill(0.0)
        for c in criteria:
            c.accumulate(state, g, H)
        return g, H

    def _solve_diagonal(self, J, F, criterion, state, relaxed, ineq) -> StepOutcome:
        """One step for a single criterion with ``H = diag(w)`` (default, CYCLIC,
        RECONFIGURATION): the compact QP without forming ``H``."""
        g = criterion.gradient(state, self._g)
        w = criterion.w
        bounds = self._bounds
        np.subtract(self.box.bounds, state.sigma, out=bounds)
        if not relaxed:
            out = self.stepper.hard_diagonal(J, F, w, g, bounds, ineq)
            if out is not None:
                return out
        if ineq is None and self.params.solver == "quadprog":
            return self.stepper.relaxed_diagonal(J, F, w, g, bounds)
        return self._relaxed(J, F, np.diag(w), g, bounds[0], bounds[1], ineq)

    def _relaxed(self, J, F, H, g, lower, upper, ineq) -> StepOutcome:
        try:
            return self.stepper.relaxed(J, F, H, g, lower, upper, ineq)
        except FloatingPointError:
            if ineq is None:
                raise
            soft = self._soft_rows  # the clearance rows (last): the step without them
            if soft:
                keep = len(ineq[1]) - soft
                hard = None if keep == 0 else (ineq[0][:keep], ineq[1][:keep])
                self._soft_rows = 0
                try:
                    return self._relaxed(J, F, H, g, lower, upper, hard)
                finally:
                    self._soft_rows = soft
            raise IKFailure(
                "the joint box and the coupled joint limits leave no admissible step "
                "(the coupled combination moves too fast to stop before its bound)"
            ) from None

    def _solve(self, J, F, g, H, frozen: FrozenJoints, theta, relaxed, ineq=None):
        lower, upper = self._lower, self._upper
        if not frozen:
            if not relaxed:
                out = self.stepper.hard(J, F, H, g, lower, upper, ineq)
                if out is not None:
                    return out, out.dtheta
            out = self._relaxed(J, F, H, g, lower, upper, ineq)
            return out, out.dtheta
        free, fz = frozen.free, frozen.frozen
        c = frozen.step(theta)
        if np.any(c < lower[fz] - 1e-12) or np.any(c > upper[fz] + 1e-12):
            raise IKFailure(
                "frozen joints are away from their held values by more than the "
                "joint box allows in one cycle"
            )
        Ff = F + J[:, fz] @ c
        Hf = H[np.ix_(free, free)]
        gf = g[free] + H[np.ix_(free, fz)] @ c
        Jf = J[:, free]
        ineq_f = None if ineq is None else (ineq[0][:, free], ineq[1] - ineq[0][:, fz] @ c)
        out = None
        if not relaxed:
            out = self.stepper.hard(Jf, Ff, Hf, gf, lower[free], upper[free], ineq_f)
        if out is None:
            out = self._relaxed(Jf, Ff, Hf, gf, lower[free], upper[free], ineq_f)
        if out.singular and self.m <= free.size and _full_rank(J, self.m):
            raise FreezeError(frozen.describe_impossible(self.model, self.m, self.naming))
        dtheta = np.empty(self.n)
        dtheta[free] = out.dtheta
        dtheta[fz] = c
        return out, dtheta

    def _clearances(self, theta, frames, opts: CycleOptions) -> dict[str, tuple[float, int]]:
        if not opts.obstacles:
            return {}
        bodies = self.chain.bodies
        world = bodies.world(theta, frames)
        return {
            cp.name: (cp.distance, cp.link) for cp in bodies.critical_points(world, opts.obstacles)
        }


def _single_diagonal(criteria: list, frozen: FrozenJoints):
    """The criterion if the cost is exactly one diagonal criterion and nothing is frozen."""
    if len(criteria) == 1 and not frozen and hasattr(criteria[0], "gradient"):
        return criteria[0]
    return None


def _finite(x: np.ndarray) -> bool:
    """All entries finite (one dot product; ‖x‖² overflowing is not a configuration —
    the caller then runs the exact check)."""
    return math.isfinite(x.dot(x))


def _tiny(dtheta: np.ndarray, theta: np.ndarray) -> bool:
    return float(np.max(np.abs(dtheta))) <= 1e-13 * (1.0 + float(np.max(np.abs(theta))))
