"""Compiled obstacle distances (numba): :func:`critical_points` and the obstacle
criterion's terms (:func:`obstacle_terms`) of the compiled IK cycle.

The numpy reference is :mod:`irlc.runtime.model.distance` (closest pairs) and
:mod:`irlc.runtime.ik.obstacle` (the terms); every function here is the same arithmetic
written as loops over scalars, with the same choices (which part is closest, ties, the
escape direction of touching cores), so results agree to rounding (tested against the
numpy path on random configurations in ``tests/ik/test_compiled_distance.py``):

* segment–segment (point, sphere and capsule obstacles): Ericson's clamped stationary
  point (``distance.closest_segment_segment``); the part by the point–segment distance
  (point, sphere) or by the exact distance of the parts a bound does not exclude
  (capsule, ``_search_parts``);
* segment–box: the exact minimiser of the piecewise-quadratic outside distance
  (``_segment_box_outside``), the deepest point when the segment enters
  (``_segment_box_deepest``); parts in index order, pruned by the same lower bound as
  ``_closest_part_box``;
* segment–plane: the lower end (the midpoint when both are level).

Ties (``distance.TIE``): the lowest part index within 1e-12 m of the least distance, the
lowest face within 1e-12 m of the deepest — a rule the numpy reference follows too, so
the different rounding of the two never picks a different part or face.

**Packed input** (public, built in Python once per robot / obstacle set):

* the robot's parts: :class:`~irlc.runtime.model.distance.RobotSegments`' ``links`` (k,),
  ``a_local``, ``b_local`` (k, 3) in their link frames, ``radius`` (k,) and ``fallback``
  (no collision geometry: segments between successive link origins, the last one to the
  TCP — then the local ends are unused);
* the obstacles: :func:`pack_obstacles`, one row of :data:`N_COLS` floats per obstacle —
  ``[kind, radius, p(3), q(3), half(3), R(9, row-major)]`` with ``p, q`` the core's ends
  (point: position twice; sphere: centre twice; capsule: ``a, b``; box: centre, ``q``
  unused; plane: point and unit normal).

**Output** of :func:`critical_points`: one row of :data:`N_CP` floats per obstacle,
``[distance, robot point(3), obstacle point(3), direction(3), link]`` (the fields of
:class:`~irlc.runtime.model.distance.CriticalPoint`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

KIND_CODES = {"point": 0, "sphere": 1, "capsule": 2, "box": 3, "plane": 4}
POINT, SPHERE, CAPSULE, BOX, PLANE = range(5)
C_KIND, C_RADIUS, C_P, C_Q, C_HALF, C_ROT, N_COLS = 0, 1, 2, 5, 8, 11, 20
D_DIST, D_ROBOT, D_OBST, D_DIR, D_LINK, N_CP = 0, 1, 4, 7, 10, 11
# obstacle criterion parameters (ObstacleParams), in this order
P_A_OBST, P_C, P_ACTIVATION, P_RAMP, P_MIN_DISTANCE, N_PARAMS = range(6)

_EPS = 1e-14  # distance._EPS
_TIE = 1e-12  # distance.TIE: distances (and face depths) this close are ties


def pack_obstacles(obstacles) -> np.ndarray:
    """The rows of :mod:`irlc.runtime.model.obstacles` shapes (module doc), read-only."""
    out = np.zeros((len(obstacles), N_COLS))
    for row, o in zip(out, obstacles, strict=True):
        kind = o.kind
        row[C_KIND] = KIND_CODES[kind]
        row[C_RADIUS] = o.radius
        if kind == "point":
            p = q = o.position
        elif kind == "sphere":
            p = q = o.center
        elif kind == "capsule":
            p, q = o.a, o.b
        elif kind == "plane":
            p, q = o.point, o.normal
        else:
            p = q = o.center
            row[C_HALF : C_HALF + 3] = o.half
            row[C_ROT : C_ROT + 9] = np.asarray(o.rotation, dtype=float).ravel()
        row[C_P : C_P + 3] = p
        row[C_Q : C_Q + 3] = q
    out.flags.writeable = False
    return out


def pack_params(params) -> np.ndarray:
    """:class:`~irlc.runtime.ik.params.ObstacleParams` as the kernel's parameter vector."""
    return np.array([params.a_obst, params.c, params.activation, params.ramp, params.min_distance])


