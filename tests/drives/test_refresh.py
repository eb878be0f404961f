"""The adaptive refresh of M(q), C q̇ + G (runtime/drives/refresh.py): the held terms stay
within the documented first-order bound, and the trajectory matches the every-step run."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
from irlc.robots.loader import load_toml
from irlc.runtime.drives import deviation_percent, simulate_drives
from irlc.runtime.drives.refresh import DELTA_Q, DELTA_V, Refresh
from irlc.runtime.model.dynamics import Dynamics

ROBOTS = Path(__file__).resolve().parents[2] / "robots"


def smooth_move(model, delta, duration=1.0):
    times = np.linspace(0.0, duration, 51)
    s = times / duration
    return times, model.home_q() + np.outer(s * s * (3 - 2 * s), delta)


def run(model, times, q, every):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return simulate_drives(
            model, times, q, level="coupled", step=1e-3, hold=0.2, dynamics_every=every
        )


def derivatives(dyn, q, qd, eps=1e-6):
    """Central differences ``∂M/∂q_k``, ``∂h/∂q_k``, ``∂h/∂q̇_k``."""
    n = len(q)
    dm, dhq, dhv = np.empty((n, n, n)), np.empty((n, n)), np.empty((n, n))
    for k in range(n):
        e = np.zeros(n)
        e[k] = eps
        mp, hp = dyn.mass_and_bias(q + e, qd)
        mm, hm = dyn.mass_and_bias(q - e, qd)
        dm[k], dhq[:, k] = (mp - mm) / (2 * eps), (hp - hm) / (2 * eps)
        dhv[:, k] = (dyn.mass_and_bias(q, qd + e)[1] - dyn.mass_and_bias(q, qd - e)[1]) / (2 * eps)
    return dm, dhq, dhv


def test_held_terms_within_the_first_order_bound():
    model = load_toml(ROBOTS / "irb6_track.toml")
    times, q = smooth_move(model, np.array([0.02, 0.15, 0.1, -0.1, 0.15, 0.3]))
    exact = run(model, times, q, 1)
    dyn = Dynamics(model)
    policy = Refresh(None, exact.step, model.n)
    held = None
    checked = 0
    for s in range(0, len(exact.t)):
        qs, vs = exact.q_actual[s], exact.qd_actual[s]
        if policy.due(s, qs, vs):
            policy.mark(s, qs, vs)
            m0, h0 = dyn.mass_and_bias(qs, vs)
            dm, dhq, dhv = derivatives(dyn, qs, vs)
            held = (m0, h0, dm, dhq, dhv)
            continue
        if s % 7:
            continue  # a sample of the held steps keeps the test fast
        m0, h0, dm, dhq, dhv = held
        assert np.abs(qs - policy.q0).max() <= DELTA_Q and np.abs(vs - policy.qd0).max() <= DELTA_V
        m, h = dyn.mass_and_bias(qs, vs)
        bound_m = np.abs(dm).sum(axis=0) * DELTA_Q
        bound_h = np.abs(dhq).sum(axis=1) * DELTA_Q + np.abs(dhv).sum(axis=1) * DELTA_V
        # 20 % + 1 mN·m for the second-order remainder
        assert np.all(np.abs(m - m0) <= 1.2 * bound_m + 1e-3)
        assert np.all(np.abs(h - h0) <= 1.2 * bound_h + 1e-3)
        checked += 1
    assert checked > 20
    assert policy.count < len(exact.t) / 3  # the point: far fewer evaluations


def test_adaptive_run_matches_the_every_step_run():
    model = load_toml(ROBOTS / "irb6_track.toml")
    times, q = smooth_move(model, np.array([0.02, 0.15, 0.1, -0.1, 0.15, 0.3]))
    exact, adaptive = run(model, times, q, 1), run(model, times, q, None)
    assert np.max(deviation_percent(exact, adaptive)) < 0.1  # % of the commanded range
    assert adaptive.could_follow and exact.could_follow


def test_cached_karnopp_step_equals_the_general_loop():
    """The Karnopp fast path (blocks of the held M cached per stuck mask) gives the same
    accelerations, friction and stuck set as the general two-pass loop."""
    from irlc.runtime.drives.mechanics import Mechanics

    model = load_toml(ROBOTS / "irb6_track.toml")
    rng = np.random.default_rng(3)
    plain = Mechanics(model, "coupled", np.full(model.n, 0.5), model.home_q(), None)
    cached = Mechanics(model, "coupled", np.full(model.n, 0.5), model.home_q(), None)
    none = np.zeros(model.n, dtype=bool)
    for _ in range(200):
        q = model.home_q() + rng.uniform(-0.3, 0.3, model.n)
        m, h = plain.terms(q, rng.uniform(-0.5, 0.5, model.n))
        m_inv = cached.inverse(m)
        drive, slide = rng.normal(0, 30, model.n), rng.normal(0, 2, model.n)
        stuck = rng.random(model.n) < 0.5
        static = rng.uniform(0, 40, model.n)
        running = 0.8 * static
        a = plain.accel(m, h, drive, slide, stuck, static, running, none, np.zeros(model.n))
        b = cached.accel(m, h, drive, slide, stuck, static, running, none, np.zeros(model.n), m_inv)
        assert np.allclose(a[0], b[0]) and np.allclose(a[1], b[1])
        assert np.array_equal(a[2], b[2])
