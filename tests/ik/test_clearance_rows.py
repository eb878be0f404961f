"""R_CLEARANCE's QP rows (runtime/ik/clearance.py): each row is the first-order change of its
pair's distance (finite differences of the exact distance), its bound the velocity damper, and
an inverse transformation with the rows stops a self-motion at the clearance that runs into an
obstacle robot's part without them."""

from __future__ import annotations

import numpy as np
import pytest
from irlc.robots import load_robot
from irlc.runtime.ik.clearance import DAMPING, MARGIN, ClearanceRows, ClearanceSpec, Neighbours
from irlc.runtime.ik.newton import InverseTransformation
from irlc.runtime.ik.params import CycleOptions, IKParams
from irlc.runtime.model.chain import SerialChain
from irlc.runtime.model.distance import closest_segment_segment


def _sphere(center, radius: float) -> Neighbours:
    c = np.asarray(center, dtype=float)[None, :]
    return Neighbours(c, c.copy(), np.zeros((1, 3)), np.zeros((1, 3)), np.array([radius]),
                      ("other",), np.array([1]))  # fmt: skip


def _pair_distance(rows: ClearanceRows, theta, pair, nb: Neighbours | None) -> float:
    """The exact distance of a row's pair at ``theta`` (segment–segment of the cores)."""
    parts = rows.parts
    a, b = parts.world([rows.chain.world_frames(theta)])
    i, j = pair
    if j >= 0:
        p0, p1, q0, q1, r = a[i], b[i], a[j], b[j], parts.radius[j]
    else:
        j = -1 - j
        p0, p1, q0, q1, r = a[i], b[i], nb.a[j], nb.b[j], nb.radius[j]
    _, _, p, q = closest_segment_segment(p0, p1, q0, q1)
    return float(np.linalg.norm(p - q)) - parts.radius[i] - r


def test_rows_are_the_distance_gradient_and_the_damped_bound():
    panda = load_robot("panda")
    chain = SerialChain(panda)
    rng = np.random.default_rng(3)
    q = panda.home_q() + rng.normal(scale=0.2, size=7)
    elbow = chain.world_frames(q)[4][:3, 3]
    nb = _sphere(elbow + np.array([0.0, 0.0, 0.15]), 0.02)
    rows = ClearanceRows(chain)
    rows.prepare(ClearanceSpec(0.05, lambda: nb), q)
    assert len(rows) and any(j < 0 for _, j in rows.pairs) and any(j >= 0 for _, j in rows.pairs)
    for r, pair in enumerate(rows.pairs):
        d0 = _pair_distance(rows, q, pair, nb)
        for _ in range(3):
            step = rng.normal(size=7) * 1e-6
            fd = _pair_distance(rows, q + step, pair, nb) - d0
            assert rows.A[r] @ step == pytest.approx(fd, abs=1e-10 + 1e-3 * abs(fd))
        keep = 0.05 if pair[1] < 0 else rows.parts.keep(0.05)[_own_index(rows, pair)]
        assert rows.bound_d[r] == pytest.approx(-DAMPING * (d0 - keep - MARGIN), abs=1e-12)


def _own_index(rows: ClearanceRows, pair) -> int:
    parts = rows.parts
    return int(np.flatnonzero((parts.i == pair[0]) & (parts.j == pair[1]))[0])


def _self_motion(obstacle: Neighbours | None, distance: float, cycles: int = 400):
    """The Panda holding its TCP while CYCLIC pulls it towards a reference: the joints and
    the least distance to ``obstacle`` per cycle."""
    panda = load_robot("panda")
    chain = SerialChain(panda)
    ik = InverseTransformation(chain, params=IKParams())
    q = panda.home_q()
    target = chain.tcp(q)
    ref = q + np.radians([60.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])
    spec = ClearanceSpec(distance, lambda: obstacle) if distance > 0 else None
    opts = CycleOptions(reference=ref, clearance=spec)
    q_prev, out = q.copy(), []
    for _ in range(cycles):
        res = ik.step(q, q_prev, target, 0.01, opts)
        q_prev, q = q, res.q
        assert res.position_error < 1e-7 and res.orientation_error < 1e-7
        out.append(q.copy())
    return chain, np.array(out)


def test_the_rows_stop_a_self_motion_at_the_clearance():
    """Without rows the self-motion takes the elbow through the sphere put where it ends;
    with R_CLEARANCE the elbow stops at the clearance, the TCP held in both."""
    chain, free = _self_motion(None, 0.0)
    start, end = chain.world_frames(free[0])[4][:3, 3], chain.world_frames(free[-1])[4][:3, 3]
    assert np.linalg.norm(end - start) > 0.1  # the elbow swings
    sphere = _sphere(end, 0.03)
    rows = ClearanceRows(chain)

    def least(qs) -> float:
        out = np.inf
        for q in qs:
            a, b = rows.parts.world([chain.world_frames(q)])
            for i in range(len(a)):
                _, _, p, s = closest_segment_segment(a[i], b[i], sphere.a[0], sphere.b[0])
                out = min(out, np.linalg.norm(p - s) - rows.parts.radius[i] - 0.03)
        return out

    assert least(free) < 0.0
    _, kept = _self_motion(sphere, 0.04)
    assert least(kept) >= 0.04 - 1e-4
    assert least(kept[-1:]) < 0.06  # it went as near as allowed
