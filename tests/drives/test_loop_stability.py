"""The linearised loops of every robot file's DC drives are stable with margin (docs/drives.md
gives the same numbers), and the rejected reading of the printed gains is not."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from irlc.robots.loader import load_toml
from irlc.runtime.drives import drive_params
from irlc.runtime.drives.linear import (
    AxisLoop,
    margins,
    open_position_loop,
    open_velocity_loop,
    poles,
)
from irlc.runtime.drives.params import DcDrives
from irlc.runtime.drives.transmission import Transmission
from irlc.runtime.model.dynamics import Dynamics

ROBOTS = Path(__file__).resolve().parents[2] / "robots"


def axis_loops(name: str, scale: float):
    model = load_toml(ROBOTS / f"{name}.toml")
    p = drive_params(model)
    assert isinstance(p.chain, DcDrives)
    ratio = Transmission(model, p).local_ratio(model.home_q())
    load = np.diag(Dynamics(model).mass_matrix(model.home_q()))[list(p.axes)] / ratio**2
    c = p.chain
    for a, j in enumerate(p.axes):
        yield (
            j,
            AxisLoop(
                c.ke[a],
                c.kp[a],
                c.ki[a],
                c.kz[a],
                c.R[a],
                c.L[a],
                c.ks[a],
                c.k[a],
                c.kiwzm[a],
                c.J_m[a] + scale * load[a],
            ),
        )


@pytest.mark.parametrize("name", ["irb6_track", "irb6", "as6", "koch11"])
@pytest.mark.parametrize("scale", [0.5, 1.0, 2.0])  # arm inertia ±2× (configuration changes)
def test_loops_stable_with_margin(name, scale):
    for j, loop in axis_loops(name, scale):
        if name == "irb6_track" and j == 0 and scale != 1.0:
            continue  # the track carries the whole robot: its inertia does not change with the pose
        assert poles(loop).real.max() < 0.0, (name, j)
        pm_v, _, gm_v = margins(open_velocity_loop(loop))
        pm_p, _, _ = margins(open_position_loop(loop))
        assert pm_v >= 30.0, (name, j, pm_v)
        assert gm_v >= 6.0, (name, j, gm_v)
        assert pm_p >= 30.0, (name, j, pm_p)


def test_rejected_reading_is_unstable():
    """Reading the printed ki as the proportional and kp [1/s] as the integral corner
    (PI = ki·(1 + kp/s)) destabilises the IRb-6 axis-1 loop for any motor-side inertia up to
    3·10⁻³ kg·m² — yet 1.05 N·m peak torque and a_max = 137 rad/s² demand J ≤ 7.7·10⁻³."""
    for inertia in (1e-3, 3e-3):
        loop = AxisLoop(
            0.105, 267.01, 267.01 * 32.02, 3.15, 3.053, 2.3e-3, 0.105, 0.42, 1668.4, inertia
        )
        assert poles(loop).real.max() > 0.0


def test_margins_of_a_known_loop():
    """margins() on L(s) = 10 / (s (s + 1)): crossover ≈ 3.08 rad/s, PM = 180 − 90 − atan(3.08)."""
    from scipy import signal

    loop = signal.StateSpace([[0.0, 1.0], [0.0, -1.0]], [[0.0], [10.0]], [[1.0, 0.0]], [[0.0]])
    pm, wc, gm = margins(loop)
    w_expected = np.sqrt((-1 + np.sqrt(1 + 400)) / 2)
    assert wc == pytest.approx(w_expected, rel=1e-3)
    assert pm == pytest.approx(90.0 - np.degrees(np.arctan(w_expected)), abs=0.05)
    assert gm == float("inf")
