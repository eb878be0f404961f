"""Exact closest points between the robot's link geometry and obstacles (SI, world frame).

Both sides are a *core* swept by a sphere: robot capsules are segments with a radius,
robot spheres are degenerate segments (``a = b``); obstacles are points, spheres and
capsules (segments with a radius), boxes and planes (radius 0). The distance between
two swept shapes is the distance between their cores minus both radii, along the same
direction, so three core problems suffice, each solved in closed form:

* **segment–segment** (covers point and sphere): minimise ``‖p(s) − q(t)‖²`` over the
  unit square; the unconstrained stationary point is clamped edge by edge ([Ericson 2005],
  *Real-Time Collision Detection*, §5.1.9), with the degenerate and parallel cases
  handled explicitly.
* **segment–box** (oriented box, half extents ``h``, in the box frame): the squared
  distance ``φ(t) = Σ_i max(0, |p_i(t)| − h_i)²`` of ``p(t) = a + t·u`` is convex and
  piecewise quadratic with breakpoints where ``p_i(t) = ±h_i``; on each piece it is an
  explicit quadratic, minimised exactly. If the minimum is 0 the segment enters the box
  and the *signed* distance ``max_i(|p_i| − h_i)`` (convex, piecewise linear) is
  minimised exactly over its breakpoints (``p_i = 0`` and the crossings of two pieces):
  the deepest point, escaping through the nearest face.
* **segment–plane**: the signed distance is linear along the segment, so the minimum is
  at an endpoint (the midpoint when both are equal).

Sign convention: ``distance < 0`` is penetration (its magnitude is the depth of the
deepest core point beyond the obstacle's surface, reduced by the radii for swept
shapes). ``direction`` is the unit vector along which the robot point should move to
get away from the obstacle (obstacle → robot); for a penetrating box core it is the
normal of the face nearest to the deepest point, for a plane its normal.

Ties: parts whose distances are within :data:`TIE` (1e-12 m) of the least one are equally
close, and the lowest part index wins; a deepest box point equally deep (within ``TIE``)
below two faces escapes through the lower-indexed face (the deepest point of a segment
that enters a box is usually such a point, on the crossing of two faces' depths). So
rounding never decides which part or face is reported, and the compiled queries
(:mod:`irlc.runtime.ik.compiled.distance`), whose rounding differs, report the same ones.

Robots without collision geometry fall back to radius-0 segments between successive
link-frame origins, the last one ending at the TCP.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
from irlc.robots.model import Capsule, Sphere
from irlc.runtime.model.kinematics import Kinematics

_EPS = 1e-14
TIE = 1e-12  # m: distances (and face depths) this close are ties (module doc)


@dataclass
class Proximity:
    """Closest pair between one robot part and one obstacle."""

    distance: float  # m, negative = penetration
    robot_point: np.ndarray  # on the robot part's surface
    obstacle_point: np.ndarray  # on the obstacle's surface
    direction: np.ndarray  # unit, obstacle → robot (escape direction of the robot point)


@dataclass
class CriticalPoint(Proximity):
    """The closest robot part to one obstacle (seed 4.2.4: x_k, v, R)."""

    name: str = ""
    link: int = 0  # link index 0..n the robot point moves with


# ---------------------------------------------------------------------- core problems
def closest_segment_segment(p0, p1, q0, q1) -> tuple[float, float, np.ndarray, np.ndarray]:
    """Parameters ``s, t ∈ [0, 1]`` and points of the closest pair of two segments."""
    d1 = p1 - p0
    d2 = q1 - q0
    r = p0 - q0
    a = float(d1 @ d1)
    e = float(d2 @ d2)
    f = float(d2 @ r)
    if a <= _EPS and e <= _EPS:
        return 0.0, 0.0, p0.copy(), q0.copy()
    if a <= _EPS:
        s, t = 0.0, _clamp01(f / e)
    else:
        c = float(d1 @ r)
        if e <= _EPS:
            s, t = _clamp01(-c / a), 0.0
        else:
            b = float(d1 @ d2)
            denom = a * e - b * b
            s = _clamp01((b * f - c * e) / denom) if denom > _EPS * a * e else 0.0
            t = (b * s + f) / e
            if t < 0.0:
                t, s = 0.0, _clamp01(-c / a)
            elif t > 1.0:
                t, s = 1.0, _clamp01((b - c) / a)
    return s, t, p0 + s * d1, q0 + t * d2


def closest_segment_box(a, b, center, rotation, half):
    """Signed core distance of segment ``a``–``b`` to an oriented box, with the segment
    point, the box point and the unit escape direction (all world frame)."""
    pa = rotation.T @ (a - center)
    u = rotation.T @ (b - a)
    t, d2 = _segment_box_outside(pa.tolist(), u.tolist(), half.tolist())
    return _box_pair(pa, u, t, d2, center, rotation, half)


def _box_pair(pa, u, t: float, d2: float, center, rotation, half):
    """The closest pair of one segment (box frame: ``p(t) = pa + t·u``) and the box, from
    the outside minimiser ``t`` and ``min φ = d2``; the deepest point when it enters."""
    if d2 > 1e-24:
        p = pa + t * u
        q = np.minimum(np.maximum(p, -half), half)  # np.clip, without its overhead
        dist = float(np.sqrt(d2))
        normal = (p - q) / dist
    else:  # touching or entering (rounding may leave ~1e-32): signed depth, nearest face
        t, dist, face = _segment_box_deepest(pa, u, half)
        p = pa + t * u
        sign = 1.0 if p[face] >= 0.0 else -1.0
        q = p.copy()
        q[face] = sign * half[face]
        normal = np.zeros(3)
        normal[face] = sign
    return dist, center + rotation @ p, center + rotation @ q, rotation @ normal


def _segment_box_outside(pa: list, u: list, half: list) -> tuple[float, float]:
    """Exact ``argmin_t φ(t)`` and ``min φ`` of the squared outside distance of
    ``p(t) = pa + t·u`` (box frame; Python floats: a few hundred float operations are
    cheaper than numpy calls on 3-vectors).

    The breakpoints ``p_i(t) = ±h_i`` inside ``(0, 1)`` and the ends 0, 1 cut ``[0, 1]``
    into at most 7 pieces; on each piece (identified by its midpoint) ``φ`` is the
    quadratic ``αt² + 2βt + γ``, minimised exactly on the piece; the best piece wins
    (the first one on ties) and ``φ`` is evaluated directly at its minimiser."""
    cuts = [0.0, 1.0]
    for i in range(3):
        ui = u[i]
        if ui != 0.0:
            for bound in (half[i], -half[i]):
                t = (bound - pa[i]) / ui
                if 0.0 < t < 1.0:
                    cuts.append(t)
    cuts.sort()
    best_t, best = 0.0, math.inf
    for t0, t1 in itertools.pairwise(cuts):
        m = 0.5 * (t0 + t1)
        alpha = beta = gamma = 0.0
        for i in range(3):
            mid, h = pa[i] + m * u[i], half[i]
            if mid > h:
                c, d = pa[i] - h, u[i]
            elif mid < -h:
                c, d = -h - pa[i], -u[i]
            else:
                continue
            alpha += d * d
            beta += c * d
            gamma += c * c
        t = t0 if alpha <= 0.0 else min(max(-beta / alpha, t0), t1)
        value = max(alpha * t * t + 2.0 * beta * t + gamma, 0.0)
        if value < best:
            best_t, best = t, value
    # the piecewise form above is exact; evaluate the clamp directly at the minimiser
    exact = 0.0
    for i in range(3):
        p, h = pa[i] + best_t * u[i], half[i]
        e = p - h if p > h else (p + h if p < -h else 0.0)
        exact += e * e
    return best_t, exact


def _box_lower_bounds(pa: np.ndarray, u: np.ndarray, half: np.ndarray) -> np.ndarray:
    """Lower bounds of the signed core distances of ``k`` segments (rows, box frame) to
    a box: the gap between the segment's bounding box and the box; a segment whose
    bounding box meets the box may enter it, at most as deep as the box centre (minus
    the smallest half edge)."""
    pb = pa + u
    gap = np.minimum(pa, pb)
    np.maximum(gap, -np.maximum(pa, pb), out=gap)  # per axis: max(lo, −hi)
    gap -= half
    np.maximum(gap, 0.0, out=gap)
    lower = np.sqrt(np.einsum("ij,ij->i", gap, gap))
    lower[lower == 0.0] = -float(half.min())
    return lower


def _segment_box_deepest(pa, u, half) -> tuple[float, float, int]:
    """Exact minimum over t of ``max_i(|p_i(t)| − h_i)`` (≤ 0 here) and its face (the
    lowest-indexed one within :data:`TIE` of the maximum: module doc)."""
    cands = [0.0, 1.0]
    for i in range(3):
        if u[i] != 0.0:
            cands.append(-pa[i] / u[i])
        for j in range(i + 1, 3):
            for si in (1.0, -1.0):
                for sj in (1.0, -1.0):
                    den = si * u[i] - sj * u[j]
                    if den != 0.0:
                        cands.append((half[i] - half[j] - si * pa[i] + sj * pa[j]) / den)
    best_t, best, face = 0.0, np.inf, 0
    for t in cands:
        if 0.0 <= t <= 1.0:
            excess = np.abs(pa + t * u) - half
            top = float(excess.max())
            if top < best:  # the face: the lowest index within TIE of the deepest
                best_t, best, face = t, top, int(np.argmax(excess >= top - TIE))
    return best_t, best, face


def closest_segment_plane(a, b, point, normal):
    """Signed core distance of a segment to a plane (solid below the normal)."""
    sa = float(normal @ (a - point))
    sb = float(normal @ (b - point))
    if abs(sa - sb) <= 1e-15:
        p, s = 0.5 * (a + b), 0.5 * (sa + sb)
    elif sa < sb:
        p, s = a, sa
    else:
        p, s = b, sb
    return s, p, p - s * normal, normal


# ---------------------------------------------------------------------- swept shapes
def segment_obstacle(a: np.ndarray, b: np.ndarray, radius: float, obstacle) -> Proximity:
    """Closest pair between a robot part (segment ``a``–``b`` with ``radius``, world) and
    an obstacle of :mod:`irlc.runtime.model.obstacles`."""
    kind = obstacle.kind
    if kind == "box":
        core, p, q, v = closest_segment_box(a, b, obstacle.center, obstacle.rotation, obstacle.half)
    elif kind == "plane":
        core, p, q, v = closest_segment_plane(a, b, obstacle.point, obstacle.normal)
    else:
        if kind == "point":
            q0 = q1 = obstacle.position
        elif kind == "sphere":
            q0 = q1 = obstacle.center
        else:
            q0, q1 = obstacle.a, obstacle.b
        _, _, p, q = closest_segment_segment(a, b, q0, q1)
        diff = p - q
        core = float(np.sqrt(diff @ diff))
        v = diff / core if core > _EPS else fallback_direction(b - a, q1 - q0)
    return _swept(core, p, q, v, radius, obstacle.radius)


def _swept(core: float, p, q, v, radius: float, r_obst: float) -> Proximity:
    """The pair of two swept shapes from their cores' pair (``v``: unit, core → robot)."""
    return Proximity(core - radius - r_obst, p - radius * v, q + r_obst * v, v)


