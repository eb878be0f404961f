"""The optional compiled drive loop (runtime/drives/compiled/) against the numpy reference:
same trajectories, currents, voltages, friction, energies and flags to rounding, on every
transmission kind it covers, both refresh policies, friction sticking and the saturation
branches; the numpy loop where it does not cover; the use/skip decision."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
from irlc.robots.loader import load_toml
from irlc.runtime import accel_support, engine
from irlc.runtime.drives import motor, simulate_drives
from irlc.runtime.drives.compiled.loop import CompiledLoop

ROBOTS = Path(__file__).resolve().parents[2] / "robots"
needs_numba = pytest.mark.skipif(
    not accel_support.AVAILABLE, reason="numba not installed / disabled"
)
FIELDS = ("q_actual", "qd_actual", "current", "voltage", "torque", "friction")


def move(model, delta, duration):
    times = np.linspace(0.0, duration, 41)
    s = times / duration
    return times, model.home_q() + np.outer(s * s * (3 - 2 * s), delta)


def both(model, times, q, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = simulate_drives(model, times, q, hold=0.15, accel=False, **kw)
        fast = simulate_drives(model, times, q, hold=0.15, accel=True, **kw)
    return ref, fast


def assert_same(ref, fast):
    for name in FIELDS:
        a, b = getattr(ref, name), getattr(fast, name)
        assert np.allclose(a, b, rtol=0.0, atol=1e-9 * max(1.0, np.abs(a).max())), name
    for name in ("electrical_energy", "copper_energy"):
        assert np.allclose(getattr(ref, name), getattr(fast, name), rtol=1e-9, atol=1e-12)
    for x, y in zip(ref.axes, fast.axes, strict=True):
        assert x.could_follow == y.could_follow
        assert abs(x.saturation_time - y.saturation_time) <= 1.5 * ref.step  # borderline ties


IRB6_MOVE = np.array([0.03, 0.4, 0.25, -0.2, 0.3, 0.6])  # fast: current clamp on A3–A5


@needs_numba
@pytest.mark.parametrize("level, every", [("coupled", None), ("coupled", 3), ("decoupled", None)])
def test_screw_levers_friction_and_limits(level, every):
    """irb6_track: screw levers (K(q) every step), Karnopp sticking of the slow axes,
    current clamp and velocity-PI saturation on the fast ones."""
    model = load_toml(ROBOTS / "irb6_track.toml")
    times, q = move(model, IRB6_MOVE, 0.5)
    ref, fast = both(model, times, q, level=level, step=1e-3, dynamics_every=every)
    assert_same(ref, fast)
    assert max(a.saturation_time for a in ref.axes) > 0.0  # the limit branches ran
    assert np.count_nonzero(ref.qd_actual[10:] == 0.0) > 20  # axes held by friction (Karnopp)


@needs_numba
@pytest.mark.parametrize("every", [None, 1])
def test_coupled_1ms_adaptive_and_every_step(every):
    """The bench case (coupled, forced 1 ms) on both robots, adaptive refresh and a refresh
    every step: the compiled run (refreshes inside run_segment) equals the numpy loop."""
    irb6 = load_toml(ROBOTS / "irb6_track.toml")
    times, q = move(irb6, IRB6_MOVE / 2, 0.4)
    ref, fast = both(irb6, times, q, level="coupled", step=1e-3, dynamics_every=every)
    assert_same(ref, fast)
    koch = load_toml(ROBOTS / "koch11.toml")
    delta = np.linspace(0.05, 0.3, koch.n) * np.where(np.arange(11) == 9, 0.2, 1)
    times, q = move(koch, delta, 0.6)
    ref, fast = both(koch, times, q, level="coupled", step=1e-3, dynamics_every=every)
    assert_same(ref, fast)


@needs_numba
def test_plain_ratios_and_rule_step():
    """koch11: diagonal transmission, no friction, the step-size rule's step."""
    model = load_toml(ROBOTS / "koch11.toml")
    times, q = move(
        model, np.linspace(0.05, 0.3, model.n) * np.where(np.arange(11) == 9, 0.2, 1), 0.6
    )
    ref, fast = both(model, times, q, level="coupled")
    assert_same(ref, fast)


