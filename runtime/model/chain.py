"""The chain: what the inverse transformation and the controller work on.

The monograph (seed 001, ch. 3.2, fig. 3.1) names three categories of redundant chains —
the serial open chain, the mobile robot (a platform of ``n_a`` joints carrying an arm of
``n_b``) and cooperating robots — and shows that each reduces to the same equation
``ẋ = J(θ)θ̇`` (its eq. 2), possibly with extra equality rows ``Φ(θ) = 0`` stacked under
the task (``F = [f(θ) − x; Φ(θ)]``, ch. 4.2), and so to the same Newton–Raphson /
compact-QP step. A :class:`Chain` is that common form, built from parts:

* ``model`` — the joints as ONE serial :class:`~irlc.robots.model.RobotModel`: their
  number, kinds, names, limits (position, speed, acceleration, ``(n, 2)`` SI), weights,
  coupled and motor rows (``extra``). For one robot its own model; for two cooperating
  robots the model of the chain from robot I's tool through its base to robot II's
  base and tool (:mod:`~irlc.runtime.model.cooperating`).
* ``kin`` — the task's forward kinematics and Jacobian
  (:class:`~irlc.runtime.model.kinematics.Kinematics` of ``model`` and the tool): the
  pose ``f(θ)`` the task rows control, in the chain's base frame (the world for one
  robot; robot I's tool frame — the workpiece — for a cooperating pair).
* ``bodies`` — the links in the world, for distances and obstacles
  (:mod:`~irlc.runtime.model.bodies`): their frames at ``θ``, the critical points to
  obstacles and the point Jacobians in the chain's columns.
* ``task_rows`` — the components of the pose error ``f(θ) ⊖ x`` controlled (``x y z rx
  ry rz`` → 0..5; a robot file's ``[ik] task``), and ``tasks`` — extra equality rows
  contributed by task parts (:class:`EqualityTask`; ``runtime/ik/tasks/``: a platform
  following its own path, a tool axis held vertical). The Newton step stacks them:
  ``F = [F_task; F_extra]``, ``J = [J_task; J_extra]``.

:class:`SerialChain` is one robot (exactly the behaviour and numbers of the solver before
chains; the compiled engine covers it, as any chain without extra rows: :attr:`Chain.
compiled`); :class:`~irlc.runtime.model.cooperating.
CooperatingChain` two robots as one chain; a mobile robot with a platform task is a
:class:`SerialChain` with a :class:`~irlc.runtime.ik.tasks.platform.PlatformTask`.
"""

from __future__ import annotations

import copy
from collections.abc import Sequence
from typing import NamedTuple, Protocol

import numpy as np
from irlc.robots.model import TASK_COMPONENTS, RobotModel
from irlc.runtime.model.bodies import Bodies, SerialBodies
from irlc.runtime.model.kinematics import Kinematics


class JointLimits(NamedTuple):
    """A chain's own joint limits, ``(n, 2)`` [min, max] SI each."""

    position: np.ndarray
    speed: np.ndarray
    accel: np.ndarray


class ChainPoint:
    """The chain at one iterate ``θ``: what a task part reads. ``frames`` are the task
    chain's link frames (``kin.chain(θ)``, read-only until the next FK); ``world`` the
    bodies' world frames, computed on first use (the same array for one robot)."""

    __slots__ = ("_world", "chain", "frames", "theta")

    def __init__(self, chain: Chain, theta: np.ndarray, frames: np.ndarray):
        self.chain, self.theta, self.frames = chain, theta, frames
        self._world: np.ndarray | None = None

    @property
    def world(self) -> np.ndarray:
        if self._world is None:
            self._world = self.chain.bodies.world(self.theta, self.frames)
        return self._world


class EqualityTask(Protocol):
    """Extra equality rows ``F_k(θ) = 0`` of a chain's task (seed ch. 3.2: ``Φ(θ) = 0``
    beside ``f(θ) = x``), solved together with the pose rows.

    ``size`` rows; ``kind`` ``"position"`` (m: converged below ``tol_position``) or
    ``"orientation"`` (rad: ``tol_orientation``); ``residual`` the rows ``F_k`` at an
    iterate, ``jacobian`` their ``∂F_k/∂θ`` (``(size, n)``, the chain's columns). A
    task whose rows follow a path (a platform's line) holds its target, which the caller
    sets before each cycle (``task.target = …``), as pink's tasks do."""

    name: str
    size: int
    kind: str

    def residual(self, at: ChainPoint) -> np.ndarray: ...

    def jacobian(self, at: ChainPoint) -> np.ndarray: ...


