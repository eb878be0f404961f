"""The links' velocities along a recorded motion, many samples at once (numpy, SI).

For ``k`` samples of joints ``q`` and joint speeds ``q̇`` (a trace's rows) this computes,
per sample, the link frames (forward kinematics: the chain of
:attr:`Kinematics.chain_data`, ``T_i = T_{i−1}·origin_i·M_i(q_i + offset_i)`` as
:mod:`~irlc.robots.model` defines it) and the links' velocities by the
forward recursion of the Newton–Euler algorithm, in the world frame, with ``P_i`` the
origin of link ``i`` (on joint ``i``'s axis ``z_i``)::

    ω_i = ω_{i−1} + z_i q̇_i                                    (revolute)
    v_{P_i} = v_{P_{i−1}} + ω_{i−1} × (P_i − P_{i−1}) [+ z_i q̇_i]  (prismatic)
    v_{c_i} = v_{P_i} + ω_i × (c_i − P_i)                       (c_i the link's centre)

and from them

* the links' kinetic energy ``E = Σ_i ½ m_i |v_{c_i}|² + ½ ω_iᵀ I_i ω_i`` (``I_i`` about
  ``c_i``, world) — equal to ``½ q̇ᵀ M(q) q̇`` with the links' inertia matrix ``M``
  (:meth:`Dynamics.link_mass_matrix`; tests compare both, and a finite-difference
  check of the frames' motion); rotor inertia is not included;
* the TCP's twist ``(v, ω)`` with ``v = v_{P_n} + ω_n × (p − P_n)`` for the TCP point ``p``
  of each sample (the tool may change during a run), i.e. ``J(q) q̇``.

One pass over the joints, each step vectorised over the samples: a trace of 10,000 rows
of an 11-joint robot takes a few milliseconds.
"""

from __future__ import annotations

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime.model.dynamics import link_inertials
from irlc.runtime.model.kinematics import Kinematics


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Cross products over the last axis (``(k, 3)``)."""
    return np.stack(
        (
            a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1],
            a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2],
            a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0],
        ),
        axis=1,
    )


class LinkVelocities:
    """Batched link frames and velocities of one serial :class:`RobotModel` (module doc)."""

    def __init__(self, model: RobotModel):
        self.model = model
        self.n = model.n
        self.revolute = [j.kind == "revolute" for j in model.joints]
        self.axes = np.array([np.asarray(j.axis, dtype=float) for j in model.joints])
        self.chain = Kinematics(model).chain_data  # L_i = A0 + cos v·A1 + sin v·A2 + v·A3
        self.mass, self.com, self.inertia = link_inertials(model)

    def frames(self, q: np.ndarray) -> np.ndarray:
        """World frames of links ``0 … n`` for each sample, ``(k, n + 1, 4, 4)``: the chain
        of :attr:`Kinematics.chain_data` (``T_i = T_{i−1}·L_i``), samples at once."""
        q = np.atleast_2d(np.asarray(q, dtype=float))
        k = q.shape[0]
        basis, joints, ends = self.chain.basis, self.chain.joints, self.chain.ends
        out = np.empty((k, self.n + 1, 4, 4))
        out[:, 0] = ends[0]
        coef = np.ones((k, 4))
        for i in range(self.n):
            v = q[:, i] + joints[i, 0]
            coef[:, 1], coef[:, 2], coef[:, 3] = np.cos(v), np.sin(v), v
            local = (coef @ basis[i]).reshape(k, 4, 4)
            np.matmul(out[:, i], local, out=out[:, i + 1])
        return out

    def velocities(self, q: np.ndarray, qd: np.ndarray):
        """``(frames, ω, v_c, v_P)``: the frames (:meth:`frames`), each link's angular
        velocity, its centre's velocity and its origin's, ``(k, n, 3)`` each (world)."""
        qd = np.atleast_2d(np.asarray(qd, dtype=float))
        frames = self.frames(q)
        k, n = qd.shape[0], self.n
        omega, v_com, v_origin = np.zeros((k, n, 3)), np.zeros((k, n, 3)), np.zeros((k, n, 3))
        w = np.zeros((k, 3))
        v = np.zeros((k, 3))
        prev = frames[:, 0, :3, 3]
        for i in range(n):
            rot, p = frames[:, i + 1, :3, :3], frames[:, i + 1, :3, 3]
            z = rot @ self.axes[i]
            v = v + _cross(w, p - prev)
            if self.revolute[i]:
                w = w + z * qd[:, i : i + 1]
            else:
                v = v + z * qd[:, i : i + 1]
            omega[:, i], v_origin[:, i] = w, v
            v_com[:, i] = v + _cross(w, rot @ self.com[i])
            prev = p
        return frames, omega, v_com, v_origin

    def energy_and_twist(self, q: np.ndarray, qd: np.ndarray, tcp: np.ndarray | None = None):
        """``(E, twist)``: per sample the links' kinetic energy ``Σ_i ½ m_i |v_{c_i}|² +
        ½ ω_iᵀ I_i ω_i`` (J) and, for the TCP poses ``tcp`` ``(k, 4, 4)`` (world), the TCP's
        ``(v, ω)`` ``(k, 6)`` (m/s, rad/s; ``J(q) q̇``) — ``None`` without ``tcp``."""
        frames, omega, v_com, v_origin = self.velocities(q, qd)
        rot = frames[:, 1:, :3, :3]
        local = np.einsum("kiab,kia->kib", rot, omega)  # R_iᵀ ω_i: ω in the link's frame
        spin = np.einsum("kia,iab,kib->k", local, self.inertia, local)
        energy = 0.5 * (np.einsum("kia,kia,i->k", v_com, v_com, self.mass) + spin)
        if tcp is None or self.n == 0:
            return energy, None
        p = np.asarray(tcp)[:, :3, 3]
        w, v = omega[:, -1], v_origin[:, -1]
        return energy, np.hstack((v + _cross(w, p - frames[:, -1, :3, 3]), w))

    def kinetic_energy(self, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        """The links' kinetic energy per sample (J; :meth:`energy_and_twist`)."""
        return self.energy_and_twist(q, qd)[0]
