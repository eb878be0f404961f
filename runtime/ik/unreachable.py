"""When a pose is *provably* out of reach — the one place that may say "not reachable".

A search that stalls has only failed from its start(s); it says ``no solution found from
this start`` (:data:`NOT_FOUND`) unless one of these proves that no configuration within
the limits reaches the pose (:func:`proof`; then :data:`NOT_REACHABLE`):

* **plane** (5-joint arms, ``[reachability] vertical_plane``): the approach vector leaves
  the arm's vertical plane (:func:`irlc.runtime.model.reachability.check_vertical_plane`);
* **closed form** (robots with ``[ik] closed_form``, :mod:`.closed_form`): the family
  enumerates every configuration reaching the pose; none exists, or every one lies
  outside the position or coupled limits (the first such limit is named);
* **reach**: the controlled position components of the target lie farther from the
  robot's base than its links laid end to end (the message's number: not the reach of
  the arm, which is shorter where joint offsets cannot line up, but a bound of it).
  Between consecutive link origins ``o_i`` (``o_0`` the base, ``o_{n+1}`` the TCP) the
  distance depends on joint ``i+1`` only: fixed for a revolute joint, convex in the value
  of a prismatic one, so
  ``Σ_i max |o_{i+1} − o_i|`` over the prismatic ranges' ends bounds ``|TCP − o_0|``
  (an infinite prismatic range: no bound).
"""

from __future__ import annotations

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime import units
from irlc.runtime.ik import closed_form
from irlc.runtime.ik.seed import seed_problem
from irlc.runtime.model.kinematics import Kinematics

NOT_REACHABLE = "target not reachable"
NOT_FOUND = "no solution found from this start"


def proof(
    model: RobotModel,
    target: np.ndarray,
    tool: np.ndarray | None = None,
    position: np.ndarray | None = None,
    task_rows: tuple[int, ...] = (0, 1, 2, 3, 4, 5),
) -> str | None:
    """Why no configuration within ``position`` (``(n, 2)`` SI, default the robot's box)
    and the coupled limits reaches the world TCP pose ``target``; ``None`` when that is
    not proven."""
    box = model.position_limits if position is None else np.asarray(position, dtype=float)
    if tuple(sorted(task_rows)) != (0, 1, 2, 3, 4, 5):
        return _beyond_reach(model, target, tool, box, task_rows)
    from irlc.runtime.model.reachability import check_vertical_plane

    check = check_vertical_plane(model, target, tool)
    if not check.reachable:
        return check.message
    return _beyond_reach(model, target, tool, box, task_rows) or _closed_form(
        model, target, tool, box
    )


def _closed_form(model, target, tool, box) -> str | None:
    found = closed_form.branches(model, target, tool, box)
    if found is None or any(b.within_limits for b in found):
        return None
    if not found:
        return "no configuration reaches it (closed form)"
    limited = _with_box(model, box)
    why = "; ".join(
        f"{b.label}: {(seed_problem(limited, b.q) or '').removeprefix('seed ')}" for b in found
    )
    return f"every configuration reaching it lies outside the limits (closed form: {why})"


def _with_box(model: RobotModel, box: np.ndarray) -> RobotModel:
    import dataclasses

    joints = tuple(
        dataclasses.replace(j, limits=dataclasses.replace(j.limits, position=tuple(box[i])))
        for i, j in enumerate(model.joints)
    )
    return dataclasses.replace(model, joints=joints)


def reach_bound(model: RobotModel, tool: np.ndarray | None, box: np.ndarray) -> float:
    """An upper bound (m) of ``|TCP − base|`` over the configurations within ``box``."""
    prismatic = np.array([k == "prismatic" for k in model.joint_kinds])
    if np.any(~np.isfinite(box[prismatic])):
        return np.inf
    kin = Kinematics(model, tool)
    steps = []
    for q in (np.where(prismatic, box[:, 0], 0.0), np.where(prismatic, box[:, 1], 0.0)):
        frames = kin.link_frames(q)
        _, origins = kin.joint_axes_world(frames)
        points = np.vstack([frames[0][:3, 3], origins, kin.tcp_from_frames(frames)[:3, 3]])
        steps.append(np.linalg.norm(np.diff(points, axis=0), axis=1))
    return float(np.sum(np.maximum(*steps)))


def _beyond_reach(model, target, tool, box, task_rows) -> str | None:
    rows = [r for r in task_rows if r < 3]
    if not rows:
        return None
    gap = float(np.linalg.norm(np.asarray(target)[rows, 3] - model.base[rows, 3]))
    bound = reach_bound(model, tool, box)
    if gap <= bound * (1.0 + 1e-9):
        return None
    return (
        f"it lies {gap / units.MM:.6g} mm from the robot's base, beyond the "
        f"{bound / units.MM:.6g} mm of its links laid end to end, which no configuration "
        "exceeds"
    )
