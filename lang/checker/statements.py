"""Statements: assignments, calls, control flow, WAIT, WRITE and the digital outputs.

:class:`StatementChecker` checks each statement list in order; motion statements go to
:class:`.MotionChecker`, the modal START/END statements to :class:`.ModalBlocks` (which
also tracks the blocks each list opens). GOTO targets are the labels of the routine being
checked (collected before its body); an assignment to a system variable that is a motion
setting is range-checked when constant, as ``WITH`` is.
"""

from __future__ import annotations

from irlc.lang import ast, foreign
from irlc.lang import types as T
from irlc.lang.builtins import BUILTINS
from irlc.lang.checker.constants import number
from irlc.lang.checker.expressions import ExpressionTyper
from irlc.lang.checker.modal import ModalBlocks
from irlc.lang.checker.motion import MotionChecker
from irlc.lang.checker.scope import Reporter, Scope, Symbol
from irlc.lang.diagnostics import Span
from irlc.lang.digital_io import pulse_error
from irlc.lang.irdata import Value
from irlc.lang.platform import SETTING as PLATFORM_SETTING
from irlc.lang.settings import BY_SYSTEM_VARIABLE, SettingChoices


class StatementChecker:
    """Checks statement lists in the current scope."""

    def __init__(
        self,
        scope: Scope,
        typer: ExpressionTyper,
        motion: MotionChecker,
        modal: ModalBlocks,
        report: Reporter,
    ):
        self.scope = scope
        self.typer = typer
        self.motion = motion
        self.modal = modal
        self.report = report
        self.labels: dict[str, ast.Label] = {}
        self._elsewhere = {  # statement class (lower case) -> its checker elsewhere
            "move": motion.s_move,
            "movegroup": motion.s_movegroup,
            "reconfigure": motion.s_reconfigure,
            "modalon": modal.s_modalon,
            "modaloff": modal.s_modaloff,
        }

    def check_list(
        self, stmts: list[ast.Stmt], end_span: Span, end_word: str, main: bool = False
    ) -> None:
        """One statement list, ended by ``end_word`` at ``end_span`` (for open blocks);
        ``main``: the program's main body."""
        self.modal.enter_list(main)
        for s in stmts:
            name = type(s).__name__.lower()
            handler = self._elsewhere.get(name) or getattr(self, f"s_{name}")
            handler(s)
        self.modal.leave_list(end_span, end_word)

    def collect_labels(self, body: list[ast.Stmt]) -> None:
        self.labels = {}
        for s in ast.statements_in_order(body):
            if isinstance(s, ast.Label):
                prev = self.labels.get(s.name.lower())
                if prev is not None:
                    self.report.error(
                        s.span, f"label '{s.name}' is already defined on line {prev.span.line}"
                    )
                else:
                    self.labels[s.name.lower()] = s

    def s_label(self, s: ast.Label) -> None:
        pass

    def s_assign(self, s: ast.Assign) -> None:
        if self.typer.is_output(s.target):
            self.s_output(s)
            return
        node = s.target  # robot.R_TOOL …: the checker marks the robot's variable (Field.sym)
        while isinstance(node, ast.Field | ast.Index):
            if isinstance(node, ast.Field):
                self.typer.robot_field(node)
            node = node.base
        root = assignment_root(s.target)
        if isinstance(root, ast.Field):  # robot.R_TOOL: a robot's own system variable
            sym: Symbol | None = self.typer.robot_field(root)
        else:
            sym = self.scope.lookup(root.name)
        reported = sym is not None and sym.kind == "sysvar" and sym.type == T.ERROR
        if sym is not None and (reported or self.scope.robot_variable_problem(sym, root.span)):
            self.typer.after_error(s.value)
            return
        if sym is None:
            hint = self.scope.suggest(root.name)
            self.report.error(root.span, f"unknown name '{root.name}'", hint)
            self.typer.after_error(s.value)
            return
        if sym.kind not in ("var", "param", "sysvar"):
            what = {
                "const": "a constant",
                "routine": "a routine",
                "type": "a type",
                "robot": "the robot",
                "obstacle": "an obstacle",
            }.get(sym.kind, sym.kind)
            self.report.error(root.span, f"cannot assign to '{sym.name}': it is {what}")
            self.typer.after_error(s.value)
            return
        if not sym.writable:
            self.report.error(root.span, f"{sym.name} is read-only")
            return
        if sym.type == T.SIGNAL and s.target is not root:
            self.report.error(s.target.span, "a SIGNAL is assigned as a whole")
            return
        want = self.target_type(s.target, sym)
        if want is None:
            self.typer.expr(s.value, None)
            return
        if self.unquoted_word(s, sym):
            return
        got = self.typer.expr(s.value, want)
        ok = self.typer.require(
            s.value, want, got, f"cannot assign to '{_describe(s.target, sym)}'"
        )
        if ok and s.target is root and sym.name in BY_SYSTEM_VARIABLE and sym.kind == "sysvar":
            self.motion.constant_setting(BY_SYSTEM_VARIABLE[sym.name].field, s.value, sym.name)
            if sym.name == PLATFORM_SETTING:
                self.motion.platform.hold_setting(s.value)

    def unquoted_word(self, s: ast.Assign, sym: Symbol) -> bool:
        """``R_CRITERION := ENERGY``: a word setting given an unknown bare name — say that
        its words are quoted (reported; True) instead of "unknown name"."""
        setting = BY_SYSTEM_VARIABLE.get(sym.name) if sym.kind == "sysvar" else None
        value = s.value
        if setting is None or not isinstance(setting.range, SettingChoices):
            return False
        if not isinstance(value, ast.Name) or self.scope.lookup(value.name) is not None:
            return False
        word = value.name.upper()
        example = word if word in setting.range.words else setting.range.words[0]
        self.report.error(
            value.span,
            f"{sym.name} takes a quoted word: {setting.range}",
            f"write {sym.name} := '{example}'",
        )
        return True

    def target_type(self, target: ast.Expr, sym: Symbol) -> T.Type | None:
        if isinstance(target, ast.Name) or target is assignment_root(target):
            target.sym = sym
            target.ty = sym.type
            return None if sym.type == T.ERROR else sym.type
        t = self.typer.expr(target, None)
        return None if t == T.ERROR else t

    def s_callstmt(self, s: ast.CallStmt) -> None:
        sym = self.scope.lookup(s.name)
        if sym is None and s.name.upper() == "PULSE":
            self.s_pulse(s)
            return
        if sym is None or sym.kind != "routine":
            up = s.name.upper()
            if sym is None and (up in BUILTINS or up == "POSE"):
                self.report.error(
                    s.span, f"'{s.name}' is a built-in function: use its value in an expression"
                )
            elif sym is None:
                self.report.error(
                    s.span,
                    f"unknown procedure '{s.name}'",
                    self.scope.suggest(s.name, kinds=("routine",))
                    or foreign.statement_hint(s.name, ""),
                )
            else:
                self.report.error(s.span, f"'{sym.name}' is not a procedure")
            for a in s.args:
                self.typer.expr(a, None)
            return
        s.sym = sym
        assert sym.routine is not None
        self.typer.args(s, sym.routine)

    def s_return(self, s: ast.Return) -> None:
        r = self.scope.routine
        if r is None or r.index == 0:
            self.report.error(
                s.span,
                "RETURN outside a procedure or function",
                "use HALT to stop the main program",
            )
            return
        if r.is_function:
            if s.value is None:
                self.report.error(s.span, f"function '{r.name}' must return a value: RETURN expr")
                return
            got = self.typer.expr(s.value, r.result)
            self.typer.require(s.value, r.result or T.ERROR, got, f"RETURN of '{r.name}'")
        elif s.value is not None:
            self.report.error(
                s.value.span,
                f"procedure '{r.name}' cannot return a value",
                "declare it as FUNCTION name(...): TYPE",
            )

    def cond(self, e: ast.Expr, what: str) -> None:
        t = self.typer.expr(e, T.BOOLEAN)
        if t not in (T.BOOLEAN, T.ERROR):
            self.report.error(e.span, f"the condition of {what} must be BOOLEAN, got {t}")

    def s_if(self, s: ast.If) -> None:
        for k, (c, body) in enumerate(s.arms):
            self.cond(c, "IF" if k == 0 else "ELSIF")
            last = k == len(s.arms) - 1 and s.else_body is None
            self.check_list(
                body, s.end_span, "ENDIF" if last else "the next ELSIF/ELSE of the IF ending"
            )
        if s.else_body is not None:
            self.check_list(s.else_body, s.end_span, "ENDIF")

    def s_while(self, s: ast.While) -> None:
        self.cond(s.cond, "WHILE")
        self.check_list(s.body, s.end_span, "ENDWHILE")

    def s_repeat(self, s: ast.Repeat) -> None:
        self.check_list(s.body, s.end_span, "UNTIL")
        self.cond(s.cond, "UNTIL")

    def s_for(self, s: ast.For) -> None:
        sym = self.scope.lookup(s.var.name)
        if sym is None:
            self.report.error(
                s.var.span, f"unknown name '{s.var.name}'", "declare it: VAR INTEGER: i;"
            )
        elif sym.kind not in ("var", "param") or sym.type != T.INTEGER:
            self.report.error(
                s.var.span, f"the FOR variable '{sym.name}' must be an INTEGER variable"
            )
        else:
            s.var.sym, s.var.ty = sym, T.INTEGER
        for e, what in ((s.start, "start"), (s.stop, "end")):
            t = self.typer.expr(e, T.INTEGER)
            self.typer.require(e, T.INTEGER, t, f"FOR {what} value")
        if s.step is not None:
            t = self.typer.expr(s.step, T.INTEGER)
            k = number(s.step.const)
            if t != T.ERROR and (t != T.INTEGER or k is None):
                self.report.error(s.step.span, "the BY step must be an INTEGER constant")
            elif k == 0:
                self.report.error(s.step.span, "the BY step must not be 0")
        self.check_list(s.body, s.end_span, "ENDFOR")

    def s_case(self, s: ast.Case) -> None:
        t = self.typer.expr(s.selector, None)
        if t not in (T.INTEGER, T.CHAR, T.BOOLEAN, T.STRING, T.ERROR):
            self.report.error(
                s.selector.span, f"CASE needs an INTEGER, CHAR, STRING or BOOLEAN, got {t}"
            )
            t = T.ERROR
        seen: dict[object, int] = {}
        for arm in s.arms:
            for lo, hi in arm.labels:
                self.case_label(t, lo, hi, seen)
            self.check_list(arm.body, s.end_span, "the next CASE label")
        if s.else_body is not None:
            self.check_list(s.else_body, s.end_span, "ENDCASE")

    def case_label(self, sel: T.Type, lo: ast.Expr, hi: ast.Expr | None, seen: dict) -> None:
        for e in (lo, hi):
            if e is None:
                continue
            lt = self.typer.expr(e, T.CHAR if sel == T.CHAR else None)
            ok = (
                sel == T.ERROR
                or lt == sel
                or (sel == T.STRING and lt == T.CHAR)
                or (
                    sel == T.CHAR
                    and lt == T.STRING
                    and isinstance(e, ast.Str)
                    and len(e.value) == 1
                )
            )
            if not ok:
                self.report.error(e.span, f"CASE label of type {lt} for a {sel} selector")
                return
            if sel == T.CHAR and isinstance(e, ast.Str):
                e.const = Value("CHAR", (e.value,))
        if hi is not None and sel not in (T.INTEGER, T.CHAR, T.ERROR):
            self.report.error(hi.span, "ranges lo..hi are for INTEGER and CHAR labels")
            return
        lo_v = lo.const.data[0] if lo.const else None
        hi_v = hi.const.data[0] if hi is not None and hi.const else lo_v
        if hi is not None and lo_v is not None and hi_v is not None and hi_v < lo_v:
            self.report.error(lo.span, f"empty CASE range {lo_v}..{hi_v}")
            return
        if isinstance(lo_v, int) and isinstance(hi_v, int) and hi_v - lo_v < 10_000:
            values = range(lo_v, hi_v + 1)
        else:
            values = [lo_v] if hi is None else []
        for v in values:
            if v in seen:
                self.report.error(
                    lo.span, f"CASE label {v!r} is repeated (first on line {seen[v]})"
                )
                return
            seen[v] = lo.span.line

    def s_goto(self, s: ast.Goto) -> None:
        if s.label.lower() not in self.labels:
            known = ", ".join(lb.name for lb in self.labels.values())
            self.report.error(
                s.span,
                f"unknown label '{s.label}'",
                f"labels of this routine: {known}"
                if known
                else "declare a label with 'name:' before a statement in the same routine",
            )

    def s_wait(self, s: ast.Wait) -> None:
        t = self.typer.expr(s.seconds, T.REAL)
        if self.typer.require(s.seconds, T.REAL, t, "WAIT time"):
            k = number(s.seconds.const)
            if k is not None and k < 0:
                self.report.error(s.seconds.span, f"WAIT time must not be negative, got {k}")

    def s_waitfor(self, s: ast.WaitFor) -> None:
        self.cond(s.cond, "WAIT FOR")

    def s_pause(self, s: ast.Pause) -> None:
        pass

    def s_halt(self, s: ast.Halt) -> None:
        pass

    def s_write(self, s: ast.Write) -> None:
        for a in s.args:
            self.typer.expr(a, None)

    def s_output(self, s: ast.Assign) -> None:
        """``OUT[n] := b;``"""
        assert isinstance(s.target, ast.Index)
        self.typer.e_output(s.target)
        got = self.typer.expr(s.value, T.BOOLEAN)
        self.typer.require(s.value, T.BOOLEAN, got, "cannot assign to 'OUT[…]'")

    def s_pulse(self, s: ast.CallStmt) -> None:
        """``PULSE(OUT[n], t);`` with ``t`` seconds (in range when constant)."""
        s.pulse = True
        if len(s.args) != 2 or not self.typer.is_output(s.args[0]):
            self.report.error(
                s.span, "PULSE needs an output and a duration: PULSE(OUT[n], seconds)"
            )
            for a in s.args:
                self.typer.expr(a, None)
            return
        self.typer.e_output(s.args[0])  # type: ignore[arg-type]
        got = self.typer.expr(s.args[1], T.REAL)
        if got != T.ERROR and not got.is_numeric:
            self.report.error(
                s.args[1].span, f"PULSE: the duration must be a number of seconds, got {got}"
            )
            return
        k = number(s.args[1].const)
        if k is not None and pulse_error(k) is not None:
            self.report.error(s.args[1].span, str(pulse_error(k)))


