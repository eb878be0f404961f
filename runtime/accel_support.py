"""When the optional compiled kernels (``pip install irlc[fast]``: numba) are used.

Shared by the IK accelerator (:mod:`irlc.runtime.ik.accel`) and the drive accelerator
(:mod:`irlc.runtime.drives.accel`). The numpy paths are the reference; a kernel is used
(:func:`decide`) when the caller's ``requested`` flag is ``True``, never when it is
``False``, and by default (``None``) whenever numba is importable. The default depends
on the installation only — not on whether numba's on-disk cache is already warm — so the
same program gives the same output bytes on every run of one installation (the two
paths agree to round-off, not bit for bit). The first run after installing compiles the
kernels once (about 15 s) and caches them; ``python -m irlc.runtime.ik.accel`` and
``python -m irlc.runtime.drives.accel`` do that ahead of time. ``IRLC_NO_ACCEL=1``
disables every kernel whatever the flag says; ``IRLC_ACCEL=1`` / ``0`` overrides the
default ``None``.
"""

from __future__ import annotations

import importlib
import importlib.util
import os

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


def decide(requested: bool | None) -> bool:
    """Use a kernel? (:meth:`Kernels.cache_warm` only tells benchmarks and warm-up
    commands whether the next use will compile; it does not enter the decision.)"""
    if not AVAILABLE or requested is False:
        return False
    if requested is True:
        return True
    env = os.environ.get("IRLC_ACCEL", "")
    if env in ("0", "1"):
        return env == "1"
    return True


class Kernels:
    """The kernel module of one accelerator, imported on first use (importing numba costs
    ≈ 0.2 s, which a run on the numpy path should not pay). ``probe`` names the kernel whose
    cache entry tells whether the next use compiles."""

    def __init__(self, module: str, probe: str):
        self._name, self._probe, self._module = module, probe, None

    def load(self):
        if self._module is None:
            self._module = importlib.import_module(self._name)
        return self._module

    def cache_warm(self) -> bool:
        """True when numba's on-disk cache holds the probe kernel for the current source."""
        return AVAILABLE and kernel_cached(getattr(self.load(), self._probe))
