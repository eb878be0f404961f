"""Rigid-body dynamics of a serial :class:`~irlc.robots.model.RobotModel` (numpy, SI).

Equations of motion, joint space::

    M(q) q̈ + C(q, q̇) q̇ + G(q) = τ,      M = M_arm(q) + diag(J_r)

``J_r`` is the reflected rotor inertia ``J_m · i²`` of each axis (``i`` the gear ratio,
motor rad per joint unit); it enters the diagonal only (the rotors' gyroscopic coupling is
neglected, as in [Yurevich] and in Spong's reduced model [Spong 1987]).

All vectors are world-frame. Link ``i`` has frame origin ``P_i``, rotation ``R_i``, mass
``m_i``, centre of mass ``c_i = P_i + R_i·com_i`` and inertia ``I_i = R_i·I_i^L·R_iᵀ`` about
``c_i``. Joint ``i`` acts along the world axis ``z_i`` through ``P_i``.

* **RNEA** (inverse dynamics). Forward, with ``r_i = P_i − P_{i−1}``::

      ω_i = ω_{i−1} + z_i q̇_i                       (revolute)
      α_i = α_{i−1} + z_i q̈_i + ω_{i−1} × z_i q̇_i   (revolute)
      a_i = a_{i−1} + α_{i−1} × r_i + ω_{i−1} × (ω_{i−1} × r_i)
            [+ z_i q̈_i + 2 ω_{i−1} × z_i q̇_i]       (prismatic)
      a_ci = a_i + α_i × ρ_i + ω_i × (ω_i × ρ_i),   ρ_i = c_i − P_i,   a_0 = −g

  backward, moments about ``P_i``::

      f_i = m_i a_ci + f_{i+1}
      n_i = n_{i+1} + r_{i+1} × f_{i+1} + ρ_i × m_i a_ci + I_i α_i + ω_i × I_i ω_i
      τ_i = z_i·n_i (revolute) | z_i·f_i (prismatic)   (+ J_r,i q̈_i)

* **CRBA** (``M``): the composite body ``i..n`` (mass ``m^C``, centre ``c^C``, inertia
  ``I^C`` about ``c^C``) driven by a unit ``q̈_i`` needs the wrench
  ``F = m^C·(z_i × (c^C − P_i))``, ``N = I^C z_i + (c^C − P_i) × F`` (revolute) or
  ``F = m^C z_i``, ``N = (c^C − P_i) × F`` (prismatic), about ``P_i``; then for ``j ≤ i``
  ``M_ji = z_j·(N + (P_i − P_j) × F)`` (revolute ``j``) or ``z_j·F`` (prismatic ``j``).
* ``G(q) = RNEA(q, 0, 0)``, ``C q̇ = RNEA(q, q̇, 0) − G``, forward dynamics
  ``q̈ = M⁻¹ (τ − C q̇ − G)`` (Cholesky).

:meth:`Dynamics.mass_and_bias` is the vectorised hot path for the drive simulation: the
Jacobian form ``M = Σ m_i J_viᵀJ_vi + J_ωiᵀ I_i J_ωi`` and
``h = Σ J_viᵀ m_i (J̇_vi q̇ − g) + J_ωiᵀ (I_i J̇_ωi q̇ + ω_i × I_i ω_i)``, cross-checked
against RNEA/CRBA in the tests.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from irlc.lang.errors import IrlcError
from irlc.robots.model import RobotModel


@dataclass(frozen=True)
class DynamicsData:
    """The inertial data of one :class:`Dynamics` as packed, read-only arrays (what
    compiled kernels take; :attr:`Dynamics.data`): per joint ``axes`` ``(n, 3)`` (link
    frame), ``revolute`` ``(n,)`` 1.0 / 0.0, ``rotor`` ``(n,)`` (``J_r``); per link
    ``mass`` ``(n,)``, ``com`` ``(n, 3)`` (link frame), ``inertia`` ``(n, 3, 3)`` (about
    the centre, link frame); ``gravity`` ``(3,)`` (world, m/s²). The link frames are
    :attr:`irlc.runtime.model.kinematics.Kinematics.chain_data`'s."""

    axes: np.ndarray
    revolute: np.ndarray
    rotor: np.ndarray
    mass: np.ndarray
    com: np.ndarray
    inertia: np.ndarray
    gravity: np.ndarray


