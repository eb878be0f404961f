"""Position controller: proportional, motor side, output saturated (the velocity reference).

    u_ω = sat_{±U_ref}( kz · (θ_ref − θ) )      [V; ``u_ω / ke`` is the speed reference]

With the tachogenerator constant ``ke`` the position-loop gain is ``K_v = kz / ke``
[1/s]; the steady following error at motor speed ``ω`` is ``ω / K_v``.
"""

from __future__ import annotations

import numpy as np


def position_p(kz, theta_ref, theta, limit) -> tuple[np.ndarray, np.ndarray]:
    """Velocity reference (V) and the per-axis saturation flag."""
    raw = kz * (theta_ref - theta)
    out = np.minimum(np.maximum(raw, -limit), limit)  # np.clip, cheaper on small arrays
    return out, out != raw
