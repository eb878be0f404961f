"""Parse IRL source into the AST (:mod:`irlc.lang.ast`) with positioned diagnostics.

LALR(1) with lark's contextual lexer (lang/grammar.py); the AST is built during parsing
(lang/ast_builder.py, no parse tree). Lark's errors become :class:`Diagnostic` values that
speak the programmer's language (lang/syntax_errors.py).
"""

from __future__ import annotations

from irlc.lang import ast
from irlc.lang.ast_builder import SourceError
from irlc.lang.diagnostics import Diagnostic
from irlc.lang.grammar import keywords, lark_parser
from irlc.lang.syntax_errors import source_error_diagnostic, syntax_diagnostic
from lark.exceptions import UnexpectedInput

__all__ = ["keywords", "parse"]


def parse(text: str, filename: str) -> tuple[ast.Program | None, list[Diagnostic]]:
    """Parse ``text``; return the program (or ``None``) and diagnostics (one on error)."""
    try:
        return lark_parser().parse(text), []
    except SourceError as e:
        return None, [source_error_diagnostic(e, text, filename)]
    except UnexpectedInput as e:
        return None, [syntax_diagnostic(e, text, filename)]
