"""One naming rule for joints, everywhere a user reads one.

A joint is called by its **program name**: the name in the program's MAIN_JOINT record,
by default ``a1 … aN`` (the trace columns, the report, the summary, plots, REPL, messages).
Where the robot file names the joint differently (``J9``, ``panda_joint4``, ``A3``), that
name follows in parentheses in text meant for people — ``a4 (panda_joint4)`` — and is a
separate key in JSON (``robot_name``). Tools that feed other software by the robot's own
names (the trajectory export, for ROS) use the robot's names.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from irlc.lang.signature import joint_label

__all__ = ["JointNaming", "default_names", "joint_label", "naming_or_default"]


def default_names(n: int) -> tuple[str, ...]:
    """``a1 … aN``: the program names when a program declares none."""
    return tuple(f"a{i + 1}" for i in range(n))


@dataclass(frozen=True)
class JointNaming:
    """Program names beside the robot file's names, one pair per joint."""

    program: tuple[str, ...]
    robot: tuple[str, ...]

    @classmethod
    def of(cls, robot_names: Sequence[str], program_names: Sequence[str] | None = None):
        robot = tuple(robot_names)
        program = tuple(program_names) if program_names and len(program_names) == len(robot) else ()
        return cls(program or default_names(len(robot)), robot)

    @classmethod
    def for_model(cls, model, program_names: Sequence[str] | None = None) -> JointNaming:
        return cls.of(model.joint_names, program_names)

    def name(self, j: int) -> str:
        """The program name of joint ``j`` (0-based)."""
        return self.program[j]

    def label(self, j: int) -> str:
        """``a4 (panda_joint4)``, or ``a4`` where both names agree (case-insensitively)."""
        return joint_label(self.program[j], self.robot[j])

    def labels(self, joints: Sequence[int]) -> str:
        return ", ".join(self.label(j) for j in joints)


def naming_or_default(naming: JointNaming | None, model) -> JointNaming:
    """``naming`` where a caller passes the program's, else the default ``a1 … aN``
    beside the robot file's names (the one fallback of every message that names joints)."""
    return naming if naming is not None else JointNaming.for_model(model)
