"""What is where in a checked program: every name written in it and what it stands for.

An :class:`Index` is built once per analysed text from the checker's annotated AST
(:class:`irlc.lang.checker.Checked`): the checker has resolved every name it met
(``Name.sym``, ``Call.sym``, ``CallStmt.sym``), and each symbol knows where it is declared
(``Symbol.span``, ``Symbol.file``). The index adds the places the checker does not
annotate — a declaration's own name, an obstacle after ``OBSTACLE``, a ``GOTO`` label, the
``ROBOT`` clause, an ``IMPORT DATALIST`` clause, a ``WITH`` option — and answers "what is at
this line and column" for hover and go to definition, and "which names are visible here"
for completion.

A cell's robots (docs/language.md §10) are found wherever a robot is named: the name of a
``ROBOT`` clause, ``MOVE name …`` (each part of a group move), ``… FOR name``,
``COOPERATE a IN b``, ``name.R_…`` and ``FK(name, k)``. A name used in a statement of one
robot (a MOVE part's targets and WITH clauses, ``JOINTLIMIT … FOR r``,
``RECONFIGURATION … FOR r``, ``FK(r, …)``) carries that robot (:attr:`Occurrence.robot`):
its joint values are that robot's.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator
from dataclasses import dataclass

from irlc.lang import ast
from irlc.lang.cell import ProgramRobot
from irlc.lang.checker import Checked, Symbol
from irlc.lang.checker.scope import RoutineInfo
from irlc.lang.diagnostics import Span
from irlc.lsp.positions import contains


@dataclass(frozen=True)
class SymbolRef:
    """A name that stands for a declared symbol (variable, constant, routine, …)."""

    symbol: Symbol


@dataclass(frozen=True)
class RobotRef:
    """The robot of the ``ROBOT`` clause (a library name or a file)."""

    name: str


@dataclass(frozen=True)
class CellRobotRef:
    """A robot of the program by its name (``ROBOT name := …``, ``MOVE name``, ``FOR name``,
    ``COOPERATE a IN b``, ``name.R_…``, ``FK(name, …)``)."""

    robot: ProgramRobot


@dataclass(frozen=True)
class RobotVariableRef:
    """A robot's own system variable, ``name.R_TOOL`` (``lang.cell.ROBOT_VARIABLES``)."""

    robot: ProgramRobot
    name: str
    type: object


@dataclass(frozen=True)
class DatalistRef:
    """The data list of an ``IMPORT DATALIST`` clause."""

    name: str


@dataclass(frozen=True)
class OptionRef:
    """A ``WITH`` option word (``SPEED``, ``APPROX``, …)."""

    word: str


@dataclass(frozen=True)
class LabelRef:
    """A ``GOTO`` target: where its label is."""

    name: str
    span: Span | None


@dataclass(frozen=True)
class ValueRef:
    """An expression the checker typed without a symbol: a record field, a built-in."""

    text: str
    type: object


Target = (SymbolRef | RobotRef | CellRobotRef | RobotVariableRef | DatalistRef | OptionRef
          | LabelRef | ValueRef)  # fmt: skip


@dataclass(frozen=True)
class Occurrence:
    span: Span
    target: Target
    robot: ProgramRobot | None = None  # the robot a value is used with (module doc)


def walk(node: object) -> Iterator[ast.Node]:
    """Every AST node under ``node`` (itself included), declarations and statements alike.

    Follows the fields of the AST's dataclasses, lists and tuples; never the checker's
    annotations (types, folded values, symbols), which are not AST nodes."""
    stack = [node]
    while stack:
        x = stack.pop()
        if isinstance(x, list | tuple):
            stack.extend(reversed(x))
        elif dataclasses.is_dataclass(x) and type(x).__module__ == ast.__name__:
            if isinstance(x, ast.Node):
                yield x
            stack.extend(
                getattr(x, f.name)
                for f in reversed(dataclasses.fields(x))
                if f.name not in ("span", "ty", "const", "sym")
            )


