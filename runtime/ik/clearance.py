"""``R_CLEARANCE``: the links keep a distance, as inequality rows of the cycle's QP.

The chain's parts (each robot's capsules and spheres, :mod:`irlc.runtime.model.clearance`)
are measured against each other — a robot's non-adjacent links, and in a cooperating chain
one robot's links against the other's — and against the parts of the cell's other robots
(moving obstacles, :class:`Neighbours`). A pair keeps ``d`` (``R_CLEARANCE``; a robot's own
pair closer than ``d`` at home only 0, :meth:`PartSet.keep`). For every watched pair
closer than its ``d⁺ + BAND`` at the start of the cycle ``θ_s``, with the closest points
``x_a`` (on the chain) and ``x_b``, ``n`` the unit vector from ``x_b`` to ``x_a`` and ``R``
their distance, the distance after the cycle's displacement ``δ`` is to first order
``R + n·(J_a(x_a) − J_b(x_b))δ − n·Δx_b`` (``J``: the point Jacobians in the chain's
columns, ``J_b = 0`` for another robot's part, ``Δx_b`` that part's predicted displacement
this cycle: its robot's last one). The row keeps it from closing faster than a damper
allows (the velocity damper of [Faverjon & Tournassoud 1987])::

    n·(J_a − J_b)δ ≥ n·Δx_b − ξ(R − d⁺),      ξ = DAMPING,  d⁺ = keep + MARGIN

so the distance approaches ``d⁺`` no faster than a fraction ``ξ`` of what is left per
cycle, and a pair already closer is pushed apart. Like the coupled limits
(:mod:`~irlc.runtime.ik.coupled`) the rows bound the whole cycle's displacement: in
Newton iteration ``k`` they read ``AΔθ ≥ b − AΣ_k``. Where the QP cannot keep a row the
cycle is relaxed (a path deviation, ``binding`` names the pair); where not even the relaxed
step can (the joints' acceleration box cannot brake the approach in time), the step is
taken without the clearance rows (:attr:`ClearanceRows.soft`), and a clearance that falls
below what the pair keeps fails the run (:mod:`irlc.runtime.control.clearance_rule`).

``MARGIN`` (1 mm): a part sliding along another at speed dips below its linearised row by
the surfaces' curvature (≈ s²/2ρ for a step s along a capsule of radius ρ: 0.1 mm at 5 mm a
cycle on a 0.1 m capsule); aiming 1 mm beyond ``d`` keeps the recorded clearance ≥ ``d``.
``BAND`` (0.2 m): farther pairs get no row (the damper allows them to close by
``ξ·0.2 m`` = 20 mm a cycle, faster than any motion of the library's robots).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from irlc.runtime import units
from irlc.runtime.model.clearance import PartSet, RobotParts, segment_distances
from irlc.runtime.model.distance import fallback_direction

DAMPING = 0.1  # ξ: the share of the distance left above d⁺ a pair may close per cycle
MARGIN = 1e-3  # m: the rows aim this far beyond R_CLEARANCE (module doc)
BAND = 0.2  # m: pairs farther than d + BAND get no row


@dataclass(frozen=True)
class Neighbours:
    """The parts of the cell's other robots during one cycle (world, SI): core ends ``a``,
    ``b`` at its start and their predicted displacement ``da``, ``db`` over it, radii, and
    for messages each part's robot name and link."""

    a: np.ndarray
    b: np.ndarray
    da: np.ndarray
    db: np.ndarray
    radius: np.ndarray
    robot: tuple[str, ...]
    link: np.ndarray


@dataclass
class ClearanceSpec:
    """``CycleOptions.clearance``: the distance to keep (m, ``R_CLEARANCE`` > 0) and,
    in a cell, where the other robots' parts are this cycle (``None``: no others)."""

    distance: float
    neighbours: Callable[[], Neighbours | None] | None = None
    robot: str = ""  # the chain's robot in messages (a cell's; a chain of two names its own)


