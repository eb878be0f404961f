"""Parse IRL source into the AST (:mod:`irlc.lang.ast`) with positioned diagnostics.

LALR(1) with lark's contextual lexer; the AST is built during parsing (no parse tree).
Lark's errors become :class:`Diagnostic` values that speak the programmer's language:
expected tokens are listed as words (``';'``, ``ENDIF``, ``an expression``), keywords used
as names are reported as reserved words, and unterminated strings/comments are named.
"""

from __future__ import annotations

import hashlib
import os
import re
import sys
from functools import lru_cache
from importlib import resources

import lark
from irlc.lang import ast
from irlc.lang.diagnostics import Diagnostic, Span
from irlc.lang.errors import IrlcError
from irlc.lang.irdata import parse_integer
from irlc.lang.settings import approximation_hint
from irlc.lang.types import INT_MAX
from lark import Lark, Token, Transformer
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken


class _LexError(IrlcError):
    def __init__(self, span: Span, message: str, hint: str | None = None):
        super().__init__(message)
        self.span, self.message, self.hint = span, message, hint


def _comment_callback(tok: Token) -> Token:
    text = tok.value
    closed = (
        (text.startswith("{") and text.endswith("}"))
        or (text.startswith("(*") and text.endswith("*)") and len(text) >= 4)
        or text.startswith("//")
    )
    if not closed:
        opener = "{" if text.startswith("{") else "(*"
        closer = "}" if opener == "{" else "*)"
        raise _LexError(
            Span(tok.line, tok.column, tok.line, tok.column + len(opener)),
            f"unterminated comment: '{opener}' is never closed",
            f"close the comment with '{closer}' (comments do not nest)",
        )
    return tok


def _name_callback(tok: Token) -> Token:
    """A NAME that spells a keyword: the keyword was not acceptable here, so it is misused."""
    if tok.value.upper() in _keywords():
        raise _LexError(
            _tok_span(tok),
            f"'{tok.value}' is a reserved word",
            "choose another name (keywords cannot name variables, routines or labels)",
        )
    return tok


_NUMBER_RE = re.compile(r"(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")


def _malformed_number(tok: Token) -> _BuildError:
    return _BuildError(
        _tok_span(tok),
        f"malformed number '{tok.value}'",
        "numbers look like 12, 180., .5, 1e-3 or 2.5E+2; put a space between a number and "
        "a following word",
    )


@lru_cache(maxsize=1)
def _lark() -> Lark:
    grammar = resources.files("irlc.lang").joinpath("irl.lark").read_text(encoding="utf-8")
    return Lark(
        grammar,
        parser="lalr",
        lexer="contextual",
        transformer=_Builder(),
        maybe_placeholders=True,
        lexer_callbacks={
            "COMMENT": _comment_callback,
            "NAME": _name_callback,
        },
        cache=grammar_cache_file(grammar),
    )


def grammar_cache_file(grammar: str) -> str | bool:
    """Where lark keeps the built LALR tables (~10x faster start-up than building them).

    A per-user directory (``$XDG_CACHE_HOME/irlc``, else ``~/.cache/irlc``), never the
    install (it may be read-only) nor the shared temp directory (lark unpickles the file).
    The name carries a hash of the grammar, lark's and Python's versions; lark also checks
    a hash of the grammar and its options inside the file and rebuilds a stale one. The
    transformer and lexer callbacks are not cached: lark attaches them on every load.
    ``False`` (no cache) when the directory cannot be made; lark ignores failed writes.
    """
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    folder = os.path.join(base, "irlc")
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError:
        return False
    key = hashlib.sha256(f"{grammar}{lark.__version__}{sys.version_info[:2]}".encode()).hexdigest()
    return os.path.join(folder, f"irl-grammar-{key[:20]}.lark-cache")


def keywords() -> frozenset[str]:
    """The reserved words (upper case)."""
    return _keywords()


