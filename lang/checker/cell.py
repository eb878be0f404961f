"""The robots of a program: their names, their placements (``AT``) and ``robot.R_…``.

Each ROBOT clause declares its robot's name as a global (two robots with one name clash
like any two declarations). ``AT`` must be a constant POSE, folded at compile time: a
6-tuple of numbers, ``POSE(x, y, z, a, b, c)``, a POSE constant of the program or a
data-list pose (checked after the global declarations, so both may be used), with its
position in the physical range of geometry.
"""

from __future__ import annotations

from irlc.lang import types as T
from irlc.lang.cell import placement_problem
from irlc.lang.checker.expressions import ExpressionTyper
from irlc.lang.checker.scope import Reporter, Scope, Symbol


class RobotDeclarations:
    """Declares the robots and folds their placements."""

    def __init__(self, scope: Scope, typer: ExpressionTyper, report: Reporter):
        self.scope = scope
        self.typer = typer
        self.report = report

    def declare(self) -> None:
        for robot in self.scope.robots:
            c = robot.clause
            if c is not None:
                sym = Symbol("robot", c.var, None, f"line {c.span.line}", index=robot.index)
                self.scope.declare_global(c.var, sym, c.var_span or c.span)

    def placements(self) -> None:
        for robot in self.scope.robots:
            at = robot.clause.at if robot.clause is not None else None
            if at is None:
                continue
            what = f"AT of robot {robot.var}"
            got = self.typer.expr(at, T.POSE)
            if not self.typer.require(at, T.POSE, got, what) or got == T.ERROR:
                continue
            if at.const is None or at.const.type != "POSE":
                self.report.error(
                    at.span,
                    f"{what} must be a constant POSE",
                    "write a 6-tuple (x, y, z, a, b, c) of numbers (mm, ZYX deg), "
                    "POSE(x, y, z, a, b, c), a POSE constant or a data-list pose",
                )
                continue
            pose = tuple(float(x) for x in at.const.data)
            if problem := placement_problem(pose):
                self.report.error(at.span, f"{what}: {problem}")
                continue
            robot.at = pose