def fallback_direction(d1: np.ndarray, d2: np.ndarray) -> np.ndarray:
    """Escape direction when two cores touch: the common normal of the two segments,
    else any direction perpendicular to the robot segment, else +z."""
    n = np.cross(d1, d2)
    if n @ n <= _EPS:
        n = (
            np.cross(d1, (1.0, 0.0, 0.0))
            if abs(d1[0]) < 0.9 * np.linalg.norm(d1)
            else np.cross(d1, (0.0, 1.0, 0.0))
        )
    if n @ n <= _EPS:
        return np.array([0.0, 0.0, 1.0])
    return n / np.linalg.norm(n)


# ---------------------------------------------------------------------- the robot side
class RobotSegments:
    """The robot's parts as arrays (hot path; also the packed input of the compiled
    queries, :mod:`irlc.runtime.ik.compiled.distance`): ``links (k,)`` int64, the ends
    ``a_local, b_local (k, 3)`` in their link frames (zeros for the fallback chain, whose
    ends are link origins and the TCP), ``radius (k,)``, ``fallback``. Built from the
    model's capsules/spheres, or the fallback chain; :meth:`world` gives the world ends."""

    def __init__(self, kin: Kinematics):
        geometry = [g for g in kin.model.geometry if isinstance(g, Capsule | Sphere)]
        self.fallback = not geometry
        if self.fallback:
            self.links = np.arange(1, kin.n + 1, dtype=np.int64)
            self.radius = np.zeros(kin.n)
            self.a_local = self.b_local = np.zeros((kin.n, 3))
            return
        self.links = np.array([g.link for g in geometry], dtype=np.int64)
        self.a_local = np.array(
            [g.a if isinstance(g, Capsule) else g.center for g in geometry], dtype=float
        )
        self.b_local = np.array(
            [g.b if isinstance(g, Capsule) else g.center for g in geometry], dtype=float
        )
        self.radius = np.array([g.radius for g in geometry], dtype=float)

    def world(self, kin: Kinematics, frames: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        if self.fallback:
            origins = np.empty((kin.n + 1, 3))
            origins[:-1] = frames[1:, :3, 3]
            origins[-1] = kin.tcp_from_frames(frames)[:3, 3]
            return origins[:-1], origins[1:]
        rot = frames[self.links, :3, :3]
        pos = frames[self.links, :3, 3]
        a = np.einsum("kij,kj->ki", rot, self.a_local) + pos
        b = np.einsum("kij,kj->ki", rot, self.b_local) + pos
        return a, b

    def world_many(self, kin: Kinematics, frames: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`world` of ``k`` configurations' link frames (``(k, n+1, 4, 4)`` →
        ``(k, parts, 3)`` each)."""
        if self.fallback:
            ends = [self.world(kin, f) for f in frames]
            return np.stack([e[0] for e in ends]), np.stack([e[1] for e in ends])
        linked = frames[:, self.links]  # (k, parts, 4, 4)
        rot, pos = linked[:, :, :3, :3], linked[:, :, :3, 3]
        a = np.einsum("kpij,pj->kpi", rot, self.a_local) + pos
        b = np.einsum("kpij,pj->kpi", rot, self.b_local) + pos
        return a, b


_SEGMENTS: dict[int, tuple[object, RobotSegments]] = {}


def robot_segments(kin: Kinematics) -> RobotSegments:
    """Cached :class:`RobotSegments` of a kinematics object's model."""
    hit = _SEGMENTS.get(id(kin))
    if hit is None or hit[0] is not kin.model:
        hit = (kin.model, RobotSegments(kin))
        _SEGMENTS[id(kin)] = hit
    return hit[1]


def robot_parts(
    kin: Kinematics, frames: np.ndarray
) -> list[tuple[int, np.ndarray, np.ndarray, float]]:
    """World segments ``(link, a, b, radius)`` of the robot's collision geometry."""
    seg = robot_segments(kin)
    a, b = seg.world(kin, frames)
    return [(int(seg.links[i]), a[i], b[i], float(seg.radius[i])) for i in range(a.shape[0])]


def _points_to_segments(a: np.ndarray, b: np.ndarray, p: np.ndarray):
    """Closest points on each segment ``a_i b_i`` to ``p`` and their distances."""
    u = b - a
    uu = np.einsum("ij,ij->i", u, u)
    t = np.einsum("ij,ij->i", p - a, u) / np.where(uu > _EPS, uu, 1.0)
    np.clip(t, 0.0, 1.0, out=t)
    c = a + t[:, None] * u
    diff = c - p
    return c, np.sqrt(np.einsum("ij,ij->i", diff, diff))


def critical_points(kin: Kinematics, frames: np.ndarray, obstacles) -> list[CriticalPoint]:
    """One record per obstacle: the robot part closest to it and the closest pair.

    Point, sphere, box and plane obstacles are measured against all parts at once
    (vectorised core distances; the closest pair is then built for the closest part
    only). For capsules, parts are visited in order of a lower bound of their distance
    (centre distance minus the obstacle's bounding radius) and the search stops when the
    bound exceeds the best exact distance found — the result is still exact. Ties
    (distances within :data:`TIE`, e.g. a sphere at a joint and the capsule starting
    there) go to the lowest part index (module doc)."""
    seg = robot_segments(kin)
    a_all, b_all = seg.world(kin, frames)
    return closest_parts(a_all, b_all, seg.radius, seg.links, obstacles)


def closest_parts(
    a_all: np.ndarray, b_all: np.ndarray, radius: np.ndarray, links: np.ndarray, obstacles
) -> list[CriticalPoint]:
    """:func:`critical_points` of parts given by their world ends ``a_all``, ``b_all``
    (``(k, 3)``), radii and the link each moves with (a chain of several robots gathers
    its robots' parts: :class:`~irlc.runtime.model.bodies.CellBodies`)."""
    out = []
    for obstacle in obstacles:
        kind = obstacle.kind
        if kind in ("point", "sphere"):
            p = obstacle.position if kind == "point" else obstacle.center
            _, dist = _points_to_segments(a_all, b_all, p)
            i = _first_tie(dist - radius)
            best = segment_obstacle(a_all[i], b_all[i], float(radius[i]), obstacle)
        elif kind == "box":
            best, i = _closest_part_box(a_all, b_all, radius, obstacle)
        elif kind == "plane":
            i = _closest_part_plane(a_all, b_all, radius, obstacle)
            best = segment_obstacle(a_all[i], b_all[i], float(radius[i]), obstacle)
        else:
            best, i = _search_parts(a_all, b_all, radius, obstacle)
        out.append(
            CriticalPoint(
                best.distance,
                best.robot_point,
                best.obstacle_point,
                best.direction,
                obstacle.name,
                int(links[i]),
            )
        )
    return out


def _closest_part_box(a_all, b_all, radius, box) -> tuple[Proximity, int]:
    """The part closest to a box: a cheap lower bound (:func:`_box_lower_bounds`) for all
    parts, then exact distances in increasing order of the bound until the bound
    exceeds the best distance found (+1 nm, so that ties are all seen); ties (within
    :data:`TIE`) go to the lowest part index."""
    center, rotation, half = box.center, box.rotation, box.half
    pa = (a_all - center) @ rotation  # rows: Rᵀ(a − c)
    u = (b_all - a_all) @ rotation
    lower = _box_lower_bounds(pa, u, half)
    lower -= radius
    h, r_obst = half.tolist(), box.radius
    best = math.inf
    found = {}  # part → (distance, t, φ(t))
    for i in np.argsort(lower).tolist():
        if lower[i] > best + 1e-9:
            break
        t, d2 = _segment_box_outside(pa[i].tolist(), u[i].tolist(), h)
        core = math.sqrt(d2) if d2 > 1e-24 else _segment_box_deepest(pa[i], u[i], half)[1]
        found[i] = (core - float(radius[i]) - r_obst, t, d2)
        best = min(best, found[i][0])
    _, i = _lowest_tie([(d, j) for j, (d, _, _) in found.items()])
    _, t, d2 = found[i]
    pair = _box_pair(pa[i], u[i], t, d2, center, rotation, half)
    return _swept(*pair, float(radius[i]), r_obst), i


def _closest_part_plane(a_all, b_all, radius, plane) -> int:
    """Index of the part closest to a plane (the signed distance is linear along a part:
    its minimum is at an end, the midpoint when both are equal)."""
    sa = (a_all - plane.point) @ plane.normal
    sb = (b_all - plane.point) @ plane.normal
    core = np.where(np.abs(sa - sb) <= 1e-15, 0.5 * (sa + sb), np.minimum(sa, sb))
    return _first_tie(core - radius)


def _first_tie(d: np.ndarray) -> int:
    """The lowest index whose value is within :data:`TIE` of the least."""
    return int(np.argmax(d <= d.min() + TIE))


def _lowest_tie(found: list[tuple[float, int]]) -> tuple[float, int]:
    """Of ``(distance, part)`` pairs, the lowest part within :data:`TIE` of the least
    distance (the same whatever order the parts were visited in)."""
    least = min(d for d, _ in found)
    i, d = min((i, d) for d, i in found if d <= least + TIE)
    return d, i


def _visit_order(a_all, b_all, radius, capsule):
    """Parts in increasing order of a lower bound of their distance to a capsule (the
    distance to its centre minus its bounding radius), and the bounds."""
    center = 0.5 * (capsule.a + capsule.b)
    reach = 0.5 * float(np.linalg.norm(capsule.b - capsule.a)) + capsule.radius
    _, dist = _points_to_segments(a_all, b_all, center)
    bound = dist - reach - radius
    return np.argsort(bound), bound


def _search_parts(a_all, b_all, radius, obstacle) -> tuple[Proximity, int]:
    """Parts in increasing order of the bound until it exceeds the best distance found
    (+ :data:`TIE`, so that ties are all seen); ties go to the lowest part index."""
    order, bound = _visit_order(a_all, b_all, radius, obstacle)
    best = math.inf
    found: dict[int, Proximity] = {}
    for i in order.tolist():
        if bound[i] > best + TIE:
            break
        found[i] = segment_obstacle(a_all[i], b_all[i], float(radius[i]), obstacle)
        best = min(best, found[i].distance)
    _, i = _lowest_tie([(p.distance, j) for j, p in found.items()])
    return found[i], i


def _clamp01(x: float) -> float:
    return 0.0 if x < 0.0 else (1.0 if x > 1.0 else x)
