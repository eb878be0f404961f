"""The compiled cycle (runtime/ik/accel.py, numba) equals the numpy reference path.

Both solvers get the same inputs every cycle (the numpy result is fed to both), so each
cycle's mapping is compared on its own: q and the TCP to 1e-10, the same iteration
count (hard cycles; a relaxed cycle stops when its step falls below ~1e-13, a round-off
decision), relaxed / converged / singular flags and the same binding text.
"""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

pytest.importorskip("numba")

from irlc.robots import load_robot
from irlc.runtime.ik import CycleOptions, IKParams, InverseTransformation, intersect_limits
from irlc.runtime.ik import accel as accel_mod
from irlc.runtime.kinematics import Kinematics
from irlc.runtime.obstacles import BoxObstacle, SphereObstacle

pytestmark = pytest.mark.skipif(not accel_mod.AVAILABLE, reason="no numba or IRLC_ENGINE=numpy")


def _pair(model, **params):
    out = []
    for flag in (True, False):
        p = IKParams.for_robot(model, accel=flag, **params)
        out.append(InverseTransformation(model, Kinematics(model), p))
    assert out[0].accelerated and not out[1].accelerated
    return out


def _random_q(model, rng, margin=0.15):
    lo, hi = model.position_limits.T
    lo = np.maximum(lo, -3.0)
    hi = np.minimum(hi, 3.0)
    return lo + (hi - lo) * rng.uniform(margin, 1.0 - margin, size=model.n)


def _compare(model, options, *, seed=0, starts=6, cycles=25, step=0.01, jump=0.0, **params):
    """Random starts, random walks of targets; ``jump`` adds far targets (relaxed)."""
    fast, ref = _pair(model, **params)
    kin = Kinematics(model)
    rng = np.random.default_rng(seed)
    stats = {"relaxed": 0, "bound": 0, "cycles": 0}
    for _ in range(starts):
        q = _random_q(model, rng)
        if fast.coupled is not None:  # a start inside the coupled rows
            while np.any(fast.coupled.A[: fast.coupled.npos] @ q - fast.coupled.b < 0.0):
                q = _random_q(model, rng)
        q_prev = q.copy()
        target = kin.tcp(q)
        for c in range(cycles):
            target = target.copy()
            target[:3, 3] += rng.normal(size=3) * step
            if jump and c % 7 == 3:
                target[:3, 3] += rng.normal(size=3) * jump
            a = fast.step(q, q_prev, target, 0.01, options)
            b = ref.step(q, q_prev, target, 0.01, options)
            assert np.allclose(a.q, b.q, rtol=0.0, atol=1e-10), (c, a.q - b.q)
            assert np.allclose(a.tcp, b.tcp, rtol=0.0, atol=1e-10)
            if not b.relaxed:  # relaxed cycles stop when the step is ~1e-13: round-off
                assert a.iterations == b.iterations
            assert (a.relaxed, a.converged, a.singular) == (b.relaxed, b.converged, b.singular)
            assert a.binding == b.binding
            assert a.active == b.active
            assert abs(a.position_error - b.position_error) < 1e-10
            assert a.clearances.keys() == b.clearances.keys()
            for name, (dist, link) in a.clearances.items():
                assert link == b.clearances[name][1]
                assert abs(dist - b.clearances[name][0]) < 1e-10
            stats["relaxed"] += a.relaxed
            stats["bound"] += bool(a.binding)
            stats["cycles"] += 1
            q_prev, q = q, b.q
    return stats


@pytest.fixture(scope="module")
def robots():
    return {name: load_robot(name) for name in ("koch11", "panda", "planar3", "irb6")}


def _tight(model, scale=0.3):
    speed = model.speed_limits * scale
    accel = model.accel_limits * scale
    return intersect_limits(model, None, speed, accel)


@pytest.mark.parametrize("name", ["koch11", "panda", "planar3"])
def test_default_criterion_equal(robots, name):
    stats = _compare(robots[name], CycleOptions(), jump=0.3)
    assert stats["relaxed"] > 0  # the far targets exercised the relaxed QP too


