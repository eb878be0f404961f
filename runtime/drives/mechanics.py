"""Joint-space mechanics of the drive simulation, with Karnopp stick–slip.

Equations (joint side; ``T`` the drive torques ``i·τ_m``, ``f`` friction ``i·τ_f``)::

    coupled:    M(q) q̈ + C(q,q̇) q̇ + G(q) = T − f       (M includes J_m·i² on the diagonal)
    decoupled:  D q̈ + G(q) = T − f,  D = diag(M(q₀)) constant (rotor + arm at the start)

Decoupled means one independent inertia per *motor*: with a coupled or non-linear
transmission (``θ_m = f(q)``, ``K = ∂f/∂q`` square at ``q₀``) the axes are decoupled in
motor coordinates, ``J = diag(K⁻ᵀ M(q₀) K⁻¹)``, i.e. ``D = Kᵀ J K`` in joint space (not
diagonal: the IRb-6's A3 screw turns θ2 + θ3, so its rotor couples A2 and A3).

Joints without a drive are prescribed (``q̈_P`` given, their torque is computed). Axes
inside the Karnopp band are first assumed stuck (``q̈_S = 0``); the reduced system is
solved for the others, the holding torque of each stuck axis is checked against its
breakaway torque, and axes that break away slide with ``F_tr`` (one re-solve).
Integration (in the caller): semi-implicit Euler ``q̇ += h q̈; q += h q̇`` (symplectic).
"""

from __future__ import annotations

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime.drives import friction
from irlc.runtime.model.dynamics import Dynamics, MissingInertialData


