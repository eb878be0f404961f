"""Positions: the compiler's spans (1-based lines and columns in characters) ↔ LSP positions
(0-based lines, columns in the client's code units: UTF-16 unless it chose another).

Lines are counted as the compiler counts them (at ``\\n`` only, a ``\\r`` before it
dropped: :func:`irlc.lang.file_access.split_source_lines`), so a diagnostic's line is the
line the editor shows. A span without an end covers the word at its start (a data list's
key, a keyword), or one character.
"""

from __future__ import annotations

import re

from irlc.lang.diagnostics import Span
from lsprotocol import types
from pygls.workspace.position_codec import PositionCodec

_WORD = re.compile(r"[\w.\"'-]+")


class SourceLines:
    """One text's lines, for converting positions in it."""

    def __init__(self, text: str, codec: PositionCodec):
        self.lines = [line.removesuffix("\r") for line in text.split("\n")]
        self.codec = codec

    def line(self, number: int) -> str:
        """Line ``number`` (1-based; ``""`` beyond the text)."""
        return self.lines[number - 1] if 1 <= number <= len(self.lines) else ""

    def position(self, line: int, column: int) -> types.Position:
        """The LSP position of 1-based ``line``, ``column``."""
        text = self.line(line)
        prefix = text[: max(0, column - 1)]
        return types.Position(max(0, line - 1), self.codec.client_num_units(prefix))

    def range(self, span: Span | None) -> types.Range:
        """The LSP range of ``span`` (``None``: the start of the text)."""
        if span is None:
            return types.Range(types.Position(0, 0), types.Position(0, 0))
        start = self.position(span.line, span.column)
        if span.end_line and (span.end_line, span.end_column) > (span.line, span.column):
            return types.Range(start, self.position(span.end_line, span.end_column))
        word = _WORD.match(self.line(span.line), max(0, span.column - 1))
        length = len(word.group()) if word else 1
        return types.Range(start, self.position(span.line, span.column + length))

    def cursor(self, position: types.Position) -> tuple[int, int]:
        """The 1-based line and column (in characters) of an LSP position."""
        text = self.line(position.line + 1)
        units = 0
        for i, char in enumerate(text):
            if units >= position.character:
                return position.line + 1, i + 1
            units += self.codec.client_num_units(char)
        return position.line + 1, len(text) + 1

    def before(self, line: int, column: int) -> str:
        """The text of ``line`` before ``column``."""
        return self.line(line)[: column - 1]


def contains(span: Span, line: int, column: int) -> bool:
    """Whether ``line``:``column`` lies in ``span`` or right after its end (a cursor just
    behind a word is on it)."""
    end_line = span.end_line or span.line
    end_column = span.end_column or span.column + 1
    return (span.line, span.column) <= (line, column) <= (end_line, end_column)
