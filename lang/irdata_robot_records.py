"""The ``ROBOT`` and ``JOINTS`` records of an ``.ird`` file: one pair per robot
(docs/irdata.md, Header records and Cells).

``ROBOT var robot n kinds [AT x y z a b c]`` names a robot, its joint count and kinds and,
with ``AT``, where its base stands in the cell (mm, ZYX deg); the ``JOINTS`` record after it
names its joints. Robot ``k`` is the k-th ROBOT record (from 0). Checked: the kinds match
the count, the placement is 6 finite numbers in the physical range, no two robots share a
name (names are case-insensitive), each robot has one JOINTS record with one name per joint,
and in a cell the k-th joint has the same name for every robot that has one (a joint tuple's
field names mean one joint number whatever robot it is used with).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass, replace

from irlc.lang.cell import placement_problem
from irlc.lang.irdata_model import CellRobot, Code, shown_word

Report = Callable[[int, int, str], None]  # (line, column, message)


@dataclass
class _Row:
    """A ROBOT record read, with its JOINTS record's names once read."""

    robot: CellRobot
    line: int
    column: int  # of the robot operand
    names_at: tuple[int, int] | None = None  # (line, column) of its JOINTS record


class RobotRecords:
    """Collects the ROBOT and JOINTS records while the header is read."""

    def __init__(self, file: str, report: Report):
        self.file = file
        self.report = report
        self.rows: list[_Row] = []

    def robot(self, words: list[str], cols: list[int], line: int, name: str) -> None:
        """``ROBOT var robot n kinds [AT x y z a b c]`` (``name``: the robot operand read)."""
        var, kinds = words[1], words[4]
        if not re.fullmatch(r"[RP]+", kinds) or str(len(kinds)) != words[3]:
            self.report(
                line,
                cols[4],
                f"ROBOT: joint kinds {shown_word(kinds)} do not match count {shown_word(words[3])}",
            )
        at = self._placement(words[5:], cols[5:], line) if len(words) > 5 else None
        twin = next((r for r in self.rows if r.robot.var.lower() == var.lower()), None)
        if twin is not None:
            self.report(
                line, cols[1], f"ROBOT: robot {shown_word(var)} is named twice (line {twin.line})"
            )
        position = (self.file, line, cols[2])
        self.rows.append(_Row(CellRobot(var, name, kinds, (), at, position), line, cols[2]))

    def _placement(self, words: list[str], cols: list[int], line: int) -> tuple[float, ...] | None:
        if words[0] != "AT" or len(words) != 7:
            self.report(line, cols[0], "ROBOT: expected 'AT x y z a b c' after the joint kinds")
            return None
        try:
            at = tuple(float(w) for w in words[1:])
        except ValueError:
            at = ()
        if len(at) != 6 or not all(math.isfinite(v) for v in at):
            self.report(line, cols[1], "ROBOT: AT needs 6 finite numbers (mm and ZYX deg)")
            return None
        if problem := placement_problem(at):
            self.report(line, cols[1], f"ROBOT: AT: {problem}")
            return None
        return at

    def joints(self, words: list[str], cols: list[int], line: int) -> None:
        """``JOINTS n1 … nN``: the joint names of the robot of the ROBOT record before it."""
        if not self.rows:
            self.report(line, cols[0], "JOINTS: no ROBOT record before it")
            return
        row = self.rows[-1]
        if row.names_at is not None:
            self.report(
                line,
                cols[0],
                f"JOINTS: robot {row.robot.var} has a JOINTS record (line {row.names_at[0]})",
            )
            return
        row.names_at = (line, cols[0])
        row.robot = replace(row.robot, joint_names=tuple(words[1:]))
        n, count = row.robot.joint_count, len(words) - 1
        if count != n:
            self.report(
                line, cols[0], f"JOINTS: {count} name(s) for the ROBOT record's {n} joint(s)"
            )

    def install(self, code: Code) -> None:
        """Check what is missing and put the robots into ``code`` (robot 0 in its first
        robot's fields, the others in ``other_robots``)."""
        if not self.rows:
            self.report(1, 1, "no ROBOT record")
            return
        for row in self.rows:
            if row.names_at is None:
                n = row.robot.joint_count
                self.report(
                    row.line, row.column, f"no JOINTS record for the ROBOT record's {n} joint(s)"
                )
        self._agreeing_names()
        first = self.rows[0].robot
        code.robot_var, code.robot, code.joint_kinds = first.var, first.robot, first.joint_kinds
        code.joint_names, code.at = first.joint_names, first.at
        code.robot_record = first.position
        code.other_robots = [row.robot for row in self.rows[1:]]

    def _agreeing_names(self) -> None:
        """In a cell the k-th joint has one name in every JOINTS record that has it."""
        seen: dict[int, tuple[str, str]] = {}  # joint index -> (name, robot)
        for row in self.rows:
            for k, name in enumerate(row.robot.joint_names):
                first = seen.setdefault(k, (name, row.robot.var))
                if first[0] != name and row.names_at is not None:
                    self.report(
                        *row.names_at,
                        f"JOINTS: joint {k + 1} of robot {row.robot.var} is {shown_word(name)}, "
                        f"of robot {first[1]} {shown_word(first[0])} (a cell's joints agree)",
                    )
                    return

    @property
    def joint_counts(self) -> tuple[int, ...]:
        """The robots' joint counts (a joint-tuple constant has one of them)."""
        return tuple(sorted({row.robot.joint_count for row in self.rows}))
