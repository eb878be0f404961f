"""Syntax errors in the programmer's words: lark's exceptions become diagnostics.

Expected tokens are listed as words (``';'``, ``ENDIF``, ``an expression``, ``a
statement``), keywords used as names are reported as reserved words, a missing ``;`` is
placed after the previous word, unterminated strings and stray characters are named, and a
misspelled block end (``END_IF``) gets the keyword meant (lang/typos.py). Every message is
found in time linear in the text.
"""

from __future__ import annotations

import re

from irlc.lang.ast_builder import token_span
from irlc.lang.diagnostics import Diagnostic, Span
from irlc.lang.grammar import keywords, lark_parser
from irlc.lang.settings import BY_LIMIT_WORD, approximation_hint
from irlc.lang.typos import misspelled_keyword
from lark import Token
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

_PUNCT = {
    "SEMICOLON": "';'",
    "COLON": "':'",
    "COMMA": "','",
    "LPAR": "'('",
    "RPAR": "')'",
    "LSQB": "'['",
    "RSQB": "']'",
    "DOT": "'.'",
    "DOTDOT": "'..'",
    "EQUAL": "'='",
    "PLUS": "'+'",
    "MINUS": "'-'",
    "STAR": "'*'",
    "SLASH": "'/'",
    "RELOP": "a comparison",
    "__ANON_0": "':='",
    "AND_PART": "AND",  # before the next part of a group move (irl.lark)
    "NAME": "a name",
    "NUMBER": "a number",
    "STRING": "a string",
    "$END": "end of file",
}
_STATEMENT_STARTS = {
    "IF",
    "WHILE",
    "REPEAT",
    "FOR",
    "CASE",
    "GOTO",
    "WAIT",
    "PAUSE",
    "HALT",
    "WRITE",
    "WRITELN",
    "MOVE",
    "MOVE_INC",
    "RETURN",
    *BY_LIMIT_WORD,
    "CYCLICSTART",
    "OBSTACLE",
    "FREEZESTART",
    "RECONFIGURATION",
}
_EXPR_STARTS = {"NUMBER", "STRING", "TRUE", "FALSE", "NOT", "IN", "LPAR", "MINUS", "PLUS"}
_OPERATORS = {
    "PLUS",
    "MINUS",
    "STAR",
    "SLASH",
    "DIV",
    "MOD",
    "AND",
    "AND_PART",
    "OR",
    "EXOR",
    "COLON",
    "RELOP",
    "EQUAL",
    "DOT",
    "LSQB",
}
_TYPES = {
    "INTEGER",
    "REAL",
    "BOOLEAN",
    "CHAR",
    "STRING_T",
    "POSITION",
    "ORIENTATION",
    "SIGNAL",
    "MAIN_JOINT",
    "ARRAY",
    "RECORD",
}


def _term_word(name: str) -> str:
    if name in _PUNCT:
        return _PUNCT[name]
    if name == "STRING_T":
        return "STRING"
    try:
        pattern = next(t.pattern for t in lark_parser().terminals if t.name == name)
        if pattern.type == "str":
            return pattern.value.upper() if pattern.value.isidentifier() else f"'{pattern.value}'"
    except StopIteration:
        pass
    return name


def _describe_expected(expected: set[str]) -> str:
    words: list[str] = []
    rest = set(expected)
    if len(rest & _STATEMENT_STARTS) >= 4:
        words.append("a statement")
        rest -= _STATEMENT_STARTS | {"NAME"}
        rest -= {t for t in rest if t.endswith("END") and t != "$END"}
    if "NUMBER" in rest and "NAME" in rest:
        words.append("an expression")
        rest -= _EXPR_STARTS | {"NAME", "POSE", "POSITION"}
    if len(rest & _TYPES) >= 4:
        words.append("a type")
        rest -= _TYPES | {"POSE", "NAME"} | {t for t in rest if t.startswith("MAIN_JOINT")}
    if len(rest & _OPERATORS) >= 4:
        words.append("an operator")
        rest -= _OPERATORS
    words += sorted(_term_word(t) for t in rest)
    if len(words) > 8:
        words = [*words[:8], "..."]
    if len(words) <= 1:
        return "".join(words)
    return ", ".join(words[:-1]) + " or " + words[-1]


