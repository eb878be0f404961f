"""The optional compiled ``pwm`` loop (runtime/drives/compiled/pwm_loop.py) against the numpy
reference (power_stage.PwmStage): same trajectories, currents, voltages, torques, friction,
energies and flags to rounding, on two robots, with the current limit reached inside PWM
intervals, duty saturation, Karnopp sticking and both refresh policies."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
from irlc.robots.loader import load_toml
from irlc.runtime.accel_support import AVAILABLE
from irlc.runtime.drives import simulate_drives
from irlc.runtime.drives.compiled.pwm_loop import PwmLoop
from irlc.runtime.drives.params import drive_params

ROBOTS = Path(__file__).resolve().parents[2] / "robots"
needs_numba = pytest.mark.skipif(not AVAILABLE, reason="numba not installed / disabled")
FIELDS = ("q_actual", "qd_actual", "current", "voltage", "torque", "friction")


def move(model, delta, duration, samples=21):
    times = np.linspace(0.0, duration, samples)
    s = times / duration
    return times, model.home_q() + np.outer(s * s * (3 - 2 * s), delta)


def both(model, times, q, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = simulate_drives(model, times, q, level="pwm", accel=False, **kw)
        fast = simulate_drives(model, times, q, level="pwm", accel=True, **kw)
    return ref, fast


def assert_same(ref, fast):
    """Every recorded array to 1e-9 of its largest value (the loops differ in summation
    order: ``M⁻¹ rhs`` as a loop vs BLAS, the reduced Karnopp system by elimination vs the
    cached inverse; rounding, ≈ 1e-15 relative per step), energies to 1e-9 relative; the
    saturation flags may differ on a borderline period (a duty or current exactly at its
    limit to rounding)."""
    assert ref.t.shape == fast.t.shape and ref.step == fast.step
    for name in FIELDS:
        a, b = getattr(ref, name), getattr(fast, name)
        assert np.allclose(a, b, rtol=0.0, atol=1e-9 * max(1.0, np.abs(a).max())), name
    for name in ("electrical_energy", "copper_energy"):
        assert np.allclose(getattr(ref, name), getattr(fast, name), rtol=1e-9, atol=1e-12)
    for x, y in zip(ref.axes, fast.axes, strict=True):
        assert x.could_follow == y.could_follow
        assert abs(x.saturation_time - y.saturation_time) <= 1.5 * ref.step
        assert np.isclose(x.peak_current, y.peak_current, rtol=1e-9)


def current_limited_periods(run, i_max) -> int:
    """Periods whose mean current is within 2 % of ±i_max (the limit reached inside)."""
    driven = run.current[:, run.driven]
    return int(np.count_nonzero(np.abs(driven) >= 0.98 * i_max))


IRB6_FAST = np.array([0.03, 0.4, 0.25, -0.2, 0.3, 0.6])  # current limit on A3–A5


@needs_numba
@pytest.mark.parametrize("every", [None, 3])
def test_irb6_track_levers_current_limit_and_sticking(every):
    """irb6_track: screw levers, Karnopp sticking, the ±10 A limit reached inside PWM
    intervals (the closed form's limited branch) and the duty at 0 | 1."""
    model = load_toml(ROBOTS / "irb6_track.toml")
    times, q = move(model, IRB6_FAST, 0.25)
    ref, fast = both(model, times, q, hold=0.05, dynamics_every=every)
    assert_same(ref, fast)
    i_max = drive_params(model).chain.i_max
    assert current_limited_periods(ref, i_max.min()) > 50  # the limit branch ran
    assert np.count_nonzero(np.abs(ref.voltage) == 50.0) > 20  # duty saturated (±U)
    assert np.count_nonzero(ref.qd_actual[10:] == 0.0) > 20  # Karnopp held axes


@needs_numba
def test_irb6_track_slow_move():
    """A slow move: long adaptive holds of M, the arm's axes mostly inside their limits."""
    model = load_toml(ROBOTS / "irb6_track.toml")
    times, q = move(model, IRB6_FAST / 10, 0.3)
    ref, fast = both(model, times, q, hold=0.05)
    assert_same(ref, fast)
    assert all(a.could_follow for a in ref.axes)


@needs_numba
def test_as6_dry_friction_and_current_limit():
    """as6: plain ratios, its own gains and supply, dry friction; a move fast enough to
    reach its current limit."""
    model = load_toml(ROBOTS / "as6.toml")
    times, q = move(model, np.full(model.n, 0.5), 0.3)
    ref, fast = both(model, times, q, hold=0.05)
    assert_same(ref, fast)
    i_max = drive_params(model).chain.i_max
    assert current_limited_periods(ref, i_max.min()) > 20


@needs_numba
def test_koch11_plain_ratios():
    model = load_toml(ROBOTS / "koch11.toml")
    times, q = move(model, np.linspace(0.02, 0.1, model.n), 0.1)
    ref, fast = both(model, times, q, hold=0.02)
    assert_same(ref, fast)


@needs_numba
def test_state_carried_across_refreshes():
    """The PI integral, current and controller output after the run equal the numpy
    bank's (the kernel's state is written back): one more run from the same setpoints
    with ``dynamics_every=1`` (a refresh every period, a kernel call per period) still
    agrees."""
    model = load_toml(ROBOTS / "irb6_track.toml")
    times, q = move(model, IRB6_FAST / 3, 0.05, samples=6)
    ref, fast = both(model, times, q, hold=0.01, dynamics_every=1)
    assert_same(ref, fast)


@needs_numba
def test_interval_against_first_order():
    """The kernel's switching interval (closed form and the limit flag) against
    ``motor.first_order`` on one axis: inside the limit, reaching it, starting at it."""
    from irlc.runtime.drives import motor
    from irlc.runtime.drives.compiled import pwm_kernels as kp

    r, ell, ks, i_max = 1.2, 1e-3, 0.1, 10.0
    rng = np.random.default_rng(7)
    cases = [(9.9, 50.0, 0.0, 1e-4), (-10.0, -50.0, 3.0, 6e-5), (10.0, -50.0, 0.0, 1e-4)]
    cases += [tuple(x) for x in rng.uniform([-10, -50, -40, 0], [10, 50, 40, 1.25e-4], (600, 4))]
    hits = 0
    for i0, volts, omega, tau in cases:
        res = np.empty(4)
        hit = kp.switching_interval(i0, volts, omega, r, ell, ks, tau, i_max, res)
        ref = motor.first_order(np.array([i0]), volts, omega, r, ell, ks, tau, i_max)
        assert np.allclose(res, [ref[0][0], ref[1][0], ref[2][0], ref[3][0]], rtol=1e-12,
                           atol=1e-15)  # fmt: skip
        assert hit == bool(ref[4][0])
        hits += hit
    assert hits > 10


def test_covers_pwm_only():
    class Sim:
        is_dc, pwm, n = True, True, 3
        driven = np.ones(3, dtype=bool)
        axes = np.arange(3)

    assert PwmLoop.covers(Sim)
    Sim.pwm = False
    assert not PwmLoop.covers(Sim)
    Sim.pwm, Sim.is_dc = True, False
    assert not PwmLoop.covers(Sim)
    Sim.is_dc, Sim.driven = True, np.array([True, False, True])
    assert not PwmLoop.covers(Sim)


@needs_numba
def test_sources_digest_recorded():
    """The kernel's machine code includes the helpers of compiled/kernels.py; their digest
    must be the recorded one (a change there must change compiled/pwm_kernels.py, numba's
    cache key)."""
    from irlc.runtime.drives.compiled import pwm_kernels as kp

    assert kp.sources_digest() == kp.SOURCES_DIGEST
