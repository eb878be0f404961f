"""Two cooperating robots as ONE serial chain (seed 001, ch. 3.2, fig. 3.1c).

Robot I holds the workpiece, robot II works along a path ``x_Bp(t)`` given in the
workpiece's frame ``B_p`` (robot I's tool). Taking ``B_p`` as the base frame, the two
robots form one serial chain "starting at robot I's tool, through its base, then robot
II's base and ending at its tool"; its forward kinematics is

    x_Bp = f_I,II(θ_I, θ_II) = T_I(θ_I)⁻¹ · T_II(θ_II)

(``T_r``: robot r's TCP in the cell) and its Jacobian ``[J_I(θ_I) J_II(θ_II)]``, so the
task is the seed's eq. (2) again, solved by the same Newton–Raphson / compact-QP step
over all ``n_I + n_II`` joints (12 for two 6-axis robots, fig. 3.4).

**The chain as a serial model.** With ``T_r = B_r·O_1M_1(θ_1)·…·O_nM_n(θ_n)·F_r·G_r``
(placement in the cell ``B_r``, joint origins ``O_i``, joint motions ``M_i``, flange
``F``, tool ``G``)::

    T_I⁻¹·T_II = (G_I⁻¹F_I⁻¹) · M_n⁻¹ · O_n⁻¹M_{n−1}⁻¹ ⋯ O_2⁻¹M_1⁻¹
                 · (O_1⁻¹B_I⁻¹B_II·O'_1)M'_1 · O'_2M'_2 ⋯ O'_mM'_m · F_II·G_II

which is again ``base · Π origin_i·M_i · flange · tool``: the fixed transforms are the
inverses of robot I's, re-associated (robot I's joint ``i`` takes the origin
``O_{i+1}⁻¹``, its last joint the identity, the chain's base is ``G_I⁻¹F_I⁻¹``), and the
two robots meet in one fixed transform, the cell placement of both bases. A reversed
joint is the same joint with its variable negated — ``M(v)⁻¹ = M(−v)`` about the same
axis, i.e. ``M(v)`` about the negated axis — so the chain's variables are the robots'
own joint values (same limits, offsets, weights), robot I's in reverse order:
``θ = [θ_I,n … θ_I,1, θ_II,1 … θ_II,m]`` (:meth:`CooperatingChain.join`, ``split``).

The links are the robots' own in the cell (:class:`~irlc.runtime.model.bodies.
CellBodies`: robot I's frames ``0 … n_I``, then robot II's), for clearances and
obstacles; the chain's tool body for world-frame task rows (a tool held vertical) is
robot II's tool. A coupled joint limit of either robot is a row of the chain (its
coefficients moved to the robot's columns); motor speed rows (a transmission's) are not
carried over yet.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from irlc.robots.model import Joint, RobotModel
from irlc.runtime.model import spatial
from irlc.runtime.model.bodies import CellBodies, Member
from irlc.runtime.model.chain import Chain, EqualityTask
from irlc.runtime.model.kinematics import Kinematics


@dataclass(frozen=True)
class CellRobot:
    """A robot of a cell: its ``name``, model, the placement of its base in the cell
    (``at``, 4×4 SI: ``ROBOT r := … AT (…)``) and its tool (4×4 in the flange frame;
    ``None``: the robot file's)."""

    name: str
    model: RobotModel
    at: np.ndarray = dataclasses.field(default_factory=lambda: np.eye(4))
    tool: np.ndarray | None = None

    def placed(self) -> RobotModel:
        """The model with its base in the cell frame and its tool."""
        tool = self.model.tool if self.tool is None else np.asarray(self.tool, dtype=float)
        return dataclasses.replace(self.model, base=self.at @ self.model.base, tool=tool)


def cooperating_model(holder: CellRobot, worker: CellRobot) -> RobotModel:
    """The serial model of the chain from ``holder``'s tool to ``worker``'s tool
    (module docstring); joint names ``<robot>_<joint>``."""
    a, b = holder.placed(), worker.placed()
    inv = spatial.inverse
    joints: list[Joint] = []
    for i in range(a.n - 1, -1, -1):  # robot I backwards: inverted, re-associated
        j = a.joints[i]
        origin = np.eye(4) if i == a.n - 1 else inv(a.joints[i + 1].origin)
        joints.append(_renamed(j, holder.name, origin=origin, axis=-np.asarray(j.axis)))
    bridge = inv(a.joints[0].origin) @ inv(a.base) @ b.base @ b.joints[0].origin
    for i, j in enumerate(b.joints):
        joints.append(_renamed(j, worker.name, origin=bridge if i == 0 else j.origin))
    home = np.concatenate((a.home_q()[::-1], b.home_q()))
    return RobotModel(
        name=f"{holder.name}+{worker.name}",
        joints=tuple(joints),
        base=inv(a.tool) @ inv(a.flange),
        flange=b.flange,
        tool=b.tool,
        home=home,
        gravity=a.gravity,
        extra={"coupled_limits": _coupled_rows(a, holder.name, b, worker.name)},
        source=f"cooperating chain of {holder.name} ({a.name}) and {worker.name} ({b.name})",
        description="two cooperating robots as one serial chain (seed ch. 3.2)",
    )


def _renamed(j: Joint, robot: str, **changes) -> Joint:
    return dataclasses.replace(j, name=f"{robot}_{j.name}", **changes)


def _coupled_rows(a: RobotModel, a_name: str, b: RobotModel, b_name: str) -> list[dict]:
    """Both robots' coupled joint limits as rows over the chain's columns."""
    rows = []
    cols_a, cols_b = _columns(a.n, b.n)
    for model, name, columns in ((a, a_name, cols_a), (b, b_name, cols_b)):
        for r in model.extra.get("coupled_limits", []):
            coeffs = np.zeros(a.n + b.n)
            coeffs[columns] = np.asarray(r["coeffs"], dtype=float)
            rows.append({**r, "name": f"{name}_{r['name']}", "coeffs": coeffs})
    return rows


def _columns(n_a: int, n_b: int) -> tuple[np.ndarray, np.ndarray]:
    """The chain column of each joint of robot I (reversed) and of robot II."""
    return np.arange(n_a)[::-1].copy(), n_a + np.arange(n_b)


class CooperatingChain(Chain):
    """``holder`` (robot I, holding the workpiece: the task frame is its tool) and
    ``worker`` (robot II, whose tool follows the task) as one chain (module docstring).
    The task pose is the worker's tool in the holder's tool frame."""

    def __init__(
        self,
        holder: CellRobot,
        worker: CellRobot,
        *,
        task_rows: Sequence[int] = (0, 1, 2, 3, 4, 5),
        tasks: Sequence[EqualityTask] = (),
    ):
        model = cooperating_model(holder, worker)
        cols_a, cols_b = _columns(holder.model.n, worker.model.n)
        members = (
            Member(holder.name, Kinematics(holder.placed()), cols_a),
            Member(worker.name, Kinematics(worker.placed()), cols_b),
        )
        super().__init__(model, Kinematics(model), CellBodies(members, model.n), task_rows, tasks)
        self.holder, self.worker = holder, worker
        self.members = members

    def robot_columns(self) -> tuple[tuple[RobotModel, np.ndarray], ...]:
        """The two robots (placed, with their tools) and their columns of the chain."""
        return tuple(
            (robot.placed(), m.columns)
            for robot, m in zip((self.holder, self.worker), self.members, strict=True)
        )

    def split(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(θ_I, θ_II)``, each in its robot's own joint order."""
        return tuple(np.asarray(theta)[m.columns].copy() for m in self.members)

    def join(self, q_holder: np.ndarray, q_worker: np.ndarray) -> np.ndarray:
        """The chain's ``θ`` from the two robots' joints."""
        theta = np.empty(self.n)
        for m, q in zip(self.members, (q_holder, q_worker), strict=True):
            theta[m.columns] = q
        return theta
