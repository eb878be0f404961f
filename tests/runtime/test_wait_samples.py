"""WAIT records one sample per IPO cycle of the standing robot; the TCP is computed once
for the whole wait (regression for the per-cycle FK) and must equal an independent FK of
the recorded joints."""

from __future__ import annotations

import numpy as np
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.run import run_code

from .conftest import Ird


def test_wait_samples_stand_still_at_the_fk_pose(planar3):
    p = Ird("planar3t", "RRR")
    p.move(3, "LIN", p.pose(1800, 900, 0))
    p.push(4, p.const("REAL", 0.05)).op(4, "WAIT")
    run = run_code(p.code_object(), robot=planar3)
    assert run.status == "ok", run.error
    wait = run.lines == 4
    assert wait.sum() == 5  # 0.05 s of 10 ms cycles
    np.testing.assert_allclose(np.diff(run.times[wait]), 0.01, atol=1e-9)
    q = run.q[wait]
    assert np.array_equal(q, np.repeat(q[:1], len(q), axis=0))
    fk = Kinematics(planar3).tcp(q[0])
    for tcp in run.tcp[wait]:
        np.testing.assert_allclose(tcp, fk, atol=1e-12)
    # the robot stands where the LIN ended
    np.testing.assert_array_equal(q[0], run.q[np.flatnonzero(run.lines == 3)[-1]])


def test_a_long_wait_records_its_first_cycles_and_its_end(planar3):
    # A WAIT allocated one sample per IPO cycle (24 h: 8.6 million; MemoryError for more).
    from irlc.runtime.control.executor import WAIT_SAMPLED_CYCLES

    p = Ird("planar3t", "RRR")
    p.push(3, p.const("REAL", 100.0)).op(3, "WAIT")
    run = run_code(p.code_object(), robot=planar3)
    assert run.status == "ok", run.error
    times = run.times[run.lines == 3]
    assert len(times) == WAIT_SAMPLED_CYCLES + 1
    np.testing.assert_allclose(np.diff(times[:WAIT_SAMPLED_CYCLES]), 0.01, atol=1e-9)
    assert times[-1] == 100.0