@lru_cache(maxsize=1)
def _keywords() -> frozenset[str]:
    grammar = resources.files("irlc.lang").joinpath("irl.lark").read_text(encoding="utf-8")
    words = re.findall(r'^[A-Z_]+:\s*"([a-z_]+)"i\s*$', grammar, flags=re.MULTILINE)
    return frozenset(w.upper() for w in words)


def parse(text: str, filename: str) -> tuple[ast.Program | None, list[Diagnostic]]:
    """Parse ``text``; return the program (or ``None``) and diagnostics (one on error)."""
    try:
        return _lark().parse(text), []
    except _LexError as e:
        return None, [Diagnostic("error", e.message, filename, e.span, e.hint)]
    except UnexpectedInput as e:
        return None, [_syntax_diagnostic(e, text, filename)]
    except _BuildError as e:
        return None, [Diagnostic("error", e.message, filename, e.span, e.hint)]


# ============================================================ errors in user words

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
    "JOINTLIMIT",
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
        pattern = next(t.pattern for t in _lark().terminals if t.name == name)
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
        rest -= _STATEMENT_STARTS | {"NAME", "JOINTSPEEDLIMIT", "JOINTACCELLIMIT"}
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


def _tok_span(tok: Token) -> Span:
    line = tok.line or 1
    col = tok.column or 1
    end_col = tok.end_column or col + 1
    return Span(line, col, tok.end_line or line, end_col)


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


def _syntax_diagnostic(e: UnexpectedInput, text: str, filename: str) -> Diagnostic:
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
    span = _tok_span(tok)
    if "NAME" in expected and tok.type != "NAME" and tok.value.upper() in keywords():
        return Diagnostic(
            "error",
            f"'{tok.value}' is a reserved word",
            filename,
            span,
            "choose another name (keywords cannot name variables, routines or labels)",
        )
    prev = _previous_token(text, span.line, span.column)
    if prev is not None and prev[0].upper() in _MISSPELLED:
        word = prev[0]
        return Diagnostic(
            "error",
            f"'{word}' is not a keyword of this dialect",
            filename,
            prev[1],
            f"write {_MISSPELLED[word.upper()]}",
        )
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


_MISSPELLED = {
    "ELSEIF": "ELSIF",
    "ELIF": "ELSIF",
    "ENDPROCEDURE": "ENDPROC",
    "ENDFUNCTION": "ENDFCT",
    "ENDFUNC": "ENDFCT",
    "END_IF": "ENDIF",
    "END_WHILE": "ENDWHILE",
    "END_FOR": "ENDFOR",
    "END_CASE": "ENDCASE",
    "END_PROC": "ENDPROC",
    "END_PROCEDURE": "ENDPROC",
    "END_FCT": "ENDFCT",
    "END_FUNCTION": "ENDFCT",
    "END_PROGRAM": "ENDPROGRAM",
    "CYCLIC_START": "CYCLICSTART",
    "CYCLIC_END": "CYCLICEND",
    "FREEZE_START": "FREEZESTART",
    "FREEZE_END": "FREEZEEND",
    "JOINTLIMIT_END": "JOINTLIMITEND",
    "ENDCYCLIC": "CYCLICEND",
}


def _misspelled_last_word(text: str, filename: str) -> Diagnostic | None:
    """The typo diagnostic when the text ends in a misspelled keyword (``END_PROGRAM``)."""
    end = _end_of_text(text)
    prev = _previous_token(text, end.line, end.column)
    if prev is None or prev[0].upper() not in _MISSPELLED:
        return None
    word, span = prev
    return Diagnostic(
        "error",
        f"'{word}' is not a keyword of this dialect",
        filename,
        span,
        f"write {_MISSPELLED[word.upper()]}",
    )


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


# ============================================================ tree → AST


class _BuildError(IrlcError):
    def __init__(self, span: Span, message: str, hint: str | None = None):
        super().__init__(message)
        self.span, self.message, self.hint = span, message, hint


def _span(x) -> Span:
    if isinstance(x, Token):
        return _tok_span(x)
    if isinstance(x, ast.Node):
        return x.span
    raise TypeError(x)


