"""One TCP pose for ``irlc ik``: the seed first, then the other starts, or a chosen branch.

:func:`find_pose` solves from ``seed`` (:func:`pose.solve_pose` within the robot's
limits); if that stalls it tries the starts of the PTP pose search
(:meth:`reach.Reach.starts`: the closed-form configurations within the limits, nearest
to the seed first, then the seed moved, home, mid-range, a Halton spread, here of
:data:`SPREAD` points), unless the first failure already proves the pose out of reach.
It returns the first solution, or the closest pose with a message that says "target not
reachable" only when :mod:`unreachable` proves it, else "no solution found from this
start nor from N other starts".

``branch`` (robots with ``[ik] closed_form``): the configuration of that closed-form
branch (labels: :func:`closed_form.branch_labels`), polished by the same solver; a
branch whose configuration lies outside the limits is reported as not reachable on that
branch, naming the limit.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
from irlc.lang.errors import IrlcError
from irlc.robots.model import RobotModel
from irlc.runtime.ik import closed_form, unreachable
from irlc.runtime.ik.pose import PoseSolution, solve_pose
from irlc.runtime.ik.reach import restarts, tried_starts
from irlc.runtime.ik.seed import seed_problem
from irlc.runtime.model import spatial

SPREAD = 64  # Halton starts: as6 (no closed form), 100 random reachable poses from home:
# 6 not found with 8, 1 with 32, none with 64 (each tried only while none converged)


class BranchError(IrlcError, ValueError):
    """``branch`` names no branch of the robot's closed form (or it has none)."""


@dataclass(frozen=True)
class Found:
    solution: PoseSolution
    start: str  # "seed" | "closed form <label>" | "restart <k>" | "branch <label>"
    tried: int  # starts tried
    branches: tuple[closed_form.Branch, ...]  # the closed-form branches (empty: none)

    @property
    def branch(self) -> str | None:
        """The label of the closed-form branch the solution lies on (``None``: unknown)."""
        q = self.solution.q
        for b in self.branches:
            if np.allclose(b.q, q, atol=1e-6):
                return b.label
        return None


def find_pose(
    model: RobotModel,
    target: np.ndarray,
    seed: np.ndarray,
    *,
    branch: str | None = None,
    tool: np.ndarray | None = None,
) -> Found:
    """Solve ``target`` (world TCP pose, SI) from ``seed``, retrying from other starts, or
    on the closed-form ``branch`` (:class:`BranchError` when it does not exist)."""
    tool = model.tool if tool is None else tool
    found = tuple(closed_form.branches(model, target, tool) or ())
    if branch is not None:
        return _on_branch(model, target, seed, branch, tool, found)
    sol = solve_pose(model, target, seed, tool=tool)
    proven = sol.message.startswith(unreachable.NOT_REACHABLE)  # no start can help
    if sol.converged or proven or not np.all(np.isfinite(sol.q)):
        return Found(sol, "seed", 1, found)
    exact = closed_form.starts(model, target, seed, None, tool)
    starts = [q for _, q in exact] + restarts(model, seed, model.position_limits, SPREAD)
    best = sol
    for k, start in enumerate(starts):
        trial = solve_pose(model, target, start, tool=tool)
        if trial.converged:
            n_exact = len(exact)
            label = f"closed form {exact[k][0]}" if k < n_exact else f"restart {k - n_exact + 1}"
            return Found(trial, label, k + 2, found)
        if _residual(trial) < _residual(best):
            best = trial
    message = tried_starts(best.message, len(starts))
    return Found(dataclasses.replace(best, message=message), "seed", len(starts) + 1, found)


def _on_branch(model, target, seed, branch, tool, found) -> Found:
    labels = closed_form.branch_labels(model)
    if not labels:
        raise BranchError(
            f"robot {model.name} has no closed-form inverse kinematics ([ik] closed_form in "
            "its file), so it has no branches to choose"
        )
    if branch not in labels:
        raise BranchError(
            f"robot {model.name} has no branch {branch!r}; its branches: {', '.join(labels)}"
        )
    match = [b for b in found if b.label == branch]
    if match and match[0].within_limits:
        sol = solve_pose(model, target, match[0].q, tool=tool)
        return Found(sol, f"branch {branch}", 1, found)
    q = match[0].q if match else np.asarray(seed, dtype=float)
    error = spatial.pose_error(_tcp(model, tool, q), target)
    if match:  # the branch's configuration (shown) and the first limit it breaks
        limit = (seed_problem(model, q) or "").removeprefix("seed: ").removeprefix("seed ")
        why = f"its configuration lies outside the limits: {limit}"
    else:
        why = "no configuration of it reaches the pose"
    return Found(
        PoseSolution(
            q,
            False,
            float(np.linalg.norm(error[:3])),
            float(np.linalg.norm(error[3:])),
            0,
            f"{unreachable.NOT_REACHABLE} on branch {branch}: {why}",
        ),
        f"branch {branch}",
        0,
        found,
    )


def _residual(sol: PoseSolution) -> float:
    return sol.position_error + sol.orientation_error


def _tcp(model: RobotModel, tool: np.ndarray, q: np.ndarray) -> np.ndarray:
    from irlc.runtime.model.kinematics import Kinematics

    return Kinematics(model, tool).tcp(q)
