"""Forward kinematics and Jacobians of a serial :class:`~irlc.robots.model.RobotModel`.

For link frames ``T_i = T_{i−1} · origin_i · M_i(q_i + offset_i)`` (see the model), the
world-frame geometric Jacobian column of joint ``i`` at a point ``p`` is

* revolute:  ``[ z_i × (p − o_i) ; z_i ]``
* prismatic: ``[ z_i ; 0 ]``

with ``z_i`` the joint axis and ``o_i`` the joint origin in the world. Rows are linear
velocity then angular velocity.

Speed: the joint motion ``M_i(v)`` is affine in ``(1, cos v, sin v, v)`` — Rodrigues,
``R = k kᵀ + cos v (I − k kᵀ) + sin v [k]×`` for a revolute joint, ``Trans(v k)`` for a
prismatic one — so the local transform ``L_i = origin_i · M_i`` is
``A0_i + cos v·A1_i + sin v·A2_i + v·A3_i`` with the ``A`` precomputed per robot. All
``L_i`` then come from one batched product; only the chain ``T_i = T_{i−1} L_i`` is a
loop (one in-place 4×4 product per joint). See ``bench/bench_kinematics.py``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from irlc.robots.model import RobotModel

# columns of ChainData.joints
J_OFFSET, J_AXIS, J_REVOLUTE = 0, slice(1, 4), 4


@dataclass(frozen=True)
class ChainData:
    """The chain of one :class:`Kinematics` as packed, read-only arrays (what compiled
    kernels take; :attr:`Kinematics.chain_data`)::

        v_i = q_i + offset_i,   L_i = A0_i + cos v_i·A1_i + sin v_i·A2_i + v_i·A3_i,
        T_0 = base,   T_i = T_{i−1}·L_i,   TCP = T_n·end

    ``basis`` ``(n, 4, 16)``: the rows ``A0 … A3`` of each joint, flattened 4×4;
    ``joints`` ``(n, 5)``: ``(offset, kx, ky, kz, revolute)`` — the joint axis ``k`` in
    its link frame and 1.0 for revolute, 0.0 for prismatic joints; ``ends`` ``(2, 4, 4)``:
    ``[base; end]``, ``end = flange·tool`` (a new object when the tool changes)."""

    basis: np.ndarray
    joints: np.ndarray
    ends: np.ndarray


def _read_only(a: np.ndarray) -> np.ndarray:
    out = np.array(a, dtype=float, order="C")
    out.flags.writeable = False
    return out


_NEXT = np.array([1, 2, 0])
_PREV = np.array([2, 0, 1])


def _motion_basis(axis: np.ndarray, revolute: bool) -> np.ndarray:
    """``P`` with ``M(v) = P[0] + cos v·P[1] + sin v·P[2] + v·P[3]`` (each 4×4)."""
    k = np.asarray(axis, dtype=float)
    p = np.zeros((4, 4, 4))
    p[0] = np.eye(4)
    if revolute:
        kk = np.outer(k, k)
        p[0, :3, :3] = kk
        p[1, :3, :3] = np.eye(3) - kk
        p[2, :3, :3] = [[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]]
    else:
        p[3, :3, 3] = k
    return p


def _axis_columns(axes: np.ndarray) -> tuple[np.ndarray | None, np.ndarray | None]:
    """Column index and sign per joint when every axis is ±x, ±y or ±z, else ``None``."""
    cols = np.argmax(np.abs(axes), axis=1)
    signs = axes[np.arange(len(axes)), cols]
    if not np.allclose(np.abs(signs), 1.0, atol=0.0, rtol=0.0):
        return None, None
    return cols, signs[:, None].copy()


class Kinematics:
    """FK and Jacobians for one robot; the TCP transform can be changed (``R_TOOL``)."""

    def __init__(self, model: RobotModel, tool: np.ndarray | None = None):
        self.model = model
        self.n = n = model.n
        self._origins = [j.origin for j in model.joints]
        self._axes = np.array([np.asarray(j.axis, dtype=float) for j in model.joints])
        self._revolute = np.array([j.kind == "revolute" for j in model.joints])
        self._rev_f = self._revolute.astype(float)[:, None]
        self._pri_f = 1.0 - self._rev_f
        self._all_revolute = bool(self._revolute.all())
        self._links = np.arange(1, n + 1)
        self._axis_cols, self._axis_signs = _axis_columns(self._axes)
        self._offsets = np.array([j.offset for j in model.joints])
        self.tool = model.tool if tool is None else tool
        # L_i = coef_i · A_i with coef = (1, cos v, sin v, v), A_i = origin_i · P_i (4 × 16)
        basis = np.empty((n, 4, 16))
        for i, j in enumerate(model.joints):
            p = _motion_basis(j.axis, j.kind == "revolute")
            basis[i] = (j.origin @ p).reshape(4, 16)
        self._basis = basis
        self._coef = np.ones((n, 1, 4))
        self._base = np.array(model.base, dtype=float)
        # chain buffer with its per-link views made once (indexing costs ~0.1 µs a time)
        self._frames = np.empty((n + 1, 4, 4))
        self._frames[0] = self._base
        self._views = [self._frames[i] for i in range(n + 1)]
        self._local = np.empty((n, 1, 16))
        self._local_views = [self._local[i].reshape(4, 4) for i in range(n)]
        self._cos = self._coef[:, 0, 1]  # strided views: cos/sin/v written in place
        self._sin = self._coef[:, 0, 2]
        self._val = self._coef[:, 0, 3]
        self._plain = self._all_revolute and not np.any(self._offsets)
        self._jac_indices()

    @property
    def tool(self) -> np.ndarray:
        return self._tool

    @tool.setter
    def tool(self, value: np.ndarray) -> None:
        self._tool = np.array(value, dtype=float)
        self._end = self.model.flange @ self._tool
        self._chain_data: ChainData | None = None

    @property
    def end(self) -> np.ndarray:
        """``flange·tool``: the TCP in the last link's frame."""
        return self._end

    @property
    def chain_data(self) -> ChainData:
        """The packed chain (:class:`ChainData`); rebuilt only when the tool changes."""
        data = self._chain_data
        if data is None:
            joints = np.empty((self.n, 5))
            joints[:, J_OFFSET] = self._offsets
            joints[:, J_AXIS] = self._axes
            joints[:, J_REVOLUTE] = self._revolute
            ends = np.stack((self._base, self._end))
            data = ChainData(_read_only(self._basis), _read_only(joints), _read_only(ends))
            self._chain_data = data
        return data

    # ------------------------------------------------------------------ frames

    def link_frames(self, q: np.ndarray) -> np.ndarray:
        """World frames of links ``0..n`` (shape ``(n+1, 4, 4)``); index 0 is the base."""
        return self.chain(q).copy()

    def chain(self, q: np.ndarray) -> np.ndarray:
        """:meth:`link_frames` without the copy: the returned buffer is overwritten by the
        next call (hot loops that use the frames before the next FK)."""
        v = self._val
        if self._plain:  # revolute joints without offsets: v (the Trans part) is unused
            v = q
        else:
            np.add(q, self._offsets, out=v)
        np.cos(v, out=self._cos)
        np.sin(v, out=self._sin)
        np.matmul(self._coef, self._basis, out=self._local)
        views, local, dot = self._views, self._local_views, np.dot
        for i in range(self.n):
            dot(views[i], local[i], out=views[i + 1])
        return self._frames

    def link_frames_many(self, qs: np.ndarray) -> np.ndarray:
        """:meth:`link_frames` of ``k`` configurations at once (``(k, n)`` → ``(k, n+1, 4,
        4)``; the same products, batched over the configurations: a run's samples after
        the run)."""
        qs = np.asarray(qs, dtype=float)
        v = qs + self._offsets
        coef = np.stack((np.ones_like(v), np.cos(v), np.sin(v), v), axis=2)  # (k, n, 4)
        local = np.einsum("knc,ncm->knm", coef, self._basis).reshape(len(qs), self.n, 4, 4)
        out = np.empty((len(qs), self.n + 1, 4, 4))
        out[:, 0] = self._base
        for i in range(self.n):
            np.matmul(out[:, i], local[:, i], out=out[:, i + 1])
        return out

    def tcp_from_frames(self, frames: np.ndarray) -> np.ndarray:
        return frames[-1] @ self._end

    def tcp(self, q: np.ndarray) -> np.ndarray:
        """World pose of the TCP (4×4)."""
        return self.tcp_from_frames(self.link_frames(q))

    def flange_from_frames(self, frames: np.ndarray) -> np.ndarray:
        return frames[-1] @ self.model.flange

    def link_point(self, frames: np.ndarray, link: int, point: np.ndarray) -> np.ndarray:
        """World position of ``point`` given in link ``link``'s frame (0 = base)."""
        f = frames[link]
        return f[:3, :3] @ point + f[:3, 3]

    # ------------------------------------------------------------------ Jacobians

    def joint_axes_world(self, frames: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Joint axes ``z_i`` and origins ``o_i`` in the world (each ``(n, 3)``)."""
        if self._axis_cols is not None:  # axes along ±x/y/z: a column of the frame
            z = frames[self._links, :3, self._axis_cols]
            z *= self._axis_signs
        else:
            z = np.matmul(frames[1:, :3, :3], self._axes[:, :, None])[:, :, 0]
        return z, frames[1:, :3, 3]

    def _jac_indices(self) -> None:
        """Flat indices for the TCP Jacobian in two ``take`` calls from the gather source
        ``[frames (n+1)·16 | point (3) | 0.0 | 1.0]``: with ``s`` the axis sign, ``a``/``b``
        the rows rotated forward/back (x → y → z → x), the factors ``Z = [z; z_a; z_b]``
        and ``R = P − O = [s; s(p − o)_b; s(p − o)_a]`` (9×n each; ``s < 0`` swaps ``P``
        and ``O``, so no sign products), then ``[ang; A; B] = Z∘R`` and ``lin = A − B``:
        ``lin = s·z × (p − o)``, ``ang = s·z``. A prismatic column takes ``[0; z; 0]`` and
        ``[0; s; 0]``: ``lin = s·z``, ``ang = 0``."""
        self._z_idx = self._po_idx = None
        if self._axis_cols is None:
            return
        n = self.n
        size = (n + 1) * 16
        point, zero, one = size + np.arange(3), size + 3, size + 4
        link = self._links[None, :] * 16
        col, rev = self._axis_cols[None, :], self._revolute[None, :]
        rows = np.arange(3)[:, None]
        pos = self._axis_signs[:, 0][None, :] > 0.0
        z = link + rows * 4 + col
        z_a, z_b = link + _NEXT[:, None] * 4 + col, link + _PREV[:, None] * 4 + col
        o_b, o_a = link + _PREV[:, None] * 4 + 3, link + _NEXT[:, None] * 4 + 3
        p_b, p_a = point[_PREV][:, None] + 0 * link, point[_NEXT][:, None] + 0 * link
        z_rows = (np.where(rev, z, zero), np.where(rev, z_a, z), np.where(rev, z_b, zero))
        self._z_idx = np.concatenate(np.broadcast_arrays(*z_rows)).ravel()
        sign_p, sign_o = np.where(pos, one, zero), np.where(pos, zero, one)
        p_rows = (
            np.where(rev, sign_p, zero),
            np.where(rev, np.where(pos, p_b, o_b), sign_p),
            np.where(rev, np.where(pos, p_a, o_a), zero),
        )
        o_rows = (
            np.where(rev, sign_o, zero),
            np.where(rev, np.where(pos, o_b, p_b), sign_o),
            np.where(rev, np.where(pos, o_a, p_a), zero),
        )
        self._po_idx = np.concatenate(np.broadcast_arrays(*p_rows, *o_rows)).ravel()
        self._signed_axes = bool(np.any(self._axis_signs < 0.0))
        # the gather source around the chain buffer (frames are a view of it)
        self._source = np.empty(size + 5)
        self._source[:size] = self._frames.reshape(-1)
        self._source[size + 3 :] = (0.0, 1.0)
        self._frames = self._source[:size].reshape(n + 1, 4, 4)
        self._views = [self._frames[i] for i in range(n + 1)]
        self._point = self._source[size : size + 3]
        self._zr = np.empty((27, n))  # [Z; P; O], then R = P − O in the P rows
        self._z, self._p, self._o = self._zr[:9], self._zr[9:18], self._zr[18:]
        self._z_flat, self._po_flat = self._z.reshape(-1), self._zr[9:].reshape(-1)
        self._own_out: np.ndarray | None = None
        self._jac_out: tuple = (None,)  # (out, [ang; A; B], lin, A, B) of the last call

    def jacobian_out(self) -> np.ndarray:
        """A 6×n array for :meth:`tcp_jacobian`'s ``out`` that it fills without a copy
        (the first rows of a 12×n buffer: ``[lin; ang; A; B]``)."""
        return np.empty((12, self.n))[:6]

    def tcp_jacobian(self, frames: np.ndarray, point: np.ndarray, out: np.ndarray) -> np.ndarray:
        """``jacobian_at(frames, point)`` written into ``out`` — the IK hot path: the
        same numbers (products and differences of the same factors; see
        :meth:`_jac_indices`) from two ``take`` calls. ``frames`` (``(n+1, 4, 4)``) must
        be C-contiguous; ``out`` from :meth:`jacobian_out` saves a copy."""
        if self._z_idx is None:
            out[:] = self.jacobian_at(frames, point)
            return out
        if frames is self._frames:
            np.copyto(self._point, point)
            src = self._source
        else:
            src = np.concatenate((frames.reshape(-1), point, (0.0, 1.0)))
        views = self._jac_out
        if views[0] is not out:
            views = self._jac_out = self._jacobian_views(out)
        _, prod, lin, a, b = views
        src.take(self._z_idx, out=self._z_flat)
        src.take(self._po_idx, out=self._po_flat)
        np.subtract(self._p, self._o, out=self._p)
        np.multiply(self._z, self._p, out=prod)
        np.subtract(a, b, out=lin)
        if prod.base is not out.base:
            out[3:] = prod[:3]
        return out

    def _jacobian_views(self, out: np.ndarray) -> tuple:
        """``(out, [ang; A; B], lin, A, B)``: in ``out``'s own 12×n buffer when it comes
        from :meth:`jacobian_out`, else in an internal one (``ang`` copied at the end)."""
        base = out.base
        n = self.n
        own = (
            base is not None
            and base.shape == (12, n)
            and base.flags.c_contiguous
            and out.ctypes.data == base.ctypes.data
        )
        if not own:
            if self._own_out is None:
                self._own_out = self.jacobian_out()
            base = self._own_out.base
        prod = base[3:]
        return (out, prod, out[:3], prod[3:6], prod[6:])

    def jacobian_at(self, frames: np.ndarray, point: np.ndarray, upto: int | None = None):
        """6×n Jacobian of a world ``point`` rigidly attached to link ``upto`` (default:
        the last link); columns of joints after ``upto`` are zero."""
        z, o = self.joint_axes_world(frames)
        r = point - o
        lin = z.take(_NEXT, 1) * r.take(_PREV, 1)
        lin -= z.take(_PREV, 1) * r.take(_NEXT, 1)  # z × r, row-wise
        jac = np.empty((6, self.n))
        if self._all_revolute:
            jac[:3] = lin.T
            jac[3:] = z.T
        else:
            lin *= self._rev_f
            lin += z * self._pri_f
            jac[:3] = lin.T
            jac[3:] = (z * self._rev_f).T
        if upto is not None and upto < self.n:
            jac[:, upto:] = 0.0
        return jac

    def jacobian(self, q: np.ndarray) -> np.ndarray:
        """6×n geometric Jacobian of the TCP in the world frame."""
        frames = self.link_frames(q)
        return self.jacobian_at(frames, self.tcp_from_frames(frames)[:3, 3])

    def tcp_and_jacobian(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        frames = self.link_frames(q)
        t = self.tcp_from_frames(frames)
        return t, self.jacobian_at(frames, t[:3, 3])

    def point_jacobian_at(self, frames: np.ndarray, link: int, point: np.ndarray) -> np.ndarray:
        """3×n Jacobian of the world ``point`` moving with link ``link`` (0..n), reusing
        ``frames`` (the IK evaluates several points per iteration)."""
        return self.jacobian_at(frames, np.asarray(point, dtype=float), upto=link)[:3]

    def point_jacobian(self, q: np.ndarray, link: int, point: np.ndarray) -> np.ndarray:
        """3×n Jacobian of the world ``point`` moving with link ``link`` (0..n)."""
        return self.point_jacobian_at(self.link_frames(q), link, point)