def _nodes(children) -> list:
    return [c for c in children if not isinstance(c, Token) and c is not None]


_LIMIT_OPTION = {
    "JOINTLIMIT": "JOINTLIMIT",
    "JOINTSPEEDLIMIT": "JOINTSPEEDLIMIT",
    "JOINTACCELLIMIT": "JOINTACCELLIMIT",
    "JOINTLIMITEND": "JOINTLIMIT",
    "JOINTSPEEDLIMITEND": "JOINTSPEEDLIMIT",
    "JOINTACCELLIMITEND": "JOINTACCELLIMIT",
}
_BINOPS = {"PLUS": "+", "MINUS": "-", "STAR": "*", "SLASH": "/", "COLON": ":"}


class _Builder(Transformer):
    """Builds AST nodes bottom-up while the LALR parser reduces (lark ``transformer=``)."""

    # ---------------------------------------------------------------- program
    def start(self, c):
        prog_tok, name = c[0], c[1]
        robots, datalists, unsupported = [], [], []
        decls = ast.Decls()
        routines: list[ast.Routine] = []
        body: list[ast.Stmt] = []
        end_span = _span(c[0])
        first_decl: Span | None = None
        for x in c[2:]:
            if isinstance(x, (ast.RobotClause, ast.DatalistClause)) and first_decl is not None:
                what = "ROBOT" if isinstance(x, ast.RobotClause) else "IMPORT DATALIST"
                raise _BuildError(
                    x.span,
                    f"{what} must come before the declarations",
                    f"move it up, right after the PROGRAM line (first declaration: line "
                    f"{first_decl.line})",
                )
            if isinstance(x, (ast.Decls, ast.Routine)) and first_decl is None:
                first_decl = x.order[0].span if isinstance(x, ast.Decls) and x.order else x.span
            if isinstance(x, ast.RobotClause):
                robots.append(x)
            elif isinstance(x, ast.DatalistClause):
                datalists.append(x)
            elif isinstance(x, ast.Unsupported):
                unsupported.append(x)
            elif isinstance(x, ast.Decls):
                _merge(decls, x)
            elif isinstance(x, ast.Routine):
                routines.append(x)
                decls.order.append(x)
            elif isinstance(x, list):
                body = x
            elif isinstance(x, Token) and x.type == "ENDPROGRAM":
                end_span = _span(x)
        return ast.Program(
            _span(prog_tok),
            name.value,
            robots,
            datalists,
            unsupported,
            decls,
            routines,
            body,
            end_span,
        )

    def robot_clause(self, c):
        kw, var, target = c[0], c[1], c[2]
        robot = target.value
        if target.type == "STRING":
            robot = _unquote(robot)
        return ast.RobotClause(_span(kw), var.value, robot, _span(target))

    def datalist_clause(self, c):
        return ast.DatalistClause(_span(c[2]), c[2].value)

    def system_spec(self, c):
        return ast.Unsupported(_span(c[0]), "SYSTEM SPECIFICATION")

    def standard_in(self, c):
        return ast.Unsupported(_span(c[0]), "STANDARD_IN")

    def standard_out(self, c):
        return ast.Unsupported(_span(c[0]), "STANDARD_OUT")

    def from_import(self, c):
        return ast.Unsupported(_span(c[0]), "FROM ... IMPORT")

    def export(self, c):
        return ast.Unsupported(_span(c[0]), "EXPORT ... TO")

    # ---------------------------------------------------------------- declarations
    def const_section(self, c):
        return _section("consts", c)

    def const_plain(self, c):
        name, value = c[0], _nodes(c)[-1]
        return ast.ConstDecl(_span(name), name.value, None, value)

    def const_typed(self, c):
        ty = c[0]
        name = next(t for t in c[1:] if isinstance(t, Token) and t.type == "NAME")
        return ast.ConstDecl(_span(name), name.value, ty, c[-1])

    def type_section(self, c):
        return _section("types", c)

    def type_alias(self, c):
        name = c[0]
        return ast.TypeDecl(_span(name), name.value, _nodes(c)[-1], _span(name))

    def type_record(self, c):
        rec = c[0]
        target = c[-1]
        if isinstance(target, ast.SimpleTypeRef):
            return ast.TypeDecl(rec.span, target.name, rec, target.span)
        return ast.TypeDecl(rec.span, target.value, rec, _span(target))

    def var_section(self, c):
        return _section("vars", c)

    def var_decl(self, c):
        ty, names = _nodes(c)
        return ast.VarDecl(ty.span, ty, names)

    def name_list(self, c):
        return [(t.value, _span(t)) for t in c if isinstance(t, Token) and t.type == "NAME"]

    def type(self, c):
        x = c[0]
        if isinstance(x, Token):
            return ast.NamedTypeRef(_span(x), x.value)
        return x

    def simple_type(self, c):
        t = c[0]
        name = "STRING" if t.type == "STRING_T" else t.type
        return ast.SimpleTypeRef(_span(t), name)

    joint_type = simple_type

    def array_type(self, c):
        lo, hi, elem = _nodes(c)
        return ast.ArrayTypeRef(_span(c[0]), lo, hi, elem)

    def record_type(self, c):
        return ast.RecordTypeRef(_span(c[0]), _nodes(c))

    def field_decl(self, c):
        ty, names = _nodes(c)
        return (ty, names)

    def procedure(self, c):
        return self._routine(c, is_function=False)

    def function(self, c):
        return self._routine(c, is_function=True)

    def _routine(self, c, is_function: bool) -> ast.Routine:
        kw, name = c[0], c[1]
        params: list[ast.Param] = []
        result = None
        decls = ast.Decls()
        body: list[ast.Stmt] = []
        end_span = _span(kw)
        seen_begin = False
        for x in c[2:]:
            if isinstance(x, Token):
                if x.type == "BEGIN":
                    seen_begin = True
                elif x.type in ("ENDPROC", "ENDFCT"):
                    end_span = _span(x)
            elif isinstance(x, ast.Decls):
                _merge(decls, x)
            elif isinstance(x, list) and (not x or isinstance(x[0], ast.Param)) and not seen_begin:
                params = x
            elif isinstance(x, list):
                body = x
            elif isinstance(x, ast.TypeRef):
                result = x
        return ast.Routine(
            _span(name), name.value, is_function, params, result, decls, body, end_span
        )

    def params(self, c):
        return [p for group in _nodes(c) for p in group]

    def param_group(self, c):
        by_ref = c[0] is not None
        ty, names = _nodes(c)
        return [ast.Param(span, name, ty, by_ref) for name, span in names]

    # ---------------------------------------------------------------- statements
    def stmt_list(self, c):
        out: list[ast.Stmt] = []
        for s in c:
            if isinstance(s, list):
                out.extend(s)
            elif s is not None and not isinstance(s, Token):
                out.append(s)
        return out

    def empty(self, c):
        return None

    def labeled(self, c):
        name, stmt = c[0], c[-1]
        label = ast.Label(_span(name), name.value)
        if stmt is None or isinstance(stmt, Token):
            return [label]
        return [label, *(stmt if isinstance(stmt, list) else [stmt])]

    def assign(self, c):
        target, value = _nodes(c)
        return ast.Assign(target.span, target, value)

    def call_noargs(self, c):
        word = c[0].value.upper()
        if word in _MISSPELLED:  # `END_IF;` parses as a call: the typo's hint, at the typo
            raise _BuildError(
                _span(c[0]),
                f"'{c[0].value}' is not a keyword of this dialect",
                f"write {_MISSPELLED[word]}",
            )
        return ast.CallStmt(_span(c[0]), c[0].value, [])

    def call(self, c):
        args = c[1] if len(c) > 1 and c[1] is not None else []
        return ast.CallStmt(_span(c[0]), c[0].value, args)

    def return_(self, c):
        return ast.Return(_span(c[0]), c[1])

    def if_(self, c):
        cond, body = c[1], c[3]
        arms = [(cond, body)]
        else_body = None
        end = _span(c[-1])
        rest = c[4:-1]
        for x in rest:
            if isinstance(x, tuple):
                arms.append(x)
            elif isinstance(x, list):
                else_body = x
        return ast.If(_span(c[0]), arms, else_body, end)

    def elsif(self, c):
        return (c[1], c[3])

    def while_(self, c):
        return ast.While(_span(c[0]), c[1], c[3], _span(c[4]))

    def repeat(self, c):
        return ast.Repeat(_span(c[0]), c[1], c[3], _span(c[2]))

    def for_(self, c):
        # FOR NAME := expr TO expr [BY expr] DO stmt_list ENDFOR
        var = ast.Name(_span(c[1]), c[1].value)
        start, stop = c[2], c[4]
        step = c[6]
        body = c[8]
        return ast.For(_span(c[0]), var, start, stop, step, body, _span(c[9]))

    def case(self, c):
        selector = c[1]
        arms = [x for x in c if isinstance(x, ast.CaseArm)]
        else_body = None
        for i, x in enumerate(c):
            if isinstance(x, Token) and x.type == "ELSE":
                else_body = c[i + 1]
        return ast.Case(_span(c[0]), selector, arms, else_body, _span(c[-1]))

    def case_arm(self, c):
        labels = [x for x in c if isinstance(x, tuple)]
        body = c[-1]
        return ast.CaseArm(labels[0][0].span, labels, body)

    def case_label(self, c):
        return (c[0], c[2] if len(c) > 2 else None)

    def case_const(self, c):
        minus, tok = c[0], c[1]
        node = self._literal(tok)
        if minus is not None:
            if not isinstance(node, ast.Num):
                raise _BuildError(_span(minus), "'-' before a non-number case label")
            node = ast.Num(_span(minus), -node.value, "-" + node.text)
        return node

    def goto(self, c):
        return ast.Goto(_span(c[1]), c[1].value)

    def wait(self, c):
        return ast.Wait(_span(c[0]), c[1])

    def wait_for(self, c):
        return ast.WaitFor(_span(c[0]), c[2])

    def pause(self, c):
        return ast.Pause(_span(c[0]))

    def halt(self, c):
        return ast.Halt(_span(c[0]))

    def write(self, c):
        return ast.Write(_span(c[0]), c[1] or [], False)

    def writeln(self, c):
        return ast.Write(_span(c[0]), c[1] or [] if len(c) > 1 else [], True)

    # motion
    def _move(self, c, kind: str, targets: list) -> ast.Move:
        clauses = [x for x in c if isinstance(x, ast.WithClause)]
        return ast.Move(_span(c[0]), kind, targets, clauses)

    def move_ptp(self, c):
        return self._move(c, "PTP", [c[2]])

    def move_lin(self, c):
        return self._move(c, "LIN", c[2])

    def move_path(self, c):
        return self._move(c, "LINPATH", c[3])

    def move_circle(self, c):
        return self._move(c, "CIRCLE", [c[2], c[3]])

    def move_inc_lin(self, c):
        return self._move(c, "LININC", [c[2]])

    def move_inc_ptp(self, c):
        return self._move(c, "PTPINC", [c[2]])

    def with_param(self, c):
        word = c[1]
        return ast.WithClause(_span(word), word.value.upper(), [c[2]], word.value)

    def with_limit(self, c):
        return ast.WithClause(_span(c[1]), c[1].type, [c[2], c[3]], c[1].value)

    def with_reconf(self, c):
        return ast.WithClause(_span(c[1]), "RECONF", c[2], c[1].value)

    # modal redundancy options
    def limit_on(self, c):
        return ast.ModalOn(_span(c[0]), _LIMIT_OPTION[c[0].type], [c[1], c[2]])

    def limit_off(self, c):
        return ast.ModalOff(_span(c[0]), _LIMIT_OPTION[c[0].type])

    def cyclic_on(self, c):
        return ast.ModalOn(_span(c[0]), "CYCLIC", [])

    def cyclic_off(self, c):
        return ast.ModalOff(_span(c[0]), "CYCLIC")

    def obstacle_on(self, c):
        return ast.ModalOn(_span(c[0]), "OBSTACLE", [], c[1].value, _span(c[1]))

    def obstacle_off(self, c):
        return ast.ModalOff(_span(c[0]), "OBSTACLE", c[1].value, _span(c[1]))

    def freeze_on(self, c):
        return ast.ModalOn(_span(c[0]), "FREEZE", c[1])

    def freeze_off(self, c):
        return ast.ModalOff(_span(c[0]), "FREEZE")

    def reconf(self, c):
        return ast.Reconfigure(_span(c[0]), c[1])

    def designator(self, c):
        node: ast.Expr = ast.Name(_span(c[0]), c[0].value)
        for sel in c[1:]:
            kind, arg, span = sel
            node = ast.Field(span, node, arg) if kind == "field" else ast.Index(span, node, arg)
        return node

    def field_sel(self, c):
        return ("field", c[0].value, _span(c[0]))

    def index_sel(self, c):
        return ("index", c[0], c[0].span)

    # ---------------------------------------------------------------- expressions
    def expr_list(self, c):
        return list(c)

    def compare(self, c):
        left, op, right = c
        return ast.Binary(_span(op), op.value, left, right)

    def binop(self, c):
        left, op, right = c
        return ast.Binary(_span(op), _BINOPS.get(op.type, op.value.upper()), left, right)

    def unop(self, c):
        op, operand = c
        return ast.Unary(_span(op), op.value.upper(), operand)

    def field(self, c):
        return ast.Field(_span(c[1]), c[0], c[1].value)

    def index(self, c):
        return ast.Index(c[1].span, c[0], c[1])

    def _literal(self, tok: Token) -> ast.Expr:
        if tok.type == "NUMBER":
            return self.number([tok])
        if tok.type == "STRING":
            return self.string([tok])
        return self.boolean([tok])

    def number(self, c):
        tok = c[0]
        text = tok.value
        if not _NUMBER_RE.fullmatch(text):  # NUMBER swallows trailing letters: '1e', '12abc'
            raise _malformed_number(tok)
        if re.fullmatch(r"\d+", text):
            value = parse_integer(text)
            if isinstance(value, str):
                raise _BuildError(
                    _span(tok),
                    value,
                    f"INTEGER literals go up to {INT_MAX} (write {-INT_MAX} - 1 for the "
                    "smallest INTEGER); a larger number needs a REAL literal such as 1e20",
                )
            return ast.Num(_span(tok), value, text)
        value = float(text)
        if value == float("inf"):
            raise _BuildError(_span(tok), f"number {text} is too large")
        return ast.Num(_span(tok), value, text)

    def string(self, c):
        return ast.Str(_span(c[0]), _unquote(c[0].value))

    def boolean(self, c):
        return ast.Bool(_span(c[0]), c[0].type == "TRUE")

    def name(self, c):
        return ast.Name(_span(c[0]), c[0].value)

    def funcall(self, c):
        name = c[0]
        args = c[1] if len(c) > 1 and c[1] is not None else []
        spelled = name.value.upper() if name.type in ("POSE", "POSITION") else name.value
        return ast.Call(_span(name), spelled, args)

    def input(self, c):
        return ast.Input(_span(c[0]), c[1])

    def tuple(self, c):
        paren, first, rest = c
        return ast.Tuple(_span(paren), [first, *rest])


def _section(kind: str, c) -> ast.Decls:
    """A CONST / TYPE / VAR section: its declarations (``kind`` = the Decls list)."""
    items = _nodes(c)
    return ast.Decls(**{kind: items}, order=list(items))


def _unquote(text: str) -> str:
    q = text[0]
    return text[1:-1].replace(q + q, q)


def _merge(into: ast.Decls, d: ast.Decls) -> None:
    into.consts += d.consts
    into.types += d.types
    into.vars += d.vars
    into.order += d.order
