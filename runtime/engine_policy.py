"""When the compiled kernels pay: the engine of a run where ``IRLC_ENGINE`` is unset.

The compiled kernels (``pip install 'irlc[fast]'``: numba) cost a fixed price per process —
importing numba and loading the cached machine code, ≈ 0.4 s of CPU (compiling it is a
once-per-installation ≈ 40 s, ``irlc warmup``) — and save per cycle: ≈ 80 µs of a koch11
IK cycle (≈ 120 against ≈ 40 µs per cycle of a whole kinematic run), more per drive step
(docs/benchmarks.md, "Where the compiled engine pays"). A short run loses (the square:
0.86 s numpy, 1.22 s compiled); a long run, a drive run of many steps and a study of
many variants in long-lived workers win. So, with numba installed and ``IRLC_ENGINE``
unset (:func:`deciding`):

* **a long run** goes on on the compiled IK kernels from its :data:`SWITCH_IK_CYCLES`-th
  IK cycle (at the next motion statement): a run that long has spent ≈ 0.6 s of numpy,
  about the kernels' fixed price, so it pays at most that price more than the better
  engine (the ski-rental bound) and gains ≈ 80 µs per later cycle;
* **a drive run** of at least :data:`DRIVE_STEPS` drive steps runs its drive loop on the
  compiled drive kernels (the steps are known before the drive stage starts);
* **a study** of at least :data:`STUDY_VARIANTS` variants runs every variant on the
  compiled kernels (:func:`for_study`): a worker pays the price once and saves ≈ 20 ms
  of a short koch11 variant, so from ≈ 25 variants per worker.

The choice is a function of the installation (numba present), ``IRLC_ENGINE`` and the
run's own program and options (its cycle count, its drive steps, the study's variant
count) — never of numba's cache, the machine's speed or the worker count — so the output
bytes of a run (or a study's results.csv) are a function of the installation and the
documented settings only, as before. The engines agree to round-off, not bit for bit.
An explicit ``IRLC_ENGINE`` decides by itself (``numpy``: never the kernels; ``compiled``,
``auto``: always, :mod:`irlc.runtime.accel_support`), and so does a caller's explicit
``IKParams.accel`` or ``simulate_drives(accel=…)``.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

from irlc.runtime import accel_support

SWITCH_IK_CYCLES = 5_000  # ≈ 0.6 s of numpy IK cycles: the kernels' fixed price
DRIVE_STEPS = 40_000  # ≈ 40 s of robot time at a 1 ms drive step (5 s at pwm's 125 µs)
STUDY_VARIANTS = 100  # ≥ 25 variants per worker up to 4 workers


@dataclass(frozen=True)
class EngineChoice:
    """A run's engine: ``ik_from`` — the IK cycle from which it runs on the compiled
    kernels (0: from the start; ``None``: ``IRLC_ENGINE`` decides); ``drives`` — the drive
    loop's ``accel`` flag (``None``: by :func:`drive_kernels`, else ``IRLC_ENGINE``)."""

    ik_from: int | None = None
    drives: bool | None = None
    drive_steps: int | None = None  # drive steps from which the drive loop is compiled


def deciding() -> bool:
    """The policy decides: numba is installed and ``IRLC_ENGINE`` is unset or empty (an
    invalid value is the usual :class:`~irlc.runtime.accel_support.EngineChoiceError`)."""
    accel_support.engine()
    unset = os.environ.get(accel_support.ENV, "").strip() == ""
    return unset and accel_support.NUMBA_INSTALLED


def for_run(engine: str | None = None) -> EngineChoice:
    """The engine of one run: ``engine="compiled"`` (a study's choice, :func:`for_study`)
    from the start; ``None`` — the policy (module doc) where it decides."""
    if engine == "compiled" and accel_support.kernels_allowed():
        return EngineChoice(ik_from=0, drives=True)
    if engine is None and deciding():
        return EngineChoice(ik_from=SWITCH_IK_CYCLES, drive_steps=DRIVE_STEPS)
    return EngineChoice()


def drive_kernels(choice: EngineChoice | None, steps: float) -> bool | None:
    """The drive loop's ``accel`` flag for a drive run of ``steps`` drive steps."""
    if choice is None:
        return None
    if choice.drives is not None:
        return choice.drives
    if choice.drive_steps is not None and steps >= choice.drive_steps:
        return True
    return None


def for_study(variants: int) -> str | None:
    """``"compiled"`` for a study whose variants pay the kernels' price (module doc), else
    ``None`` (each run as the policy says: the numpy engine for short runs)."""
    return "compiled" if deciding() and variants >= STUDY_VARIANTS else None


def compile_once(obstacles: bool, drives: bool) -> None:
    """Before the workers of a study on the compiled engine start: compile the kernels
    they will load, here, once — each worker would otherwise compile them itself, all at
    the same time (≈ 40 s of CPU each). Nothing when numba's cache holds them; the bytes
    of the runs do not depend on it (compiled or loaded, the machine code is the same)."""
    from irlc.runtime import warmup

    if not warmup.GROUPS["ik"][1]():
        warmup.warm_ik()
        if obstacles:
            warmup.warm_ik_obstacles()
    if drives and not warmup.GROUPS["drives"][1]():
        warmup.warm_drives()
