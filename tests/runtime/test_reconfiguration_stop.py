"""RECONFIGURATION k ends by the two-cycle rule (runtime/ik/self_motion.py, docs/ik.md):
the joints overshoot and reverse when the reference arrives faster than the held TCP lets
them follow; the seed's one-cycle rule ‖θ(t) − θ(t−Δt)‖ < ε_conf stopped the statement at
that reversal, 0.019 rad (and 0.069 rad with a lower acceleration limit) from k."""

from __future__ import annotations

import numpy as np
import pytest
from irlc.runtime.commands import ModalOptions, Settings
from irlc.runtime.control.executor import ExecutionOptions, SimulatedController
from irlc.runtime.ik import IKParams, solve_pose
from irlc.runtime.model import spatial
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.values import JointTuple

from tests.ik.ik_robots import XY, planar_arm


@pytest.mark.parametrize("accel", [50.0, 5.0])
def test_reconfiguration_ends_at_k_not_at_a_reversal(accel):
    model = planar_arm(3, speed=2.0, accel=accel)
    kin = Kinematics(model)
    q0 = np.array([0.2, 1.0, 1.0])
    hold = kin.tcp(q0)
    # the same TCP position with the hand turned by −0.8 rad: k lies on the self-motion
    turned = hold @ spatial.transform(spatial.rot_z(-0.8))
    sol = solve_pose(model, turned, q0, task_rows=(0, 1, 5))
    assert sol.converged
    k = sol.q
    ctrl = SimulatedController(model, q0, options=ExecutionOptions(ik=IKParams(task_rows=XY)))
    target = JointTuple("MAIN_JOINT", tuple(np.degrees(k)))
    settings = Settings()
    settings.speed_ptp = 100.0  # the reference as fast as the joint limits allow
    ctrl.reconfigure(target, 1, settings, ModalOptions())
    assert not ctrl.recorder.warnings  # it settled, not the settle-time fallback
    assert np.linalg.norm(ctrl.q - k) < 1e-6 * np.linalg.norm(q0 - k)
    assert np.linalg.norm(kin.tcp(ctrl.q)[:2, 3] - hold[:2, 3]) < 1e-9
