"""The controller's platform part: ``R_PLATFORM``, the platform task's solver, its
pre-check, its failures and its record (docs/runtime.md, Platform).

* **R_PLATFORM** (``lang/settings.py``): ``'FREE'`` (the start value) leaves the platform
  to the redundancy, as before; ``'HOLD'`` keeps it still — a FREEZE of its joints at their
  values, added to the motion's options (:meth:`PlatformControl.options`), named for what
  it means. ``WITH PLATFORM`` wins over HOLD for its own motion.
* **WITH PLATFORM := q** (:mod:`~irlc.runtime.plan.platform_path`): the segments carry the
  platform's line; their IK cycles run on the chain with the platform task
  (:func:`platform_chain`: ``SerialChain`` + ``PlatformTask(link, coords, point)``), whose
  target the cycle runner sets every cycle from the segment's ``s``. A platform motion is
  not blended: it starts and ends with an exact stop (the blender's superposition of two
  segments has no platform line).
* **The pre-check** (:meth:`PlatformControl.check_targets`): every segment end (and a
  circle's via) must be reachable with the platform where its line puts it there; if not,
  the failure (:func:`platform_failure`) says whether the TCP target is out of reach
  altogether (cause ``unreachable``) or only with the platform on its line (cause
  ``platform``: the TCP alone could reach it with the platform elsewhere — how far off its
  line is in the message).
* **A cycle that fails** (:func:`platform_failure`, from the cycle runner): the deviation
  of the TCP task and of the platform task, and which one could not be met — by the same
  pose searches (or, where both are reachable there, the binding bound's cause).
* **The record** (:class:`PlatformRecord`): per platform motion its line, start, target and
  the largest deviation of the platform from its line — the report's ``platform``.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from irlc.lang.platform import WORD as PLATFORM_WORD
from irlc.robots.model import RobotModel
from irlc.robots.platform import Platform
from irlc.runtime import units
from irlc.runtime.commands import ModalOptions, MotionCommand
from irlc.runtime.errors import RunFailure
from irlc.runtime.ik import cause
from irlc.runtime.ik.reach import Reach
from irlc.runtime.ik.tasks.platform import PlatformTask
from irlc.runtime.model.chain import Chain
from irlc.runtime.model.naming import JointNaming
from irlc.runtime.plan.interpolator import Segment
from irlc.runtime.plan.motion_values import MotionValues

PLATFORM_CAUSE = "platform"
"""The failure cause when the platform task (its line) cannot be met with the TCP's."""


def platform_chain(chain: Chain, platform: Platform) -> tuple[Chain, PlatformTask]:
    """``chain`` with the platform task's rows (the same parts, one more task) and the task,
    whose ``target`` the cycle runner sets."""
    task = PlatformTask(platform.link, platform.rows, platform.point, name="platform")
    return chain.with_tasks((*chain.tasks, task)), task


@dataclass
class PlatformMotion:
    """One motion WITH PLATFORM in the report (mm): its line, kind, start and target, and
    the largest distance of the platform from its line over its cycles."""

    line: int
    kind: str
    start_mm: list[float]
    target_mm: list[float]
    max_error_mm: float = 0.0

    def entry(self) -> dict:
        return dataclasses.asdict(self)


@dataclass
class PlatformRecord:
    """The platform motions of a run, in order (the report's ``platform.motions``)."""

    motions: list[PlatformMotion] = field(default_factory=list)

    def begin(self, cmd: MotionCommand, platform: Platform, q: np.ndarray) -> None:
        start = platform.coordinates_at(q) / units.MM
        target = list(cmd.platform_target or ())
        self.motions.append(PlatformMotion(cmd.line, cmd.kind, [float(v) for v in start], target))

    def error(self, distance: float) -> None:
        """A cycle's platform deviation (m) of the current platform motion."""
        if self.motions:
            last = self.motions[-1]
            last.max_error_mm = max(last.max_error_mm, float(distance) / units.MM)


class PlatformControl:
    """The platform part of the simulated controller (module docstring)."""

    def __init__(self, model: RobotModel):
        self.model = model
        self.platform: Platform | None = model.platform
        self.record = PlatformRecord()

    def options(
        self,
        cmd: MotionCommand | None,
        motion: MotionValues,
        options: ModalOptions,
        joints: Callable[[], np.ndarray],
        pending_options: ModalOptions | None,
        flush: Callable[[str], None],
    ) -> ModalOptions:
        """The motion's options under ``R_PLATFORM``: with ``'HOLD'`` (and no WITH
        PLATFORM) the platform's joints frozen where they are (``joints()``: SI, read after
        any flush; frozen values are program units, mm: the joints are prismatic). A
        pending approximated segment that did not hold them ends first with an exact stop
        (``flush``), so that "where they are" is where it ends; one that held them left
        them where they are. A motion WITH PLATFORM starts with an exact stop."""
        platform = self.platform
        moving = cmd is not None and cmd.platform_target is not None
        if cmd is not None and moving:
            flush(f"the motion on line {cmd.line} moves the platform ({PLATFORM_WORD}): exact stop")
        if platform is None or motion.platform != "HOLD" or moving:
            return options
        if pending_options is not None and not self.held(pending_options):
            flush("R_PLATFORM := 'HOLD': the platform stops (exact stop)")
        q = joints()
        held = {j: float(q[j]) / units.MM for j in platform.joints}
        return dataclasses.replace(options, frozen={**options.frozen, **held})

    def held(self, options: ModalOptions) -> bool:
        """Whether ``options`` freeze every platform joint (R_PLATFORM = 'HOLD' or FREEZE)."""
        return self.platform is not None and all(j in options.frozen for j in self.platform.joints)

    def explained(self, exc: RunFailure, held: bool, naming: JointNaming) -> RunFailure:
        """``exc`` with a note when R_PLATFORM = 'HOLD' held the platform's joints in the
        failing motion (``held``) and the failure blames the frozen joints (its words say
        FREEZE)."""
        platform = self.platform
        blamed = exc.cause in ("freeze", "freeze_jointlimit")
        if platform is not None and held and blamed and "R_PLATFORM" not in exc.message:
            exc.message += (
                f" (the platform's joints {naming.labels(platform.joints)} are held by "
                "R_PLATFORM := 'HOLD'; 'FREE' lets the redundancy move them)"
            )
            exc.args = (exc.message,)
        return exc

    def check_targets(
        self, reach: Reach, segments: list[Segment], seed: np.ndarray, line: int, t: float,
        what: str,
    ) -> None:  # fmt: skip
        """The pre-check of a platform motion (module docstring): each segment end (and a
        circle's via point) with the platform held where its line is there."""
        platform = self.platform
        assert platform is not None
        q = np.asarray(seed, dtype=float)
        for seg in segments:
            pl = seg.platform
            assert pl is not None
            via = getattr(seg.path, "via_fraction", None)
            for s in ([float(via)] if via is not None else []) + [1.0]:
                held = held_reach(platform, reach, pl.at(s))
                q_seed = q.copy()
                q_seed[list(platform.joints)] = [held.frozen[j] for j in platform.joints]
                target = seg.path.at(s)
                sol = held.search(target, q_seed)
                if not held.reached(sol):
                    where = (what, line, t)
                    raise platform_failure(platform, reach, target, pl.at(s), q, where)
                q = sol.q