# ---------------------------------------------------------------------- robot parts
@njit(cache=True)
def _world_parts(frames, tcp, links, a_local, b_local, fallback, A, B):
    """World ends of every part into ``A``, ``B`` (``RobotSegments.world``)."""
    k = links.shape[0]
    if fallback:
        for i in range(k):
            for r in range(3):
                A[i, r] = frames[i + 1, r, 3]
                B[i, r] = frames[i + 2, r, 3] if i + 2 < frames.shape[0] else tcp[r, 3]
        return
    for i in range(k):
        f = frames[links[i]]
        for r in range(3):
            A[i, r] = f[r, 0] * a_local[i, 0] + f[r, 1] * a_local[i, 1] + f[r, 2] * a_local[i, 2]
            A[i, r] += f[r, 3]
            B[i, r] = f[r, 0] * b_local[i, 0] + f[r, 1] * b_local[i, 1] + f[r, 2] * b_local[i, 2]
            B[i, r] += f[r, 3]


@njit(cache=True)
def _point_segment(a, b, p):
    """Distance of ``p`` to the segment ``a``–``b`` (``distance._points_to_segments``)."""
    u0, u1, u2 = b[0] - a[0], b[1] - a[1], b[2] - a[2]
    uu = u0 * u0 + u1 * u1 + u2 * u2
    t = ((p[0] - a[0]) * u0 + (p[1] - a[1]) * u1 + (p[2] - a[2]) * u2) / (uu if uu > _EPS else 1.0)
    t = min(max(t, 0.0), 1.0)
    d0 = a[0] + t * u0 - p[0]
    d1 = a[1] + t * u1 - p[1]
    d2 = a[2] + t * u2 - p[2]
    return math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)


# ---------------------------------------------------------------------- core problems
@njit(cache=True)
def _clamp01(x):
    return 0.0 if x < 0.0 else (1.0 if x > 1.0 else x)


@njit(cache=True)
def _segment_segment(p0, p1, q0, q1, pq):
    """Closest points of two segments into ``pq[0:3]``, ``pq[3:6]``
    (``distance.closest_segment_segment``)."""
    d10, d11, d12 = p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]
    d20, d21, d22 = q1[0] - q0[0], q1[1] - q0[1], q1[2] - q0[2]
    r0, r1, r2 = p0[0] - q0[0], p0[1] - q0[1], p0[2] - q0[2]
    a = d10 * d10 + d11 * d11 + d12 * d12
    e = d20 * d20 + d21 * d21 + d22 * d22
    f = d20 * r0 + d21 * r1 + d22 * r2
    s = 0.0
    t = 0.0
    if a <= _EPS and e <= _EPS:
        pass
    elif a <= _EPS:
        t = _clamp01(f / e)
    else:
        c = d10 * r0 + d11 * r1 + d12 * r2
        if e <= _EPS:
            s = _clamp01(-c / a)
        else:
            b = d10 * d20 + d11 * d21 + d12 * d22
            denom = a * e - b * b
            s = _clamp01((b * f - c * e) / denom) if denom > _EPS * a * e else 0.0
            t = (b * s + f) / e
            if t < 0.0:
                t = 0.0
                s = _clamp01(-c / a)
            elif t > 1.0:
                t = 1.0
                s = _clamp01((b - c) / a)
    pq[0], pq[1], pq[2] = p0[0] + s * d10, p0[1] + s * d11, p0[2] + s * d12
    pq[3], pq[4], pq[5] = q0[0] + t * d20, q0[1] + t * d21, q0[2] + t * d22


@njit(cache=True)
def _cross(x0, x1, x2, y0, y1, y2):
    return x1 * y2 - x2 * y1, x2 * y0 - x0 * y2, x0 * y1 - x1 * y0


