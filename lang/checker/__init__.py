"""Static checks of an IRL program: names, types, arities and the rules of docs/language.md.

The checker walks the AST once, resolves every name (case-insensitively; messages use the
declared spelling), gives every expression its type (``Expr.ty``) and folds constants
(``Expr.const``, an IRDATA :class:`Value`). Its parts, one file each:

- :mod:`.scope`: symbols, the global and local scopes, lookup, the diagnostics, the robots
  a statement names (a cell's, docs/language.md §10).
- :mod:`.cell`: the robots' names and their placements (``AT``).
- :mod:`.declarations`: constants, types, variables, routines, data-list entries.
- :mod:`.expressions`: the type of every expression, calls against their signatures.
- :mod:`.constants`: constant folding.
- :mod:`.statements`: assignments, calls, control flow, WAIT, WRITE, digital outputs.
- :mod:`.motion`: MOVE targets, WITH clauses, RECONFIGURATION.
- :mod:`.modal`: the modal redundancy START/END blocks per statement list (COOPERATE too).

:class:`Checker` runs them over a program: declarations first (global, then each routine's
signature), then each routine's body, then the main program's.
"""

from __future__ import annotations

from dataclasses import dataclass

from irlc.lang import ast
from irlc.lang import types as T
from irlc.lang.approx_lint import approx_warnings
from irlc.lang.cell import ProgramRobot
from irlc.lang.checker.cell import RobotDeclarations
from irlc.lang.checker.declarations import Declarations
from irlc.lang.checker.expressions import ExpressionTyper
from irlc.lang.checker.modal import ModalBlocks
from irlc.lang.checker.motion import MotionChecker
from irlc.lang.checker.scope import Reporter, RoutineInfo, Scope, Symbol
from irlc.lang.checker.statements import StatementChecker, always_returns
from irlc.lang.datalist import Datalist
from irlc.lang.diagnostics import Diagnostic
from irlc.lang.irdata import ObstacleDef, Slot

__all__ = ["Checked", "Checker", "RoutineInfo", "Symbol"]


@dataclass
class Checked:
    """What the code generator needs besides the annotated AST."""

    program: ast.Program
    robots: list[ProgramRobot]
    joint_names: tuple[str, ...]
    records: list[T.Record]
    globals: list[Slot]
    global_types: list[T.Type]
    routines: list[RoutineInfo]
    obstacles: list[ObstacleDef]
    inputs: dict[int, list[tuple[float, bool]]]
    datalists: list[Datalist]
    symbols: dict[str, Symbol]  # the global scope (lower-case name → symbol), for editors


class Checker:
    """Checks one program; ``diags`` holds what it found, ``check()`` the annotated result."""

    def __init__(
        self,
        program: ast.Program,
        filename: str,
        robots: list[ProgramRobot],
        datalists: list[Datalist],
        *,
        repl: bool = False,
        cooperating: tuple[tuple[int, int], ...] = (),
    ):
        self.prog = program
        self.datalists = datalists
        self.report = Reporter(filename)
        self.scope = Scope(robots, self.report)
        self.typer = ExpressionTyper(self.scope, self.report)
        self.decls = Declarations(self.scope, self.typer, self.report)
        self.robots = RobotDeclarations(self.scope, self.typer, self.report)
        motion = MotionChecker(self.scope, self.typer, self.report)
        modal = ModalBlocks(
            self.scope, self.typer, motion, self.report, repl=repl, cooperating=cooperating
        )
        self.statements = StatementChecker(self.scope, self.typer, motion, modal, self.report)

    @property
    def diags(self) -> list[Diagnostic]:
        return self.report.diags

    def check(self) -> Checked:
        p = self.prog
        for u in p.unsupported:
            self.report.error(
                u.span,
                f"{u.what} is not supported by irlc",
                "irlc runs one program on its simulated robots; remove this clause",
            )
        self.robots.declare()
        decls = self.decls
        decls.find_joint_record(p.decls)
        decls.add_datalists(self.datalists)
        decls.check_trace_columns()
        decls.declare_all(p.decls, is_global=True)
        self.robots.placements()
        for r in p.routines:
            decls.declare_routine(r)
        main = RoutineInfo(0, p.name, False, [], [], None)
        decls.routines.insert(0, main)
        for i, info in enumerate(decls.routines):
            info.index = i
        for info in decls.routines[1:]:
            self.check_routine(info)
        self.scope.routine = main
        self.statements.collect_labels(p.body)
        self.statements.check_list(p.body, p.end_span, "ENDPROGRAM", main=True)
        self.scope.routine = None
        for node, message, hint in approx_warnings(p.body):
            self.report.warning(node.span, message, hint)
        return Checked(
            p,
            self.scope.robots,
            self.scope.joint_names,
            decls.records,
            decls.global_slots,
            decls.global_types,
            decls.routines,
            list(self.scope.obstacles.values()),
            decls.inputs,
            self.datalists,
            self.scope.globals,
        )

    def check_routine(self, info: RoutineInfo) -> None:
        r = info.node
        assert r is not None
        scope = self.scope
        scope.routine = info
        scope.locals = {}
        for prm, slot, ty in zip(r.params, info.params, info.param_types, strict=True):
            sym = Symbol("param", prm.name, ty, f"line {prm.span.line}", "L", slot.index)
            scope.declare(scope.locals, prm.name, sym, prm.span)
        self.decls.declare_all(r.decls, is_global=False)
        self.statements.collect_labels(r.body)
        end_word = "ENDFCT" if r.is_function else "ENDPROC"
        self.statements.check_list(r.body, r.end_span, end_word)
        if r.is_function and not always_returns(r.body):
            self.report.warning(
                r.end_span,
                f"function '{r.name}' may end without RETURN",
                "a function that ends without RETURN stops the program with a run-time error",
            )
        info.symbols = scope.locals
        scope.locals = None
        scope.routine = None
