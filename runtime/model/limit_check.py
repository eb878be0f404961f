"""Do the position limits contain a joint state? The one check, tolerance and message.

A position limit that excludes the current state (a JOINTLIMIT switched on, a ``WITH``
limit, the intersection of the active limits at a motion's start) or a joint target it
excludes (a PTP or RECONFIGURATION target) is a run-time error naming the joint, its value
and the bound — never a silent clamp. Joint ``j`` at ``q_j`` is inside ``[lo_j, hi_j]`` when

    lo_j − tol_j ≤ q_j ≤ hi_j + tol_j,     tol_j = TOLERANCE (m | rad)

in SI, i.e. ``TOLERANCE / scale_j`` in program units (1e-6 mm, 5.7e-8 deg;
:func:`program_tolerances`). ``TOLERANCE`` is the slack of the inverse transformation's
per-cycle joint box (``runtime/ik/limits.py``): a state the solver left on a bound, within
its rounding, is inside; anything further out is excluded at every layer alike.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np
from irlc.runtime import units
from irlc.runtime.errors import RunFailure

TOLERANCE = 1e-9  # m | rad: a joint value this far beyond a position bound is still inside


@dataclass(frozen=True)
class Outside:
    """The first joint a position limit excludes: index (0-based), value and the bound it
    passes (both in the caller's units), and whether it is below the lower bound."""

    joint: int
    value: float
    bound: float
    below: bool

    @property
    def where(self) -> str:
        """``"below the lower"`` or ``"above the upper"`` (bound): where a message says the
        value lies."""
        return "below the lower" if self.below else "above the upper"

    @property
    def side(self) -> str:
        """``"min"`` or ``"max"``: the bound's side as a constraint names it."""
        return "min" if self.below else "max"


def program_tolerances(kinds: Sequence[str]) -> np.ndarray:
    """:data:`TOLERANCE` per joint in program units (mm | deg) for joint ``kinds``."""
    return TOLERANCE / units.joint_scale(kinds)


def each_outside(
    q: Sequence[float], lower: Sequence[float], upper: Sequence[float], tolerance=TOLERANCE
) -> Iterator[Outside]:
    """Every joint with ``q_j < lo_j − tol_j`` or ``q_j > hi_j + tol_j``, in joint order.
    ``tolerance`` is one number or one per joint, in the units of ``q`` (default: SI)."""
    tol = np.broadcast_to(np.asarray(tolerance, dtype=float), (len(q),))
    for j, (v, lo, hi) in enumerate(zip(q, lower, upper, strict=True)):
        if v < lo - tol[j]:
            yield Outside(j, float(v), float(lo), True)
        elif v > hi + tol[j]:
            yield Outside(j, float(v), float(hi), False)


def first_outside(
    q: Sequence[float], lower: Sequence[float], upper: Sequence[float], tolerance=TOLERANCE
) -> Outside | None:
    """The first of :func:`each_outside`, or ``None``."""
    return next(each_outside(q, lower, upper, tolerance), None)


def limit_failure(
    subject: str,
    outside: Outside,
    name: str,
    value: str,
    bound: str,
    line: int | None = None,
    cause: str | None = None,
) -> RunFailure:
    """The one message of :func:`first_outside`'s finding, e.g. ``"JOINTLIMIT excludes the
    current state: joint a3 is at 30.0 deg, above the upper bound 25.0 deg"``, with the
    constraint ``"joint a3 position max 25.0 deg"``. ``subject`` says what is checked
    (``"<option> excludes the current state"``, ``"PTP target"``); ``name`` is the joint's
    label (runtime/model/naming.py), ``value`` and ``bound`` are formatted with their unit."""
    return RunFailure(
        f"{subject}: joint {name} is at {value}, {outside.where} bound {bound}",
        line,
        constraint=f"joint {name} position {outside.side} {bound}",
        cause=cause,
    )
