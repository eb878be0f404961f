"""Clearance between links: the distances between the parts of several robots and between
the non-adjacent parts of one robot (self-collision), SI, world frame.

A robot's parts are its collision geometry (capsules and spheres of the robot file,
:class:`~irlc.runtime.model.distance.RobotSegments`: a core segment ``a``–``b`` swept by a
sphere of ``radius``; a robot without geometry: radius-0 segments between its link
origins and the TCP). The distance of two parts is the distance of their cores minus both
radii, along the line of the cores' closest points ([Ericson 2005] §5.1.9, the clamped
stationary point of ``‖p(s) − q(t)‖²`` over the unit square): negative is penetration.
:func:`segment_distances` solves many pairs at once (numpy, one pass); it equals
:func:`~irlc.runtime.model.distance.closest_segment_segment` pair by pair.

**Which pairs are watched** (:class:`PartSet`):

* every part of one robot against every part of every other robot (a cell);
* within one robot, parts on links at least two apart (``|l_i − l_j| ≥ 2``: adjacent links
  touch at their common joint by construction) that are apart — distance > 0 — in the
  robot's home configuration. *Decision:* parts that touch or overlap at home (a sphere at
  a joint and the capsule of the next-but-one link starting there; a wrist whose middle
  link has no length) are in contact by design, as MoveIt's setup assistant disables the
  pairs "in collision by default"; they are never watched.

**What a pair keeps** (:meth:`PartSet.keep`) under ``R_CLEARANCE := d``: ``d`` between two
robots; within one robot ``d`` when the pair is at least ``d`` apart at home, else only
apart (``≥ 0``) — links that are close by design (the Panda's wrist parts, 8 mm apart at
home) may come closer, but not into each other.

A :class:`Clearance` is the closest watched pair at one configuration: its distance, the two
parts (robot and link of each, by the robots' names), the closest points and the direction
from the second part to the first (the first part's escape direction).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from irlc.runtime.model.distance import fallback_direction, robot_segments
from irlc.runtime.model.kinematics import Kinematics

_EPS = 1e-14


def segment_distances(p0, p1, q0, q1) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Closest points of ``k`` pairs of segments ``p0 p1`` and ``q0 q1`` (rows, ``(k, 3)``):
    parameters ``s, t`` in [0, 1] and the points ``p(s)``, ``q(t)`` — Ericson's clamping
    (module doc), with the degenerate (point) and parallel cases as in
    :func:`~irlc.runtime.model.distance.closest_segment_segment`."""
    d1, d2, r = p1 - p0, q1 - q0, p0 - q0
    a = np.einsum("ij,ij->i", d1, d1)
    e = np.einsum("ij,ij->i", d2, d2)
    f = np.einsum("ij,ij->i", d2, r)
    c = np.einsum("ij,ij->i", d1, r)
    b = np.einsum("ij,ij->i", d1, d2)
    p_point, q_point = a <= _EPS, e <= _EPS
    safe_a = np.where(p_point, 1.0, a)
    safe_e = np.where(q_point, 1.0, e)
    denom = a * e - b * b
    s = np.zeros_like(a)
    np.divide(b * f - c * e, denom, out=s, where=denom > _EPS * a * e)
    np.clip(s, 0.0, 1.0, out=s)
    t = (b * s + f) / safe_e
    s = np.where(t < 0.0, -c / safe_a, np.where(t > 1.0, (b - c) / safe_a, s))
    np.clip(s, 0.0, 1.0, out=s)
    np.clip(t, 0.0, 1.0, out=t)
    odd = p_point | q_point
    if odd.any():  # a point against a segment, a segment against a point, two points
        only_q = q_point & ~p_point
        s[p_point] = 0.0
        s[only_q] = np.clip(-c[only_q] / safe_a[only_q], 0.0, 1.0)
        t[only_q] = 0.0
        t[p_point] = np.where(q_point[p_point], 0.0, np.clip(f[p_point] / safe_e[p_point], 0, 1))
    return s, t, p0 + s[:, None] * d1, q0 + t[:, None] * d2


@dataclass(frozen=True)
class Clearance:
    """The closest watched pair (SI): ``distance`` (m, negative: penetration), the parts'
    robots and links (``robot_a``/``robot_b``: indices into the part set's robots), their
    closest points and the unit ``direction`` from part b to part a."""

    distance: float
    robot_a: int
    link_a: int
    robot_b: int
    link_b: int
    point_a: np.ndarray
    point_b: np.ndarray
    direction: np.ndarray


