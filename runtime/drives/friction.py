"""Stick–slip friction on the motor side [Karnopp 1985], with viscous friction.

Sliding (``|ω| ≥ δ``):   τ_f = F_tr·sign(ω) + k_v·ω
Sticking (``|ω| < δ``):  the axis holds (``ω := 0``) while the torque ``τ_s`` needed to
keep it at rest satisfies ``|τ_s| ≤ F_ts``; then ``τ_f = τ_s``. Otherwise it breaks away
and slides with ``τ_f = F_tr·sign(τ_s)``.

``δ`` (Karnopp's zero-velocity band) is the speed one step of the breakaway torque
gives the axis: ``δ = 2 h F_ts / J`` — below it the sign of ``ω`` is numerical noise.
"""

from __future__ import annotations

import numpy as np


def sliding(omega, running, viscous) -> np.ndarray:
    return running * np.sign(omega) + viscous * omega


def breakaway(needed, static, running) -> tuple[np.ndarray, np.ndarray]:
    """For stuck candidates: (holds, friction torque) given the holding torque needed."""
    holds = np.abs(needed) <= static
    return holds, np.where(holds, needed, running * np.sign(needed))


def band(step: float, static, inertia) -> np.ndarray:
    return 2.0 * step * static / inertia
