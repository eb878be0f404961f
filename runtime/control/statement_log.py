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
            override=None) -> None:  # fmt: skip
        self.spans.append(StatementSpan(line, kind, start, end, stop, limit, override))

    def exact_stop(self, line: int, t: float) -> None:
        """The span of the statement whose point was pending (approximated) ends where its
        exact stop ends, at ``t`` (the spans keep tiling the run)."""
        if self.spans and self.spans[-1].line == line:
            last = self.spans[-1]
            self.spans[-1] = dataclasses.replace(last, end=t, stop="exact")
