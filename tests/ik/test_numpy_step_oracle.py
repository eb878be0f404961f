"""The numpy IPO cycle against an independent computation of the same cycle.

The numpy path (the reference engine) takes the compact QP's unconstrained minimiser
when no box row can bind, skips the braking candidates when they cannot be the least
one, rejects "no joint at a bound" from the least distance to a bound and builds the
TCP Jacobian from two gathers. The oracle below is the cycle of docs/ik.md written out
plainly: the joint box from its formulas (braking always evaluated), ``link_frames`` and
``jacobian_at``, :func:`spatial.pose_error`, and each Newton step as the **full-space**
QP ``min ½ΔθᵀWΔθ + gᵀΔθ  s.t.  JΔθ = −F,  lower ≤ Δθ ≤ upper`` solved by quadprog with
the task rows as equalities (no compact form, no shortcut). Same stopping rules; the
configurations must agree to 1e-12, and the active bounds and the binding constraint
must be the same.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
import quadprog
from irlc.robots import load_robot
from irlc.runtime.ik import CycleOptions, IKParams, InverseTransformation
from irlc.runtime.ik.compact import CompactBasis
from irlc.runtime.ik.limits import (
    SOURCE_NAMES,
    BoxSnapshot,
    JointBox,
    LimitViolationError,
    describe_box_bound,
)
from irlc.runtime.ik.limits import active_codes as fast_active_codes
from irlc.runtime.ik.newton_step import NewtonStep
from irlc.runtime.ik.qp import QuadprogSolver
from irlc.runtime.model import spatial
from irlc.runtime.model.kinematics import Kinematics

ROBOTS = ["koch11", "panda", "mobile8", "planar4"]
DT = 0.01


def plain_box(limits, q_start, q_prev, dt):
    """``(lower, upper, cand)`` of docs/ik.md (Joint box): the four candidates per side,
    braking as ``2R/(1 + √(1 + 2R/ε))``; ``cand`` in the signed layout ``[−lower; upper]``."""
    pos, spd, acc = (np.clip(x, -1e30, 1e30) for x in limits)
    d = q_start - q_prev
    cand = np.empty((4, 2, q_start.size))
    cand[0] = [q_start - pos[:, 0], pos[:, 1] - q_start]
    cand[1] = [-dt * spd[:, 0], dt * spd[:, 1]]
    cand[2] = [-dt * dt * acc[:, 0] - d, dt * dt * acc[:, 1] + d]
    eps = dt * dt * np.abs(acc[:, ::-1].T)
    room = np.maximum(cand[0], 0.0)
    cand[3] = 2.0 * room / (1.0 + np.sqrt(1.0 + room * (2.0 / np.maximum(eps, 1e-300))))
    bound = cand.min(axis=0)
    return -bound[0], bound[1], cand


def plain_codes(delta, lower, upper, cand):
    """Per joint: ``None`` or ``(source, upper side)`` with the tolerance of docs/ik.md."""
    tol = 1e-10 + 1e-9 * np.abs(delta)
    out = {}
    for j in range(delta.size):
        hi = delta[j] >= upper[j] - tol[j]
        if hi or delta[j] <= lower[j] + tol[j]:
            out[j] = (int(np.argmin(cand[:, int(hi), j])), bool(hi))
    return out


def oracle_cycle(model, kin, rows, q_start, q_prev, target, limits, reference=None):
    """The cycle with the full-space QP per Newton step (see the module docstring)."""
    params = IKParams.for_robot(model)
    lower, upper, cand = plain_box(limits, q_start, q_prev, DT)
    w = np.asarray(model.weights, dtype=float)
    theta = q_start + np.clip(q_start - q_prev, lower, upper)  # warm start
    pos_rows, ori_rows = rows[rows < 3], rows[rows >= 3]
    rows_qp = None
    for k in range(params.max_iter + 1):
        frames = kin.link_frames(theta)
        tcp = kin.tcp_from_frames(frames)
        e = spatial.pose_error(tcp, target)
        pe, oe = np.linalg.norm(e[pos_rows]), np.linalg.norm(e[ori_rows])
        converged = pe < params.tol_position and oe < params.tol_orientation
        if k > 0 and (converged or k == params.max_iter):
            break
        J = kin.jacobian_at(frames, tcp[:3, 3])[rows]
        sigma = theta - q_start
        g = w * (theta - reference) if reference is not None else w * sigma
        n, m = model.n, rows.size
        C = np.hstack((J.T, np.eye(n), -np.eye(n)))
        b = np.concatenate((-e[rows], lower - sigma, sigma - upper))
        scale = 1.0 / w.max()
        z, _, _, _, lagr, iact = quadprog.solve_qp(np.diag(w * scale), -g * scale, C, b, m)
        active = iact[iact > m] - 1 - m
        rows_qp = (active, lagr[active + m] / scale)
        theta = theta + z
    return theta, k, converged, (lower, upper, cand), rows_qp


def oracle_binding(model, box, limits, codes, rows_qp):
    """``CycleResult.binding`` from the oracle's QP multipliers and box (docs/ik.md)."""
    lower, upper, cand = box
    snapshot = BoxSnapshot(lower, upper, cand, tuple(np.clip(x, -1e30, 1e30) for x in limits))
    active, mult = rows_qp
    if active.size:
        r = int(active[int(np.argmax(mult))])
        return describe_box_bound(model, snapshot, r % model.n, r >= model.n)
    if codes:
        j = min(codes, key=lambda i: (codes[i][1], i))
        return describe_box_bound(model, snapshot, j, codes[j][1])
    return ""


