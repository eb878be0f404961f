"""The simulated controller's state: what an IPO cycle (or a statement) changes.

One :class:`ControllerState` is shared by the controller's parts (the cycle runner, the
blender, self-motion); :meth:`ControllerState.snapshot` / :meth:`ControllerState.restore`
copy it field by field, so a blend that is tried and undone restores every field — a new
field is covered without touching the undo (tests/runtime/test_controller_parts.py).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
from irlc.runtime.control.segment_run import PendingSegment


@dataclass
class ControllerState:
    """``q``, ``q_prev``: the joints now and one cycle earlier (SI); ``t``: simulated time
    (s); ``cycles``: IPO cycles simulated; ``line``: the statement being executed;
    ``last_reference``: θ⁰ of the last IK cycle (``None`` after joint motion);
    ``segment_start``: the joints where the current segment started (a failure's cause);
    ``active_obstacles``: the avoided obstacles of the current segment; ``pending``: an
    approximated segment waiting for the next motion."""

    q: np.ndarray
    q_prev: np.ndarray
    t: float = 0.0
    cycles: int = 0
    line: int = 0
    last_reference: np.ndarray | None = None
    segment_start: np.ndarray | None = None
    active_obstacles: frozenset[str] = frozenset()
    pending: PendingSegment | None = None

    @classmethod
    def at(cls, q: np.ndarray) -> ControllerState:
        """At rest at ``q`` at t = 0."""
        q = np.array(q, dtype=float)
        return cls(q, q.copy(), segment_start=q.copy())

    def snapshot(self) -> ControllerState:
        """A copy (arrays copied; the other fields are immutable or replaced, not
        changed in place)."""
        return dataclasses.replace(self, **{f: _copy(getattr(self, f)) for f in _FIELDS})

    def restore(self, snap: ControllerState) -> None:
        """Every field back to ``snap``'s."""
        for name in _FIELDS:
            setattr(self, name, _copy(getattr(snap, name)))


_FIELDS = tuple(f.name for f in dataclasses.fields(ControllerState))


def _copy(value):
    return value.copy() if isinstance(value, np.ndarray) else value