def assignment_root(target: ast.Expr) -> ast.Name | ast.Field:
    """The variable an assignment stores into: the name under the target's fields and
    elements, or a robot's system variable ``robot.R_TOOL`` (a Field the checker marked
    with its ``sym``)."""
    node = target
    while isinstance(node, ast.Field | ast.Index):
        if isinstance(node, ast.Field) and node.sym is not None:
            return node
        node = node.base
    assert isinstance(node, ast.Name)
    return node


def always_returns(body: list[ast.Stmt]) -> bool:
    """Whether every path through ``body`` ends in RETURN or HALT."""
    for s in body:
        if isinstance(s, ast.Return | ast.Halt):
            return True
        if isinstance(s, ast.If) and s.else_body is not None:
            branches = [b for _, b in s.arms] + [s.else_body]
            if all(always_returns(b) for b in branches):
                return True
        if isinstance(s, ast.Case) and s.else_body is not None:
            branches = [a.body for a in s.arms] + [s.else_body]
            if all(always_returns(b) for b in branches):
                return True
        if isinstance(s, ast.Repeat) and always_returns(s.body):
            return True
    return False


def _describe(target: ast.Expr, sym: Symbol) -> str:
    if isinstance(target, ast.Field) and target.sym is sym and isinstance(target.base, ast.Name):
        return f"{target.base.name}.{sym.name}"  # robot.R_TOOL
    if isinstance(target, ast.Name):
        return sym.name
    if isinstance(target, ast.Field):
        return f"{_describe(target.base, sym)}.{target.name}"
    if isinstance(target, ast.Index):
        return f"{_describe(target.base, sym)}[...]"
    return sym.name
