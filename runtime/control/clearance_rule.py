"""The clearance rule between links: robots do not pass through each other or themselves.

The watched pairs (:mod:`irlc.runtime.model.clearance`: every part of one robot against
every part of another, a robot's non-adjacent parts apart at home) are measured at every
recorded IPO cycle; their smallest distance is the *clearance*. The rule
(:meth:`ClearanceRule.judge`):

* a clearance below 0 is a **collision** between two links — a run failure (exit 2) naming
  both robots and links, the depth, the time and the line (cause ``clearance``), unless
  collisions are allowed (``--allow-collisions``, as for obstacles: reported, not judged);
* with ``R_CLEARANCE := d`` > 0 the inverse transformation keeps the pairs ``d`` apart
  (:mod:`irlc.runtime.ik.clearance`); a clearance below ``d`` anyway — the QP could not keep
  it, a PTP (which is not steered) or another robot came closer — is a run failure at the
  first such sample, with the same facts.

In a cell (:mod:`irlc.runtime.control.cell`) the rule judges every pair at every sample. In
a program of one robot its own links are judged only while ``R_CLEARANCE`` > 0
(:class:`OwnClearance`); otherwise the report states their smallest distance
(:mod:`irlc.runtime.outputs.self_clearance`) and the run's verdict is what it was before
cells — the library's robot files model links by generous capsules that overlap in the
monograph's own programs (koch11's links 8 and 10 by 19 mm on ``square.irl``).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from irlc.runtime import units
from irlc.runtime.control.collision import DEEPER
from irlc.runtime.errors import RunFailure
from irlc.runtime.model.chain import Chain
from irlc.runtime.model.clearance import Clearance, PartSet, RobotParts

KEEP_TOLERANCE = 1e-4  # m: a pair this much below what it keeps fails the run (0.1 mm)


@dataclass(frozen=True)
class Measured:
    """Every watched pair of one sample (:meth:`PartSet.distances` at the parts' world
    ends ``a, b``): distances ``d`` and closest points ``p``, ``q``."""

    parts: PartSet
    a: np.ndarray
    b: np.ndarray
    d: np.ndarray
    p: np.ndarray
    q: np.ndarray

    @classmethod
    def at(cls, parts: PartSet, a: np.ndarray, b: np.ndarray) -> Measured:
        d, _, _, p, q = parts.distances(a, b)
        return cls(parts, a, b, d, p, q)

    def pair(self, k: int) -> Clearance:
        return self.parts.clearance(k, float(self.d[k]), self.p[k], self.q[k], self.a, self.b)

    def closest(self) -> Clearance | None:
        """The closest pair (the first of equal ones); ``None`` without pairs."""
        return self.nearest

    @cached_property
    def nearest(self) -> Clearance | None:
        if not self.d.size:
            return None
        k = int(np.argmin(self.d))
        return self.parts.clearance(k, float(self.d[k]), self.p[k], self.q[k], self.a, self.b)


class CellClearances:
    """Per cell sample: the clearance (m) and its pair (robot and link of each part), the
    least distance per pair of robots (``PartSet.groups``) with its pair's index, and the
    R_CLEARANCE in effect (m)."""

    def __init__(self) -> None:
        self.distance: list[float] = []
        self.pair: list[tuple[int, int, int, int]] = []
        self.groups: list[tuple[np.ndarray, np.ndarray]] = []
        self.required: list[float] = []

    def __len__(self) -> int:
        return len(self.distance)

    def add(self, m: Measured, required: float) -> None:
        c = m.closest()
        if c is None:
            self.distance.append(float("inf"))
            self.pair.append((-1, -1, -1, -1))
        else:
            self.distance.append(c.distance)
            self.pair.append((c.robot_a, c.link_a, c.robot_b, c.link_b))
        self.groups.append(m.parts.group_minima(m.d))
        self.required.append(required)

    def truncate(self, k: int) -> None:
        del self.distance[k:], self.pair[k:], self.groups[k:], self.required[k:]


class ClearanceRule:
    """Judges the clearance of a sample (module doc). ``parts`` are the watched parts and
    pairs (their names in messages); ``allow``: collisions (penetrations) are allowed."""

    def __init__(self, parts: PartSet, allow: bool = False):
        self.parts = parts
        self.allow = allow
        # pair → (distance it may not come closer than, distance that releases it), m (REPL)
        self._tolerated: dict[int, tuple[float, float]] = {}

    def judge(
        self, m: Measured, required: float, line: int, t: float, actual: bool = False
    ) -> None:
        """A :class:`RunFailure` when a pair of the sample ``m`` penetrates (not allowed)
        or, with ``required`` (m, R_CLEARANCE) > 0, a pair is closer than it keeps
        (:meth:`PartSet.keep`) by more than :data:`KEEP_TOLERANCE`. A tolerated pair
        (:meth:`tolerate`) passes both as long as it comes no closer. ``actual``: ``m``
        is the drives' actual motion (:meth:`failure`)."""
        parts, d = self.parts, m.d
        if not d.size:
            return
        moving_apart = self._moving_apart(d) if self._tolerated else set()
        if not self.allow:
            inside = np.flatnonzero(d < 0.0)  # (every sample: nearly always none)
            for k in inside[np.argsort(d[inside], kind="stable")]:
                if int(k) not in moving_apart:
                    raise self.failure(m.pair(int(k)), 0.0, line, t, actual)
        if required > 0.0:
            slack = d - parts.keep(required)
            if moving_apart:
                slack[list(moving_apart)] = np.inf
            j = int(np.argmin(slack))
            if slack[j] < -KEEP_TOLERANCE:
                raise self.failure(m.pair(j), float(d[j] - slack[j]), line, t, actual)

    def tolerate(self, m: Measured, required: float) -> None:
        """The pairs of ``m`` inside each other, or closer than they keep under
        ``required`` (m, R_CLEARANCE), may move apart but not closer — a REPL entry after
        a collision or a clearance failed the last one, as one jogs robots out of a
        collision stop (:class:`~irlc.runtime.control.collision.CollisionRule` does the
        same for obstacles) — until they are out (at what they keep). Replaces what was
        tolerated before."""
        keep = self.parts.keep(required) if required > 0.0 else np.zeros_like(m.d)
        close = np.flatnonzero(m.d < keep - KEEP_TOLERANCE)
        if not self.allow:
            close = np.union1d(close, np.flatnonzero(m.d < 0.0))
        self._tolerated = {int(k): (float(m.d[k]), float(max(keep[k], 0.0))) for k in close}

    def _moving_apart(self, d: np.ndarray) -> set[int]:
        """The tolerated pairs no closer than before (each keeps the farthest distance it
        reached: never closer again); a pair that came out, or closer, is judged again."""
        out = set()
        for k, (held, release) in list(self._tolerated.items()):
            if d[k] >= release or d[k] < held - DEEPER:
                del self._tolerated[k]
                continue
            self._tolerated[k] = (max(held, float(d[k])), release)
            out.add(k)
        return out

    def failure(
        self, c: Clearance, required: float, line: int, t: float, actual: bool = False
    ) -> RunFailure:
        """The failure of pair ``c``, which keeps ``required`` (m, R_CLEARANCE; 0: a
        collision). ``actual``: the drives' actual motion (a drive run of a cell, whose set
        points were clear), said as :func:`~irlc.runtime.control.collision.failure` says it
        for an obstacle; ``details["actual"]`` is then true."""
        a, b = self.parts.label(c.robot_a, c.link_a), self.parts.label(c.robot_b, c.link_b)
        mm = c.distance / units.MM
        who = "the actual motion (simulated drives): " if actual else ""
        if required <= 0.0:
            what = f"{a} and {b} collide: they are {-mm:.4g} mm inside each other at t = {t:.3f} s"
            hint = "change the path, or keep them apart with R_CLEARANCE"
            if actual:
                hint = (
                    "slow down (the drives lag the set points), keep them further apart "
                    "(R_CLEARANCE), or allow collisions (--allow-collisions)"
                )
        else:
            what = (
                f"{a} and {b} are {mm:.4g} mm apart at t = {t:.3f} s, closer than R_CLEARANCE "
                f"{required / units.MM:g} mm"
            )
            hint = "the clearance cannot be kept here (a PTP is not steered by it): change the path"
            if actual:
                what += f" by more than {KEEP_TOLERANCE / units.MM:g} mm"
                hint = (
                    "the set points keep it, the lagging drives do not: slow down, or keep more "
                    "clearance (R_CLEARANCE)"
                )
        details = {
            "robot_a": self.parts.robots[c.robot_a].name,
            "link_a": c.link_a,
            "robot_b": self.parts.robots[c.robot_b].name,
            "link_b": c.link_b,
            "distance_mm": mm,
            "required_mm": required / units.MM,
        }
        if actual:
            details["actual"] = True
        return RunFailure(
            f"{who}{what}; {hint}", line, t, f"clearance {a} – {b}", "clearance", details
        )


class OwnClearance:
    """A program of one robot: its own links judged while ``R_CLEARANCE`` > 0 (module doc).
    A cycle observer (:class:`~irlc.runtime.control.cycles.CycleObserver`); ``chain`` is
    the chain of the statement's tool (the controller sets it)."""

    def __init__(self, allow: bool = False):
        self.allow = allow
        self.chain: Chain | None = None
        self._parts: dict[int, tuple[Chain, PartSet]] = {}

    def cycle(self, runner) -> None:
        if runner.clearance <= 0.0 or self.chain is None:
            return
        chain = self.chain
        hit = self._parts.get(id(chain))
        if hit is None or hit[0] is not chain:
            robots = chain.bodies.robots()
            hit = (chain, PartSet([RobotParts(name, kin) for name, kin, _ in robots]))
            self._parts[id(chain)] = hit
        parts = hit[1]
        world = chain.world_frames(runner.state.q)
        frames = [world[o : o + kin.n + 1] for _, kin, o in chain.bodies.robots()]
        st = runner.state
        rule = ClearanceRule(parts, self.allow)
        rule.judge(Measured.at(parts, *parts.world(frames)), runner.clearance, st.line, st.t)