def random_cycles(model, kin, rng, count):
    """``(q_start, q_prev, target, limits, reference)``: within the limits, moving at up
    to 40 % of the speed limits, the target one cycle ahead; a third with position limits
    pulled in to just beyond the cycle's reach (bounds bind), a third with CYCLIC, a third
    without acceleration limits (mostly free steps)."""
    pos, spd, acc = model.position_limits, model.speed_limits, model.accel_limits
    n = model.n
    for i in range(count):
        span = pos[:, 1] - pos[:, 0]
        q_start = pos[:, 0] + span * rng.uniform(0.25, 0.75, n)
        v = rng.uniform(-0.4, 0.4, n) * np.minimum(spd[:, 1], 2.0)
        q_prev = q_start - v * DT
        step = (v + rng.uniform(-0.05, 0.05, n) * np.minimum(spd[:, 1], 2.0)) * DT
        target = kin.tcp(q_start + step)
        tight, accel = pos.copy(), acc
        reference = None
        if i % 3 == 0:  # no acceleration limits: the step is often free
            accel = np.tile([-np.inf, np.inf], (n, 1))
        elif i % 3 == 1:  # bounds close in on both sides of some joints
            pick = rng.random(n) < 0.4
            tight[pick, 0] = np.maximum(pos[pick, 0], q_start[pick] - 0.3 * np.abs(step[pick]))
            tight[pick, 1] = np.minimum(pos[pick, 1], q_start[pick] + 0.3 * np.abs(step[pick]))
        elif i % 3 == 2:
            reference = q_start + rng.uniform(-0.2, 0.2, n)
        yield q_start, q_prev, target, (tight, spd, accel), reference


@pytest.mark.parametrize("robot", ROBOTS)
def test_numpy_cycle_equals_the_full_space_qp_oracle(robot):
    model = load_robot(robot)
    kin = Kinematics(model)
    ik = InverseTransformation(model, kin, replace(IKParams.for_robot(model), accel=False))
    rows = np.array(ik.params.task_rows)
    rng = np.random.default_rng(20261128)
    compared = binding = 0
    for q_start, q_prev, target, limits, reference in random_cycles(model, kin, rng, 120):
        opts = CycleOptions(position=limits[0], accel=limits[2], reference=reference)
        try:
            res = ik.step(q_start, q_prev, target, DT, opts)
        except LimitViolationError:  # too fast for the pulled-in limit: no box
            continue
        if res.relaxed or not res.converged:
            continue  # (the bounds left no exact step: not what this test compares)
        theta, iterations, converged, box, rows_qp = oracle_cycle(
            model, kin, rows, q_start, q_prev, target, limits, reference
        )
        np.testing.assert_allclose(res.q, theta, rtol=0.0, atol=1e-12)
        assert res.iterations == iterations and converged
        codes = plain_codes(theta - q_start, *box)
        labels = {j: f"{SOURCE_NAMES[s]} {'max' if hi else 'min'}" for j, (s, hi) in codes.items()}
        assert res.active == labels
        assert res.binding == oracle_binding(model, box, limits, codes, rows_qp)
        compared += 1
        binding += res.binding != ""
    assert compared >= 50 and binding >= 20 and compared - binding >= 20


def step_instances(rng, n, m, count):
    """``(J, F, w, g, lower, upper)``: a well-conditioned ``J``, weights in 0.5…2, a box
    of ±0.05…0.5 around zero that often cuts the unconstrained step off."""
    for _ in range(count):
        U, _, Vt = np.linalg.svd(rng.normal(size=(m, n)), full_matrices=False)
        J = U @ np.diag(rng.uniform(0.5, 2.0, m)) @ Vt
        w = rng.uniform(0.5, 2.0, n)
        g = rng.normal(size=n) * 0.3
        F = rng.normal(size=m) * 0.05
        yield J, F, w, g, -rng.uniform(0.05, 0.5, n), rng.uniform(0.05, 0.5, n)


