"""The collision rule: the arm never passes through a known cell obstacle.

Every obstacle of the code (the data lists' cell objects) is measured every IPO cycle —
its clearance ``d``, the signed distance of the nearest robot part (``d < 0``:
penetration, ``−d`` deep; :mod:`irlc.runtime.model.distance`). The rule:

* a sample with ``d < 0`` for any obstacle is a **collision**, a run failure (exit 2)
  naming the obstacle, the link, the depth, the time and the program line
  (cause ``obstacle``), whether or not ``OBSTACLE`` (avoidance) is on for it — ``OBSTACLE``
  makes the inverse transformation keep away from it; this rule judges the motion;
* it holds for the set points (every IK and PTP cycle: :meth:`CollisionRule.check`, the
  controller's per-cycle hook), for the start configuration (:meth:`start_failure`: a
  program that starts inside an obstacle fails at its first statement, t = 0) and, with
  drives, for the actual motion (:func:`first_collision` on the measured clearances,
  :mod:`irlc.runtime.outputs.verdict`);
* ``allow`` (``--allow-collisions``, ``run.allow_collisions`` of a study, the
  ``allow_collisions`` option of ``run_file`` and of a golden test) opts out: nothing
  fails, and the report's ``collisions`` lists each obstacle's deepest penetration
  (:func:`penetrations`), which the summary and the warnings repeat;
* an obstacle the robot is already inside when a REPL entry starts (after a collision
  that failed the previous entry) is *tolerated* for that entry as long as the arm does
  not go deeper (:meth:`tolerate`): it may back out, as one jogs a robot out of a
  collision stop.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from irlc.runtime import units
from irlc.runtime.errors import RunFailure

# m: deeper than the tolerated depth by more than this is going deeper (round-off of the
# distance queries is ≈ 1e-15 m)
DEEPER = 1e-9


@dataclass(frozen=True)
class Collision:
    """A penetration of one obstacle: ``depth`` m (> 0) of link ``link`` at ``time``."""

    obstacle: str
    link: int
    depth: float  # m
    time: float  # s
    line: int

    def as_dict(self) -> dict:
        """The report's form (mm, s)."""
        return {
            "obstacle": self.obstacle,
            "link": self.link,
            "depth_mm": self.depth / units.MM,
            "time_s": self.time,
            "line": self.line,
        }

    def text(self) -> str:
        """``slup 119.9 mm deep (link 6) at t = 2.310 s, line 13``."""
        return (
            f"{self.obstacle} {self.depth / units.MM:.4g} mm deep (link {self.link}) "
            f"at t = {self.time:.3f} s, line {self.line}"
        )


def failure(hit: Collision, avoided: bool = False, actual: bool = False, label=None) -> RunFailure:
    """The run failure of a collision (the one message): what collides, how deep, and
    what would help. ``avoided``: OBSTACLE was on for it; ``actual``: the drives' actual
    motion (the set points were clear); ``label(link)``: how the link is named (a chain of
    two robots: ``welder link 2``; default ``link 2``)."""
    who = "the actual motion (simulated drives)" if actual else "the arm"
    link = label(hit.link) if label is not None else f"link {hit.link}"
    what = (
        f"{who} collides with obstacle {hit.obstacle}: {link} is "
        f"{hit.depth / units.MM:.4g} mm inside it at t = {hit.time:.3f} s"
    )
    if actual:
        help_ = "slow down (the drives lag the set points), keep further from it"
    elif avoided:
        help_ = "OBSTACLE is on but cannot keep the arm out: change the path or the limits"
    else:
        help_ = f"switch OBSTACLE {hit.obstacle} on to avoid it, or change the path"
    message = f"{what}; {help_}, or allow collisions (--allow-collisions)"
    details = {"obstacle": hit.obstacle, "link": hit.link, "depth_mm": hit.depth / units.MM}
    return RunFailure(message, hit.line, hit.time, f"obstacle {hit.obstacle}", "obstacle", details)


