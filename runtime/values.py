"""Run-time values of IRL programs, in program units (mm, deg, s), and their geometry.

The interpreter computes with these; the controller converts them to SI through
:mod:`irlc.runtime.units` at its boundary (:func:`pose_to_matrix`, :func:`pose_from_matrix`).

Geometry (all in mm and unit quaternions ``q = (w, x, y, z)``, ``w ≥ 0``):

* pose composition ``p1 : p2``:  ``R = R₁R₂``, ``t = t₁ + R₁t₂`` (p2 expressed in p1's frame),
  computed as the quaternion product ``q₁ ⊗ q₂``;
* inverse ``INV(p)``:  ``R = R₁ᵀ``, ``t = −R₁ᵀt₁``;
* ZYX angles ``(a, b, c)`` in degrees mean ``R = Rz(a)·Ry(b)·Rx(c)`` (see :mod:`spatial`);
* ``ORIRS(roll, pitch, yaw)`` = roll about the fixed X, then pitch about the fixed Y, then
  yaw about the fixed Z: ``R = Rz(yaw)·Ry(pitch)·Rx(roll)`` = ``ORIZYX(yaw, pitch, roll)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from irlc.runtime import units
from irlc.runtime.model import spatial


@dataclass(frozen=True, slots=True)
class Position:
    x: float
    y: float
    z: float

    def as_tuple(self) -> tuple[float, float, float]:
        return (self.x, self.y, self.z)


@dataclass(frozen=True, slots=True)
class Orientation:
    """A rotation as a unit quaternion ``(w, x, y, z)``."""

    w: float
    x: float
    y: float
    z: float

    def as_tuple(self) -> tuple[float, float, float, float]:
        return (self.w, self.x, self.y, self.z)


IDENTITY = Orientation(1.0, 0.0, 0.0, 0.0)


@dataclass(frozen=True, slots=True)
class Pose:
    pos: Position
    ori: Orientation


@dataclass(frozen=True, slots=True)
class JointTuple:
    """A value of MAIN_JOINT or one of the limit types: one number per joint (deg | mm)."""

    type: str  # "MAIN_JOINT", "MAIN_JOINT_MIN", ...
    values: tuple[float, ...]


@dataclass(frozen=True, slots=True)
class ArrayValue:
    """An ARRAY value; ``elem`` is the IRDATA type its items are known to have (set by the
    interpreter's :class:`~irlc.runtime.interpreter.datatypes.DataTypes`, which then stores
    the array in a cell of that type without looking at each item again)."""

    low: int
    items: tuple
    elem: str | None = field(default=None, compare=False)


@dataclass(frozen=True, slots=True)
class RecordValue:
    type_index: int
    fields: tuple[tuple[str, object], ...]


# --------------------------------------------------------------------------- positions


def position_add(a: Position, b: Position) -> Position:
    return Position(a.x + b.x, a.y + b.y, a.z + b.z)


def position_sub(a: Position, b: Position) -> Position:
    return Position(a.x - b.x, a.y - b.y, a.z - b.z)


def position_scale(s: float, p: Position) -> Position:
    return Position(s * p.x, s * p.y, s * p.z)


def distance(a: Position, b: Position) -> float:
    """Euclidean distance ``‖a − b‖`` (mm)."""
    return math.hypot(a.x - b.x, a.y - b.y, a.z - b.z)  # the squares would overflow at 1e155


# --------------------------------------------------------------------------- joint tuples


def joint_add(a: JointTuple, b: JointTuple) -> JointTuple:
    return JointTuple(a.type, tuple(x + y for x, y in zip(a.values, b.values, strict=True)))


def joint_sub(a: JointTuple, b: JointTuple) -> JointTuple:
    return JointTuple(a.type, tuple(x - y for x, y in zip(a.values, b.values, strict=True)))


def joint_scale(s: float, j: JointTuple) -> JointTuple:
    return JointTuple(j.type, tuple(s * v for v in j.values))


# --------------------------------------------------------------------------- orientations


def _orientation(q: spatial.Quat) -> Orientation:
    return Orientation(*q)


def orientation_from_quat(w: float, x: float, y: float, z: float) -> Orientation:
    """``ORIQUAT``: normalised; raises ``ValueError`` for the zero quaternion."""
    if math.sqrt(w * w + x * x + y * y + z * z) < 1e-12:
        raise ValueError("the quaternion (0, 0, 0, 0) is not a rotation")
    return _orientation(spatial.quat_unit(w, x, y, z))


def orientation_from_matrix(r: np.ndarray) -> Orientation:
    w, x, y, z = (float(v) for v in spatial.matrix_to_quat(r))
    return Orientation(w, x, y, z)


def orientation_matrix(o: Orientation) -> np.ndarray:
    return spatial.quat_to_matrix(o.as_tuple())


def orientation_from_zyx(a: float, b: float, c: float) -> Orientation:
    """``ORIZYX(a, b, c)``: ``R = Rz(a)·Ry(b)·Rx(c)``, degrees."""
    d = units.DEG
    return orientation_from_matrix(spatial.zyx_to_matrix(a * d, b * d, c * d))


def orientation_from_xyz(a: float, b: float, c: float) -> Orientation:
    """``ORIXYZ(a, b, c)``: ``R = Rx(a)·Ry(b)·Rz(c)``, degrees."""
    d = units.DEG
    return orientation_from_matrix(spatial.xyz_to_matrix(a * d, b * d, c * d))


def orientation_from_zyz(a: float, b: float, c: float) -> Orientation:
    """``ORIZYZ(a, b, c)``: ``R = Rz(a)·Ry(b)·Rz(c)``, degrees (Euler ZYZ)."""
    d = units.DEG
    return orientation_from_matrix(spatial.zyz_to_matrix(a * d, b * d, c * d))


def orientation_from_rpy(roll: float, pitch: float, yaw: float) -> Orientation:
    """``ORIRS(roll, pitch, yaw)``: fixed axes X, Y, Z in turn = ``ORIZYX(yaw, pitch, roll)``."""
    return orientation_from_zyx(yaw, pitch, roll)


def orientation_from_axis_angle(axis: Position, angle: float) -> Orientation:
    """``ORIVANG(axis, angle)``: rotation by ``angle`` degrees about ``axis`` (any length > 0)."""
    n = math.hypot(axis.x, axis.y, axis.z)
    if n < 1e-12:
        raise ValueError("the rotation axis (0, 0, 0) has no direction")
    return _orientation(spatial.quat_from_axis_angle(axis.as_tuple(), angle * units.DEG))


def orientation_to_zyx(o: Orientation) -> tuple[float, float, float]:
    """ZYX angles ``(a, b, c)`` in degrees (``c = 0`` at the singularity ``b = ±90°``)."""
    a, b, c = spatial.matrix_to_zyx(orientation_matrix(o))
    return (a / units.DEG, b / units.DEG, c / units.DEG)


def quat_multiply(p: Orientation, q: Orientation) -> Orientation:
    """Hamilton product ``p ⊗ q`` (the rotation ``R_p·R_q``), normalised, ``w ≥ 0``."""
    return _orientation(spatial.quat_multiply(p.as_tuple(), q.as_tuple()))


def orientation_inverse(o: Orientation) -> Orientation:
    return _orientation(spatial.quat_conjugate(o.as_tuple()))


def rotate(o: Orientation, v: Position) -> Position:
    """``R(o) · v`` (:func:`irlc.runtime.model.spatial.quat_rotate`)."""
    return Position(*spatial.quat_rotate(o.as_tuple(), v.as_tuple()))


# --------------------------------------------------------------------------- poses


def pose_from_zyx(x: float, y: float, z: float, a: float, b: float, c: float) -> Pose:
    """The 6-tuple ``(x, y, z, a, b, c)``: mm and ZYX degrees."""
    return Pose(Position(float(x), float(y), float(z)), orientation_from_zyx(a, b, c))


def pose_to_zyx(p: Pose) -> tuple[float, float, float, float, float, float]:
    return (p.pos.x, p.pos.y, p.pos.z, *orientation_to_zyx(p.ori))


def compose(p1: Pose, p2: Pose) -> Pose:
    """``p1 : p2`` — the frame product ``T₁·T₂``."""
    return Pose(position_add(p1.pos, rotate(p1.ori, p2.pos)), quat_multiply(p1.ori, p2.ori))


def transform_point(p: Pose, v: Position) -> Position:
    """``p : v`` — the point ``v`` given in frame ``p``, expressed in p's parent frame."""
    return position_add(p.pos, rotate(p.ori, v))


