"""Reading user text files and writing output files: the front door's one place for both.

* :func:`read_user_text` reads a file the user gave (robot, program code, report,
  expectation) as UTF-8, raising the caller's error type; it is owned by
  :mod:`irlc.lang.textfile` (the robot loader and the runtime read files too, and must
  not import the front door) and re-exported here.
* :func:`parse_user_json` parses the JSON text of such a file (an expectation, a report
  read back), raising the caller's error type for anything :mod:`json` cannot turn into
  finite numbers and bounded nesting.
* :func:`atomic_write_bytes` / :func:`atomic_write_text` / :func:`atomic_write_chunks`
  write to a temporary file in the target's folder, ``fsync`` it, give it the usual mode
  (``0o666 & ~umask``, i.e. 0644 with the common umask 022; ``mkstemp`` alone would leave
  0600) and rename it over the target (``os.replace``), so a reader never sees half a
  file. A symbolic link to a file is followed (the file is replaced, the link stays); a
  target that is no regular file — ``/dev/null``, ``/dev/stdout``, a terminal, a named
  pipe — is written in place, never replaced by a file (a pipe nobody reads is an error,
  not a wait). An error names the target, not the temporary file.
"""

from __future__ import annotations

import contextlib
import errno
import json
import math
import os
import stat
import tempfile
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from irlc.lang.errors import IrlcError
from irlc.lang.file_access import describe, is_finite_number, shown_key
from irlc.lang.textfile import ErrorFactory, read_user_text

__all__ = [
    "ErrorFactory",
    "atomic_write_bytes",
    "atomic_write_chunks",
    "atomic_write_text",
    "parse_user_json",
    "read_user_text",
]

JSON_INT_DIGITS = 4000  # below Python's int-from-text limit (4,300 digits): a clear error


class _BadNumber(IrlcError, ValueError):
    """A number of a JSON text that irlc does not take (raised inside the parser)."""


def _json_float(word: str) -> float:
    value = float(word)
    if not math.isfinite(value):
        raise _BadNumber(f"the number {shown_key(word)} is beyond a float's range")
    return value


def _json_int(word: str) -> int:
    if len(word.lstrip("-")) > JSON_INT_DIGITS:
        raise _BadNumber(f"an integer of {len(word)} digits (at most {JSON_INT_DIGITS})")
    value = int(word)
    if not is_finite_number(value):  # every number irlc reads is a float's
        raise _BadNumber(f"the number {shown_key(word)} is beyond a float's range")
    return value


def _json_constant(word: str) -> float:
    raise _BadNumber(f"a number that is not finite ({describe(float(word))})")


def parse_user_json(text: str, path: str | Path, error: ErrorFactory) -> Any:
    """The value of the JSON ``text`` of the user's file ``path``; raises ``error(file,
    reason)`` for a syntax error (``file`` is then ``PATH:LINE:COL``), nesting deeper than
    the parser can follow, a non-finite number (``NaN``, ``Infinity``, ``1e400``: described
    as ``not-a-number`` or ``infinity``, never echoed) or an integer too long to convert or
    beyond a float's range."""
    try:
        return json.loads(
            text, parse_float=_json_float, parse_int=_json_int, parse_constant=_json_constant
        )
    except json.JSONDecodeError as e:
        raise error(f"{path}:{e.lineno}:{e.colno}", f"not valid JSON: {e.msg}") from None
    except RecursionError:
        raise error(str(path), "not valid JSON: nested too deeply") from None
    except _BadNumber as e:
        raise error(str(path), f"not valid JSON: {e}") from None


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def atomic_write_bytes(path: str | Path, data: bytes) -> Path:
    """Write ``data`` atomically to ``path`` (folders created); returns the path."""
    return atomic_write_chunks(path, (data,))


def atomic_write_chunks(path: str | Path, chunks: Iterable[bytes]) -> Path:
    """Write the concatenated ``chunks`` atomically to ``path``, one chunk at a time (a
    long output never has to be one string in memory); an exception while producing them
    leaves the target untouched. A target that is no regular file is written in place
    (module doc). An :class:`OSError` names ``path``."""
    path = Path(path)
    try:
        target, in_place = _target(path)
        if in_place:
            _write_in_place(target, chunks)
        else:
            _replace(target, chunks)
    except OSError as exc:
        raise OSError(exc.errno, exc.strerror or str(exc), str(path)) from None
    return path


def _target(path: Path) -> tuple[Path, bool]:
    """``(file to write, in place?)``: a link to a (possibly not yet existing) file
    resolved, so that the file and not the link is replaced; a device, pipe or socket in
    place; a folder is :class:`IsADirectoryError`."""
    try:
        mode = os.stat(path).st_mode  # follows links
    except FileNotFoundError:
        mode = None
    if mode is not None and stat.S_ISDIR(mode):
        raise IsADirectoryError(errno.EISDIR, "is a folder", str(path))
    if mode is not None and not stat.S_ISREG(mode):
        return path, True
    return (Path(os.path.realpath(path)) if path.is_symlink() else path), False


def _write_in_place(path: Path, chunks: Iterable[bytes]) -> None:
    """Write to a device, pipe or socket as it is (``/dev/null``, ``/dev/stdout``); opened
    without blocking, so a pipe with no reader fails at once (ENXIO) instead of waiting. A
    reader that stops reading (``--trace /dev/stdout | head``) drops the rest, as standard
    output does (docs/interfaces.md, Exit codes)."""
    fd = os.open(path, os.O_WRONLY | getattr(os, "O_NONBLOCK", 0))
    if hasattr(os, "set_blocking"):
        os.set_blocking(fd, True)  # the writes themselves may wait for a slow reader
    with contextlib.suppress(BrokenPipeError), os.fdopen(fd, "wb") as f:
        for chunk in chunks:
            f.write(chunk)


def _replace(path: Path, chunks: Iterable[bytes]) -> None:
    """Write a temporary file beside ``path`` and rename it over ``path`` (module doc)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as f:
            for chunk in chunks:
                f.write(chunk)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, _mode_of(path))
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def _mode_of(path: Path) -> int:
    """The permissions the written file gets: those of the file it replaces (a report kept
    private with chmod 600 stays so), else a new file's (0o666 less the umask)."""
    try:
        return stat.S_IMODE(path.stat().st_mode)
    except OSError:
        return 0o666 & ~_umask()


def atomic_write_text(path: str | Path, text: str) -> Path:
    """Write ``text`` (UTF-8, line ends as given — ``\\n`` in irlc) atomically to ``path``."""
    return atomic_write_bytes(path, text.encode("utf-8"))
