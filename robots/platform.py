"""A robot's platform: the ``[platform]`` table of a robot file (docs/robots.md).

The monograph's mobile robot (seed 001, ch. 3.2, fig. 3.1b) is a platform of ``n_a``
joints ``θ_a`` carrying an arm of ``n_b`` joints ``θ_b``; a job may add a condition on the
platform itself — it follows its own path, ``f_platform(θ_a) = x_platform(t)`` — solved
with the TCP's task (``runtime/ik/tasks/platform.py``). The file names what that needs::

    [platform]
    joints = ["X", "Y"]          # the platform's joints: the chain's first ones, prismatic
    coordinates = ["x", "y"]     # the world coordinates of the platform point the task sets
    point = [0.0, 0.0, 0.5]      # optional: that point in the platform frame (length unit)

The platform frame is the body link the last platform joint moves (link ``k`` for ``k``
platform joints); the controlled point is ``point`` in it (default its origin). Its world
coordinates are

    c(θ_a) = c₀ + A·θ_a           (m; A = ∂c/∂θ_a, k × k)

— affine, because the platform's joints are prismatic (a slide moves every later frame by
``axis·Δθ``, whatever the other slides are). The file is refused unless ``A`` is
invertible (each coordinate is reached independently): then a platform target ``c`` has
exactly one set of platform joints, ``θ_a = A⁻¹(c − c₀)``, and is inside the platform's
limits exactly when those joints are inside theirs (:meth:`Platform.problem`, the one
check of the compiler — for constants — and of the runtime). A revolute platform joint
(a wheeled base's heading) is not supported yet.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from irlc.lang.file_access import shown_key
from irlc.robots.model import RobotModel
from irlc.robots.toml_reader import Reader, show
from irlc.runtime import units

COORDINATES = ("x", "y", "z")
PLATFORM_KEYS = {"joints", "coordinates", "point", "description"}
_SINGULAR = 1e-9  # |det A| (m/m) below this: the coordinates are not independent


@dataclass(frozen=True)
class Platform:
    """A robot's platform (module docstring); SI. ``joints``: 0-based indices ``0 … k−1``;
    ``link``: the platform frame (``k``); ``point``: the controlled point in it (m);
    ``coordinates``: the world coordinates it controls (``"x"``, ``"y"``, ``"z"``);
    ``origin`` ``c₀`` and ``matrix`` ``A`` of ``c(θ_a) = c₀ + A·θ_a`` (m, m/m)."""

    joints: tuple[int, ...]
    joint_names: tuple[str, ...]
    link: int
    point: np.ndarray
    coordinates: tuple[str, ...]
    origin: np.ndarray
    matrix: np.ndarray
    limits: np.ndarray  # (k, 2) the platform joints' own position limits (m)
    description: str = ""

    @property
    def dimension(self) -> int:
        return len(self.coordinates)

    @property
    def rows(self) -> tuple[int, ...]:
        """The coordinates as indices of a world position (``x y z`` → 0 1 2)."""
        return tuple(COORDINATES.index(c) for c in self.coordinates)

    def coordinates_at(self, q: np.ndarray) -> np.ndarray:
        """``c(θ_a)`` (m) of the configuration ``q`` (SI; its first ``k`` values)."""
        return self.origin + self.matrix @ np.asarray(q, dtype=float)[: len(self.joints)]

    def joints_for(self, target: np.ndarray) -> np.ndarray:
        """``θ_a = A⁻¹(c − c₀)`` (m): the platform joints that put it at ``target`` (m)."""
        return np.linalg.solve(self.matrix, np.asarray(target, dtype=float) - self.origin)

    def ranges(self) -> np.ndarray:
        """``(k, 2)`` the least and the largest value (m) of each coordinate over the
        platform joints' limits (the corners of their box: the map is affine)."""
        corners = np.array(np.meshgrid(*self.limits)).reshape(len(self.joints), -1)
        values = self.origin[:, None] + self.matrix @ corners
        return np.column_stack((values.min(axis=1), values.max(axis=1)))

    def describe(self, target_mm: Sequence[float]) -> str:
        """``(x 1000, y 300) mm``: a platform target in program units, for messages."""
        parts = ", ".join(f"{c} {v:g}" for c, v in zip(self.coordinates, target_mm, strict=True))
        return f"({parts}) mm"

    def problem(
        self,
        target_mm: Sequence[float],
        position: np.ndarray | None = None,
        labels: Sequence[str] | None = None,
        bound: str = "its limit",
    ) -> str | None:
        """Why the platform cannot be at ``target_mm`` (program units, one value per
        coordinate), else ``None``: its joints ``θ_a`` for it lie outside ``position``
        (``(n, 2)`` SI, the active position limits; default the platform joints' own).
        ``labels``: the joints as a message names them (default the file's names);
        ``bound``: what ``position`` is (``"the active JOINTLIMIT"``). The compiler (for a
        constant target) and the runtime use this one check."""
        values = np.asarray(target_mm, dtype=float)
        if values.shape != (self.dimension,) or not np.all(np.isfinite(values)):
            return f"a platform target has {self.dimension} finite coordinates (mm)"
        theta = self.joints_for(values * units.MM)
        box = self.limits if position is None else np.asarray(position)[: len(self.joints)]
        names = labels or self.joint_names
        for j, (v, (lo, hi)) in enumerate(zip(theta, box, strict=True)):
            tol = 1e-9 * (1.0 + abs(v))
            if lo - tol <= v <= hi + tol:
                continue
            side, edge = ("min", lo) if v < lo else ("max", hi)
            return (
                f"the platform target {self.describe(values)} is outside the platform's "
                f"limits: it needs joint {names[j]} at {v / units.MM:.6g} mm, beyond {bound} "
                f"({side} {edge / units.MM:.6g} mm)"
            )
        return None


