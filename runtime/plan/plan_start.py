"""Where a Cartesian motion is planned from: the programmed point, not the round-off.

After an exact stop the robot stands at the configuration the inverse transformation
found for the last point, whose TCP differs from the programmed point by the solver's
residual (about 1e-9 m, different with and without CYCLIC, FREEZE, …). Planning the next
LIN or CIRCLE from that *actual* pose makes its length, and so its time
``T = ⌈T_trap(L)/Δt⌉·Δt``, depend on the residual: a segment whose closed-form time is a
whole number of cycles gains one cycle when ``L`` grows by 1e-9 m (two laps of the koch11
square took 2564 samples with CYCLIC and 2560 without).

The rule: the next Cartesian segment starts at the **programmed** previous point (world
frame, the same tool) when the actual TCP agrees with it within the round-off bound
``ROUND_OFF`` × the inverse transformation's convergence tolerance (1e-9 m, 1e-9 rad →
1 µm, 1 µrad; never more than ``R_PATH_TOL`` and the orientation tolerance), on the
rows the task controls; otherwise (a tool changed, a relaxed stop that ended off the
point, a joint move in between) at the actual pose. Below that bound the difference is
the solver's residual, and the first cycle of the new segment removes it as every cycle
removes its own (a 1 µm correction in one 10 ms cycle: 0.1 mm/s). A larger, real
deviation (a relaxed stop within a wide ``R_PATH_TOL``) keeps the old behaviour: the
segment starts where the robot is, without a jump back to the programmed point.
With a residual-sized offset the segment's geometry, length and cycle count are those of
the program alone: the same program and options give the same sample count whatever the
redundancy criterion.
"""

from __future__ import annotations

import numpy as np
from irlc.runtime.model import spatial

ROUND_OFF = 1e3  # × the IK convergence tolerance: below this a TCP offset is residual


def planning_start(
    actual: np.ndarray,
    programmed: np.ndarray | None,
    rows: tuple[int, ...],
    tol_position: float,
    tol_orientation: float,
) -> np.ndarray:
    """``programmed`` (4×4, SI) when it agrees with ``actual`` within the tolerances on
    the controlled ``rows`` of the pose error (0–2 position, 3–5 rotation vector), else
    ``actual`` (a copy either way)."""
    if programmed is None:
        return actual.copy()
    e = spatial.pose_error(actual, programmed)
    pos = [r for r in rows if r < 3]
    ori = [r for r in rows if r >= 3]
    if np.linalg.norm(e[pos]) <= tol_position and np.linalg.norm(e[ori]) <= tol_orientation:
        return programmed.copy()
    return actual.copy()