class CollisionRule:
    """The controller's part that applies the rule to each recorded cycle (module doc)."""

    def __init__(self, allow: bool = False):
        self.allow = allow
        self._tolerated: dict[str, float] = {}  # obstacle → depth (m) the arm may keep
        self.link_label = None  # how a link is named (a chain of two robots' links)

    def check(
        self,
        clearances: Mapping[str, tuple[float, int]] | None,
        avoided: frozenset[str] | set[str],
        line: int,
        t: float,
    ) -> None:
        """A :class:`RunFailure` for the first obstacle (by name) the cycle's clearances
        ``name → (distance m, link)`` penetrate, unless collisions are allowed or the
        obstacle is tolerated and the arm not deeper in it."""
        if not clearances or self.allow:
            return
        for name in sorted(clearances):
            distance, link = clearances[name]
            if distance >= 0.0:
                self._tolerated.pop(name, None)  # out of it: from now on, the rule
                continue
            held = self._tolerated.get(name)
            if held is not None and -distance <= held + DEEPER:
                self._tolerated[name] = min(held, -distance)  # backing out: never deeper again
                continue
            hit = Collision(name, int(link), -float(distance), float(t), int(line))
            raise failure(hit, avoided=name in avoided, label=self.link_label)

    def tolerate(self, clearances: Mapping[str, tuple[float, int]]) -> None:
        """The obstacles the robot is inside now may be left, not entered deeper (a REPL
        entry after a collision); replaces what was tolerated before."""
        self._tolerated = {
            name: -float(distance) for name, (distance, _) in clearances.items() if distance < 0.0
        }

    def start_failure(
        self, clearances: Mapping[str, tuple[float, int]], line: int, start: str
    ) -> RunFailure | None:
        """The failure of a start configuration inside an obstacle (``None``: clear, or
        collisions allowed): at ``line`` (the program's first statement), t = 0. ``start``
        says where the configuration came from (``the robot's home``, ``--seed-config``)."""
        if self.allow:
            return None
        inside = sorted((d, name, link) for name, (d, link) in clearances.items() if d < 0.0)
        if not inside:
            return None
        distance, name, link = inside[0]
        depth = -float(distance)
        message = (
            f"the robot starts inside obstacle {name}: link {link} is {depth / units.MM:.4g} mm "
            f"inside it in the start configuration ({start}); start elsewhere (--seed-config) "
            "or move the obstacle, or allow collisions (--allow-collisions)"
        )
        details = {"obstacle": name, "link": int(link), "depth_mm": depth / units.MM}
        return RunFailure(message, line, 0.0, f"obstacle {name}", "obstacle", details)


def first_collision(
    times: np.ndarray,
    lines: np.ndarray,
    clearance: Mapping[str, np.ndarray],
    links: Mapping[str, np.ndarray] | None,
) -> Collision | None:
    """The first sample (in time; at one time the deepest) that penetrates an obstacle,
    of clearance arrays ``name → (k,)`` m (with the nearest link per sample)."""
    first: tuple | None = None
    for name in sorted(clearance):
        d = clearance[name]
        hit = np.flatnonzero(d < 0.0)
        if not hit.size:
            continue
        k = int(hit[0])
        key = (k, float(d[k]), name)
        if first is None or key < first:
            first = key
    if first is None:
        return None
    k, distance, name = first
    link = int(links[name][k]) if links is not None and name in links else 0
    return Collision(name, link, -distance, float(times[k]), int(lines[k]))


def penetrations(
    times: np.ndarray,
    lines: np.ndarray,
    clearance: Mapping[str, np.ndarray],
    links: Mapping[str, np.ndarray] | None,
) -> list[Collision]:
    """Per obstacle (by name) its deepest penetration over the samples (the first sample
    at that depth), for the report of a run that allows collisions."""
    out = []
    for name in sorted(clearance):
        d = clearance[name]
        if not d.size or not d.min() < 0.0:
            continue
        k = int(np.argmin(d))
        link = int(links[name][k]) if links is not None and name in links else 0
        out.append(Collision(name, link, -float(d[k]), float(times[k]), int(lines[k])))
    return out
