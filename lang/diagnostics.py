"""Diagnostics carried as values: ``FILE:LINE:COL: error: message`` + source line + caret + hint.

Every stage of the front end (lexer, parser, checker, data-list loader, assembler)
reports problems as :class:`Diagnostic` values with positions; nothing in the
front end prints or raises for bad user input except :class:`CompileError`,
which carries the diagnostics to the caller.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

from irlc.lang.errors import IrlcError
from irlc.lang.file_access import split_source_lines


@dataclass(frozen=True, order=True)
class Span:
    """A source region; lines and columns are 1-based, ``end`` is exclusive."""

    line: int
    column: int
    end_line: int = 0
    end_column: int = 0


@dataclass(frozen=True)
class Diagnostic:
    severity: str  # "error" | "warning" | "note"
    message: str
    file: str
    span: Span | None = None
    hint: str | None = None
    notes: tuple[str, ...] = field(default=())

    @property
    def line(self) -> int | None:
        return self.span.line if self.span else None

    @property
    def column(self) -> int | None:
        return self.span.column if self.span else None

    @property
    def is_error(self) -> bool:
        return self.severity == "error"

    def header(self) -> str:
        where = self.file
        if self.span is not None:
            where += f":{self.span.line}:{self.span.column}"
        return f"{where}: {self.severity}: {self.message}"


def render(diag: Diagnostic, source: str | None = None) -> str:
    """Plain-text rendering: header, source line, caret (under the span), hint, notes.

    Without ``source`` the line is read from ``diag.file`` only for a program (``.irl``):
    a robot file's or data list's error names file, line and key, never its text
    (``irlc.lang.file_access``)."""
    out = [diag.header()]
    if source is None and diag.span is not None:
        source = program_text(diag.file)
    if source is not None and diag.span is not None:
        lines = split_source_lines(source)
        if 1 <= diag.span.line <= len(lines):
            text = lines[diag.span.line - 1].expandtabs(1)
            col = max(1, diag.span.column)
            width = 1
            if diag.span.end_line == diag.span.line and diag.span.end_column > col:
                width = diag.span.end_column - col
            out.append(f"  {text}")
            out.append("  " + " " * (col - 1) + "^" + "~" * (width - 1))
    if diag.hint:
        out.append(f"  hint: {diag.hint}")
    out.extend(f"  note: {n}" for n in diag.notes)
    return "\n".join(out)


def program_text(file: str) -> str | None:
    """The text of a program file (``.irl``, a regular file: never a FIFO), else ``None``."""
    if not (file.lower().endswith(".irl") and Path(file).is_file()):
        return None
    try:
        return Path(file).read_text(encoding="utf-8", errors="replace")
    except OSError:
        return None


def line_span(source: str | None, line: int) -> Span:
    """The non-blank text of ``line`` of ``source``, as a :class:`Span` — where a run-time
    failure points: the code records the line of the statement, not its column. Without
    the text (or on a blank line) column 1."""
    lines = split_source_lines(source) if source is not None else []
    text = lines[line - 1].expandtabs(1) if 1 <= line <= len(lines) else ""
    stripped = text.strip()
    if not stripped:
        return Span(line, 1)
    start = len(text) - len(text.lstrip()) + 1
    return Span(line, start, line, start + len(stripped))


class CompileError(IrlcError):
    """Raised at the API boundary when compilation produced errors."""

    def __init__(self, diagnostics: Iterable[Diagnostic]):
        self.diagnostics = list(diagnostics)
        first = next((d for d in self.diagnostics if d.is_error), None)
        super().__init__(first.header() if first else "compilation failed")
