"""Reading user text files and writing output files: the front door's one place for both.

* :func:`read_user_text` reads a file the user gave (robot, program code, report,
  expectation) as UTF-8, raising the caller's error type; it is owned by
  :mod:`irlc.lang.textfile` (the robot loader and the runtime read files too, and must
  not import the front door) and re-exported here.
* :func:`atomic_write_bytes` / :func:`atomic_write_text` / :func:`atomic_write_chunks`
  write to a temporary file in the target's folder, ``fsync`` it, give it the usual mode
  (``0o666 & ~umask``, i.e. 0644 with the common umask 022; ``mkstemp`` alone would leave
  0600) and rename it over the target (``os.replace``), so a reader never sees half a
  file.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Iterable
from pathlib import Path

from irlc.lang.textfile import ErrorFactory, read_user_text

__all__ = [
    "ErrorFactory",
    "atomic_write_bytes",
    "atomic_write_chunks",
    "atomic_write_text",
    "read_user_text",
]


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
    leaves the target untouched."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as f:
            for chunk in chunks:
                f.write(chunk)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
    return path


def atomic_write_text(path: str | Path, text: str) -> Path:
    """Write ``text`` (UTF-8, line ends as given — ``\\n`` in irlc) atomically to ``path``."""
    return atomic_write_bytes(path, text.encode("utf-8"))
