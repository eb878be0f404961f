"""Where a REPL entry's messages point: ``FILE:LINE:COL`` in the entry as the user typed it.

Every entry is compiled inside the session's program (``repl.irl`` in the session's
folder, :mod:`irlc.repl`); a diagnostic there is moved to the entry — ``<stdin>:LINE:COL``
for a script piped in (``LINE``: the script's line), ``<input>:LINE:COL`` at the terminal
(``LINE`` within the entry) — as every diagnostic of the session is (``docs/interfaces.md``,
Diagnostics). A diagnostic in another file (a data list the entry imports) keeps its own.
"""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

from irlc.lang.diagnostics import Diagnostic, Span, line_span
from irlc.lang.diagnostics import render as render_diagnostic

INPUT_NAME = "<input>"  # an entry typed at the terminal
SCRIPT_NAME = "<stdin>"  # a script piped in
ADDED_END = "unexpected ';'"  # a parse error at the ';' the session adds to a statement
_CITED_LINE = re.compile(r"\(line (\d+)\)")


class Positions:
    """The positions of the current entry's messages (module doc): ``origin`` is the
    script line the entry starts on (``None``: typed at the terminal)."""

    def __init__(self, session_file: str):
        self.session_file = session_file
        self.origin: int | None = None

    def named_file(self, file: str, chunk: str) -> str:
        """The entry's own error when its errors lie in another file (a data list it
        imports, positioned there): at the entry's first mention of the file's name."""
        name = Path(file).stem
        for line, text in enumerate(chunk.split("\n"), 1):
            column = text.lower().find(name.lower()) + 1
            if column:
                return self.located(f"data list '{name}' has errors (above)", line, column)
        return self.located(f"data list '{name}' has errors (above)")

    def render(self, diag, chunk: str, chunk_line: int) -> str:
        """``diag`` (a position in the session program) as a position in the entry."""
        span = diag.span
        n_lines = chunk.count("\n") + 1
        session = self.session_file
        if diag.file != session:  # a data list's problem: its own file and line
            return render_diagnostic(diag, "")
        diag = dataclasses.replace(
            diag, message=self.cited_lines(diag.message, chunk_line, n_lines)
        )
        if span is None or not chunk_line <= span.line < chunk_line + n_lines:
            # outside the entry (the session program's end): at the entry's first or last line
            local_line = n_lines if span is not None and span.line >= chunk_line else 1
            _, _, rest = render_diagnostic(dataclasses.replace(diag, span=None), "").partition("\n")
            header = self.located(diag.message, local_line, severity=diag.severity)
            return f"{header}\n{rest}" if rest else header
        local = shifted(span, 1 - chunk_line)  # line 1 = the entry's first line
        typed = chunk.split("\n")[local.line - 1].rstrip()
        if local.column > len(typed) and diag.message.startswith(ADDED_END):
            # at the ';' the session adds to a statement: the user's entry ends there
            rest = diag.message[len(ADDED_END) :]
            diag = dataclasses.replace(diag, message=f"unexpected end of the entry{rest}")
        rendered = render_diagnostic(dataclasses.replace(diag, span=local), chunk)
        _, _, shown = rendered.partition("\n")
        file, where = self.entry_file(), local
        if self.origin is not None:
            where = shifted(local, self.origin - 1)
        header = dataclasses.replace(diag, file=file, span=where).header()
        return f"{header}\n{shown}" if shown else header

    def cited_lines(self, message: str, chunk_line: int, n_lines: int) -> str:
        """``(line N)`` in a message — a line of the session program — as the user knows it:
        a line of this entry where it is one, else ``(earlier in the session)``."""

        def cited(m: re.Match) -> str:
            n = int(m.group(1))
            if not chunk_line <= n < chunk_line + n_lines:
                return "(earlier in the session)"
            line = self.entry_line(n - chunk_line + 1)
            return f"(line {line})" if self.origin is not None else f"(line {line} of the entry)"

        return _CITED_LINE.sub(cited, message)

    def entry_file(self) -> str:
        return INPUT_NAME if self.origin is None else SCRIPT_NAME

    def located(
        self, message: str, local_line: int = 1, column: int = 1, severity: str = "error"
    ) -> str:
        """``FILE:LINE:COL: error: message`` at a line of the entry (1 = its first), as
        every diagnostic of the session is (``docs/interfaces.md``, Diagnostics)."""
        line = self.entry_line(local_line)
        return f"{self.entry_file()}:{line}:{column}: {severity}: {message}"

    def entry_line(self, local_line: int) -> int:
        """A line of the entry (1 = its first) as the user counts it."""
        return local_line if self.origin is None else self.origin + local_line - 1

    def run_error(self, error, first: int, body: str) -> str:
        """``FILE:LINE:COL: error: run-time failure at t = … s: message`` (as ``irlc run``:
        the column of the line's statement text); a failure in a routine declared earlier
        is placed at the entry's first line."""
        line = getattr(error, "line", None)
        local = 1
        if line is not None and first <= line < first + body.count("\n") + 1:
            local = line - first + 1
        t = getattr(error, "time_s", None)
        at = f" at t = {t:.3f} s" if t is not None else ""
        message = f"run-time failure{at}: {getattr(error, 'message', str(error))}"
        span = line_span(body, local)
        header = self.located(message, local, span.column)
        # the line and its underline, as a compile error shows them
        rendered = render_diagnostic(Diagnostic("error", message, "", span), body)
        _, _, shown = rendered.partition("\n")
        return f"{header}\n{shown}" if shown else header


def shifted(span: Span, lines: int) -> Span:
    """``span`` moved down by ``lines`` lines (up when negative)."""
    end = max(span.end_line + lines, 0) if span.end_line else 0
    return Span(span.line + lines, span.column, end, span.end_column)
