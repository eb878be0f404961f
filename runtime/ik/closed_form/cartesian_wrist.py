"""Closed-form IK of the L-1 family (Szkodny (4.4)): three prismatic axes, then a wrist of
three revolute axes meeting in one point ``w`` (the wrist centre).

The book's end pose is X = Trans(λ2, λ3+λ4−l1, λ1)·Rot(x,−90°)·Rot(z,θ4)·Rot(y,−θ5)·
Rot(z,θ6)·Trans(0,0,λ6+λ7): the slides place the wrist centre, the wrist angles are Z-Y-Z
Euler angles of the orientation. Backwards, read from the model's frames:

* ``w`` is fixed in the TCP frame (it lies on axis 6): ``w = X·v`` with ``v`` taken from
  the model at its home; ``w`` is affine in the slides, ``w = w_h + U·(λ − λ_h)`` with
  ``U`` the slides' directions, a 3×3 linear system;
* the wrist: with ``A`` the frame of axis 4 (fixed while only slides move), ``O5``, ``O6``
  the fixed rotations between the wrist axes (``O5·O6 = I``, ``O5·z ⊥ z``: the L-1's
  Rot(x, ±90°)), ``N = Aᵀ·R6 = Rz(θ4')·Rot(e, θ5')·Rz(θ6')`` with ``e = O5·z``; turning
  ``e`` onto y by γ makes it the Z-Y-Z form ``Rz(θ4'+γ)·Ry(θ5')·Rz(θ6'−γ)``:
  ``θ5' = atan2(±√(N02² + N12²), N22)``, ``θ4'+γ = atan2(±N12, ±N02)``,
  ``θ6'−γ = atan2(±N21, ∓N20)`` — the ``noflip`` (θ5' ≥ 0) and ``flip`` branches
  (θ' = θ + offset). At θ5' = 0 only θ4'+θ6' is determined; θ6' = γ is taken.
"""

from __future__ import annotations

import math

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime.ik.closed_form import Branch, turns
from irlc.runtime.model import spatial
from irlc.runtime.model.kinematics import Kinematics

SINGULAR = 1e-12  # |sin θ5'| below this: the wrist is stretched (θ4' + θ6' only)


def solve(model: RobotModel, flange: np.ndarray, kin: Kinematics) -> list[Branch]:
    """Every branch reaching the last link's frame ``flange`` (base frame of the chain)."""
    inv_base = spatial.inverse(model.base)
    home = model.home_q()
    frames = np.array([inv_base @ f for f in kin.link_frames(home)])
    joint_frames = _joint_frames(model, frames)
    axes = np.array([f[:3, :3] @ j.axis for f, j in zip(joint_frames, model.joints, strict=True)])
    centre = joint_frames[4][:3, 3]  # axis 5 meets axes 4 and 6 here
    v = spatial.inverse(frames[-1]) @ np.append(centre, 1.0)  # in the last link's frame
    w = (flange @ v)[:3]
    slides = np.linalg.solve(axes[:3].T, w - centre) + home[:3]
    a = joint_frames[3][:3, :3]  # frame of axis 4 (rotation fixed by slides)
    o5, o6 = model.joints[4].origin[:3, :3], model.joints[5].origin[:3, :3]
    e = o5 @ np.array([0.0, 0.0, 1.0])
    if not np.allclose(o5 @ o6, np.eye(3), atol=1e-12) or abs(e[2]) > 1e-12:
        return []  # not a wrist of this family
    gamma = math.atan2(e[1], e[0]) - 0.5 * math.pi
    n = a.T @ flange[:3, :3]
    box = model.position_limits
    out: list[Branch] = []
    for label, sign in (("noflip", 1.0), ("flip", -1.0)):
        w4, w5, w6 = _zyz(n, sign)
        angles = (w4 - gamma, w5, w6 + gamma)
        q = np.concatenate([slides, [0.0, 0.0, 0.0]])
        for k in range(3):
            q[3 + k] = angles[k] - model.joints[3 + k].offset
        for t4 in turns(q[3], *box[3]):
            for t6 in turns(q[5], *box[5]):
                out.append(Branch(label, np.array([*q[:3], t4, turns(q[4], *box[4])[0], t6])))
    return out


def _joint_frames(model: RobotModel, frames: np.ndarray) -> list[np.ndarray]:
    """Frame of each joint before its own motion: link ``i−1``'s frame · ``origin_i``."""
    return [frames[i] @ j.origin for i, j in enumerate(model.joints)]


def _zyz(n: np.ndarray, sign: float) -> tuple[float, float, float]:
    """Z-Y-Z angles (α, β, γ) with ``n = Rz(α)·Ry(β)·Rz(γ)``, ``sign·sin β ≥ 0``."""
    s = sign * math.hypot(n[0, 2], n[1, 2])
    beta = math.atan2(s, n[2, 2])
    if abs(s) < SINGULAR:  # Rz(α ± γ): keep γ = 0
        flip = 1.0 if n[2, 2] > 0 else -1.0
        return math.atan2(flip * n[1, 0], flip * n[0, 0]), beta, 0.0
    return math.atan2(n[1, 2] / s, n[0, 2] / s), beta, math.atan2(n[2, 1] / s, -n[2, 0] / s)