@njit(cache=True)
def _fallback_direction(a, b, q0, q1, v):
    """Escape direction of touching cores into ``v`` (``distance._fallback_direction``
    of ``b − a`` and ``q1 − q0``)."""
    d0, d1, d2 = b[0] - a[0], b[1] - a[1], b[2] - a[2]
    n0, n1, n2 = _cross(d0, d1, d2, q1[0] - q0[0], q1[1] - q0[1], q1[2] - q0[2])
    if n0 * n0 + n1 * n1 + n2 * n2 <= _EPS:
        if abs(d0) < 0.9 * math.sqrt(d0 * d0 + d1 * d1 + d2 * d2):
            n0, n1, n2 = _cross(d0, d1, d2, 1.0, 0.0, 0.0)
        else:
            n0, n1, n2 = _cross(d0, d1, d2, 0.0, 1.0, 0.0)
    nn = n0 * n0 + n1 * n1 + n2 * n2
    if nn <= _EPS:
        v[0], v[1], v[2] = 0.0, 0.0, 1.0
        return
    norm = math.sqrt(nn)
    v[0], v[1], v[2] = n0 / norm, n1 / norm, n2 / norm


@njit(cache=True)
def _segment_core(a, b, q0, q1, out):
    """Core pair of a part and a point / segment core: ``out = [core, p, q, v]``
    (``distance.segment_obstacle``, before the radii)."""
    _segment_segment(a, b, q0, q1, out[1:7])
    d0, d1, d2 = out[1] - out[4], out[2] - out[5], out[3] - out[6]
    core = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    out[0] = core
    if core > _EPS:
        out[7], out[8], out[9] = d0 / core, d1 / core, d2 / core
    else:
        _fallback_direction(a, b, q0, q1, out[7:10])


@njit(cache=True)
def _box_frame(a, b, center, rot, pa, u):
    """``pa = Rᵀ(a − c)``, ``u = Rᵀ(b − a)`` (box frame)."""
    for j in range(3):
        pa[j] = (a[0] - center[0]) * rot[0, j] + (a[1] - center[1]) * rot[1, j]
        pa[j] += (a[2] - center[2]) * rot[2, j]
        u[j] = (b[0] - a[0]) * rot[0, j] + (b[1] - a[1]) * rot[1, j] + (b[2] - a[2]) * rot[2, j]


@njit(cache=True)
def _segment_box_outside(pa, u, half, cuts):
    """Exact ``argmin_t φ(t)`` and ``min φ`` (``distance._segment_box_outside``: the same
    pieces in the same order, the first best piece on ties)."""
    cuts[0] = 0.0
    cuts[1] = 1.0
    nc = 2
    for i in range(3):
        ui = u[i]
        if ui != 0.0:
            for sign in (1.0, -1.0):
                t = (sign * half[i] - pa[i]) / ui
                if 0.0 < t < 1.0:
                    cuts[nc] = t
                    nc += 1
    for i in range(1, nc):  # insertion sort
        x = cuts[i]
        j = i - 1
        while j >= 0 and cuts[j] > x:
            cuts[j + 1] = cuts[j]
            j -= 1
        cuts[j + 1] = x
    best_t = 0.0
    best = math.inf
    for piece in range(nc - 1):
        t0, t1 = cuts[piece], cuts[piece + 1]
        m = 0.5 * (t0 + t1)
        alpha = 0.0
        beta = 0.0
        gamma = 0.0
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
            best_t = t
            best = value
    exact = 0.0
    for i in range(3):
        p, h = pa[i] + best_t * u[i], half[i]
        e = p - h if p > h else (p + h if p < -h else 0.0)
        exact += e * e
    return best_t, exact


@njit(cache=True)
def _deepest_candidate(pa, u, half, t, best_t, best, face):
    """One candidate ``t`` of :func:`_segment_box_deepest` (kept when strictly deeper;
    its face: the lowest index within ``_TIE`` of the deepest)."""
    if 0.0 <= t <= 1.0:
        e0 = abs(pa[0] + t * u[0]) - half[0]
        e1 = abs(pa[1] + t * u[1]) - half[1]
        e2 = abs(pa[2] + t * u[2]) - half[2]
        top = max(e0, e1, e2)
        if top < best:
            k = 0 if e0 >= top - _TIE else (1 if e1 >= top - _TIE else 2)
            return t, top, k
    return best_t, best, face


