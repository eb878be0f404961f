"""Which engine runs the hot loops: numpy (the reference) or the compiled kernels.

Shared by the compiled IK cycle (:mod:`irlc.runtime.ik.compiled`) and the compiled drive
loops (:mod:`irlc.runtime.drives.compiled`); :mod:`irlc.runtime.engine` is the one factory
that asks :func:`decide` and builds them. One environment switch, ``IRLC_ENGINE``, chooses
for every caller that leaves its ``accel`` flag at ``None`` (:func:`decide`):

=============  ==========================================================================
(unset, empty) the default engine, numpy: callers at ``None`` run numpy; a caller's
               ``accel=True`` still runs the kernels (tests, benchmarks).
``numpy``      the numpy paths only (the reference), even where a caller asks for the
               kernels (``accel=True``).
``compiled``   the numba kernels wherever they cover the cycle (``pip install
               'irlc[fast]'``); numba missing is an environment error (exit 3).
``auto``       ``compiled`` when numba is importable, ``numpy`` otherwise.
=============  ==========================================================================

Any other value raises :class:`EngineChoiceError` (the command line exits 3 with its
message). ``accel=True`` / ``False`` on a caller overrides the switch, except that an
explicit ``numpy`` wins.

**Why numpy is the default.** The kernels must be compiled once per installation (``irlc
warmup`` with an empty cache, 2026-11-25: ≈ 24 s of CPU, ≈ 17 s for the IK kernels and ≈ 7
s for the drive kernels, so ≈ 25 s of wall time on a quiet machine and 35 s at load 2.7 on
2 shared cores; earlier, at heavier load, 50–100 s; 2026-11-26, the drive kernels with the
coupled refresh compiled in: ≈ 14.5 s of CPU alone, the PWM drive kernels ≈ 3 s, the IK
obstacle kernels ≈ 8 s); numba caches the machine code
(``__pycache__`` next to the kernel module, or ``NUMBA_CACHE_DIR``) and later processes
load it in ≈ 0.3 s. A default that compiles makes the first run slow; a default that
switches to the kernels once the cache is warm makes the output bytes depend on the
cache's state (the two paths agree to round-off, not bit for bit). With ``numpy`` as the
default every run is fast from the first one and gives the same bytes whatever the cache
holds; with ``compiled`` the bytes are those of the kernels on every run, compiled or
loaded (the cached machine code is the compiled one), and a run that has to compile says
so once on stderr (:meth:`Kernels.load`). ``irlc warmup`` (or ``python -m
irlc.runtime.warmup``) compiles ahead of the first run.
"""

from __future__ import annotations

import importlib
import importlib.util
import os
import sys

from irlc.lang.errors import IrlcError

ENV = "IRLC_ENGINE"
ENGINES = ("numpy", "compiled", "auto")
DEFAULT_ENGINE = "numpy"
KERNEL_NAMES = {  # the kernel modules, as the compile message names them
    "irlc.runtime.ik.compiled.cycle": "IK kernels",
    "irlc.runtime.drives.compiled.kernels": "drive kernels",
    "irlc.runtime.drives.compiled.pwm_kernels": "PWM drive kernels",
}
COMPILE_ESTIMATE = {  # wall time of the first compile, quiet machine … load ≈ 3 on 2 cores
    "IK kernels": "15–25 s",  # (measured 24.4 s wall at load 2.7, ≈ 17 s CPU)
    # (2026-11-26, with the coupled refresh compiled in: 14.6 s CPU, 53 s wall at load 13;
    # the previous drive kernel 7.3 s CPU in the same run, earlier 9.0 s wall at load 2.7)
    "drive kernels": "10–20 s",
    "PWM drive kernels": "3–6 s",  # (measured 4.0 s wall at load 5.5, ≈ 2.6 s CPU)
    "IK obstacle kernels": "5–15 s",  # (measured ≈ 8 s CPU; compiled on first use)
}
NUMBA_INSTALLED = importlib.util.find_spec("numba") is not None  # (not imported)


class EngineChoiceError(IrlcError, ValueError):
    """``IRLC_ENGINE`` names no engine, or one this installation lacks (exit 3)."""


