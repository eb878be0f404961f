"""The one factory that picks the engine of the hot loops: the numpy reference or the
compiled kernels (numba).

Two loops have a compiled copy: the inverse transformation's IPO cycle
(:mod:`irlc.runtime.ik.compiled`) and the drive simulation's steps
(:mod:`irlc.runtime.drives.compiled`). Each caller asks here once, when it builds its
solver or loop, and runs the numpy path when the answer is ``None``:

* :func:`compiled_cycle` — for :class:`~irlc.runtime.ik.newton.InverseTransformation`;
* :func:`compiled_loop` — for the drive simulation (:mod:`irlc.runtime.drives.simulate`).

The choice is :func:`irlc.runtime.accel_support.decide` (``IRLC_ENGINE``, the caller's
``accel`` flag), then the kernels' coverage (what each compiled copy does not cover runs
on numpy). The compiled modules are imported only when chosen: numba's import costs
≈ 0.2 s that a numpy run should not pay. What the compiled copy costs to keep and where
it pays: docs/ik.md, "Compiled accelerator".
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from irlc.runtime import accel_support

if TYPE_CHECKING:
    from irlc.runtime.drives.compiled.loop import CompiledLoop
    from irlc.runtime.ik.compiled.driver import CompiledCycle


def compiled_cycle(ik) -> CompiledCycle | None:
    """The compiled cycle of solver ``ik`` (an ``InverseTransformation``), or ``None``:
    ``ik`` runs its numpy path. Not covered: ``solver = "daqp"``, ``max_iter < 1``."""
    p = ik.params
    if p.solver != "quadprog" or p.max_iter < 1 or not accel_support.decide(p.accel):
        return None
    from irlc.runtime.ik.compiled.driver import CompiledCycle

    return CompiledCycle(ik)


def compiled_loop(sim, requested: bool | None) -> type[CompiledLoop] | None:
    """The compiled loop class for drive simulation ``sim`` (averaged DC drives, or the
    ``pwm`` level), or ``None``: the numpy loop (``requested``: the run's ``accel`` flag;
    not covered: stepper drives, joints without drive data)."""
    from irlc.runtime.drives.compiled.loop import CompiledLoop
    from irlc.runtime.drives.compiled.pwm_loop import PwmLoop

    for loop in (CompiledLoop, PwmLoop):
        if loop.covers(sim):
            return loop if accel_support.decide(requested) else None
    return None
