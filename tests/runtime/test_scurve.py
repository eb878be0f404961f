"""Jerk-limited (S-curve) profiles against closed forms, a brute-force minimum and finite
differences."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from irlc.runtime.plan.profiles import ProfileError, trapezoid
from irlc.runtime.plan.profiles import minimum_time as trapezoid_time
from irlc.runtime.plan.scurve import common_bounds, minimum_time, scurve


def brute_minimum(v: float, a: float, j: float) -> float:
    """min over cruise speeds ``w ≤ v`` of ``t_a(w) + 1/w`` subject to ``w·t_a(w) ≤ 1``
    (accelerate to ``w`` with peak ``min(a, √(w·j))``, cruise, mirror) on a grid, refined
    twice around the best point — no case analysis."""
    lo, hi, best = v * 1e-9, v, math.inf
    for _ in range(3):
        w = np.linspace(lo, hi, 100001)
        ap = np.minimum(a, np.sqrt(w * j))
        ta = w / ap + ap / j
        times = np.where(w * ta <= 1.0, ta + 1.0 / w, np.inf)
        k = int(np.argmin(times))
        best = min(best, float(times[k]))
        step = w[1] - w[0]
        lo, hi = max(v * 1e-9, w[k] - step), min(v, w[k] + step)
    return best


# (v, a, j, expected T, case): hand-computed closed forms
KNOWN = [
    (0.5, 2.0, 50.0, 0.5 / 2.0 + 2.0 / 50.0 + 1 / 0.5, "v and a reached"),
    (0.3, 5.0, 1.0, 2 * math.sqrt(0.3 / 1.0) + 1 / 0.3, "v reached, a not"),
    (1.0, 1.0, 1.0, 4 * 2 ** (-1 / 3), "neither: four jerk phases"),
    # a reached, v not: w²/a + w·a/j = 1 with a = 1, j = 10: w² + 0.1·w = 1, T = 2(w/a + a/j)
    (10.0, 1.0, 10.0, 2 * ((-0.1 + math.sqrt(0.01 + 4)) / 2 + 0.1), "a reached, v not"),
    (10.0, 2.0, 3.0, 4 * 6 ** (-1 / 3), "neither (a³ ≥ j²/2)"),
]


@pytest.mark.parametrize(("v", "a", "j", "expected", "case"), KNOWN)
def test_minimum_time_known_cases(v, a, j, expected, case):
    assert minimum_time(v, a, j) == pytest.approx(expected, rel=1e-12), case
    assert minimum_time(v, a, j) == pytest.approx(brute_minimum(v, a, j), rel=1e-9), case


def _check_profile(p, v, a, j, n=40001):
    """Rest to rest, ``s`` from 0 to 1, continuity of s, ṡ, s̈ and the bounds, all by
    finite differences of ``position``."""
    t = np.linspace(0.0, p.duration, n)
    h = t[1] - t[0]
    s = p.position(t)
    assert s[0] == 0.0 and s[-1] == 1.0
    sd = np.diff(s) / h
    sdd = np.diff(sd) / h
    assert sd.min() >= -1e-9 and sd.max() <= v * (1 + 1e-6)
    assert np.abs(sdd).max() <= a * (1 + 1e-6) + j * h
    tc = np.linspace(0.0, p.duration, 1001)  # third differences (coarse: round-off ~ ε/h³)
    assert np.abs(np.diff(p.position(tc), 3)).max() / (tc[1] - tc[0]) ** 3 <= j * (1 + 1e-6)
    mid = 0.5 * (t[1:] + t[:-1])
    assert np.allclose(p.speed(mid), sd, atol=j * h * h + 1e-12)  # ṡ is the derivative of s
    mid2 = t[1:-1]
    assert np.allclose(p.acceleration(mid2), sdd, atol=j * h)  # s̈ that of ṡ
    # continuity: no jump of speed or acceleration between neighbouring samples
    assert np.abs(np.diff(p.speed(t))).max() <= a * h * (1 + 1e-9)
    assert np.abs(np.diff(p.acceleration(t))).max() <= j * h * (1 + 1e-9)
    d = 1e-6 * p.duration  # at rest at both ends, reached with ṡ ≤ j·d²/2, s̈ ≤ j·d
    for f, bound in ((p.speed, 0.5 * j * d * d), (p.acceleration, j * d)):
        assert f(0.0) == 0.0 and abs(float(f(p.duration))) == 0.0
        assert abs(float(f(d))) <= bound * (1 + 1e-6)
        assert abs(float(f(p.duration - d))) <= bound * (1 + 1e-6)


@pytest.mark.parametrize(("v", "a", "j", "expected", "case"), KNOWN)
def test_profile_by_finite_differences(v, a, j, expected, case):
    _check_profile(scurve(v, a, j), v, a, j)


@pytest.mark.parametrize("stretch", [1.0 + 1e-9, 1.05, 1.7, 4.0, 50.0])
@pytest.mark.parametrize(("v", "a", "j", "expected", "case"), KNOWN)
def test_stretched_profile_keeps_bounds_and_lasts_the_time(v, a, j, expected, case, stretch):
    p = scurve(v, a, j, expected * stretch)
    assert p.duration == expected * stretch
    _check_profile(p, v, a, j)
    # the lowered cruise speed closes the distance: 1 = v_c·(T − t_a)
    assert p.cruise * (p.duration - p.t_acc) == pytest.approx(1.0, rel=1e-9)


def test_shorter_than_minimum_is_an_error():
    with pytest.raises(ProfileError, match="shorter than"):
        scurve(1.0, 1.0, 1.0, 3.0)
    for bad in ((0.0, 1.0, 1.0), (1.0, -1.0, 1.0), (1.0, 1.0, math.inf), (1.0, 1.0, math.nan)):
        with pytest.raises(ProfileError, match="positive and finite"):
            scurve(*bad)


def test_slower_than_trapezoid_and_converges_to_it():
    for v, a in ((0.5, 2.0), (2.0, 1.0), (0.3, 5.0)):
        times = [minimum_time(v, a, j) for j in (1.0, 10.0, 1e3, 1e6)]
        assert all(t >= trapezoid_time(v, a) for t in times)
        assert times == sorted(times, reverse=True)
        assert times[-1] == pytest.approx(trapezoid(v, a).duration, rel=1e-3)


@settings(max_examples=60, deadline=None)
@given(
    v=st.floats(1e-2, 1e2),
    a=st.floats(1e-2, 1e2),
    j=st.floats(1e-2, 1e3),
    stretch=st.one_of(st.just(1.0), st.floats(1.0, 10.0)),
)
def test_random_profiles(v, a, j, stretch):
    t_min = minimum_time(v, a, j)
    assert t_min == pytest.approx(brute_minimum(v, a, j), rel=1e-9)
    p = scurve(v, a, j, t_min * stretch)
    assert p.duration == pytest.approx(t_min * stretch, rel=1e-12)
    assert p.cruise <= v * (1 + 1e-12) and p.accel <= a * (1 + 1e-12)
    _check_profile(p, v, a, j, n=4001)


def test_common_bounds_synchronise_axes():
    # axis 0: 2 units at v 1, a 1, j 1; axis 1: 1 unit at v 4, a 4, j 4 (twice as fast)
    v, a, j, slowest = common_bounds([2.0, 1.0], [1.0, 4.0], [1.0, 4.0], [1.0, 4.0])
    assert (v, a, j, slowest) == (0.5, 0.5, 0.5, 0)
    # every axis's jerk on the common profile is within its own bound
    p = scurve(v, a, j)
    t = np.linspace(0.0, p.duration, 1001)
    h = t[1] - t[0]
    jerk = np.abs(np.diff(p.position(t), 3)) / h**3
    assert (2.0 * jerk).max() <= 1.0 * (1 + 1e-6) and (1.0 * jerk).max() <= 4.0
    v, a, j, slowest = common_bounds([0.0, 0.0], [1.0, 1.0], [1.0, 1.0], [1.0, 1.0])
    assert slowest == -1 and v == math.inf


def test_phase_marks_the_held_acceleration():
    p = scurve(0.5, 2.0, 50.0)  # t₁ = 0.04 s, t₂ = 0.21 s
    assert p.t_jerk == pytest.approx(0.04) and p.t_const == pytest.approx(0.21)
    assert list(p.phase([0.02, 0.1, 1.0, p.duration - 0.1, p.duration - 0.02])) == [0, 1, 0, -1, 0]
