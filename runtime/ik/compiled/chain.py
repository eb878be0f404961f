"""Compiled kinematics of one IK cycle (numba; the package doc lists the numpy
reference of each): the chain ``T_i = T_{i−1}·L_i``, ``L_i = A0 + cos v·A1 + sin v·A2 +
v·A3`` (``forward_chain``), the TCP Jacobian ``[z_i × (p − o_i); z_i]`` (revolute), ``[z_i; 0]``
(prismatic) (``tcp_jacobian``), the pose error with its near-π branch (``pose_error``) and the
evaluation at ``θ`` of FK, task error and its norms (``evaluate``).
"""

from __future__ import annotations

import math

import numpy as np
from irlc.runtime.ik.compiled.layout import E0, NPOS, OE, PE, THETA
from numba import njit


@njit(cache=True)
def forward_chain(basis, joint, base, q, frames, local):
    """FK into ``frames`` (n+1, 4, 4); ``joint[i] = (offset, kx, ky, kz, revolute)``."""
    n = q.shape[0]
    frames[0, :, :] = base
    for i in range(n):
        v = q[i] + joint[i, 0]
        c = math.cos(v)
        s = math.sin(v)
        for e in range(16):
            local[e // 4, e % 4] = (
                basis[i, 0, e] + c * basis[i, 1, e] + s * basis[i, 2, e] + v * basis[i, 3, e]
            )
        for r in range(4):
            f0 = frames[i, r, 0]
            f1 = frames[i, r, 1]
            f2 = frames[i, r, 2]
            f3 = frames[i, r, 3]
            for col in range(4):
                frames[i + 1, r, col] = (
                    f0 * local[0, col]
                    + f1 * local[1, col]
                    + f2 * local[2, col]
                    + f3 * local[3, col]
                )


@njit(cache=True)
def matmul44(a, b, out):
    for r in range(4):
        for col in range(4):
            out[r, col] = (
                a[r, 0] * b[0, col]
                + a[r, 1] * b[1, col]
                + a[r, 2] * b[2, col]
                + a[r, 3] * b[3, col]
            )


@njit(cache=True)
def tcp_jacobian(frames, joint, p, out):
    """6×n TCP Jacobian at the world point ``p`` (``Kinematics.tcp_jacobian``)."""
    n = joint.shape[0]
    for i in range(n):
        f = frames[i + 1]
        kx, ky, kz = joint[i, 1], joint[i, 2], joint[i, 3]
        zx = f[0, 0] * kx + f[0, 1] * ky + f[0, 2] * kz
        zy = f[1, 0] * kx + f[1, 1] * ky + f[1, 2] * kz
        zz = f[2, 0] * kx + f[2, 1] * ky + f[2, 2] * kz
        if joint[i, 4] != 0.0:
            rx = p[0] - f[0, 3]
            ry = p[1] - f[1, 3]
            rz = p[2] - f[2, 3]
            out[0, i] = zy * rz - zz * ry
            out[1, i] = zz * rx - zx * rz
            out[2, i] = zx * ry - zy * rx
            out[3, i] = zx
            out[4, i] = zy
            out[5, i] = zz
        else:
            out[0, i] = zx
            out[1, i] = zy
            out[2, i] = zz
            out[3, i] = 0.0
            out[4, i] = 0.0
            out[5, i] = 0.0


@njit(cache=True)
def pose_error(t, d, e):
    """``spatial.pose_error(t, d)`` into ``e`` (6): position, rotation vector of R·R_dᵀ."""
    e[0] = t[0, 3] - d[0, 3]
    e[1] = t[1, 3] - d[1, 3]
    e[2] = t[2, 3] - d[2, 3]
    m = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            m[i, j] = t[i, 0] * d[j, 0] + t[i, 1] * d[j, 1] + t[i, 2] * d[j, 2]
    w0 = m[2, 1] - m[1, 2]
    w1 = m[0, 2] - m[2, 0]
    w2 = m[1, 0] - m[0, 1]
    cos_t = max(-1.0, min(1.0, (m[0, 0] + m[1, 1] + m[2, 2] - 1.0) / 2.0))
    theta = math.acos(cos_t)
    if theta < 1e-6:
        k = 0.5
    elif math.pi - theta > 1e-4:
        k = theta / (2.0 * math.sin(theta))
    else:  # near a half turn: the axis from the symmetric part (spatial.rotation_vector)
        best, kk = -1.0, 0
        for i in range(3):
            a = math.sqrt(max((m[i, i] + 1.0) / 2.0, 0.0))
            if a > best:
                best, kk = a, i
        s = math.sqrt((m[kk, kk] + 1.0) / 2.0)
        a0 = (m[0, kk] + (1.0 if kk == 0 else 0.0)) / 2.0 / s
        a1 = (m[1, kk] + (1.0 if kk == 1 else 0.0)) / 2.0 / s
        a2 = (m[2, kk] + (1.0 if kk == 2 else 0.0)) / 2.0 / s
        if a0 * w0 + a1 * w1 + a2 * w2 < 0.0:
            a0, a1, a2 = -a0, -a1, -a2
        norm = math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
        e[3] = theta * a0 / norm
        e[4] = theta * a1 / norm
        e[5] = theta * a2 / norm
        return
    e[3] = k * w0
    e[4] = k * w1
    e[5] = k * w2


@njit(cache=True)
def evaluate(kb, kj, ends, target, frames, local, tcp, rows, V, ist, fst):
    """FK, TCP, task error (``fst[E0:E0 + 6]``) and its norms at ``θ``."""
    e6 = fst[E0 : E0 + 6]
    forward_chain(kb, kj, ends[0], V[THETA], frames, local)
    matmul44(frames[frames.shape[0] - 1], ends[1], tcp)
    pose_error(tcp, target, e6)
    npos = ist[NPOS]
    pe = 0.0
    oe = 0.0
    for i in range(rows.shape[0]):
        x = e6[rows[i]]
        if i < npos:
            pe += x * x
        else:
            oe += x * x
    fst[PE] = math.sqrt(pe)
    fst[OE] = math.sqrt(oe)
