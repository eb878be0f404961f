"""The robots of a program: one robot, or a cell of several (docs/language.md §10).

Each ``ROBOT name := robot [AT pose];`` clause is a :class:`ProgramRobot`, numbered in the
order of the clauses (its index is the ``ROBOT:k`` operand of the IRDATA code,
docs/irdata.md). A program with more than one is a *cell*: there every motion, every
redundancy construct and every robot's own system variable names its robot; a program with
one robot may name it, and means that robot.

Which system variables belong to one robot is decided here (:data:`ROBOT_VARIABLES`): its
tool, its base frame, its actual pose and joints. The motion settings (speeds,
accelerations, profile, IPO cycle, tolerances, override, approximation, clearance) are the
cell's: one value for every robot's following motion.
"""

from __future__ import annotations

from dataclasses import dataclass

from irlc.lang import ast
from irlc.lang.geometry_range import geometry_problem
from irlc.lang.signature import RobotSignature

ROBOT_VARIABLES = ("R_TOOL", "R_BASE", "R_ACT_POSE", "R_ACT_JOINT")
"""The system variables of one robot: ``holder.R_TOOL`` in a cell (``R_TOOL`` with one
robot); every other system variable is the cell's."""

IDENTITY = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
"""The placement of a robot without ``AT``: its base is the cell frame."""


@dataclass(eq=False)
class ProgramRobot:
    """A robot of the program: its ROBOT clause (``None`` for a robot given only with
    ``--robot``), what it resolved to, and its placement (``AT``, folded by the checker)."""

    index: int
    var: str  # the program's name for the robot, as declared
    text: str  # the library name or the file as written (or given with --robot)
    signature: RobotSignature
    clause: ast.RobotClause | None = None
    at: tuple[float, ...] | None = None  # mm and ZYX deg; None: no AT (the identity)

    @property
    def n(self) -> int:
        """The robot's number of joints."""
        return self.signature.joint_count


def robot_list(robots: list[ProgramRobot]) -> str:
    """``holder, welder``: the robots of a program as a message lists them."""
    return ", ".join(r.var for r in robots)


def common_joint_count(robots: list[ProgramRobot]) -> int | None:
    """The joint count all ``robots`` share, else ``None``: then a joint tuple's arity is
    checked where it is used with a robot (docs/language.md §10)."""
    counts = {r.n for r in robots}
    return counts.pop() if len(counts) == 1 else None


def placement_problem(at: tuple[float, ...]) -> str | None:
    """Why an ``AT`` placement (x, y, z mm, a, b, c ZYX deg) is not one, else ``None``:
    the position lies in the physical range of geometry (lang/geometry_range.py); the
    compiler and the IRDATA reader check it alike."""
    if len(at) != 6:
        return f"a placement is x, y, z, a, b, c: 6 numbers, got {len(at)}"
    return geometry_problem("point", at[:3])
