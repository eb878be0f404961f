"""``COOPERATE worker IN holder``: two robots of a cell as one chain (seed 001, ch. 3.2).

A :class:`Cooperation` is a unit of the cell (:mod:`irlc.runtime.control.cell`) that moves
two robots: its own :class:`~irlc.runtime.control.executor.SimulatedController` over the
serial model of the :class:`~irlc.runtime.model.cooperating.CooperatingChain` — the
holder's joints reversed, then the worker's (12 joints for two 6-axis arms) — whose task
pose is the worker's tool in the holder's tool frame (the workpiece). A motion of the
worker inside the block is planned and solved there: its poses are in the workpiece frame,
one Newton–Raphson / compact-QP problem over both robots' joints per IPO cycle, the
holder's motion being the redundancy; ``WITH VERTICAL`` adds the seed's welding condition
(:class:`~irlc.runtime.ik.tasks.axis.AxisTask`: the worker's tool z axis vertical in the
cell, two orientation rows).

Both robots' redundancy options enter the one problem (:func:`chain_options`): their
JOINTLIMIT / JOINTSPEEDLIMIT / JOINTACCELLIMIT sets become the chain's (a robot without
one: its own limits), FREEZE its joints' columns, CYCLIC the chain's reference (a robot
without CYCLIC on is referenced to where it stood when the statement started), OBSTACLE the
union of both robots' avoided obstacles (the chain's links avoid them all).

Each cycle of the pair becomes a sample of each robot (:meth:`Cooperation.emit`): its
joints (the chain's ``θ`` split), its TCP in the cell from its own forward kinematics, the
worker's path error (the chain's task error) and desired pose in the cell, the limit codes
of its columns, its obstacle clearances.

A motion of the holder inside the block moves the workpiece and the worker follows,
keeping its tool where it is on the workpiece (master–slave): the holder's motion is its
own, the worker's target every cycle is :class:`FollowPath` — the holder's tool now times
the worker's pose in it when the motion started — solved by the worker's own inverse
transformation, in lock-step (:mod:`irlc.runtime.control.group`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np
from irlc.runtime import units
from irlc.runtime.commands import ModalOptions, MotionCommand
from irlc.runtime.control.budget import RunBudget
from irlc.runtime.control.executor import ExecutionOptions, SimulatedController
from irlc.runtime.ik.tasks.axis import AxisTask
from irlc.runtime.model.chain import Chain
from irlc.runtime.model.cooperating import CellRobot, CooperatingChain, cooperating_model
from irlc.runtime.model.distance import critical_points
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.model.naming import JointNaming
from irlc.runtime.values import JointTuple


class Cooperation:
    """The pair ``worker`` IN ``holder`` (each the cell's robot unit: ``index``, ``name``,
    ``model`` placed in the cell, ``controller``) with the holder's full tool
    ``holder_tool`` (the robot file's · ``R_TOOL``) — a unit of the cell (module doc)."""

    def __init__(
        self,
        worker,
        holder,
        vertical: bool,
        holder_tool: np.ndarray,
        *,
        obstacles: dict,
        options: ExecutionOptions,
        budget: RunBudget,
        progress: Callable[[float, int], None] | None = None,
    ):
        self.worker, self.holder, self.vertical = worker, holder, vertical
        self.robots = (worker.index, holder.index)
        self.own_channels: tuple[int, ...] = ()  # its robots' samples come from emit()
        self.holder_tool = np.array(holder_tool, dtype=float)
        h = CellRobot(holder.name, holder.model, tool=self.holder_tool)
        self.layout = CooperatingChain(h, CellRobot(worker.name, worker.model))
        self.model = cooperating_model(h, CellRobot(worker.name, worker.model))

        def chain_of(tool: np.ndarray) -> Chain:
            chain = CooperatingChain(h, CellRobot(worker.name, worker.model, tool=tool))
            return chain.with_tasks((AxisTask.vertical(chain),)) if vertical else chain

        naming = JointNaming(
            self.join_names(holder.controller.naming.program, worker.controller.naming.program),
            self.join_names(holder.controller.naming.robot, worker.controller.naming.robot),
        )
        theta = self.layout.join(holder.controller.state.q, worker.controller.state.q)
        self.controller = SimulatedController(
            self.model,
            theta,
            obstacles=obstacles,
            options=options,
            progress=progress,
            naming=naming,
            chain_of=chain_of,
            budget=budget,
        )
        self.base = 0  # the cell sample index of the pair's sample 0 (begin())
        self.controller.collisions.link_label = self.layout.bodies.link_label  # welder link 2
        self._holder_kin = Kinematics(holder.model, self.holder_tool)

    def join_names(self, holder: tuple[str, ...], worker: tuple[str, ...]) -> tuple[str, ...]:
        """The chain's joint names: ``holder_a6 … holder_a1, welder_a1 …``."""
        return tuple(f"{self.holder.name}_{n}" for n in reversed(holder)) + tuple(
            f"{self.worker.name}_{n}" for n in worker
        )

    @property
    def name(self) -> str:
        return f"{self.worker.name} in {self.holder.name}"

    # ------------------------------------------------------------------ unit interface
    def last_sample(self) -> int:
        """The cell sample index of the pair's last sample."""
        return len(self.controller.recorder) - 1 + self.base

    def begin(self, cell_samples: int, t: float) -> None:
        """Before a statement of the pair: its chain's state from the two robots' (they
        may have moved on their own since), its next sample is the cell's ``cell_samples``."""
        st = self.controller.state
        hq, wq = self.holder.controller.state, self.worker.controller.state
        theta = self.layout.join(hq.q, wq.q)
        if not np.array_equal(theta, st.q):
            st.last_reference = None  # moved outside the pair: no reference to blend from
            st.pending = None
        st.q, st.q_prev = theta, self.layout.join(hq.q_prev, wq.q_prev)
        st.t, st.line = t, max(hq.line, wq.line)
        self.base = cell_samples - len(self.controller.recorder)

    def emit(self, k: int) -> None:
        """The pair's sample ``k`` (cell index) as a sample of each robot (module doc)."""
        rec, j = self.controller.recorder, k - self.base
        row = {name: rec.rows(name, j, j + 1)[0] for name in _ROWS}
        q_h, q_w = self.layout.split(row["q"])
        codes = row["active"]
        cols = [m.columns for m in self.layout.members]
        t, line, dt = float(row["times"]), int(row["lines"]), float(row["dt"])
        tcp_h = self._holder_kin.tcp(q_h)
        kin_w = self.controller.chain.bodies.robots()[1][1]  # the worker's, with its tool
        tcp_w = kin_w.tcp(q_w)
        desired = tcp_h @ row["desired"] if row["on_path"] else None
        common = {
            "iterations": int(row["iterations"]),
            "relaxed": bool(row["relaxed"]),
            "manipulability": float(row["manipulability"]),
            "dt": dt,
        }
        for robot, q, tcp, kin, c, errors, want in (
            (self.holder, q_h, tcp_h, self._holder_kin, cols[0], (0.0, 0.0), None),
            (
                self.worker,
                q_w,
                tcp_w,
                kin_w,
                cols[1],
                (float(row["pos_error"]), float(row["ori_error"])),
                desired,
            ),
        ):
            channel = robot.controller.recorder
            channel.tol_position = rec.tol_position
            clear = _clearances(kin, q, channel.obstacle_names, self.controller.obstacles)
            channel.add(
                t,
                line,
                q,
                tcp,
                want,
                errors=errors,
                active_codes=codes[c].copy(),
                clearances=clear,
                **common,
            )
            if common["iterations"]:
                channel.ik_cycles += 1
            st = robot.controller.state
            st.q_prev, st.q, st.t, st.line = st.q, q.copy(), t, line

    # ------------------------------------------------------------------ commands
    def options(self, holder: ModalOptions, worker: ModalOptions) -> ModalOptions:
        """:func:`chain_options` of the two robots' options now."""
        return chain_options(self, holder, worker)

    def command(self, cmd: MotionCommand) -> MotionCommand:
        """The worker's command for the chain: its WITH limits and configurations joined
        with the holder's limits and joints now."""
        h = self.holder
        limits = {}
        for field, which in (("joint_limits", 0), ("speed_limits", 1), ("accel_limits", 2)):
            given = getattr(cmd, field)
            if given is not None:
                own = robot_limits(h.model, which)
                limits[field] = tuple(self.joined(own[i], given[i]) for i in range(2))
        reconf = None
        if cmd.reconfiguration is not None:
            now = self.holder.controller.joints()
            reconf = tuple(
                self.joined(JointTuple("MAIN_JOINT", now), k) for k in cmd.reconfiguration
            )
        return dataclasses.replace(cmd, reconfiguration=reconf, **limits)

    def joined(self, holder: JointTuple, worker: JointTuple) -> JointTuple:
        """A joint tuple of the chain from the two robots' (the holder's reversed)."""
        return JointTuple(worker.type, tuple(reversed(holder.values)) + tuple(worker.values))


_ROWS = (
    "times",
    "lines",
    "q",
    "pos_error",
    "ori_error",
    "iterations",
    "relaxed",
    "manipulability",
    "dt",
    "active",
    "desired",
    "on_path",
)


def robot_limits(model, which: int) -> tuple[JointTuple, JointTuple]:
    """A robot's own position (0), speed (1) or acceleration (2) limits as the program's
    JOINTLIMIT-style tuples (deg | mm per s^which)."""
    array = (model.position_limits, model.speed_limits, model.accel_limits)[which]
    scale = units.joint_scale(model.joint_kinds)
    kinds = ("MAIN_JOINT", "MAIN_JOINT_SPEED", "MAIN_JOINT_ACCEL")[which]
    lo = tuple(float(v) for v in array[:, 0] / scale)
    hi = tuple(float(v) for v in array[:, 1] / scale)
    return JointTuple(f"{kinds}_MIN", lo), JointTuple(f"{kinds}_MAX", hi)


def chain_options(pair: Cooperation, holder: ModalOptions, worker: ModalOptions) -> ModalOptions:
    """The two robots' redundancy options as the chain's (module doc)."""
    h, w = pair.holder, pair.worker
    out = ModalOptions()
    for field, which in (("joint_limits", 0), ("speed_limits", 1), ("accel_limits", 2)):
        mine, theirs = getattr(holder, field), getattr(worker, field)
        if mine is None and theirs is None:
            continue
        mine = mine or robot_limits(h.model, which)
        theirs = theirs or robot_limits(w.model, which)
        setattr(out, field, tuple(pair.joined(mine[i], theirs[i]) for i in range(2)))
    if holder.cyclic_reference is not None or worker.cyclic_reference is not None:
        ref_h = holder.cyclic_reference or h.controller.joints()
        ref_w = worker.cyclic_reference or w.controller.joints()
        out.cyclic_reference = tuple(reversed(ref_h)) + tuple(ref_w)
    out.obstacles = tuple(dict.fromkeys((*holder.obstacles, *worker.obstacles)))
    n_h = h.model.n
    frozen = {n_h - 1 - j: v for j, v in holder.frozen.items()}
    frozen.update({n_h + j: v for j, v in worker.frozen.items()})
    out.frozen = frozen
    return out


class FollowPath:
    """The worker's tool fixed in the holder's moving tool frame (master–slave, module
    doc): ``at(s)`` is the holder's TCP now (``kin`` at its controller's joints) times
    ``grip``, the worker's TCP in the holder's tool frame when the motion started."""

    def __init__(self, kin: Kinematics, state, grip: np.ndarray):
        self.kin, self.state, self.grip = kin, state, grip

    def at(self, s: float) -> np.ndarray:
        return self.kin.tcp(self.state.q) @ self.grip


def _clearances(kin: Kinematics, q: np.ndarray, names: tuple[str, ...], obstacles: dict):
    """Obstacle name → (distance m, link) of one robot's own links at ``q``."""
    if not names:
        return None
    cps = critical_points(kin, kin.link_frames(q), tuple(obstacles[n] for n in names))
    return {cp.name: (cp.distance, cp.link) for cp in cps}
