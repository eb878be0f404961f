"""Motion statements: MOVE targets, WITH clauses and RECONFIGURATION.

A MOVE's targets are typed by its kind (PTP: a POSE or a MAIN_JOINT; PTPINC: a MAIN_JOINT
increment; the path motions: POSEs). Each WITH clause is given at most once: a setting
(SPEED, ACC, …) must be accepted by the motion kind and, when constant, lie in its range
(the settings table, lang/settings.py); a limit pair (JOINTLIMIT …) takes the minimum then
the maximum tuple, minimum ≤ maximum per joint when constant; RECONFIGURATION gives one
MAIN_JOINT per point (or one for a whole multi-point LIN).
"""

from __future__ import annotations

from irlc.lang import ast
from irlc.lang import types as T
from irlc.lang.checker.constants import number
from irlc.lang.checker.expressions import ExpressionTyper
from irlc.lang.checker.scope import Reporter, Scope
from irlc.lang.diagnostics import Span
from irlc.lang.settings import (
    BY_LIMIT_WORD,
    BY_WITH_WORD,
    KIND_WORDS,
    approximation_hint,
    reconfiguration_counts,
    setting_message,
)

LIMIT_TYPES = {o.word: o.types for o in BY_LIMIT_WORD.values()}
"""The limit options and their (minimum, maximum) joint-tuple types (lang/settings.py)."""
_WITH_PARAMS = tuple(BY_WITH_WORD)  # SPEED ACC SPEED_ORI SPEED_PTP ACC_PTP TIME


class MotionChecker:
    """Checks MOVE and RECONFIGURATION statements and the constant settings."""

    def __init__(self, scope: Scope, typer: ExpressionTyper, report: Reporter):
        self.scope = scope
        self.typer = typer
        self.report = report

    def s_move(self, s: ast.Move) -> None:
        for t in s.targets:
            self.move_target(s, t)
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
            self.with_clause(s, c)

    def move_target(self, s: ast.Move, t: ast.Expr) -> None:
        joint = self.scope.main_joint()
        if s.kind == "PTP":
            if isinstance(t, ast.Tuple):
                n = len(t.items)
                want = joint if n == self.scope.n or n != 6 else T.POSE
                got = self.typer.expr(t, want)
                return
            got = self.typer.expr(t, None)
            if got not in (T.POSE, T.ERROR) and got != joint:
                self.report.error(
                    t.span, f"MOVE PTP needs a POSE or a MAIN_JOINT target, got {got}"
                )
            return
        want = joint if s.kind == "PTPINC" else T.POSE
        got = self.typer.expr(t, want)
        self.typer.require(t, want, got, f"{KIND_WORDS[s.kind]} target")

    def with_clause(self, s: ast.Move, c: ast.WithClause) -> None:
        ptp = s.kind in ("PTP", "PTPINC")
        if c.kind in LIMIT_TYPES:
            self.limit_pair(c.kind, c.args[0], c.args[1], f"WITH {c.kind}")
            return
        if c.kind == "RECONF":
            self.reconf_clause(s, c)
            return
        if c.kind not in _WITH_PARAMS:
            self.report.error(
                c.span,
                f"unknown WITH option '{c.word}'",
                approximation_hint(c.word)
                or f"WITH options: {', '.join((*_WITH_PARAMS, *LIMIT_TYPES))}, RECONFIGURATION",
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

    def reconf_clause(self, s: ast.Move, c: ast.WithClause) -> None:
        joint = self.scope.main_joint()
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
            got = self.typer.expr(k, joint)
            self.typer.require(k, joint, got, "WITH RECONFIGURATION")
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
        if s.kind in ("PTP", "PTPINC") and s.targets and s.targets[0].ty == joint:
            self.report.error(
                c.span,
                "WITH RECONFIGURATION needs a POSE target",
                "a MAIN_JOINT target already fixes the configuration",
            )

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

    def limit_pair(self, option: str, lo: ast.Expr, hi: ast.Expr, what: str) -> None:
        lo_name, hi_name = LIMIT_TYPES[option]
        lo_t, hi_t = T.JointTuple(lo_name, self.scope.n), T.JointTuple(hi_name, self.scope.n)
        got_lo, got_hi = self.typer.expr(lo, lo_t), self.typer.expr(hi, hi_t)
        if got_lo == hi_t and got_hi == lo_t:
            self.report.error(
                lo.span,
                f"{what} takes {lo_name} then {hi_name}: the arguments are swapped",
                f"write {what.split()[-1]} {_text(hi)}, {_text(lo)}",
            )
            return
        ok = self.typer.require(lo, lo_t, got_lo, f"{what}, first argument")
        ok = self.typer.require(hi, hi_t, got_hi, f"{what}, second argument") and ok
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
        joint = self.scope.main_joint()
        got = self.typer.expr(s.target, joint)
        self.typer.require(s.target, joint, got, "RECONFIGURATION")


def _fmt(x: float) -> str:
    return f"{x:g}"


def _text(e: ast.Expr) -> str:
    if isinstance(e, ast.Name):
        return e.name
    return "..."