@pytest.mark.parametrize("name", ["koch11", "panda", "planar3"])
def test_tight_limits_equal(robots, name):
    model = robots[name]
    pos, spd, acc = _tight(model)
    stats = _compare(model, CycleOptions(position=pos, speed=spd, accel=acc), step=0.02, seed=1)
    assert stats["bound"] > 0  # some box bound was active


@pytest.mark.parametrize("name", ["koch11", "panda", "planar3"])
def test_cyclic_and_self_motion_equal(robots, name):
    model = robots[name]
    ref = np.clip(np.array(model.home, dtype=float), *model.position_limits.T)
    _compare(model, CycleOptions(reference=ref), seed=2)
    _compare(model, CycleOptions(reference=ref, self_motion=True), seed=3, step=0.0)


def test_planar3_task_rows_and_scalar_qp_off(robots):
    model = robots["planar3"]
    _compare(model, CycleOptions(), seed=4, jump=1.0)
    _compare(model, CycleOptions(), seed=5, scalar_qp=False)


def test_panda_quadprog_for_the_1d_qp_and_no_warm_start(robots):
    _compare(robots["panda"], CycleOptions(), seed=6, scalar_qp=False, jump=0.2)
    _compare(robots["panda"], CycleOptions(), seed=7, warm_start=False)


def test_irb6_coupled_limits_equal(robots):
    model = robots["irb6"]
    fast, _ = _pair(model)
    assert fast.coupled is not None
    stats = _compare(model, CycleOptions(), seed=8, step=0.02, jump=0.2, starts=8)
    assert stats["cycles"] > 0


def test_frozen_and_avoided_obstacles_fall_back_reported_obstacles_do_not(robots):
    model = robots["koch11"]
    kin = Kinematics(model)
    tcp = kin.tcp(np.array(model.home, dtype=float))
    box = BoxObstacle("box", tcp[:3, 3] + (0.0, 0.0, 0.6), np.array([0.2, 0.2, 0.2]), np.eye(3))
    ball = SphereObstacle("ball", tcp[:3, 3] + (0.5, 0.0, 0.0), 0.1)
    _compare(model, CycleOptions(obstacles=[box, ball]), seed=9, starts=3)  # accelerated
    avoid = CycleOptions(obstacles=[box, ball], active_obstacles=frozenset({"box"}))
    _compare(model, avoid, seed=10, starts=2)  # numpy path in both
    frozen = CycleOptions(frozen={1: float(model.home[1]), 2: float(model.home[2])})
    fast, _ = _pair(model)
    q = np.array(model.home, dtype=float)
    r = fast.step(q, q, kin.tcp(q), 0.01, frozen)
    assert r.q[1] == model.home[1] and r.q[2] == model.home[2]


def test_use_accel_decision(monkeypatch):
    assert accel_mod.use_accel(False) is False
    assert accel_mod.use_accel(True) is True
    monkeypatch.delenv("IRLC_ENGINE", raising=False)
    # the default is numpy whatever numba's cache holds (fast first run, same bytes)
    assert accel_mod.use_accel(None) is False
    monkeypatch.setenv("IRLC_ENGINE", "numpy")
    assert accel_mod.use_accel(None) is False
    assert accel_mod.use_accel(True) is False  # numpy wins over the parameter
    monkeypatch.setenv("IRLC_ENGINE", "compiled")
    assert accel_mod.use_accel(None) is True
    assert accel_mod.use_accel(False) is False
    monkeypatch.setenv("IRLC_ENGINE", "auto")
    assert accel_mod.use_accel(None) is True


def test_irlc_engine_numpy_disables_it():
    code = (
        "from irlc.robots import load_robot\n"
        "from irlc.runtime.ik import IKParams, InverseTransformation, accel\n"
        "from irlc.runtime.kinematics import Kinematics\n"
        "m = load_robot('panda')\n"
        "ik = InverseTransformation(m, Kinematics(m), IKParams(accel=True))\n"
        "print(accel.AVAILABLE, ik.accelerated)\n"
    )
    env = dict(os.environ, IRLC_ENGINE="numpy")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["False", "False"]