@njit(cache=True)
def _segment_box_deepest(pa, u, half):
    """Exact minimum over t of ``max_i(|p_i(t)| − h_i)`` and its face
    (``distance._segment_box_deepest``, candidates in the same order)."""
    best_t, best, face = 0.0, math.inf, 0
    best_t, best, face = _deepest_candidate(pa, u, half, 0.0, best_t, best, face)
    best_t, best, face = _deepest_candidate(pa, u, half, 1.0, best_t, best, face)
    for i in range(3):
        if u[i] != 0.0:
            best_t, best, face = _deepest_candidate(pa, u, half, -pa[i] / u[i], best_t, best, face)
        for j in range(i + 1, 3):
            for si in (1.0, -1.0):
                for sj in (1.0, -1.0):
                    den = si * u[i] - sj * u[j]
                    if den != 0.0:
                        t = (half[i] - half[j] - si * pa[i] + sj * pa[j]) / den
                        best_t, best, face = _deepest_candidate(pa, u, half, t, best_t, best, face)
    return best_t, best, face


@njit(cache=True)
def _box_pair(pa, u, t, d2, center, rot, half, out):
    """``out = [core, p, q, v]`` of a part and a box from the outside minimiser
    (``distance._box_pair``; the deepest point and nearest face when it enters)."""
    p = np.empty(3)
    q = np.empty(3)
    v = np.zeros(3)
    if d2 > 1e-24:
        for i in range(3):
            p[i] = pa[i] + t * u[i]
            q[i] = min(max(p[i], -half[i]), half[i])
        dist = math.sqrt(d2)
        for i in range(3):
            v[i] = (p[i] - q[i]) / dist
    else:
        t, dist, face = _segment_box_deepest(pa, u, half)
        for i in range(3):
            p[i] = pa[i] + t * u[i]
            q[i] = p[i]
        sign = 1.0 if p[face] >= 0.0 else -1.0
        q[face] = sign * half[face]
        v[face] = sign
    out[0] = dist
    for r in range(3):
        out[1 + r] = center[r] + (rot[r, 0] * p[0] + rot[r, 1] * p[1] + rot[r, 2] * p[2])
        out[4 + r] = center[r] + (rot[r, 0] * q[0] + rot[r, 1] * q[1] + rot[r, 2] * q[2])
        out[7 + r] = rot[r, 0] * v[0] + rot[r, 1] * v[1] + rot[r, 2] * v[2]


@njit(cache=True)
def _plane_core(a, b, point, normal, out):
    """``out = [core, p, q, n]`` of a part and a plane (``distance.closest_segment_plane``)."""
    sa = normal[0] * (a[0] - point[0]) + normal[1] * (a[1] - point[1])
    sa += normal[2] * (a[2] - point[2])
    sb = normal[0] * (b[0] - point[0]) + normal[1] * (b[1] - point[1])
    sb += normal[2] * (b[2] - point[2])
    if abs(sa - sb) <= 1e-15:
        s = 0.5 * (sa + sb)
        for r in range(3):
            out[1 + r] = 0.5 * (a[r] + b[r])
    elif sa < sb:
        s = sa
        for r in range(3):
            out[1 + r] = a[r]
    else:
        s = sb
        for r in range(3):
            out[1 + r] = b[r]
    out[0] = s
    for r in range(3):
        out[4 + r] = out[1 + r] - s * normal[r]
        out[7 + r] = normal[r]


# ---------------------------------------------------------------------- per obstacle
@njit(cache=True)
def _swept(pair, radius, r_obst, link, out):
    """The critical point's row from the cores' pair ``[core, p, q, v]`` (``_swept``)."""
    out[D_DIST] = pair[0] - radius - r_obst
    for r in range(3):
        v = pair[7 + r]
        out[D_ROBOT + r] = pair[1 + r] - radius * v
        out[D_OBST + r] = pair[4 + r] + r_obst * v
        out[D_DIR + r] = v
    out[D_LINK] = link


@njit(cache=True)
def _first_tie(d):
    """The lowest index whose value is within ``_TIE`` of the least
    (``distance._first_tie`` / ``_lowest_tie``)."""
    least = math.inf
    for i in range(d.shape[0]):
        least = min(least, d[i])
    for i in range(d.shape[0]):
        if d[i] <= least + _TIE:
            return i
    return 0