@pytest.mark.parametrize("n,m", [(11, 6), (8, 6), (9, 3)])
def test_hard_diagonal_equals_the_full_space_qp(n, m):
    """One Newton step: the compact QP (shortcut or quadprog) against quadprog on the
    full-space QP with ``JΔθ = −F`` as equalities — same step to 1e-12, same active
    rows; both branches of the shortcut are exercised. (A basis kept from an earlier J,
    as in a cycle, only has its pivot spread bounded by ``cond_max``: the rounding then
    grows with it, for quadprog on the compact QP as for the shortcut.)"""
    rng = np.random.default_rng(n * 100 + m)
    free = bound = 0
    for J, F, w, g, lower, upper in step_instances(rng, n, m, 300):
        step = NewtonStep(QuadprogSolver(), basis=CompactBasis())  # (a basis chosen for J)
        out = step.hard_diagonal(J, F, w, g, np.array([lower, upper]))
        C = np.hstack((J.T, np.eye(n), -np.eye(n)))
        b = np.concatenate((-F, lower, -upper))
        try:
            z, _, _, _, _, iact = quadprog.solve_qp(np.diag(w), -g, C, b, m)
        except ValueError:
            assert out is None
            continue
        assert out is not None
        np.testing.assert_allclose(out.dtheta, z, rtol=0.0, atol=1e-12)
        assert sorted(out.active.tolist()) == sorted((iact[iact > m] - 1 - m).tolist())
        free += out.active.size == 0
        bound += out.active.size > 0
    assert free >= 20 and bound >= 20


def test_box_with_braking_skipped_equals_the_plain_formulas():
    """The box and its candidates are bit for bit the plain formulas', whether the
    braking candidates were computed with the box or skipped as unable to bind (then
    computed when ``cand`` is read)."""
    skipped = computed = 0
    for robot in ["koch11", "panda", "mobile8", "l1", "irb6"]:
        model = load_robot(robot)
        rng = np.random.default_rng(7)
        box = JointBox(model.n)
        limits = (model.position_limits, model.speed_limits, model.accel_limits)
        pos, spd = limits[0], limits[1]
        for _ in range(400):
            near = rng.uniform(size=model.n) ** rng.choice([1, 8])  # often at a limit
            side = rng.random(model.n) < 0.5
            span = pos[:, 1] - pos[:, 0]
            q = np.where(side, pos[:, 1] - 0.5 * span * near, pos[:, 0] + 0.5 * span * near)
            v = rng.uniform(-0.9, 0.9, model.n) * np.minimum(np.abs(spd).min(axis=1), 10.0)
            q_prev = q - v * DT
            try:
                box.prepare(model, q, q_prev, DT, *limits)
            except Exception:  # the limits exclude this state (tested elsewhere)
                continue
            lower, upper, cand = plain_box(limits, q, q_prev, DT)
            assert np.array_equal(box.lower_d, lower) and np.array_equal(box.upper_d, upper)
            assert np.array_equal(box.cand, cand)  # (braking values computed when read)
            skip = np.all(cand[0] >= box.constants(*limits, DT).brake_free)
            skipped += skip
            computed += not skip
    assert skipped > 100 and computed > 100


def test_active_codes_equal_the_per_joint_comparisons():
    rng = np.random.default_rng(11)
    found = 0
    for _ in range(2000):
        n = 9
        cand = rng.uniform(0.0, 1.0, size=(4, 2, n))
        bounds = np.stack((-cand[:, 0].min(axis=0), cand[:, 1].min(axis=0)))
        pick = rng.integers(0, 6, n)
        near = np.where(pick == 0, bounds[0], np.where(pick == 1, bounds[1], 0.0))
        jitter = rng.choice([0.0, 1e-11, -1e-11, 3e-10, 1e-9], n)
        delta = np.where(pick < 2, near + jitter, rng.uniform(-0.5, 0.5, n) * 1e-3)
        codes = fast_active_codes(delta, bounds, cand)
        plain = plain_codes(delta, bounds[0], bounds[1], cand)
        assert (codes is None) == (not plain)
        if codes is not None:
            found += 1
            expected = np.zeros(n, dtype=np.int8)
            for j, (s, hi) in plain.items():
                expected[j] = 1 + 2 * s + int(hi)
            assert np.array_equal(codes, expected)
    assert found > 500


def test_oracle_is_not_trivially_the_same_code():
    """Guard: the oracle's box formulas match the definition at one hand-made state."""
    q, q_prev = np.array([0.9]), np.array([0.85])
    pos, spd, acc = np.array([[-1.0, 1.0]]), np.array([[-10.0, 10.0]]), np.array([[-50.0, 50.0]])
    lower, upper, _ = plain_box((pos, spd, acc), q, q_prev, 0.01)
    eps = 50.0 * 1e-4
    brake = -eps + math.sqrt(eps * eps + 2.0 * eps * 0.1)
    assert upper[0] == pytest.approx(min(0.1, 0.1, 0.005 + 0.05, brake), rel=1e-12)
    assert lower[0] == pytest.approx(max(-1.9, -0.1, -0.005 + 0.05), rel=1e-12)
