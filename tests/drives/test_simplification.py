"""Decoupled vs coupled, reported as in Szkodny's simplification tables: the largest
difference of the two runs per axis in % of that axis' commanded range."""

from __future__ import annotations

import numpy as np
import pytest
from irlc.runtime.drives import deviation_percent, simulate_drives

from .drive_models import dc_drives, planar

TIMES = np.linspace(0.0, 0.6, 61)
S = TIMES / TIMES[-1]
Q = np.column_stack([0.5, -0.5]) * (S * S * (3 - 2 * S))[:, None]


def runs(ratio: float):
    model = planar(2, mass=2.0, link=0.4, gravity=(0.0, 0.0, -9.81), drives=dc_drives(2, ratio))
    a = simulate_drives(model, TIMES, Q, level="coupled", step=2e-4, hold=0.3)
    b = simulate_drives(model, TIMES, Q, level="decoupled", step=2e-4, hold=0.3)
    return a, b


def test_deviation_measure_itself():
    a, b = runs(10.0)
    manual = [np.max(np.abs(a.q_actual[:, j] - b.q_actual[:, j])) / 0.5 * 100 for j in (0, 1)]
    assert deviation_percent(a, b) == pytest.approx(manual)


def test_geared_axes_decouple_direct_drive_does_not():
    geared = deviation_percent(*runs(10.0))  # rotor inertia dominates: J_m·i² ≫ arm
    direct = deviation_percent(*runs(3.0))  # the arm dominates: coupling matters
    assert np.all(geared < 1.0)
    assert direct[0] > 5.0
    assert direct[0] > 20 * geared[0]
