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


@dataclass(frozen=True)
class SimpleRobot:
    """A plain signature (tests, REPL, tools that know a robot without loading it)."""

    name: str
    joint_kinds: tuple[str, ...]
    joint_names: tuple[str, ...] = ()

    @property
    def joint_count(self) -> int:
        return len(self.joint_kinds)


def kind_letters(sig: RobotSignature) -> str:
    """``"RRP..."``: one letter per joint, as in the IRDATA ``ROBOT`` record
    (:func:`irlc.lang.joint_kinds.kind_letters`)."""
    try:
        return joint_kinds.kind_letters(sig.joint_kinds)
    except ValueError as e:
        raise ValueError(f"robot {sig.name}: {e}") from None
