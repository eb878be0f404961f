"""Obstacle shapes of the robot cell, in SI (metres), world frame.

Obstacles are taught outside the program (data lists, in mm and degrees) and referred
to by name (``OBSTACLE name``). Kinds:

* ``point``: a point ``center``;
* ``sphere``: ``center``, ``radius``;
* ``box``: ``center``, full edge lengths ``size`` (x, y, z of the box frame) and an
  optional ``rotation`` (3×3, box frame → world; data lists give it as ZYX angles
  ``rotation = [a, b, c]`` in degrees);
* ``capsule``: segment ``a``–``b`` swept by a sphere of ``radius``;
* ``plane``: ``point`` and ``normal``; the free side is where the normal points, the
  other half-space is solid (a floor, a wall).

Every shape is a *core* (point, segment, box, plane) plus a ``radius`` (0 for point,
box, plane), which is how :mod:`irlc.runtime.model.distance` measures it.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from irlc.lang.irdata import OBSTACLE_KEYS, OBSTACLE_KINDS, ObstacleDef, obstacle_field_problem
from irlc.runtime import units
from irlc.runtime.model import spatial

KINDS = OBSTACLE_KINDS


def _vec3(value: Numbers, shown, what: str) -> np.ndarray:
    v = np.asarray(value, dtype=float)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{what} must be 3 finite numbers, got {shown!r}")
    return v


@dataclass(frozen=True)
class PointObstacle:
    name: str
    position: np.ndarray
    kind: str = field(default="point", init=False)
    radius: float = field(default=0.0, init=False)


@dataclass(frozen=True)
class SphereObstacle:
    name: str
    center: np.ndarray
    radius: float
    kind: str = field(default="sphere", init=False)


@dataclass(frozen=True)
class BoxObstacle:
    name: str
    center: np.ndarray
    size: np.ndarray  # full edge lengths
    rotation: np.ndarray = field(default_factory=lambda: np.eye(3))
    kind: str = field(default="box", init=False)
    radius: float = field(default=0.0, init=False)

    @cached_property
    def half(self) -> np.ndarray:
        """Half edge lengths (computed once: the distance queries read it every cycle)."""
        return 0.5 * np.asarray(self.size, dtype=float)


@dataclass(frozen=True)
class CapsuleObstacle:
    name: str
    a: np.ndarray
    b: np.ndarray
    radius: float
    kind: str = field(default="capsule", init=False)


@dataclass(frozen=True)
class PlaneObstacle:
    name: str
    point: np.ndarray
    normal: np.ndarray  # unit; points into the free half-space
    kind: str = field(default="plane", init=False)
    radius: float = field(default=0.0, init=False)


Obstacle = PointObstacle | SphereObstacle | BoxObstacle | CapsuleObstacle | PlaneObstacle


Numbers = tuple[float, ...]


def from_definition(o: ObstacleDef) -> Obstacle:
    """The shape of the code's OBSTACLE record (:class:`~irlc.lang.irdata.ObstacleDef`:
    numbers in mm and degrees, from a data list or an ``.ird`` file), checked against the
    record's keys and the data-list rules (:func:`build`)."""
    return build(o.name, o.kind, dict(o.fields))


def from_program_units(name: str, spec: Mapping) -> Obstacle:
    """A shape from a hand-written table (``{"kind": …, key: number | numbers}``, mm and
    degrees): its numbers read, then :func:`build`. Raises ``ValueError`` naming the key."""
    kind = spec.get("kind")
    fields = {key: _numbers(name, key, v) for key, v in spec.items() if key != "kind"}
    return build(name, kind, fields)


def _numbers(name: str, key: str, value) -> Numbers:
    items = value if isinstance(value, list | tuple | np.ndarray) else (value,)
    if not all(isinstance(x, int | float | np.number) and not isinstance(x, bool) for x in items):
        raise ValueError(f"obstacle {name}.{key} must be numbers, got {value!r}")
    return tuple(float(x) for x in items)


def build(name: str, kind, fields: Mapping[str, Numbers]) -> Obstacle:
    """The shape of kind ``kind`` from its fields (key → numbers, mm and degrees; the keys
    of docs/language.md §8 and of IRDATA's OBSTACLE record). Raises ``ValueError`` naming
    the key for unknown kinds, missing or unknown keys and bad values."""
    if not isinstance(kind, str) or kind not in OBSTACLE_KEYS:
        raise ValueError(f"obstacle {name}: kind must be one of {', '.join(KINDS)}, got {kind!r}")
    keys = set(fields)
    unknown = keys - {k for k, _, _ in OBSTACLE_KEYS[kind]}
    if unknown:
        raise ValueError(f"obstacle {name}: unknown key(s) {sorted(unknown)} for kind {kind}")
    required = {k for k, _, needed in OBSTACLE_KEYS[kind] if needed}
    missing = required - keys
    if missing:
        raise ValueError(f"obstacle {name}: missing key(s) {sorted(missing)} for kind {kind}")

    def shown(key: str):  # a field as written: one number, or the numbers
        vals = fields[key]
        return vals[0] if len(vals) == 1 else vals

    def checked(key: str, value: np.ndarray) -> np.ndarray:  # the data-list rule (irdata.py)
        if problem := obstacle_field_problem(key, tuple(float(x) for x in value)):
            raise ValueError(f"obstacle {name}.{key}: {problem}")
        return value

    def vec3(key: str) -> np.ndarray:
        return _vec3(fields[key], shown(key), f"obstacle {name}.{key}")

    def mm3(key: str) -> np.ndarray:
        return checked(key, vec3(key)) * units.MM

    def radius() -> float:
        vals = fields["radius"]
        r = vals[0] if len(vals) == 1 else -1.0
        if not np.isfinite(r) or r <= 0.0:  # the data-list rule (lang/datalist.py)
            raise ValueError(f"obstacle {name}.radius must be > 0, got {shown('radius')!r}")
        checked("radius", np.array([r]))
        return r * units.MM

    if kind == "point":
        return PointObstacle(name, mm3("center"))
    if kind == "sphere":
        return SphereObstacle(name, mm3("center"), radius())
    if kind == "capsule":
        return CapsuleObstacle(name, mm3("a"), mm3("b"), radius())
    if kind == "plane":
        normal = checked("normal", vec3("normal"))
        normal = normal / float(np.max(np.abs(normal)))  # first: ‖(1e308, 1e308, 0)‖ overflows
        return PlaneObstacle(name, mm3("point"), normal / float(np.linalg.norm(normal)))
    size = mm3("size")
    rotation = np.eye(3)
    if "rotation" in fields:
        a, b, c = vec3("rotation") * units.DEG
        rotation = spatial.zyx_to_matrix(a, b, c)
    return BoxObstacle(name, mm3("center"), size, rotation)