def _read_only(a) -> np.ndarray:
    out = np.array(a, dtype=float, order="C")
    out.flags.writeable = False
    return out


class MissingInertialData(IrlcError, ValueError):
    """The robot has no inertial data the simulation needs: no ``[[inertials]]`` for the
    coupled dynamics, neither inertials nor ``[drives] load_inertia`` for decoupled drives,
    or a joint with no inertia at all (no link mass and no rotor)."""


_C1 = np.array([1, 2, 0])
_C2 = np.array([2, 0, 1])


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Cross product over the last axis (``np.cross`` is ~6× slower on small arrays)."""
    return a.take(_C1, axis=-1) * b.take(_C2, axis=-1) - a.take(_C2, axis=-1) * b.take(_C1, axis=-1)


_SKEW_IDX = np.array([[0, 2, 1], [2, 0, 0], [1, 0, 0]])
_SKEW_SIGN = np.array([[0.0, -1.0, 1.0], [1.0, 0.0, -1.0], [-1.0, 1.0, 0.0]])


def _skew(v: np.ndarray) -> np.ndarray:
    x, y, z = v
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def link_inertials(model: RobotModel) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per link ``1 … n``: mass ``(n,)``, centre ``(n, 3)`` and inertia about it ``(n, 3, 3)``
    in the link frame, from the model's ``inertials`` (zero where it has none; link 0, the
    base, carries no dynamics)."""
    n = model.n
    mass, com, inertia = np.zeros(n), np.zeros((n, 3)), np.zeros((n, 3, 3))
    for inertial in model.inertials:
        if 1 <= inertial.link <= n:
            k = inertial.link - 1
            mass[k] = inertial.mass
            com[k] = inertial.com
            inertia[k] = inertial.inertia
    return mass, com, inertia