def held_reach(platform: Platform, reach: Reach, coords: np.ndarray) -> Reach:
    """``reach`` with the platform's joints held where they put it at ``coords`` (m)."""
    at = platform.joints_for(coords)
    frozen = {**reach.frozen, **{j: float(at[j]) for j in platform.joints}}
    return dataclasses.replace(reach, frozen=frozen)


def platform_failure(
    platform: Platform, reach: Reach, target: np.ndarray, coords: np.ndarray,
    seed: np.ndarray, where: tuple[str, int, float], deviation: dict | None = None,
    binding: str = "",
) -> RunFailure:  # fmt: skip
    """Which task cannot be met at the TCP pose ``target`` with the platform on its line
    at ``coords`` (m), and by how much (module docstring). ``where``: the statement's
    words, line and time; ``deviation``: a failing cycle's deviations (m: ``tcp``,
    ``platform``), ``None`` in the pre-check; ``binding``: the cycle's binding bound.

    * the TCP target out of reach even with the platform free: the TCP task (cause
      ``unreachable``, the closest pose's distance);
    * out of reach only with the platform on its line: the platform task (cause
      ``platform``): the TCP alone reaches it with the platform ``platform_off_line_mm``
      off its line;
    * reachable with the platform on its line (a failing cycle): the joints cannot follow
      in time — the cause of the binding bound (speed, acceleration, position)."""
    what, line, t = where
    shown = platform.describe(coords / units.MM)
    held = held_reach(platform, reach, coords)
    q_seed = np.array(seed, dtype=float)
    q_seed[list(platform.joints)] = [held.frozen[j] for j in platform.joints]
    sol = held.search(target, q_seed)
    details: dict = {"platform_mm": [float(v) for v in coords / units.MM]}
    head = what
    if deviation is not None:
        tcp_mm, off_mm = deviation["tcp"] / units.MM, deviation["platform"] / units.MM
        tcp_deg = deviation.get("tcp_angle", 0.0) / units.DEG
        details.update({"tcp_deviation_mm": tcp_mm, "platform_deviation_mm": off_mm})
        head += (
            f": TCP deviation {tcp_mm:.4g} mm, {tcp_deg:.4g} deg; platform {off_mm:.4g} mm off "
            f"its line (tolerance {reach.tol_position / units.MM:g} mm)"
        )
    if held.reached(sol):  # a failing cycle whose pose is reachable: the rates
        bound = f"; bound by {binding}" if binding else ""
        return RunFailure(
            f"{head}: the TCP target is reachable with the platform at {shown} on its line, "
            f"but the joints cannot follow in time{bound} (a lower speed may help)",
            line, t, binding or None, cause=cause.of_bound(binding), details=details,
        )  # fmt: skip
    distance = sol.position_error / units.MM
    details.update({"distance_mm": distance, "distance_deg": sol.orientation_error / units.DEG})
    free = reach.search(target, seed)
    if not reach.reached(free):
        return RunFailure(
            f"{head}: the TCP task cannot be met: the target is out of reach even with the "
            f"platform free (the closest pose found is {free.position_error / units.MM:.4g}"
            f" mm away; {distance:.4g} mm with the platform at {shown} on its line)",
            line, t, cause="unreachable", details=details,
        )  # fmt: skip
    needed = platform.coordinates_at(free.q)
    off = float(np.linalg.norm(needed - coords)) / units.MM
    details["platform_off_line_mm"] = off
    return RunFailure(
        f"{head}: the platform task cannot be met: with the platform at {shown} on its line "
        f"the TCP target is out of reach (the closest pose found is {distance:.4g} mm and "
        f"{sol.orientation_error / units.DEG:.4g} deg away); the TCP alone reaches it with "
        f"the platform at {platform.describe(needed / units.MM)}, {off:.4g} mm off its line",
        line, t, f"{PLATFORM_WORD} {shown}", cause=PLATFORM_CAUSE, details=details,
    )  # fmt: skip