def read_platform(rd: Reader, value: Any, model: RobotModel, task_rows: int) -> Platform:
    """``[platform]`` of ``model``'s file (module docstring); ``task_rows``: how many pose
    rows the robot's task has (the platform's rows must leave the arm enough joints)."""
    t = rd.table(value, "platform", PLATFORM_KEYS)
    for key in ("joints", "coordinates"):
        if key not in t:
            raise rd.fail("platform", f"missing key '{key}'")
    names = _strings(rd, t["joints"], "platform.joints")
    index = {j.name: i for i, j in enumerate(model.joints)}
    for i, name in enumerate(names):
        key = f"platform.joints[{i}]"
        if name not in index:
            raise rd.fail(key, f"no joint named '{shown_key(name)}' (joints: {', '.join(index)})")
        if index[name] != i:
            raise rd.fail(
                key,
                f"the platform's joints are the chain's first joints, in order: joint {i + 1} "
                f"is '{model.joints[i].name}', not '{name}'",
            )
        if model.joints[i].kind != "prismatic":
            raise rd.fail(
                key,
                f"joint '{name}' is revolute: a platform of prismatic joints only "
                "(a heading joint is not supported yet)",
            )
    k = len(names)
    if k >= model.n:
        raise rd.fail("platform.joints", "the platform needs an arm: at least one joint after it")
    coords = _strings(rd, t["coordinates"], "platform.coordinates", COORDINATES)
    if len(coords) != k:
        raise rd.fail(
            "platform.coordinates",
            f"one coordinate per platform joint: {k} joint(s), {len(coords)} coordinate(s)",
        )
    if task_rows + k > model.n:
        raise rd.fail(
            "platform",
            f"the task's {task_rows} pose rows and the platform's {k} rows are more than "
            f"the robot's {model.n} joints",
        )
    point = np.zeros(3)
    if "point" in t:
        point = rd.vector(t["point"], "platform.point", 3) * rd.length
        rd.in_range("platform.point", "point", point)
    description = rd.string(t.get("description", ""), "platform.description")
    origin, matrix = _affine_map(model, k, point, coords)
    if abs(np.linalg.det(matrix)) < _SINGULAR:
        raise rd.fail(
            "platform.coordinates",
            f"the platform joints {', '.join(names)} do not move the platform point along "
            f"{', '.join(coords)} independently",
        )
    limits = model.position_limits[:k].copy()
    return Platform(
        tuple(range(k)), tuple(names), k, point, coords, origin, matrix, limits, description
    )


def _strings(rd: Reader, value: Any, key: str, choices: tuple[str, ...] | None = None):
    if not isinstance(value, list) or not value:
        raise rd.fail(key, f"expected a non-empty list of names, got {show(value)}")
    out = tuple(rd.string(v, f"{key}[{i}]", choices) for i, v in enumerate(value))
    if len(set(out)) != len(out):
        raise rd.fail(key, "a name is listed twice")
    return out


def _affine_map(model: RobotModel, k: int, point: np.ndarray, coords: tuple[str, ...]):
    """``(c₀, A)`` of the platform point's coordinates from the robot's own forward
    kinematics (exact: the platform's joints are prismatic)."""
    from irlc.runtime.model.kinematics import Kinematics

    kin = Kinematics(model)
    rows = [COORDINATES.index(c) for c in coords]

    def at(q_a: np.ndarray) -> np.ndarray:
        q = np.zeros(model.n)
        q[:k] = q_a
        frame = kin.link_frames(q)[k]
        return (frame[:3, :3] @ point + frame[:3, 3])[rows]

    origin = at(np.zeros(k))
    matrix = np.column_stack([at(e) - origin for e in np.eye(k)])
    return origin, matrix
