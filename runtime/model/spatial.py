"""Spatial math in SI: homogeneous transforms, rotations, ZYX angles, unit quaternions.

Conventions (fixed by the spec):

* A pose is a 4×4 homogeneous transform ``T = [[R, p], [0, 1]]``, metres.
* ZYX angles ``(a, b, c)`` mean ``R = Rz(a) · Ry(b) · Rx(c)`` (KUKA's A, B, C).
* Z-Y-Z Euler angles ``(Φ, Θ, Ψ)`` (Szkodny's convention) mean ``R = Rz(Φ) · Ry(Θ) · Rz(Ψ)``;
  :data:`EULER` maps a convention's name to its pair of conversions.
* Quaternions are ``(w, x, y, z)`` with ``w ≥ 0`` after normalisation. The algebra on
  them (:func:`quat_unit`, :func:`quat_multiply`, :func:`quat_conjugate`,
  :func:`quat_rotate`, :func:`quat_from_axis_angle`) works on plain float 4-tuples: the
  interpreter's ORIENTATION values (:mod:`irlc.runtime.values`) call it per operation.
* The orientation error of ``R`` against a desired ``R_d`` is the rotation vector
  ``log(R · R_dᵀ)`` expressed in the world frame, so that for a small joint step
  ``e ≈ J_ω Δθ`` with ``J_ω`` the angular rows of the geometric Jacobian.
"""

from __future__ import annotations

import math

import numpy as np

Vec = np.ndarray
Mat = np.ndarray


def rot_x(angle: float) -> Mat:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rot_y(angle: float) -> Mat:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rot_z(angle: float) -> Mat:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def transform(rotation: Mat | None = None, translation=(0.0, 0.0, 0.0)) -> Mat:
    """Homogeneous transform from a rotation matrix and a translation."""
    t = np.eye(4)
    if rotation is not None:
        t[:3, :3] = rotation
    t[:3, 3] = translation
    return t


def inverse(t: Mat) -> Mat:
    """Inverse of a rigid transform (no general matrix inversion)."""
    out = np.eye(4)
    rt = t[:3, :3].T
    out[:3, :3] = rt
    out[:3, 3] = -rt @ t[:3, 3]
    return out


def axis_angle(axis: Vec, angle: float) -> Mat:
    """Rotation matrix about a unit ``axis`` by ``angle`` (Rodrigues)."""
    x, y, z = axis
    c, s = math.cos(angle), math.sin(angle)
    v = 1.0 - c
    return np.array(
        [
            [c + x * x * v, x * y * v - z * s, x * z * v + y * s],
            [y * x * v + z * s, c + y * y * v, y * z * v - x * s],
            [z * x * v - y * s, z * y * v + x * s, c + z * z * v],
        ]
    )


def zyx_to_matrix(a: float, b: float, c: float) -> Mat:
    """``R = Rz(a) · Ry(b) · Rx(c)`` (angles in radians)."""
    return rot_z(a) @ rot_y(b) @ rot_x(c)


HALF_TURN_SNAP = 1e-12  # rad: an angle this close above −π is taken as +π


def half_open(angle: float) -> float:
    """``angle`` (from ``atan2``, in [−π, π]) in (−π, π]: a half turn is +π, also when
    round-off puts it just above −π — the sign of a 1e-17 matrix entry made a constant
    c = 180° flip between +180° and −180° from one sample to the next."""
    return math.pi if angle <= -math.pi + HALF_TURN_SNAP else angle


def matrix_to_zyx(r: Mat) -> tuple[float, float, float]:
    """Inverse of :func:`zyx_to_matrix` (``a``, ``c`` in (−π, π], :func:`half_open`); at the
    singularity ``b = ±90°`` it sets ``c = 0``."""
    sb = -r[2, 0]
    sb = max(-1.0, min(1.0, sb))
    b = math.asin(sb)
    if abs(sb) < 1.0 - 1e-12:
        a = math.atan2(r[1, 0], r[0, 0])
        c = math.atan2(r[2, 1], r[2, 2])
    else:  # gimbal lock: only a - c (or a + c) is defined
        c = 0.0
        a = math.atan2(-r[0, 1], r[1, 1])
    return half_open(a), b, half_open(c)


