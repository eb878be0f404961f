"""Writing TOML, the one writer of the project: ``tomllib`` reads TOML but cannot write it,
and no TOML writer is a core dependency. Its users: the REPL's ``:teach`` (a pose and its
joints into a data list, edited as text), a study's varied data lists, and the export of a
robot model to a description file (``python -m irlc.robots.toml_export``); the reader's
helpers are :mod:`irlc.lang.toml_keys`.

``tomllib.loads(dumps(doc)) == doc`` for the values the project's documents hold —
tables, arrays of tables, arrays, strings, integers (64-bit), floats (``nan`` and ``inf``
as TOML writes them), booleans — tested on random documents
(``tests/lang/test_toml_text.py``):

* a key is bare when it can be (``[A-Za-z0-9_-]+``), else a basic string;
* a string is a basic string: ``"`` and ``\\`` escaped, control characters as
  ``\\n``, ``\\t``, … or ``\\uXXXX``;
* a float is its shortest exact text (``repr``; ``-0.0`` is ``0.0``), or with
  ``decimals`` at most that many decimals with trailing zeros dropped (``12.5``, ``90``: a
  whole value then reads back as an integer); ``finite=True`` refuses ``nan`` and ``inf``
  (:class:`ValueError`) where a document must not hold them;
* :func:`dumps` writes a table's plain values first, then its sub-tables (``[a.b]``),
  then its arrays of tables (``[[a]]``), each header after a blank line; a table inside an
  array, or an :class:`InlineTable`, is written inline (``{ x = 1, y = 2 }``).
"""

from __future__ import annotations

import math
import numbers
import re
from typing import Any

_BARE = re.compile(r"[A-Za-z0-9_-]+")
_ESCAPES = {'"': '\\"', "\\": "\\\\", "\b": "\\b", "\t": "\\t", "\n": "\\n", "\f": "\\f",
            "\r": "\\r"}  # fmt: skip
_MUST_ESCAPE = re.compile(r'["\\\x00-\x1f\x7f]')
_CONTROL = re.compile(r"[\x00-\x08\x0a-\x1f\x7f]")
INT_RANGE = (-(2**63), 2**63 - 1)  # TOML's integers: 64-bit signed


class InlineTable(dict):
    """A table :func:`dumps` writes inline, ``{ key = value, … }`` (a pose's ``origin``, a
    file's ``units``), where a plain ``dict`` would become a ``[table]``."""


def string(text: str) -> str:
    """``text`` as a TOML basic string."""
    return '"' + _MUST_ESCAPE.sub(lambda m: _escape(m.group()), text) + '"'


def _escape(ch: str) -> str:
    return _ESCAPES.get(ch) or f"\\u{ord(ch):04X}"


def key(name: str) -> str:
    """A key: bare when it can be, else a basic string (``"a b"``, ``"x.y"``, ``""``)."""
    return name if _BARE.fullmatch(name) else string(name)


def number(x: numbers.Real, decimals: int | None = None, *, finite: bool = False) -> str:
    """An integer as it is (64-bit); a float as its shortest exact text, or rounded to at
    most ``decimals`` decimals with trailing zeros dropped; never ``-0``. ``nan`` and
    ``inf`` are TOML's ``nan``, ``inf``, ``-inf``, or a :class:`ValueError` when
    ``finite``."""
    if isinstance(x, numbers.Integral) and not isinstance(x, bool):
        if not INT_RANGE[0] <= x <= INT_RANGE[1]:
            raise ValueError(f"cannot write the integer {x}: TOML's integers are 64-bit")
        return str(int(x))
    x = float(x)
    if not math.isfinite(x):
        if finite:
            raise ValueError(f"cannot write the non-finite number {x!r}")
        return "nan" if math.isnan(x) else ("inf" if x > 0 else "-inf")
    if decimals is None:
        return repr(x + 0.0)  # (+ 0.0: no negative zero)
    text = f"{round(x, decimals):.{decimals}f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def value(v: Any, decimals: int | None = None, *, finite: bool = False) -> str:
    """Any value on one line: a boolean, number, string, array or inline table."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, numbers.Real):
        return number(v, decimals, finite=finite)
    if isinstance(v, str):
        return string(v)
    if isinstance(v, list | tuple):
        return "[" + ", ".join(value(x, decimals, finite=finite) for x in v) + "]"
    if isinstance(v, dict):
        items = ", ".join(f"{key(k)} = {value(x, decimals, finite=finite)}" for k, x in v.items())
        return "{ " + items + " }" if items else "{}"
    raise ValueError(f"cannot write {type(v).__name__} as TOML")


def _comment(line: str) -> str:
    """A comment's text: control characters (TOML allows only the tab) as ``\\uXXXX``."""
    return _CONTROL.sub(lambda m: f"\\u{ord(m.group()):04X}", line)


def _is_table(v: Any) -> bool:
    return isinstance(v, dict) and not isinstance(v, InlineTable)


def _is_table_array(v: Any) -> bool:
    return isinstance(v, list) and bool(v) and all(_is_table(x) for x in v)


def dumps(doc: dict, *, header: str = "", decimals: int | None = None, finite: bool = False) -> str:
    """The TOML text of ``doc`` (module doc); ``header``: comment lines before it, each
    written ``# line``; ``decimals``, ``finite``: as :func:`number`."""
    comments = "".join(f"# {_comment(line)}".rstrip() + "\n" for line in header.splitlines())
    body = _table(doc, "", decimals, finite)
    return comments + (body if comments else body.removeprefix("\n"))


def _table(doc: dict, prefix: str, decimals: int | None, finite: bool) -> str:
    out = "".join(
        f"{key(k)} = {value(v, decimals, finite=finite)}\n"
        for k, v in doc.items()
        if not (_is_table(v) or _is_table_array(v))
    )
    for k, v in doc.items():
        name = f"{prefix}.{key(k)}" if prefix else key(k)
        if _is_table(v):
            out += f"\n[{name}]\n" + _table(v, name, decimals, finite)
        elif _is_table_array(v):
            for row in v:
                out += f"\n[[{name}]]\n" + _table(row, name, decimals, finite)
    return out
