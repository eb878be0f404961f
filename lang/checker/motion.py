"""Motion statements: MOVE targets, WITH clauses and RECONFIGURATION.

A MOVE's targets are typed by its kind (PTP: a POSE or a MAIN_JOINT; PTPINC: a MAIN_JOINT
increment; the path motions: POSEs). Each WITH clause is given at most once: a setting
(SPEED, ACC, …) must be accepted by the motion kind and, when constant, lie in its range
(the settings table, lang/settings.py); a limit pair (JOINTLIMIT …) takes the minimum then
the maximum tuple, minimum ≤ maximum per joint when constant; RECONFIGURATION gives one
MAIN_JOINT per point (or one for a whole multi-point LIN); PLATFORM a target of the
robot's platform (:mod:`.platform`).

In a cell a motion names its robot (``MOVE welder LIN p``), whose joint count types its
joint tuples; a group move (``MOVE a LIN p AND b PTP k``) names each robot once.
"""

from __future__ import annotations

from irlc.lang import ast
from irlc.lang import platform as P
from irlc.lang import types as T
from irlc.lang.cell import ProgramRobot
from irlc.lang.checker.constants import number
from irlc.lang.checker.expressions import ExpressionTyper
from irlc.lang.checker.platform import PlatformChecker
from irlc.lang.checker.scope import Reporter, Scope
from irlc.lang.diagnostics import Span
from irlc.lang.settings import (
    BY_LIMIT_WORD,
    BY_WITH_WORD,
    KIND_WORDS,
    PTP_KINDS,
    approximation_hint,
    reconfiguration_counts,
    setting_message,
)
from irlc.lang.signature import criterion_problem

LIMIT_TYPES = {o.word: o.types for o in BY_LIMIT_WORD.values()}
"""The limit options and their (minimum, maximum) joint-tuple types (lang/settings.py)."""
_WITH_PARAMS = tuple(BY_WITH_WORD)  # SPEED ACC SPEED_ORI SPEED_PTP ACC_PTP TIME


