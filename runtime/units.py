"""The one place where program units (mm, deg, s) meet SI units (m, rad, s).

Programs, data lists, IRDATA operands, CLI arguments and user-facing outputs use
millimetres and degrees; everything inside the runtime uses metres and radians.
Joint values depend on the joint kind: revolute joints are in degrees, prismatic
joints in millimetres.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from irlc.lang.joint_kinds import PRISMATIC as PRISMATIC  # the joint kinds' owner
from irlc.lang.joint_kinds import REVOLUTE as REVOLUTE
from irlc.runtime.model import spatial

MM = 1e-3  # metres per millimetre
DEG = math.pi / 180.0  # radians per degree

# Below this magnitude a value in program units (mm, deg, s and their rates) is
# round-off of a zero (a 1e-16 relative error on a 1e3-scale quantity, a sum of
# conversions) and is shown as 0: no "1.99e-32 deg", no "-0.0000".
SNAP = 5e-13


def shown(value: float, unit: float = 1.0) -> float:
    """``value`` (program units) as a user sees it: 0.0 when ``|value| < SNAP·unit``
    (``unit`` scales the threshold for a quantity whose natural size differs, e.g. a
    value in SI metres: ``unit = MM``), never a negative zero; non-finite values pass."""
    v = float(value)
    if abs(v) < SNAP * unit:
        return 0.0
    return v + 0.0


def fixed(value: float, decimals: int) -> str:
    """``value`` with ``decimals`` fixed decimals, snapped (:func:`shown`) and without a
    negative zero after rounding (``-0.00004`` → ``"0.0000"``)."""
    return f"{shown(round(shown(value), decimals)):.{decimals}f}"


def seconds_text(seconds: float) -> str:
    """A duration for a message: ``"12.5 s"`` (6 significant digits), or ``"longer than
    any finite time"`` when it overflowed (a message never shows ``inf`` or ``nan``)."""
    return f"{seconds:.6g} s" if math.isfinite(seconds) else "longer than any finite time"


def joint_scale(kinds: Sequence[str]) -> np.ndarray:
    """Per-joint factor from program units to SI (deg → rad, mm → m)."""
    return np.array([DEG if k == REVOLUTE else MM for k in kinds])


def joints_to_si(values: Sequence[float], kinds: Sequence[str]) -> np.ndarray:
    return np.asarray(values, dtype=float) * joint_scale(kinds)


def joints_from_si(values: Sequence[float], kinds: Sequence[str]) -> np.ndarray:
    return np.asarray(values, dtype=float) / joint_scale(kinds)


def joint_unit(kind: str, derivative: int = 0) -> str:
    """Unit label of a joint quantity: ``deg``, ``deg_s``, ``deg_s2`` / ``mm``, ..."""
    base = "deg" if kind == REVOLUTE else "mm"
    return base + ("", "_s", "_s2")[derivative]


def joint_unit_label(kind: str, derivative: int = 0) -> str:
    """Display form of :func:`joint_unit` for messages: ``deg``, ``deg/s``, ``mm/s²``."""
    base = "deg" if kind == REVOLUTE else "mm"
    return base + ("", "/s", "/s²")[derivative]


def pose_to_si(
    x: float, y: float, z: float, a: float, b: float, c: float, euler: str = "zyx"
) -> np.ndarray:
    """Program pose (mm, deg, ZYX — or ``euler="zyz"``: Φ, Θ, Ψ) → 4×4 transform in metres."""
    to_matrix = spatial.EULER[euler][0]
    return spatial.transform(to_matrix(a * DEG, b * DEG, c * DEG), (x * MM, y * MM, z * MM))


def pose_from_si(
    t: np.ndarray, euler: str = "zyx"
) -> tuple[float, float, float, float, float, float]:
    """4×4 transform in metres → program pose (mm, deg, ZYX — or ``euler="zyz"``)."""
    a, b, c = spatial.EULER[euler][1](t[:3, :3])
    x, y, z = (float(v) / MM for v in t[:3, 3])
    return (x, y, z, a / DEG, b / DEG, c / DEG)
