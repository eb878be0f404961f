"""The ENERGY criterion's metric for the compiled cycle (numba): ``Ĝ(θ) = M(θ)·Σw/tr M(θ)``
scaled by the term's weight — :class:`~irlc.runtime.ik.energy.InertiaMetric` on packed
data. The links' ``M`` comes from the drives' kernel :func:`mass_and_bias` (the Jacobian
form of :meth:`Dynamics.mass_and_bias`; the bias it also computes is not used) on the link
frames of :func:`forward_chain` (``Kinematics.chain_data``), with the rotor inertia left
out (the :class:`DynamicsData` of ``Dynamics(model)``: ``rotor = 0``).

numba keys the cache of :func:`inertia_metric` by this file only, while its machine code
includes the two kernels it calls: :data:`CALLEES_DIGEST` is the digest of their modules
(:func:`callees_digest`, checked by tests/ik/test_compiled_sources_digest.py), so a change
there changes this file and with it the cache key.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

from irlc.runtime.drives.compiled.kernels import mass_and_bias
from irlc.runtime.ik.compiled.chain import forward_chain
from numba import njit

CALLEES_DIGEST = "106bd77d5f34f838"  # callees_digest() when this file was last updated


CALLEES = ("ik/compiled/chain.py", "drives/compiled/kernels.py")  # under runtime/


def callees_digest() -> str:
    """SHA-256 (first 16 hex digits) of the sources of :data:`CALLEES`, in that order:
    the modules of :func:`forward_chain` and :func:`mass_and_bias`."""
    runtime = Path(__file__).resolve().parents[2]
    h = hashlib.sha256()
    for name in CALLEES:
        h.update((runtime / name).read_bytes())
    return h.hexdigest()[:16]


@njit(cache=True)
def inertia_metric(chain, dyn, q, weight_sum, scale, buf, out):
    """``out = scale·M(q)·weight_sum/tr M(q)`` (``M`` the links' inertia matrix);
    ``chain = (basis, joints, base)`` (:class:`ChainData`), ``dyn`` the seven arrays of
    :class:`DynamicsData` (rotor zero), ``buf = (frames (n+1, 4, 4), local (4, 4),
    zero speeds (n,), bias (n,))``."""
    basis, joints, base = chain
    axes, revolute, rotor, mass, com, inertia, gravity = dyn
    frames, local, qd, bias = buf
    forward_chain(basis, joints, base, q, frames, local)
    mass_and_bias(frames, axes, revolute, rotor, mass, com, inertia, gravity, qd, out, bias)
    n = q.shape[0]
    trace = 0.0
    for i in range(n):
        trace += out[i, i]
    factor = scale * (weight_sum / trace)
    for i in range(n):
        for j in range(n):
            out[i, j] *= factor
