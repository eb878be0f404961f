"""The cycle-time table as the controller writes it: one
:class:`~irlc.runtime.outputs.cycle_time.StatementSpan` per statement that advances
simulated time (runtime/outputs/cycle_time.py has the rules and the report)."""

from __future__ import annotations

import dataclasses

from irlc.runtime.outputs.cycle_time import StatementSpan


class StatementLog:
    """The spans in the order the statements ran (they tile ``[0, duration]``)."""

    def __init__(self) -> None:
        self.spans: list[StatementSpan] = []

    def add(self, kind: str, line: int, start: float, end: float, stop, limit: str,
            override=None, call=None) -> None:  # fmt: skip
        """A statement's span (``call``: the routine and the line of its call, for a
        motion in a routine)."""
        self.spans.append(StatementSpan(line, kind, start, end, stop, limit, override, call))

    def end_at(self, index: int, t: float, stop: str | None = None) -> None:
        """The span at ``index`` — a statement whose point was pending (approximated) —
        ends at ``t``: where its exact stop ends, or where the next motion starts (after
        the cycles of its tail that run alone: a blend shorter than its tail leaves some),
        so the next statement's span is its own time (a ``WITH TIME := 3`` shows 3 s).
        Spans logged after it that took no time (a zero-length move) move to ``t``: the
        spans keep tiling the run (cycle_time.py)."""
        if index >= len(self.spans):  # its statement is still running (its points)
            return
        own = self.spans[index]
        self.spans[index] = dataclasses.replace(own, end=t, stop=stop or own.stop)
        for k in range(index + 1, len(self.spans)):
            self.spans[k] = dataclasses.replace(self.spans[k], start=t, end=t)
