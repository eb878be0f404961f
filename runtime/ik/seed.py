"""Can a joint configuration seed the pose solver? The one check: position limits (joint,
value, limit) and the robot file's coupled limits."""

from __future__ import annotations

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime.ik.limits import format_joint_value
from irlc.runtime.model.coupled_limits import coupled_limits, describe, violations
from irlc.runtime.model.naming import JointNaming, naming_or_default


def seed_problem(model: RobotModel, q: np.ndarray, naming: JointNaming | None = None) -> str | None:
    """Why ``q`` (SI) cannot seed the solver — outside a position limit (joint, value,
    limit) or violating a coupled limit — or ``None``."""
    limits = model.position_limits
    outside = np.flatnonzero((q < limits[:, 0]) | (q > limits[:, 1]))
    if outside.size:
        j = int(outside[0])
        side = 0 if q[j] < limits[j, 0] else 1
        name = naming_or_default(naming, model).label(j)
        return (
            f"seed joint {name} = {format_joint_value(model, j, q[j], 0)} is "
            f"outside its position {('min', 'max')[side]} "
            f"{format_joint_value(model, j, limits[j, side], 0)}"
        )
    found = violations(coupled_limits(model), q, 1e-9)
    if found:
        return f"seed: {describe(max(found, key=lambda v: v.amount))}"
    return None
