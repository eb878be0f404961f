"""Small robot models built in code for the drive tests (no robot files needed)."""

from __future__ import annotations

import numpy as np
from irlc.robots.model import Inertial, Joint, Limits, RobotModel
from irlc.runtime.model import spatial

LIM = Limits((-3.0, 3.0), (-2.0, 2.0), (-10.0, 10.0))

# The measured IRb-6 axis-1 chain (robots.md) with the project's assumed kz and J_m.
DC_AXIS = {
    "ke": 0.105,
    "kp": 32.02,
    "ki": 267.01,
    "kz": 3.15,
    "R": 3.053,
    "L": 2.3e-3,
    "ks": 0.105,
    "k": 0.42,
    "kiwzm": 1668.4,
    "i_max": 10.0,
    "U": 50.0,
    "J_m": 3e-3,
}


def planar(
    n: int = 2,
    link: float = 0.5,
    mass: float = 4.0,
    gravity=(0.0, -9.81, 0.0),
    drives: dict | None = None,
    prismatic: tuple[int, ...] = (),
) -> RobotModel:
    """Planar arm in the x–y plane (axes z), links along x; gravity −y by default."""
    joints, inertials = [], []
    for i in range(n):
        kind = "prismatic" if i in prismatic else "revolute"
        axis = np.array([1.0, 0.0, 0.0]) if kind == "prismatic" else np.array([0.0, 0.0, 1.0])
        origin = spatial.transform(None, (link if i else 0.0, 0.0, 0.0))
        joints.append(Joint(f"a{i + 1}", kind, origin, axis, LIM))
        r = 0.03
        inertia = np.diag([0.5 * mass * r * r, mass * link**2 / 12, mass * link**2 / 12])
        inertials.append(Inertial(i + 1, mass, np.array([link / 2, 0.0, 0.0]), inertia))
    extra = {} if drives is None else {"drives": drives}
    return RobotModel(
        "planar_test",
        tuple(joints),
        gravity=np.array(gravity, float),
        inertials=tuple(inertials),
        extra=extra,
        source="<test model>",
    )


def dc_drives(n: int, ratio: float = 30.0, **over) -> dict:
    chain = dict(DC_AXIS)
    chain.update(over)
    return {"type": "dc", "ratio": ratio, "dc": chain}


# The L-1's axis 1–3 stepper (robots.md), with an assumed rotor inertia.
STEPPER_AXIS = {
    "R": 1.0,
    "L": 2.2e-3,
    "L12": 1.97e-3,
    "psi_max": 6.3e-3,
    "I": 4.8,
    "M_max": 1.5,
    "teeth": 50.0,
    "step_rate": 2.5 * 3.141592653589793,
    "J_m": 4.8e-5,
}


def stepper_drives(ratio: float = 10.0, **over) -> dict:
    chain = dict(STEPPER_AXIS)
    chain.update(over)
    return {"type": "stepper", "ratio": ratio, "stepper": chain}
