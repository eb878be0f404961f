"""The inverse transformation of one IPO cycle: Newton–Raphson with the compact QP.

For the desired TCP pose ``x`` and ``θ_s`` the configuration at the start of the cycle::

    F(θ) = [ f(θ) ⊖ x ]_task          (rows selected by ``IKParams.task_rows``)
    k = 0, 1, …:   Δθ = argmin  gᵀΔθ + ½ΔθᵀHΔθ
                         s.t.   J(θ_k)Δθ = −F(θ_k),   lower_k ≤ Δθ ≤ upper_k
                   θ_{k+1} = θ_k + Δθ
    until ‖F_position‖ < tol_position and ‖F_orientation‖ < tol_orientation

* ``f(θ) ⊖ x`` is :func:`spatial.pose_error` (position error; world rotation vector of
  ``R·R_dᵀ``), so its Jacobian is the geometric Jacobian of the TCP.
* ``(g, H)`` is the sum of the active criteria (:mod:`weighted`, :mod:`cyclic`,
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

import math

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime import spatial
from irlc.runtime.distance import critical_points
from irlc.runtime.errors import RunFailure
from irlc.runtime.ik.compact import CompactBasis
from irlc.runtime.ik.cyclic import CyclicReference
from irlc.runtime.ik.freeze import FreezeError, FrozenJoints
from irlc.runtime.ik.limits import JointBox
from irlc.runtime.ik.newton_step import NewtonStep, StepOutcome
from irlc.runtime.ik.obstacle import obstacle_terms
from irlc.runtime.ik.params import CycleOptions, CycleResult, IKParams
from irlc.runtime.ik.qp import make_solver
from irlc.runtime.ik.state import IterationState
from irlc.runtime.ik.weighted import WeightedDisplacement
from irlc.runtime.kinematics import Kinematics


class IKFailure(RunFailure):
    """The inverse transformation cannot produce a valid configuration."""


class DeviationError(IKFailure):
    """A relaxed cycle left the path by more than the tolerance; ``result`` has details."""

    def __init__(self, message: str, result: CycleResult):
        super().__init__(message, constraint=result.binding or None)
        self.result = result


class InverseTransformation:
    """Per-robot solver state (arrays, compact basis) reused from cycle to cycle."""

    def __init__(self, model: RobotModel, kinematics: Kinematics, params: IKParams | None = None):
        self.model = model
        self.kin = kinematics
        self.params = params or IKParams.for_robot(model)
        self.n = model.n
        self.rows = np.array(self.params.task_rows, dtype=int)
        npos = int(np.sum(self.rows < 3))  # rows are sorted: position rows come first
        self.pos_rows, self.ori_rows = slice(0, npos), slice(npos, self.rows.size)
        self._all_rows = self.rows.size == 6
        self.weights = model.weights
        self.box = JointBox(self.n)
        basis = CompactBasis(self.params.cond_max, self.params.singular_cond)
        self.stepper = NewtonStep(make_solver(self.params.solver), self.params.relax_weight, basis)
        self._g = np.zeros(self.n)
        self._H = np.zeros((self.n, self.n))
        self._lower = np.empty(self.n)
        self._upper = np.empty(self.n)
        self._frozen_cache: tuple[tuple, FrozenJoints] | None = None
        self._limits = (model.position_limits, model.speed_limits, model.accel_limits)
        self._default = CycleOptions()
        self._weighted = WeightedDisplacement(self.weights)
        self._conf = WeightedDisplacement(self.weights, self.params.obstacle.a_conf)

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
        world, m). Raises ``LimitViolationError``, ``FreezeError``, ``DeviationError``
        (only if ``IKParams.max_deviation`` is set) or :class:`IKFailure`.
        """
        opts = options or self._default
        _require_finite("start configuration", q_start)
        _require_finite("target pose", target)
        pos = self._limits[0] if opts.position is None else opts.position
        spd = self._limits[1] if opts.speed is None else opts.speed
        acc = self._limits[2] if opts.accel is None else opts.accel
        self.box.prepare(self.model, q_start, q_prev, dt, pos, spd, acc)
        frozen = self._frozen(opts.frozen)
        frozen.check_task(self.model, self.rows.size)
        free = frozen.free

        p = self.params
        kin = self.kin
        theta = np.array(q_start, dtype=float)
        if p.warm_start and not opts.self_motion:
            # first iterate: repeat the previous displacement (kept inside this box)
            d = np.clip(q_start - q_prev, self.box.lower_d, self.box.upper_d)
            d[frozen.frozen] = 0.0
            theta += d
        state = IterationState(theta, q_start, np.zeros(self.n))
        criteria: list = []
        relaxed = singular = False
        outcome: StepOutcome | None = None
        J = None
        iterations = 0
        for k in range(p.max_iter + 1):
            frames = kin.link_frames(theta)
            tcp = kin.tcp_from_frames(frames)
            F = spatial.pose_error(tcp, target)
            if not self._all_rows:
                F = F[self.rows]
            if k == 0:
                criteria = self._criteria(opts, frames)
            elif self._done(F, k, relaxed, outcome, theta):
                break
            if k == 0 and opts.self_motion:
                F[:] = 0.0
            J = kin.jacobian_at(frames, tcp[:3, 3])
            if not self._all_rows:
                J = J[self.rows]
            np.subtract(theta, q_start, out=state.sigma)
            state.iteration = k
            g, H = self._cost(criteria, state)
            self.box.at(state.sigma, self._lower, self._upper)
            outcome, dtheta = self._solve(J, F, g, H, frozen, theta, relaxed)
            relaxed = relaxed or outcome.relaxed
            singular = singular or outcome.singular
            if not np.isfinite(dtheta @ dtheta):
                raise IKFailure(f"inverse transformation produced a non-finite step: {dtheta}")
            theta += dtheta
            iterations = k + 1
        pe, oe = _norm(F, self.pos_rows), _norm(F, self.ori_rows)
        converged = pe < p.tol_position and oe < p.tol_orientation
        clearances = self._clearances(frames, opts)
        result = CycleResult(
            theta,
            iterations,
            pe,
            oe,
            converged,
            relaxed,
            singular,
            clearances,
            delta=theta - q_start,
            box=self.box.snapshot(),
            model=self.model,
            free=free,
            qp_active=None if outcome is None else outcome.active,
            qp_multipliers=None if outcome is None else outcome.multipliers,
            jacobian=None if J is None else J[:, free],
        )
        self._check_deviation(result)
        return result

    # ------------------------------------------------------------------ pieces
    def _frozen(self, frozen: dict[int, float]) -> FrozenJoints:
        key = tuple(sorted(frozen.items()))
        if self._frozen_cache is None or self._frozen_cache[0] != key:
            self._frozen_cache = (key, FrozenJoints(self.n, frozen))
        return self._frozen_cache[1]

    def _criteria(self, opts: CycleOptions, frames: np.ndarray) -> list:
        out: list = []
        active = [o for o in opts.obstacles if o.name in opts.active_obstacles]
        if opts.reference is not None:
            out.append(CyclicReference(self.weights, opts.reference))
            if active:
                out.append(self._conf)
        else:
            out.append(self._conf if active else self._weighted)
        if active:
            out.extend(obstacle_terms(self.kin, frames, active, self.params.obstacle))
        return out

    def _cost(self, criteria, state) -> tuple[np.ndarray, np.ndarray]:
        g, H = self._g, self._H
        g.fill(0.0)
        H.fill(0.0)
        for c in criteria:
            c.accumulate(state, g, H)
        return g, H

    def _solve(self, J, F, g, H, frozen: FrozenJoints, theta, relaxed):
        lower, upper = self._lower, self._upper
        if not frozen:
            solve = self.stepper.relaxed if relaxed else self.stepper.solve
            out = solve(J, F, H, g, lower, upper)
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
        if relaxed:
            out = self.stepper.relaxed(Jf, Ff, Hf, gf, lower[free], upper[free])
        else:
            out = self.stepper.solve(Jf, Ff, Hf, gf, lower[free], upper[free])
        if out.singular and self.rows.size <= free.size and _full_rank(J, self.rows.size):
            raise FreezeError(frozen.describe_impossible(self.model, self.rows.size))
        dtheta = np.empty(self.n)
        dtheta[free] = out.dtheta
        dtheta[fz] = c
        return out, dtheta

    def _done(self, F, k: int, relaxed: bool, outcome, theta) -> bool:
        if self._converged(F) or k == self.params.max_iter:
            return True
        return relaxed and _tiny(outcome.dtheta, theta)

    def _converged(self, F: np.ndarray) -> bool:
        p = self.params
        return (
            _norm(F, self.pos_rows) < p.tol_position and _norm(F, self.ori_rows) < p.tol_orientation
        )

    def _clearances(self, frames, opts: CycleOptions) -> dict[str, tuple[float, int]]:
        if not opts.obstacles:
            return {}
        return {
            cp.name: (cp.distance, cp.link)
            for cp in critical_points(self.kin, frames, opts.obstacles)
        }

    def _check_deviation(self, r: CycleResult) -> None:
        p = self.params
        too_far = p.max_deviation is not None and r.position_error > p.max_deviation
        too_far |= (
            p.max_orientation_deviation is not None
            and r.orientation_error > p.max_orientation_deviation
        )
        if too_far:
            what = f" (bound by {r.binding})" if r.binding else ""
            raise DeviationError(
                f"the path cannot be followed: TCP deviation {r.position_error * 1e3:.3f} mm, "
                f"{np.degrees(r.orientation_error):.3f} deg{what}",
                r,
            )


def _norm(F: np.ndarray, rows: slice) -> float:
    part = F[rows]
    return math.sqrt(part @ part)


def _tiny(dtheta: np.ndarray, theta: np.ndarray) -> bool:
    return float(np.max(np.abs(dtheta))) <= 1e-13 * (1.0 + float(np.max(np.abs(theta))))


def _full_rank(J: np.ndarray, m: int) -> bool:
    s = np.linalg.svd(J, compute_uv=False)
    return s.size >= m and s[m - 1] > 1e-10 * s[0]


def _require_finite(what: str, x: np.ndarray) -> None:
    if not np.all(np.isfinite(x)):
        raise IKFailure(f"inverse transformation: non-finite {what}")