def xyz_to_matrix(a: float, b: float, c: float) -> Mat:
    """``R = Rx(a) · Ry(b) · Rz(c)``."""
    return rot_x(a) @ rot_y(b) @ rot_z(c)


def zyz_to_matrix(a: float, b: float, c: float) -> Mat:
    """``R = Rz(a) · Ry(b) · Rz(c)`` (Euler ZYZ)."""
    return rot_z(a) @ rot_y(b) @ rot_z(c)


def matrix_to_zyz(r: Mat) -> tuple[float, float, float]:
    """Inverse of :func:`zyz_to_matrix` with ``Θ ∈ [0, π]``::

        Θ = atan2(√(r13² + r23²), r33),  Φ = atan2(r23, r13),  Ψ = atan2(r32, −r31)

    At the singularity ``Θ = 0`` (``Θ = π``) only ``Φ + Ψ`` (``Φ − Ψ``) is defined: ``Ψ = 0``
    and ``Φ = atan2(r21, r11)`` (``atan2(−r21, −r11)``)."""
    sin_b = math.hypot(r[0, 2], r[1, 2])
    b = math.atan2(sin_b, r[2, 2])
    if sin_b > 1e-12:
        return (
            half_open(math.atan2(r[1, 2], r[0, 2])),
            b,
            half_open(math.atan2(r[2, 1], -r[2, 0])),
        )
    if r[2, 2] > 0.0:
        return half_open(math.atan2(r[1, 0], r[0, 0])), 0.0, 0.0
    return half_open(math.atan2(-r[1, 0], -r[0, 0])), math.pi, 0.0


# convention name → (angles → matrix, matrix → angles), radians
EULER = {
    "zyx": (zyx_to_matrix, matrix_to_zyx),
    "zyz": (zyz_to_matrix, matrix_to_zyz),
}


def quat_to_matrix(q: Vec) -> Mat:
    w, x, y, z = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def matrix_to_quat(r: Mat) -> Vec:
    """Unit quaternion ``(w, x, y, z)`` with ``w ≥ 0`` (Shepperd's method)."""
    tr = r[0, 0] + r[1, 1] + r[2, 2]
    if tr > 0.0:
        s = 2.0 * math.sqrt(tr + 1.0)
        q = [0.25 * s, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s]
    elif r[0, 0] > r[1, 1] and r[0, 0] > r[2, 2]:
        s = 2.0 * math.sqrt(1.0 + r[0, 0] - r[1, 1] - r[2, 2])
        q = [(r[2, 1] - r[1, 2]) / s, 0.25 * s, (r[0, 1] + r[1, 0]) / s, (r[0, 2] + r[2, 0]) / s]
    elif r[1, 1] > r[2, 2]:
        s = 2.0 * math.sqrt(1.0 + r[1, 1] - r[0, 0] - r[2, 2])
        q = [(r[0, 2] - r[2, 0]) / s, (r[0, 1] + r[1, 0]) / s, 0.25 * s, (r[1, 2] + r[2, 1]) / s]
    else:
        s = 2.0 * math.sqrt(1.0 + r[2, 2] - r[0, 0] - r[1, 1])
        q = [(r[1, 0] - r[0, 1]) / s, (r[0, 2] + r[2, 0]) / s, (r[1, 2] + r[2, 1]) / s, 0.25 * s]
    qa = np.array(q)
    qa /= np.linalg.norm(qa)
    return -qa if qa[0] < 0.0 else qa


Quat = tuple[float, float, float, float]


def quat_unit(w: float, x: float, y: float, z: float) -> Quat:
    """``q / ‖q‖`` with the sign chosen so that ``w ≥ 0``; the caller guarantees ``q ≠ 0``."""
    n = math.hypot(w, x, y, z)  # no overflow or underflow of the squares (1e300, 1e-300)
    if w < 0.0:
        n = -n
    return (w / n, x / n, y / n, z / n)


