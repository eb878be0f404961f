"""Manipulator velocity ratio, ``R_CRITERION := 'MVR'`` (seed chapter 7; [Dubey & Luh 1988]).

The velocity ratio of a motion is the TCP's speed per unit of joint speed,

    MVR = r_v = ‖ẋ‖_Wx / ‖θ̇‖_Wθ,        ‖a‖_W = (aᵀWa)^½,

large where little joint motion moves the TCP far, small near a singular configuration
(the joints race for a slow TCP). The seed maximises it by minimising ``MVR⁻²``, which it
brings to the quadratic form (40a) (seed eq. 40) with the *mean* speeds over one IPO cycle:
the Cartesian ``ẋ = Δx/Δt`` (``Δx`` the cycle's commanded TCP displacement, fixed by the
interpolator) and the joint ``θ̇ = (Δθ + Σ)/Δt`` (``Σ = θ_k − θ_s`` the cycle's
displacement before Newton iteration ``k``)::

    MVR⁻² = (Δθ + Σ)ᵀ Wθ (Δθ + Σ) / (Δxᵀ Wx Δx)
          = ΔθᵀWθΔθ/c + 2 ΣᵀWθΔθ/c + ΣᵀWθΣ/c,       c = ΔxᵀWxΔx   (Δt² cancels)
    →  in ``gᵀΔθ + ½ΔθᵀHΔθ``:  g = 2WθΣ/c,  H = 2Wθ/c   (the last term is constant)

What this means: ``c`` is fixed in the cycle, so the seed's MVR criterion is the
``Wθ``-norm of the cycle's joint displacement scaled by ``2/c``; its minimiser is the
``Wθ``-least-norm step that reaches the cycle's target, i.e. the step with the highest
velocity ratio this cycle can have from where it starts. It is greedy, one cycle at a
time: Dubey and Luh's own method — raising the *configuration's* ratio along the
direction of motion by a null-space gradient, so that later cycles find a better
configuration — is not in the seed and not here (docs/references.md).

**Weights.** ``Wθ = I`` (SI: rad and m) and ``Wx = I`` on the controlled task rows (m, rad),
the unweighted ratio of [Dubey & Luh 1988]. With ``Wθ`` the robot's redundancy weights
``W`` the criterion would be DISTANCE itself (the same minimiser); ``Wθ = I`` makes it the
unweighted minimum-norm (pseudoinverse) step, where DISTANCE is the ``W``-weighted one. The
trace's ``mvr`` column is this ratio with the same weights
(:func:`velocity_ratio`), so the criterion maximises, cycle by cycle, what it reports.

**Scale.** As for ENERGY (:mod:`~irlc.runtime.ik.energy`), a positive factor does not
change the minimiser; the criterion is used with the weights
``ŵ = Wθ·Σw/tr Wθ`` (``g = ŵ∘Σ``, ``H = diag(ŵ)``) — the seed's terms times
``κ = c·Σw/(2n)`` — which have the trace of ``W`` (so that the obstacles' ``a_obst`` and
``a_conf`` weigh it as they weigh ``W``) and need no ``c``: the seed's form is undefined
where the TCP stands still (``c = 0``: RECONFIGURATION, the cycles of a stop), ours is
not. ``H`` stays diagonal, so MVR runs on the diagonal fast path and the compiled kernel's
diagonal weights.
"""

from __future__ import annotations

import numpy as np


def joint_weights(weights: np.ndarray) -> np.ndarray:
    """``ŵ = Σw/n`` for every joint: ``Wθ = I`` scaled to the trace of ``W`` (module doc)."""
    w = np.asarray(weights, dtype=float)
    return np.full(w.shape, float(np.sum(w)) / w.size)


def seed_terms(sigma: np.ndarray, dx: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The seed's ``g = 2WθΣ/c`` and ``H = 2Wθ/c`` (``Wθ = Wx = I``, ``c = ΔxᵀΔx``; for
    tests: the criterion's terms are these times ``κ``, module doc)."""
    c = float(np.dot(dx, dx))
    return 2.0 * np.asarray(sigma, dtype=float) / c, 2.0 * np.eye(len(sigma)) / c


def velocity_ratio(task_speed: np.ndarray, joint_speed: np.ndarray) -> np.ndarray:
    """``r_v = ‖ẋ‖/‖θ̇‖`` per row (``(k, m)`` task speeds in m/s and rad/s, ``(k, n)``
    joint speeds in rad/s and m/s; ``Wx = Wθ = I``); 0 where the joints stand still (no
    motion, no ratio)."""
    num = np.sqrt(np.einsum("ij,ij->i", task_speed, task_speed))
    den = np.sqrt(np.einsum("ij,ij->i", joint_speed, joint_speed))
    out = np.zeros(len(den))
    moving = den > 0.0
    out[moving] = num[moving] / den[moving]
    return out
