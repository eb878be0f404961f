"""Test robots built directly from the model dataclasses."""

from __future__ import annotations

import itertools
import math

import numpy as np
from irlc.robots.model import Capsule, Joint, Limits, RobotModel
from irlc.runtime.model import spatial


def planar_arm(n: int, link: float = 1.0, *, speed=math.pi, accel=20.0, radius=0.0):
    """Planar nR arm, z axes, links of ``link`` m along x; the flange is the last link's end.
    Joint i (i ≥ 2) sits at the end of link i−1: origin Trans(link, 0, 0)."""
    joints = []
    for i in range(n):
        origin = spatial.transform(None, (link if i else 0.0, 0.0, 0.0))
        joints.append(
            Joint(
                name=f"J{i + 1}",
                kind="revolute",
                origin=origin,
                axis=np.array([0.0, 0.0, 1.0]),
                limits=Limits((-math.pi, math.pi), (-speed, speed), (-accel, accel)),
                weight=float(n - i),
            )
        )
    geometry = ()
    if radius > 0.0:
        geometry = tuple(
            Capsule(i + 1, np.zeros(3), np.array([link, 0.0, 0.0]), radius) for i in range(n)
        )
    return RobotModel(
        name=f"planar{n}",
        joints=tuple(joints),
        flange=spatial.transform(None, (link, 0.0, 0.0)),
        geometry=geometry,
    )


XY = (0, 1)  # planar position task


def run_path(ik, q0, poses, dt, options=None):
    """Drive the solver along a list of target poses; returns configurations and results."""
    q_prev, q = q0.copy(), q0.copy()
    qs, results = [q0.copy()], []
    for target in poses:
        r = ik.step(q, q_prev, target, dt, options)
        q_prev, q = q, r.q
        qs.append(q.copy())
        results.append(r)
    return np.array(qs), results


def smooth(s):
    return s * s * (3.0 - 2.0 * s)


def line_poses(start, end, steps):
    out = []
    for i in range(1, steps + 1):
        t = start.copy()
        t[:3, 3] = start[:3, 3] + smooth(i / steps) * (end[:3, 3] - start[:3, 3])
        out.append(t)
    return out


def square_poses(center, side, steps_per_side):
    corners = [center + side / 2 * np.array(c) for c in ((1, 1), (-1, 1), (-1, -1), (1, -1))]
    corners.append(corners[0])
    poses = []
    for a, b in itertools.pairwise(corners):
        for i in range(1, steps_per_side + 1):
            p = a + smooth(i / steps_per_side) * (b - a)
            poses.append(spatial.transform(None, (p[0], p[1], 0.0)))
    return poses
