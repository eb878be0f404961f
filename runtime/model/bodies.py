"""A chain's links in the world: their frames, their distances to obstacles, and the
Jacobians of points on them — what clearances, the obstacle criterion and world-frame
task rows need (:mod:`~irlc.runtime.model.chain`).

The world link frames are numbered in one array. For one robot (:class:`SerialBodies`)
they are the task chain's own frames (link ``0`` = base … ``n``), so nothing is computed
twice. For several robots in one chain (:class:`CellBodies`) each robot's frames follow
the previous robot's (robot ``r``'s link ``l`` is index ``offset_r + l``), each from the
robot's own forward kinematics of its joints (its columns of the chain's ``θ``); a point
Jacobian is the robot's own ``6×n_r`` Jacobian scattered into the chain's columns (the
other robots' columns are zero: their joints do not move that link).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np
from irlc.runtime.model import distance
from irlc.runtime.model.distance import CriticalPoint, closest_parts, robot_segments
from irlc.runtime.model.kinematics import Kinematics


class Bodies(Protocol):
    """The links of a chain in the world (module docstring)."""

    task_frames_are_world: bool

    def world(self, theta: np.ndarray, frames: np.ndarray) -> np.ndarray:
        """World link frames ``(k, 4, 4)`` at ``theta`` (``frames``: the task chain's)."""
        ...

    def critical_points(self, world: np.ndarray, obstacles) -> list[CriticalPoint]:
        """Per obstacle the closest part (``link`` indexes ``world``)."""
        ...

    def jacobian(self, world: np.ndarray, link: int, point: np.ndarray) -> np.ndarray:
        """``6×n`` world Jacobian (linear; angular) of ``point`` moving with ``link``."""
        ...

    def tool_body(self) -> tuple[int, np.ndarray]:
        """``(link, T)``: the link carrying the working tool and the tool in its frame."""
        ...

    def link_label(self, link: int) -> str:
        """How a message names ``link``."""
        ...

    def robots(self) -> tuple[tuple[str, Kinematics, int], ...]:
        """``(name, kinematics, offset)`` per robot: its links are the world links
        ``offset … offset + n`` (one robot: ``("", kin, 0)``)."""
        ...


class SerialBodies:
    """One robot's links: the task chain's frames are the world frames."""

    task_frames_are_world = True

    def __init__(self, kin: Kinematics):
        self.kin = kin

    def world(self, theta: np.ndarray, frames: np.ndarray) -> np.ndarray:
        return frames

    def critical_points(self, world: np.ndarray, obstacles) -> list[CriticalPoint]:
        return distance.critical_points(self.kin, world, obstacles)

    def jacobian(self, world: np.ndarray, link: int, point: np.ndarray) -> np.ndarray:
        return self.kin.jacobian_at(world, np.asarray(point, dtype=float), upto=link)

    def tool_body(self) -> tuple[int, np.ndarray]:
        return self.kin.n, self.kin.end

    def link_label(self, link: int) -> str:
        return f"link {link}"

    def robots(self) -> tuple[tuple[str, Kinematics, int], ...]:
        return (("", self.kin, 0),)


def bodies_of(bodies: Bodies | Kinematics) -> Bodies:
    """``bodies`` itself, or a :class:`~irlc.runtime.model.kinematics.Kinematics`'s one
    robot as :class:`SerialBodies`."""
    return SerialBodies(bodies) if isinstance(bodies, Kinematics) else bodies


@dataclass(frozen=True)
class Member:
    """One robot of a :class:`CellBodies`: its name, its kinematics in the cell (the
    model with its base placed and its tool) and the chain column of each of its
    joints (``columns[j]``: joint ``j``)."""

    name: str
    kin: Kinematics
    columns: np.ndarray


class CellBodies:
    """The links of several robots that form one chain (module docstring)."""

    task_frames_are_world = False

    def __init__(self, members: Sequence[Member], n: int, tool_member: int = -1):
        self.members = tuple(members)
        self.n = n
        sizes = [m.kin.n + 1 for m in self.members]
        self.offsets = np.concatenate(([0], np.cumsum(sizes)[:-1])).astype(int)
        self.size = int(sum(sizes))
        self._tool = tool_member % len(self.members)

    def world(self, theta: np.ndarray, frames: np.ndarray) -> np.ndarray:
        out = np.empty((self.size, 4, 4))
        for m, offset in zip(self.members, self.offsets, strict=True):
            out[offset : offset + m.kin.n + 1] = m.kin.link_frames(theta[m.columns])
        return out

    def _member(self, link: int) -> tuple[int, int]:
        """``(member, its own link)`` of a world link index."""
        r = int(np.searchsorted(self.offsets, link, side="right")) - 1
        return r, link - int(self.offsets[r])

    def critical_points(self, world: np.ndarray, obstacles) -> list[CriticalPoint]:
        ends_a, ends_b, radius, links = [], [], [], []
        for m, offset in zip(self.members, self.offsets, strict=True):
            seg = robot_segments(m.kin)
            a, b = seg.world(m.kin, world[offset : offset + m.kin.n + 1])
            ends_a.append(a)
            ends_b.append(b)
            radius.append(seg.radius)
            links.append(seg.links + offset)
        return closest_parts(
            np.concatenate(ends_a),
            np.concatenate(ends_b),
            np.concatenate(radius),
            np.concatenate(links),
            obstacles,
        )

    def jacobian(self, world: np.ndarray, link: int, point: np.ndarray) -> np.ndarray:
        r, own = self._member(link)
        m, offset = self.members[r], int(self.offsets[r])
        local = m.kin.jacobian_at(
            world[offset : offset + m.kin.n + 1], np.asarray(point, dtype=float), upto=own
        )
        out = np.zeros((6, self.n))
        out[:, m.columns] = local
        return out

    def tool_body(self) -> tuple[int, np.ndarray]:
        m = self.members[self._tool]
        return int(self.offsets[self._tool]) + m.kin.n, m.kin.end

    def link_label(self, link: int) -> str:
        r, own = self._member(link)
        return f"{self.members[r].name} link {own}"

    def robots(self) -> tuple[tuple[str, Kinematics, int], ...]:
        return tuple(
            (m.name, m.kin, int(off)) for m, off in zip(self.members, self.offsets, strict=True)
        )
