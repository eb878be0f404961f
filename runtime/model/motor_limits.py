"""Motor-side speed/acceleration limits seen through a coupled transmission. SI units.

Where the transmission couples joints (the L-1 wrist: ``θs5 = k5 (θ5 − 0.5 θ4)``,
``θs6 = k6 (θ6 − 2 θ5)``; the IRb-6's tilt motor on ``θ2+θ3+θ4``) the joint speed limits
of the robot file cannot express the motors' limits: a motor runs at ``θ̇s = K(q) q̇``
with ``K = ∂θs/∂q`` (:meth:`MotorMap.motor_jacobian`), so several joints moving together
can overrun one motor although each joint keeps its own bound. The drive data give the
limits (``[drives.stepper] step_rate`` — the commanded step rate; ``[drives.slave]
v_max, a_max`` — the slave controller's trapezoid), per driven motor.

**PTP** (a straight line in joint space, ``q(s) = q0 + s Δq``): motor ``m`` turns at
``θ̇s_m = (K(q(s)) Δq)_m · ṡ``. It is one more axis of the common profile
(:func:`profiles.common_bounds`) with the "distance" ``D_m = max_s |(K(q(s)) Δq)_m|``
(for a linear map the motor travel ``|ΔΘs_m|``; for a non-linear one the largest slope
over 17 points of the line), speed ``v_m`` and acceleration ``a_m``. For a linear map the
trapezoid then needs ``T ≥ |ΔΘs_m| / v_m + v_m / a_m`` for every motor — the book's rule
"plan no shorter than the slowest motor", ``T ≥ max_m |ΔΘs_m| / v_max``, is its
constant-speed part. (For a non-linear map the curvature term ``(dK/ds Δq) ṡ²`` of the
motor acceleration is not bounded: a documented approximation.)

**LIN / CIRCLE / PATH**: the pre-interpolator samples the joint path with the pose solver
and times the motors on its secant slopes (:meth:`MotorLimits.path_rates`); in the
IK of every cycle the rows ``|K δ|_m ≤ v_m Δt`` on the
cycle displacement ``δ`` join the coupled joint limits in the QP
(:class:`irlc.runtime.ik.coupled.CoupledRows`; ``K`` constant for a linear map, the L-1,
``K(θ_s)`` at the start of each cycle for a non-linear one, the IRb-6).

Robots without such a transmission, or without motor limits in their drive data, get
``None`` from :func:`motor_limits` (nothing changes for them).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime.model.motor_maps import MotorMap

_SAMPLES = 17  # points of a PTP line where a non-linear map's slope is evaluated
PATH_SAMPLES = 32  # intervals of a Cartesian path sampled for its motors' timing


@dataclass(frozen=True)
class MotorLimits:
    """Per-motor limits (rad/s, rad/s²; ``inf`` where none) and the robot's motor map."""

    map: MotorMap
    speed: np.ndarray
    accel: np.ndarray
    source: str  # where the limits come from, for messages and docs

    @property
    def linear(self) -> bool:
        """True when every motor is a (coupled) ratio: ``K`` does not depend on ``q``."""
        return all(e["type"] == "ratio" for e in self.map.entries)

    @property
    def limited(self) -> np.ndarray:
        """Indices of the motors with a finite speed limit."""
        return np.flatnonzero(np.isfinite(self.speed))

    def travel(self, q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
        """Motor travel ``θs(q1) − θs(q0)`` (rad) per motor."""
        return self.map.motor_from_joint(q1) - self.map.motor_from_joint(q0)

    def ptp_rates(self, q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
        """``D_m = max_s |(K(q(s)) Δq)_m|`` (rad per unit ``s``) of the line ``q0 → q1``."""
        delta = np.asarray(q1, dtype=float) - np.asarray(q0, dtype=float)
        if self.linear:
            return np.abs(self.map.motor_jacobian(q0) @ delta)
        rates = np.zeros(self.map.n)
        for s in np.linspace(0.0, 1.0, _SAMPLES):
            np.maximum(rates, np.abs(self.map.motor_jacobian(q0 + s * delta) @ delta), out=rates)
        return rates

    def path_rates(
        self,
        pose_at: Callable[[float], np.ndarray],
        q: np.ndarray,
        solve: Callable[[np.ndarray, np.ndarray], np.ndarray],
    ) -> tuple[np.ndarray, np.ndarray]:
        """``(D_m, q_end)`` of a Cartesian path ``pose_at(s)``, ``s ∈ [0, 1]``, from ``q``:
        the joints at ``PATH_SAMPLES + 1`` points (``solve(pose, seed)``, warm-started
        along the path), their motor angles, and per motor the largest secant slope
        ``|Δθs_m| / Δs`` plus the largest change between neighbouring secants (the slope
        between samples may exceed its secant by about that much; 0 on a straight joint
        path, e.g. the L-1's Cartesian axes). ``solve`` raises where it finds no joints."""
        qs = [np.asarray(q, dtype=float)]
        for s in np.linspace(0.0, 1.0, PATH_SAMPLES + 1)[1:]:
            qs.append(solve(pose_at(float(s)), qs[-1]))
        theta = np.array([self.map.motor_from_joint(x) for x in qs])
        slopes = np.diff(theta, axis=0) * PATH_SAMPLES  # secants dθs/ds per interval
        change = np.abs(np.diff(slopes, axis=0)).max(axis=0)
        return np.abs(slopes).max(axis=0) + change, qs[-1]

    def travel_times(self, q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
        """The book's per-motor travel time ``|ΔΘs_m| / v_m`` (s; 0 for an unlimited motor)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.abs(self.travel(q0, q1)) / self.speed
        return np.where(np.isfinite(t), t, 0.0)


def couples_joints(mm: MotorMap) -> bool:
    """True when some motor's angle depends on another joint than its own."""
    for i, e in enumerate(mm.entries):
        if e["type"] == "ratio" and any(c != 0.0 for _, c in e["couple"]):
            return True
        if e["type"] != "ratio" and any(j != i and c != 0.0 for j, c in e["angle"]):
            return True
    return False


def motor_limits(model: RobotModel) -> MotorLimits | None:
    """The robot's motor limits where its transmission couples joints, else ``None``.

    Raises the drive tables' ``DriveParamError`` (a robot-file error) when they are
    malformed: the limits cannot be known then."""
    if "transmission" not in model.extra or "drives" not in model.extra:
        return None
    mm = MotorMap.from_model(model)
    if not couples_joints(mm):
        return None
    from irlc.runtime.drives.params import drive_params

    params = drive_params(model)
    speed = np.full(model.n, math.inf)
    accel = np.full(model.n, math.inf)
    axes = list(params.axes)
    if params.type == "stepper":
        speed[axes] = params.chain.step_rate
        source = "[drives.stepper] step_rate"
    elif params.slave is not None:
        speed[axes] = params.slave.v_max
        accel[axes] = params.slave.a_max
        source = "[drives.slave] v_max, a_max"
    else:
        return None
    if not np.isfinite(speed).any() and not np.isfinite(accel).any():
        return None
    return MotorLimits(mm, speed, accel, source)