@njit(cache=True)
def _closest_box(A, B, radius, row, pair, work, dist, ts, d2s):
    """Index of the part closest to a box and its core pair in ``pair``
    (``distance._closest_part_box``: ties to the lowest index)."""
    center = row[C_P : C_P + 3]
    half = row[C_HALF : C_HALF + 3]
    rot = row[C_ROT : C_ROT + 9].reshape((3, 3))
    r_obst = row[C_RADIUS]
    pa, u, cuts = work[0:3], work[3:6], work[6:14]
    best = math.inf
    for i in range(A.shape[0]):
        dist[i] = math.inf
        _box_frame(A[i], B[i], center, rot, pa, u)
        # lower bound (``distance._box_lower_bounds``): the gap between the part's
        # bounding box and the box; when they meet, the deepest a core can be
        gap = 0.0
        for j in range(3):
            lo = min(pa[j], pa[j] + u[j])
            hi = max(pa[j], pa[j] + u[j])
            g = max(max(lo, -hi) - half[j], 0.0)
            gap += g * g
        lower = math.sqrt(gap) if gap > 0.0 else -min(half[0], half[1], half[2])
        if lower - radius[i] > best + 1e-9:
            continue  # farther than the best found: not the closest, not a tie
        t, d2 = _segment_box_outside(pa, u, half, cuts)
        core = math.sqrt(d2) if d2 > 1e-24 else _segment_box_deepest(pa, u, half)[1]
        dist[i], ts[i], d2s[i] = core - radius[i] - r_obst, t, d2
        best = min(best, dist[i])
    i = _first_tie(dist)
    _box_frame(A[i], B[i], center, rot, pa, u)
    _box_pair(pa, u, ts[i], d2s[i], center, rot, half, pair)
    return i


@njit(cache=True)
def _closest_point(A, B, radius, row, pair, dist):
    """Point / sphere: the part of least ``‖c − p‖ − r`` (ties: the lowest index) and
    its pair."""
    c = row[C_P : C_P + 3]
    for i in range(A.shape[0]):
        dist[i] = _point_segment(A[i], B[i], c) - radius[i]
    i = _first_tie(dist)
    _segment_core(A[i], B[i], c, c, pair)
    return i


@njit(cache=True)
def _closest_plane(A, B, radius, row, pair, dist):
    """Plane: the part of least signed core distance minus radius (ties: the lowest
    index) and its pair."""
    point, normal = row[C_P : C_P + 3], row[C_Q : C_Q + 3]
    for i in range(A.shape[0]):
        _plane_core(A[i], B[i], point, normal, pair)
        dist[i] = pair[0] - radius[i]
    i = _first_tie(dist)
    _plane_core(A[i], B[i], point, normal, pair)
    return i


@njit(cache=True)
def _closest_capsule(A, B, radius, row, pair, dist):
    """Capsule: the part of least distance (ties: the lowest index); a part whose bound
    ``‖c − m‖ − reach − r`` exceeds the best distance found (+ ``_TIE``) is skipped
    (``distance._search_parts``)."""
    q0, q1, r_obst = row[C_P : C_P + 3], row[C_Q : C_Q + 3], row[C_RADIUS]
    m = np.empty(3)
    h0, h1, h2 = q1[0] - q0[0], q1[1] - q0[1], q1[2] - q0[2]
    for r in range(3):
        m[r] = 0.5 * (q0[r] + q1[r])
    reach = 0.5 * math.sqrt(h0 * h0 + h1 * h1 + h2 * h2) + r_obst
    best = math.inf
    for i in range(A.shape[0]):
        dist[i] = math.inf
        if _point_segment(A[i], B[i], m) - reach - radius[i] > best + _TIE:
            continue
        _segment_core(A[i], B[i], q0, q1, pair)
        dist[i] = pair[0] - radius[i] - r_obst
        best = min(best, dist[i])
    i = _first_tie(dist)
    _segment_core(A[i], B[i], q0, q1, pair)
    return i


