"""The modal redundancy statements: START/END blocks per statement list.

JOINTLIMIT / JOINTSPEEDLIMIT / JOINTACCELLIMIT … END, CYCLICSTART … CYCLICEND,
OBSTACLE name … OBSTACLEEND name and FREEZESTART … FREEZEEND are checked per statement list:
an END needs an earlier START of the same kind in the same list, a START is not repeated
while it is open (also from an enclosing list), and every START is closed before its list
ends. ``repl`` mode skips the two pairing checks (the interpreter checks them at run time).
"""

from __future__ import annotations

from irlc.lang import ast
from irlc.lang import types as T
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
}
_END_WORD = {
    **{o.word: o.end_word for o in LIMIT_OPTIONS},
    "CYCLIC": "CYCLICEND",
    "OBSTACLE": "OBSTACLEEND",
    "FREEZE": "FREEZEEND",
}


class _ListState:
    def __init__(self, outer: _ListState | None):
        self.outer = outer
        self.open: dict[str, tuple[str, Span]] = {}  # key -> (display, START span)

    def find_open(self, key: str) -> Span | None:
        s: _ListState | None = self
        while s is not None:
            if key in s.open:
                return s.open[key][1]
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
    ):
        self.scope = scope
        self.typer = typer
        self.motion = motion
        self.report = report
        self.repl = repl
        self.state: _ListState | None = None

    def enter_list(self) -> None:
        """A statement list starts: its own START statements open in it."""
        self.state = _ListState(self.state)

    def leave_list(self, end_span: Span, end_word: str) -> None:
        """The list ends at ``end_word`` (line of ``end_span``): report what is still open."""
        assert self.state is not None
        if not self.repl:
            for key, (display, span) in self.state.open.items():
                opt = key.split(":")[0]
                closing = _END_WORD[opt] + (f" {display.split()[-1]}" if opt == "OBSTACLE" else "")
                self.report.error(
                    span,
                    f"{display} is not closed before {end_word} (line {end_span.line})",
                    f"add {closing}; in the same statement list",
                )
        self.state = self.state.outer

    def s_modalon(self, s: ast.ModalOn) -> None:
        assert self.state is not None
        if s.option in LIMIT_TYPES:
            self.motion.limit_pair(s.option, s.args[0], s.args[1], s.option)
        elif s.option == "FREEZE":
            self.freeze_joints(s)
        opened = self.modal_key(s)
        if opened is None:
            return
        key, display = opened
        prev = self.state.find_open(key)
        if prev is not None:
            self.report.error(
                s.span,
                f"{display} is already on (since line {prev.line})",
                f"close it with {_END_WORD[s.option]} first",
            )
        self.state.open[key] = (display, s.span)

    def s_modaloff(self, s: ast.ModalOff) -> None:
        assert self.state is not None
        closed = self.modal_key(s)
        if closed is None:
            return
        key, display = closed
        if key in self.state.open:
            del self.state.open[key]
            return
        if self.repl:
            return
        outer = self.state.outer.find_open(key) if self.state.outer else None
        end = _END_WORD[s.option] + (f" {s.name}" if s.name else "")
        if outer is not None:
            self.report.error(
                s.span,
                f"{end} closes {display} of line {outer.line} from another statement list",
                "START and END must be in the same statement list (same block)",
            )
        elif s.option == "OBSTACLE":
            active = [d for d, _ in self.state.open.values() if d.startswith("OBSTACLE ")]
            self.report.error(
                s.name_span or s.span,
                f"OBSTACLEEND {s.name}: obstacle '{s.name}' is not active here",
                f"active obstacles: {', '.join(a.split()[1] for a in active)}"
                if active
                else f"switch it on first with OBSTACLE {s.name};",
            )
        else:
            self.report.error(
                s.span, f"{end} without an earlier {display} in the same statement list"
            )

    def modal_key(self, s: ast.ModalOn | ast.ModalOff) -> tuple[str, str] | None:
        """``(key, display)`` of the option a START/END names; None: unknown obstacle."""
        if s.option != "OBSTACLE":
            return s.option, _START_WORD[s.option]
        assert s.name is not None
        o = self.scope.obstacles.get(s.name.lower())
        if o is None:
            self.unknown_obstacle(s.name, s.name_span or s.span)
            return None
        return f"OBSTACLE:{o.name.lower()}", f"OBSTACLE {o.name}"

    def unknown_obstacle(self, name: str, span: Span) -> None:
        known = sorted(o.name for o in self.scope.obstacles.values())
        hint = (
            f"known obstacles: {shown_names(known)}"
            if known
            else "define obstacles in an imported data list: [obstacles.NAME]"
        )
        self.report.error(span, f"unknown obstacle '{name}'", hint)

    def freeze_joints(self, s: ast.ModalOn) -> None:
        seen: set[int] = set()
        for e in s.args:
            t = self.typer.expr(e, T.INTEGER)
            k = number(e.const)
            if t == T.ERROR:
                continue
            if t != T.INTEGER or k is None:
                self.report.error(e.span, "FREEZESTART takes joint numbers (INTEGER constants)")
            elif self.scope.n and not 1 <= k <= self.scope.n:
                name = self.scope.robot.name if self.scope.robot else "the robot"
                self.report.error(
                    e.span, f"joint {k} does not exist: {name} has joints 1..{self.scope.n}"
                )
            elif k in seen:
                self.report.error(e.span, f"joint {k} is listed twice")
            else:
                seen.add(int(k))
