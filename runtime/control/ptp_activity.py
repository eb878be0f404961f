"""Which joints of a PTP segment are at a speed or acceleration bound in a cycle: the
report's limit activity of joint motion (``limit_active_s``, ``limit_activity``), the
counterpart of the inverse transformation's active box for Cartesian motion.

The joint profile (:meth:`~irlc.runtime.plan.preinterp.PreInterpolator.joint_profile`) keeps
each joint's peak speed and acceleration in ``seg.peaks``
(:class:`~irlc.runtime.plan.interpolator.JointPeaks`); a joint is at its bound when that
peak equals its active limit within a relative 1e-9.
"""

from __future__ import annotations

from irlc.runtime.plan.interpolator import Segment


def at_bounds(seg: Segment, k: int, dt: float) -> dict[int, str] | None:
    """The joints of a PTP segment that are at a bound in cycle ``k``: while ramping,
    those whose acceleration equals their active acceleration limit (none at
    ``R_ACC_PTP`` < 100 %); while cruising, those whose speed equals their speed
    limit (none at ``R_SPEED_PTP`` < 100 % or on a stretched profile). The side is
    that of the joint's acceleration (``max`` when it speeds up in the positive
    direction or brakes a negative motion) or speed."""
    phase = int(seg.profile.phase((k - 0.5) * dt))
    at_accel, at_speed = _bounds(seg)
    if phase != 0:
        out = {j: "accel max" if (phase > 0) == up else "accel min" for j, up in at_accel}
    elif float(seg.profile.speed((k - 0.5) * dt)) < seg.profile.cruise:
        return None  # an S-curve's jerk phases: neither bound is reached
    else:
        out = {j: "speed max" if up else "speed min" for j, up in at_speed}
    return out or None


def _bounds(seg: Segment) -> tuple[list, list]:
    """``(joints at their acceleration bound, joints at their speed bound)`` of a PTP
    segment, each as ``(joint, moves up)``, within a relative 1e-9 (cached per segment)."""
    peaks = seg.peaks
    if peaks is None:
        return [], []
    if peaks.at_bounds is None:
        path, (_, spd, acc) = seg.path, seg.limits
        accel, speed = peaks.accel, peaks.speed
        at_accel, at_speed = [], []
        for j in range(len(path.q0)):
            up = bool(path.q1[j] >= path.q0[j])
            if path.q1[j] == path.q0[j]:
                continue
            if accel[j] >= min(acc[j, 1], -acc[j, 0]) * (1.0 - 1e-9):
                at_accel.append((j, up))
            if speed[j] >= (spd[j, 1] if up else -spd[j, 0]) * (1.0 - 1e-9):
                at_speed.append((j, up))
        peaks.at_bounds = (at_accel, at_speed)
    return peaks.at_bounds