@needs_numba
def test_dry_friction_robot_decoupled():
    model = load_toml(ROBOTS / "as6.toml")
    times, q = move(model, np.full(model.n, 0.2), 0.8)
    ref, fast = both(model, times, q, level="decoupled", step=1e-3)
    assert_same(ref, fast)


@needs_numba
def test_decoupled_without_inertial_data(monkeypatch):
    """``[drives] load_inertia`` and no ``[[inertials]]``: the kernel gets empty inertial
    arrays (never refreshed inside) and equals the numpy loop."""
    from .drive_models import dc_drives, planar

    calls = []
    kernel_run = CompiledLoop.run
    monkeypatch.setattr(
        CompiledLoop, "run", lambda self, *a: calls.append(1) or kernel_run(self, *a)
    )

    model = planar(2, drives=dict(dc_drives(2, 30.0), load_inertia=0.5))
    bare = type(model)(model.name, model.joints, extra=model.extra, source="<bare>")
    times = np.linspace(0.0, 0.3, 31)
    q = np.outer((times / 0.3) ** 2 * (3 - 2 * times / 0.3), [0.2, -0.1])
    ref, fast = both(bare, times, q, level="decoupled")
    assert_same(ref, fast)
    assert calls == [1] and ref.axes[0].peak_current > 0.0  # the kernel ran (once)


@needs_numba
def test_steppers_run_the_numpy_loop():
    """Outside the kernels' scope ``accel=True`` is the numpy loop: identical results
    (pwm has its own compiled loop: tests/drives/test_compiled_pwm.py)."""
    l1 = load_toml(ROBOTS / "l1.toml")
    times, q = move(l1, np.full(l1.n, 0.05), 0.3)
    ref, fast = both(l1, times, q, level="coupled")
    for name in FIELDS:
        assert np.array_equal(getattr(ref, name), getattr(fast, name))


def test_the_factory_picks_the_loop(monkeypatch):
    """engine.compiled_loop: the run's accel flag and IRLC_ENGINE decide; the default is
    numpy whatever numba's cache holds (fast first run, same bytes); stepper drives are
    not covered."""
    from irlc.runtime.drives.compiled.pwm_loop import PwmLoop

    class Sim:
        is_dc, pwm, n = True, False, 3
        driven = np.ones(3, dtype=bool)
        axes = np.arange(3)

    available = accel_support.AVAILABLE
    assert engine.compiled_loop(Sim, False) is None
    assert engine.compiled_loop(Sim, True) is (CompiledLoop if available else None)
    monkeypatch.delenv("IRLC_ENGINE", raising=False)
    assert engine.compiled_loop(Sim, None) is None
    monkeypatch.setenv("IRLC_ENGINE", "numpy")
    assert engine.compiled_loop(Sim, None) is None
    assert engine.compiled_loop(Sim, True) is None
    monkeypatch.setenv("IRLC_ENGINE", "auto")
    assert engine.compiled_loop(Sim, None) is (CompiledLoop if available else None)
    Sim.pwm = True
    assert engine.compiled_loop(Sim, None) is (PwmLoop if available else None)
    Sim.is_dc = False  # stepper drives
    assert engine.compiled_loop(Sim, True) is None


def test_first_order_mixed_axes_equal_single_axes():
    """The closed-form armature with some axes reaching the current limit and others not:
    each axis as if alone (the unlimited ones never jump to the limit)."""
    r, ell, ks, i_max, tau = np.full(3, 1.0), np.full(3, 1e-3), np.full(3, 0.1), 10.0, 5e-4
    i0, volts, omega = np.array([9.0, 0.0, -2.0]), np.array([50.0, 5.0, -50.0]), np.zeros(3)
    mixed = motor.first_order(i0, volts, omega, r, ell, ks, tau, i_max)
    assert mixed[0][0] == i_max and mixed[0][2] == -i_max  # clamped
    for a in range(3):
        alone = motor.first_order(
            i0[a : a + 1], volts[a], omega[a], r[a], ell[a], ks[a], tau, i_max
        )
        for x, y in zip(mixed, alone, strict=True):
            assert np.isclose(x[a], y[0], rtol=1e-12, atol=1e-15)
    # the unlimited axis: i(τ) = a + (i0 − a) e^{−τR/L}, a = u/R
    assert np.isclose(mixed[0][1], 5.0 + (0.0 - 5.0) * np.exp(-tau / 1e-3))
