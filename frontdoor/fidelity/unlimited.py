"""A robot whose position limits are not enforced — how the books ran their drive studies.

Szkodny's simulations of the L-1 and the IRb-6 drives compute the joint (motor) command of
a test motion and feed it to the drive models; nothing checks the joint ranges. irlc
enforces them everywhere (the IK's box, the verdict of the actual motion), so a book
motion that starts on a bound — the L-1's line P→K from the branch with W6 = 0° — fails
within a cycle. :func:`without_position_limits` gives the same robot with every joint's
position range opened to ±:data:`OPEN_RANGE` and the coupled position limits dropped; its
name says so (``"l1 (position limits not enforced)"``), so every report, summary and
trace header of a run on it states it. Speed, acceleration and motor limits stay.

    from irlc.fidelity import without_position_limits
    run = run_file("line.irl", robot=without_position_limits(load_robot("l1")))
"""

from __future__ import annotations

import dataclasses

from irlc.robots.model import RobotModel

OPEN_RANGE = 1e3
"""rad | m: the opened position range (finite, so every range check still computes)."""

NOTE = "position limits not enforced"


def without_position_limits(model: RobotModel) -> RobotModel:
    """``model`` with the position limits opened (see the module doc)."""
    joints = tuple(
        dataclasses.replace(
            j, limits=dataclasses.replace(j.limits, position=(-OPEN_RANGE, OPEN_RANGE))
        )
        for j in model.joints
    )
    extra = {k: v for k, v in model.extra.items() if k != "coupled_limits"}
    extra["position_limits_enforced"] = False
    limit_sets = {
        name: tuple(dataclasses.replace(lim, position=(-OPEN_RANGE, OPEN_RANGE)) for lim in sets)
        for name, sets in model.limit_sets.items()
    }
    return dataclasses.replace(
        model, name=f"{model.name} ({NOTE})", joints=joints, extra=extra, limit_sets=limit_sets
    )


def enforces_position_limits(model: RobotModel) -> bool:
    return model.extra.get("position_limits_enforced", True)
