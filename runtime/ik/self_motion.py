"""Self-motion RECONFIGURATION k (seed 4.2.3): move the joints towards ``k``, keep the TCP.

The cost is the cyclic one (:class:`~irlc.runtime.ik.cyclic.CyclicReference`) with
``θ⁰ := k`` (``g = W(θ_k − k)``, ``H = W``), and in the *first* Newton iteration of every
cycle the task residual is set to ``F := 0`` (in the Newton loop) so the first step is a
pure null-space motion; later iterations pull the TCP back onto the held pose (removing
the linearisation error). The joint box keeps each cycle's change small.

If ``k`` is not compatible with the held pose the arm gets as close to ``k`` as the
weighted criterion allows. The statement ends when the configuration stops changing:
``‖θ(t) − θ(t − Δt)‖ < ε_conf`` (seed 4.2.3) — decided by the caller with
:func:`reconfiguration_done`; the executor passes the configuration two cycles back as
well (the two-cycle rule, a departure from the seed, see there and docs/ik.md).
"""

from __future__ import annotations

import numpy as np


def reconfiguration_done(
    q: np.ndarray, q_prev: np.ndarray, eps_conf: float, q_prev2: np.ndarray | None = None
) -> bool:
    """True when the last cycle changed the configuration by less than ``eps_conf``
    (Euclidean norm over all joints, SI) — and, if ``q_prev2`` (one more cycle back) is
    given, the cycle before too.

    The second condition is our addition: with acceleration limits the joints may
    overshoot ``k`` and reverse, passing through zero speed for one cycle; one small
    change alone would end the statement there, away from ``k``."""
    done = float(np.linalg.norm(np.asarray(q) - np.asarray(q_prev))) < eps_conf
    if done and q_prev2 is not None:
        done = float(np.linalg.norm(np.asarray(q_prev) - np.asarray(q_prev2))) < eps_conf
    return done