class MotionChecker:
    """Checks MOVE and RECONFIGURATION statements and the constant settings."""

    def __init__(self, scope: Scope, typer: ExpressionTyper, report: Reporter):
        self.scope = scope
        self.typer = typer
        self.report = report
        self.platform = PlatformChecker(scope, typer, report)  # WITH PLATFORM, R_PLATFORM

    def s_movegroup(self, g: ast.MoveGroup) -> None:
        """``MOVE a LIN p AND b PTP k``: every part names its robot, each robot once."""
        robots = self.scope.robots
        if not self.scope.cell:
            self.report.error(
                g.span,
                f"a group move (… AND …) moves several robots of a cell; this program has one "
                f"robot, {robots[0].var}",
                "write each part as a statement of its own: "
                + " ".join(f"{KIND_WORDS[p.kind]} …;" for p in g.parts),
            )
            for part in g.parts:
                self.s_move(part)
            return
        first: dict[int, ast.Move] = {}
        for part in g.parts:
            if part.robot is None:
                self.report.error(
                    part.span,
                    "each part of a group move names its robot",
                    f"write {KIND_WORDS[part.kind].split()[0]} {robots[0].var} "
                    f"{_kind_word(part.kind)} … AND {robots[1].var} …",
                )
            self.s_move(part, unnamed_reported=True)
            if not part.resolved:
                continue
            k = part.resolved[0]
            if k in first:
                where = first[k].robot_span or first[k].span
                self.report.error(
                    part.robot_span or part.span,
                    f"robot {self.scope.robots[k].var} moves twice in one group move",
                    f"a robot moves at most once in a group (first at column {where.column})",
                )
            first.setdefault(k, part)

    def s_move(self, s: ast.Move, unnamed_reported: bool = False) -> None:
        """One motion (a part of a group with ``unnamed_reported``: its missing robot name
        has been reported)."""
        words = KIND_WORDS[s.kind]
        if unnamed_reported and s.robot is None and self.scope.cell:
            robot = None
        else:
            example = f"{words.split()[0]} {{}} {_kind_word(s.kind)} …"
            robot = self.scope.robot_of(s, words, example)
        if robot is not None:
            s.resolved = (robot.index,)
        for t in s.targets:
            self.move_target(s, t, robot)
        seen: dict[str, Span] = {}
        for c in s.clauses:
            if c.kind in seen:
                self.report.error(
                    c.span,
                    f"WITH {c.word.upper()} is given twice",
                    f"first on line {seen[c.kind].line}",
                )
                continue
            seen[c.kind] = c.span
            self.with_clause(s, c, robot)

    def main_joint(self, robot: ProgramRobot | None) -> T.JointTuple:
        """The MAIN_JOINT type of ``robot`` (``None``: the program's)."""
        return T.JointTuple("MAIN_JOINT", robot.n) if robot is not None else self.scope.main_joint()

    def move_target(self, s: ast.Move, t: ast.Expr, robot: ProgramRobot | None) -> None:
        joint = self.main_joint(robot)
        what = f"{KIND_WORDS[s.kind]} target"
        if s.kind == "PTP":
            if isinstance(t, ast.Tuple):
                n = len(t.items)
                want = joint if n == joint.n or n != 6 else T.POSE
                if want == joint and robot is not None:
                    self.typer.robot_tuple(t, "MAIN_JOINT", robot, what)
                else:
                    self.typer.expr(t, want)
                return
            got = self.typer.expr(t, None)
            if got not in (T.POSE, T.ERROR) and not T.assignable(joint, got):
                self.report.error(
                    t.span, f"MOVE PTP needs a POSE or a MAIN_JOINT target, got {got}"
                )
            elif isinstance(got, T.JointTuple) and robot is not None:
                self.typer.robot_arity(t, robot, what)
            return
        if s.kind == "PTPINC" and robot is not None:
            self.typer.robot_tuple(t, "MAIN_JOINT", robot, what)
            return
        want = joint if s.kind == "PTPINC" else T.POSE
        got = self.typer.expr(t, want)
        self.typer.require(t, want, got, what)

    def with_clause(self, s: ast.Move, c: ast.WithClause, robot: ProgramRobot | None) -> None:
        ptp = s.kind in ("PTP", "PTPINC")
        if c.kind in LIMIT_TYPES:
            self.limit_pair(c.kind, c.args[0], c.args[1], f"WITH {c.kind}", robot)
            return
        if c.kind == "RECONF":
            self.reconf_clause(s, c, robot)
            return
        if c.kind == P.WORD:
            self.platform.clause(s, c, robot)
            return
        if c.kind not in _WITH_PARAMS:
            self.report.error(
                c.span,
                f"unknown WITH option '{c.word}'",
                approximation_hint(c.word)
                or f"WITH options: {', '.join((*_WITH_PARAMS, *LIMIT_TYPES))}, RECONFIGURATION, "
                f"{P.WORD}",
            )
            self.typer.expr(c.args[0], None)
            return
        row = BY_WITH_WORD[c.kind]
        if s.kind not in row.kinds:
            self.report.error(
                c.span,
                f"WITH {c.kind} sets a path speed; PTP motion uses SPEED_PTP / ACC_PTP (%)"
                if ptp
                else f"WITH {c.kind} is for PTP motion; path motion uses SPEED / ACC",
            )
        t = self.typer.expr(c.args[0], T.REAL)
        if self.typer.require(c.args[0], T.REAL, t, f"WITH {c.kind}"):
            self.constant_setting(row.field, c.args[0], f"WITH {c.kind}")

    def constant_setting(self, field_name: str, value: ast.Expr, what: str) -> None:
        """A constant setting outside its range (lang/settings.py) is an error at the value,
        in the run-time words; a non-constant one is checked when it runs."""
        k: float | int | str | None = number(value.const)
        if value.const is not None and value.const.type in ("STRING", "CHAR"):
            k = value.const.data[0]  # a string setting (R_PROFILE)
        written = ast.literal_text(value)  # the value as written: -5, not -5.0
        message = setting_message(field_name, k, what, written) if k is not None else None
        if message is not None:
            self.report.error(value.span, message)
        elif field_name == "criterion" and isinstance(k, str):  # ENERGY needs inertials
            for robot in self.scope.robots:
                problem = criterion_problem(k, robot.signature)
                if problem is not None:
                    self.report.error(value.span, problem)

    def reconf_clause(self, s: ast.Move, c: ast.WithClause, robot: ProgramRobot | None) -> None:
        joint = self.main_joint(robot)
        npts = len(s.targets)
        configs = c.args
        if (
            len(configs) == 1
            and isinstance(configs[0], ast.Tuple)
            and npts > 1
            and not self._numbers_only(configs[0])
        ):
            configs = configs[0].items  # (k1, k2, k3): one configuration per point
        c.args = list(configs)
        for k in configs:
            self.configuration(k, robot, "WITH RECONFIGURATION")
        allowed = reconfiguration_counts(s.kind, npts)
        if len(configs) not in allowed:
            plural = "s" if len(configs) != 1 else ""
            self.report.error(
                c.span,
                f"WITH RECONFIGURATION gives {len(configs)} configuration{plural}"
                f" for {npts} point{'s' if npts != 1 else ''}",
                "give one MAIN_JOINT configuration for the whole move, or one per point, in order"
                if len(allowed) > 1
                else "give one MAIN_JOINT configuration per point, in order",
            )
        target = s.targets[0].ty if s.targets else None
        if s.kind in PTP_KINDS and target not in (T.ERROR, None) and T.assignable(joint, target):
            self.report.error(
                c.span,
                "WITH RECONFIGURATION needs a POSE target",
                "a MAIN_JOINT target already fixes the configuration",
            )

    def configuration(self, k: ast.Expr, robot: ProgramRobot | None, what: str) -> None:
        """A MAIN_JOINT configuration of ``robot`` (its arity checked when constant)."""
        if robot is not None:
            self.typer.robot_tuple(k, "MAIN_JOINT", robot, what)
            return
        joint = self.scope.main_joint()
        got = self.typer.expr(k, joint)
        self.typer.require(k, joint, got, what)

    def _numbers_only(self, t: ast.Tuple) -> bool:
        """Whether every item of ``t`` is a number (then ``t`` is one configuration, not a
        list of them). Typed quietly: the items are typed again, with diagnostics, after."""
        mark = len(self.report.diags)
        numeric = all(
            not isinstance(item, ast.Tuple) and self.typer.expr(item, None).is_numeric
            for item in t.items
        )
        del self.report.diags[mark:]
        return numeric

    def limit_pair(
        self, option: str, lo: ast.Expr, hi: ast.Expr, what: str, robot: ProgramRobot | None
    ) -> None:
        lo_name, hi_name = LIMIT_TYPES[option]
        n = robot.n if robot is not None else self.scope.n
        lo_t, hi_t = T.JointTuple(lo_name, n), T.JointTuple(hi_name, n)
        got_lo, got_hi = self.typer.expr(lo, lo_t), self.typer.expr(hi, hi_t)
        if (
            T.assignable(hi_t, got_lo)
            and T.assignable(lo_t, got_hi)
            and T.ERROR
            not in (
                got_lo,
                got_hi,
            )
        ):
            self.report.error(
                lo.span,
                f"{what} takes {lo_name} then {hi_name}: the arguments are swapped",
                f"write {what.split()[-1]} {_text(hi)}, {_text(lo)}",
            )
            return
        ok = self.typer.require(lo, lo_t, got_lo, f"{what}, first argument")
        ok = self.typer.require(hi, hi_t, got_hi, f"{what}, second argument") and ok
        if ok and robot is not None:
            ok = self.typer.robot_arity(lo, robot, f"{what}, first argument")
            ok = self.typer.robot_arity(hi, robot, f"{what}, second argument") and ok
        if not ok or lo.const is None or hi.const is None:
            return
        for k, (a, b) in enumerate(zip(lo.const.data, hi.const.data, strict=False)):
            if a > b:
                name = self.scope.joint_names[k] if k < len(self.scope.joint_names) else str(k + 1)
                self.report.error(
                    lo.span,
                    f"{what}: minimum {_fmt(a)} of joint {k + 1} ({name}) is "
                    f"above the maximum {_fmt(b)}",
                )
                return

    def s_reconfigure(self, s: ast.Reconfigure) -> None:
        robot = self.scope.robot_of(s, "RECONFIGURATION", "RECONFIGURATION k FOR {}")
        if robot is not None:
            s.resolved = (robot.index,)
        self.configuration(s.target, robot, "RECONFIGURATION")


def _kind_word(kind: str) -> str:
    """``LIN`` for ``LIN``/``LININC``, ``LIN PATH``, ``CIRCLE``, ``PTP``."""
    return KIND_WORDS[kind].split(" ", 1)[1]


def _fmt(x: float) -> str:
    return f"{x:g}"


def _text(e: ast.Expr) -> str:
    if isinstance(e, ast.Name):
        return e.name
    return "..."
