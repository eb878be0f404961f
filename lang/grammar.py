"""The IRL grammar (irl.lark) as a lark LALR(1) parser with the contextual lexer.

:func:`lark_parser` builds it once per process (its tables cached per user, see
:func:`grammar_cache_file`) with :class:`~irlc.lang.ast_builder.Builder` as the transformer,
so parsing yields the AST. The lexer callbacks report what the token patterns accept but
the language does not: an unterminated comment, a keyword used as a name; the post-lexer
(:class:`GluedWords`) one word the contextual lexer split into a keyword and a name.
"""

from __future__ import annotations

import hashlib
import os
import re
import sys
from functools import lru_cache
from importlib import resources

import lark
from irlc.lang.ast_builder import Builder, SourceError, token_span
from irlc.lang.diagnostics import Span
from lark import Lark, Token


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
        raise SourceError(
            Span(tok.line, tok.column, tok.line, tok.column + len(opener)),
            f"unterminated comment: '{opener}' is never closed",
            f"close the comment with '{closer}' (comments do not nest)",
        )
    return tok


def _name_callback(tok: Token) -> Token:
    """A NAME that spells a keyword: the keyword was not acceptable here, so it is misused."""
    if tok.value.upper() in _keywords():
        raise SourceError(
            token_span(tok),
            f"'{tok.value}' is a reserved word",
            "choose another name (keywords cannot name variables, routines or labels)",
        )
    return tok


class GluedWord(SourceError):
    """One word read as a keyword and the word glued to it: where only keywords may come
    (``MOVE a ▯``: PTP, LIN, CIRCLE), the contextual lexer reads ``LIN_REL`` as ``LIN`` and
    the name ``_REL``, ``LINEAR`` as ``LIN`` and ``EAR``. ``word`` is the whole word."""

    def __init__(self, span: Span, word: str, keyword: str):
        super().__init__(span, f"'{word}' is not a word of this language")
        self.word, self.keyword = word, keyword


class GluedWords:
    """Lark post-lexer: a keyword token followed, with nothing between them, by a word
    token is one word of the text the lexer split (see :class:`GluedWord`); it is raised
    as that word, never parsed as two."""

    always_accept = ()

    def process(self, stream):
        previous = None
        for tok in stream:
            if previous is not None and _glued(previous, tok):
                whole = previous.value + tok.value
                end = Span(tok.line, tok.column, tok.end_line, tok.end_column)
                span = Span(previous.line, previous.column, end.end_line, end.end_column)
                raise GluedWord(span, whole, previous.value)
            previous = tok
            yield tok


def _glued(first: Token, second: Token) -> bool:
    if first.end_pos != second.start_pos or first.type == "NAME":
        return False
    head = str(second.value)[:1]
    return (head.isalnum() or head == "_") and str(first.value).upper() in _keywords()


@lru_cache(maxsize=1)
def lark_parser() -> Lark:
    grammar = resources.files("irlc.lang").joinpath("irl.lark").read_text(encoding="utf-8")
    return Lark(
        grammar,
        parser="lalr",
        lexer="contextual",
        transformer=Builder(),
        maybe_placeholders=True,
        lexer_callbacks={
            "COMMENT": _comment_callback,
            "NAME": _name_callback,
        },
        postlex=GluedWords(),
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
