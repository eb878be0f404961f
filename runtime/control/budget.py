"""The bounds of a run: its simulated-time budget and its cycle budget (docs/runtime.md,
"Bounds of a run"). Both are checked before any cycle of a statement is simulated, so a
statement that would take the run past them fails at its own line at once.

The cycle budget counts the IPO cycles a run may simulate — those of motion (a motion
statement counts at least :data:`MOTION_MIN_CYCLES`) and those a WAIT records — since
what a run computes and records grows with its cycles (an IK cycle costs 0.1–2 ms of
CPU), not with its simulated time. With drives their steps count too,
:data:`DRIVE_STEPS_PER_CYCLE` to a cycle.
"""

from __future__ import annotations

import math
from typing import Protocol

from irlc.runtime import units
from irlc.runtime.errors import RunFailure

# ≈ 8 min of robot time at the default 10 ms: a small R_IPO, a long slow motion or a loop
# of motions or waits is bounded here; a long WAIT's time by the time budget.
DEFAULT_MAX_CYCLES = 50_000
# Planning a motion statement and checking that its target is reachable cost about four IK
# cycles (a loop of one-cycle LINs on koch11: ≈ 2 ms of CPU a statement against ≈ 0.4 ms an
# IK cycle), so a statement counts at least five: such a loop meets the default budget
# after 10,000 statements, not 50,000 (24 s of CPU instead of 100 on a slow, loaded machine).
MOTION_MIN_CYCLES = 5
# With drives (``--drives`` other than ideal) the drive simulation steps through the run's
# time at its own step h (≤ 1 ms; 125 µs at the pwm level), each step costing about a fifth
# of a koch11 IK cycle (70–140 µs of CPU against 350 µs) and keeping ≈ 2 kB until the run
# ends: DRIVE_STEPS_PER_CYCLE drive steps count as one cycle (250,000 steps by default,
# ≈ 0.5 GB on koch11).
DRIVE_STEPS_PER_CYCLE = 5


class BudgetOptions(Protocol):
    """Where the budgets are set (``ExecutionOptions``; read when a statement asks)."""

    max_time_s: float  # the simulated-time budget (s)
    max_cycles: int  # the cycle budget
    drive_step_s: float | None  # the drives' step h (s) when drives are simulated


class RunBudget:
    """The time budget and the cycle budget of a run, as ``opts`` sets them."""

    def __init__(self, opts: BudgetOptions):
        self.opts = opts
        self.granted = 0  # cycles granted so far (since the last restart)

    def check_time(self, t: float, seconds: float, line: int, what: str) -> None:
        """:class:`RunFailure` (line, time ``t``) when ``seconds`` more would take the run
        past its simulated-time budget (so a WAIT 1e9 SEC fails at once)."""
        budget = self.opts.max_time_s
        if t + seconds > budget:
            raise RunFailure(
                f"{what} would take {units.seconds_text(seconds)} and the run past its"
                " simulated-time budget "
                f"of {budget:g} s (at t = {t:.3f} s; raise it with --max-time)",
                line,
                t,
            )

    def grant(
        self, cycles: int, seconds: float, t: float, line: int, what: str, minimum: int = 0
    ) -> None:
        """Count a statement's ``cycles`` recorded IPO cycles (over ``seconds`` of robot
        time), at least ``minimum``, before they are simulated; :class:`RunFailure` if
        they would exceed the budget. With drives the drive steps of ``seconds`` count
        instead when they are more (the drives simulate every step, a long WAIT's too)."""
        h, charged = self.opts.drive_step_s, max(cycles, minimum)
        if h:
            charged = max(charged, math.ceil(seconds / (DRIVE_STEPS_PER_CYCLE * h) - 1e-9))
        limit = self.opts.max_cycles
        if self.granted + charged <= limit:
            self.granted += charged
            return
        cost = f"{cycles} IPO cycle{'s' if cycles != 1 else ''}"
        if charged > max(cycles, minimum):
            cost = (
                f"{charged} cycles of the budget ({math.ceil(seconds / h - 1e-9)} drive steps"
                f" of {h * 1e3:.3g} ms, {DRIVE_STEPS_PER_CYCLE} to a cycle)"
            )
        elif charged > cycles:
            cost = (
                f"{charged} cycles of the budget ({cost}; a motion statement counts at least"
                f" {minimum})"
            )
        raise RunFailure(
            f"{what} would take {cost} and the run past its budget of {limit} simulated"
            f" cycles ({self.granted} so far, at t = {t:.3f} s; raise it with"
            " --max-cycles)",
            line,
            t,
        )

    def restart(self) -> None:
        """Count the cycle budget from here (the REPL: each entry has the whole budget)."""
        self.granted = 0
