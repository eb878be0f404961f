"""Forward kinematics and Jacobians of a serial :class:`~irlc.robots.model.RobotModel`.

For link frames ``T_i = T_{i−1} · origin_i · M_i(q_i + offset_i)`` (see the model), the
world-frame geometric Jacobian column of joint ``i`` at a point ``p`` is

* revolute:  ``[ z_i × (p − o_i) ; z_i ]``
* prismatic: ``[ z_i ; 0 ]``

with ``z_i`` the joint axis and ``o_i`` the joint origin in the world. Rows are linear
velocity then angular velocity.
"""

from __future__ import annotations

import numpy as np

from irlc.robots.model import RobotModel
from irlc.runtime import spatial


class Kinematics:
    """FK and Jacobians for one robot; the TCP transform can be changed (``R_TOOL``)."""

    def __init__(self, model: RobotModel, tool: np.ndarray | None = None):
        self.model = model
        self.n = model.n
        self._origins = [j.origin for j in model.joints]
        self._axes = [np.asarray(j.axis, dtype=float) for j in model.joints]
        self._revolute = [j.kind == "revolute" for j in model.joints]
        self._offsets = np.array([j.offset for j in model.joints])
        self.tool = model.tool if tool is None else tool

    def link_frames(self, q: np.ndarray) -> np.ndarray:
        """World frames of links ``0..n`` (shape ``(n+1, 4, 4)``); index 0 is the base."""
        frames = np.empty((self.n + 1, 4, 4))
        t = self.model.base.copy()
        frames[0] = t
        for i in range(self.n):
            t = t @ self._origins[i]
            v = q[i] + self._offsets[i]
            if self._revolute[i]:
                m = spatial.transform(spatial.axis_angle(self._axes[i], v))
            else:
                m = spatial.transform(None, self._axes[i] * v)
            t = t @ m
            frames[i + 1] = t
        return frames

    def tcp_from_frames(self, frames: np.ndarray) -> np.ndarray:
        return frames[-1] @ self.model.flange @ self.tool

    def tcp(self, q: np.ndarray) -> np.ndarray:
        """World pose of the TCP (4×4)."""
        return self.tcp_from_frames(self.link_frames(q))

    def joint_axes_world(self, frames: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Joint axes ``z_i`` and origins ``o_i`` in the world (each ``(n, 3)``)."""
        z = np.array([frames[i + 1, :3, :3] @ self._axes[i] for i in range(self.n)])
        o = frames[1:, :3, 3]
        return z, o

    def jacobian_at(self, frames: np.ndarray, point: np.ndarray, upto: int | None = None):
        """6×n Jacobian of a point rigidly attached to link ``upto`` (default: last link)."""
        upto = self.n if upto is None else upto
        z, o = self.joint_axes_world(frames)
        jac = np.zeros((6, self.n))
        for i in range(upto):
            if self._revolute[i]:
                jac[:3, i] = np.cross(z[i], point - o[i])
                jac[3:, i] = z[i]
            else:
                jac[:3, i] = z[i]
        return jac

    def jacobian(self, q: np.ndarray) -> np.ndarray:
        """6×n geometric Jacobian of the TCP in the world frame."""
        frames = self.link_frames(q)
        return self.jacobian_at(frames, self.tcp_from_frames(frames)[:3, 3])

    def tcp_and_jacobian(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        frames = self.link_frames(q)
        t = self.tcp_from_frames(frames)
        return t, self.jacobian_at(frames, t[:3, 3])

    def point_jacobian(self, q: np.ndarray, link: int, point: np.ndarray) -> np.ndarray:
        """3×n Jacobian of the world ``point`` moving with link ``link`` (0..n)."""
        frames = self.link_frames(q)
        return self.jacobian_at(frames, np.asarray(point, dtype=float), upto=link)[:3]
