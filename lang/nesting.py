"""The nesting bound of IRL programs: expressions and statements nest at most MAX_NESTING deep.

The checker and the code generator walk the syntax tree recursively (one Python frame or
three per level), so an unbounded depth would end in Python's RecursionError. A program is
measured once, right after parsing, by an explicit-stack walk (no recursion here): the depth
of a node is the number of syntax-tree nodes above it, so ``x + x + … + x`` with *n* terms,
*n* nested IFs, *n* unary minuses and *n* nested calls all have depth ≈ *n*. Parentheses alone
add no node. The first node deeper than the bound is reported at its position.
"""

from __future__ import annotations

import dataclasses
import functools

from irlc.lang import ast
from irlc.lang.diagnostics import Diagnostic

MAX_NESTING = 200
"""The deepest nesting of expressions, statements and types (syntax-tree levels)."""


@functools.cache
def _init_fields(cls: type) -> tuple[str, ...]:
    """The init fields of a node class (the checker's own, ``init=False``, are skipped)."""
    return tuple(f.name for f in dataclasses.fields(cls) if f.init)


def nesting_error(program: ast.Program, filename: str) -> Diagnostic | None:
    """A diagnostic at the first node nested deeper than :data:`MAX_NESTING`, else ``None``."""
    stack: list[tuple[object, int]] = [(program, 0)]
    tree = (ast.Node, ast.Decls, list, tuple)
    while stack:
        obj, depth = stack.pop()
        if isinstance(obj, list | tuple):
            stack.extend((c, depth) for c in obj if isinstance(c, tree))
            continue
        if isinstance(obj, ast.Node):
            depth += 1
            if depth > MAX_NESTING:
                return Diagnostic(
                    "error",
                    f"nested more than {MAX_NESTING} levels deep",
                    filename,
                    obj.span,
                    "split the expression or the statement with intermediate variables or "
                    "procedures (expressions, statements and types nest at most "
                    f"{MAX_NESTING} levels)",
                )
        for name in _init_fields(type(obj)):
            child = getattr(obj, name)
            if isinstance(child, tree):
                stack.append((child, depth))
    return None
