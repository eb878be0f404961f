"""What the language checker needs to know about a robot: its signature.

``irlc.lang`` never imports the runtime or the robot library; the caller passes a resolver
``resolve_robot(name_or_path) -> RobotSignature`` (the CLI wires ``irlc.robots.load_robot``,
whose ``RobotModel`` satisfies this protocol). A resolver raises ``LookupError``
(e.g. ``irlc.robots.RobotFileError``) with a message for an unknown or broken robot; that
becomes a diagnostic. Any other exception is a bug and propagates.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

from irlc.lang import joint_kinds


@runtime_checkable
class RobotSignature(Protocol):
    @property
    def name(self) -> str: ...

    @property
    def joint_count(self) -> int: ...

    @property
    def joint_names(self) -> Sequence[str]: ...

    @property
    def joint_kinds(self) -> Sequence[str]:
        """Per joint ``"revolute"`` / ``"prismatic"`` (or ``"R"`` / ``"P"``)."""
        ...


RobotResolver = Callable[[str], RobotSignature]


def joint_label(program: str, robot: str | None) -> str:
    """The rule for naming one joint in a message: ``a4 (panda_joint4)``; ``a4`` where the
    robot file's name agrees case-insensitively or is unknown (e.g. a report written before
    it was kept). The compiler and the runtime name joints by it."""
    if not robot or program.lower() == robot.lower():
        return program
    return f"{program} ({robot})"


@dataclass(frozen=True)
class SimpleRobot:
    """A plain signature (tests, REPL, tools that know a robot without loading it)."""

    name: str
    joint_kinds: tuple[str, ...]
    joint_names: tuple[str, ...] = ()

    @property
    def joint_count(self) -> int:
        return len(self.joint_kinds)


def missing_inertia(sig: RobotSignature) -> str | None:
    """What the robot lacks for its links' inertia matrix (an optional member of a
    signature: ``RobotModel.missing_inertia``), or ``None`` when it has it or when the
    signature does not say (a :class:`SimpleRobot`)."""
    return getattr(sig, "missing_inertia", None)


def criterion_problem(word: str, sig: RobotSignature) -> str | None:
    """Why ``R_CRITERION := word`` cannot run on the robot (``'ENERGY'`` needs the links'
    inertia matrix), else ``None``; the compiler and the runtime say it in these words."""
    problem = missing_inertia(sig) if word.upper() == "ENERGY" else None
    if problem is None:
        return None
    return f"R_CRITERION := 'ENERGY' needs the links' inertia matrix: {problem}"


def kind_letters(sig: RobotSignature) -> str:
    """``"RRP..."``: one letter per joint, as in the IRDATA ``ROBOT`` record
    (:func:`irlc.lang.joint_kinds.kind_letters`)."""
    try:
        return joint_kinds.kind_letters(sig.joint_kinds)
    except ValueError as e:
        raise ValueError(f"robot {sig.name}: {e}") from None