def inverse(p: Pose) -> Pose:
    """``INV(p)`` — ``T⁻¹``."""
    qi = orientation_inverse(p.ori)
    return Pose(position_scale(-1.0, rotate(qi, p.pos)), qi)


def pose_to_matrix(p: Pose) -> np.ndarray:
    """4×4 homogeneous transform in metres (the SI boundary, with :mod:`units`' factors)."""
    mm = units.MM
    return spatial.transform(
        spatial.quat_to_matrix(p.ori.as_tuple()), (p.pos.x * mm, p.pos.y * mm, p.pos.z * mm)
    )


def pose_from_matrix(t: np.ndarray) -> Pose:
    """Inverse of :func:`pose_to_matrix`: 4×4 in metres → pose (mm, quaternion)."""
    x, y, z = (float(v) / units.MM for v in t[:3, 3])
    w, qx, qy, qz = (float(v) for v in spatial.matrix_to_quat(t[:3, :3]))
    return Pose(Position(x, y, z), Orientation(w, qx, qy, qz))


# --------------------------------------------------------------------------- equality

GEOMETRY_TOLERANCE = 1e-9  # mm / quaternion component, for EQ and NE of geometric values


def geometric_equal(a: object, b: object) -> bool:
    """``=`` for POSITION, ORIENTATION, POSE and joint tuples (``q`` and ``−q`` are equal)."""
    tol = GEOMETRY_TOLERANCE
    if isinstance(a, Position) and isinstance(b, Position):
        return all(abs(u - v) <= tol for u, v in zip(a.as_tuple(), b.as_tuple(), strict=True))
    if isinstance(a, Orientation) and isinstance(b, Orientation):
        qa, qb = a.as_tuple(), b.as_tuple()
        return all(abs(u - v) <= tol for u, v in zip(qa, qb, strict=True)) or all(
            abs(u + v) <= tol for u, v in zip(qa, qb, strict=True)
        )
    if isinstance(a, Pose) and isinstance(b, Pose):
        return geometric_equal(a.pos, b.pos) and geometric_equal(a.ori, b.ori)
    if isinstance(a, JointTuple) and isinstance(b, JointTuple):
        return len(a.values) == len(b.values) and all(
            abs(u - v) <= tol for u, v in zip(a.values, b.values, strict=True)
        )
    return False


