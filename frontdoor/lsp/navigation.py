"""Go to definition and the document's symbols (the outline).

Definitions: a variable, parameter, constant, type or routine → its declaration; a
data-list entry or obstacle → its key in the ``.toml``; ``IMPORT DATALIST name`` → that
file; the ``ROBOT`` clause → the robot's description file; a robot's name (``MOVE name``,
``FOR name``, ``COOPERATE a IN b``, ``name.R_…``) → its ``ROBOT`` clause; ``GOTO l`` → the
label. The outline lists the program's robots, constants, types, variables and routines
(with their parameters and locals), from the parsed program: it needs no robot file.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from irlc.lang import ast
from irlc.lang import datalist as dlmod
from irlc.lang.diagnostics import Span
from irlc.lsp.index import CellRobotRef, DatalistRef, LabelRef, RobotRef, SymbolRef, Target
from lsprotocol import types

# (file, span) → Location: the server converts with the file's text (open or on disk)
Locate = Callable[[Path, Span | None], types.Location]


def definition(
    target: Target, program: Path, datalist_path: tuple[str, ...], allow_any_path: bool,
    locate: Locate,
) -> types.Location | None:  # fmt: skip
    if isinstance(target, SymbolRef):
        sym = target.symbol
        if sym.span is None:
            return None  # a system variable, an entry that failed its check
        return locate(Path(sym.file) if sym.file else program, sym.span)
    if isinstance(target, LabelRef):
        return locate(program, target.span) if target.span else None
    if isinstance(target, CellRobotRef):
        clause = target.robot.clause
        return locate(program, clause.var_span or clause.span) if clause is not None else None
    if isinstance(target, DatalistRef):
        path, _ = dlmod.find(target.name, program.parent, datalist_path)
        return locate(path, None) if path is not None else None
    if isinstance(target, RobotRef):
        from irlc.robots import RobotFileError, resolve_robot

        try:
            model = resolve_robot(target.name, program.parent, restricted=not allow_any_path)
        except RobotFileError:
            return None
        return locate(Path(model.source), None) if model.source else None
    return None


def document_symbols(
    program: ast.Program, rng: Callable[[Span], types.Range]
) -> list[types.DocumentSymbol]:
    """The outline: robots, constants, types, variables, then the routines with their
    insides."""
    out = [_symbol(c.var, types.SymbolKind.Object, c.var_span or c.span, rng, _robot(c))
           for c in program.robot]  # fmt: skip
    out += _declarations(program.decls, rng)
    for r in program.routines:
        children = [_symbol(p.name, types.SymbolKind.Variable, p.span, rng, _type(p.type))
                    for p in r.params]  # fmt: skip
        children += _declarations(r.decls, rng)
        kind = types.SymbolKind.Function if r.is_function else types.SymbolKind.Method
        whole = Span(r.span.line, r.span.column, r.end_span.end_line or r.end_span.line,
                     r.end_span.end_column or r.end_span.column)  # fmt: skip
        detail = "FUNCTION" if r.is_function else "PROCEDURE"
        symbol = _symbol(r.name, kind, r.span, rng, detail, children)
        symbol.range = rng(whole)
        out.append(symbol)
    return out


def _declarations(decls: ast.Decls, rng) -> list[types.DocumentSymbol]:
    out = []
    for d in decls.order:
        if isinstance(d, ast.ConstDecl):
            out.append(_symbol(d.name, types.SymbolKind.Constant, d.span, rng, "CONST"))
        elif isinstance(d, ast.TypeDecl):
            out.append(_symbol(d.name, types.SymbolKind.Struct, d.name_span, rng, "TYPE"))
        elif isinstance(d, ast.VarDecl):
            for name, span in d.names:
                out.append(_symbol(name, types.SymbolKind.Variable, span, rng, _type(d.type)))
    return out


def _symbol(name, kind, span, rng, detail, children=None) -> types.DocumentSymbol:
    r = rng(span)
    return types.DocumentSymbol(
        name=name, kind=kind, range=r, selection_range=r, detail=detail, children=children
    )


def _robot(clause: ast.RobotClause) -> str:
    """``ROBOT as6 AT (0, -1500, 0, 90, 0, 0)``: its robot and placement as written (the
    outline needs no checker; an expression it does not show is ``…``)."""
    at = clause.at
    if at is None:
        return f"ROBOT {clause.robot}"
    if isinstance(at, ast.Name):
        shown = at.name
    elif isinstance(at, ast.Tuple):
        shown = "(" + ", ".join(ast.literal_text(e) or "…" for e in at.items) + ")"
    else:
        shown = "…"
    return f"ROBOT {clause.robot} AT {shown}"


def _type(ref: ast.TypeRef) -> str:
    """A declared type as written (the outline needs no checker)."""
    if isinstance(ref, ast.SimpleTypeRef | ast.NamedTypeRef):
        return ref.name
    if isinstance(ref, ast.ArrayTypeRef):
        lo, hi = (ast.literal_text(e) or "…" for e in (ref.lo, ref.hi))
        return f"ARRAY [{lo}..{hi}] OF {_type(ref.elem)}"
    return "RECORD"
