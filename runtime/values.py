"""Run-time values of IRL programs, in program units (mm, deg, s).

The interpreter computes with these; the controller converts them to SI through
:mod:`irlc.runtime.units` at its boundary.
"""

from __future__ import annotations

from dataclasses import dataclass


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
    low: int
    items: tuple


@dataclass(frozen=True, slots=True)
class RecordValue:
    type_index: int
    fields: tuple[tuple[str, object], ...]