# --------------------------------------------------------------------------- names and text


def type_name(v: object) -> str:
    """The IRL type name of a run-time value, for messages."""
    if isinstance(v, bool):
        return "BOOLEAN"
    if isinstance(v, int):
        return "INTEGER"
    if isinstance(v, float):
        return "REAL"
    if isinstance(v, str):
        return "CHAR" if len(v) == 1 else "STRING"
    if isinstance(v, JointTuple):
        return v.type
    if isinstance(v, ArrayValue):
        return f"ARRAY[{v.low}..{v.low + len(v.items) - 1}]"
    if isinstance(v, RecordValue):
        return "RECORD"
    return {Position: "POSITION", Orientation: "ORIENTATION", Pose: "POSE"}.get(
        type(v), type(v).__name__
    )


def format_real(x: float) -> str:
    """A REAL for WRITE: rounded to 6 decimals, shortest form, ``2000.0`` keeps its ``.0``."""
    r = round(x, 6)
    if r == 0.0:
        return "0.0"
    return repr(r)


def _seq(items) -> str:
    return "(" + ", ".join(items) + ")"


_REAL_TEXT = 24  # the longest format_real: repr of a float, e.g. -1.7976931348623157e+308
_INTEGER_TEXT = 20  # the longest 64-bit integer, -9223372036854775808


def text_bound(v: object) -> int:
    """An upper bound of ``len(format_value(v))`` without building the text: the reals
    of a value count :data:`_REAL_TEXT` characters each (O(elements), strings by length).
    """
    if isinstance(v, bool):
        return 5
    if isinstance(v, int):
        return _INTEGER_TEXT
    if isinstance(v, float):
        return _REAL_TEXT
    if isinstance(v, str):
        return len(v)
    if isinstance(v, Position | Pose | JointTuple | Orientation):
        n = len(v.values) if isinstance(v, JointTuple) else 6
        return 6 + n * (_REAL_TEXT + 2)
    if isinstance(v, ArrayValue):
        return 2 + sum(text_bound(item) + 2 for item in v.items)
    if isinstance(v, RecordValue):
        return 2 + sum(len(name) + 4 + text_bound(item) for name, item in v.fields)
    return len(str(v))


def format_value(v: object) -> str:
    """Text of a value for WRITE / WRITELN (see docs/interpreter.md)."""
    if isinstance(v, bool):
        return "TRUE" if v else "FALSE"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return format_real(v)
    if isinstance(v, str):
        return v
    if isinstance(v, Position):
        return _seq(format_real(c) for c in v.as_tuple())
    if isinstance(v, Orientation):
        return "ORIZYX" + _seq(format_real(c) for c in orientation_to_zyx(v))
    if isinstance(v, Pose):
        return _seq(format_real(c) for c in pose_to_zyx(v))
    if isinstance(v, JointTuple):
        return _seq(format_real(c) for c in v.values)
    if isinstance(v, ArrayValue):
        return _seq(format_value(item) for item in v.items)
    if isinstance(v, RecordValue):
        return _seq(f"{name}: {format_value(item)}" for name, item in v.fields)
    return str(v)
