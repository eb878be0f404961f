"""The task error ``f(θ) ⊖ x`` of :func:`spatial.pose_error`, on Python floats (hot path).

``f(θ) ⊖ x = [p − p_d ; log(R·R_dᵀ)^∨]``. Only the trace and the skew part of
``M = R·R_dᵀ`` are needed away from a half turn::

    cos φ = (tr M − 1)/2,   w = (M21 − M12, M02 − M20, M10 − M01),
    log(M)^∨ = w/2 (φ < 1e-6),   φ/(2 sin φ)·w (otherwise)

which are 9 + 18 products of Python floats — cheaper than the numpy calls of the
general function for one 4×4 pose. Within ``1e-4`` rad of a half turn the axis comes
from the symmetric part: there :func:`spatial.pose_error` itself is called. Same
formulas and branches as :func:`spatial.rotation_vector`, so the result agrees with it
to rounding (tested).
"""

from __future__ import annotations

import math

import numpy as np
from irlc.runtime.model import spatial


def pose_error_list(tcp: np.ndarray, rd: tuple, pd: tuple, target: np.ndarray) -> list[float]:
    """``spatial.pose_error(tcp, target)`` as a list of six floats; ``rd``/``pd`` are the
    rows of ``target``'s rotation and its position (``target.tolist()`` parts)."""
    r0, r1, r2, _ = tcp.tolist()
    d0, d1, d2 = rd
    a0, a1, a2 = r0[0], r0[1], r0[2]
    b0, b1, b2 = r1[0], r1[1], r1[2]
    c0, c1, c2 = r2[0], r2[1], r2[2]
    trace = (
        a0 * d0[0]
        + a1 * d0[1]
        + a2 * d0[2]
        + b0 * d1[0]
        + b1 * d1[1]
        + b2 * d1[2]
        + c0 * d2[0]
        + c1 * d2[1]
        + c2 * d2[2]
    )
    # M_ij = row i of R · row j of R_d
    w0 = (c0 * d1[0] + c1 * d1[1] + c2 * d1[2]) - (b0 * d2[0] + b1 * d2[1] + b2 * d2[2])
    w1 = (a0 * d2[0] + a1 * d2[1] + a2 * d2[2]) - (c0 * d0[0] + c1 * d0[1] + c2 * d0[2])
    w2 = (b0 * d0[0] + b1 * d0[1] + b2 * d0[2]) - (a0 * d1[0] + a1 * d1[1] + a2 * d1[2])
    cos_t = max(-1.0, min(1.0, (trace - 1.0) / 2.0))
    theta = math.acos(cos_t)
    if theta < 1e-6:
        k = 0.5
    elif math.pi - theta > 1e-4:
        k = theta / (2.0 * math.sin(theta))
    else:  # near a half turn: the general formula (axis from the symmetric part)
        return spatial.pose_error(tcp, target).tolist()
    return [r0[3] - pd[0], r1[3] - pd[1], r2[3] - pd[2], k * w0, k * w1, k * w2]