@njit(cache=True)
def critical_points(frames, tcp, links, a_local, b_local, radius, fallback, obst, out):
    """One row of ``out`` per obstacle row of ``obst``: the closest part and pair
    (``distance.critical_points``) at the link ``frames`` (n+1, 4, 4) and ``tcp``."""
    k = links.shape[0]
    A = np.empty((k, 3))
    B = np.empty((k, 3))
    _world_parts(frames, tcp, links, a_local, b_local, fallback, A, B)
    pair = np.empty(10)
    work = np.empty(14)
    dist, ts, d2s = np.empty(k), np.empty(k), np.empty(k)
    for o in range(obst.shape[0]):
        row = obst[o]
        kind = int(row[C_KIND])
        if kind in (POINT, SPHERE):
            i = _closest_point(A, B, radius, row, pair, dist)
        elif kind == BOX:
            i = _closest_box(A, B, radius, row, pair, work, dist, ts, d2s)
        elif kind == PLANE:
            i = _closest_plane(A, B, radius, row, pair, dist)
        else:
            i = _closest_capsule(A, B, radius, row, pair, dist)
        _swept(pair, radius[i], row[C_RADIUS], links[i], out[o])


# ---------------------------------------------------------------------- the criterion
@njit(cache=True)
def _activation_weight(distance, far, ramp):
    """``obstacle.activation_weight``: 1 near, 0 far, smoothstep in between."""
    near = far * (1.0 - ramp)
    if distance >= far:
        return 0.0
    if distance <= near:
        return 1.0
    s = (far - distance) / (far - near)
    return s * s * (3.0 - 2.0 * s)


@njit(cache=True)
def obstacle_terms(frames, tcp, joints, links, a_local, b_local, radius, fallback, obst,
                   params, cps, ow, opush, ojac, ojtj):  # fmt: skip
    """The criterion's terms (``obstacle.obstacle_terms`` / ``ObstacleTerm``) of the
    obstacles ``obst`` closer than the activation distance, packed in their order into
    the first rows of ``ow`` (``a_obst·β(R)``), ``opush`` (``αv``, ``α = c/max(R,
    R_min)``), ``ojac`` (``J_k``: 3×n, columns from the critical point's link on zero;
    ``joints``: ``ChainData.joints``) and ``ojtj`` (``J_kᵀJ_k``). ``cps`` receives every
    obstacle's critical point. Returns the number of terms."""
    critical_points(frames, tcp, links, a_local, b_local, radius, fallback, obst, cps)
    n = joints.shape[0]
    cnt = 0
    for o in range(obst.shape[0]):
        dist = cps[o, D_DIST]
        if dist >= params[P_ACTIVATION]:
            continue
        ow[cnt] = params[P_A_OBST] * _activation_weight(dist, params[P_ACTIVATION], params[P_RAMP])
        alpha = params[P_C] / max(dist, params[P_MIN_DISTANCE])
        for r in range(3):
            opush[cnt, r] = alpha * cps[o, D_DIR + r]
        link = int(cps[o, D_LINK])
        px, py, pz = cps[o, D_ROBOT], cps[o, D_ROBOT + 1], cps[o, D_ROBOT + 2]
        jac = ojac[cnt]
        for i in range(n):
            if i >= link:
                jac[0, i] = 0.0
                jac[1, i] = 0.0
                jac[2, i] = 0.0
                continue
            f = frames[i + 1]
            kx, ky, kz = joints[i, 1], joints[i, 2], joints[i, 3]
            zx = f[0, 0] * kx + f[0, 1] * ky + f[0, 2] * kz
            zy = f[1, 0] * kx + f[1, 1] * ky + f[1, 2] * kz
            zz = f[2, 0] * kx + f[2, 1] * ky + f[2, 2] * kz
            if joints[i, 4] != 0.0:
                rx, ry, rz = px - f[0, 3], py - f[1, 3], pz - f[2, 3]
                jac[0, i] = zy * rz - zz * ry
                jac[1, i] = zz * rx - zx * rz
                jac[2, i] = zx * ry - zy * rx
            else:
                jac[0, i] = zx
                jac[1, i] = zy
                jac[2, i] = zz
        jtj = ojtj[cnt]
        for a in range(n):
            for b in range(n):
                jtj[a, b] = jac[0, a] * jac[0, b] + jac[1, a] * jac[1, b] + jac[2, a] * jac[2, b]
        cnt += 1
    return cnt
