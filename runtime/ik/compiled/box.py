"""Compiled joint box of one IK cycle (numba; the package doc lists the numpy
reference of each): the signed candidates of the per-cycle box of displacements with the
braking bound ``2R/(1 + √(1 + 2R/ε))`` (``joint_box``: ``JointBox.prepare``) and the code of the
bound each joint ends on (``active_codes``: ``limits.active_codes``).
"""

from __future__ import annotations

import math

from irlc.runtime.ik.compiled.layout import BIG, TOL
from numba import njit


@njit(cache=True)
def joint_box(boxc, accel_bounded, dtol, q_start, q_prev, cand, bounds):
    """``JointBox.prepare`` without the error path: False when the state needs the
    Python check (outside the limits, or an empty box)."""
    n = q_start.shape[0]
    ok = True
    for j in range(n):
        lo_pos = boxc[0, 0, j] + q_start[j]  # θ_s − θmin
        hi_pos = boxc[0, 1, j] - q_start[j]  # θmax − θ_s
        cand[0, 0, j] = lo_pos
        cand[0, 1, j] = hi_pos
        cand[1, 0, j] = boxc[1, 0, j]
        cand[1, 1, j] = boxc[1, 1, j]
        d = q_start[j] - q_prev[j]
        if lo_pos < -TOL or hi_pos < -TOL:
            ok = False
        if -d - boxc[1, 0, j] > dtol or d - boxc[1, 1, j] > dtol:
            ok = False
        if accel_bounded:
            cand[2, 0, j] = boxc[2, 0, j] - d
            cand[2, 1, j] = boxc[2, 1, j] + d
            for side in range(2):
                room = max(cand[0, side, j], 0.0)
                b = math.sqrt(room * boxc[3, side, j] + 1.0) + 1.0
                b = room / b
                cand[3, side, j] = b + b
        else:
            for s in range(2, 4):
                cand[s, 0, j] = BIG
                cand[s, 1, j] = BIG
        lo = min(cand[0, 0, j], cand[1, 0, j])
        hi = min(cand[0, 1, j], cand[1, 1, j])
        if accel_bounded:
            lo = min(min(lo, cand[2, 0, j]), cand[3, 0, j])
            hi = min(min(hi, cand[2, 1, j]), cand[3, 1, j])
        bounds[0, j] = -lo
        bounds[1, j] = hi
        if hi + lo < 0.0:
            ok = False
    return ok


@njit(cache=True)
def active_codes(theta, q_start, bounds, cand, codes):
    """``limits.active_codes``: per joint 0 inside, else ``1 + 2·source + side`` (the
    candidate that sets the bound; a joint at both bounds counts as max); True when any
    joint is at a bound."""
    n = theta.shape[0]
    found = False
    for j in range(n):
        d = theta[j] - q_start[j]
        tol = 1e-10 + 1e-9 * abs(d)
        code = 0
        for side in range(2):
            at = d <= bounds[0, j] + tol if side == 0 else d >= bounds[1, j] - tol
            if at:
                src, best = 0, cand[0, side, j]
                for s in range(1, 4):
                    if cand[s, side, j] < best:
                        src, best = s, cand[s, side, j]
                code = 1 + 2 * src + side
        codes[j] = code
        found = found or code != 0
    return found