class RobotParts:
    """One robot's parts (its :class:`~irlc.runtime.model.distance.RobotSegments`) and the
    pairs of its own parts that are watched (module doc: links two apart, apart at home)."""

    def __init__(self, name: str, kin: Kinematics):
        self.name, self.kin = name, kin
        self.segments = seg = robot_segments(kin)
        self.links = seg.links
        self.radius = seg.radius
        self.size = len(seg.links)
        i, j = np.triu_indices(self.size, k=1)
        apart = np.abs(seg.links[i] - seg.links[j]) >= 2
        i, j = i[apart], j[apart]
        home = np.zeros(0)
        if i.size:
            a, b = self.world(kin.link_frames(kin.model.home_q()))
            home = _pair_distances(a, b, seg.radius, i, j)
            i, j, home = i[home > 0.0], j[home > 0.0], home[home > 0.0]
        self.self_pairs = (i, j)
        self.home = home  # m: each own pair's distance at home

    def world(self, frames: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """World ends ``a, b`` (``(k, 3)``) of the parts at the link ``frames``."""
        return self.segments.world(self.kin, frames)


def _pair_distances(a, b, radius, i, j) -> np.ndarray:
    """Distances of the parts pairs ``(i, j)`` (surfaces: cores minus radii)."""
    _, _, p, q = segment_distances(a[i], b[i], a[j], b[j])
    diff = p - q
    return np.sqrt(np.einsum("ij,ij->i", diff, diff)) - radius[i] - radius[j]


class PartSet:
    """The parts of several robots in one array and the watched pairs among them (module
    doc): each robot's own pairs and, for ``between`` (default: all), every part of one
    robot against every part of the other. Part ``k`` of the set is robot
    ``robot[k]``'s part on link ``link[k]``."""

    def __init__(
        self,
        robots: Sequence[RobotParts],
        *,
        between: Sequence[tuple[int, int]] | None = None,
        own: bool = True,
    ):
        self.robots = tuple(robots)
        sizes = [r.size for r in self.robots]
        self.offsets = np.concatenate(([0], np.cumsum(sizes)[:-1])).astype(int)
        self.robot = np.concatenate([np.full(r.size, k) for k, r in enumerate(self.robots)])
        self.link = np.concatenate([r.links for r in self.robots]).astype(int)
        self.radius = np.concatenate([r.radius for r in self.robots])
        first, second, home = [], [], []
        if own:
            for r, off in zip(self.robots, self.offsets, strict=True):
                first.append(r.self_pairs[0] + off)
                second.append(r.self_pairs[1] + off)
                home.append(r.home)
        n = len(self.robots)
        pairs = [(x, y) for x in range(n) for y in range(x + 1, n)] if between is None else between
        for x, y in pairs:
            gi, gj = np.meshgrid(
                np.arange(sizes[x]) + self.offsets[x], np.arange(sizes[y]) + self.offsets[y]
            )
            first.append(gi.ravel())
            second.append(gj.ravel())
            home.append(np.full(gi.size, np.inf))
        self.i = np.concatenate(first).astype(int) if first else np.zeros(0, dtype=int)
        self.j = np.concatenate(second).astype(int) if second else np.zeros(0, dtype=int)
        self.home = np.concatenate(home) if home else np.zeros(0)  # ∞ between robots
        # the robots of each pair, and the pairs of robots (a ≤ b) that have pairs
        ra, rb = self.robot[self.i], self.robot[self.j]
        self.groups = sorted({(int(x), int(y)) for x, y in zip(ra, rb, strict=True)})
        index = {g: k for k, g in enumerate(self.groups)}
        self.group = np.array(
            [index[(int(x), int(y))] for x, y in zip(ra, rb, strict=True)], dtype=int
        )
        # the pairs come group by group: (group, start, stop) of each block of pairs
        edges = (np.flatnonzero(np.diff(self.group)) + 1).tolist()
        bounds = list(zip([0, *edges], [*edges, self.group.size], strict=True))
        self._blocks = [(int(self.group[a]), a, b) for a, b in bounds if b > a]

    def __len__(self) -> int:
        return self.i.size

    def group_minima(self, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Per pair of robots (:attr:`groups`: ``(a, a)`` a robot's own parts) the least of
        the pair distances ``d`` and the index of its pair."""
        best = np.full(len(self.groups), np.inf)
        arg = np.zeros(len(self.groups), dtype=int)
        for g, start, stop in self._blocks:
            k = start + int(np.argmin(d[start:stop]))
            if d[k] < best[g]:
                best[g], arg[g] = d[k], k
        return best, arg

    def keep(self, distance: float) -> np.ndarray:
        """What each pair keeps under ``R_CLEARANCE`` ``distance`` (m, module doc)."""
        return np.where(self.home >= distance, distance, 0.0)

    def world(self, frames: Sequence[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        """The parts' world ends from each robot's link frames (in the robots' order)."""
        ends = [r.world(f) for r, f in zip(self.robots, frames, strict=True)]
        return np.concatenate([e[0] for e in ends]), np.concatenate([e[1] for e in ends])

    def distances(self, a: np.ndarray, b: np.ndarray):
        """``(distance, s, t, p, q)`` of every watched pair (rows in the order of ``i, j``)
        at the world ends ``a, b``."""
        i, j = self.i, self.j
        s, t, p, q = segment_distances(a[i], b[i], a[j], b[j])
        diff = p - q
        core = np.sqrt(np.einsum("ij,ij->i", diff, diff))
        return core - self.radius[i] - self.radius[j], s, t, p, q

    def closest(self, a: np.ndarray, b: np.ndarray) -> Clearance | None:
        """The closest watched pair at the world ends ``a, b`` (``None``: no pairs); of
        equal distances the first pair."""
        if not len(self):
            return None
        d, _, _, p, q = self.distances(a, b)
        k = int(np.argmin(d))
        return self.clearance(k, float(d[k]), p[k], q[k], a, b)

    def clearance(self, k: int, distance: float, p, q, a, b) -> Clearance:
        """Pair ``k`` as a :class:`Clearance` (its surface points and direction)."""
        i, j = int(self.i[k]), int(self.j[k])
        diff = p - q
        core = float(np.linalg.norm(diff))
        v = diff / core if core > _EPS else fallback_direction(b[i] - a[i], b[j] - a[j])
        ri, rj = float(self.radius[i]), float(self.radius[j])
        return Clearance(
            distance, int(self.robot[i]), int(self.link[i]), int(self.robot[j]),
            int(self.link[j]), p - ri * v, q + rj * v, v,
        )  # fmt: skip

    def label(self, robot: int, link: int) -> str:
        """``welder link 3`` (``link 3`` for an unnamed robot)."""
        name = self.robots[robot].name
        return f"{name} link {link}" if name else f"link {link}"
