"""Closed-form IK of the IRb-6 family (Szkodny (5.6)): base turn θ1, three parallel
horizontal axes θ2, θ3, θ4, approach roll θ5. User (redefined) angles; ``S23 = sin(θ2+θ3)``.

The wrist point ``p`` (origin of the last link, where axes 4 and 5 meet) and the approach
vector ``c`` (the last link's z) of the book's forward kinematics are

    p = ( S1·ρ, −C1·ρ, λ1 + l2·C2 + l3·S23 ),   ρ = l2·S2 − l3·C23
    c = ( −S1·C234, C1·C234, S234 )

so, backwards:

* θ1 = atan2(−p_x, p_y) on the ``front`` branch (ρ < 0, the arm's own side: every pose
  inside the IRb-6's limits), atan2(p_x, −p_y) on the ``back`` one (ρ > 0);
* in the arm's plane, with r = S1·p_x − C1·p_y (= ρ) and h = p_z − λ1, the two links
  l2, l3 measured from the vertical: sin θ3 = (r² + h² − l2² − l3²) / (2·l2·l3),
  θ3 = asin(·) (``elbow-up``) or π − asin(·) (``elbow-down``),
  θ2 = atan2(r, h) + atan2(l3·cos θ3, l2 + l3·sin θ3);
* θ234 = atan2(c_z, −S1·c_x + C1·c_y), θ4 = θ234 − θ2 − θ3;
* θ5 = the rotation about axis 5 from the pose with θ5 = 0 to the target.

With five joints the approach vector must lie in the arm's vertical plane
(c_x·d_y − c_y·d_x = 0, :mod:`irlc.runtime.model.reachability`); off it the branches here do
not reproduce the pose and are dropped by the FK check of :func:`..branches`. The lengths
λ1, l2, l3 are read from the model's joint origins (no number of the IRb-6 is written here).
"""

from __future__ import annotations

import math

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime.ik.closed_form import Branch, rotation_about, turns
from irlc.runtime.model import spatial
from irlc.runtime.model.kinematics import Kinematics


def _lengths(model: RobotModel, kin: Kinematics) -> tuple[float, float, float]:
    """λ1 (height of axis 2 on axis 1), l2 (axis 2 → 3), l3 (axis 3 → wrist point)."""
    frames = kin.link_frames(np.zeros(model.n))
    inv_base = spatial.inverse(model.base)
    _, origins = kin.joint_axes_world(frames)
    o = (inv_base[:3, :3] @ origins.T).T + inv_base[:3, 3]
    return (
        float(o[1, 2] - o[0, 2]),
        float(np.linalg.norm(o[2] - o[1])),
        float(np.linalg.norm(o[4] - o[2])),
    )


def solve(model: RobotModel, flange: np.ndarray, kin: Kinematics) -> list[Branch]:
    """Every branch reaching the last link's frame ``flange`` (base frame of the chain)."""
    lam1, l2, l3 = _lengths(model, kin)
    p, c = flange[:3, 3], flange[:3, 2]
    box = model.position_limits
    out: list[Branch] = []
    for side, sign in (("front", 1.0), ("back", -1.0)):
        t1 = math.atan2(-sign * p[0], sign * p[1])
        s1, c1 = math.sin(t1), math.cos(t1)
        r, h = s1 * p[0] - c1 * p[1], p[2] - lam1
        d = (r * r + h * h - l2 * l2 - l3 * l3) / (2.0 * l2 * l3)
        if abs(d) > 1.0 + 1e-12:
            continue  # the wrist point is out of the arm's reach
        base3 = math.asin(max(-1.0, min(1.0, d)))
        t234 = math.atan2(c[2], -s1 * c[0] + c1 * c[1])
        for elbow, t3 in (("up", base3), ("down", math.pi - base3)):
            t2 = math.atan2(r, h) + math.atan2(l3 * math.cos(t3), l2 + l3 * math.sin(t3))
            q = np.array([t1, t2, t3, t234 - t2 - t3, 0.0])
            for k in range(4):
                q[k] = turns(q[k], *box[k])[0]
            q[4] = _roll(model, kin, q, flange)
            for t5 in turns(q[4], *box[4]):
                q5 = q.copy()
                q5[4] = t5
                out.append(Branch(f"{side}-elbow-{elbow}", q5))
    return out


def _roll(model: RobotModel, kin: Kinematics, q: np.ndarray, flange: np.ndarray) -> float:
    """θ5: the rotation about axis 5 from the last link's frame at θ5 = 0 to ``flange``."""
    at_zero = spatial.inverse(model.base) @ kin.link_frames(q)[-1]
    m = at_zero[:3, :3].T @ flange[:3, :3]
    return rotation_about(model.joints[-1].axis, m)
