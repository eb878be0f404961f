"""Syntax errors in the programmer's words: lark's exceptions become diagnostics.

Expected tokens are listed as words (``';'``, ``ENDIF``, ``an expression``, ``a
statement``), keywords used as names are reported as reserved words, a missing ``;`` is
placed after the previous word, unterminated strings and stray characters are named, and a
misspelled block end (``END_IF``) gets the keyword meant (lang/typos.py). Every message is
found in time linear in the text.
"""

from __future__ import annotations

import re

from irlc.lang import foreign
from irlc.lang.ast_builder import SourceError, token_span
from irlc.lang.diagnostics import Diagnostic, Span
from irlc.lang.grammar import GluedWord, keywords, lark_parser
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
        habit = _foreign_character(text, e.pos_in_stream, span, filename)
        if habit is not None:
            return habit
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
    prev = _previous_token(text, span.line, span.column)
    habit = _foreign_word(tok, prev, expected, text, filename)
    if habit is not None:
        return habit
    if "NAME" in expected and tok.type != "NAME" and tok.value.upper() in keywords():
        return Diagnostic(
            "error",
            f"'{tok.value}' is a reserved word",
            filename,
            span,
            "choose another name (keywords cannot name variables, routines or labels)",
        )
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
        if p.line < span.line:
            hint = f"found {_token_text(tok)} on line {span.line}"
        elif tok.type == "__ANON_0":  # RAPID's VAR num x := 0;
            hint = "a variable takes no value where it is declared: assign it after BEGIN"
        else:
            hint = None
        return Diagnostic("error", f"expected ';' after '{prev[0]}'", filename, where, hint)
    return Diagnostic(
        "error",
        f"unexpected {_token_text(tok)}; expected {_describe_expected(expected)}",
        filename,
        span,
        approximation_hint(str(tok.value))
        or _with_flag_hint(prev, expected)
        or _token_hint(tok, expected, text),
    )


def _with_flag_hint(prev: tuple[str, Span] | None, expected: set[str]) -> str | None:
    """``MOVE … WITH VERTICAL;``: COOPERATE's condition written on a motion."""
    if prev is not None and prev[0].upper() == "VERTICAL" and "__ANON_0" in expected:
        return (
            "VERTICAL is a condition of a cooperation, not a motion's option: "
            "COOPERATE welder IN holder WITH VERTICAL;"
        )
    return None


def source_error_diagnostic(e: SourceError, text: str, filename: str) -> Diagnostic:
    """The diagnostic of an error found while lexing: a keyword used as a name, unless it is
    another language's motion word at the start of a statement (KRL's ``PTP left;``)."""
    span = e.span
    lines = text.split("\n")
    if isinstance(e, GluedWord):
        return _glued_word(e, lines[span.line - 1], text, filename)
    if e.message.endswith("is a reserved word") and 0 < span.line <= len(lines):
        row = lines[span.line - 1]
        word = row[span.column - 1 : span.end_column - 1]
        prev = _previous_token(text, span.line, span.column)
        hint = foreign.motion_hint(word, _statement_rest(row, span.end_column - 1))
        if hint is not None and _statement_starts_after(prev):
            return Diagnostic("error", foreign.statement_message(word), filename, span, hint)
        if word.upper() == "SEC" and prev is not None and prev[0].upper() == "WAIT":
            return _wait_sec_first(row, span, filename)  # KRL: WAIT SEC 1
        unfinished = prev is not None and not _statement_starts_after(prev)
        if unfinished and _closes_a_block(word) and not row[: span.column - 1].strip():
            return Diagnostic(
                "error",
                f"the statement is not finished: '{word}' on the next line cannot follow "
                f"'{prev[0]}'",
                filename,
                prev[1],
                "finish the statement (and end it with ';') or delete it",
            )
    return e.diagnostic(filename)


def _closes_a_block(word: str) -> bool:
    """``ENDPROGRAM``, ``ENDIF``, ``ELSE`` …: first on its line where a name must come, the
    word is the next line's after an unfinished statement (``MOVE``), not a chosen name."""
    upper = word.upper()
    return upper.startswith("END") or upper in {"ELSE", "UNTIL", "BEGIN"}


def _glued_word(e: GluedWord, row: str, text: str, filename: str) -> Diagnostic:
    """A word the lexer split into a keyword and a name (``MOVE a LIN_REL p``): another
    language's motion word gets irlc's statement, naming the cell's robot; any other word
    the keyword it starts with."""
    span = e.span
    robot = _moved_robot(text, span)
    hint = foreign.motion_hint(e.word, _statement_rest(row, span.end_column - 1), robot)
    if hint is not None:
        return Diagnostic("error", foreign.statement_message(e.word), filename, span, hint)
    rest = e.word[len(e.keyword) :]
    hint = f"irlc read {e.keyword.upper()} and then '{rest}': a keyword is followed by a space"
    return Diagnostic("error", f"unknown word '{e.word}'", filename, span, hint)


def _moved_robot(text: str, span: Span) -> str | None:
    """The robot a cell's motion names before ``span`` (``MOVE a ▯``, ``MOVE_INC a ▯``,
    ``AND a ▯``), else ``None``."""
    robot = _previous_token(text, span.line, span.column)
    if robot is None or not robot[0].isidentifier() or robot[0].upper() in keywords():
        return None
    before = _previous_token(text, robot[1].line, robot[1].column)
    if before is None or before[0].upper() not in ("MOVE", "MOVE_INC", "AND"):
        return None
    return robot[0]