def _token_text(tok: Token) -> str:
    if tok.type == "$END":
        return "end of file"
    kind = tok.type
    if kind in ("NAME",):
        return f"name '{tok.value}'"
    if kind == "NUMBER":
        return f"number {tok.value}"
    if kind == "STRING":
        return f"string {tok.value}"
    return f"'{tok.value}'"


def _end_of_text(text: str) -> Span:
    lines = text.split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    if not lines:
        return Span(1, 1)
    return Span(len(lines), len(lines[-1]) + 1)


def _previous_token(text: str, line: int, col: int) -> tuple[str, Span] | None:
    """The last non-blank, non-comment word before (line, col) — for 'after X' messages.

    Linear in the text: comments are blanked by one left-to-right scan (:func:`_blank_comments`)
    and the last word is matched on the reversed segment, anchored at its start, so no pattern
    is retried at every position of a long run of word characters.
    """
    lines = text.split("\n")
    for ln in range(min(line, len(lines)), 0, -1):
        seg = lines[ln - 1] if ln < line else lines[ln - 1][: max(col - 1, 0)]
        cut = seg.find("//")
        if cut >= 0:
            seg = seg[:cut]
        stripped = _blank_comments(seg).rstrip()
        if stripped and not stripped.endswith(("}", "*)")):
            m = _LAST_WORD_REVERSED.match(stripped[::-1])
            if m:
                start = len(stripped) - m.end()
                return stripped[start:], Span(ln, start + 1, ln, len(stripped) + 1)
    return None


# The last word of a segment, read backwards: a quoted string (the patterns are palindromes, so
# greedy on the reversed text = the leftmost start in the text), a run of word characters, or
# one non-blank character.
_LAST_WORD_REVERSED = re.compile(r"'(?:[^']|'')*'|\"[^\"]*\"|[A-Za-z0-9_.]+|\S")


def _blank_comments(seg: str) -> str:
    """``seg`` with every closed ``{...}`` and ``(*...*)`` replaced by blanks of equal length.

    The same leftmost, non-overlapping choice as ``re.sub(r"\\{[^}]*\\}|\\(\\*.*?\\*\\)")``, in
    one pass: the next ``}`` and the next ``*)`` after each position are found by ``str.find``
    from a moving cursor, each search starting where the previous one for its kind ended.
    """
    out: list[str] = []
    i, n = 0, len(seg)
    next_brace, next_star = -2, -2  # cached positions of the next '}' / '*)' (−1: none left)
    while i < n:
        ch = seg[i]
        if ch == "{":
            if next_brace != -1 and next_brace < i:
                next_brace = seg.find("}", i)
            if next_brace != -1:
                out.append(" " * (next_brace + 1 - i))
                i = next_brace + 1
                continue
        elif ch == "(" and seg.startswith("*", i + 1):
            if next_star != -1 and next_star < i + 2:
                next_star = seg.find("*)", i + 2)
            if next_star != -1:
                out.append(" " * (next_star + 2 - i))
                i = next_star + 2
                continue
        out.append(ch)
        i += 1
    return "".join(out)


