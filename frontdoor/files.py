"""Reading user text files and writing output files: the one place for both.

* :func:`read_user_text` reads a file the user gave (robot, program code, report,
  expectation) as UTF-8. A missing, unreadable or non-UTF-8 file raises the *caller's*
  error type, built by ``error(file, reason)``, so the message names the file and the
  exit code is the caller's (never a ``UnicodeDecodeError`` traceback).
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
from collections.abc import Callable, Iterable
from pathlib import Path

ErrorFactory = Callable[[str, str], Exception]  # (file, reason) → the caller's error


def read_user_text(path: str | Path, error: ErrorFactory) -> str:
    """The UTF-8 text of ``path`` (a leading byte-order mark dropped); raises
    ``error(str(path), reason)`` when it cannot be read."""
    file = str(path)
    try:
        data = Path(path).read_bytes()
    except OSError as e:
        raise error(file, f"cannot read the file ({e.strerror or e})") from None
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as e:
        line = data.count(b"\n", 0, e.start) + 1
        reason = f"not a UTF-8 text file (byte 0x{data[e.start]:02x} on line {line})"
        raise error(file, reason) from None


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
