"""The platform task in the language: ``MOVE LIN p WITH PLATFORM := q;`` (docs/language.md §7).

A robot whose file names a platform (``[platform]``, docs/robots.md) has ``k`` platform
coordinates (a track: 1, mobile8's base: x and y), in mm in the robot's world frame. A
motion ``WITH PLATFORM := q`` moves the platform along its own straight line from where it
is to ``q`` in step with the TCP's path (the runtime's platform task). ``q`` has the
platform's shape (:func:`target_type`): a REAL for one coordinate, a tuple of ``k`` numbers
or an ``ARRAY [1..k] OF REAL`` (a variable, a data list's ``[platform]`` entry) for more.

The IRDATA clause is the word ``PLATFORM`` with one operand on the stack, that REAL or
ARRAY (docs/irdata.md). What the checker asks of the robot is its
:class:`PlatformSignature` (:func:`platform_of`; ``irlc.robots.platform.Platform`` is one):
its coordinates and the one limit check of a target (:meth:`PlatformSignature.problem`,
which the runtime uses too).
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Protocol, runtime_checkable

from irlc.lang import types as T
from irlc.lang.irdata_model import Value

WORD = "PLATFORM"
"""The WITH word (``WITH PLATFORM := q``) and the IRDATA MOVE clause word."""

MAX_COORDINATES = 3
"""A platform sets at most x, y and z (docs/robots.md)."""
_CONSTANT_TYPE = re.compile(r"ARRAY\[1\.\.([1-3])\]OFREAL")

MEANING = (
    "**WITH PLATFORM** := q — the robot's platform (its file's [platform]) moves along its "
    "own straight line from where it is to q, in step with the TCP's path (the same "
    "fraction of the way at every cycle); the arm's joints take the rest. q in mm: a "
    "number for one coordinate (a track), a tuple or an ARRAY [1..k] OF REAL for more "
    "(mobile8: (x, y)). LIN, LIN PATH, CIRCLE, MOVE_INC LIN, and PTP to a POSE; not "
    "blended (exact stops)."
)
"""What the clause does, in words (editors' hover)."""

SETTING = "R_PLATFORM"
"""The modal setting (a row of lang/settings.py): 'FREE' or 'HOLD' outside WITH PLATFORM."""


@runtime_checkable
class PlatformSignature(Protocol):
    """What the checker knows of a robot's platform."""

    @property
    def coordinates(self) -> Sequence[str]:
        """The world coordinates a target sets: ``("x", "y")``, ``("y",)``."""
        ...

    @property
    def joints(self) -> Sequence[int]:
        """The platform's joints (0-based indices of the robot's joints)."""
        ...

    def problem(
        self, target_mm: Sequence[float], labels: Sequence[str] | None = None
    ) -> str | None:
        """Why the platform cannot be at ``target_mm`` (one value per coordinate, mm) —
        outside its limits —, else ``None``; ``labels``: the platform joints as a message
        names them."""
        ...


def platform_of(robot: object) -> PlatformSignature | None:
    """The platform of a robot signature (``None``: the robot has none)."""
    platform = getattr(robot, "platform", None)
    return platform if isinstance(platform, PlatformSignature) else None


def target_type(dimension: int) -> T.Type:
    """The type of a platform target: REAL for one coordinate, else ARRAY [1..k] OF REAL."""
    return T.REAL if dimension == 1 else T.Array("ARRAY", 1, dimension, T.REAL)


def constant(values: Sequence[float]) -> Value:
    """A platform target as a constant of the code (a data list's ``[platform]`` entry):
    ``REAL x`` for one coordinate, ``ARRAY[1..k]OFREAL x y …`` for more."""
    data = tuple(float(v) for v in values)
    return Value(target_type(len(data)).ird(), data)


def constant_count(type_word: str) -> int | None:
    """``k`` of a constant type ``ARRAY[1..k]OFREAL`` (k ≤ 3: a platform target), else
    ``None`` — the only ARRAY a constant of the code may be."""
    m = _CONSTANT_TYPE.fullmatch(type_word)
    return int(m.group(1)) if m else None


def shape_text(platform: PlatformSignature) -> str:
    """``2 coordinates (x, y mm)`` / ``1 coordinate (y mm)``: a target's shape in words."""
    k = len(platform.coordinates)
    return f"{k} coordinate{'s' if k != 1 else ''} ({', '.join(platform.coordinates)} mm)"


def how_to_write(platform: PlatformSignature) -> str:
    """The forms a target of ``platform`` may take, for a hint."""
    k = len(platform.coordinates)
    if k == 1:
        return "a number (mm): WITH PLATFORM := 1500"
    example = ", ".join(str(1000 * (i + 1)) for i in range(k))
    return f"a tuple ({example}) or an ARRAY [1..{k}] OF REAL (mm)"