def quat_multiply(p: Quat, q: Quat) -> Quat:
    """Hamilton product ``p ⊗ q`` (the rotation ``R_p·R_q``), normalised, ``w ≥ 0``."""
    pw, px, py, pz = p
    qw, qx, qy, qz = q
    return quat_unit(
        pw * qw - px * qx - py * qy - pz * qz,
        pw * qx + px * qw + py * qz - pz * qy,
        pw * qy - px * qz + py * qw + pz * qx,
        pw * qz + px * qy - py * qx + pz * qw,
    )


def quat_conjugate(q: Quat) -> Quat:
    """``q* = (w, −x, −y, −z)``: the inverse rotation of a unit quaternion."""
    return (q[0], -q[1], -q[2], -q[3])


def quat_rotate(q: Quat, v: tuple[float, float, float]) -> tuple[float, float, float]:
    """``R(q) · v`` for a unit ``q``: ``v' = v + 2w(u×v) + 2u×(u×v)``, ``u`` the vector part."""
    w, ux, uy, uz = q
    vx, vy, vz = v
    tx = 2.0 * (uy * vz - uz * vy)
    ty = 2.0 * (uz * vx - ux * vz)
    tz = 2.0 * (ux * vy - uy * vx)
    return (
        vx + w * tx + (uy * tz - uz * ty),
        vy + w * ty + (uz * tx - ux * tz),
        vz + w * tz + (ux * ty - uy * tx),
    )


def quat_from_axis_angle(axis: tuple[float, float, float], angle: float) -> Quat:
    """The rotation by ``angle`` (rad) about ``axis`` (any length > 0, the caller's check):
    ``(cos(θ/2), sin(θ/2)·axis/‖axis‖)``, ``w ≥ 0``."""
    x, y, z = axis
    n = math.hypot(x, y, z)
    h = 0.5 * angle
    s = math.sin(h) / n
    return quat_unit(math.cos(h), x * s, y * s, z * s)


def slerp(q0: Vec, q1: Vec, s: float) -> Vec:
    """Spherical linear interpolation along the shorter arc, ``s ∈ [0, 1]``."""
    q0 = np.asarray(q0, dtype=float)
    q1 = np.asarray(q1, dtype=float)
    d = float(np.dot(q0, q1))
    if d < 0.0:
        q1, d = -q1, -d
    if d > 1.0 - 1e-12:
        q = q0 + s * (q1 - q0)
        return q / np.linalg.norm(q)
    theta = math.acos(min(1.0, d))
    st = math.sin(theta)
    return (math.sin((1.0 - s) * theta) * q0 + math.sin(s * theta) * q1) / st


def quat_angle(q0: Vec, q1: Vec) -> float:
    """Angle (rad) of the rotation between two unit quaternions."""
    d = abs(float(np.dot(q0, q1)))
    return 2.0 * math.acos(min(1.0, d))


def rotation_vector(r: Mat) -> Vec:
    """``log(R)`` as a rotation vector (axis · angle), robust near 0 and π."""
    cos_t = max(-1.0, min(1.0, (r[0, 0] + r[1, 1] + r[2, 2] - 1.0) / 2.0))
    theta = math.acos(cos_t)
    w = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])
    if theta < 1e-6:
        return 0.5 * w
    if math.pi - theta > 1e-4:
        return theta / (2.0 * math.sin(theta)) * w
    # near π: axis from the symmetric part
    b = (r + np.eye(3)) / 2.0
    axis = np.sqrt(np.clip(np.diag(b), 0.0, None))
    k = int(np.argmax(axis))
    axis = b[:, k] / math.sqrt(b[k, k])
    if np.dot(axis, w) < 0.0:
        axis = -axis
    return theta * axis / np.linalg.norm(axis)


def pose_error(t: Mat, t_desired: Mat) -> Vec:
    """6-vector ``f(θ) ⊖ x``: position error then the world-frame rotation vector of
    ``R · R_dᵀ``. Zero when ``t == t_desired``."""
    e = np.empty(6)
    e[:3] = t[:3, 3] - t_desired[:3, 3]
    e[3:] = rotation_vector(t[:3, :3] @ t_desired[:3, :3].T)
    return e