class Index:
    """The occurrences of a checked program, by line (see the module doc)."""

    def __init__(self, checked: Checked):
        self.checked = checked
        self.program = checked.program
        self.routines = [r for r in checked.routines if r.node is not None]
        self.robots = {r.var.lower(): r for r in checked.robots}
        self.used_with = robots_of_values(self.program, checked.robots)
        self.by_line: dict[int, list[Occurrence]] = {}
        for occurrence in self._occurrences():
            self.by_line.setdefault(occurrence.span.line, []).append(occurrence)

    def at(self, line: int, column: int) -> Occurrence | None:
        """The occurrence at ``line``:``column`` (the narrowest, when several touch it)."""
        hits = [o for o in self.by_line.get(line, ()) if contains(o.span, line, column)]
        return min(hits, key=lambda o: (o.span.end_column or o.span.column + 1) - o.span.column,
                   default=None)  # fmt: skip

    def routine_at(self, line: int) -> RoutineInfo | None:
        """The routine whose text holds ``line`` (``None``: the main program)."""
        for info in self.routines:
            node = info.node
            if node is not None and node.span.line <= line <= node.end_span.line:
                return info
        return None

    def visible(self, line: int) -> dict[str, Symbol]:
        """The symbols visible at ``line``: the routine's parameters and locals, which
        shadow the globals."""
        routine = self.routine_at(line)
        visible = dict(self.checked.symbols)
        if routine is not None:
            visible.update(routine.symbols)
        return visible

    # ------------------------------------------------------------------ building
    def _occurrences(self) -> Iterator[Occurrence]:
        p = self.program
        for clause in p.robot:
            yield Occurrence(clause.robot_span, RobotRef(clause.robot))
            yield from self._robot(clause.var_span, clause.var)
        for d in p.datalists:
            yield Occurrence(d.span, DatalistRef(d.name))
        yield from self._in_scope(p.decls, p.body, self.checked.symbols)
        for info in self.routines:
            r = info.node
            assert r is not None
            yield from self._declared(r.span, r.name, self.checked.symbols)
            for prm in r.params:
                yield from self._declared(prm.span, prm.name, info.symbols)
            scope = {**self.checked.symbols, **info.symbols}
            yield from self._in_scope(r.decls, r.body, scope, [r.params, r.result])

    def _in_scope(
        self,
        decls: ast.Decls,
        body: list[ast.Stmt],
        scope: dict[str, Symbol],
        header: list | None = None,
    ) -> Iterator[Occurrence]:
        for c in decls.consts:
            yield from self._declared(c.span, c.name, scope)
        for t in decls.types:
            yield from self._declared(t.name_span, t.name, scope)
        for v in decls.vars:
            for name, span in v.names:
                yield from self._declared(span, name, scope)
        labels = {s.name.lower(): s.span for s in ast.statements_in_order(body)
                  if isinstance(s, ast.Label)}  # fmt: skip
        for node in walk([header or [], decls.consts, decls.types, decls.vars, body]):
            yield from self._used(node, scope, labels)

    def _declared(self, span: Span, name: str, scope: dict[str, Symbol]) -> Iterator[Occurrence]:
        sym = scope.get(name.lower())
        if sym is not None and sym.span == span:
            yield Occurrence(span, SymbolRef(sym))

    def _robot(self, span: Span | None, name: str | None) -> Iterator[Occurrence]:
        """The robot ``name`` written at ``span`` (nothing when it names no robot)."""
        robot = self.robots.get(name.lower()) if name else None
        if robot is not None and span is not None:
            yield Occurrence(_name_span(span, name or ""), CellRobotRef(robot))

    def _robots_named(self, node: ast.Node) -> Iterator[Occurrence]:
        """The robots a statement names: MOVE name, FOR name, COOPERATE a IN b [WITH w]."""
        if isinstance(node, ast.Move | ast.ModalOn | ast.ModalOff | ast.Reconfigure):
            yield from self._robot(node.robot_span, node.robot)
        if isinstance(node, ast.ModalOn) and node.option == "COOPERATE":
            yield from self._robot(node.name_span, node.name)  # the holding robot
            if node.word and node.word_span:
                span = _name_span(node.word_span, node.word)
                yield Occurrence(span, OptionRef(node.word.upper()))

    def _robot_of_field(self, node: ast.Field) -> ProgramRobot | None:
        """The robot of ``name.R_…`` (None: the field of another value)."""
        base = node.base
        if not isinstance(base, ast.Name) or getattr(base.sym, "kind", None) != "robot":
            return None
        return self.robots.get(base.name.lower())

    def _used(
        self, node: ast.Node, scope: dict[str, Symbol], labels: dict[str, Span]
    ) -> Iterator[Occurrence]:
        yield from self._robots_named(node)
        sym = getattr(node, "sym", None)
        if isinstance(node, ast.Name) and sym is not None and sym.kind == "robot":
            yield from self._robot(node.span, node.name)
        elif isinstance(node, ast.Name | ast.Call | ast.CallStmt) and sym is not None:
            robot = self.used_with.get(id(node))
            yield Occurrence(_name_span(node.span, node.name), SymbolRef(sym), robot)
        elif isinstance(node, ast.Field) and (robot := self._robot_of_field(node)) is not None:
            target = RobotVariableRef(robot, node.name.upper(), node.ty)
            yield Occurrence(_name_span(node.span, node.name), target)
        elif isinstance(node, ast.Call) and node.robot is not None and node.args:
            yield Occurrence(_name_span(node.span, node.name), ValueRef("FK", node.ty))
            first = node.args[0]  # FK(robot, k)
            if isinstance(first, ast.Name):
                yield from self._robot(first.span, first.name)
        elif isinstance(node, ast.Call) and node.ty is not None:
            yield Occurrence(_name_span(node.span, node.name), ValueRef(node.name.upper(), node.ty))
        elif isinstance(node, ast.Field) and node.ty is not None:
            yield Occurrence(_name_span(node.span, node.name), ValueRef(node.name, node.ty))
        elif isinstance(node, ast.ModalOn | ast.ModalOff) and node.name and node.name_span:
            obstacle = scope.get(node.name.lower())
            if obstacle is not None and obstacle.kind == "obstacle":
                yield Occurrence(node.name_span, SymbolRef(obstacle))
        elif isinstance(node, ast.NamedTypeRef):
            named = scope.get(node.name.lower())
            if named is not None and named.kind == "type":
                yield Occurrence(_name_span(node.span, node.name), SymbolRef(named))
        elif isinstance(node, ast.Goto):
            span = _name_span(node.span, node.label)
            yield Occurrence(span, LabelRef(node.label, labels.get(node.label.lower())))
        elif isinstance(node, ast.WithClause) and node.word:
            yield Occurrence(_name_span(node.span, node.word), OptionRef(node.kind))


