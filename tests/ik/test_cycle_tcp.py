"""``CycleResult.tcp`` is the TCP pose at the returned configuration (no second FK needed)."""

from __future__ import annotations

import numpy as np
import pytest
from irlc.runtime.ik import CycleOptions, IKParams, InverseTransformation
from irlc.runtime.model.kinematics import Kinematics

from .ik_robots import line_poses


@pytest.mark.parametrize("max_iter", [0, 1, 10])
def test_cycle_tcp_equals_fk_of_the_returned_q(koch11, max_iter):
    kin = Kinematics(koch11)
    ik = InverseTransformation(koch11, kin, IKParams.for_robot(koch11, max_iter=max_iter))
    q = np.array(koch11.home, dtype=float)
    start = kin.tcp(q)
    end = start.copy()
    end[:3, 3] += (0.05, -0.03, 0.02)
    q_prev = q.copy()
    for target in line_poses(start, end, 20):
        r = ik.step(q, q_prev, target, 0.01, CycleOptions())
        expected = Kinematics(koch11).tcp(r.q)  # independent instance: fresh buffers
        assert r.tcp.shape == (4, 4)
        assert np.allclose(r.tcp, expected, rtol=0.0, atol=1e-14)
        q_prev, q = q, r.q
