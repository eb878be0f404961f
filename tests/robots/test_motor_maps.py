"""Motor ↔ joint maps: round trips, Jacobians vs finite differences, the L-1 formulas."""

from __future__ import annotations

import numpy as np
import pytest
from irlc.robots import load_robot
from irlc.runtime.model.motor_maps import MotorMap


@pytest.mark.parametrize("name", ["l1", "irb6", "irb6_track", "as6", "koch11"])
def test_round_trip_and_jacobians(name):
    model = load_robot(name)
    mm = MotorMap.from_model(model)
    rng = np.random.default_rng(0)
    lim = model.position_limits
    h = 1e-6
    for _ in range(10):
        q = rng.uniform(lim[:, 0], lim[:, 1])
        th = mm.motor_from_joint(q)
        assert np.allclose(mm.joint_from_motor(th), q, atol=1e-10)
        fd = np.empty((model.n, model.n))
        for i in range(model.n):
            dq = np.zeros(model.n)
            dq[i] = h
            fd[:, i] = (mm.motor_from_joint(q + dq) - mm.motor_from_joint(q - dq)) / (2 * h)
        jac = mm.motor_jacobian(q)
        assert np.allclose(jac, fd, rtol=1e-6, atol=1e-6)
        assert np.allclose(mm.joint_jacobian(q) @ jac, np.eye(model.n), atol=1e-9)


def test_l1_book_formulas():
    """λ_i = θs_i/k_i; θ4 = θs4/k4; θ5 = θs5/k5 + 0.5·θ4; θ6 = θs6/k6 + 2·θ5."""
    mm = MotorMap.from_model(load_robot("l1"))
    ts = np.array([100.0, 200.0, 300.0, 1.2, -0.7, 2.5])
    k = 360 * np.pi
    t4 = ts[3] / -3.6
    t5 = ts[4] / 7.2 + 0.5 * t4
    t6 = ts[5] / 7.2 + 2 * t5
    assert np.allclose(mm.joint_from_motor(ts), [100 / k, 200 / k, 300 / k, t4, t5, t6])


def test_direct_drive_without_table():
    model = load_robot("planar3")
    mm = MotorMap.from_model(model)
    q = np.array([0.1, -0.2, 0.3])
    assert np.allclose(mm.motor_from_joint(q), q)
    assert np.allclose(mm.motor_jacobian(q), np.eye(3))


def test_screw_out_of_reach_is_an_error():
    mm = MotorMap.from_model(load_robot("irb6"))
    with pytest.raises(ValueError, match="joint 2"):
        mm.joint_from_motor(np.array([0.0, 1e4, 0.0, 0.0, 0.0]))


def test_irb6_wrist_motors_follow_5_22():
    """(5.22): Θs4 = k4·Θ234, Θs5 = k4·Θ234 − k4·k5·Θ5 (Θ234 = Θ2+Θ3+Θ4), with the robot
    file's assumed k4 = 80, k5 = 1; computed here from the book's form, not the map's rows.
    Motor 5 turns when only the wrist tilts (Θ5 held), and stands when Θ5 follows Θ234/k5."""
    k4, k5 = 80.0, 1.0
    mm = MotorMap.from_model(load_robot("irb6"))
    rng = np.random.default_rng(5)
    for _ in range(20):
        q = np.radians(rng.uniform([0, -40, -40, -115, -270], [340, 40, 40, 130, 270]))
        t234 = q[1] + q[2] + q[3]
        ts = mm.motor_from_joint(q)
        assert ts[3] == pytest.approx(k4 * t234, rel=1e-12, abs=1e-12)
        assert ts[4] == pytest.approx(k4 * t234 - k4 * k5 * q[4], rel=1e-12, abs=1e-12)
    tilt = np.radians([90.0, 0.0, 0.0, 30.0, 0.0])
    assert mm.motor_from_joint(tilt)[4] == pytest.approx(k4 * np.radians(30.0))
    follow = np.radians([90.0, 0.0, 0.0, 30.0, 30.0 / k5])
    assert mm.motor_from_joint(follow)[4] == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("name", ["l1", "irb6", "irb6_track", "as6"])
def test_many_configurations_at_once_match_one_by_one(name):
    model = load_robot(name)
    mm = MotorMap.from_model(model)
    lim = model.position_limits
    qs = np.random.default_rng(1).uniform(lim[:, 0], lim[:, 1], size=(25, model.n))
    one_by_one = np.array([mm.motor_from_joint(q) for q in qs])
    assert np.allclose(mm.motor_from_joints(qs), one_by_one, rtol=1e-13, atol=1e-12)
