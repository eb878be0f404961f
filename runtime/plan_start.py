"""Where a Cartesian motion is planned from: the programmed point, not the round-off.

After an exact stop the robot stands at the configuration the inverse transformation
found for the last point, whose TCP differs from the programmed point by the solver's
residual (about 1e-9 m, different with and without CYCLIC, FREEZE, …). Planning the next
LIN or CIRCLE from that *actual* pose makes its length, and so its time
``T = ⌈T_trap(L)/Δt⌉·Δt``, depend on the residual: a segment whose closed-form time is a
whole number of cycles gains one cycle when ``L`` grows by 1e-9 m (two laps of the koch11
square took 2564 samples with CYCLIC and 2560 without).

The rule: the next Cartesian segment starts at the **programmed** previous point (world
frame, the same tool) when the actual TCP agrees with it within the path tolerance
(``R_PATH_TOL`` and the orientation tolerance, on the rows the task controls); otherwise
(a tool changed, a relaxed stop further off, a PTP or RECONFIGURATION in between) at the
actual pose. Within the tolerance the robot is *on* the point by the run's own
definition, and the first cycle of the new segment removes the residual as every cycle
removes its own. The segment's geometry, length and cycle count are then those of the
program alone: the same program and options give the same sample count whatever the
redundancy criterion.
"""

from __future__ import annotations

import numpy as np
from irlc.runtime import spatial


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
