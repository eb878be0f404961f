"""Inverse transformation: Newton–Raphson with the compact QP (seed chapter 4.2).

Public API::

    solve_pose(model, target, seed, ...) -> PoseSolution        # one pose (CLI, PTP)
    InverseTransformation(model, kinematics, IKParams).step(     # one IPO cycle
        q_start, q_prev, target, dt, CycleOptions) -> CycleResult
    intersect_limits(model, position, speed, accel)
    reconfiguration_done(q, q_prev, eps_conf, q_prev2)         # the two-cycle stop rule
"""

from irlc.runtime.ik.coupled import CoupledLimitError
from irlc.runtime.ik.freeze import FreezeError
from irlc.runtime.ik.limits import LimitViolation, LimitViolationError, intersect_limits
from irlc.runtime.ik.newton import IKFailure, InverseTransformation
from irlc.runtime.ik.params import CycleOptions, IKParams, ObstacleParams
from irlc.runtime.ik.pose import PoseSolution, solve_pose
from irlc.runtime.ik.result import CycleResult
from irlc.runtime.ik.self_motion import reconfiguration_done
from irlc.runtime.model.chain import task_rows_for

__all__ = [
    "CoupledLimitError",
    "CycleOptions",
    "CycleResult",
    "FreezeError",
    "IKFailure",
    "IKParams",
    "InverseTransformation",
    "LimitViolation",
    "LimitViolationError",
    "ObstacleParams",
    "PoseSolution",
    "intersect_limits",
    "reconfiguration_done",
    "solve_pose",
    "task_rows_for",
]
