"""The numpy loop's fast paths against their reference paths (issue 14): the fused cascade
(one block matrix on the stacked state) against the element-wise cascade, the PWM period
in one pass against three calls of ``motor.first_order``, and the stacked refresh test
against the per-part one."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from irlc.robots.loader import load_toml
from irlc.runtime.drives.cascade import DcBank
from irlc.runtime.drives.params import drive_params
from irlc.runtime.drives.power_stage import PwmStage
from irlc.runtime.drives.refresh import DELTA_Q, DELTA_V, Refresh

ROBOTS = Path(__file__).resolve().parents[2] / "robots"


def chain():
    return drive_params(load_toml(ROBOTS / "irb6_track.toml")).chain


def test_fused_step_equals_the_element_wise_step_inside_the_limits():
    c = chain()
    m = len(c.kz)
    rng = np.random.default_rng(3)
    for _ in range(20):
        hold = rng.uniform(-0.2, 0.2, m) * c.ks * c.i_max
        fused, plain = DcBank(c, 1e-3, False, hold), DcBank(c, 1e-3, False, hold)
        d = rng.uniform(-0.01, 0.01, m)  # small errors and speeds: no limit reached
        omega = rng.uniform(-0.2, 0.2, m)
        out = fused.fused_step(d, np.zeros(m), omega)
        assert out is not None
        tau, i_mean, u_mean, sat, _, _ = plain.limited_step(d, np.zeros(m), omega)
        assert not sat.any()
        scale = np.abs(i_mean).max() + 1e-3
        assert np.allclose(out[2 * m : 3 * m], i_mean, rtol=1e-12, atol=1e-12 * scale)
        assert np.allclose(out[3 * m : 4 * m], u_mean, rtol=1e-12, atol=1e-12)
        # the state held in z equals the element-wise objects' state
        assert np.allclose(fused.z[2 * m : 3 * m], plain.pi.x, rtol=1e-12, atol=1e-15)
        assert np.allclose(fused.z[3 * m : 4 * m], plain.loop.x[:, 0], rtol=1e-12, atol=1e-15)
        assert np.allclose(fused.z[4 * m :], plain.loop.x[:, 1], rtol=1e-12, atol=1e-12)
        assert np.allclose(tau, c.ks * i_mean)


def test_fused_step_declines_a_limited_step_and_keeps_the_state():
    c = chain()
    m = len(c.kz)
    bank = DcBank(c, 1e-3, False, np.zeros(m))
    before = bank.z.copy()
    big = np.full(m, 50.0)  # the position P output saturates
    assert bank.fused_step(big, np.zeros(m), np.zeros(m)) is None
    assert np.array_equal(bank.z[2 * m :], before[2 * m :])
    # the next step goes element-wise directly, the one after tries again
    assert bank.fused_step(np.zeros(m), np.zeros(m), np.zeros(m)) is None
    assert bank.fused_step(np.zeros(m), np.zeros(m), np.zeros(m)) is not None


def stage(c, i0, u_c):
    s = PwmStage(c.R, c.L, c.ks, c.k, c.kiwzm, c.U, c.i_max, c.pwm_frequency)
    s.i, s.u_c = i0.copy(), u_c.copy()
    return s


def test_pwm_period_in_one_pass_equals_three_first_order_calls():
    c = chain()
    m = len(c.kz)
    rng = np.random.default_rng(5)
    checked = 0
    for _ in range(50):
        i0 = rng.uniform(-0.5, 0.5, m) * c.i_max
        duty = rng.uniform(0.3, 0.7, m)
        omega = rng.uniform(-20.0, 20.0, m)
        s = stage(c, i0, np.zeros(m))
        fast = s._unlimited(duty, omega)
        slow = s._limited(duty, omega)
        if fast is None:  # the current reaches ±i_max somewhere: the limited path applies
            assert slow[4].any() or np.abs(slow[0]).max() >= c.i_max * (1 - 1e-12)
            continue
        checked += 1
        for a, b in zip(fast[:4], slow[:4], strict=True):
            assert np.array_equal(a, b)  # same operations, same bits
        assert not fast[4].any()
    assert checked >= 25


def test_pwm_one_pass_declines_when_the_current_limit_is_reached():
    c = chain()
    m = len(c.kz)
    s = stage(c, np.full(m, 0.95) * c.i_max, np.zeros(m))
    assert s._unlimited(np.ones(m), np.zeros(m)) is None  # full +U from 95 % of i_max
    i, _, _, _, hit = s._limited(np.ones(m), np.zeros(m))
    assert hit.all() and np.allclose(i, c.i_max)


def test_stacked_refresh_test_agrees_with_the_per_part_test():
    n = 4
    rng = np.random.default_rng(7)
    a, b = Refresh(None, 1e-3, n), Refresh(None, 1e-3, n)
    x = np.zeros(2 * n)
    assert a.due(0, x[:n], x[n:]) and b.due_state(0, x)  # nothing computed yet
    a.mark(0, x[:n], x[n:])
    b.mark_state(0, x)
    for s in range(1, 200):
        step = rng.choice([0.5, 0.99, 1.01, 2.0], 2 * n) * rng.choice([-1, 1], 2 * n)
        x = np.concatenate([step[:n] * DELTA_Q, step[n:] * DELTA_V]) * (rng.random() < 0.5)
        assert a.due(s, x[:n], x[n:]) == b.due_state(s, x)
    assert b.due_state(a.max_steps, np.zeros(2 * n))  # the hold time runs out
