"""FREEZE together with JOINTLIMIT: when neither alone stops a pose, name the combination.

A pose the search cannot reach with the frozen joints held, inside the active position
limits (robot ∩ JOINTLIMIT), but can reach with them free is blamed on FREEZE. That is
wrong when the JOINTLIMIT is needed too: if the pose is also reachable with the frozen
joints *held* within the robot's own position limits, each option alone leaves it
reachable and only the two together do not — the cause is ``freeze_jointlimit``, and the
message names the frozen joints and the joints the JOINTLIMIT narrows (those at their
narrowed bound in the closest pose found first).
"""

from __future__ import annotations

import dataclasses

import numpy as np
from irlc.runtime.errors import RunFailure
from irlc.runtime.ik.limits import format_joint_value
from irlc.runtime.model.naming import JointNaming

# ``reach`` below is a :class:`irlc.runtime.ik.reach.Reach`; reach.py asks this module, so
# it is not imported here (not even for the annotations: no import cycle)

CAUSE = "freeze_jointlimit"
AT_BOUND = 1e-6  # SI: a joint this close to its narrowed bound presses on it


def narrowed_joints(reach, target: np.ndarray, seed: np.ndarray, q_closest) -> list[int]:
    """The joints the active JOINTLIMIT narrows when the pose ``target`` is reachable with
    the frozen joints held within the robot's own position limits (so the JOINTLIMIT is
    part of the cause): those at a narrowed bound in ``q_closest`` first. ``[]`` when the
    JOINTLIMIT narrows nothing or the pose is out of reach without it too."""
    own = reach.model.position_limits
    narrowed = [j for j in range(reach.model.n) if not np.array_equal(reach.position[j], own[j])]
    narrowed = [j for j in narrowed if j not in reach.frozen]
    if not narrowed:
        return []
    wide = dataclasses.replace(reach, position=own)
    if not wide.reached(wide.search(target, seed)):
        return []
    q = np.asarray(q_closest, dtype=float)
    pressed = [
        j
        for j in narrowed
        if min(abs(q[j] - reach.position[j, 0]), abs(q[j] - reach.position[j, 1])) <= AT_BOUND
    ]
    return pressed + [j for j in narrowed if j not in pressed]


def describe_narrowed(reach, joints: list[int]) -> str:
    """``a3 (A1) -10…10 deg, …``: the JOINTLIMIT's range of each joint."""
    model = reach.model
    parts = []
    for j in joints:
        lo = format_joint_value(model, j, reach.position[j, 0], 0)
        hi = format_joint_value(model, j, reach.position[j, 1], 0)
        parts.append(f"{reach.naming.label(j)} {lo.rsplit(' ', 1)[0]}…{hi}")
    return ", ".join(parts)


def failure(
    reach, narrowed: list[int], head: str, tail: str, line, time_s, details: dict
) -> RunFailure:
    """The failure naming FREEZE and JOINTLIMIT together: ``head`` says what cannot be done
    (``"MOVE LIN: the target is out of reach"``), ``tail`` what is known beyond it."""
    naming: JointNaming = reach.naming
    frozen = sorted(reach.frozen)
    names = naming.labels(frozen)
    details = {
        **details,
        "joints": [naming.name(j) for j in frozen],
        "limited_joints": [naming.name(j) for j in narrowed],
    }
    return RunFailure(
        f"{head} with FREEZE of joints {names} together with the active JOINTLIMIT "
        f"({describe_narrowed(reach, narrowed)}){tail}",
        line,
        time_s,
        f"FREEZE {names} with JOINTLIMIT {naming.labels(narrowed)}",
        cause=CAUSE,
        details=details,
    )


EACH_ALONE = (
    "; each alone leaves it reachable (with the frozen joints free, or within the robot's "
    "own position limits)"
)
