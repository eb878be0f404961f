"""The robots of a study's program and the ``robot.…`` keys that change them.

A program with **one robot**: ``robot.…`` is a value of its robot description file, in the
file's units (``robot.joints.10.weight``; docs/studies.md), and ``robot.at`` its placement
``AT`` — a whole pose ``[x, y, z, a, b, c]`` (mm, ZYX deg) — or ``robot.at.x`` / ``.1`` …
one component of it, as a pose of a data list. ``robot.NAME.…`` with the robot's name
means the same (as ``MOVE r LIN p`` does in the language).

A **cell** (several ``ROBOT`` clauses): every robot key names its robot right after
``robot.`` — ``robot.welder.joints.4.position`` a value of the welder's file,
``robot.welder.at`` / ``robot.welder.at.x`` its placement; a key that names no robot of
the program is an error that lists them. ``robot = "…"`` (another robot for the program)
is refused for a cell, as ``--robot`` is: a cell names its robots.

What a key changes is a :class:`RobotKey`; a variant's values become the run's
:class:`~irlc.runtime.run_setup.RobotOverride` per robot (:func:`override`), checked by the
owners of what they change: the robot loader (a file value, :func:`robot_model`) and the
run's placement check (``with_overrides``: the compiler's rule for ``AT``).
"""

from __future__ import annotations

import copy
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from irlc.lang.errors import IrlcError
from irlc.lang.file_access import describe, is_finite_real
from irlc.lang.joint_kinds import kind_letters
from irlc.study import paths

PLACEMENT = "at"


class VariantSetupError(IrlcError):
    """A value does not fit its document (a robot-file or data-list message)."""


@dataclass(frozen=True)
class PlanRobot:
    """A robot of the program as a study sees it: its name in the program, the robot it
    is (a library name or a file: the ``ROBOT`` clause's, or the study's ``robot = …``),
    its joints as compiled, its placement ``AT`` (mm, ZYX deg; ``None``: the identity) and
    its description file with the parsed text (``None``s for a URDF robot, whose values a
    study cannot change)."""

    var: str
    source: str
    joint_kinds: str  # one letter per joint: R | P
    at: tuple[float, ...] | None = None
    file: str | None = None
    doc: dict | None = None


@dataclass(frozen=True)
class RobotKey:
    """What a ``robot.…`` key changes: robot ``robot``'s placement (``at``; ``component``
    1 … 6, or ``None`` for the whole pose) or the value at ``parts`` of its file."""

    robot: str
    parts: tuple[str, ...] = ()
    at: bool = False
    component: int | None = None


def robot_key(robots: Sequence[PlanRobot], parts: list[str]) -> RobotKey:
    """The :class:`RobotKey` of ``robot.PARTS`` (the module doc); a
    :class:`~irlc.study.paths.PathError` when it names nothing of the program's robots."""
    from irlc.robots.loader import TOP_KEYS

    names = ", ".join(r.var for r in robots)
    named = next((r for r in robots if r.var.lower() == parts[0].lower()), None)
    if len(robots) > 1:
        if named is None:
            raise paths.PathError(
                f"'{parts[0]}' is not a robot of the program: in a cell a robot key is "
                f"robot.NAME.… with NAME one of its robots ({names})"
            )
        robot, rest = named, parts[1:]
    elif named is not None and parts[0] not in TOP_KEYS:  # robot.r.… = robot.…
        robot, rest = named, parts[1:]
    else:
        robot, rest = robots[0], parts
    if not rest:
        raise paths.PathError(
            f"robot.{robot.var} is a robot: vary robot.{robot.var}.at (its placement) or a "
            f"value of its robot file (robot.{robot.var}.joints.1.position …)"
        )
    if rest[0].lower() == PLACEMENT:
        return RobotKey(robot.var, at=True, component=_component(robot, rest[1:]))
    if len(rest) > 1 and rest[0] == "joints":
        rest = [rest[0], paths.joint_index(rest[1]), *rest[2:]]
    return RobotKey(robot.var, tuple(rest))


def _component(robot: PlanRobot, rest: list[str]) -> int | None:
    """``[]`` → ``None`` (the whole pose); ``["x"]`` or ``["1"]`` → 1 …"""
    if not rest:
        return None
    where = f"robot.{robot.var}.at"
    if len(rest) == 1 and rest[0].lower() in paths.POSE:
        return paths.POSE.index(rest[0].lower()) + 1
    if len(rest) == 1 and rest[0].isdigit() and 1 <= int(rest[0]) <= 6:
        return int(rest[0])
    raise paths.PathError(
        f"'{where}.{'.'.join(rest)}': a placement's component is x, y, z, a, b, c or 1 … 6"
    )


def robot_named(robots: Sequence[PlanRobot], name: str) -> PlanRobot:
    return next(r for r in robots if r.var == name)


def placement(robot: PlanRobot, changes: list[tuple[int | None, Any]]) -> tuple[float, ...]:
    """The robot's ``AT`` with ``changes`` (component or ``None`` for the whole pose, value)
    applied in order; a value that is no number (or no list of them) is a
    :class:`VariantSetupError` (its range is the run's to check: ``with_overrides``)."""
    pose = list(robot.at or (0.0,) * 6)
    for component, value in changes:
        if component is None:
            if not (isinstance(value, list) and all(is_finite_real(v) for v in value)):
                raise VariantSetupError(
                    f"expected a placement [x, y, z, a, b, c] of finite numbers (mm, deg), "
                    f"got {describe(value)}"
                )
            pose = list(value)
        else:
            if not is_finite_real(value):
                raise VariantSetupError(f"expected a finite number, got {describe(value)}")
            if len(pose) == 6:
                pose[component - 1] = value
    return tuple(float(v) for v in pose)


def check_placement(code, robot: PlanRobot, at: tuple[float, ...]) -> None:
    """The run's check of a placement (``with_overrides``: the compiler's rule for ``AT``)."""
    from irlc.runtime.run_setup import RobotOverride, RunSetupError, with_overrides

    try:
        with_overrides(code, {robot.var: RobotOverride(at=at)})
    except RunSetupError as e:
        raise VariantSetupError(str(e)) from None


def robot_model(robot: PlanRobot, changes: list[tuple[list[str], Any]]):
    """The robot with ``changes`` applied to its file, loaded by the robot loader (and,
    for a ``drives`` change, its drive data read by the drives' reader)."""
    from irlc.robots import RobotFileError
    from irlc.robots.loader import build_model

    assert robot.file is not None and robot.doc is not None
    doc = copy.deepcopy(robot.doc)
    for parts, value in changes:
        paths.set_value(doc, parts, value, create=True)
    try:
        model = build_model(doc, robot.file, Path(robot.file).parent)
    except RobotFileError as e:
        raise VariantSetupError(
            e.message if e.key == "" else f"key '{e.key}': {e.message}"
        ) from None
    kinds = kind_letters(model.joint_kinds)
    if robot.joint_kinds and kinds != robot.joint_kinds:
        raise VariantSetupError(f"the robot's joints become {kinds}, the program's are "
                                f"{robot.joint_kinds}")  # fmt: skip
    if any(parts[0] == "drives" for parts, _ in changes):
        from irlc.runtime.drives import drive_params

        try:
            drive_params(model)
        except ValueError as e:
            raise VariantSetupError(str(e)) from None
    return model
