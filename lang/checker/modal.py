"""The modal redundancy statements: START/END blocks per statement list.

JOINTLIMIT / JOINTSPEEDLIMIT / JOINTACCELLIMIT … END, CYCLICSTART … CYCLICEND,
OBSTACLE name … OBSTACLEEND name, FREEZESTART … FREEZEEND and COOPERATE robot IN holder …
COOPERATEEND are checked per statement list: an END needs an earlier START of the same
kind in the same list, a START is not repeated while it is open (also from an enclosing
list), and every START is closed before its list ends. ``repl`` mode skips the two pairing
checks (the interpreter checks them at run time); there the main body starts with the
cooperations an earlier entry opened (``cooperating``), which its COOPERATEEND closes.

In a cell every option belongs to one robot (``FOR robot``): the blocks of different robots
are independent. COOPERATEEND closes the innermost open COOPERATE of its list, and a robot
cooperates in at most one open COOPERATE (as the cooperating or the holding robot).
"""

from __future__ import annotations

from dataclasses import dataclass

from irlc.lang import ast
from irlc.lang import types as T
from irlc.lang.cell import ProgramRobot, robot_list
from irlc.lang.checker.constants import number
from irlc.lang.checker.expressions import ExpressionTyper
from irlc.lang.checker.motion import LIMIT_TYPES, MotionChecker
from irlc.lang.checker.scope import Reporter, Scope
from irlc.lang.diagnostics import Span
from irlc.lang.file_access import shown_names
from irlc.lang.settings import LIMIT_OPTIONS

_START_WORD = {
    **{o.word: o.word for o in LIMIT_OPTIONS},
    "CYCLIC": "CYCLICSTART",
    "OBSTACLE": "OBSTACLE",
    "FREEZE": "FREEZESTART",
    "COOPERATE": "COOPERATE",
}
_END_WORD = {
    **{o.word: o.end_word for o in LIMIT_OPTIONS},
    "CYCLIC": "CYCLICEND",
    "OBSTACLE": "OBSTACLEEND",
    "FREEZE": "FREEZEEND",
    "COOPERATE": "COOPERATEEND",
}
_EXAMPLE = {  # how a START or END names its robot in a cell ({} is the robot)
    "JOINTLIMIT": "JOINTLIMIT lo, hi FOR {}",
    "JOINTSPEEDLIMIT": "JOINTSPEEDLIMIT lo, hi FOR {}",
    "JOINTACCELLIMIT": "JOINTACCELLIMIT lo, hi FOR {}",
    "CYCLIC": "CYCLICSTART FOR {}",
    "OBSTACLE": "OBSTACLE name FOR {}",
    "FREEZE": "FREEZESTART 1, 2 FOR {}",
}
_VERTICAL = "VERTICAL"  # COOPERATE … WITH VERTICAL: the only option


@dataclass
class _Open:
    """An open START: its words (``JOINTLIMIT FOR holder``), where, how it is closed, the
    robots it holds (a cooperation: both)."""

    display: str
    span: Span
    closing: str
    robots: tuple[int, ...] = ()
    earlier: bool = False  # opened by an earlier REPL entry

    def where(self) -> str:
        return "an earlier entry" if self.earlier else f"line {self.span.line}"


class _ListState:
    def __init__(self, outer: _ListState | None):
        self.outer = outer
        self.open: dict[str, _Open] = {}  # key -> the open START

    def find_open(self, key: str) -> _Open | None:
        s: _ListState | None = self
        while s is not None:
            if key in s.open:
                return s.open[key]
            s = s.outer
        return None

    def cooperation_of(self, robots: tuple[int, ...]) -> _Open | None:
        """An open COOPERATE (here or in an enclosing list) holding one of ``robots``."""
        s: _ListState | None = self
        while s is not None:
            for key, o in s.open.items():
                if key.startswith("COOPERATE") and set(o.robots) & set(robots):
                    return o
            s = s.outer
        return None