def syntax_diagnostic(e: UnexpectedInput, text: str, filename: str) -> Diagnostic:
    if isinstance(e, UnexpectedCharacters):
        span = Span(e.line, e.column, e.line, e.column + 1)
        ch = text[e.pos_in_stream] if e.pos_in_stream < len(text) else ""
        if ch in "'\"":
            return Diagnostic(
                "error",
                "unterminated string",
                filename,
                span,
                f"close the string with {ch} on the same line (write {ch}{ch} for a quote inside)",
            )
        if ch == "}":
            return Diagnostic("error", "'}' without an opening '{'", filename, span)
        shown = repr(ch) if ch.isprintable() else f"U+{ord(ch):04X}" if ch else "end of file"
        return Diagnostic("error", f"unexpected character {shown}", filename, span)
    if isinstance(e, UnexpectedEOF) or (isinstance(e, UnexpectedToken) and e.token.type == "$END"):
        typo = _misspelled_last_word(text, filename)  # `END_PROGRAM` at the end of the file
        if typo is not None:
            return typo
    if isinstance(e, UnexpectedEOF):
        expected = set(e.expected)
        return Diagnostic(
            "error",
            f"unexpected end of file; expected {_describe_expected(expected)}",
            filename,
            _end_of_text(text),
        )
    assert isinstance(e, UnexpectedToken)
    tok = e.token
    expected = set(e.accepts or e.expected)
    if tok.type == "$END":
        span = _end_of_text(text)
        return Diagnostic(
            "error",
            f"unexpected end of file; expected {_describe_expected(expected)}",
            filename,
            span,
            _eof_hint(expected),
        )
    span = token_span(tok)
    if "NAME" in expected and tok.type != "NAME" and tok.value.upper() in keywords():
        return Diagnostic(
            "error",
            f"'{tok.value}' is a reserved word",
            filename,
            span,
            "choose another name (keywords cannot name variables, routines or labels)",
        )
    prev = _previous_token(text, span.line, span.column)
    if prev is not None and (typo := misspelled_keyword(*prev, filename)) is not None:
        return typo
    if (
        tok.type == "COLON"
        and prev is not None
        and prev[0].upper() in keywords()
        and not text[tok.end_pos :].lstrip().startswith(";")
    ):
        return Diagnostic(
            "error",
            f"'{prev[0]}' is a reserved word and cannot be a label",
            filename,
            prev[1],
            "choose another label name",
        )
    if tok.type == "COLON" and text[tok.end_pos :].lstrip().startswith(";") and prev:
        return Diagnostic(
            "error",
            f"stray ':' after '{prev[0]}'",
            filename,
            span,
            f"write '{prev[0]};' (the seed's '{prev[0]}:;' is a misprint)",
        )
    if (
        "SEMICOLON" in expected
        and prev is not None
        and (prev[1].line < span.line or len(expected) <= 2)
    ):
        p = prev[1]
        where = Span(p.line, p.end_column, p.line, p.end_column + 1)
        return Diagnostic(
            "error",
            f"expected ';' after '{prev[0]}'",
            filename,
            where,
            f"found {_token_text(tok)} on line {span.line}" if p.line < span.line else None,
        )
    return Diagnostic(
        "error",
        f"unexpected {_token_text(tok)}; expected {_describe_expected(expected)}",
        filename,
        span,
        approximation_hint(str(tok.value)) or _token_hint(tok, expected),
    )


def _misspelled_last_word(text: str, filename: str) -> Diagnostic | None:
    """The typo diagnostic when the text ends in a misspelled keyword (``END_PROGRAM``)."""
    end = _end_of_text(text)
    prev = _previous_token(text, end.line, end.column)
    return None if prev is None else misspelled_keyword(*prev, filename)


def _eof_hint(expected: set[str]) -> str | None:
    if "ENDPROGRAM" in expected:
        return "the main program ends with ENDPROGRAM"
    ends = sorted(t for t in expected if t.startswith("END") and t != "ENDPROGRAM")
    if ends:
        return f"a block is not closed: add {' or '.join(_term_word(t) for t in ends)}"
    return None


def _token_hint(tok: Token, expected: set[str]) -> str | None:
    if tok.type == "EQUAL" and "__ANON_0" in expected:
        return "assignment is written ':='"
    if tok.type in ("RELOP", "EQUAL") and not expected & {"RELOP", "EQUAL"}:
        return (
            "comparisons bind looser than AND/OR (Pascal precedence) and do not chain: "
            "parenthesize each one, e.g. (x > 1) AND (y < 2)"
        )
    if tok.type == "NAME" and tok.value.upper() in ("END", "ENDMOVE", "ENDLOOP"):
        ends = sorted(t for t in expected if t.startswith("END"))
        if ends:
            return f"blocks end with their own keyword: {', '.join(ends)}"
    if tok.type == "NAME" and tok.value.upper() == "ELSEIF":
        return "write ELSIF"
    return None
