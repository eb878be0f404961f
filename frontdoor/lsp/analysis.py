"""One program as the editor has it: the compiler's diagnostics and, on demand, its index.

:func:`analyze` runs the compiler's own pipeline (:func:`irlc.lang.compiler.analyze_source`:
lexer, parser, checks; the robot and the data lists resolved as ``irlc check`` resolves
them, an open data list's unsaved text in place of its file). Its diagnostics are what the
editor shows; nothing here parses IRL a second time.

The :class:`Index` (hover, go to definition, completion) needs a checked program. While a
statement is half typed the program does not parse; :meth:`ProgramAnalysis.index` then
blanks the line of the syntax error (spaces, so every other line and column stays where it
is) and analyses again, a few times at most, and falls back to the last text that checked.
Completion knows where the cursor is: when that fails, the line being typed is blanked
(:meth:`ProgramAnalysis.names_index`), so that a half-typed ``MOVE`` whose syntax error is
reported on a later line still sees the program's names and robots.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from irlc.lang.compiler import Analysis, analyze_source
from irlc.lsp.index import Index
from irlc.robots import resolver

RECOVERY_ATTEMPTS = 4  # syntax-error lines blanked, at most, to index a half-typed program


@dataclass(frozen=True)
class Settings:
    """How programs are compiled (``irlc lsp`` options, as for ``irlc check``)."""

    datalist_path: tuple[str, ...] = ()
    allow_any_path: bool = False


def analyze(
    text: str, path: Path, settings: Settings, datalist_texts: Mapping[str, str] | None = None
) -> Analysis:
    """Compile ``text`` as the program file ``path`` (:mod:`irlc.lang.compiler`)."""
    return analyze_source(
        text,
        str(path),
        resolve_robot=resolver(path.parent, allow_any_path=settings.allow_any_path),
        datalist_path=settings.datalist_path,
        allow_any_path=settings.allow_any_path,
        datalist_texts=datalist_texts,
    )


@dataclass
class ProgramAnalysis:
    """A program's text and its analysis; the index is built on first use."""

    path: Path
    text: str
    settings: Settings
    datalist_texts: dict[str, str]
    analysis: Analysis
    previous: Index | None = None  # the last index of this document (a fallback)
    _index: Index | None = field(default=None, init=False)
    _indexed: bool = field(default=False, init=False)
    _without_line: dict[int, Index | None] = field(default_factory=dict, init=False)

    @classmethod
    def of(
        cls,
        path: Path,
        text: str,
        settings: Settings,
        datalist_texts: dict[str, str],
        previous: ProgramAnalysis | None = None,
    ) -> ProgramAnalysis:
        fallback = previous.built_index() if previous is not None else None
        analysis = analyze(text, path, settings, datalist_texts)
        return cls(path, text, settings, datalist_texts, analysis, fallback)

    @property
    def diagnostics(self):
        return self.analysis.result.diagnostics

    @property
    def checked(self):
        return self.analysis.checked

    def index(self) -> Index | None:
        """The index of this text, or of the nearest text that checks (module doc)."""
        if not self._indexed:
            self._indexed = True
            checked = self.analysis.checked or self._recovered()
            self._index = Index(checked) if checked is not None else None
        return self._index

    def built_index(self) -> Index | None:
        """The newest index built so far (this text's or the fallback), building none: a
        change must not wait for an index nobody asked for."""
        return self._index if self._index is not None else self.previous

    def names_index(self, line: int | None = None) -> Index | None:
        """This text's index, else (``line``: the cursor's) this text without that line,
        else the last one of this document that checked: for completion, where the names
        matter and their positions may be stale."""
        index = self.index()
        if index is None and line is not None:
            index = self._index_without(line)
        return index or self.previous

    def _index_without(self, line: int) -> Index | None:
        if line not in self._without_line:
            lines = self.text.split("\n")
            checked = None
            if 1 <= line <= len(lines) and lines[line - 1].strip():
                lines[line - 1] = " " * len(lines[line - 1])
                blanked = "\n".join(lines)
                checked = analyze(blanked, self.path, self.settings, self.datalist_texts).checked
            self._without_line[line] = Index(checked) if checked is not None else None
        return self._without_line[line]

    def _recovered(self):
        lines = self.text.split("\n")
        analysis = self.analysis
        for _ in range(RECOVERY_ATTEMPTS):
            if analysis.program is not None:
                return analysis.checked  # parsed (None: no usable robot, nothing to check)
            errors = [d for d in analysis.result.diagnostics if d.is_error and d.span]
            if not errors:
                return None
            row = errors[0].span.line - 1
            if not 0 <= row < len(lines) or not lines[row].strip():
                return None
            lines[row] = " " * len(lines[row])
            analysis = analyze("\n".join(lines), self.path, self.settings, self.datalist_texts)
        return analysis.checked