class ModalBlocks:
    """The open START statements of the statement lists being checked, innermost first."""

    def __init__(
        self,
        scope: Scope,
        typer: ExpressionTyper,
        motion: MotionChecker,
        report: Reporter,
        *,
        repl: bool,
        cooperating: tuple[tuple[int, int], ...] = (),
    ):
        self.scope = scope
        self.typer = typer
        self.motion = motion
        self.report = report
        self.repl = repl
        self.cooperating = cooperating if repl else ()
        self.state: _ListState | None = None

    def enter_list(self, main: bool = False) -> None:
        """A statement list starts: its own START statements open in it (the main body of
        a REPL entry: also the cooperations an earlier entry opened)."""
        self.state = _ListState(self.state)
        for worker, holder in self.cooperating if main else ():
            w, h = self.scope.robots[worker].var, self.scope.robots[holder].var
            self.state.open[f"COOPERATE#{worker}"] = _Open(
                f"COOPERATE {w} IN {h}", Span(1, 1), "COOPERATEEND", (worker, holder), True
            )

    def leave_list(self, end_span: Span, end_word: str) -> None:
        """The list ends at ``end_word`` (line of ``end_span``): report what is still open."""
        assert self.state is not None
        if not self.repl:
            for o in self.state.open.values():
                self.report.error(
                    o.span,
                    f"{o.display} is not closed before {end_word} (line {end_span.line})",
                    f"add {o.closing}; in the same statement list",
                )
        self.state = self.state.outer

    def s_modalon(self, s: ast.ModalOn) -> None:
        assert self.state is not None
        if s.option == "COOPERATE":
            self.cooperate_on(s)
            return
        robot = self.statement_robot(s, _START_WORD[s.option])
        if s.option in LIMIT_TYPES:
            self.motion.limit_pair(s.option, s.args[0], s.args[1], s.option, robot)
        elif s.option == "FREEZE":
            self.freeze_joints(s, robot)
        opened = self.modal_key(s, robot)
        if opened is None:
            return
        key, display, closing = opened
        prev = self.state.find_open(key)
        if prev is not None:
            self.report.error(
                s.span,
                f"{display} is already on (since line {prev.span.line})",
                f"close it with {closing} first",
            )
        self.state.open[key] = _Open(display, s.span, closing)

    def s_modaloff(self, s: ast.ModalOff) -> None:
        assert self.state is not None
        if s.option == "COOPERATE":
            self.cooperate_off(s)
            return
        closed = self.modal_key(s, self.statement_robot(s, _END_WORD[s.option]))
        if closed is None:
            return
        key, display, closing = closed
        if key in self.state.open:
            del self.state.open[key]
            return
        if self.repl:
            return
        outer = self.state.outer.find_open(key) if self.state.outer else None
        if outer is not None:
            self.report.error(
                s.span,
                f"{closing} closes {display} of line {outer.span.line} from another statement list",
                "START and END must be in the same statement list (same block)",
            )
        elif s.option == "OBSTACLE":
            on = [o.display for o in self.state.open.values() if o.display.startswith("OBSTACLE ")]
            self.report.error(
                s.name_span or s.span,
                f"OBSTACLEEND {s.name}: obstacle '{s.name}' is not active here",
                f"active obstacles: {', '.join(d.split()[1] for d in on)}"
                if on
                else f"switch it on first with OBSTACLE {s.name};",
            )
        else:
            self.report.error(
                s.span, f"{closing} without an earlier {display} in the same statement list"
            )

    def statement_robot(self, s: ast.ModalOn | ast.ModalOff, word: str) -> ProgramRobot | None:
        """The robot a START or END names (``FOR robot``; ``s.resolved``)."""
        robot = self.scope.robot_of(s, word, _EXAMPLE[s.option])
        if robot is not None:
            s.resolved = (robot.index,)
        return robot

    def modal_key(
        self, s: ast.ModalOn | ast.ModalOff, robot: ProgramRobot | None
    ) -> tuple[str, str, str] | None:
        """``(key, display, closing)`` of the option a START/END names (in a cell, for its
        robot); None: an unknown obstacle, or a cell's statement without its robot."""
        if s.option != "OBSTACLE":
            key, display, closing = s.option, _START_WORD[s.option], _END_WORD[s.option]
        else:
            assert s.name is not None
            o = self.scope.obstacles.get(s.name.lower())
            if o is None:
                self.unknown_obstacle(s.name, s.name_span or s.span)
                return None
            key, display = f"OBSTACLE:{o.name.lower()}", f"OBSTACLE {o.name}"
            closing = f"OBSTACLEEND {o.name}"
        if not self.scope.cell:
            return key, display, closing
        if robot is None:
            return None
        suffix = f" FOR {robot.var}"
        return f"{key}#{robot.index}", display + suffix, closing + suffix

    def unknown_obstacle(self, name: str, span: Span) -> None:
        known = sorted(o.name for o in self.scope.obstacles.values())
        hint = (
            f"known obstacles: {shown_names(known)}"
            if known
            else "define obstacles in an imported data list: [obstacles.NAME]"
        )
        self.report.error(span, f"unknown obstacle '{name}'", hint)

    def freeze_joints(self, s: ast.ModalOn, robot: ProgramRobot | None) -> None:
        n = robot.n if robot is not None else self.scope.n
        seen: set[int] = set()
        for e in s.args:
            t = self.typer.expr(e, T.INTEGER)
            k = number(e.const)
            if t == T.ERROR:
                continue
            if t != T.INTEGER or k is None:
                self.report.error(e.span, "FREEZESTART takes joint numbers (INTEGER constants)")
            elif n and not 1 <= k <= n:
                name = _robot_name(robot, self.scope.cell)
                self.report.error(e.span, f"joint {k} does not exist: {name} has joints 1..{n}")
            elif k in seen:
                self.report.error(e.span, f"joint {k} is listed twice")
            else:
                seen.add(int(k))

    # ------------------------------------------------------------------ COOPERATE
    def cooperate_on(self, s: ast.ModalOn) -> None:
        """``COOPERATE robot IN holder [WITH VERTICAL]``: two different robots of a cell,
        neither in another open cooperation."""
        assert self.state is not None and s.robot is not None and s.name is not None
        if s.word is not None and s.word.upper() != _VERTICAL:
            self.report.error(
                s.word_span or s.span,
                f"unknown COOPERATE option '{s.word}'",
                f"COOPERATE {s.robot} IN {s.name} WITH {_VERTICAL}; keeps the tool's z axis "
                "vertical",
            )
        display = f"COOPERATE {s.robot} IN {s.name}"
        key = f"COOPERATE@{s.span.line}:{s.span.column}"  # (an error: its END still pairs)
        if not self.scope.cell:
            self.report.error(
                s.span,
                "COOPERATE needs a cell of two or more robots",
                f"this program has one robot ({self.scope.robots[0].var}); add a ROBOT clause",
            )
            self.state.open[key] = _Open(display, s.span, "COOPERATEEND")
            return
        robot = self.scope.find_robot(s.robot, s.robot_span or s.span)
        holder = self.scope.find_robot(s.name, s.name_span or s.span)
        if robot is not None and robot is holder:
            self.report.error(
                s.name_span or s.span,
                f"robot {robot.var} cannot cooperate with itself",
                "COOPERATE names the working robot, then the robot holding the workpiece",
            )
        if robot is None or holder is None or robot is holder:
            self.state.open[key] = _Open(display, s.span, "COOPERATEEND")
            return
        s.resolved = (robot.index, holder.index)
        display = f"COOPERATE {robot.var} IN {holder.var}"
        busy = self.state.cooperation_of(s.resolved)
        if busy is not None:
            both = [r.var for r in (robot, holder) if r.index in busy.robots]
            self.report.error(
                s.span,
                f"robot {both[0]} already cooperates ({busy.display}, {busy.where()})",
                "close that cooperation with COOPERATEEND first",
            )
        key = f"COOPERATE#{robot.index}"
        self.state.open[key] = _Open(display, s.span, "COOPERATEEND", s.resolved)

    def cooperate_off(self, s: ast.ModalOff) -> None:
        """COOPERATEEND: closes the innermost open COOPERATE of its statement list."""
        assert self.state is not None
        keys = [k for k in self.state.open if k.startswith("COOPERATE")]
        if keys:
            s.resolved = self.state.open.pop(keys[-1]).robots
            return
        outer = (
            self.state.outer.cooperation_of(tuple(range(len(self.scope.robots))))
            if (self.state.outer)
            else None
        )
        if outer is not None:
            self.report.error(
                s.span,
                f"COOPERATEEND closes {outer.display} of line {outer.span.line} from another "
                "statement list",
                "START and END must be in the same statement list (same block)",
            )
        else:
            hint = (
                f"start one with COOPERATE robot IN holder; ({robot_list(self.scope.robots)})"
                if self.scope.cell
                else "COOPERATE needs a cell of two or more robots"
            )
            self.report.error(
                s.span, "COOPERATEEND without an earlier COOPERATE in the same statement list", hint
            )


def _robot_name(robot: ProgramRobot | None, cell: bool) -> str:
    """How FREEZESTART's message names the robot: its model (``six``), in a cell also its
    name in the program."""
    if robot is None:
        return "the robot"
    return f"robot {robot.var} ({robot.signature.name})" if cell else robot.signature.name