class Dynamics:
    """M(q), C(q,q̇)q̇, G(q), RNEA and forward dynamics of one robot."""

    def __init__(self, model: RobotModel, rotor_inertia: np.ndarray | None = None):
        if not model.inertials:
            raise MissingInertialData(
                f"robot {model.name} has no inertial data; --drives coupled needs it "
                f"([[inertials]] in {model.source or 'the robot file'})"
            )
        n = model.n
        self.model, self.n = model, n
        self.mass, self.com, self.inertia = link_inertials(model)
        self.rotor = np.zeros(n) if rotor_inertia is None else np.asarray(rotor_inertia, float)
        self.gravity = np.asarray(model.gravity, dtype=float)
        self.revolute = np.array([j.kind == "revolute" for j in model.joints])
        self.offsets = np.array([j.offset for j in model.joints])
        self._origins = np.array([j.origin for j in model.joints])
        axes = np.array([np.asarray(j.axis, float) for j in model.joints])
        self._axes = axes
        self._k = np.array(
            [_skew(a) if r else np.zeros((3, 3)) for a, r in zip(axes, self.revolute, strict=True)]
        )
        self._slide = axes * (~self.revolute)[:, None]
        self._eye3 = np.eye(3)
        self._axis_com = np.stack([axes, self.com], axis=2)
        self._k2 = self._k @ self._k
        self._lower = np.tril(np.ones((n, n), dtype=bool))  # [i, j]: joint j moves link i
        self._strict = np.tril(np.ones((n, n), dtype=bool), -1)
        self._frames = np.empty((n + 1, 4, 4))
        self._frames[0] = model.base
        self._motion = np.tile(np.eye(4), (n, 1, 1))
        self._rev_col = self.revolute[:, None].astype(float)
        self._zero3 = np.zeros((1, 3))
        self._skew_idx = np.array([[0, 2, 1], [2, 0, 0], [1, 0, 0]])
        self._skew_sign = np.array([[0.0, -1.0, 1.0], [1.0, 0.0, -1.0], [-1.0, 1.0, 0.0]])
        self._rev_mask3 = self.revolute[None, :, None]
        self._lower3 = self._lower[:, :, None].astype(float)
        self._jw_mask = (self._lower & self.revolute[None, :])[:, :, None].astype(float)
        self._diag = np.diag_indices(n)
        self._rev_col3 = self.revolute[:, None, None]
        self._upper3 = self._lower.T[:, None, :].astype(float)  # [j, ·, i]: j ≤ i
        self._jw_mask3 = (self._lower.T & self.revolute[:, None])[:, None, :].astype(float)
        self._mass3 = np.repeat(self.mass, 3)[None, :]
        self._mass_tail = np.cumsum(self.mass[::-1])[::-1]
        self._low = self._lower.astype(float)
        self._strict_f = self._strict.astype(float)
        self._upper_f = self._low.T.copy()

    @property
    def data(self) -> DynamicsData:
        """The packed inertial data (:class:`DynamicsData`), built once."""
        cached = getattr(self, "_data", None)
        if cached is None:
            arrays = (self._axes, self.revolute, self.rotor, self.mass, self.com)
            arrays += (self.inertia, self.gravity)
            cached = self._data = DynamicsData(*(_read_only(a) for a in arrays))
        return cached

    # ------------------------------------------------------------------ kinematics
    def frames(self, q: np.ndarray) -> np.ndarray:
        """World frames of links ``0..n``: ``T_i = T_{i−1} · origin_i · M_i(q_i + offset_i)``."""
        v = np.asarray(q, float) + self.offsets
        mot = self._motion
        # Rodrigues (K = 0 for prismatic joints, so their rotation stays I)
        mot[:, :3, :3] = self._eye3 + np.sin(v)[:, None, None] * self._k
        mot[:, :3, :3] += (1.0 - np.cos(v))[:, None, None] * self._k2
        mot[:, :3, 3] = self._slide * v[:, None]
        # prefix products L_1 L_2 … L_i by a log-depth (Hillis–Steele) scan: ⌈log2 n⌉
        # batched products instead of n small ones
        x = self._origins @ mot
        d = 1
        while d < self.n:
            x = np.concatenate([x[:d], x[:-d] @ x[d:]])
            d *= 2
        f = self._frames
        f[1:] = self.model.base @ x
        return f

    def _world(self, q: np.ndarray):
        f = self.frames(q)
        rot = f[1:, :3, :3]
        p = f[1:, :3, 3].copy()
        zc = rot @ self._axis_com  # (n, 3, 2): axis and centre offset in the world
        z = zc[:, :, 0]
        c = p + zc[:, :, 1]
        inertia = rot @ self.inertia @ rot.transpose(0, 2, 1)
        return p, z, c, inertia

    # ------------------------------------------------------------------ RNEA
    def rnea(self, q, qd, qdd, gravity: bool = True) -> np.ndarray:
        """Inverse dynamics ``τ = M q̈ + C q̇ + G`` (recursive Newton–Euler, world frame)."""
        n = self.n
        qd, qdd = np.asarray(qd, float), np.asarray(qdd, float)
        p, z, c, inertia = self._world(q)
        base = self.model.base[:3, 3]
        w = np.zeros(3)
        al = np.zeros(3)
        a = -self.gravity.copy() if gravity else np.zeros(3)
        prev = base
        acc_c = np.empty((n, 3))
        ws = np.empty((n, 3))
        als = np.empty((n, 3))
        for i in range(n):
            r = p[i] - prev
            a = a + _cross(al, r) + _cross(w, _cross(w, r))
            if self.revolute[i]:
                al = al + z[i] * qdd[i] + _cross(w, z[i] * qd[i])
                w = w + z[i] * qd[i]
            else:
                a = a + z[i] * qdd[i] + 2.0 * _cross(w, z[i] * qd[i])
            rho = c[i] - p[i]
            acc_c[i] = a + _cross(al, rho) + _cross(w, _cross(w, rho))
            ws[i], als[i] = w, al
            prev = p[i]
        tau = np.empty(n)
        f = np.zeros(3)
        m = np.zeros(3)
        for i in range(n - 1, -1, -1):
            fi = self.mass[i] * acc_c[i]
            rho = c[i] - p[i]
            iw = inertia[i] @ ws[i]
            r_next = p[i + 1] - p[i] if i + 1 < n else np.zeros(3)
            m = m + _cross(r_next, f) + _cross(rho, fi) + inertia[i] @ als[i]
            m = m + _cross(ws[i], iw)
            f = f + fi
            tau[i] = z[i] @ m if self.revolute[i] else z[i] @ f
        return tau + self.rotor * qdd

    def gravity_torque(self, q) -> np.ndarray:
        """``G(q)``: joint torques that hold the arm still against gravity."""
        zero = np.zeros(self.n)
        return self.rnea(q, zero, zero)

    def coriolis(self, q, qd) -> np.ndarray:
        """``C(q, q̇) q̇`` = RNEA with ``q̈ = 0`` minus ``G``."""
        zero = np.zeros(self.n)
        return self.rnea(q, qd, zero) - self.gravity_torque(q)

    # ------------------------------------------------------------------ CRBA
    def mass_matrix(self, q) -> np.ndarray:
        """``M(q)`` by the composite-rigid-body algorithm (plus rotor inertia)."""
        n = self.n
        p, z, c, inertia = self._world(q)
        out = np.zeros((n, n))
        mc, cc, ic = 0.0, np.zeros(3), np.zeros((3, 3))
        for i in range(n - 1, -1, -1):
            mc, cc, ic = _combine(mc, cc, ic, self.mass[i], c[i], inertia[i])
            if mc == 0.0:
                continue
            d = cc - p[i]
            if self.revolute[i]:
                force = mc * _cross(z[i], d)
                moment = ic @ z[i] + _cross(d, force)
            else:
                force = mc * z[i]
                moment = _cross(d, force)
            for j in range(i + 1):
                if self.revolute[j]:
                    out[j, i] = z[j] @ (moment + _cross(p[i] - p[j], force))
                else:
                    out[j, i] = z[j] @ force
                out[i, j] = out[j, i]
        return out + np.diag(self.rotor)

    def forward(self, q, qd, tau) -> np.ndarray:
        """Forward dynamics ``q̈ = M⁻¹ (τ − C q̇ − G)``."""
        m, h = self.mass_and_bias(q, qd)
        return np.linalg.solve(m, np.asarray(tau, float) - h)

    # ------------------------------------------------------------------ hot path
    def gravity_vector(self, q) -> np.ndarray:
        """``G(q)`` in O(n): with ``μ_j = Σ_{i≥j} m_i`` and ``s_j = Σ_{i≥j} m_i c_i``,
        ``G_j = −z_j·((s_j − μ_j P_j) × g)`` (revolute), ``−μ_j z_j·g`` (prismatic)."""
        p, z, c, _ = self._world(q)
        mu = self._mass_tail
        s = np.cumsum((self.mass[:, None] * c)[::-1], axis=0)[::-1]
        moment = _cross(s - mu[:, None] * p, self.gravity[None, :])
        return -np.where(self.revolute, np.einsum("ij,ij->i", z, moment), mu * (z @ self.gravity))

    @staticmethod
    def _kz_of(z: np.ndarray) -> np.ndarray:
        """``(n, 3, 3)`` skew matrices ``[z_j]×``."""
        return z[:, _SKEW_IDX] * _SKEW_SIGN

    def mass_and_bias(self, q, qd) -> tuple[np.ndarray, np.ndarray]:
        """``(M(q), C(q,q̇)q̇ + G(q))`` in one vectorised pass (Jacobian form, O(n) bias).

        With ``w_j = z_j q̇_j`` (revolute), ``ω_i = Σ_{j≤i} w_j``, ``ż_j = ω_{j−1} × z_j`` and
        cumulative sums ``Σ_{j≤i}`` written ``S[·]_i``, the velocity of a point ``x`` on link
        ``i`` is ``ω_i × x − S[w × P]_i + S[z q̇]^{pris}_i`` and the bias acceleration of
        ``c_i`` is ``A_i × c_i − S[ż q̇ × P]_i + ω_i × v_ci − S[w × v_P]_i + S[ż q̇]^{pris}_i``
        with ``A = S[ż q̇]^{rev}`` (= the bias ``α_i``). Joint ``j`` then receives
        ``z_j·(Σ_{i≥j} c_i × F_i − P_j × Σ_{i≥j} F_i + Σ_{i≥j} N_i)`` (revolute) or
        ``z_j·Σ_{i≥j} F_i`` (prismatic), ``F_i = m_i (a_ci − g)``,
        ``N_i = I_i α_i + ω_i × I_i ω_i``.
        """
        qd = np.asarray(qd, float)
        p, z, c, inertia = self._world(q)
        n, rev, low = self.n, self._rev_col, self._low
        zq = z * qd[:, None]
        wj = zq * rev
        w = low @ wj  # ω_i
        w_prev = self._strict_f @ wj  # ω_{i−1}
        # batched cross products: ż_i, w_i × P_i, ω_i × c_i, ω_{i−1} × P_i, z_i × P_i
        cr = _cross(np.concatenate([w_prev, wj, w, w_prev, z]), np.concatenate([z, p, c, p, p]))
        zdq = cr[:n] * qd[:, None]
        # prefix sums S[·] as products with triangular matrices
        x = np.concatenate([cr[n : 2 * n], zq - wj, zdq * rev, zdq - zdq * rev], axis=1)
        sx = low @ x
        sx_prev = self._strict_f @ x[:, :6]
        alpha = sx[:, 6:9]
        vc = cr[2 * n : 3 * n] - sx[:, :3] + sx[:, 3:6]
        vp = cr[3 * n : 4 * n] - sx_prev[:, :3] + sx_prev[:, 3:6]
        cr2 = _cross(np.concatenate([alpha, zdq * rev, w, wj]), np.concatenate([c, p, vc, vp]))
        acc = cr2[:n] + cr2[2 * n : 3 * n] + sx[:, 9:12] - low @ (cr2[n : 2 * n] + cr2[3 * n :])
        force = self.mass[:, None] * (acc - self.gravity)
        iw = np.einsum("ikl,il->ik", inertia, w)
        cr3 = _cross(np.concatenate([w, c]), np.concatenate([iw, force]))
        moment = np.einsum("ikl,il->ik", inertia, alpha) + cr3[:n]
        tail = self._upper_f @ np.concatenate([force, cr3[n:], moment], axis=1)  # Σ_{i≥j}
        rf = tail[:, :3]
        ang = tail[:, 3:6] - _cross(p, rf) + tail[:, 6:9]
        bias = np.einsum("ij,ij->i", z, np.where(rev > 0.0, ang, rf))
        mass = self._jacobian_mass(z, c, inertia, cr[4 * n :])
        mass[self._diag] += self.rotor
        return mass, bias

    def link_mass_matrix(self, q) -> np.ndarray:
        """``M(q)`` of the links alone (no rotor inertia), the Jacobian form of
        :meth:`mass_and_bias` without the bias: the kinetic energy of the links is
        ``½ q̇ᵀ M q̇`` (``R_CRITERION := 'ENERGY'``, :mod:`irlc.runtime.ik.energy`)."""
        p, z, c, inertia = self._world(q)
        return self._jacobian_mass(z, c, inertia, _cross(z, p))

    def _jacobian_mass(self, z, c, inertia, z_cross_p) -> np.ndarray:
        """``M = Σ m_i J_viᵀ J_vi + J_ωiᵀ I_i J_ωi`` (links only), as two matrix products
        with the Jacobians laid out [joint j, (link i, xyz)]:
        ``jv[j, :, i] = z_j × c_i − z_j × P_j``."""
        n = self.n
        jv = self._kz_of(z) @ c.T - z_cross_p[:, :, None]
        jv = np.where(self._rev_col3, jv, z[:, :, None]) * self._upper3  # (j, xyz, i)
        jv = jv.transpose(0, 2, 1).reshape(n, 3 * n)
        jw = z[:, :, None] * self._jw_mask3  # (j, xyz, i)
        g = inertia @ jw.transpose(2, 1, 0)  # (i, xyz, l) = I_i J_ωi
        return (jv * self._mass3) @ jv.T + jw.transpose(0, 2, 1).reshape(n, 3 * n) @ g.reshape(
            3 * n, n
        )


def _combine(m1: float, c1, i1, m2: float, c2, i2):
    """Mass, centre and inertia (about the centre) of two rigid bodies together."""
    m = m1 + m2
    if m == 0.0:
        return 0.0, np.zeros(3), np.zeros((3, 3))
    c = (m1 * c1 + m2 * c2) / m
    return m, c, i1 + i2 + _shift(m1, c1 - c) + _shift(m2, c2 - c)


def _shift(m: float, d: np.ndarray) -> np.ndarray:
    """Parallel-axis term ``m (|d|² I − d dᵀ)``."""
    return m * (d @ d * np.eye(3) - np.outer(d, d))
