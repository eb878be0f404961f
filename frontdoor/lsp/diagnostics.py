"""The compiler's diagnostics as LSP diagnostics, each in the file it is about.

A program's own diagnostics keep their exact ranges. A data list's problem (a ``.toml``
the program imports: a wrong shape, a TOML syntax error, a name defined twice) is shown
twice: on the program's ``IMPORT DATALIST`` line (its message prefixed with the file and
line, with a link to the place when the client takes related information), and in the
data list itself — :func:`datalist_diagnostics`, published while it is open in the editor.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from pathlib import Path

from irlc.lang import ast
from irlc.lang.diagnostics import Diagnostic
from irlc.lsp.positions import SourceLines
from lsprotocol import types

SOURCE = "irlc"
SEVERITY = {
    "error": types.DiagnosticSeverity.Error,
    "warning": types.DiagnosticSeverity.Warning,
    "note": types.DiagnosticSeverity.Information,
}


def message(d: Diagnostic) -> str:
    """The message with its hint and notes, as ``irlc check`` prints them."""
    parts = [d.message]
    if d.hint:
        parts.append(f"hint: {d.hint}")
    parts += [f"note: {n}" for n in d.notes]
    return "\n".join(parts)


def to_lsp(d: Diagnostic, lines: SourceLines, related=None) -> types.Diagnostic:
    return types.Diagnostic(
        range=lines.range(d.span),
        message=message(d),
        severity=SEVERITY.get(d.severity, types.DiagnosticSeverity.Information),
        source=SOURCE,
        related_information=related,
    )


def program_diagnostics(
    diagnostics: Iterable[Diagnostic],
    program: Path,
    lines: SourceLines,
    datalist_clauses: dict[str, ast.DatalistClause],
    location: Callable[[Diagnostic], types.Location | None] | None,
) -> list[types.Diagnostic]:
    """The diagnostics to show in the program: its own, and each data list's on its
    importing line (``datalist_clauses``: the data list's file → its clause)."""
    out = []
    for d in diagnostics:
        if d.file == str(program):
            out.append(to_lsp(d, lines))
            continue
        clause = datalist_clauses.get(d.file)
        if clause is None:
            continue
        where = Path(d.file).name + (f":{d.span.line}" if d.span else "")
        shown = Diagnostic(d.severity, f"{where}: {d.message}", d.file, clause.span, d.hint)
        place = location(d) if location is not None else None
        related = [types.DiagnosticRelatedInformation(place, d.message)] if place else None
        out.append(to_lsp(shown, lines, related))
    return out


def datalist_diagnostics(
    diagnostics: Iterable[Diagnostic], datalist: Path, lines: SourceLines
) -> list[types.Diagnostic]:
    """The diagnostics about ``datalist`` itself, once each."""
    out, seen = [], set()
    wanted = datalist.resolve()
    for d in diagnostics:
        if (d.span, d.message) in seen or Path(d.file).resolve() != wanted:
            continue
        seen.add((d.span, d.message))
        out.append(to_lsp(d, lines))
    return out
