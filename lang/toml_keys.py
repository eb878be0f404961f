"""The line of a key in a TOML text: robot files and data lists name the key of an error
(``joints[3].axis``, ``obstacles.wall.size``); ``tomllib`` gives no positions, so the
line is searched in the text (best effort: tables ``[a.b]``, arrays of tables
``[[joints]]`` counted from 1, dotted and quoted keys, ``key = …`` lines; an index into an
inline array names the array's line)."""

from __future__ import annotations

import re
import tomllib

from irlc.lang.errors import IrlcError

_HEADER = re.compile(r"\s*(\[\[?)\s*([^\]]*?)\s*\]\]?\s*(#.*)?$")
_KEY = r"(?:[A-Za-z0-9_-]+|\"[^\"]*\"|'[^']*')"
_ASSIGN = re.compile(rf"\s*({_KEY}(?:\s*\.\s*{_KEY})*)\s*=")
_PART = re.compile(r"([^.\[\]]+)((?:\[\d+\])*)")

Path_ = list[tuple[str, int | None]]


def _dotted(text: str) -> list[str]:
    parts = re.findall(r"\"[^\"]*\"|'[^']*'|[^.\s]+", text)
    return [p[1:-1] if p[:1] in "\"'" else p for p in parts]


def key_path(key: str) -> Path_:
    """``joints[3].axis`` → ``[("joints", 3), ("axis", None)]`` (the first index only)."""
    out: Path_ = []
    for name, idx in _PART.findall(key):
        first = re.match(r"\[(\d+)\]", idx)
        out.append((name, int(first.group(1)) if first else None))
    return out


def key_line(text: str, key: str) -> int | None:
    """The 1-based line that defines ``key`` (or the nearest enclosing table or array of
    tables written in the text), ``None`` when no part of it is found."""
    position = key_position(text, key)
    return position[0] if position else None


def key_position(text: str, key: str) -> tuple[int, int] | None:
    """:func:`key_line` and the 1-based column where that line's key or ``[`` starts."""
    want = key_path(key)
    if not want:
        return None
    best: tuple[int, int] | None = None
    best_len = 0
    counts: dict[str, int] = {}
    table: Path_ = []
    for lineno, raw in enumerate(text.splitlines(), start=1):
        if (m := _HEADER.match(raw)) and not raw.lstrip().startswith("#"):
            names = _dotted(m.group(2))
            if m.group(1) == "[[":
                dotted = ".".join(names)
                counts[dotted] = counts.get(dotted, 0) + 1
                table = [(n, None) for n in names[:-1]] + [(names[-1], counts[dotted])]
            else:
                table = [(n, None) for n in names]
            path, column = table, raw.index("[") + 1
        elif m := _ASSIGN.match(raw):
            path, column = table + [(n, None) for n in _dotted(m.group(1))], m.start(1) + 1
        else:
            continue
        n = _common(path, want)
        if n > best_len:
            best, best_len = (lineno, column), n
    return best


def _common(path: Path_, want: Path_) -> int:
    """How many leading parts of ``want`` the line's ``path`` matches (an array of tables
    must match its index; a line deeper than ``want`` does not match)."""
    if len(path) > len(want):
        return 0
    n = 0
    for (name, idx), (wname, widx) in zip(path, want, strict=False):
        if name != wname or (idx is not None and idx != widx):
            return 0 if idx is not None and name == wname else n
        n += 1
    return n


MAX_KEY_PARTS = 64
"""The most dotted parts a key or table header of a user's TOML file may have: ``tomllib``
builds the nested tables of a dotted key in time and memory growing with the square of its
length (a key of 100,000 parts fills gigabytes)."""


class TomlError(IrlcError, ValueError):
    """A user's TOML text is not valid TOML: the reason (without the parser's position, and
    never the text) and the line (and column) where the parser stopped, when known."""

    def __init__(self, reason: str, line: int | None, column: int | None = None):
        self.reason, self.line, self.column = reason, line, column
        super().__init__(reason)


def parse_toml(text: str) -> dict:
    """``tomllib.loads(text)``, raising :class:`TomlError` for every way a text can fail:
    a syntax error, a number of more than 4,300 digits (``ValueError`` in ``int()``),
    nesting deeper than Python's recursion limit, a key of more than
    :data:`MAX_KEY_PARTS` parts."""
    lines = text.splitlines()
    for lineno, raw in enumerate(lines, start=1):
        if _key_text(raw).count(".") >= MAX_KEY_PARTS:
            raise TomlError(f"a key of more than {MAX_KEY_PARTS} dotted parts", lineno, 1)
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        m = re.search(r"\(at line (\d+), column (\d+)\)", str(e))
        reason = re.sub(r"\s*\(at (line \d+, column \d+|end of document)\)", "", str(e))
        if m:
            raise TomlError(reason or "invalid TOML", int(m.group(1)), int(m.group(2))) from None
        raise TomlError(reason or "invalid TOML", max(1, len(lines))) from None
    except RecursionError:
        line = _first(lines, lambda s: s.count("[") + s.count("{") > 100)
        raise TomlError("arrays or tables nested too deeply", line) from None
    except ValueError:  # int() of more than 4,300 digits (sys.get_int_max_str_digits)
        line = _first(lines, re.compile(r"[0-9_]{4000,}").search)
        raise TomlError("a number with too many digits", line) from None


def _key_text(raw: str) -> str:
    """The key part of a line: a table header's name, or the text before ``=``."""
    stripped = raw.lstrip()
    if stripped.startswith("["):
        return stripped.split("]", 1)[0]
    return raw.split("=", 1)[0] if "=" in raw else ""


def _first(lines: list[str], test) -> int | None:
    return next((k for k, s in enumerate(lines, start=1) if test(s)), None)
