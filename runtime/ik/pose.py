"""Joint configuration for one TCP pose (``irlc ik``, PTP to a POSE target).

The same machinery as the IPO cycle (:mod:`newton_step`: compact QP, relaxed QP when
the hard step has no solution) iterated from a seed configuration::

    min  ½(θ_k + Δθ − θ_seed)ᵀW(θ_k + Δθ − θ_seed)
    s.t. JΔθ = −F(θ_k),   max(θmin − θ_k, −s) ≤ Δθ ≤ min(θmax − θ_k, s)

The robot's position limits always hold, and so do its coupled limits
(``[[coupled_limits]]``, rows ``A(θ_k + Δθ) ≥ b`` added to both QPs; a seed violating
them is reported like a seed outside its box); the trust box ``s`` (``max_step`` rad for
revolute, ``max_step_prismatic`` m for prismatic joints) keeps steps short for far
targets, where the hard step is infeasible and the relaxed step (damped Gauss–Newton
inside the box) walks towards the target; a relaxed step that increases the error
(Gauss–Newton overshooting near a singular, stretched arm) is taken back and the trust
box halved, so the walk ends at the closest pose instead of oscillating around it. Near
the solution the hard step is plain Newton–Raphson (quadratic convergence) and the cost
picks, among the configurations reaching the pose, one close to the seed (five hard steps
in a row that do not halve the error — the pull makes long null-space moves of a
redundant arm that the linearisation does not follow, and the error oscillates — switch
the pull off for the rest of the search). If the relaxed
steps stall away from the target (the step vanishes, or the error falls by less than 0.1
% over ten steps), no solution was found from this seed: the result says how far the
closest pose is and which limits are reached, and "target not reachable" only where
:mod:`unreachable` proves that no configuration within the limits reaches it (closed
form, the 5-axis plane condition, the chain's reach); other seeds: :mod:`find`. In
relaxed steps the seed pull is dropped (pure damped least squares), so it cannot bias
where the iteration stops.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime.ik import unreachable
from irlc.runtime.ik.compact import CompactBasis
from irlc.runtime.ik.limits import format_joint_value
from irlc.runtime.ik.newton_step import NewtonStep
from irlc.runtime.ik.qp import QuadprogSolver
from irlc.runtime.ik.seed import seed_problem
from irlc.runtime.model import spatial
from irlc.runtime.model.chain import task_rows_for
from irlc.runtime.model.coupled_limits import (
    as_inequalities,
    coupled_limits,
    row_label,
)
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.model.naming import JointNaming, naming_or_default

SLOW_HARD_STEPS = 5  # this many hard steps in a row not halving the error: drop the pull


@dataclass
class PoseSolution:
    q: np.ndarray  # SI
    converged: bool
    position_error: float  # m (controlled components only)
    orientation_error: float  # rad
    iterations: int
    message: str


def solve_pose(
    model: RobotModel,
    target: np.ndarray,
    seed: np.ndarray,
    *,
    tool: np.ndarray | None = None,
    max_iter: int = 200,
    tol_position: float = 1e-7,
    tol_orientation: float = 1e-7,
    task_rows: tuple[int, ...] | None = None,
    max_step: float = 0.3,
    max_step_prismatic: float = 0.1,
    naming: JointNaming | None = None,
    kin: Kinematics | None = None,
) -> PoseSolution:
    """Solve ``f(q) = target`` (4×4 world pose, m) starting from ``seed`` (SI); messages
    name joints by ``naming`` (default ``a1 … aN``). ``kin``: ``Kinematics(model, tool)``
    from a caller that solves many poses with one model and tool (built here if not
    given; ``tool`` is then ignored)."""
    naming = naming_or_default(naming, model)
    target = np.asarray(target, dtype=float)
    q = np.array(seed, dtype=float)
    if target.shape != (4, 4) or not np.all(np.isfinite(target)):
        return PoseSolution(q, False, np.inf, np.inf, 0, "target must be a finite 4×4 pose")
    if q.shape != (model.n,) or not np.all(np.isfinite(q)):
        return PoseSolution(
            q, False, np.inf, np.inf, 0, f"seed must be {model.n} finite joint values"
        )
    kin = Kinematics(model, tool) if kin is None else kin
    rows = np.array(task_rows if task_rows is not None else task_rows_for(model), dtype=int)
    pos_rows, ori_rows = np.flatnonzero(rows < 3), np.flatnonzero(rows >= 3)
    problem = seed_problem(model, q, naming)
    if problem is not None:  # the errors are those of the seed
        F = spatial.pose_error(kin.tcp(q), target)[rows]
        return PoseSolution(q, False, _norm(F[pos_rows]), _norm(F[ori_rows]), 0, problem)
    limits = model.position_limits
    coupled = coupled_limits(model)
    A, b = as_inequalities(coupled, model.n)
    step = np.array(
        [max_step if j.kind == "revolute" else max_step_prismatic for j in model.joints]
    )
    w = model.weights
    H = np.diag(w)
    stepper = NewtonStep(QuadprogSolver(), basis=CompactBasis())
    zero = np.zeros(model.n)
    pe = oe = np.inf
    last = None
    history: list[float] = []
    before: tuple | None = None  # (q, error) before the last relaxed step
    scale = 1.0  # trust-box scale: halved when a relaxed step overshoots
    pull = 1.0  # weight of the seed pull in hard steps (dropped when they stop converging)
    slow = 0  # consecutive hard steps that did not halve the error
    for it in range(max_iter + 1):
        frames = kin.link_frames(q)
        tcp = kin.tcp_from_frames(frames)
        F = spatial.pose_error(tcp, target)[rows]
        pe, oe = _norm(F[pos_rows]), _norm(F[ori_rows])
        if pe < tol_position and oe < tol_orientation:
            return PoseSolution(q, True, pe, oe, it, f"converged in {it} iterations")
        if it == max_iter:
            break
        if before is not None and pe + oe > before[1] and scale > 1e-6:
            q, scale, before = before[0], 0.5 * scale, None  # overshoot: back, shorter
            continue
        if last is not None and not last.relaxed and pe + oe > 0.5 * history[-1]:
            slow += 1  # a hard step that did not halve the error
            pull = 0.0 if slow >= SLOW_HARD_STEPS else pull
        elif last is not None and not last.relaxed:
            slow = 0
        history.append(pe + oe)
        if last is not None and last.relaxed and _stalled(last.dtheta, history):
            why = unreachable.proof(model, target, kin.tool, limits, tuple(int(r) for r in rows))
            text = _unreachable(model, q, pe, oe, naming, why) + _coupled_reached(coupled, A, b, q)
            return PoseSolution(q, False, pe, oe, it, text)
        J = kin.jacobian_at(frames, tcp[:3, 3])[rows]
        lower = np.maximum(limits[:, 0] - q, -scale * step)
        upper = np.minimum(limits[:, 1] - q, scale * step)
        ineq = (A, b - A @ q) if b.size else None  # coupled limits: A(q + Δθ) ≥ b
        try:  # the seed pull acts in the null space only; the relaxed step is pure DLS
            g = pull * w * (q - seed)
            last = stepper.hard(J, F, H, g, lower, upper, ineq) or stepper.relaxed(
                J, F, H, zero, lower, upper, ineq
            )
        except FloatingPointError as exc:
            return PoseSolution(q, False, pe, oe, it, f"solver failure: {exc}")
        if not np.all(np.isfinite(last.dtheta)):
            return PoseSolution(q, False, pe, oe, it, "solver produced a non-finite step")
        before = (q, pe + oe) if last.relaxed else None
        q = np.clip(q + last.dtheta, limits[:, 0], limits[:, 1])  # rounding only (≤ 1e-12)
    return PoseSolution(
        q,
        False,
        pe,
        oe,
        max_iter,
        f"{unreachable.NOT_FOUND}: no convergence in {max_iter} iterations "
        f"(left {pe * 1e3:.4g} mm, {np.degrees(oe):.4g} deg)",
    )


def _norm(v: np.ndarray) -> float:
    """‖v‖ without overflow for huge targets (``hypot`` scales; ``sqrt(v·v)`` overflows)."""
    return math.hypot(*v)


def _stalled(dtheta: np.ndarray, history: list[float], window: int = 10) -> bool:
    """Relaxed steps vanish, or the error fell by < 0.1 % over the last ``window`` steps."""
    if float(np.max(np.abs(dtheta))) < 1e-12:
        return True
    return len(history) > window and history[-1] > 0.999 * history[-1 - window]


def _coupled_reached(coupled, A, b, q) -> str:
    """`` (coupled limits reached: theta2+theta3 max 25 deg)`` or ``""``."""
    if not b.size:
        return ""
    at = np.flatnonzero(A @ q - b <= 1e-9)
    if not at.size:
        return ""
    rows = []  # in the order of as_inequalities' rows
    for c in coupled:
        if np.isfinite(c.lower):
            rows.append(row_label(c, "min"))
        if np.isfinite(c.upper):
            rows.append(row_label(c, "max"))
    return f" (coupled limits reached: {', '.join(rows[i] for i in at)})"


def _unreachable(model, q, pe, oe, naming: JointNaming, why: str | None) -> str:
    """``target not reachable (why): …`` when :func:`unreachable.proof` proves it, else
    ``no solution found from this start: …`` (another start may still reach the pose)."""
    head = unreachable.NOT_FOUND if why is None else f"{unreachable.NOT_REACHABLE} ({why})"
    text = f"{head}: the closest pose found is {pe * 1e3:.4g} mm and {np.degrees(oe):.4g} deg away"
    limits = model.position_limits
    at = [j for j in range(model.n) if q[j] <= limits[j, 0] + 1e-9 or q[j] >= limits[j, 1] - 1e-9]
    if at:
        names = ", ".join(
            f"{naming.label(j)} at position "
            f"{'min' if q[j] <= limits[j, 0] + 1e-9 else 'max'} "
            f"{format_joint_value(model, j, q[j], 0)}"
            for j in at
        )
        text += f" (limits reached: {names})"
    return text