class Mechanics:
    def __init__(
        self,
        model: RobotModel,
        level: str,
        rotor: np.ndarray,
        q0: np.ndarray,
        load_inertia: np.ndarray | None,
        rotor_extra=None,
        kmat: np.ndarray | None = None,
    ):
        """``rotor``: diagonal rotor inertia (joint side); ``rotor_extra(q)``: an extra
        rotor inertia matrix for coupled or non-linear transmissions (``Kᵀ diag(J_m) K``);
        ``kmat``: that transmission's Jacobian ``K(q₀)`` (decoupled in motor coordinates)."""
        self.n = model.n
        self.coupled = level in ("coupled", "pwm")
        self.rotor_extra = rotor_extra
        self.dyn = Dynamics(model, rotor_inertia=rotor) if model.inertials else None
        if self.dyn is None:
            if self.coupled:
                raise MissingInertialData(
                    f"robot {model.name} has no inertial data; --drives "
                    f"{level} needs it ([[inertials]] in the robot file)"
                )
            if load_inertia is None:
                raise MissingInertialData(
                    f"robot {model.name} has no inertial data; --drives "
                    "decoupled needs it or [drives] load_inertia"
                )
            self.diag = rotor + load_inertia
            if rotor_extra is not None:
                self.diag = self.diag + np.diag(rotor_extra(q0))
        else:
            self.diag = np.diag(self.mass_matrix(q0)).copy()
        self.decoupled = self.diag
        if not self.coupled and kmat is not None and kmat.shape == (self.n, self.n):
            full = self.mass_matrix(q0) if self.dyn is not None else np.diag(self.diag)
            k_inv = np.linalg.inv(kmat)
            motor = np.diag(k_inv.T @ full @ k_inv)
            self.decoupled = kmat.T @ (motor[:, None] * kmat)
        if np.any(self.diag <= 0.0):
            j = int(np.flatnonzero(self.diag <= 0.0)[0])
            raise MissingInertialData(
                f"robot {model.name}: joint {model.joints[j].name} has no "
                "inertia (no link mass and no rotor): cannot simulate it"
            )

    def mass_matrix(self, q) -> np.ndarray:
        """Full ``M(q)`` with every rotor (needs inertial data)."""
        m = self.dyn.mass_matrix(q)
        return m if self.rotor_extra is None else m + self.rotor_extra(q)

    def terms(self, q, qd):
        """``(M, h)``: full matrix and ``C q̇ + G`` (coupled) or diagonal and ``G`` (decoupled)."""
        if self.coupled:
            m, h = self.dyn.mass_and_bias(q, qd)
            if self.rotor_extra is not None:
                m = m + self.rotor_extra(q)
            return m, h
        g = self.dyn.gravity_vector(q) if self.dyn is not None else np.zeros(self.n)
        return self.decoupled, g

    def inverse(self, m) -> np.ndarray:
        """``M⁻¹`` (or ``1/D``), computed once per refresh of ``M`` for the common case; also
        empties the cache of reduced inverses (one per set of free axes)."""
        self._reduced: dict[bytes, np.ndarray] = {}
        return np.linalg.inv(m) if m.ndim == 2 else 1.0 / m

    def accel(self, m, h, drive, slide, stuck, static, running, prescribed, qdd_p, m_inv=None):
        """Joint accelerations, joint-side friction and the final stuck mask.

        ``drive`` T, ``slide`` sliding friction of moving axes, ``stuck`` Karnopp candidates,
        ``static``/``running`` joint-side breakaway/running torques, ``prescribed`` mask
        with accelerations ``qdd_p``; ``m_inv`` the held :meth:`inverse` of ``m``.
        """
        any_ = np.count_nonzero  # cheaper than ndarray.any on small masks
        if not any_(stuck) and not any_(prescribed):  # the common case: one product
            rhs = drive - slide - h
            if m_inv is None:
                m_inv = self.inverse(m)
            return (m_inv @ rhs if m.ndim == 2 else rhs * m_inv), slide, stuck
        if m.ndim == 2 and not any_(prescribed) and hasattr(self, "_reduced"):
            return self._karnopp(m, h, drive, slide, stuck, static, running)
        fric = np.where(stuck, 0.0, slide)
        qdd = np.where(prescribed, qdd_p, 0.0)
        for _ in range(2):
            known = prescribed | stuck
            qdd = self._solve(m, h, drive - fric, known, qdd)
            if not any_(stuck):
                break
            need = (m @ qdd if m.ndim == 2 else m * qdd) + h
            holds, held = friction.breakaway(drive - need, static, running)
            fric = np.where(stuck, held, fric)
            broke = stuck & ~holds
            if not any_(broke):
                break
            stuck = stuck & holds
            qdd = np.where(broke, 0.0, qdd)
        return qdd, fric, stuck

    def accel_driven(self, m, h, drive, slide, stuck, static, running, m_inv):
        """:meth:`accel` when every joint is driven (no prescribed joints), ``m_inv`` held."""
        if not np.count_nonzero(stuck):
            rhs = drive - slide - h
            return (m_inv @ rhs if m.ndim == 2 else rhs * m_inv), slide, stuck
        if m.ndim == 2:
            return self._karnopp(m, h, drive, slide, stuck, static, running)
        none = np.zeros(self.n, dtype=bool)
        return self.accel(m, h, drive, slide, stuck, static, running, none, np.zeros(self.n), m_inv)

    def _karnopp(self, m, h, drive, slide, stuck, static, running):
        """The Karnopp step without prescribed joints, on the held ``M``: solve the free axes
        with the stuck ones at rest (``q̈ = P_S (T − f − h)``, ``P_S`` the inverse of the free
        block ``M_ff`` embedded in an n×n zero matrix, cached with ``M P_S`` per stuck mask
        ``S`` until the next refresh); the holding torque of the stuck axes is
        ``T − h − M q̈``; stuck axes whose holding torque exceeds ``static`` break away
        (sliding with ``running``) and the free axes are solved once more — the same two
        passes as the general loop."""
        fric = slide
        base = drive - h
        n = self.n
        for _ in range(2):
            both = self._embedded_inverse(m, stuck) @ (base - fric)  # [q̈; M q̈]
            qdd = both[:n]
            need = base - both[n:]
            broke = stuck & (np.abs(need) > static)
            if not np.count_nonzero(broke):  # every stuck axis holds
                fric = np.where(stuck, need, fric)
                break
            kept = stuck ^ broke
            fric = np.where(kept, need, np.where(broke, running * np.sign(need), fric))
            stuck = kept
        return qdd, fric, stuck

    def _embedded_inverse(self, m, stuck) -> np.ndarray:
        """``[P_S; M P_S]`` (2n × n), ``P_S`` = ``M_ff⁻¹`` on the free rows and columns, zero
        elsewhere; once per stuck mask and refresh of ``M``."""
        key = stuck.tobytes()
        both = self._reduced.get(key)
        if both is None:
            free = ~stuck
            n = self.n
            both = self._reduced[key] = np.zeros((2 * n, n))
            if np.count_nonzero(free):
                both[:n][np.outer(free, free)] = np.linalg.inv(m[free][:, free]).ravel()
                np.matmul(m, both[:n], out=both[n:])
        return both

    def _solve(self, m, h, tau, known, qdd):
        if m.ndim == 1:
            return np.where(known, qdd, (tau - h) / m)
        if not np.count_nonzero(known):
            return np.linalg.solve(m, tau - h)
        free = ~known
        rhs = tau - h - m @ (qdd * known)
        out = qdd.copy()
        if np.count_nonzero(free):
            cache = getattr(self, "_reduced", None)
            if cache is None:
                out[free] = np.linalg.solve(m[free][:, free], rhs[free])
                return out
            key = b"free" + free.tobytes()
            inv = cache.get(key)
            if inv is None:  # M is held between refreshes: invert each reduced block once
                inv = cache[key] = np.linalg.inv(m[free][:, free])
            out[free] = inv @ rhs[free]
        return out

    def required(self, m, h, qdd):
        """Joint torques ``M q̈ + h`` (the torque a prescribed joint needs)."""
        return (m @ qdd if m.ndim == 2 else m * qdd) + h
