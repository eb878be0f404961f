"""One axis' closed-loop step response against the analytic linear model of the same loop
(scipy.signal, same parameters, small step: no saturation)."""

from __future__ import annotations

import numpy as np
import pytest
from irlc.runtime.drives import simulate_drives
from irlc.runtime.drives.linear import AxisLoop, closed_loop
from irlc.runtime.model.dynamics import Dynamics
from scipy import signal

from .drive_models import DC_AXIS, dc_drives, planar

RATIO = 30.0
STEP = 5e-4  # rad at the joint: 15 mrad at the motor keeps every stage linear


def one_axis():
    model = planar(1, mass=2.0, link=0.4, gravity=(0.0, 0.0, 0.0), drives=dc_drives(1, RATIO))
    j_load = Dynamics(model).mass_matrix(np.zeros(1))[0, 0] / RATIO**2
    c = DC_AXIS
    loop = AxisLoop(
        c["ke"],
        c["kp"],
        c["ki"],
        c["kz"],
        c["R"],
        c["L"],
        c["ks"],
        c["k"],
        c["kiwzm"],
        c["J_m"] + j_load,
    )
    return model, loop


@pytest.mark.parametrize(
    "level,step,tol", [("decoupled", 5e-5, 0.01), ("coupled", 5e-5, 0.01), ("pwm", None, 0.03)]
)
def test_step_response_matches_linear_model(level, step, tol):
    model, loop = one_axis()
    times = np.array([0.0, 0.002, 0.3])
    q_cmd = np.array([[0.0], [STEP], [STEP]])
    run = simulate_drives(model, times, q_cmd, level=level, step=step, hold=0.0)
    assert run.axes[0].saturation_time == 0.0
    ref = run.q_cmd_interp[:, 0] * RATIO
    _, theta, _ = signal.lsim(closed_loop(loop), ref, run.t - run.t[0])
    sim = run.q_actual[:, 0] * RATIO
    assert np.max(np.abs(sim - theta)) <= tol * STEP * RATIO
    # and the response is a real one: it moves and settles at the step
    assert sim[-1] == pytest.approx(STEP * RATIO, rel=0.01)
    assert sim[len(sim) // 20] < 0.9 * STEP * RATIO