class Chain:
    """A redundant chain from its parts (module docstring): ``model``, ``kin``,
    ``bodies``, ``task_rows``, ``tasks``."""

    def __init__(
        self,
        model: RobotModel,
        kin: Kinematics,
        bodies: Bodies,
        task_rows: Sequence[int],
        tasks: Sequence[EqualityTask] = (),
    ):
        rows = tuple(int(r) for r in task_rows)
        if list(rows) != sorted(set(rows)) or not set(rows) <= set(range(6)):
            raise ValueError(f"task rows must be increasing, within 0..5: {rows}")
        self.model, self.kin, self.bodies = model, kin, bodies
        self.task_rows, self.tasks = rows, tuple(tasks)
        self.n = model.n
        self.weights = model.weights  # the redundancy weights w (W = diag(w))
        self.limits = JointLimits(model.position_limits, model.speed_limits, model.accel_limits)

    @property
    def rows(self) -> int:
        """``m``: the equality rows of the task (pose rows and extra rows)."""
        return len(self.task_rows) + sum(t.size for t in self.tasks)

    @property
    def compiled(self) -> bool:
        """True when the compiled engine covers the chain: it has no extra rows (it reads
        the packed task chain, ``kin.chain_data``). Its distances are the task chain's
        frames', so a cycle with obstacles runs on the numpy path unless the bodies are
        those frames (``bodies.task_frames_are_world``: one robot)."""
        return not self.tasks

    def with_tasks(self, tasks: Sequence[EqualityTask]) -> Chain:
        """The same chain with other extra rows (the parts are shared)."""
        out = copy.copy(self)
        out.tasks = tuple(tasks)
        return out

    def robot_columns(self) -> tuple[tuple[RobotModel, np.ndarray], ...]:
        """Each robot of the chain: its own model and the chain column of each of its
        joints (one robot: the chain itself). What sums over robots reads it (the links'
        kinetic energy of ``R_CRITERION := 'ENERGY'``)."""
        return ((self.model, np.arange(self.n)),)

    def tcp(self, q: np.ndarray) -> np.ndarray:
        """The task's TCP pose at ``q`` (4×4, the chain's base frame)."""
        return self.kin.tcp(q)

    def world_frames(self, q: np.ndarray) -> np.ndarray:
        """The bodies' link frames in the world at ``q`` (a new array)."""
        frames = self.kin.link_frames(q)
        return self.bodies.world(q, frames)

    def tool_body(self) -> tuple[int, np.ndarray]:
        """``(link, T)``: the world body link that carries the working tool and the tool's
        pose in that link's frame (one robot: its last link and ``flange·tool``)."""
        return self.bodies.tool_body()

    def point(self, theta: np.ndarray) -> ChainPoint:
        """The chain at ``theta`` for task parts (one FK)."""
        return ChainPoint(self, theta, self.kin.link_frames(theta))


class SerialChain(Chain):
    """One robot: its own model, ``Kinematics(model, tool)``, its links in the world as
    the task chain's frames. ``task_rows`` default to the robot file's ``[ik] task``."""

    def __init__(
        self,
        model: RobotModel,
        kin: Kinematics | None = None,
        *,
        tool: np.ndarray | None = None,
        task_rows: Sequence[int] | None = None,
        tasks: Sequence[EqualityTask] = (),
    ):
        kin = Kinematics(model, tool) if kin is None else kin
        rows = task_rows_for(model) if task_rows is None else task_rows
        super().__init__(model, kin, SerialBodies(kin), rows, tasks)


def task_rows_for(model: RobotModel) -> tuple[int, ...]:
    """Controlled pose-error components from the robot file (default: all six)."""
    ik = model.extra.get("ik", {}) if isinstance(model.extra, dict) else {}
    names: Sequence[str] | None = ik.get("task") if isinstance(ik, dict) else None
    if names is None:
        names = model.extra.get("task") if isinstance(model.extra, dict) else None
    if not names:
        return tuple(range(6))
    bad = [c for c in names if c not in TASK_COMPONENTS]
    if bad:
        raise ValueError(
            f"robot {model.name}: unknown task component(s) {bad}; "
            f"known: {', '.join(TASK_COMPONENTS)}"
        )
    return tuple(sorted(TASK_COMPONENTS.index(c) for c in names))