class ClearanceRows:
    """The rows of one chain (module doc): :meth:`prepare` at the start of each cycle,
    :meth:`at` per Newton iteration, :meth:`describe_row` for ``binding``."""

    def __init__(self, chain):
        self.chain = chain
        robots = chain.bodies.robots()
        self.offsets = [offset for _, _, offset in robots]
        self.parts = PartSet([RobotParts(name, kin) for name, kin, _ in robots])
        self.A = np.zeros((0, chain.n))
        self.bound_d = np.zeros(0)
        self.labels: list[tuple[str, str]] = []
        self.pairs: list[tuple[int, int]] = []  # per row: its chain part, the other's index
        self.distance = 0.0
        self.robot = ""

    def __len__(self) -> int:
        return self.A.shape[0]

    def prepare(self, spec: ClearanceSpec, theta: np.ndarray) -> None:
        """The rows of the pairs within ``d + BAND`` at the cycle's start ``θ_s``."""
        self.distance = spec.distance
        self.robot = spec.robot
        bodies = self.chain.bodies
        world = self.chain.world_frames(theta)
        parts = self.parts
        frames = [
            world[o : o + r.kin.n + 1] for r, o in zip(parts.robots, self.offsets, strict=True)
        ]
        a, b = parts.world(frames)
        rows, bounds, labels, self.pairs = [], [], [], []
        if len(parts):
            d, _, _, p, q = parts.distances(a, b)
            targets = parts.keep(spec.distance) + MARGIN
            for k in np.flatnonzero(d < targets + BAND).tolist():
                c = parts.clearance(k, float(d[k]), p[k], q[k], a, b)
                ja = bodies.jacobian(world, self._link(c.robot_a, c.link_a), c.point_a)[:3]
                jb = bodies.jacobian(world, self._link(c.robot_b, c.link_b), c.point_b)[:3]
                rows.append(c.direction @ (ja - jb))
                bounds.append(-DAMPING * (c.distance - float(targets[k])))
                self.pairs.append((int(parts.i[k]), int(parts.j[k])))
                labels.append((self._label(c.robot_a, c.link_a), self._label(c.robot_b, c.link_b)))
        others = spec.neighbours() if spec.neighbours is not None else None
        if others is not None and len(others.radius):
            target = spec.distance + MARGIN
            self._neighbour_rows(others, a, b, world, target, rows, bounds, labels)
        self.A = np.array(rows).reshape(len(rows), self.chain.n)
        self.bound_d = np.array(bounds)
        self.labels = labels

    def _label(self, robot: int, link: int) -> str:
        """``holder link 3`` (a one-robot chain's parts by the spec's robot name)."""
        if self.parts.robots[robot].name or not self.robot:
            return self.parts.label(robot, link)
        return f"{self.robot} link {link}"

    def _link(self, robot: int, link: int) -> int:
        """The world link index (the chain's bodies) of a robot's link."""
        return self.offsets[robot] + link

    def _neighbour_rows(self, nb: Neighbours, a, b, world, target, rows, bounds, labels):
        """Rows of every chain part against every part of the other robots."""
        parts = self.parts
        i, j = np.meshgrid(np.arange(len(parts.radius)), np.arange(len(nb.radius)), indexing="ij")
        i, j = i.ravel(), j.ravel()
        _, t, p, q = segment_distances(a[i], b[i], nb.a[j], nb.b[j])
        diff = p - q
        core = np.sqrt(np.einsum("ij,ij->i", diff, diff))
        d = core - parts.radius[i] - nb.radius[j]
        for k in np.flatnonzero(d < target + BAND).tolist():
            pi, pj = int(i[k]), int(j[k])
            if core[k] > 1e-14:
                n = diff[k] / core[k]
            else:
                n = fallback_direction(b[pi] - a[pi], nb.b[pj] - nb.a[pj])
            point = p[k] - parts.radius[pi] * n
            robot, link = int(parts.robot[pi]), int(parts.link[pi])
            ja = self.chain.bodies.jacobian(world, self._link(robot, link), point)[:3]
            moved = (1.0 - t[k]) * nb.da[pj] + t[k] * nb.db[pj]
            rows.append(n @ ja)
            bounds.append(float(n @ moved) - DAMPING * (float(d[k]) - target))
            self.pairs.append((pi, -1 - pj))  # (a neighbour's part j: −1 − j)
            labels.append((self._label(robot, link), f"{nb.robot[pj]} link {int(nb.link[pj])}"))

    def at(self, sigma: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(A, b_k)`` with ``AΔθ ≥ b_k`` at an iterate with increments ``sigma``."""
        return self.A, self.bound_d - self.A @ sigma

    def describe_row(self, row: int) -> str:
        """``clearance holder link 3 – welder link 5 ≥ 50 mm`` (the pair of a row)."""
        first, second = self.labels[row]
        return f"clearance {first} – {second} ≥ {self.distance / units.MM:g} mm"


class InequalityRows:
    """Several sets of rows ``AΔθ ≥ b`` (coupled limits, clearances) as one, for the QP
    and for ``binding``: row ``r`` is its set's row ``r − start``."""

    def __init__(self, parts):
        self.parts = [p for p in parts if p is not None and len(p)]

    def __len__(self) -> int:
        return sum(len(p) for p in self.parts)

    def at(self, sigma: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
        if not self.parts:
            return None
        if len(self.parts) == 1:
            return self.parts[0].at(sigma)
        pieces = [p.at(sigma) for p in self.parts]
        return np.vstack([A for A, _ in pieces]), np.concatenate([b for _, b in pieces])

    def describe_row(self, row: int) -> str:
        for p in self.parts:
            if row < len(p):
                return p.describe_row(row)
            row -= len(p)
        return ""
