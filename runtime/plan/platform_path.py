"""The platform's own path of a motion ``WITH PLATFORM := q`` (docs/runtime.md, Platform).

The platform (``irlc.robots.platform.Platform``: its coordinates ``c(θ_a) = c₀ + A·θ_a``)
moves along the straight line from where it is, ``c_s = c(θ_a)`` at the statement's start,
to the target ``c_e = q`` (SI), **in step with the TCP**: on a segment whose TCP path is
``x(s)``, ``s ∈ [0, 1]``, the platform is at ``x_platform(s) = c_a + s·(c_b − c_a)`` where
``c_a``, ``c_b`` are the line's points at the fractions of the statement's TCP path length
reached at the segment's start and end (one segment: the whole line; ``MOVE LIN p1, p2``
or ``LIN PATH``: split by arc length, as one WITH RECONFIGURATION for a whole LIN is).
Along a LIN or CIRCLE ``s`` is the fraction of the segment's length, so the platform is
the same fraction of its way as the TCP at every cycle. A segment whose TCP does not move
(the TCP holds while the platform moves) is split evenly.

Timing: the platform's joints ``θ_a(s) = A⁻¹(x_platform(s) − c₀)`` are linear in ``s``, so
joint ``j`` travels ``|Δθ_j|`` per unit ``s``, and the segment's ``s(t)`` obeys its speed and
acceleration limits (the active ones, scaled by the override like the path's settings;
under ``R_PROFILE := 'SCURVE'`` also each joint's jerk bound, the one a PTP uses) as more
axes (:func:`platform_timing`): the motion is never faster than the platform can follow.
"""

from __future__ import annotations

from collections.abc import Sequence
from itertools import pairwise

import numpy as np
from irlc.robots.platform import Platform
from irlc.runtime import units
from irlc.runtime.errors import RunFailure
from irlc.runtime.model.naming import JointNaming
from irlc.runtime.plan import scurve as sc
from irlc.runtime.plan.interpolator import PlatformLine
from irlc.runtime.plan.profiles import common_bounds, minimum_time
from irlc.runtime.plan.segment_timing import Bounds

PLATFORM_LIMIT = "platform_limit"
"""The failure cause of a platform target outside the platform's (active) limits."""


def target_failure(
    platform: Platform | None,
    robot: str,
    target_mm: Sequence[float],
    position: np.ndarray,
    naming: JointNaming,
    line: int,
) -> RunFailure | None:
    """Why the platform cannot go to ``target_mm``: the robot has none, the target has
    the wrong number of coordinates, or it lies outside the active position limits
    ``position`` (``(n, 2)`` SI; cause ``platform_limit``) — else ``None``."""
    if platform is None:
        return RunFailure(f"WITH PLATFORM: robot {robot} has no platform", line)
    k = platform.dimension
    if len(target_mm) != k:
        return RunFailure(
            f"WITH PLATFORM gives {len(target_mm)} coordinate(s); robot {robot}'s platform "
            f"has {k} ({', '.join(platform.coordinates)} mm)",
            line,
        )
    labels = [naming.label(j) for j in platform.joints]
    problem = platform.problem(target_mm, position, labels, "the active position limit")
    if problem is not None:
        return RunFailure(f"WITH PLATFORM: {problem}", line, cause=PLATFORM_LIMIT)
    return None


def held_joints(
    platform: Platform, frozen: dict[int, float], naming: JointNaming, line: int
) -> None:
    """A motion WITH PLATFORM moves the platform's joints: a FREEZE of any of them is a
    :class:`RunFailure` (both cannot hold)."""
    held = [j for j in platform.joints if j in frozen]
    if held:
        names = naming.labels(held)
        raise RunFailure(
            f"WITH PLATFORM moves the platform's joints, but FREEZE holds {names} "
            "(switch it off with FREEZEEND first)",
            line,
            cause="freeze",
        )


def platform_lines(
    platform: Platform, q: np.ndarray, target_mm: Sequence[float], lengths: Sequence[float]
) -> list[PlatformLine]:
    """The platform's line from its coordinates at ``q`` to the target, one piece per
    segment of TCP path length ``lengths[i]`` (module docstring)."""
    start = platform.coordinates_at(q)
    end = np.asarray(target_mm, dtype=float) * units.MM
    weights = np.asarray(lengths, dtype=float)
    if not weights.sum() > 0.0:  # the TCP does not move: split evenly
        weights = np.ones(len(weights))
    knots = np.concatenate(([0.0], np.cumsum(weights) / weights.sum()))
    knots[-1] = 1.0
    return [
        PlatformLine(start + f0 * (end - start), start + f1 * (end - start), f0, f1)
        for f0, f1 in pairwise(knots)
    ]


def platform_timing(
    bounds: list[Bounds],
    whats: list[str],
    lines: list[PlatformLine],
    platform: Platform,
    limits: tuple[np.ndarray, np.ndarray, np.ndarray],
    k: float,
    naming: JointNaming,
    jerks: np.ndarray | None = None,
) -> tuple[list[Bounds], list[str]]:
    """Each segment's bounds tightened by the platform's joints (module docstring):
    ``ṡ ≤ k·θ̇max_j / |Δθ_j|``, ``s̈ ≤ k²·θ̈max_j / |Δθ_j|`` (``limits``: the active
    position, speed and acceleration limits; ``k = R_OVERRIDE/100``) and, for an S-curve,
    ``s⃛ ≤ jerks_j / |Δθ_j|`` (``jerks``: the platform joints' jerk bounds, SI, already
    scaled by ``k³``; ``None``: the trapezoid); where a platform joint sets the segment's
    time its ``what`` says so."""
    _, speed, accel = limits
    rows = list(platform.joints)
    v_max = np.minimum(-speed[rows, 0], speed[rows, 1]) * k
    a_max = np.minimum(-accel[rows, 0], accel[rows, 1]) * k * k
    out_b, out_w = [], []
    for b, what, line in zip(bounds, whats, lines, strict=True):
        travel = np.abs(platform.joints_for(line.end) - platform.joints_for(line.start))
        if jerks is None:
            v, a, j = common_bounds(travel, v_max, a_max)
            jerk, t_own = None, minimum_time(v, a)
        else:
            v, a, jerk, j = sc.common_bounds(travel, v_max, a_max, jerks)
            t_own = sc.minimum_time(v, a, jerk)
        if j < 0:  # the platform does not move on this segment
            out_b.append(b)
            out_w.append(what)
            continue
        speed_s, accel_s = min(b.speed, v), min(b.accel, a)
        if jerk is None:
            t_min = minimum_time(speed_s, accel_s)
        else:
            jerk = min(jerk, b.jerk) if b.jerk is not None else jerk
            t_min = sc.minimum_time(speed_s, accel_s, jerk)
        platform_sets_it = b.slowest < 0 or t_own >= b.t_min
        slowest = b.slowest if b.slowest >= 0 else 0
        out_b.append(Bounds(speed_s, accel_s, jerk, slowest, t_min))
        out_w.append(
            f"platform joint {naming.label(rows[j])} speed/acceleration"
            + ("/jerk" if jerks is not None else "")
            if platform_sets_it
            else what
        )
    return out_b, out_w
