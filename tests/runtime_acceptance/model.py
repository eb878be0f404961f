"""Independent kinematics and geometry for the acceptance checks (no irlc.runtime imports).

Reads the robot description TOML directly and rebuilds the chain as robots.md describes it
("axes" chain): frame_i = frame_{i-1} · Motion_i(q_i) · Trans(link_{i-1}), i.e. joint i sits
at the start of arm i and rotates (prismatic: slides) about an axis of its own frame; the
TCP is frame_n · Trans(link_n) · Tool; the world frame carries the robot's base rotation.

Poses are (x, y, z) mm and ZYX (a, b, c) deg: R = Rz(a)·Ry(b)·Rx(c).
"""

from __future__ import annotations

import itertools
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

ROBOTS = Path(__file__).resolve().parents[2] / "robots"
AXES = {"x": np.array([1.0, 0, 0]), "y": np.array([0, 1.0, 0]), "z": np.array([0, 0, 1.0])}


def rot(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rodrigues: R = I + sinφ·[k]× + (1 − cosφ)·[k]×²."""
    k = np.array(
        [[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]], dtype=float
    )
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * (k @ k)


def zyx(a: float, b: float, c: float) -> np.ndarray:
    """R = Rz(a)·Ry(b)·Rx(c), angles in degrees."""
    a, b, c = np.radians([a, b, c])
    return rot(AXES["z"], a) @ rot(AXES["y"], b) @ rot(AXES["x"], c)


def to_zyx(r: np.ndarray) -> np.ndarray:
    """Inverse of zyx (b in [−90, 90])."""
    b = np.arcsin(np.clip(-r[2, 0], -1, 1))
    return np.degrees([np.arctan2(r[1, 0], r[0, 0]), b, np.arctan2(r[2, 1], r[2, 2])])


def angle_between(r1: np.ndarray, r2: np.ndarray) -> float:
    """Rotation angle of r1ᵀr2 in degrees."""
    cos = (np.trace(r1.T @ r2) - 1) / 2
    return float(np.degrees(np.arccos(np.clip(cos, -1, 1))))


@dataclass
class Shape:
    link: int  # 1-based: the frame of joint `link`
    kind: str  # capsule | sphere
    a: np.ndarray
    b: np.ndarray
    radius: float


class Robot:
    """Joint chain, tool, base and collision shapes of one robot file (SI inside)."""

    def __init__(self, name: str) -> None:
        data = tomllib.loads((ROBOTS / f"{name}.toml").read_text())
        self.name = name
        self.joints = data["joints"]
        self.n = len(self.joints)
        self.prismatic = [j["kind"] == "prismatic" for j in self.joints]
        self.base = zyx(*data.get("base", {}).get("zyx", [0, 0, 0]))
        self.tool = np.array(data.get("tool", {}).get("xyz", [0, 0, 0]), dtype=float)
        self.shapes = [
            Shape(
                g["link"],
                g["shape"],
                np.array(g.get("a", g.get("center")), dtype=float),
                np.array(g.get("b", g.get("center")), dtype=float),
                g["radius"],
            )
            for g in data.get("geometry", [])
        ]

    def to_si(self, q_prog: np.ndarray) -> np.ndarray:
        """Program units (deg, mm) → (rad, m)."""
        q = np.asarray(q_prog, dtype=float)
        return np.where(self.prismatic, q / 1000.0, np.radians(q))

    def frames(self, q_prog: np.ndarray) -> tuple[list[tuple[np.ndarray, np.ndarray]], tuple]:
        """Joint frames (R, p) in the world after each joint's motion, and the TCP (R, p)."""
        q = self.to_si(q_prog)
        r, p = self.base.copy(), np.zeros(3)
        out = []
        for joint, qi, is_p in zip(self.joints, q, self.prismatic, strict=True):
            axis = AXES[joint["axis"]]
            if is_p:
                p = p + r @ (axis * qi)
            else:
                r = r @ rot(axis, qi)
            out.append((r, p))
            p = p + r @ np.array(joint["link"], dtype=float)
        return out, (r, p + r @ self.tool)

    def tcp(self, q_prog: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """TCP position (mm) and rotation matrix."""
        _, (r, p) = self.frames(q_prog)
        return p * 1000.0, r

    def shapes_world(self, q_prog: np.ndarray) -> list[tuple[np.ndarray, np.ndarray, float]]:
        """Every collision shape as a world capsule (a, b, radius) in metres."""
        fr, _ = self.frames(q_prog)
        out = []
        for s in self.shapes:
            r, p = fr[s.link - 1]
            out.append((p + r @ s.a, p + r @ s.b, s.radius))
        return out


def point_segment_distance(x: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    """|x − (a + t(b − a))| with t = clamp(((x − a)·(b − a))/|b − a|², 0, 1)."""
    d = b - a
    dd = float(d @ d)
    t = 0.0 if dd == 0 else min(1.0, max(0.0, float((x - a) @ d) / dd))
    return float(np.linalg.norm(x - (a + t * d)))


def point_polyline_distance(x: np.ndarray, pts: list[np.ndarray]) -> float:
    """Distance of x to the polyline pts[0] … pts[-1]."""
    if len(pts) == 1:
        return float(np.linalg.norm(x - pts[0]))
    return min(point_segment_distance(x, a, b) for a, b in itertools.pairwise(pts))


def circle_through(p0: np.ndarray, p1: np.ndarray, p2: np.ndarray) -> tuple:
    """Centre, radius and unit normal of the circle through three points."""
    a, b = p1 - p0, p2 - p0
    n = np.cross(a, b)
    n2 = float(n @ n)
    centre = p0 + (np.cross(n, a) * (b @ b) + np.cross(b, n) * (a @ a)) / (2 * n2)
    return centre, float(np.linalg.norm(p0 - centre)), n / np.sqrt(n2)


def point_arc_distance(x: np.ndarray, p0: np.ndarray, via: np.ndarray, p2: np.ndarray) -> float:
    """Distance of x to the arc p0 → via → p2 (the arc of the circle that contains via)."""
    c, rad, n = circle_through(p0, via, p2)
    u = (p0 - c) / rad
    v = np.cross(n, u)

    def ang(p: np.ndarray) -> float:
        return float(np.arctan2((p - c) @ v, (p - c) @ u)) % (2 * np.pi)

    end = ang(p2)  # the arc runs counter-clockwise about n from 0 to end (via lies inside)
    rel = x - c
    h = float(rel @ n)
    inplane = rel - h * n
    phi = ang(c + inplane) if np.linalg.norm(inplane) > 0 else 0.0
    if phi <= end:
        return float(np.hypot(h, np.linalg.norm(inplane) - rad))
    return min(float(np.linalg.norm(x - p0)), float(np.linalg.norm(x - p2)))


def capsule_point_clearance(cap: tuple, x: np.ndarray) -> float:
    """Surface distance (m) between a capsule (a, b, r) and a point."""
    a, b, r = cap
    return point_segment_distance(x, a, b) - r


def capsule_sphere_clearance(cap: tuple, centre: np.ndarray, radius: float) -> float:
    return capsule_point_clearance(cap, centre) - radius
