"""The robot model: what a robot description file (TOML or URDF) loads into. SI units.

A robot is a serial chain of ``n`` joints. Link ``i`` (1-based, 1..n) is the body moved
by joint ``i``; link 0 is the robot base. Frames:

* ``base``: pose of the robot's base frame in the world (4×4).
* joint ``i``: ``origin`` is the pose of joint ``i``'s frame in link ``i−1``'s frame at
  zero motion; the joint then rotates about (revolute) or slides along (prismatic)
  its unit ``axis``, given in that frame. The moved frame is link ``i``'s frame:
  ``T_i = T_{i−1} · origin_i · M_i(q_i + offset_i)``.
* ``flange``: pose of the flange in link ``n``'s frame; ``tool``: the TCP in the flange
  frame (the program may change it through ``R_TOOL``).

Standard DH rows (``A_i = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i)``) map onto this form with
axis ``z``: ``origin_1 = I``, ``origin_{i+1} = Tz(d_i) Tx(a_i) Rx(α_i)`` and the last
row's fixed part becomes ``flange``.

Joint coordinates ``q`` are the *user* coordinates (after any redefinition such as the
IRb-6 offsets); the kinematic angle is ``q + offset``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

JointKind = Literal["revolute", "prismatic"]
# The pose-error components in error-vector order: a robot file's ``[ik] task`` names the
# ones the inverse transformation controls (extra["ik"]["task"]; default all six).
TASK_COMPONENTS = ("x", "y", "z", "rx", "ry", "rz")


@dataclass(frozen=True)
class Limits:
    """Per-joint bounds in SI: positions (rad | m), speeds (/s), accelerations (/s²) and,
    where the robot file gives it, the jerk ``|θ⃛| ≤ jerk`` (/s³; ``None``: not known, the
    S-curve derives one — docs/runtime.md)."""

    position: tuple[float, float]
    speed: tuple[float, float]
    accel: tuple[float, float]
    jerk: float | None = None


@dataclass(frozen=True)
class Joint:
    name: str
    kind: JointKind
    origin: np.ndarray  # 4×4
    axis: np.ndarray  # unit 3-vector in the joint frame
    limits: Limits
    offset: float = 0.0
    weight: float = 1.0  # redundancy weight w_i (H = W = diag(w))


@dataclass(frozen=True)
class Capsule:
    """Segment ``a``–``b`` swept by a sphere of ``radius``; points in link frame, m."""

    link: int
    a: np.ndarray
    b: np.ndarray
    radius: float


@dataclass(frozen=True)
class Sphere:
    link: int
    center: np.ndarray
    radius: float


@dataclass(frozen=True)
class Inertial:
    """Rigid-body parameters of one link, in the link frame (kg, m, kg·m²)."""

    link: int
    mass: float
    com: np.ndarray  # 3
    inertia: np.ndarray  # 3×3 about the centre of mass
    assumed: bool = False


@dataclass(frozen=True)
class RobotModel:
    name: str
    joints: tuple[Joint, ...]
    base: np.ndarray = field(default_factory=lambda: np.eye(4))
    flange: np.ndarray = field(default_factory=lambda: np.eye(4))
    tool: np.ndarray = field(default_factory=lambda: np.eye(4))
    home: np.ndarray | None = None  # SI, user coordinates
    gravity: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, -9.81]))
    geometry: tuple[Capsule | Sphere, ...] = ()
    inertials: tuple[Inertial, ...] = ()
    # Named limit sets a program may refer to (e.g. koch11's chapter-6 sets):
    # name → Limits per joint.
    limit_sets: dict[str, tuple[Limits, ...]] = field(default_factory=dict)
    # Coupled limits, drives, joint↔motor maps and the rest of the file: typed by the
    # modules that use them (loader validates), kept here as parsed tables.
    extra: dict[str, Any] = field(default_factory=dict)
    source: str = ""
    description: str = ""

    # --- the signature the language checker needs (lang's RobotSignature protocol) ---
    @property
    def n(self) -> int:
        return len(self.joints)

    @property
    def joint_count(self) -> int:
        return len(self.joints)

    @property
    def joint_names(self) -> tuple[str, ...]:
        return tuple(j.name for j in self.joints)

    @property
    def joint_kinds(self) -> tuple[str, ...]:
        return tuple(j.kind for j in self.joints)

    @property
    def platform(self) -> Any:
        """The robot's platform (:class:`irlc.robots.platform.Platform`, the file's
        ``[platform]``; lang's ``PlatformSignature``), ``None`` when it names none."""
        return self.extra.get("platform") if isinstance(self.extra, dict) else None

    @property
    def missing_inertia(self) -> str | None:
        """What the links' inertial data lack for the joint-space inertia matrix ``M(θ)``
        (``R_CRITERION := 'ENERGY'``, the trace's kinetic energy), or ``None`` when every
        joint moves a link with mass (prismatic) or with mass or rotational inertia
        (revolute). Rotor inertia does not count: ``M`` is the links' own."""
        where = self.source or "the robot file"
        if not self.inertials:
            return f"robot {self.name} has no [[inertials]] ({where})"
        mass = np.zeros(self.n + 1)
        spin = np.zeros(self.n + 1)
        for inertial in self.inertials:
            if 0 <= inertial.link <= self.n:
                mass[inertial.link] += inertial.mass
                spin[inertial.link] += float(np.trace(inertial.inertia))
        for i, joint in enumerate(self.joints):  # joint i+1 moves links i+1 … n
            moved = mass[i + 1 :].sum() + (spin[i + 1 :].sum() if joint.kind == "revolute" else 0)
            if moved <= 0.0:
                return (
                    f"robot {self.name}: joint {joint.name} moves no link with mass or "
                    f"inertia ([[inertials]] of links {i + 1}…{self.n} in {where})"
                )
        return None

    # --- convenience arrays (SI) ---
    @property
    def weights(self) -> np.ndarray:
        return np.array([j.weight for j in self.joints])

    @property
    def position_limits(self) -> np.ndarray:
        """``(n, 2)`` array of [min, max]."""
        return np.array([j.limits.position for j in self.joints])

    @property
    def speed_limits(self) -> np.ndarray:
        return np.array([j.limits.speed for j in self.joints])

    @property
    def accel_limits(self) -> np.ndarray:
        return np.array([j.limits.accel for j in self.joints])

    @property
    def jerk_limits(self) -> np.ndarray:
        """``(n,)`` jerk bounds (/s³), NaN where the robot file gives none."""
        return np.array([np.nan if j.limits.jerk is None else j.limits.jerk for j in self.joints])

    def home_q(self) -> np.ndarray:
        return np.zeros(self.n) if self.home is None else np.array(self.home, dtype=float)
