"""The step-size rule: ≤ 1/10 of the fastest explicitly integrated time constant."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from irlc.runtime.drives import StepSizeError, StepSizeWarning, drive_params, simulate_drives
from irlc.runtime.drives.stepsize import fastest_time_constant

from .drive_models import DC_AXIS, dc_drives, planar, stepper_drives

TIMES = np.array([0.0, 0.05])
Q = np.array([[0.0], [0.001]])


def model():
    return planar(1, mass=1.0, gravity=(0.0, 0.0, 0.0), drives=dc_drives(1, 30.0))


def tau_min(m) -> float:
    from irlc.runtime.model.dynamics import Dynamics

    j = DC_AXIS["J_m"] + Dynamics(m).mass_matrix(np.zeros(1))[0, 0] / 30.0**2
    return float(fastest_time_constant(drive_params(m).chain, np.array([j])).min())


def test_time_constant_is_the_velocity_loop():
    m = model()
    c = DC_AXIS
    from irlc.runtime.model.dynamics import Dynamics

    j = c["J_m"] + Dynamics(m).mass_matrix(np.zeros(1))[0, 0] / 900.0
    assert tau_min(m) == pytest.approx(j * c["k"] / (c["kp"] * c["ke"] * c["ks"]))


def test_default_step_obeys_the_rule():
    m = model()
    run = simulate_drives(m, TIMES, Q, level="coupled", hold=0.0)
    assert run.step <= tau_min(m) / 10.0
    assert 1e-3 / run.step == pytest.approx(round(1e-3 / run.step))  # 1 ms / integer


def test_rule_warns_then_refuses():
    m = model()
    tau = tau_min(m)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        simulate_drives(m, TIMES, Q, level="decoupled", step=tau / 12.0, hold=0.0)
    with pytest.warns(StepSizeWarning, match="more than 1/10"):
        simulate_drives(m, TIMES, Q, level="decoupled", step=tau / 5.0, hold=0.0)
    with pytest.raises(StepSizeError, match="exceeds"):
        simulate_drives(m, TIMES, Q, level="decoupled", step=tau * 1.5, hold=0.0)


def test_pwm_steps_one_period():
    m = model()
    run = simulate_drives(m, TIMES, Q, level="pwm", hold=0.0)
    assert run.step == pytest.approx(1.0 / 8000.0)
    with pytest.raises(StepSizeError, match="PWM period"):
        simulate_drives(m, TIMES, Q, level="pwm", step=1e-5, hold=0.0)


def test_stepper_rule_and_generator_period():
    def axis(rate):
        return planar(
            1,
            mass=0.5,
            link=0.2,
            gravity=(0.0, 0.0, 0.0),
            drives=stepper_drives(10.0, step_rate=rate),
        )

    # detent oscillation τ ≈ 1.24 ms; the 5000 steps/s generator period is 100 µs
    with pytest.raises(StepSizeError, match="step generator"):
        simulate_drives(axis(100 * math.pi), TIMES, Q, level="decoupled", step=1.2e-4, hold=0.0)
    with pytest.warns(StepSizeWarning):
        simulate_drives(axis(2.5 * math.pi), TIMES, Q, level="decoupled", step=5e-4, hold=0.0)
    run = simulate_drives(axis(100 * math.pi), TIMES, Q, level="decoupled", hold=0.0)
    assert run.step <= 1e-4
