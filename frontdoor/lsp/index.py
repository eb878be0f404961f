"""What is where in a checked program: every name written in it and what it stands for.

An :class:`Index` is built once per analysed text from the checker's annotated AST
(:class:`irlc.lang.checker.Checked`): the checker has resolved every name it met
(``Name.sym``, ``Call.sym``, ``CallStmt.sym``), and each symbol knows where it is declared
(``Symbol.span``, ``Symbol.file``). The index adds the places the checker does not
annotate — a declaration's own name, an obstacle after ``OBSTACLE``, a ``GOTO`` label, the
``ROBOT`` clause, an ``IMPORT DATALIST`` clause, a ``WITH`` option — and answers "what is at
this line and column" for hover and go to definition, and "which names are visible here"
for completion.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator
from dataclasses import dataclass

from irlc.lang import ast
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


Target = SymbolRef | RobotRef | DatalistRef | OptionRef | LabelRef | ValueRef


@dataclass(frozen=True)
class Occurrence:
    span: Span
    target: Target


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
            yield from self._declared(clause.span, clause.var, self.checked.symbols)
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

    def _used(
        self, node: ast.Node, scope: dict[str, Symbol], labels: dict[str, Span]
    ) -> Iterator[Occurrence]:
        sym = getattr(node, "sym", None)
        if isinstance(node, ast.Name | ast.Call | ast.CallStmt) and sym is not None:
            yield Occurrence(_name_span(node.span, node.name), SymbolRef(sym))
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


def _name_span(span: Span, name: str) -> Span:
    """``span`` as the name's own extent (the builder's spans start at the name)."""
    if span.end_line == span.line and span.end_column > span.column:
        return span
    return Span(span.line, span.column, span.line, span.column + len(name))
