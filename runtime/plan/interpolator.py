"""The interpolator: desired setpoints every IPO cycle Δt from profiled segments.

A :class:`Segment` (made by :mod:`~irlc.runtime.plan.preinterp`) is a geometric path
``x(s)``, ``s ∈ [0, 1]``, and a time-scaling profile ``s(t)``
(:mod:`~irlc.runtime.plan.profiles`) whose duration is a whole number ``K`` of IPO cycles.
Cycle ``k = 1 … K`` of the segment asks for ``x(s(k·Δt))`` — the last cycle lands exactly
on the target. Paths (world frame, SI):

* :class:`JointLine` (PTP): ``θ(s) = θ₀ + s·(θ₁ − θ₀)`` — synchronised joints;
* :class:`CartesianLine` (LIN): ``p(s) = p₀ + s·(p₁ − p₀)``, orientation
  ``slerp(q₀, q₁, s)`` (quaternions, shorter arc);
* :class:`CartesianArc` (CIRCLE): the circle through start, via and target,
  ``p(s) = c + r·(cos(sφ)·u + sin(sφ)·v)`` with ``u = (p₀ − c)/r``, ``v`` in the plane
  towards the via, ``φ`` the swept angle; orientation slerp start → target;
* :class:`Hold` (WAIT, RECONFIGURATION): a constant pose;
* :class:`PlatformLine` (WITH PLATFORM): the platform's own straight line in step with the
  segment's ``s`` (:mod:`~irlc.runtime.plan.platform_path`).

The reference configuration θ⁰ for WITH RECONFIGURATION is a :class:`ReferencePath`,
piecewise linear in ``s`` between configurations given at knots (start, via/points).
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass

import numpy as np
from irlc.lang.errors import IrlcError
from irlc.runtime.model import spatial
from irlc.runtime.plan.profiles import Trapezoid
from irlc.runtime.plan.scurve import SCurve


@dataclass(frozen=True)
class JointLine:
    q0: np.ndarray
    q1: np.ndarray

    def at(self, s: float) -> np.ndarray:
        return self.q0 + s * (self.q1 - self.q0)


@dataclass(frozen=True)
class CartesianLine:
    start: np.ndarray  # 4×4
    end: np.ndarray

    def __post_init__(self) -> None:
        object.__setattr__(self, "_q0", spatial.matrix_to_quat(self.start[:3, :3]))
        object.__setattr__(self, "_q1", spatial.matrix_to_quat(self.end[:3, :3]))
        object.__setattr__(self, "_slerp", Slerp(self._q0, self._q1))
        p0 = self.start[:3, 3]
        object.__setattr__(self, "_p0", p0.tolist())
        object.__setattr__(self, "_dp", (self.end[:3, 3] - p0).tolist())

    @property
    def length(self) -> float:
        return float(np.linalg.norm(self.end[:3, 3] - self.start[:3, 3]))

    @property
    def angle(self) -> float:
        return spatial.quat_angle(self._q0, self._q1)

    def at(self, s: float) -> np.ndarray:
        (x0, y0, z0), (dx, dy, dz) = self._p0, self._dp
        return _pose(self._slerp.rows(s), x0 + s * dx, y0 + s * dy, z0 + s * dz)


class Slerp:
    """``quat_to_matrix(slerp(q0, q1, s))`` of :mod:`spatial` for one segment, with the
    per-segment constants (shorter-arc sign, angle, ``sin θ``) computed once and the
    per-cycle part on Python floats — the same operations in the same order, so the
    result equals the :mod:`spatial` composition bit for bit (tested)."""

    def __init__(self, q0: np.ndarray, q1: np.ndarray):
        q0 = np.asarray(q0, dtype=float)
        q1 = np.asarray(q1, dtype=float)
        d = float(np.dot(q0, q1))
        if d < 0.0:
            q1, d = -q1, -d
        self.linear = d > 1.0 - 1e-12  # nearly equal: normalised linear interpolation
        self.q0, self.q1 = q0.tolist(), q1.tolist()
        self.dq = (q1 - q0).tolist()
        self.theta = 0.0 if self.linear else math.acos(min(1.0, d))
        self.sin_theta = math.sin(self.theta)

    def quat(self, s: float) -> list[float]:
        """``spatial.slerp(q0, q1, s)`` as four floats."""
        q0 = self.q0
        if self.linear:
            dq = self.dq
            q = [q0[0] + s * dq[0], q0[1] + s * dq[1], q0[2] + s * dq[2], q0[3] + s * dq[3]]
            return _normalised(q)
        q1, st = self.q1, self.sin_theta
        a, b = math.sin((1.0 - s) * self.theta), math.sin(s * self.theta)
        return [
            (a * q0[0] + b * q1[0]) / st,
            (a * q0[1] + b * q1[1]) / st,
            (a * q0[2] + b * q1[2]) / st,
            (a * q0[3] + b * q1[3]) / st,
        ]

    def rows(self, s: float) -> tuple[list[float], list[float], list[float]]:
        """Rows of ``spatial.quat_to_matrix(self.quat(s))``."""
        w, x, y, z = _normalised(self.quat(s))
        return (
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        )


def _normalised(q: list[float]) -> list[float]:
    """``q / np.linalg.norm(q)`` (the same norm: ``sqrt(q·q)`` by numpy's dot)."""
    v = np.array(q)
    n = math.sqrt(v.dot(v))
    return [q[0] / n, q[1] / n, q[2] / n, q[3] / n]


def _pose(rows, x: float, y: float, z: float) -> np.ndarray:
    """4×4 pose from rotation rows and a position, in one array construction."""
    r0, r1, r2 = rows
    return np.array(
        [
            [r0[0], r0[1], r0[2], x],
            [r1[0], r1[1], r1[2], y],
            [r2[0], r2[1], r2[2], z],
            [0.0, 0.0, 0.0, 1.0],
        ]
    )


class CircleError(IrlcError, ValueError):
    """Start, via and target do not define a circle."""


@dataclass(frozen=True)
class CartesianArc:
    start: np.ndarray  # 4×4
    via: np.ndarray  # 3-vector (only the position of the via point matters)
    end: np.ndarray  # 4×4

    def __post_init__(self) -> None:
        p0, p1, p2 = self.start[:3, 3], np.asarray(self.via, dtype=float), self.end[:3, 3]
        centre, radius, u, v, phi, phi_via = _circle(p0, p1, p2)
        for k, val in (
            ("centre", centre),
            ("radius", radius),
            ("u", u),
            ("v", v),
            ("phi", phi),
            ("phi_via", phi_via),
        ):
            object.__setattr__(self, "_" + k, val)
        object.__setattr__(self, "_q0", spatial.matrix_to_quat(self.start[:3, :3]))
        object.__setattr__(self, "_q1", spatial.matrix_to_quat(self.end[:3, :3]))
        object.__setattr__(self, "_slerp", Slerp(self._q0, self._q1))
        basis = (centre.tolist(), u.tolist(), v.tolist())
        object.__setattr__(self, "_basis", basis)

    @property
    def length(self) -> float:
        return self._radius * self._phi

    @property
    def angle(self) -> float:
        return spatial.quat_angle(self._q0, self._q1)

    @property
    def via_fraction(self) -> float:
        """``s`` at which the arc passes the via point."""
        return self._phi_via / self._phi

    def position(self, s: float) -> np.ndarray:
        a = s * self._phi
        return self._centre + self._radius * (np.cos(a) * self._u + np.sin(a) * self._v)

    def at(self, s: float) -> np.ndarray:
        a = s * self._phi
        (cx, cy, cz), u, v = self._basis
        ca, sa, r = math.cos(a), math.sin(a), self._radius
        return _pose(
            self._slerp.rows(s),
            cx + r * (ca * u[0] + sa * v[0]),
            cy + r * (ca * u[1] + sa * v[1]),
            cz + r * (ca * u[2] + sa * v[2]),
        )


def _circle(p0: np.ndarray, p1: np.ndarray, p2: np.ndarray):
    """Centre, radius, in-plane unit vectors ``u`` (to p0) and ``v`` (90° towards the
    sense p0 → p1 → p2), swept angle to p2 and angle to p1."""
    a, b = p1 - p0, p2 - p0
    normal = np.cross(a, b)
    nn = float(np.dot(normal, normal))
    scale = max(float(np.dot(a, a)), float(np.dot(b, b)), 1e-300)
    if nn <= 1e-18 * scale * scale:
        raise CircleError("start, via and target are collinear (or coincide): no circle")
    # circumcentre relative to p0
    rel = (np.dot(a, a) * np.cross(b, normal) + np.dot(b, b) * np.cross(normal, a)) / (2.0 * nn)
    centre = p0 + rel
    radius = float(np.linalg.norm(rel))
    u = -rel / radius
    n_hat = normal / np.sqrt(nn)
    v = np.cross(n_hat, u)

    def angle_of(p: np.ndarray) -> float:
        d = p - centre
        ang = float(np.arctan2(np.dot(d, v), np.dot(d, u)))
        return ang if ang > 0.0 else ang + 2.0 * np.pi

    return centre, radius, u, v, angle_of(p2), angle_of(p1)


@dataclass(frozen=True)
class Hold:
    pose: np.ndarray  # 4×4

    def at(self, s: float) -> np.ndarray:
        return self.pose


@dataclass(frozen=True)
class PlatformLine:
    """The platform's path on one segment: ``x_platform(s) = start + s·(end − start)``
    (its coordinates, m); ``start_fraction``, ``end_fraction``: where the segment starts
    and ends on the statement's whole line (0 … 1)."""

    start: np.ndarray
    end: np.ndarray
    start_fraction: float = 0.0
    end_fraction: float = 1.0

    def at(self, s: float) -> np.ndarray:
        return self.start + s * (self.end - self.start)

    def fraction(self, s: float) -> float:
        """How far along the statement's line the platform is at ``s`` of this segment."""
        return self.start_fraction + s * (self.end_fraction - self.start_fraction)


@dataclass(frozen=True)
class ReferencePath:
    """θ⁰(s): linear between ``configs[i]`` at knots ``knots[i]`` (``0 = knots[0] <
    … ≤ 1``); constant after the last knot."""

    knots: np.ndarray
    configs: np.ndarray  # (len(knots), n)

    def __post_init__(self) -> None:  # per-piece constants for the per-cycle lookup
        object.__setattr__(self, "_knots", [float(k) for k in self.knots])
        object.__setattr__(self, "_steps", np.diff(self.configs, axis=0))

    def at(self, s: float) -> np.ndarray:
        k = self._knots
        i = bisect.bisect_right(k, s) - 1
        if i >= len(k) - 1:
            return self.configs[-1]
        i = max(i, 0)
        w = (s - k[i]) / (k[i + 1] - k[i]) if k[i + 1] > k[i] else 1.0
        return self.configs[i] + w * self._steps[i]


@dataclass
class JointPeaks:
    """A PTP segment's peak speed and acceleration of each joint (``(n,)`` SI, ≥ 0: the
    profile's cruise speed and acceleration times the joint's travel), for the report's
    limit activity (:mod:`~irlc.runtime.control.ptp_activity`, which caches in
    ``at_bounds`` the joints at their bounds)."""

    speed: np.ndarray
    accel: np.ndarray
    at_bounds: tuple | None = None


@dataclass
class Segment:
    """One profiled piece of motion; ``kind`` is ``ptp``, ``lin``, ``circle``,
    ``reconf`` or ``wait``. Limits are ``(n, 2)`` SI arrays (program ∩ robot).
    ``peaks``: a PTP segment's joint peaks; ``override``: the factor
    ``k = R_OVERRIDE/100`` it was planned with (a failure's suggested speeds are values to
    program: ik.cause); ``with_time_s``: the statement's WITH TIME as written (a failure
    suggests a longer one); ``platform``: the platform's own line of ``WITH PLATFORM``
    (:mod:`~irlc.runtime.plan.platform_path`), ``None`` without it."""

    kind: str
    line: int
    path: JointLine | CartesianLine | CartesianArc | Hold
    profile: Trapezoid | SCurve
    cycles: int
    limits: tuple[np.ndarray, np.ndarray, np.ndarray]
    reference: ReferencePath | None = None
    limiting: str = ""  # what set the segment's time (for reports)
    limiting_joint: int = -1  # PTP: the joint whose bound sets the time
    peaks: JointPeaks | None = None
    override: float = 1.0
    with_time_s: float | None = None  # a path segment's WITH TIME as written (ik.cause)
    platform: PlatformLine | None = None  # WITH PLATFORM: the platform's x_platform(s)

    @property
    def duration(self) -> float:
        return self.profile.duration

    @property
    def is_joint(self) -> bool:
        return isinstance(self.path, JointLine)

    def setpoint(self, k: int, dt: float) -> tuple[float, np.ndarray]:
        """``(s, desired)`` for cycle ``k`` (1-based) of the segment: joints for PTP, the
        world TCP pose (4×4) otherwise."""
        s = 1.0 if k >= self.cycles else self.profile.at(k * dt)
        return s, self.path.at(s)
