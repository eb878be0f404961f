"""Which files a program may make irlc read: ``ROBOT r := 'file'`` and ``IMPORT DATALIST``.

A program is input — possibly someone else's — and the files it names are read with the
user's rights, so a program may name files only inside its *allowed roots*:

* robot files: the program's folder and the robot library (``irlc.robots``);
* data lists: the program's folder, each ``--datalist-path`` folder and the library's
  ``datalists`` folder.

The rule is applied to the *resolved* file: the named path is joined to the program's
folder (an absolute path is kept as written), then resolved — ``..`` removed and every
symbolic link followed — and the result must lie inside one of the roots, each resolved
the same way. So ``'../x.toml'``, ``'/etc/x.toml'`` and a link in the program's folder that
points elsewhere are refused unless they land inside a root; ``'cell/arm.toml'`` and an
absolute path into the program's folder are allowed.

``--allow-any-path`` (every command that compiles or runs a program), ``allow_any_path=True``
(the Python API) lifts the rule. Files the *user* names — ``--robot FILE``,
``load_robot(path)``, ``:robot FILE`` in the REPL — are the user's choice and never checked.
"""

from __future__ import annotations

import math
import os
import re
import stat
from collections.abc import Iterable
from pathlib import Path

ALLOW_HINT = "pass --allow-any-path (allow_any_path=True in Python) to read it anyway"


def _real(path: Path) -> Path | None:
    """``path`` resolved (``..`` removed, links followed); None when it cannot be."""
    try:
        return Path(path).resolve()
    except (OSError, RuntimeError, ValueError):  # a symlink loop (Python < 3.13); a NUL byte
        return None


def is_file(path: Path) -> bool:
    """``path.is_file()``, but ``False`` for a name the system refuses (too long, a NUL
    byte, any other OSError): such a name never names a file a program can use."""
    try:
        return Path(path).is_file()
    except (OSError, ValueError):
        return False


def path_kind(path: Path) -> str:
    """What ``path`` names: ``"file"`` (a regular file), ``"folder"``, ``"other"`` (a
    device, pipe or socket: never read) or ``"missing"`` — also for a name the system
    refuses (too long, a NUL byte), as :func:`is_file` treats it."""
    try:
        if Path(path).is_file():
            return "file"
        if Path(path).is_dir():
            return "folder"
        return "other" if Path(path).exists() else "missing"
    except (OSError, ValueError):
        return "missing"


def shown(path: Path) -> str:
    """``path`` as a message shows it: resolved where it can be (where ``..`` and links lead)."""
    return str(_real(path) or path)


def inside_roots(path: Path, roots: Iterable[Path]) -> bool:
    """True when the resolved ``path`` lies inside (or is) one of the resolved ``roots``."""
    real = _real(path)
    if real is None:
        return False
    for root in roots:
        base = _real(root)
        if base is not None and real.is_relative_to(base):
            return True
    return False


def refusal(roots: Iterable[Path]) -> str:
    """The message for a file outside ``roots`` (it names the roots, never the file's text)."""
    folders = ", ".join(shown(Path(r)) for r in roots)
    return f"outside the folders a program may read from ({folders})"


def is_finite_number(value: int | float) -> bool:
    """A finite float, or an integer a float can hold (TOML integers have any size:
    ``0x`` and 5,000 ``f`` is an integer ``float()`` and ``math.isfinite`` refuse)."""
    if isinstance(value, int):
        return abs(value) <= 2**1023
    return math.isfinite(value)


def is_finite_real(value: object) -> bool:
    """A number of a user's file (an int or a float, not a boolean) that a float holds
    finitely (:func:`is_finite_number`)."""
    number = isinstance(value, int | float) and not isinstance(value, bool)
    return number and is_finite_number(value)


def shown_key(key: str, limit: int = 48) -> str:
    """A key of a user's file for an error message (``joints[3].axis``): as written, or
    its start and its length when longer than ``limit`` characters (a key is named, never
    a whole line of the file)."""
    return key if len(key) <= limit else f"{key[:32]}… ({len(key)} characters)"


def shown_names(names: Iterable[str], limit: int = 10) -> str:
    """Names from a user's file for a hint (``box1, box2, and 3 more``): at most ``limit``
    of them, each as :func:`shown_key` shows a key."""
    names = list(names)
    shown = [shown_key(n) for n in names[:limit]]
    if len(names) > limit:
        shown.append(f"and {len(names) - limit} more")
    return ", ".join(shown)