def engine() -> str:
    """The engine ``IRLC_ENGINE`` selects (read on every call; see the module doc).
    Raises :class:`EngineChoiceError` for an unknown value or ``compiled`` without numba."""
    value = os.environ.get(ENV, "").strip().lower() or DEFAULT_ENGINE
    if value not in ENGINES:
        raise EngineChoiceError(
            f"{ENV}={os.environ.get(ENV)!r} is not an engine; use one of {', '.join(ENGINES)}"
        )
    if value == "compiled" and not NUMBA_INSTALLED:
        raise EngineChoiceError(
            f"{ENV}=compiled needs numba (pip install 'irlc[fast]'); or use {ENV}=auto / numpy"
        )
    return value


def _forced_numpy() -> bool:
    """``IRLC_ENGINE=numpy`` set explicitly (not merely the default)."""
    return os.environ.get(ENV, "").strip().lower() == "numpy"


def kernels_allowed() -> bool:
    """May any kernel run? numba is importable and ``IRLC_ENGINE`` is not ``numpy``."""
    return NUMBA_INSTALLED and not _forced_numpy()


# numba importable and not IRLC_ENGINE=numpy, at import (what the compiled engine's tests skip on)
AVAILABLE = kernels_allowed()


def kernel_cached(kernel) -> bool:
    """True when numba's on-disk cache holds ``kernel`` (a ``@njit(cache=True)`` dispatcher)
    for its current source (numba's index is keyed by the kernel's own source file: see
    ``SOURCES_DIGEST`` in :mod:`irlc.runtime.ik.compiled.cycle` for the modules it calls)."""
    if not NUMBA_INSTALLED:
        return False
    try:
        return bool(kernel._cache._cache_file._load_index())
    except Exception:  # numba's internal cache API changed, or unreadable: assume cold
        return False


def decide(requested: bool | None) -> bool:
    """Use a kernel? ``requested`` is the caller's ``accel`` flag; ``None`` follows
    :func:`engine`. Never a kernel without numba or under ``IRLC_ENGINE=numpy``; the
    state of numba's cache does not enter (same bytes on every run of one installation)."""
    choice = engine()  # (validates the variable even when the caller decides)
    if not kernels_allowed():
        return False
    if requested is not None:
        return requested
    return choice in ("compiled", "auto")


class Kernels:
    """The kernel module of one accelerator, imported on first use (importing numba costs
    ≈ 0.2 s, which a run on the numpy path should not pay). ``probe`` names the kernel whose
    cache entry tells whether the next use compiles; ``what`` names the kernels in the
    one-line message a compiling process prints (default: from :data:`KERNEL_NAMES`)."""

    def __init__(self, module: str, probe: str, what: str | None = None):
        self._name, self._probe = module, probe
        self._what = what or KERNEL_NAMES.get(module, module)
        self._module, self._announced = None, False

    def module(self):
        """The kernel module, imported without the compile message: for its constants (a
        caller that never calls its kernels compiles nothing)."""
        if self._module is None:
            self._module = importlib.import_module(self._name)
        return self._module

    def load(self):
        """The kernel module. The first load of a process whose cache lacks the kernels
        says on stderr that it compiles them (once; later runs load them)."""
        module = self.module()
        if not self._announced:
            self._announced = True
            if not self.cache_warm():
                print(compile_message(self._what), file=sys.stderr, flush=True)
        return module

    def cache_warm(self) -> bool:
        """True when numba's on-disk cache holds the probe kernel for the current source."""
        return kernel_cached(getattr(self.module(), self._probe))


def compile_message(what: str) -> str:
    """The line a process prints before it compiles ``what`` (see the module doc); the
    hint at ``irlc warmup`` is left out while that command runs (:data:`WARMING_UP`)."""
    hint = "" if WARMING_UP else "; `irlc warmup` does it ahead of time"
    took = COMPILE_ESTIMATE.get(what, "5–25 s")
    return f"irlc: compiling the {what} (numba, once per installation, ≈ {took}{hint}) …"


WARMING_UP = False  # set by `irlc warmup` (the message's hint would point at itself)
