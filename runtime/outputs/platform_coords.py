"""Where a robot's platform was: the trace's ``platform_<c>_mm`` columns and the report's
``platform`` (docs/interfaces.md), for a robot whose file names a platform.

The platform's coordinates are those ``WITH PLATFORM`` sets — the world coordinates ``c``
of its point, ``c(θ_a) = c₀ + A·θ_a`` (:class:`irlc.robots.platform.Platform`) — of the
joints in each trace row (the actual joints with drives). The report gives them at the
start and the end and, per motion ``WITH PLATFORM``, its start, its target and the
platform's largest distance from its line over the motion's IK cycles (the platform
task's residual, :class:`~irlc.runtime.control.platform.PlatformRecord`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
from irlc.lang import trace_columns as tc
from irlc.robots.model import RobotModel
from irlc.runtime import units


def trace_columns(model: RobotModel) -> list[str]:
    """``platform_x_mm …`` per platform coordinate (none without a platform)."""
    platform = model.platform
    return [] if platform is None else [tc.platform(c) for c in platform.coordinates]


def coordinates(model: RobotModel, q: np.ndarray) -> np.ndarray:
    """``(k, d)`` the platform's coordinates (mm) of joint rows ``q`` (SI, ``(k, n)``)."""
    platform = model.platform
    assert platform is not None
    rows = np.asarray(q, dtype=float)[:, : len(platform.joints)]
    return (platform.origin + rows @ platform.matrix.T) / units.MM


def platform_report(
    model: RobotModel,
    names: Sequence[str],
    first: np.ndarray | None,
    last: np.ndarray | None,
    motions: list[dict],
    rnd: Callable[[float], float | None],
) -> dict:
    """The report's ``platform`` (mm): its joints, coordinates, where it started and
    ended (``first``, ``last``: the joints, SI; ``None``: no sample) and its motions."""
    platform = model.platform
    assert platform is not None

    def at(q: np.ndarray | None) -> list:
        return [] if q is None else [rnd(float(v)) for v in coordinates(model, q[None, :])[0]]

    return {
        "joints": [names[j] for j in platform.joints],
        "coordinates": list(platform.coordinates),
        "start_mm": at(first),
        "end_mm": at(last),
        "motions": [
            {
                **m,
                "start_mm": [rnd(v) for v in m["start_mm"]],
                "target_mm": [rnd(v) for v in m["target_mm"]],
                "max_error_mm": rnd(m["max_error_mm"]),
            }
            for m in motions
        ],
        "max_error_mm": rnd(max((m["max_error_mm"] for m in motions), default=0.0)),
    }
