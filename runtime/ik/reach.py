"""Reachability of Cartesian targets before a motion starts, and walks along a path.

**One search.** Whether a TCP pose is reachable is decided by :func:`pose.solve_pose`,
the search PTP to a POSE uses, under the *active* position limits (robot ∩ JOINTLIMIT),
with frozen joints held (their position range collapsed to the held value) and the
active tool. :func:`solve_within` is that call; the executor's PTP and the pre-check
below share it.

**Pre-check** (:func:`check_targets`). Before a LIN, CIRCLE, LIN PATH or MOVE_INC LIN
moves, the end point of each segment and the via point of a circle (its full pose on
the arc, orientation by slerp) are solved, each seeded with the previous solution
(the first with the current configuration). A pose counts as reachable when the
search converges or leaves less than the run's path tolerance (``tol_position``,
``tol_orientation``: what the motion itself would accept). When the direct search
from the seed stalls, the path is walked (:func:`walk`) in short steps (≤ 50 mm,
≤ 10 deg) with each solution seeding the next — the way the cycle-by-cycle motion
follows it — and from other starts (:meth:`Reach.search`: the closed-form configurations
within the limits for a robot with ``[ik] closed_form``, then the seed moved off a possible
singularity, home, mid-range, a Halton spread over the limits), so that a far but
reachable target is not rejected because the direct search met a local minimum or a
joint limit. A target none of these reaches fails at its line, before the robot moves
(cause ``unreachable``, with the distance of the closest pose found); its message says
"not reachable" only where :mod:`unreachable` proves that no configuration within the
limits reaches it, else "no solution found … from this start nor from N other starts".
If it is reachable with the frozen joints released the cause is ``freeze``, if it is
reachable within the robot's own position limits (not the JOINTLIMIT) ``position_limit``.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime import units
from irlc.runtime.errors import RunFailure
from irlc.runtime.ik import closed_form, freeze_with_limits, unreachable
from irlc.runtime.ik.pose import PoseSolution, solve_pose
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.model.naming import JointNaming

STEP_LENGTH = 0.05  # m: longest walk step along the path
STEP_ANGLE = 10.0 * units.DEG  # rad


class LimitedModels:
    """The robot model narrowed to given position limits, with its kinematics for a tool,
    built once per ``(limits, tool)`` and reused: the pre-check solves a pose per target,
    the walks one per step, and building the model copy and its :class:`Kinematics`
    costs about a third of a short search. Holds the ``MAX_KEPT`` latest (a frozen
    joint's held value is part of its limits)."""

    MAX_KEPT = 32

    def __init__(self, model: RobotModel):
        self.model = model
        self._built: dict[bytes, tuple[RobotModel, Kinematics]] = {}

    def get(self, position: np.ndarray, tool: np.ndarray) -> tuple[RobotModel, Kinematics]:
        """``(model within position, Kinematics(that model, tool))`` (``position`` SI
        ``(n, 2)``, ``tool`` 4×4)."""
        position = np.ascontiguousarray(position, dtype=float)
        key = position.tobytes() + np.ascontiguousarray(tool, dtype=float).tobytes()
        built = self._built.get(key)
        if built is None:
            limited = _with_position_limits(self.model, position)
            built = (limited, Kinematics(limited, tool))
            if len(self._built) >= self.MAX_KEPT:
                del self._built[next(iter(self._built))]
            self._built[key] = built
        return built


@dataclass(frozen=True)
class Reach:
    """The search's context: model, active position limits, frozen joints, tool, task;
    ``models`` the narrowed models built so far (:class:`LimitedModels`; a caller running
    many statements passes one it keeps)."""

    model: RobotModel
    position: np.ndarray  # (n, 2) SI, the active position limits
    frozen: dict[int, float]
    tool: np.ndarray
    task_rows: tuple[int, ...]
    naming: JointNaming
    tol_position: float = 5e-5  # m: a pose this close counts as reached
    tol_orientation: float = 0.01 * units.DEG
    models: LimitedModels | None = field(default=None, compare=False, repr=False)

    def __post_init__(self) -> None:
        if self.models is None or self.models.model is not self.model:
            object.__setattr__(self, "models", LimitedModels(self.model))

    def solve(self, target: np.ndarray, seed: np.ndarray, *, frozen: bool = True) -> PoseSolution:
        """:func:`solve_within` in this context (``frozen=False``: the frozen joints free)."""
        return solve_within(
            self.model,
            target,
            seed,
            self.position,
            self.frozen if frozen else {},
            self.tool,
            self.task_rows,
            self.naming,
            self.models,
        )

    def search(self, target: np.ndarray, seed: np.ndarray, *, frozen: bool = True) -> PoseSolution:
        """:meth:`solve` from ``seed``; if that stalls, again from the other starts
        (:meth:`starts`). The first solution that reaches the pose, else the closest one,
        whose message says how many starts were tried when none proves the pose out of
        reach."""
        best = self.solve(target, seed, frozen=frozen)
        if self.reached(best):
            return best
        others = self.starts(target, seed, frozen=frozen)
        for start in others:
            sol = self.solve(target, start, frozen=frozen)
            if self.reached(sol):
                return sol
            if _residual(sol) < _residual(best):
                best = sol
        return dataclasses.replace(best, message=tried_starts(best.message, len(others)))

    def starts(self, target: np.ndarray, seed: np.ndarray, *, frozen: bool = True):
        """Other starts for a stalled search: the closed-form configurations within the
        active limits (robots with ``[ik] closed_form``; nearest to the seed first), then
        :func:`restarts`."""
        pos = np.array(self.position, dtype=float)
        for j, v in (self.frozen if frozen else {}).items():
            pos[j] = (v, v)
        exact = closed_form.starts(self.model, target, seed, pos, self.tool)
        return [q for _, q in exact] + restarts(self.model, seed, self.position)

    def reached(self, sol: PoseSolution) -> bool:
        return sol.converged or (
            sol.position_error <= self.tol_position
            and sol.orientation_error <= self.tol_orientation
        )


def solve_within(
    model: RobotModel,
    target: np.ndarray,
    seed: np.ndarray,
    position: np.ndarray,
    frozen: dict[int, float],
    tool: np.ndarray,
    task_rows: tuple[int, ...] | None = None,
    naming: JointNaming | None = None,
    models: LimitedModels | None = None,
) -> PoseSolution:
    """:func:`solve_pose` within the position limits ``position`` (SI ``(n, 2)``), the
    frozen joints held at their values (range ``[v, v]``); the narrowed model from
    ``models`` when given (built once per limits), else built for this call."""
    pos = np.array(position, dtype=float)
    for j, v in frozen.items():
        pos[j] = (v, v)
    seed = np.clip(seed, pos[:, 0], pos[:, 1])  # a frozen joint's rounding (≤ 1e-9)
    if models is None or models.model is not model:
        models = LimitedModels(model)
    limited, kin = models.get(pos, tool)
    return solve_pose(limited, target, seed, tool=tool, task_rows=task_rows, naming=naming, kin=kin)


def restarts(
    model: RobotModel, seed: np.ndarray, position: np.ndarray, spread: int = 8
) -> list[np.ndarray]:
    """Other starts for a stalled search, in this order: the seed moved by ±0.2 rad
    (±50 mm prismatic; alternating signs, off a singular stretched or folded pose), the
    robot's home, the middle of the position limits, then ``spread`` points of a Halton
    sequence spread over the limits (infinite ranges: ±π rad, ±1 m) — a deterministic
    cover of the configuration space, so that a branch the seed cannot slide to (across
    a joint limit) is still found. All inside the limits."""
    lo, hi = position[:, 0], position[:, 1]
    revolute = np.array([j.kind == "revolute" for j in model.joints])
    step = np.where(revolute, 0.2, 0.05)
    sign = np.where(np.arange(model.n) % 2 == 0, 1.0, -1.0)
    wide = np.where(revolute, math.pi, 1.0)
    lo_f, hi_f = np.maximum(lo, -wide), np.minimum(hi, wide)
    lo_f, hi_f = np.minimum(lo_f, hi), np.maximum(hi_f, lo)  # ranges outside ±wide
    mid = 0.5 * (lo_f + hi_f)
    home = model.home if model.home is not None else mid
    starts = [np.asarray(seed) + sign * step, np.asarray(home, dtype=float), mid]
    starts += [lo_f + u * (hi_f - lo_f) for u in _halton(spread, model.n)]
    return [np.clip(q, lo, hi) for q in starts]


def _halton(count: int, dim: int) -> np.ndarray:
    """The first ``count`` points (from index 1) of the Halton sequence in ``[0, 1)^dim``."""
    primes = [2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53]
    out = np.zeros((count, dim))
    for d in range(dim):
        base = primes[d % len(primes)]
        for i in range(count):
            k, f, x = i + 1, 1.0, 0.0
            while k:
                f /= base
                x += f * (k % base)
                k //= base
            out[i, d] = x
    return out


def tried_starts(message: str, others: int) -> str:
    """``no solution found from this start`` → ``… nor from N other starts`` (a proven
    ``target not reachable`` message is left as it is)."""
    return message.replace(
        unreachable.NOT_FOUND, f"{unreachable.NOT_FOUND} nor from {others} other starts", 1
    )


def _residual(sol: PoseSolution) -> float:
    return sol.position_error + sol.orientation_error


def _with_position_limits(model: RobotModel, position: np.ndarray) -> RobotModel:
    joints = tuple(
        dataclasses.replace(j, limits=dataclasses.replace(j.limits, position=tuple(position[i])))
        for i, j in enumerate(model.joints)
    )
    return dataclasses.replace(model, joints=joints)


def walk(
    reach: Reach,
    at: Callable[[float], np.ndarray],
    seed: np.ndarray,
    s0: float,
    steps: int,
    *,
    frozen: bool = True,
) -> tuple[np.ndarray, list[np.ndarray], PoseSolution | None]:
    """Solve the poses ``at(s)`` for ``s`` from ``s0`` to 1 in ``steps`` equal steps, each
    seeded with the previous solution (where that stalls, :meth:`Reach.search`'s restarts:
    the configurations may then jump to another branch, which shows as a large ``dq/ds``).
    Returns the ``s`` reached, the configurations, and the failed solution (``None``
    when the walk reached ``s = 1``)."""
    s_values = np.linspace(s0, 1.0, steps + 1)[1:]
    configs: list[np.ndarray] = []
    q = np.asarray(seed, dtype=float)
    for i, s in enumerate(s_values):
        sol = reach.solve(at(float(s)), q, frozen=frozen)
        if not reach.reached(sol):  # stalled: the restarts (a jump to another branch)
            sol = reach.search(at(float(s)), q, frozen=frozen)
        if not reach.reached(sol):
            return s_values[:i], configs, sol
        q = sol.q
        configs.append(q)
    return s_values, configs, None


def walk_steps(path, s0: float = 0.0, timed_orientation: bool = True) -> int:
    """Number of walk steps for the rest of ``path`` (≤ 50 mm, ≤ 10 deg each)."""
    rest = 1.0 - s0
    angle = path.angle if timed_orientation else 0.0
    return max(1, math.ceil(rest * max(path.length / STEP_LENGTH, angle / STEP_ANGLE)))


def check_targets(
    reach: Reach, segments, seed: np.ndarray, line: int, time_s: float, what: str
) -> None:
    """The pre-check: raise a :class:`RunFailure` (cause ``unreachable`` or ``freeze``) at
    ``line`` if a segment's end point or a circle's via point cannot be reached."""
    q = np.asarray(seed, dtype=float)
    timed = any(r >= 3 for r in reach.task_rows)
    for seg in segments:
        points = [1.0]
        via = getattr(seg.path, "via_fraction", None)
        if via is not None:
            points = [float(via), 1.0]
        s_prev = 0.0
        for s in points:
            target = seg.path.at(s)
            sol = reach.solve(target, q)
            if not reach.reached(sol):
                sol = _walked(reach, seg.path, q, s_prev, s, sol, timed)
            if not reach.reached(sol):
                sol = _closer(reach.search(target, q), sol)
            if not reach.reached(sol):
                raise unreachable_failure(reach, target, q, sol, line, time_s, what, s < 1.0)
            q, s_prev = sol.q, s


def _closer(a: PoseSolution, b: PoseSolution) -> PoseSolution:
    return a if _residual(a) <= _residual(b) else b


def _walked(reach: Reach, path, seed, s0: float, s1: float, direct, timed) -> PoseSolution:
    """The solution at ``path.at(s1)`` found by walking from ``path.at(s0)``; the direct
    one (whose residual is the reported distance) when the walk does not get there."""
    steps = max(1, math.ceil(walk_steps(path, 0.0, timed) * (s1 - s0)))
    _, configs, failed = walk(reach, lambda u: path.at(s0 + u * (s1 - s0)), seed, 0.0, steps)
    # (the walk's last pose is the target: solving it again from there takes 0 steps)
    return direct if failed is not None else reach.solve(path.at(s1), configs[-1])


def unreachable_failure(
    reach: Reach, target, seed, sol, line, time_s, what: str, via: bool = False
) -> RunFailure:
    """The pre-check's (and PTP's) failure for a pose the search did not reach: cause
    ``freeze`` when it is reachable with the frozen joints free, ``position_limit`` when
    it is reachable within the robot's own position limits (a JOINTLIMIT excludes it),
    else ``unreachable``."""
    point = "via point" if via else "target"
    details = {
        "distance_mm": sol.position_error / units.MM,
        "distance_deg": sol.orientation_error / units.DEG,
    }
    if reach.frozen and reach.reached(reach.search(target, seed, frozen=False)):
        narrowed = freeze_with_limits.narrowed_joints(reach, target, seed, sol.q)
        if narrowed:  # the JOINTLIMIT is part of the cause: each alone reaches the pose
            closest = (
                f": the closest pose found is {sol.position_error / units.MM:.4g} mm and "
                f"{sol.orientation_error / units.DEG:.4g} deg away"
            )
            head = f"{what}: the {point} is out of reach"
            tail = closest + freeze_with_limits.EACH_ALONE
            return freeze_with_limits.failure(reach, narrowed, head, tail, line, time_s, details)
        names = reach.naming.labels(sorted(reach.frozen))
        details["joints"] = [reach.naming.name(j) for j in sorted(reach.frozen)]
        return RunFailure(
            f"{what}: FREEZE of joints {names} leaves too few free joints to reach the "
            f"{point}: with them held the closest pose is "
            f"{sol.position_error / units.MM:.4g} mm and "
            f"{sol.orientation_error / units.DEG:.4g} deg away (it is reachable with "
            "them free)",
            line,
            time_s,
            f"FREEZE {names}",
            cause="freeze",
            details=details,
        )
    text = sol.message.replace(unreachable.NOT_REACHABLE, f"{point} not reachable", 1)
    found = f"no solution found for the {point} from this start"
    text = text.replace(unreachable.NOT_FOUND, found, 1)
    own = reach.model.position_limits
    if not np.array_equal(reach.position, own):  # JOINTLIMIT narrows the robot's limits
        wide = dataclasses.replace(reach, position=own)
        if wide.reached(wide.search(target, seed)):
            return RunFailure(
                f"{what}: {text}; within the robot's own position limits it is reachable: "
                "the active JOINTLIMIT excludes it",
                line,
                time_s,
                cause="position_limit",
                details=details,
            )
    return RunFailure(f"{what}: {text}", line, time_s, cause="unreachable", details=details)
