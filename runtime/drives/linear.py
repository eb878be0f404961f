"""The linearised single-axis loop (no saturation, no friction), motor side, for the
stability analysis and as the analytic reference of the simulated step response.

States ``x = [θ, ω, i, u, x_v]`` (angle, speed, armature current, armature voltage,
velocity-PI integral), input ``θ_ref``, inertia ``J`` (rotor + reflected load), viscous
``b``::

    θ̇   = ω
    J ω̇ = k_s i − b ω
    L i̇ = u − R i − k_s ω
    u̇   = kiwzm (kp e + ki x_v − k i),   e = kz (θ_ref − θ) − ke ω
    ẋ_v = e

Loop margins: the velocity loop is opened at the tachogenerator (input: the feedback
signal injected, output ``ke ω``), the position loop at ``θ`` (output ``kz θ`` vs the
injected error). Phase margin ``180° + ∠L(jω_c)`` at ``|L(jω_c)| = 1``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import signal


@dataclass(frozen=True)
class AxisLoop:
    ke: float
    kp: float
    ki: float
    kz: float
    R: float
    L: float
    ks: float
    k: float
    kiwzm: float
    J: float
    b: float = 0.0


def _matrices(a: AxisLoop, kz: float, ke: float):
    big_a = np.array(
        [
            [0.0, 1.0, 0.0, 0.0, 0.0],
            [0.0, -a.b / a.J, a.ks / a.J, 0.0, 0.0],
            [0.0, -a.ks / a.L, -a.R / a.L, 1.0 / a.L, 0.0],
            [-a.kiwzm * a.kp * kz, -a.kiwzm * a.kp * ke, -a.kiwzm * a.k, 0.0, a.kiwzm * a.ki],
            [-kz, -ke, 0.0, 0.0, 0.0],
        ]
    )
    return big_a


def closed_loop(a: AxisLoop) -> signal.StateSpace:
    """``θ_ref → θ`` (the full cascade)."""
    big_a = _matrices(a, a.kz, a.ke)
    b = np.array([[0.0], [0.0], [0.0], [a.kiwzm * a.kp * a.kz], [a.kz]])
    c = np.array([[1.0, 0.0, 0.0, 0.0, 0.0]])
    return signal.StateSpace(big_a, b, c, np.zeros((1, 1)))


def poles(a: AxisLoop) -> np.ndarray:
    return np.linalg.eigvals(_matrices(a, a.kz, a.ke))


def open_velocity_loop(a: AxisLoop) -> signal.StateSpace:
    """Loop broken at the tacho: input ``y`` replaces ``ke ω`` in ``e``; output ``ke ω``."""
    big_a = _matrices(a, 0.0, 0.0)
    b = np.array([[0.0], [0.0], [0.0], [-a.kiwzm * a.kp], [-1.0]])
    c = np.array([[0.0, -a.ke, 0.0, 0.0, 0.0]])  # sign: negative feedback → L = −G
    return signal.StateSpace(big_a, b, c, np.zeros((1, 1)))


def open_position_loop(a: AxisLoop) -> signal.StateSpace:
    """Loop broken at ``θ``: input the position error, output ``θ`` (velocity loop closed)."""
    big_a = _matrices(a, 0.0, a.ke)
    b = np.array([[0.0], [0.0], [0.0], [a.kiwzm * a.kp * a.kz], [a.kz]])
    c = np.array([[1.0, 0.0, 0.0, 0.0, 0.0]])
    return signal.StateSpace(big_a, b, c, np.zeros((1, 1)))


def frequency_response(sys: signal.StateSpace, w: np.ndarray) -> np.ndarray:
    """``C (jωI − A)⁻¹ B + D`` of a single-input single-output system (no polynomial form)."""
    eye = np.eye(sys.A.shape[0])
    mats = 1j * w[:, None, None] * eye - sys.A
    x = np.linalg.solve(mats, np.broadcast_to(sys.B, (len(w), *sys.B.shape)))
    return (sys.C @ x)[:, 0, 0] + sys.D[0, 0]


def margins(loop: signal.StateSpace) -> tuple[float, float, float]:
    """``(phase margin deg, crossover rad/s, gain margin dB)`` of an open loop ``L``
    (closed loop ``L/(1+L)``); the phase is unwrapped from 0.01 rad/s."""
    w = np.logspace(-2, 6, 40000)
    resp = frequency_response(loop, w)
    mag = np.abs(resp)
    ph = np.degrees(np.unwrap(np.angle(resp)))
    ph -= 360.0 * np.ceil(ph[0] / 360.0)  # low-frequency phase in (−360, 0]
    cross = np.flatnonzero((mag[:-1] >= 1.0) & (mag[1:] < 1.0))
    if cross.size == 0:
        return float("inf"), float("nan"), float("inf")
    k = int(cross[-1])
    down = np.flatnonzero((ph[:-1] > -180.0) & (ph[1:] <= -180.0))
    down = down[down > k]
    gm = float(-20.0 * np.log10(mag[down[0]])) if down.size else float("inf")
    return float(180.0 + ph[k]), float(w[k]), gm
