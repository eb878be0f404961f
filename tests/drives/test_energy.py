"""Energy balance over a run: electrical energy in = copper losses + friction losses +
change of magnetic, kinetic and potential energy (the drives' work on the arm)."""

from __future__ import annotations

import numpy as np
import pytest
from irlc.runtime.drives import simulate_drives
from irlc.runtime.model.dynamics import Dynamics

from .drive_models import DC_AXIS, dc_drives, planar

RATIO = 30.0


def arm():
    drives = dc_drives(2, RATIO)
    drives["friction"] = {"static": 0.03, "running": 0.02, "viscous": 1e-4}
    return planar(2, mass=1.0, link=0.4, drives=drives)


def balance(run, model):
    """Terms of the balance (J). Electrical input and copper loss are the simulation's own
    integrals (exact across PWM switching instants); friction work, magnetic, kinetic
    (with rotors) and potential energy are recomputed here from the recorded motion."""
    h = run.step
    rotor = np.full(model.n, DC_AXIS["J_m"] * RATIO**2)
    dyn = Dynamics(model, rotor_inertia=rotor)
    copper = float(run.copper_energy.sum())
    friction = np.sum(run.friction[:-1] * run.qd_actual[1:]) * h
    magnetic = 0.5 * DC_AXIS["L"] * np.sum(run.current[-1] ** 2 - run.current[0] ** 2)

    def mech(k):
        q, qd = run.q_actual[k], run.qd_actual[k]
        kinetic = 0.5 * qd @ dyn.mass_matrix(q) @ qd
        potential = -sum(
            i.mass
            * model.gravity
            @ (dyn.frames(q)[i.link, :3, :3] @ i.com + dyn.frames(q)[i.link, :3, 3])
            for i in model.inertials
        )
        return kinetic + potential

    return float(run.electrical_energy.sum()), copper, friction, magnetic, mech(-1) - mech(0)


@pytest.mark.parametrize("level,step", [("coupled", 5e-5), ("pwm", None)])
def test_energy_balance(level, step):
    model = arm()
    times = np.linspace(0.0, 0.5, 51)
    s = times / times[-1]
    prof = s * s * (3 - 2 * s)
    q_cmd = np.column_stack([1.0 * prof, -0.8 * prof])
    run = simulate_drives(model, times, q_cmd, level=level, step=step, hold=0.2)
    e_in, copper, friction, magnetic, mech = balance(run, model)
    out = copper + friction + magnetic + mech
    assert mech > 0.5 and friction > 0.05 and copper > 0.1  # every term really is there
    # stated tolerance: 1 % of the electrical energy delivered
    assert out == pytest.approx(e_in, rel=0.01)
