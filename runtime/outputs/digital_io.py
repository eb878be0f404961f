"""Digital inputs and outputs over simulated time: the outputs' timelines and the trace
columns ``in_<n>`` / ``out_<n>`` / ``signal_<name>`` (SIGNAL variables, from their events).

An output's timeline is a list of switches ``(t, value)`` in time order; its value at
time ``t`` is that of the last switch at or before ``t`` (FALSE before the first), the
same rule as the inputs of a data list (``[inputs]``, ``interpreter._input``). So a trace
row at time ``t`` shows every switch up to ``t``: an output set right after a motion
appears in that motion's last sample.

``PULSE(OUT[n], d)`` at ``t`` is the switches ``(t, TRUE)`` and ``(t + d, FALSE)``; the
program goes on at once. A later assignment of the same output at ``t' < t + d`` wins:
the pending switch back is dropped (with its event).
"""

from __future__ import annotations

import bisect
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

TIME_TOLERANCE = 1e-9  # s, as for the inputs


@dataclass
class Outputs:
    """The switches of every output used so far (``n → [(t, value), …]``)."""

    switches: dict[int, list[tuple[float, bool]]] = field(default_factory=dict)
    pending: dict[int, dict] = field(default_factory=dict)  # n → event of a pulse's end

    def set(self, n: int, t: float, value: bool) -> dict | None:
        """Switch ``n`` to ``value`` at ``t``; returns the dropped pending pulse-end event
        (to remove from the report's events), if any."""
        timeline = self.switches.setdefault(n, [])
        dropped = None
        if timeline and timeline[-1][0] > t + TIME_TOLERANCE:  # a pulse's end still ahead
            timeline.pop()
            dropped = self.pending.pop(n, None)
        self.pending.pop(n, None)
        timeline.append((t, bool(value)))
        return dropped

    def pulse(self, n: int, t: float, duration: float, end_event: dict) -> dict | None:
        """TRUE at ``t``, FALSE at ``t + duration`` (``end_event`` logs the latter)."""
        dropped = self.set(n, t, True)
        self.switches[n].append((t + duration, False))
        self.pending[n] = end_event
        return dropped

    def value(self, n: int, t: float) -> bool:
        return value_at(self.switches.get(n, ()), t)


def value_at(timeline: Sequence[tuple[float, bool]], t: float) -> bool:
    """The value of a switch timeline (in time order) at ``t``: that of its last switch at
    or before ``t``, FALSE before its first; a binary search, so a program reading an
    output it switched many times stays fast."""
    k = bisect.bisect_right(timeline, t + TIME_TOLERANCE, key=_switch_time)
    return bool(timeline[k - 1][1]) if k else False


def _switch_time(switch: tuple[float, bool]) -> float:
    return switch[0]


def signal_timelines(events: Sequence[dict]) -> dict[str, list[tuple[float, bool]]]:
    """``name → [(t, value), …]`` of the SIGNAL variables, from their ``signal`` events."""
    out: dict[str, list[tuple[float, bool]]] = {}
    for e in events:
        if e.get("kind") == "signal":
            out.setdefault(str(e["name"]), []).append((float(e["time_s"]), bool(e["value"])))
    return out


def io_columns(
    times: np.ndarray,
    inputs: Mapping[int, Sequence[tuple[float, bool]]],
    outputs: Outputs,
    signals: Mapping[str, Sequence[tuple[float, bool]]] | None = None,
) -> tuple[list[str], np.ndarray]:
    """Trace columns ``in_<n>`` (every input of the data lists), ``out_<n>`` (every output
    the run switched), each in increasing ``n``, then ``signal_<name>`` (every SIGNAL the
    run wrote, by name): 0/1 at every row time."""
    names, cols = [], []
    groups = (("in", inputs), ("out", outputs.switches), ("signal", signals or {}))
    for prefix, timelines in groups:
        for n in sorted(timelines):
            timeline = sorted(timelines[n], key=lambda e: e[0])
            names.append(f"{prefix}_{n}")
            cols.append(_sampled(timeline, times))
    table = np.column_stack(cols) if cols else np.zeros((len(times), 0))
    return names, table


def _sampled(timeline: Sequence[tuple[float, bool]], times: np.ndarray) -> np.ndarray:
    """0/1 at each of ``times`` (vectorised :func:`value_at`; a stable sort keeps switches
    at the same time in order, the last one wins)."""
    if not timeline:
        return np.zeros(len(times))
    t = np.array([e[0] for e in timeline])
    v = np.array([1.0 if e[1] else 0.0 for e in timeline])
    idx = np.searchsorted(t, np.asarray(times) + TIME_TOLERANCE, side="right") - 1
    return np.where(idx >= 0, v[np.clip(idx, 0, None)], 0.0)
