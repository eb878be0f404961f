"""``WITH PLATFORM := q`` of a motion and ``R_PLATFORM`` (docs/language.md §7).

Checks, each a compile error at the clause or its value:

* the motion's robot has a platform (its robot file's ``[platform]``);
* the motion is a path motion (LIN, LIN PATH, CIRCLE, MOVE_INC LIN) or a PTP to a POSE —
  a MAIN_JOINT target (and MOVE_INC PTP) already fixes the platform's joints;
* ``q`` has the platform's shape (:func:`irlc.lang.platform.target_type`): a number for one
  coordinate, a tuple of ``k`` numbers or an ARRAY of ``k`` REALs for ``k`` (a tuple of
  another length is named as such);
* a constant ``q`` (literals, CONSTs, a data list's ``[platform]`` entry) lies inside the
  platform's limits (:meth:`~irlc.lang.platform.PlatformSignature.problem`, the check the
  runtime makes for the others);
* not together with ``WITH APPROX``: a platform motion ends with an exact stop.

``R_PLATFORM := 'HOLD'`` with a constant value on a robot without a platform is a warning
(there is nothing to hold; the setting's range is its row's, as for every setting).
"""

from __future__ import annotations

from irlc.lang import ast
from irlc.lang import platform as P
from irlc.lang import types as T
from irlc.lang.cell import ProgramRobot
from irlc.lang.checker.constants import number
from irlc.lang.checker.expressions import ExpressionTyper
from irlc.lang.checker.scope import Reporter, Scope
from irlc.lang.settings import PTP_KINDS
from irlc.lang.signature import joint_label

_NO_PLATFORM_HINT = "a robot file names its platform in [platform] (docs/robots.md)"


class PlatformChecker:
    """The platform clause of a motion and the R_PLATFORM setting (module docstring)."""

    def __init__(self, scope: Scope, typer: ExpressionTyper, report: Reporter):
        self.scope, self.typer, self.report = scope, typer, report

    def clause(self, s: ast.Move, c: ast.WithClause, robot: ProgramRobot | None) -> None:
        """``WITH PLATFORM := q`` of ``s`` (``robot``: the motion's; ``None`` when unknown)."""
        value = c.args[0]
        platform = P.platform_of(robot.signature) if robot is not None else None
        if platform is None:
            self.typer.expr(value, None if not isinstance(value, ast.Tuple) else T.ERROR)
            if robot is not None:
                name = robot.signature.name
                self.report.error(
                    c.span, f"WITH PLATFORM: robot {name} has no platform", _NO_PLATFORM_HINT
                )
            return
        if s.kind == "PTPINC" or (s.kind in PTP_KINDS and self._joint_target(s)):
            self.report.error(
                c.span,
                "WITH PLATFORM needs a POSE target",
                "a MAIN_JOINT target already fixes the platform's joints",
            )
        if any(other.kind == "APPROX" for other in s.clauses):
            self.report.error(
                c.span,
                "a motion WITH PLATFORM ends with an exact stop: it takes no WITH APPROX",
                "the platform's path is not blended (docs/language.md §7)",
            )
        values = self.target(value, platform)
        if values is None:
            return
        problem = platform.problem(values, labels=self._labels(robot, platform))
        if problem is not None:
            self.report.error(value.span, f"WITH PLATFORM: {problem}")

    def _labels(self, robot: ProgramRobot, platform: P.PlatformSignature) -> list[str]:
        """The platform joints as run-time messages name them: ``a1 (T)``."""
        program = self.scope.joint_names
        files = robot.signature.joint_names
        return [
            joint_label(program[j] if j < len(program) else f"a{j + 1}",
                        files[j] if j < len(files) else None)
            for j in platform.joints
        ]  # fmt: skip

    def target(self, value: ast.Expr, platform: P.PlatformSignature) -> list[float] | None:
        """Types ``value`` as a target of ``platform``; its coordinates (mm) when constant."""
        k = len(platform.coordinates)
        want = P.target_type(k)
        shape = P.shape_text(platform)
        if isinstance(value, ast.Tuple) and len(value.items) != k:
            self.typer.expr(value, T.ERROR)
            self.report.error(
                value.span,
                f"WITH PLATFORM: the platform has {shape}, got {len(value.items)} values",
                P.how_to_write(platform),
            )
            return None
        got = self.typer.expr(value, want)
        if not T.assignable(want, got):
            self.report.error(
                value.span,
                f"WITH PLATFORM: the platform has {shape}: expected {want}, got {got}",
                P.how_to_write(platform),
            )
            return None
        return _constant(value)

    def _joint_target(self, s: ast.Move) -> bool:
        target = s.targets[0].ty if s.targets else None
        return isinstance(target, T.JointTuple)

    def hold_setting(self, value: ast.Expr) -> None:
        """``R_PLATFORM := 'HOLD'`` (a constant) for a program whose robot has no platform."""
        c = value.const
        word = c.data[0] if c is not None and c.type in ("STRING", "CHAR") else None
        robot = self.scope.robot
        if not isinstance(word, str) or word.upper() != "HOLD" or robot is None:
            return
        if P.platform_of(robot) is None:
            self.report.warning(
                value.span,
                f"R_PLATFORM := 'HOLD': robot {robot.name} has no platform to hold",
                _NO_PLATFORM_HINT,
            )


def _constant(value: ast.Expr) -> list[float] | None:
    """A target's coordinates when it is a constant (a number, a tuple of number
    constants, a CONST or data-list value), else ``None``."""
    if isinstance(value, ast.Tuple):
        items = [number(item.const) for item in value.items]
        return None if any(v is None for v in items) else [float(v) for v in items]  # type: ignore[arg-type]
    c = value.const
    if c is None:
        return None
    if c.type in ("INTEGER", "REAL"):
        return [float(c.data[0])]
    if c.type.startswith("ARRAY"):
        return [float(x) for x in c.data]
    return None
