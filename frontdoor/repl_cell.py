"""The REPL's cell: several robots kept between entries (``irlc repl``, docs/interfaces.md).

A session becomes a cell when it has two robots (``ROBOT`` entries, repeated ``--robot
NAME=ROBOT[@x,y,z,a,b,c]``). Its robots run on one
:class:`~irlc.runtime.control.cell.CellController` — the controller ``irlc run`` gives a
cell (:func:`irlc.runtime.cell_run.cell_members` places them and names their joints) — kept
alive between entries as the single robot's controller is, with the interpreter's
incremental :class:`~irlc.runtime.interpreter.MachineState` (each robot's ``R_TOOL``,
``R_BASE`` and modal options in ``state.robots``). The cell's controller is built again
only when its robots or the obstacles change: the robots keep their joints (a new robot
starts at its home) and the recorded trace restarts there.

:class:`CellMachine` owns that controller: each robot's view for ``:where`` and the other
meta-commands (:mod:`irlc.repl_views`), the session's run as ``irlc run`` reports a cell
(:func:`~irlc.runtime.outputs.cell_results.assemble_cell`, for ``:trace`` and ``:plot``).
:func:`robot_clause` turns a ``--robot`` value into the ``ROBOT`` clause the session's
program starts with.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np
from irlc.errors import UsageError
from irlc.repl_views import RobotView, cell_lines
from irlc.runtime import values

_PLACED = re.compile(r"^(?P<name>[A-Za-z_]\w*)=(?P<robot>.+?)(?:@(?P<at>[^@]*))?$")


def robot_spec(spec: str) -> tuple[str | None, str, str | None]:
    """A ``--robot`` value: ``ROBOT`` or ``NAME=ROBOT[@x,y,z,a,b,c]`` as ``(name, robot,
    placement)`` (``None`` where it has none; the placement as given)."""
    m = _PLACED.match(spec)
    if m is None:
        return None, spec, None
    return m.group("name"), m.group("robot"), m.group("at")


def check_distinct_names(specs: Sequence[str]) -> None:
    """UsageError if two ``--robot`` values give one name (the unnamed robot is ``r``):
    before, the compiler's "'a' is already defined (line 2)" spoke of a program the user
    never wrote."""
    seen: dict[str, str] = {}
    for spec in specs:
        name = robot_spec(spec)[0] or "r"
        if name.lower() in seen:
            raise UsageError(
                f"--robot {spec}: the name {name} is already given by --robot "
                f"{seen[name.lower()]}; give each robot its own name (NAME=ROBOT)"
            )
        seen[name.lower()] = spec


def robot_clause(spec: str, default_name: str = "r") -> str:
    """The ``ROBOT`` clause of a ``--robot`` value (:func:`robot_spec`): ``ROBOT`` is the
    robot ``r``, as before cells; ``NAME=ROBOT@x,y,z,a,b,c`` places it (mm, deg ZYX: its
    ``AT``). A robot that is not a plain name (a file) is quoted."""
    name, robot, at = robot_spec(spec)
    placement = ""
    if at is not None:
        parts = [p.strip() for p in at.split(",")]
        try:
            numbers = [float(p) for p in parts]
        except ValueError:
            numbers = []
        if len(numbers) != 6 or not all(np.isfinite(numbers)):
            raise UsageError(
                f"--robot {spec}: the placement after @ is x,y,z,a,b,c (mm, deg ZYX): 6 numbers"
            )
        placement = " AT (" + ", ".join(parts) + ")"
    return f"ROBOT {name or default_name} := {_robot_text(robot)}{placement};"


def _robot_text(robot: str) -> str:
    if re.fullmatch(r"[A-Za-z_]\w*", robot):
        return robot
    return "'" + robot.replace("'", "''") + "'"


@functools.cache
def _cell_class() -> type:
    """The cell's controller, counting the motion it is asked for (a MOVE to where the
    robots already are takes no time, yet the session should say that it ran)."""
    from irlc.runtime.control.cell import CellController

    class ReplCellController(CellController):
        motions = 0

        def move_group(self, parts, settings, options) -> None:
            self.motions += 1
            super().move_group(parts, settings, options)

        def reconfigure(self, target, line, settings, options, robot) -> None:
            self.motions += 1
            super().reconfigure(target, line, settings, options, robot)

    return ReplCellController


class CellMachine:
    """The session's robots on one cell controller (module doc). ``joints``: the robots
    that keep their joints (by name; the others start at their home)."""

    def __init__(
        self,
        code,
        base_dir: Path,
        allow_any_path: bool,
        obstacles: dict,
        joints: dict[str, np.ndarray] | None = None,
    ):
        from irlc.runtime.cell_run import cell_members
        from irlc.runtime.run import SPILL_ROWS

        kept = {k.lower(): q for k, q in (joints or {}).items()}
        members = cell_members(code, base_dir, None, allow_any_path)
        self.members = [
            replace(m, q0=np.array(kept[m.name.lower()], dtype=float))
            if m.name.lower() in kept
            else m
            for m in members
        ]
        self.base_dir = base_dir
        self.allow_any_path = allow_any_path
        self.obstacles = obstacles
        self.records = list(code.robots)
        self.controller = _cell_class()(self.members, obstacles=obstacles)
        for unit in self.controller.robots:
            unit.controller.recorder.spill(SPILL_ROWS)  # a long session: older samples on disk

    # ------------------------------------------------------------------ the robots
    @property
    def names(self) -> list[str]:
        return [m.name for m in self.members]

    def index(self, name: str) -> int | None:
        """The robot called ``name`` (any case), ``None`` when the cell has none."""
        for k, n in enumerate(self.names):
            if n.lower() == name.lower():
                return k
        return None

    def lines(self, current: int) -> list[str]:
        """The cell's robots (:func:`~irlc.repl_views.cell_lines`), then a warning when
        their links are inside each other where they stand (a program would fail at its
        first statement; here the next motions may only move them apart)."""
        out = cell_lines(self.robots(), current)
        overlap = self.controller.start_failure(0)
        if overlap is not None:
            d = overlap.details  # the clearance failure's facts (ClearanceRule.failure)
            out.append(
                f"  warning: {d['robot_a']} link {d['link_a']} and {d['robot_b']} link "
                f"{d['link_b']} collide: they are {-d['distance_mm']:.4g} mm inside each other "
                "where they stand; move them apart first"
            )
        return out

    def robots(self) -> list[tuple[str, str, tuple[float, ...]]]:
        """Each robot's name, robot file and placement (mm, deg ZYX)."""
        identity = (0.0,) * 6
        return [(r.var, r.robot, tuple(r.at) if r.at else identity) for r in self.records]

    def joints(self) -> dict[str, np.ndarray]:
        """Every robot's joints now (SI), by name."""
        return {u.name: u.controller.state.q.copy() for u in self.controller.robots}

    @property
    def time(self) -> float:
        return self.controller.time

    def cooperating(self) -> tuple[tuple[int, int], ...]:
        """The open ``COOPERATE`` blocks as the compiler takes them: ``(worker, holder)``
        robot indices."""
        pairs = self.controller.cooperations.values()
        return tuple((p.worker.index, p.holder.index) for p in pairs)

    def cooperations(self) -> list[tuple[str, str]]:
        """The open ``COOPERATE`` blocks: ``(worker, holder)``."""
        pairs = self.controller.cooperations.values()
        return [(p.worker.name, p.holder.name) for p in pairs]

    def rebuilt(self, code, obstacles: dict, state) -> CellMachine:
        """The cell on a new controller with ``obstacles``: the robots keep their joints,
        the open cooperations are opened again."""
        pairs = [(p.worker.index, p.holder.index, p.vertical)
                 for p in self.controller.cooperations.values()]  # fmt: skip
        new = CellMachine(code, self.base_dir, self.allow_any_path, obstacles, self.joints())
        settings, options = _snapshot(state)
        for worker, holder, vertical in pairs:
            new.controller.cooperate(worker, holder, vertical, 0, settings, options)
        return new

    # ------------------------------------------------------------------ entries
    def prepare(self, code) -> None:
        """Before an entry runs: the whole cycle budget; obstacles a robot is inside (a
        collision failed the last entry) may be left, and so may robots inside each other; the
        entry's joint names."""
        from irlc.runtime.model.naming import JointNaming

        cell = self.controller
        cell.restart_cycle_budget()
        cell.tolerate_collisions()
        for unit, record in zip(cell.robots, code.robots, strict=True):
            ctl = unit.controller
            ctl.collisions.tolerate(ctl.recorder.last_clearances())
            ctl.naming = JointNaming.for_model(unit.model, record.joint_names)

    # ------------------------------------------------------------------ views
    def view(self, k: int, state) -> RobotView:
        """Robot ``k`` as the session shows it; its pose as ``NAME.R_ACT_POSE`` reads it."""
        settings, options = _snapshot(state)
        unit = self.controller.robots[k]
        pose = self.controller.pose(settings, options, k)
        pair = self.controller.cooperations.get(k)
        if pair is not None:
            frame = f"{pair.holder.name}'s tool frame"
        elif np.allclose(values.pose_to_matrix(settings[k].base), np.eye(4)):
            frame = "cell frame"
        else:
            frame = f"{unit.name}.R_BASE frame"
        return RobotView(unit.name, unit.model, unit.controller.state.q.copy(),
                         unit.controller.naming, options[k], settings[k], pose,
                         frame)  # fmt: skip

    # ------------------------------------------------------------------ results
    def run_result(self, code, state):
        """The session so far as ``irlc run`` reports a cell (for traces and plots)."""
        from irlc.runtime.control.executor import ExecutionOptions
        from irlc.runtime.interpreter import ExecutionResult
        from irlc.runtime.outputs.cell_results import CellRunData, RobotRun, assemble_cell

        s = self.controller
        execution = ExecutionResult("ok", list(state.output), list(state.events),
                                    list(state.warnings), None, state, 0)  # fmt: skip
        robots = [RobotRun.kinematic(unit) for unit in s.robots]
        data = CellRunData(code, s, execution, ExecutionOptions(), robots, "ideal", self.base_dir)
        run = assemble_cell(data)
        rows = [run.report["statements"], *(r["statements"] for r in run.report["robots"])]
        for row in (row for table in rows for row in table):
            row["statement"] = row["kind"]  # entries have no source file
        return run


def _snapshot(state) -> tuple[tuple, tuple]:
    """Every robot's settings (the cell's, with its own tool and base) and modal options,
    as the interpreter hands them to the cell's controller."""
    settings = tuple(replace(state.settings, tool=r.tool, base=r.base) for r in state.robots)
    return settings, tuple(r.options for r in state.robots)
