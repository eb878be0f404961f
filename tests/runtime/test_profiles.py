"""Trapezoidal profiles against closed forms and finite differences."""

from __future__ import annotations

import math

import numpy as np
import pytest
from irlc.runtime.plan.profiles import (
    ProfileError,
    common_bounds,
    cycles,
    minimum_time,
    shared_bounds,
    trapezoid,
)


@pytest.mark.parametrize(("v", "a"), [(0.5, 2.0), (2.0, 1.0), (1.0, 1.0), (0.1, 100.0)])
def test_minimum_time_closed_form(v, a):
    # trapezoid if the cruise speed is reached within half the distance: v²/a ≤ 1
    expected = 1 / v + v / a if v * v / a <= 1 else 2 * math.sqrt(1 / a)
    assert minimum_time(v, a) == pytest.approx(expected, rel=1e-12)
    p = trapezoid(v, a)
    assert p.duration == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize(
    ("v", "a", "stretch"), [(0.5, 2.0, 1.0), (2.0, 1.0, 1.0), (0.5, 2.0, 1.7), (3.0, 3.0, 2.5)]
)
def test_profile_respects_bounds_by_finite_differences(v, a, stretch):
    p = trapezoid(v, a, minimum_time(v, a) * stretch)
    t = np.linspace(0.0, p.duration, 20001)
    s = p.position(t)
    assert s[0] == 0.0 and s[-1] == pytest.approx(1.0, abs=1e-12)
    h = t[1] - t[0]
    sd = np.diff(s) / h
    sdd = np.diff(sd) / h
    assert sd.min() >= -1e-9 and sd.max() <= v * (1 + 1e-6)
    assert np.abs(sdd).max() <= a * (1 + 1e-3)
    # speed() agrees with the derivative of position()
    mid = 0.5 * (t[1:] + t[:-1])
    assert np.allclose(p.speed(mid), sd, atol=a * h)
    # rest at both ends
    assert p.speed(0.0) == 0.0 and p.speed(p.duration) == pytest.approx(0.0, abs=1e-12)


def test_stretch_keeps_the_acceleration_and_lowers_the_speed():
    p = trapezoid(1.0, 4.0, 3.0)
    assert p.accel == 4.0
    # area under the speed profile is the unit distance: vc·(T − vc/a) = 1
    assert p.cruise * (p.duration - p.cruise / p.accel) == pytest.approx(1.0, rel=1e-12)
    assert p.cruise < 1.0


def test_too_short_time_is_an_error():
    with pytest.raises(ProfileError, match="shorter"):
        trapezoid(1.0, 1.0, 0.5 * minimum_time(1.0, 1.0))


def test_common_bounds_picks_the_slowest_axis():
    # axis 1 needs 2 m at 1 m/s: slower than axis 0 (1 rad at 2 rad/s)
    v, a, slowest = common_bounds([1.0, 2.0, 0.0], [2.0, 1.0, 5.0], [10.0, 10.0, 1.0])
    assert slowest == 1
    assert v == pytest.approx(0.5) and a == pytest.approx(5.0)
    assert common_bounds([0.0, 0.0], [1.0, 1.0], [1.0, 1.0]) == (math.inf, math.inf, -1)


def test_cycles_round_up_but_tolerate_rounding():
    assert cycles(1.0, 0.01) == 100
    assert cycles(1.0000000000001, 0.01) == 100
    assert cycles(1.001, 0.01) == 101
    assert cycles(0.0, 0.01) == 0


def test_shared_bounds_is_the_rule_of_both_profiles():
    # one loop for the trapezoid (speed, acceleration) and the S-curve (… and jerk)
    from irlc.runtime.plan import scurve

    names = ("speed", "acceleration")
    (v, a), slowest = shared_bounds([1.0, 2.0], ([2.0, 1.0], [10.0, 10.0]), minimum_time, names)
    assert (v, a, slowest) == (0.5, 5.0, 1)
    with pytest.raises(ProfileError, match=r"^axis 1: speed and acceleration bounds must be"):
        common_bounds([1.0, 1.0], [1.0, 0.0], [1.0, 1.0])
    with pytest.raises(ProfileError, match=r"^axis 0: speed, acceleration and jerk bounds must"):
        scurve.common_bounds([1.0], [1.0], [1.0], [0.0])
