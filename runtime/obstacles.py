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
box, plane), which is how :mod:`irlc.runtime.distance` measures it.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from irlc.lang.irdata import OBSTACLE_KEYS, OBSTACLE_KINDS, obstacle_field_problem
from irlc.runtime import spatial, units

KINDS = OBSTACLE_KINDS


def _vec3(value, what: str) -> np.ndarray:
    v = np.asarray(value, dtype=float)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{what} must be 3 finite numbers, got {value!r}")
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


def from_program_units(name: str, spec: Mapping) -> Obstacle:
    """Build an obstacle from a data-list table (mm, degrees; the keys of
    docs/language.md §8 and of IRDATA's OBSTACLE record). Raises ``ValueError``
    naming the key for unknown kinds, missing or unknown keys and bad values."""
    kind = spec.get("kind")
    if not isinstance(kind, str) or kind not in OBSTACLE_KEYS:
        raise ValueError(f"obstacle {name}: kind must be one of {', '.join(KINDS)}, got {kind!r}")
    keys = set(spec) - {"kind"}
    unknown = keys - {k for k, _, _ in OBSTACLE_KEYS[kind]}
    if unknown:
        raise ValueError(f"obstacle {name}: unknown key(s) {sorted(unknown)} for kind {kind}")
    required = {k for k, _, needed in OBSTACLE_KEYS[kind] if needed}
    missing = required - keys
    if missing:
        raise ValueError(f"obstacle {name}: missing key(s) {sorted(missing)} for kind {kind}")

    def checked(key: str, value: np.ndarray) -> np.ndarray:  # the data-list rule (irdata.py)
        if problem := obstacle_field_problem(key, tuple(float(x) for x in value)):
            raise ValueError(f"obstacle {name}.{key}: {problem}")
        return value

    def mm3(key: str) -> np.ndarray:
        return checked(key, _vec3(spec[key], f"obstacle {name}.{key}")) * units.MM

    def radius() -> float:
        raw = spec["radius"]
        r = float(raw) if isinstance(raw, int | float) and not isinstance(raw, bool) else -1.0
        if not np.isfinite(r) or r <= 0.0:  # read as the data list reads it (datalist.py)
            raise ValueError(f"obstacle {name}.radius must be > 0, got {spec['radius']!r}")
        checked("radius", np.array([r]))
        return r * units.MM

    if kind == "point":
        return PointObstacle(name, mm3("center"))
    if kind == "sphere":
        return SphereObstacle(name, mm3("center"), radius())
    if kind == "capsule":
        return CapsuleObstacle(name, mm3("a"), mm3("b"), radius())
    if kind == "plane":
        normal = checked("normal", _vec3(spec["normal"], f"obstacle {name}.normal"))
        normal = normal / float(np.max(np.abs(normal)))  # first: ‖(1e308, 1e308, 0)‖ overflows
        return PlaneObstacle(name, mm3("point"), normal / float(np.linalg.norm(normal)))
    size = mm3("size")
    rotation = np.eye(3)
    if "rotation" in spec:
        a, b, c = _vec3(spec["rotation"], f"obstacle {name}.rotation") * units.DEG
        rotation = spatial.zyx_to_matrix(a, b, c)
    return BoxObstacle(name, mm3("center"), size, rotation)
