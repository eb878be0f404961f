"""Open-loop stepper drive: keeps every step when commanded slowly, loses steps when the
step generator runs faster than the rotor can follow (pull-out)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from irlc.runtime.drives import simulate_drives

from .drive_models import planar, stepper_drives

RATIO = 10.0
STEP_ANGLE = 2 * math.pi / 200  # 1.8° at the motor


def axis(**over):
    return planar(
        1, mass=0.5, link=0.2, gravity=(0.0, 0.0, 0.0), drives=stepper_drives(RATIO, **over)
    )


def test_slow_command_keeps_every_step():
    model = axis()
    steps = 20
    target = steps * STEP_ANGLE / RATIO
    times = np.linspace(0.0, 0.5, 51)
    q_cmd = (target * times / times[-1])[:, None]  # 40 steps/s < 250 steps/s generator
    run = simulate_drives(model, times, q_cmd, level="decoupled", step=2e-5, hold=0.3)
    a = run.axes[0]
    assert a.drive == "stepper" and a.lost_steps == 0 and a.could_follow
    assert abs(run.q_actual[-1, 0] - target) < 0.5 * STEP_ANGLE / RATIO
    assert run.q_actual[-1, 0] > 0.9 * target  # it really moved


def test_fast_step_generator_loses_steps():
    model = axis(step_rate=100 * math.pi)  # 5000 steps/s
    steps = 40
    target = steps * STEP_ANGLE / RATIO
    times = np.array([0.0, 1e-3, 0.2])
    q_cmd = np.array([[0.0], [target], [target]])
    run = simulate_drives(model, times, q_cmd, level="decoupled", step=1e-5, hold=0.2)
    a = run.axes[0]
    assert a.lost_steps is not None and a.lost_steps >= 4
    assert not a.could_follow
    # the rotor rests in a detent a whole number of teeth (4 steps) away from the target
    rest = (target - run.q_actual[-1, 0]) * RATIO / STEP_ANGLE
    assert rest == pytest.approx(a.lost_steps, abs=0.3)
    assert a.lost_steps % 4 == 0
