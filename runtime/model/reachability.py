"""Reachability diagnostics for arms with fewer than six joints (the 5-axis IRb-6).

The IRb-6's axes 2, 3, 4 are parallel and horizontal, axis 5 is the approach axis:
flange origin ``d`` and approach vector ``c`` (flange z) always lie in the vertical plane
through axis 1. In the base frame that is the book's key equation of the IRb-6,

    c_x·d_y − c_y·d_x = 0,

in general ``r = c · (a × (d − o))`` with ``a``, ``o`` the direction and a point of the
plane joint's axis (world). ``r / |a × (d − o)|`` is the sine of the angle by which ``c``
leaves the plane. On a track (prismatic joints before the plane joint, moving ``o``
along ``u``), ``r`` is affine in the track position ``λ``: ``r(λ) = r(0) − λ·c·(a × u)``,
so the track position that makes the pose reachable is solved for in closed form.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime.model import spatial
from irlc.runtime.model.kinematics import Kinematics


@dataclass(frozen=True)
class PlaneCheck:
    residual: float  # c·(a × (d − o)), metres (= −(c_x d_y − c_y d_x) in the IRb-6 base frame)
    angle: float  # rad, how far the approach vector leaves the arm's vertical plane
    reachable: bool
    track: float | None = None  # required track position (m) when the robot has one
    message: str = ""


def _plane(model: RobotModel, target: np.ndarray, q_before: np.ndarray, kin: Kinematics):
    j = model.extra["reachability"]["plane_joint"]
    q = np.zeros(model.n)
    q[:j] = q_before
    frames = kin.link_frames(q)
    z, o = kin.joint_axes_world(frames)
    flange = target @ spatial.inverse(kin.tool)
    return z[j], o[j], flange[:3, 2], flange[:3, 3]


def check_vertical_plane(
    model: RobotModel, target: np.ndarray, tool: np.ndarray | None = None, tol: float = 1e-6
) -> PlaneCheck:
    """Is the world TCP pose ``target`` in the arm's plane? With a track in front of the
    plane joint, also the track position that puts it there (and whether it is in range)."""
    if model.extra.get("reachability", {}).get("type") != "vertical_plane":
        return PlaneCheck(0.0, 0.0, True, message="no plane condition for this robot")
    kin = Kinematics(model, tool=tool)
    j = model.extra["reachability"]["plane_joint"]
    a, o, c, d = _plane(model, target, np.zeros(j), kin)
    r0 = float(c @ np.cross(a, d - o))
    if j == 0:
        return _result(r0, a, o, c, d, tol, None, model)
    if j != 1 or model.joints[0].kind != "prismatic":
        raise ValueError("plane check with joints before the plane joint: only one track supported")
    _, o1, _, _ = _plane(model, target, np.ones(1), kin)
    u = o1 - o  # track direction per metre
    slope = float(c @ np.cross(a, u))
    if abs(slope) < 1e-12:  # the track cannot move the plane onto c
        return _result(r0, a, o, c, d, tol, None, model)
    lam = r0 / slope
    lo, hi = model.joints[0].limits.position
    check = _result(0.0, a, o + lam * u, c, d, tol, lam, model)
    if not lo <= lam <= hi:
        return PlaneCheck(
            r0,
            check.angle,
            False,
            lam,
            f"the track would have to be at {lam * 1000:.1f} mm, outside "
            f"{lo * 1000:g} … {hi * 1000:g} mm",
        )
    return check


def _result(r, a, o, c, d, tol, track, model) -> PlaneCheck:
    normal = np.cross(a, d - o)
    norm = float(np.linalg.norm(normal))
    angle = math.asin(min(1.0, abs(r) / norm)) if norm > 1e-12 else 0.0
    ok = abs(r) <= tol
    msg = (
        ""
        if ok
        else (
            f"{model.name} has {model.n} joints: the approach vector leaves the arm's vertical "
            f"plane by {math.degrees(angle):.3f} deg (c_x·d_y − c_y·d_x = {-r * 1000:.3f} mm)"
        )
    )
    return PlaneCheck(r, angle, ok, track, msg)
