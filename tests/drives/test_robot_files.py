"""The shipped robot files' drives run end to end (short smooth moves from home)."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
from irlc.robots.loader import load_toml
from irlc.runtime.drives import drive_params, simulate_drives
from irlc.runtime.drives.transmission import Transmission

ROBOTS = Path(__file__).resolve().parents[2] / "robots"


def move(model, delta, duration=0.4):
    times = np.linspace(0.0, duration, 41)
    s = times / duration
    return times, model.home_q() + np.outer(s * s * (3 - 2 * s), delta)


@pytest.mark.parametrize(
    "name,level,delta",
    [
        ("irb6_track", "coupled", [0.02, 0.05, 0.05, 0.05, 0.05, 0.05]),
        ("as6", "coupled", [0.05] * 6),
        ("l1", "decoupled", [0.001, 0.001, 0.001, 0.02, 0.02, 0.02]),
        ("koch11", "decoupled", [0.01] * 9 + [0.005, 0.01]),
    ],
)
def test_robot_drives_run(name, level, delta):
    model = load_toml(ROBOTS / f"{name}.toml")
    times, q = move(model, np.array(delta))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the default step obeys the rule
        # as6: the assumed gains leave a lightly damped ~1 Hz mode (settles in ≈ 2.6 s)
        run = simulate_drives(model, times, q, level=level, hold=3.0 if name == "as6" else 0.6)
    params = drive_params(model)
    # settled within 10 % of the move; a stepper: every motor within half a step of its
    # target (the coupled wrist adds up steps of several motors in joint space)
    tol = 0.1 * np.abs(delta) + 1e-6
    if params.type == "stepper":
        trans = Transmission(model, params)
        miss = trans.to_motor(run.q_actual[-1]) - trans.to_motor(q[-1])
        assert np.all(np.abs(miss) <= 0.5 * params.chain.step_angle + 1e-3)
        tol = np.full(model.n, np.inf)
    assert run.driven.all() and len(run.axes) == model.n
    for x in (run.q_actual, run.current, run.torque, run.voltage):
        assert np.all(np.isfinite(x))
    for a in run.axes:
        assert a.could_follow, (name, a.name)
        assert abs(run.q_actual[-1, a.joint] - q[-1, a.joint]) < tol[a.joint], (name, a.name)
    if name == "l1":
        assert all(a.lost_steps == 0 for a in run.axes)


def test_motor_maps_in_the_transmission():
    """IRb-6: screw levers and the coupled wrist go through irlc.runtime.model.motor_maps."""
    from irlc.runtime.model.motor_maps import MotorMap

    model = load_toml(ROBOTS / "irb6.toml")
    trans = Transmission(model, drive_params(model))
    q = model.home_q() + 0.1
    full = MotorMap.from_model(model)
    assert not trans.diagonal
    assert np.allclose(trans.to_motor(q), full.motor_from_joint(q))
    k = trans.jacobian(q)
    assert np.allclose(k, full.motor_jacobian(q))
    jm = drive_params(model).chain.J_m
    assert np.allclose(trans.rotor_matrix(jm, q), k.T @ np.diag(jm) @ k)
    assert np.allclose(trans.local_ratio(q), np.diag(k))


def test_vectorised_levers_match_the_motor_maps():
    """The transmission's vectorised screw levers equal irlc.runtime.model.motor_maps
    (irb6_track)."""
    from irlc.runtime.model.motor_maps import MotorMap

    model = load_toml(ROBOTS / "irb6_track.toml")
    trans = Transmission(model, drive_params(model))
    full = MotorMap.from_model(model)
    rng = np.random.default_rng(1)
    qs = model.home_q() + rng.uniform(-0.5, 0.5, (5, model.n))
    assert np.allclose(trans.to_motor(qs), [full.motor_from_joint(q) for q in qs])
    for q in qs:
        theta, k = trans.motor_and_jacobian(q)
        assert np.allclose(theta, full.motor_from_joint(q))
        assert np.allclose(k, full.motor_jacobian(q))
        assert np.allclose(trans.jacobian(q), k)
