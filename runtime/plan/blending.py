"""Approximate positioning (``WITH APPROX := d`` / ``R_APPROX := d``): the geometry and
the choice of the overlap of two consecutive segments.

**Superposition blend.** Segment A ends at the corner ``E`` (pose; joints ``θ₁`` for PTP),
segment B starts there. Both keep their own profiles; B is started ``m`` IPO cycles
before A ends, and in the ``m`` overlapping cycles ``j = 1 … m`` the setpoint is

    Cartesian:  p = p_A(k_A) + p_B(j) − p_E,   R = R_A(k_A) · R_Eᵀ · R_B(j)
    joints:     θ = θ_A(k_A) + θ_B(j) − θ₁,                      k_A = K_A − m + j.

At ``j = m`` A is at ``E`` and the setpoint is B's own; before the overlap it is A's. The
velocity is ``v_A + v_B``: continuous, and not zero at the corner unless B reverses A.
The motion saves ``m·Δt`` per corner.

**Distance.** With ``a_i = p_A(K_A − i) − p_E`` (A's remaining offset ``i`` cycles before
its end) and ``b_j = p_B(j) − p_E``, the overlap ``m`` is admissible for the limit ``d`` when

    |a_m| ≤ d  (the blend starts at most d before the point),
    |b_m| ≤ d  (and rejoins B at most d after it),
    |a_{m−j} + b_j| ≤ d  for j = 1 … m  (the blended path stays within d of the corner),

and ``d = min(APPROX, L_A/2, L_B/2)`` (``L``: the segments' path lengths; the TCP chord
for PTP) — the blend shrinks where a neighbouring segment is short. The largest
admissible ``m`` is used; for PTP (joints set directly) the blended joints must also stay
within the active position, speed and acceleration limits (finite differences on the IPO
grid), else ``m`` is shortened. Cartesian blends are followed by the inverse
transformation like every setpoint (its QP keeps every limit and option).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

Check = Callable[[int], bool]  # extra admissibility test of an overlap m
_TOL = 1e-12  # m: rounding of the distances compared with d


def blend_pose(a: np.ndarray, b: np.ndarray, corner: np.ndarray) -> np.ndarray:
    """The superposed setpoint of two 4×4 poses about the corner pose (module doc)."""
    out = np.eye(4)
    out[:3, 3] = a[:3, 3] + b[:3, 3] - corner[:3, 3]
    out[:3, :3] = a[:3, :3] @ corner[:3, :3].T @ b[:3, :3]
    return out


def blend_joints(qa: np.ndarray, qb: np.ndarray, q1: np.ndarray) -> np.ndarray:
    """The superposed joint setpoint ``θ_A + θ_B − θ₁``."""
    return qa + qb - q1


def limit_distance(approx: float, length_a: float, length_b: float) -> float:
    """``d = min(APPROX, L_A/2, L_B/2)`` (m)."""
    return max(0.0, min(approx, 0.5 * length_a, 0.5 * length_b))


def tail_cycles(remaining: Sequence[float], d: float) -> int:
    """How many final cycles of a segment lie within ``d`` of its end: ``remaining[i]``
    is the distance to the end ``i`` cycles before it (``remaining[0] = 0``); the count
    is the largest ``i`` with ``remaining[i'] ≤ d`` for all ``i' ≤ i``."""
    n = 0
    for i in range(1, len(remaining)):
        if remaining[i] > d + _TOL:
            break
        n = i
    return n


@dataclass(frozen=True)
class Overlap:
    """The chosen overlap: ``cycles`` (m), the distances where the blend leaves A and
    rejoins B, and the largest distance of the blended path from the corner (m)."""

    cycles: int
    start_distance: float
    end_distance: float
    max_distance: float

    @property
    def used(self) -> float:
        """The distance actually used at the point: where the blend leaves or rejoins
        the programmed path, whichever is farther (≤ d)."""
        return max(self.start_distance, self.end_distance)


NO_OVERLAP = Overlap(0, 0.0, 0.0, 0.0)


def choose_overlap(
    a: np.ndarray,
    b: np.ndarray,
    d: float,
    check: Check | None = None,
    *,
    superposed: bool = True,
    speed_cap: float | None = None,
    dt: float = 0.0,
) -> Overlap:
    """The largest admissible overlap (module doc). ``a[i]`` (``i = 0 … M_A``) and
    ``b[j]`` (``j = 0 … M_B``) are the TCP offsets from the corner (rows, position);
    ``check(m)`` may reject an overlap for other reasons (limits). With ``superposed``
    the blended TCP offset is ``a[m−j] + b[j]`` (Cartesian blends); otherwise (joint
    blends, whose TCP is not the sum) ``check`` measures it. ``speed_cap`` (m/s, with the
    IPO cycle ``dt``) bounds the blended TCP speed — the faster segment's programmed
    speed: superposing two cruising segments would otherwise add their speeds."""
    m_max = min(len(a), len(b)) - 1
    if d <= 0.0:
        return NO_OVERLAP
    na, nb = np.linalg.norm(a, axis=1), np.linalg.norm(b, axis=1)
    tol = _TOL
    for m in range(m_max, 0, -1):
        if na[m] > d + tol or nb[m] > d + tol:
            continue
        j = np.arange(1, m + 1)
        far = float(np.linalg.norm(a[m - j] + b[j], axis=1).max()) if superposed else 0.0
        if far > d + tol:
            continue
        if superposed and speed_cap is not None and not _speed_ok(a, b, m, speed_cap, dt):
            continue
        if check is not None and not check(m):
            continue
        return Overlap(m, float(na[m]), float(nb[m]), max(far, float(na[m])))
    return NO_OVERLAP


def _speed_ok(a: np.ndarray, b: np.ndarray, m: int, cap: float, dt: float) -> bool:
    """Finite-difference TCP speed of the blend of ``m`` cycles (one cycle either side
    included) within ``cap`` (relative tolerance 1e-6)."""
    j = np.arange(1, m + 1)
    rows = [a[m + 1]] if m + 1 < len(a) else []
    rows += [a[m], *(a[m - j] + b[j])]
    rows += [b[m + 1]] if m + 1 < len(b) else []
    speed = np.linalg.norm(np.diff(np.array(rows), axis=0), axis=1) / dt
    return bool(speed.max() <= cap * (1.0 + 1e-6))


def within_joint_limits(
    q: np.ndarray, dt: float, position: np.ndarray, speed: np.ndarray, accel: np.ndarray
) -> bool:
    """Whether the joint sequence ``q`` (rows, one per IPO cycle) stays within the position
    box and its backward differences within the speed and acceleration boxes (the
    quantities the recorder reports), with a relative tolerance of 1e-6."""
    eps = 1e-6
    lo, hi = position[:, 0], position[:, 1]
    span = np.maximum(hi - lo, 1e-9) * eps
    if np.any(q < lo - span) or np.any(q > hi + span):
        return False
    v = np.diff(q, axis=0) / dt
    if np.any(v < speed[:, 0] * (1 + eps)) or np.any(v > speed[:, 1] * (1 + eps)):
        return False
    acc = np.diff(v, axis=0) / dt
    lo_a, hi_a = accel[:, 0] * (1 + eps), accel[:, 1] * (1 + eps)
    return not (np.any(acc < lo_a) or np.any(acc > hi_a))