def robots_of_values(program: ast.Program, robots: list[ProgramRobot]) -> dict[int, ProgramRobot]:
    """The robot each name node (by its id) is used with: the names in a MOVE part's targets
    and WITH clauses, in ``JOINTLIMIT … FOR r``'s limits, ``RECONFIGURATION … FOR r``'s
    target and ``FK(r, k)``'s joints, where the checker resolved the statement's robot."""
    found: dict[int, ProgramRobot] = {}

    def mark(robot: ProgramRobot, exprs: list) -> None:
        for node in walk(exprs):
            if isinstance(node, ast.Name):
                found[id(node)] = robot

    for node in walk([program.body, *(r.body for r in program.routines)]):
        if isinstance(node, ast.Call) and isinstance(node.robot, ProgramRobot):
            mark(node.robot, node.args[1:])
            continue
        resolved = getattr(node, "resolved", ())
        if not resolved or not 0 <= resolved[0] < len(robots):
            continue
        robot = robots[resolved[0]]
        if isinstance(node, ast.Move):
            mark(robot, [node.targets, [c.args for c in node.clauses]])
        elif isinstance(node, ast.ModalOn) and node.option != "COOPERATE":
            mark(robot, node.args)
        elif isinstance(node, ast.Reconfigure):
            mark(robot, [node.target])
    return found


def _name_span(span: Span, name: str) -> Span:
    """``span`` as the name's own extent (the builder's spans start at the name)."""
    if span.end_line == span.line and span.end_column > span.column:
        return span
    return Span(span.line, span.column, span.line, span.column + len(name))
