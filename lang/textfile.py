"""Reading a text file the user gave: the one reader for every layer.

:func:`read_user_text` reads a file the user gave (robot, program code, report,
expectation) as UTF-8. A missing, unreadable or non-UTF-8 file raises the *caller's*
error type, built by ``error(file, reason)``, so the message names the file and the
exit code is the caller's (never a ``UnicodeDecodeError`` traceback).

It lives in :mod:`irlc.lang` (the lowest layer) so that the robot loader and the runtime
read files without importing the front door; the front door's :mod:`irlc.files`
re-exports it beside the atomic writers.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

ErrorFactory = Callable[[str, str], Exception]  # (file, reason) → the caller's error


def read_user_bytes(path: str | Path, error: ErrorFactory) -> bytes:
    """The bytes of ``path``; raises ``error(str(path), reason)`` when it cannot be read (a
    folder, device or pipe is no file to read: ``/dev/zero`` or a FIFO would be read
    without end)."""
    file = str(path)
    try:
        if Path(path).exists() and not Path(path).is_file():  # a device or pipe: endless
            reason = "not a regular file"
        else:
            return Path(path).read_bytes()
    except OSError as e:  # missing, a folder, a name too long, no permission
        reason = f"cannot read the file ({e.strerror or e})"
    raise error(file, reason)


def read_user_text(path: str | Path, error: ErrorFactory) -> str:
    """The UTF-8 text of ``path`` (a leading byte-order mark dropped); raises
    ``error(str(path), reason)`` when it cannot be read (:func:`read_user_bytes`) or is not
    UTF-8."""
    file = str(path)
    data = read_user_bytes(path, error)
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as e:
        line = data.count(b"\n", 0, e.start) + 1
        reason = f"not a UTF-8 text file (byte 0x{data[e.start]:02x} on line {line})"
        raise error(file, reason) from None