_WORD = re.compile(r"[a-z][a-z0-9_]{0,15}")  # a vocabulary word: shown (describe)
_NON_FINITE_WORDS = {"nan", "inf", "infinity"}  # described: no "nan" in a message


def describe(value: object, limit: int = 60) -> str:
    """A value read from a user's file, for an error message, without echoing its text.

    Numbers and booleans are shown (``-1``, ``1e+308``, ``true``), and so is a short list
    of them (``[1, 2]``) and a short lower-case word (``'cone'``: a misspelt kind or unit,
    the vocabulary of these files, which the user needs to see); any other string is only
    described (``a string of 19 characters``), a list by its length, a table by its keys —
    an error names the key and the line, never the text of a file the program may not
    own."""
    if value is None:
        return "no value"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float) and not math.isfinite(value):
        return "not-a-number" if value != value else ("-" if value < 0 else "") + "infinity"
    if isinstance(value, int) and abs(value).bit_length() > 3 * limit:  # repr() may refuse it
        return f"an integer of about {int(abs(value).bit_length() * 0.30103) + 1} digits"
    if isinstance(value, int | float):
        text = repr(value)
        return text if len(text) <= limit else f"an integer of {len(text.lstrip('-'))} digits"
    if isinstance(value, str):
        if _WORD.fullmatch(value) and value not in _NON_FINITE_WORDS:
            return repr(value)
        return f"a string of {len(value)} character{'s' if len(value) != 1 else ''}"
    if isinstance(value, list | tuple):
        if all(isinstance(v, int | float) for v in value):
            text = "[" + ", ".join(describe(v, limit) for v in value) + "]"
            if len(text) <= limit:
                return text
        return f"a list of {len(value)} value{'s' if len(value) != 1 else ''}"
    if isinstance(value, dict):
        keys = ", ".join(str(k) for k in list(value)[:6]) + (", ..." if len(value) > 6 else "")
        return f"a table (keys: {keys})" if value else "an empty table"
    return f"a {type(value).__name__}"


MAX_SOURCE_BYTES = 16 * 1024 * 1024
"""The largest program source read to show its lines (disassembly, the report's
statements): a larger or special file (a FIFO, a device) is treated as missing."""


def read_regular_bytes(path: str | Path, limit: int) -> bytes | None:
    """At most ``limit + 1`` bytes of a regular file, else ``None`` (missing, unreadable, a
    FIFO or device — which would block or never end —, or a name the system refuses: a
    NUL byte, too long). More than ``limit`` bytes returned means the file is larger."""
    try:
        with open(path, "rb", opener=_nonblocking) as f:
            if not stat.S_ISREG(os.fstat(f.fileno()).st_mode):
                return None
            return f.read(limit + 1)
    except (OSError, ValueError):
        return None


def read_source_text(path: str | Path, limit: int = MAX_SOURCE_BYTES) -> str | None:
    """The UTF-8 text of a regular file of at most ``limit`` bytes, else ``None``
    (:func:`read_regular_bytes`; too big or not UTF-8 too). For a program's source, which
    an ``.ird`` file names and which is shown only when it can be."""
    data = read_regular_bytes(path, limit)
    if data is None or len(data) > limit:
        return None
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        return None


def split_source_lines(text: str) -> list[str]:
    """A program's lines as the lexer counts them: split at ``\n`` only (a ``\r`` before
    it dropped), not at every Unicode line break ``str.splitlines`` knows (U+2028 in a
    comment would shift every line after it)."""
    lines = [line.removesuffix("\r") for line in text.split("\n")]
    return lines[:-1] if lines and lines[-1] == "" else lines


def program_source_lines(source: str, base_dir: str | Path | None) -> list[str] | None:
    """The lines of the program source an ``.ird`` file names (its SOURCE record): an
    ``.irl`` file only — a code file naming any other file shows none of it — looked up
    next to the code (``base_dir``) first, then as written; ``None`` when none is read."""
    if not source or Path(source).suffix.lower() != ".irl":
        return None
    candidates = [Path(source)]
    if base_dir is not None:
        candidates.insert(0, Path(base_dir) / Path(source).name)
    for path in candidates:  # a regular file of bounded size only
        if (text := read_source_text(path)) is not None:
            return split_source_lines(text)
    return None


def _nonblocking(path: str, flags: int) -> int:
    """Open without blocking on a FIFO (the file type is checked after opening)."""
    return os.open(path, flags | getattr(os, "O_NONBLOCK", 0))
