"""When the optional compiled kernels (``pip install irlc[fast]``: numba) are used.

Shared by the IK accelerator (:mod:`irlc.runtime.ik.accel`) and the drive accelerator
(:mod:`irlc.runtime.drives.accel`). The numpy paths are the reference; a kernel is used
(:func:`decide`) when the caller's ``requested`` flag is ``True`` (always, compiling if
needed), never when it is ``False``, and by default (``None``) when numba is importable
and the kernel is already in numba's on-disk cache — so a short run never pays the
compile. ``IRLC_NO_ACCEL=1`` disables every kernel whatever the flag says;
``IRLC_ACCEL=1`` / ``0`` overrides the default ``None``.
"""

from __future__ import annotations

import importlib.util
import os
from collections.abc import Callable

DISABLED = os.environ.get("IRLC_NO_ACCEL", "") == "1"
AVAILABLE = not DISABLED and importlib.util.find_spec("numba") is not None  # (not imported)


def kernel_cached(kernel) -> bool:
    """True when numba's on-disk cache holds ``kernel`` (a ``@njit(cache=True)`` dispatcher)
    for its current source (numba's index is keyed by the source file's time stamp and
    size)."""
    if not AVAILABLE:
        return False
    try:
        return bool(kernel._cache._cache_file._load_index())
    except Exception:  # numba's internal cache API changed, or unreadable: assume cold
        return False


def decide(requested: bool | None, cache_warm: Callable[[], bool]) -> bool:
    """Use a kernel? ``cache_warm`` is asked only for the default ``None``."""
    if not AVAILABLE or requested is False:
        return False
    if requested is True:
        return True
    env = os.environ.get("IRLC_ACCEL", "")
    if env in ("0", "1"):
        return env == "1"
    return cache_warm()