def _wait_sec_first(row: str, span: Span, filename: str) -> Diagnostic:
    after = _statement_rest(row, span.end_column - 1) or "t"
    message = "the time of a WAIT comes before SEC"
    return Diagnostic("error", message, filename, span, f"write WAIT {after} SEC;")


def _statement_starts_after(prev: tuple[str, Span] | None) -> bool:
    """Whether a statement starts after the word ``prev`` (``None``: the text's start)."""
    return prev is None or prev[0].upper() in (";", "BEGIN", "THEN", "ELSE", "DO", "REPEAT")


def _statement_rest(row: str, start: int) -> str:
    """The text of a line from ``start`` (0-based) to the statement's ``;``."""
    rest = row[start:]
    return rest.split(";", 1)[0].strip()


def _foreign_word(
    tok: Token, prev: tuple[str, Span] | None, expected: set[str], text: str, filename: str
) -> Diagnostic | None:
    """Habits of KRL and RAPID (lang/foreign.py) at an unexpected token: a motion or other
    statement word of theirs before it (``MoveL left, …``: the error is at ``left``), one of
    their motion words where a statement starts, a unit after a number, KRL's ``WAIT SEC 1``."""
    row = text.split("\n")[tok.line - 1] if tok.line else ""
    word = str(tok.value)
    if (
        tok.type != "NAME"
        and word.upper() in foreign.KRL_MOTIONS
        and "NAME" in expected
        and _statement_starts_after(prev)
    ):
        hint = foreign.motion_hint(word, _statement_rest(row, tok.end_column - 1))
        return Diagnostic("error", foreign.statement_message(word), filename, token_span(tok), hint)
    if prev is None:
        return None
    robot = _moved_robot(text, token_span(tok)) if tok.type == "NAME" else None
    if robot is not None:  # MOVE a SLIN p, … AND b LIN_REL p
        hint = foreign.motion_hint(word, _statement_rest(row, tok.end_column - 1), robot)
        if hint is not None:
            message = foreign.statement_message(word)
            return Diagnostic("error", message, filename, token_span(tok), hint)
    prev_word, prev_span = prev
    if prev_span.line == tok.line:
        args = _statement_rest(row, prev_span.end_column - 1)
        hint = foreign.statement_hint(prev_word, args)
        if hint is not None and prev_word.upper() not in keywords():
            message = foreign.statement_message(prev_word)
            return Diagnostic("error", message, filename, prev_span, hint)
        if word.upper() == "SEC" and prev_word.upper() == "WAIT":  # KRL: WAIT SEC 1
            return _wait_sec_first(row, token_span(tok), filename)
    number = prev_word if _NUMBER.fullmatch(prev_word) else None
    if tok.type == "NAME" and number is not None:
        hint = foreign.unit_hint(word, number)
        if hint is not None and "SEC" in expected and word.upper() in ("S", "SECONDS"):
            hint = f"write WAIT {number} SEC"
        if hint is not None:
            message = f"unexpected {_token_text(tok)} after the number {number}"
            return Diagnostic("error", message, filename, token_span(tok), hint)
    return None


_NUMBER = re.compile(r"(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")


def _foreign_character(text: str, pos: int, span: Span, filename: str) -> Diagnostic | None:
    """KRL's ``$`` system variables, a ``%`` after a number, C's ``!=``."""
    ch = text[pos]
    if ch == "$":
        found = foreign.system_variable(text[pos:].split("\n", 1)[0])
        if found is not None:
            end = pos + len(re.match(r"\$[\w.]*", text[pos:])[0])
            where = Span(span.line, span.column, span.line, span.column + end - pos)
            return Diagnostic("error", found[0], filename, where, found[1])
    if ch == "%":
        return Diagnostic(
            "error", "unexpected character '%'", filename, span, foreign.percent_hint()
        )
    if text.startswith("!=", pos):
        return Diagnostic(
            "error", "unexpected character '!'", filename, span, foreign.operator_hint("!=")
        )
    return None


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


def _token_hint(tok: Token, expected: set[str], text: str) -> str | None:
    pos = tok.start_pos if tok.start_pos is not None else 0
    for written in (text[pos : pos + 2], text[max(pos - 1, 0) : pos + 1]):
        if written != "!=" and (hint := foreign.operator_hint(written)) is not None:
            return hint  # ==, +=, …
    if expected == {"SEC"}:
        return "a wait is written WAIT t SEC;"
    if tok.type == "EQUAL" and text[pos - 1 : pos] == ":":  # ':=' read as ':' then '='
        if "NUMBER" in expected:
            return "':=' assigns; a comparison is written with '=', e.g. IF x = 5 THEN"
        return "a constant or type is declared with '=' (':=' assigns a variable)"
    if tok.type == "__ANON_0" and "EQUAL" in expected:
        return "a constant or type is declared with '=' (':=' assigns a variable)"
    if tok.type == "EQUAL" and "__ANON_0" in expected:
        return "assignment is written ':=' (KRL's x = 5 is x := 5)"
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
