"""Teaching: store a pose and its joints into a data list TOML file (REPL ``:teach``).

``teach(path, name, pose, joints)`` writes ``[poses] name = [x, y, z, a, b, c]`` (mm, deg
ZYX) and ``[joints] name_joints = [q1, …, qN]`` (deg | mm) — two names, because a data
list's names are one namespace (docs/language.md §8). The file is created when missing;
otherwise it is edited as **text**: an existing key's value is replaced in place (its
line's comment kept), a new key goes after the last entry of its section, a missing
section is appended. Comments, blank lines, order and every other entry stay as they
were; the new values are written by the project's one TOML writer
(:mod:`irlc.lang.toml_text`).

Every edit is verified before it is written: the new text must parse, hold exactly the
new values under the two keys, and equal the old file's data everywhere else;
otherwise nothing is written and :class:`TeachError` says why (e.g. a file that defines
``poses`` as an inline table). Numbers are written with 6 decimals at most (1 nm,
1 µdeg), trailing zeros dropped.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from pathlib import Path

from irlc.files import atomic_write_text, read_user_text
from irlc.lang import toml_text
from irlc.lang.errors import IrlcError
from irlc.lang.toml_keys import TomlError, parse_toml

NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
JOINTS_SUFFIX = "_joints"
NEW_FILE = "# Data list written by irlc :teach — poses mm, deg (ZYX); joints deg | mm\n"


class TeachError(IrlcError):
    """The pose cannot be stored (bad name, unreadable or unsuitable file)."""


DECIMALS = 6  # 1 nm, 1 µdeg


def number(v: float) -> str:
    """``12.5``, ``-0.000001``, ``90`` (6 decimals at most, no negative zero)."""
    return toml_text.number(_finite([v])[0], DECIMALS)


def array(values: Sequence[float]) -> str:
    """``[12.5, -90, 0]``, each as :func:`number`."""
    return toml_text.value(_finite(values), DECIMALS)


def _finite(values: Sequence[float]) -> list[float]:
    for v in values:
        if not math.isfinite(v):
            raise TeachError(f"cannot store the non-finite value {v!r}")
    return [float(v) for v in values]


def teach(path: Path, name: str, pose: Sequence[float], joints: Sequence[float]) -> list[str]:
    """Store ``pose`` under ``name`` and ``joints`` under ``name_joints`` in ``path``;
    returns the keys written (``["poses.p1", "joints.p1_joints"]``)."""
    if not NAME.match(name):
        raise TeachError(f"{name!r} is not a name (letters, digits, _; not starting with a digit)")
    unreadable = lambda f, reason: TeachError(f"{f}: {reason}; nothing written")  # noqa: E731
    old = read_user_text(path, unreadable) if path.exists() else NEW_FILE
    before = _parse(old, path)
    entries = (("poses", name, list(pose)), ("joints", name + JOINTS_SUFFIX, list(joints)))
    text = old
    for section, key, values in entries:
        text = upsert(text, section, key, values)
    after = _parse(text, path)
    _verify(before, after, entries, path)
    atomic_write_text(path, text)
    return [f"{section}.{key}" for section, key, _ in entries]


def _parse(text: str, path: Path) -> dict:
    try:
        return parse_toml(text)  # every way tomllib fails (lang/toml_keys.py)
    except TomlError as exc:
        where = f"{path}:{exc.line}" if exc.line else str(path)
        raise TeachError(f"{where}: not valid TOML ({exc.reason}); nothing written") from None


def _verify(before: dict, after: dict, entries, path: Path) -> None:
    """The edit changed exactly the taught keys (see the module doc)."""
    expected = {k: (dict(v) if isinstance(v, dict) else v) for k, v in before.items()}
    for section, key, values in entries:
        table = expected.setdefault(section, {})
        if not isinstance(table, dict):
            raise TeachError(f"{path}: '{section}' is not a table; nothing written")
        table[key] = [float(number(v)) for v in values]
    if _numbers(after) != _numbers(expected):
        raise TeachError(f"{path}: the file's layout cannot be edited safely; nothing written")


def _numbers(obj):
    """Data with every number as a float (``90`` and ``90.0`` compare equal)."""
    if isinstance(obj, dict):
        return {k: _numbers(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_numbers(v) for v in obj]
    if isinstance(obj, int | float) and not isinstance(obj, bool):
        return float(obj)
    return obj


# --------------------------------------------------------------------------- text edit

_HEADER = re.compile(r"\s*\[\s*([^\[\]]+?)\s*\]\s*(#.*)?\Z")  # [table], not [[array]]
_ANY_HEADER = re.compile(r"\s*\[")


def upsert(text: str, section: str, key: str, values: Sequence[float]) -> str:
    """``text`` with ``key = [values]`` set in table ``[section]`` (module doc)."""
    lines = text.splitlines()
    entry = f"{key} = {array(values)}"
    start = next((i for i, ln in enumerate(lines) if _is_header(ln, section)), None)
    if start is None:
        tail = [] if not lines or not lines[-1].strip() else [""]
        return "\n".join([*lines, *tail, f"[{section}]", entry]) + "\n"
    end = next((i for i in range(start + 1, len(lines)) if _ANY_HEADER.match(lines[i])), len(lines))
    key_re = re.compile(rf"\s*(?:{re.escape(key)}|\"{re.escape(key)}\"|'{re.escape(key)}')\s*=")
    for i in range(start + 1, end):
        if key_re.match(lines[i]):
            last, comment = _value_end(lines, i)
            indent = lines[i][: len(lines[i]) - len(lines[i].lstrip())]
            new = indent + entry + (f"  {comment}" if comment else "")
            return "\n".join([*lines[:i], new, *lines[last + 1 :]]) + "\n"
    at = end
    while at > start + 1 and not lines[at - 1].strip():  # before the section's blank lines
        at -= 1
    return "\n".join([*lines[:at], entry, *lines[at:]]) + "\n"


def _is_header(line: str, section: str) -> bool:
    m = _HEADER.match(line)
    return m is not None and m.group(1).strip("\"'") == section


def _value_end(lines: list[str], i: int) -> tuple[int, str]:
    """The last line of the value starting on line ``i`` (arrays may span lines) and the
    comment after it (``"# …"`` or ``""``)."""
    depth, j = 0, i
    started = False
    while j < len(lines):
        code, comment = _split_comment(lines[j] if j > i else lines[j].split("=", 1)[1])
        depth += code.count("[") - code.count("]")
        started = started or "[" in code or bool(code.strip())
        if started and depth <= 0:
            return j, comment
        j += 1
    raise TeachError("an unterminated array in the data list; nothing written")


def _split_comment(line: str) -> tuple[str, str]:
    """``(code, comment)`` of a TOML line (a ``#`` inside a string is not a comment)."""
    quote = ""
    for k, ch in enumerate(line):
        if quote:
            if ch == quote:
                quote = ""
        elif ch in "\"'":
            quote = ch
        elif ch == "#":
            return line[:k], line[k:].rstrip()
    return line, ""
