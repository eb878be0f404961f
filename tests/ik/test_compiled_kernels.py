"""Each compiled IK kernel (runtime/ik/compiled/) against its numpy reference, on
known cases (closed forms) and randomized inputs, so that a difference points at one
function. The kernels take only the public packed data: ``Kinematics.chain_data``
(:class:`ChainData`) and the box constants' ``data`` (:class:`BoxData`)."""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("numba")

from irlc.robots import load_robot
from irlc.runtime.accel_support import AVAILABLE
from irlc.runtime.ik.compact import CompactBasis, compact_box_qp
from irlc.runtime.ik.compiled import layout as L
from irlc.runtime.ik.compiled.box import active_codes, joint_box
from irlc.runtime.ik.compiled.chain import (
    evaluate,
    forward_chain,
    matmul44,
    pose_error,
    tcp_jacobian,
)
from irlc.runtime.ik.compiled.cycle import apply_z, general_cost, inputs_finite, reduce_frozen
from irlc.runtime.ik.compiled.qp import (
    compact_rest,
    hard_data,
    hard_data_general,
    relaxed_data,
    row_terms,
    scalar_qp,
    split,
    square_step,
    unconstrained_qp,
)
from irlc.runtime.ik.cyclic import CyclicReference
from irlc.runtime.ik.limits import JointBox
from irlc.runtime.ik.newton_step import NewtonStep, with_rows
from irlc.runtime.ik.obstacle import ObstacleTerm
from irlc.runtime.ik.params import ObstacleParams
from irlc.runtime.ik.qp import QuadprogSolver
from irlc.runtime.ik.state import IterationState
from irlc.runtime.ik.weighted import WeightedDisplacement
from irlc.runtime.model import spatial
from irlc.runtime.model.kinematics import Kinematics

from .ik_robots import planar_arm

pytestmark = pytest.mark.skipif(not AVAILABLE, reason="numba disabled")
ROBOTS = ("koch11", "panda", "mobile8", "irb6")


@pytest.fixture(scope="module")
def robots():
    return {name: load_robot(name) for name in ROBOTS}


def _random_q(model, rng):
    lo, hi = np.clip(model.position_limits, -3.0, 3.0).T
    return lo + (hi - lo) * rng.uniform(0.1, 0.9, size=model.n)


def _fk(kin, q):
    data = kin.chain_data
    frames = np.empty((kin.n + 1, 4, 4))
    forward_chain(data.basis, data.joints, data.ends[0], q, frames, np.empty((4, 4)))
    tcp = np.empty((4, 4))
    matmul44(frames[-1], data.ends[1], tcp)
    return frames, tcp


# ---------------------------------------------------------------------- chain and TCP
def test_chain_planar_closed_form():
    """Planar 3R, unit links: x = Σ cos(q1 + … + qi), y likewise, yaw = Σ q."""
    kin = Kinematics(planar_arm(3))
    q = np.array([0.3, -1.1, 0.7])
    _, tcp = _fk(kin, q)
    c = np.cumsum(q)
    assert np.allclose(tcp[:3, 3], [np.cos(c).sum(), np.sin(c).sum(), 0.0], atol=1e-14)
    assert math.isclose(math.atan2(tcp[1, 0], tcp[0, 0]), c[-1], abs_tol=1e-14)


@pytest.mark.parametrize("name", ROBOTS)
def test_chain_random(robots, name):
    model = robots[name]
    kin = Kinematics(model)
    rng = np.random.default_rng(1)
    for _ in range(50):
        q = _random_q(model, rng)
        frames, tcp = _fk(kin, q)
        assert np.allclose(frames, kin.link_frames(q), rtol=0.0, atol=1e-13)
        assert np.allclose(tcp, kin.tcp(q), rtol=0.0, atol=1e-13)


def test_chain_data_is_read_only_and_follows_the_tool(robots):
    kin = Kinematics(robots["koch11"])
    data = kin.chain_data
    for a in (data.basis, data.joints, data.ends):
        assert not a.flags.writeable
    assert kin.chain_data is data  # cached
    tool = np.eye(4)
    tool[2, 3] = 0.25
    kin.tool = tool
    assert kin.chain_data is not data
    assert np.allclose(kin.chain_data.ends[1], robots["koch11"].flange @ tool)


# ---------------------------------------------------------------------- Jacobian
def test_jacobian_planar_closed_form():
    """Planar 2R, unit links: ∂x/∂q1 = −y, ∂y/∂q1 = x; ∂x/∂q2 = −sin(q1+q2), …"""
    kin = Kinematics(planar_arm(2))
    q = np.array([0.4, 0.9])
    frames, tcp = _fk(kin, q)
    out = np.empty((6, 2))
    tcp_jacobian(frames, kin.chain_data.joints, tcp[:3, 3].copy(), out)
    x, y = tcp[0, 3], tcp[1, 3]
    s12, c12 = math.sin(q.sum()), math.cos(q.sum())
    expect = np.array([[-y, -s12], [x, c12], [0, 0], [0, 0], [0, 0], [1, 1]])
    assert np.allclose(out, expect, atol=1e-14)


@pytest.mark.parametrize("name", ROBOTS)
def test_jacobian_random(robots, name):
    """Against Kinematics.jacobian_at and a finite difference of the TCP position."""
    model = robots[name]
    kin = Kinematics(model)
    rng = np.random.default_rng(2)
    out = np.empty((6, model.n))
    for _ in range(30):
        q = _random_q(model, rng)
        frames, tcp = _fk(kin, q)
        tcp_jacobian(frames, kin.chain_data.joints, tcp[:3, 3].copy(), out)
        assert np.allclose(out, kin.jacobian_at(frames, tcp[:3, 3]), rtol=0.0, atol=1e-13)
    h = 1e-6
    fd = np.column_stack([(kin.tcp(q + h * e)[:3, 3] - kin.tcp(q - h * e)[:3, 3]) / (2 * h)
                          for e in np.eye(model.n)])  # fmt: skip
    assert np.allclose(out[:3], fd, atol=1e-7)


# ---------------------------------------------------------------------- pose error
def _pose_error(t, d):
    e = np.empty(6)
    pose_error(t, d, e)
    return e


def test_pose_error_known_rotations():
    d = np.eye(4)
    t = spatial.transform(spatial.rot_z(0.3), (0.1, -0.2, 0.05))
    assert np.allclose(_pose_error(t, d), [0.1, -0.2, 0.05, 0.0, 0.0, 0.3], atol=1e-15)
    half = spatial.transform(spatial.rot_x(math.pi), (0.0, 0.0, 0.0))
    e = _pose_error(half, d)
    assert np.allclose(np.abs(e[3:]), [math.pi, 0.0, 0.0], atol=1e-12)
    assert np.allclose(_pose_error(d, d), 0.0)


def test_pose_error_random_including_near_half_turns():
    """Random poses; a third of them within 1e-9 … 1e-3 rad of a half turn, where both
    forms are ill-conditioned (for π − θ > 1e-4, ``θ/(2 sin θ)·w`` with ``w = O(π − θ)``
    amplifies a rounding of ``w`` by ≈ 1/(π − θ)²; closer, ``acos`` of the trace by
    ≈ 1/(π − θ)): there the tolerance grows accordingly."""
    rng = np.random.default_rng(3)
    for i in range(300):
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        gap = 10.0 ** rng.uniform(-9, -3) if i % 3 == 0 else None
        angle = math.pi - gap if gap else rng.uniform(0, 3)
        tol = 1e-12
        if gap:
            tol += 4e-16 / gap**2 if gap > 1e-4 else 4e-15 / gap
        d = spatial.transform(spatial.rot_z(rng.uniform(-3, 3)), rng.normal(size=3))
        t = d.copy()
        t[:3, :3] = spatial.axis_angle(axis, angle) @ d[:3, :3]
        t[:3, 3] += rng.normal(size=3)
        assert np.allclose(_pose_error(t, d), spatial.pose_error(t, d), rtol=0, atol=tol)


# ---------------------------------------------------------------------- joint box
def _kernel_box(box, c, q_start, q_prev):
    n = q_start.shape[0]
    cand, bounds = np.empty((4, 2, n)), np.empty((2, n))
    data = c.data
    ok = joint_box(data.signed, data.accel_bounded, data.dtol, q_start, q_prev, cand, bounds)
    return ok, cand, bounds


def test_box_known_case():
    """|θ| ≤ 1, |θ̇| ≤ 2, no acceleration limit, at rest in the middle: ±Δt·2."""
    model = planar_arm(2)
    box = JointBox(2)
    pos = np.array([[-1.0, 1.0]] * 2)
    spd = np.array([[-2.0, 2.0]] * 2)
    acc = np.array([[-np.inf, np.inf]] * 2)
    c = box.constants(pos, spd, acc, 0.01)
    q = np.zeros(2)
    ok, _, bounds = _kernel_box(box, c, q, q)
    assert ok and np.allclose(bounds, [[-0.02, -0.02], [0.02, 0.02]], atol=1e-17)
    box.prepare(model, q, q, 0.01, pos, spd, acc)
    assert np.array_equal(bounds, box.bounds)


@pytest.mark.parametrize("scale", [1.0, 0.3])
def test_box_random(robots, scale):
    model = robots["koch11"]
    box = JointBox(model.n)
    pos, spd, acc = model.position_limits, model.speed_limits * scale, model.accel_limits * scale
    rng = np.random.default_rng(4)
    dt = 0.01
    for _ in range(100):
        q = _random_q(model, rng)
        d = rng.uniform(-0.5, 0.5, size=model.n) * spd[:, 1] * dt
        c = box.constants(pos, spd, acc, dt)
        ok, cand, bounds = _kernel_box(box, c, q, q - d)
        box.prepare(model, q, q - d, dt, pos, spd, acc)
        assert ok
        assert np.allclose(bounds, box.bounds, rtol=0.0, atol=1e-15)
        assert np.allclose(cand, box.cand, rtol=0.0, atol=1e-15)
    q = pos[:, 1] + 1e-3  # outside: the kernel defers to the Python check
    assert not _kernel_box(box, c, q, q)[0]


# ---------------------------------------------------------------------- compact split
def _kernel_split(J, F, perm, cond_limit=1e10):
    m, n = J.shape
    fst = np.zeros(L.N_FST)
    fst[L.COND_LIMIT] = cond_limit
    aug, N, dp = np.empty((m, n + 1)), np.empty((n, n - m)), np.empty(n)
    ok = split(J, F, perm.astype(np.int64), aug, N, dp, fst)
    return ok, dp, N, fst[L.COND]


def test_split_known_case():
    """J = [I | X]: Δθ_p = [−F; 0], N = [−X; I]."""
    X = np.array([[1.0, 2.0], [3.0, 4.0]])
    J = np.hstack((np.eye(2), X))
    F = np.array([0.5, -0.25])
    ok, dp, N, _ = _kernel_split(J, F, np.arange(4))
    assert ok
    assert np.allclose(dp, [-0.5, 0.25, 0.0, 0.0])
    assert np.allclose(N, np.vstack((-X, np.eye(2))))


def test_split_random_against_compact_basis():
    rng = np.random.default_rng(5)
    for m, n in ((6, 11), (6, 7), (2, 3), (6, 6)):
        for _ in range(20):
            J = rng.normal(size=(m, n))
            F = rng.normal(size=m)
            basis = CompactBasis()
            dp_ref, N_ref = basis.split(J, F)
            ok, dp, N, cond = _kernel_split(J, F, basis.columns)
            assert ok
            assert np.allclose(dp, dp_ref, rtol=0, atol=1e-10)
            assert np.allclose(N, N_ref, rtol=0, atol=1e-10)
            assert np.allclose(J @ dp, -F, atol=1e-10) and np.allclose(J @ N, 0, atol=1e-10)
            assert math.isclose(cond, basis.cond, rel_tol=1e-9)
    J = np.ones((2, 3))  # rank 1: the pivot spread is infinite
    assert not _kernel_split(J, np.ones(2), np.arange(3))[0]


# ---------------------------------------------------------------------- QP steps
def _workspace(n, w, g, dp, lower, upper):
    V = np.zeros((L.NV, n))
    V[L.W], V[L.G], V[L.DP], V[L.LOWER], V[L.UPPER] = w, g, dp, lower, upper
    return V


def test_scalar_qp_known_and_random():
    """One null-space direction: min ½h z² + g̃ z clipped to the box (closed form), and
    random cases against NewtonStep._scalar_qp."""
    n = 3
    col = np.array([1.0, -1.0, 2.0])
    w, g, dp = np.ones(n), np.zeros(n), np.array([0.0, 0.0, -0.3])
    lower, upper = np.full(n, -1.0), np.full(n, 1.0)
    N = col[:, None].copy()
    V = _workspace(n, w, g, dp, lower, upper)
    active, mult, ist = np.zeros(2 * n, np.int64), np.zeros(2 * n), np.zeros(L.N_IST, np.int64)
    assert scalar_qp(V, N, active, mult, ist) == 1
    z = -(col @ (w * dp)) / (col @ (w * col))  # = 0.6 / 6 = 0.1, inside
    assert np.allclose(V[L.DTHETA], dp + z * col) and ist[L.N_ACTIVE] == 0
    rng = np.random.default_rng(6)
    step = NewtonStep(QuadprogSolver())
    step._zb, step._zlo, step._zhi = np.empty((2, n)), np.empty(n), np.empty(n)
    for _ in range(200):
        col = rng.normal(size=n)
        w, g, dp = rng.uniform(0.5, 2, n), rng.normal(size=n), rng.normal(size=n) * 0.1
        lower, upper = -rng.uniform(0, 0.3, n), rng.uniform(0, 0.3, n)
        V = _workspace(n, w, g, dp, lower, upper)
        res = scalar_qp(V, col[:, None].copy(), active, mult, ist)
        ref = step._scalar_qp(dp, col, w, g, np.stack((lower, upper)))
        if ref is None:
            assert res == 0
            continue
        assert res == 1
        assert np.allclose(V[L.DTHETA], ref.dtheta, rtol=0, atol=1e-14)
        cnt = ist[L.N_ACTIVE]
        assert list(active[:cnt]) == list(ref.active)
        assert np.allclose(mult[:cnt], ref.multipliers, rtol=1e-12)


def test_hard_data_against_compact_box_qp():
    """The compact QP data (H̃ = NᵀWN, g̃ = Nᵀ(g + WΔθ_p), box columns) scaled to
    max diag H̃ = 1, against compact.compact_box_qp."""
    rng = np.random.default_rng(7)
    m, n = 6, 11
    for _ in range(20):
        J, F = rng.normal(size=(m, n)), rng.normal(size=m)
        basis = CompactBasis()
        dp, N = basis.split(J, F)
        w, g = rng.uniform(0.5, 3, n), rng.normal(size=n)
        lower, upper = -rng.uniform(0, 1, n), rng.uniform(0, 1, n)
        V = _workspace(n, w, g, dp, lower, upper)
        nz = n - m
        Ht, gt, Ct, bt = np.empty((nz, nz)), np.empty(nz), np.empty((nz, 2 * n)), np.empty(2 * n)
        fst = np.zeros(L.N_FST)
        A, bd = np.zeros((0, n)), np.zeros(0)
        hard_data(V, N.copy(), basis.columns.astype(np.int64), m, A, bd, Ht, gt, Ct, bt, fst)
        H_ref, g_ref, C_ref, b_ref = compact_box_qp(np.diag(w), g, dp, N, lower, upper)
        s = 1.0 / H_ref.diagonal().max()
        assert math.isclose(fst[L.SCALE], s, rel_tol=1e-12)
        assert np.allclose(Ht, H_ref * s, rtol=0, atol=1e-12)
        assert np.allclose(gt, -g_ref * s, rtol=0, atol=1e-12)
        assert np.allclose(Ct, C_ref) and np.allclose(bt, b_ref)


def test_relaxed_data_box_only():
    """``JᵀJ + W/ρ`` and ``−(JᵀF + g/ρ)``, ``ρ = relax_weight·max w``."""
    rng = np.random.default_rng(8)
    m, n = 6, 7
    J, F = rng.normal(size=(m, n)), rng.normal(size=m)
    w, g = rng.uniform(0.5, 3, n), rng.normal(size=n)
    V = _workspace(n, w, g, np.zeros(n), -np.ones(n), np.ones(n))
    Hr, gr, bt = np.empty((n, n)), np.empty(n), np.empty(2 * n)
    fst = np.zeros(L.N_FST)
    fst[L.RELAX_W] = 1e6
    relaxed_data(V, J, F, np.zeros((0, n)), np.zeros(0), np.zeros((n, n)), False, Hr, gr,
                    bt, fst)  # fmt: skip
    rho = 1e6 * w.max()
    assert np.allclose(Hr, J.T @ J + np.diag(w / rho), rtol=0, atol=1e-12)
    assert np.allclose(gr, -(J.T @ F + g / rho), rtol=0, atol=1e-12)
    assert fst[L.SCALE] == rho
    assert np.allclose(bt, np.concatenate((-np.ones(n), -np.ones(n))))


# ---------------------------------------------------------------------- the general cost
def _spd(rng, n):
    a = rng.normal(size=(n, n))
    return a @ a.T + n * np.eye(n)


def test_general_cost_against_the_criteria():
    """CYCLIC + a_conf·W + two obstacle terms (one of weight 0): g and H as the numpy
    criteria accumulate them (InverseTransformation._cost)."""
    rng = np.random.default_rng(9)
    n = 7
    w, ref = rng.uniform(0.5, 3, n), rng.normal(size=n)
    theta, start = rng.normal(size=n), rng.normal(size=n)
    state = IterationState(theta, start, theta - start)
    params = ObstacleParams()
    terms = [ObstacleTerm(rng.normal(size=(3, n)), np.array([0.0, 0.6, 0.8]), d, params)
             for d in (0.1, 0.6)]  # fmt: skip
    assert terms[0].weight > 0.0 and terms[1].weight == 0.0
    criteria = [CyclicReference(w, ref), WeightedDisplacement(w, params.a_conf), *terms]
    g_ref, H_ref = np.zeros(n), np.zeros((n, n))
    for c in criteria:
        c.accumulate(state, g_ref, H_ref)
    V = np.zeros((L.NV, n))
    V[L.W], V[L.WC], V[L.SIGMA] = w, params.a_conf * w, state.sigma
    V[L.G] = w * (theta - ref)
    H = np.empty((n, n))
    general_cost(V, H, np.array([t.weight for t in terms]), np.array([t.push for t in terms]),
                    np.array([t.jac for t in terms]), np.array([t.jtj for t in terms]))  # fmt: skip
    assert np.allclose(V[L.G], g_ref, rtol=0, atol=1e-13)
    assert np.allclose(H, H_ref, rtol=0, atol=1e-13)


def test_hard_data_general_with_coupled_rows():
    """Full H with coupled rows: compact_box_qp + with_rows (NewtonStep.hard), scaled."""
    rng = np.random.default_rng(10)
    m, n, r = 3, 7, 2
    for _ in range(20):
        J, F = rng.normal(size=(m, n)), rng.normal(size=m)
        basis = CompactBasis()
        dp, N = basis.split(J, F)
        H, g = _spd(rng, n), rng.normal(size=n)
        lower, upper = -rng.uniform(0, 1, n), rng.uniform(0, 1, n)
        A, bound_d, sigma = rng.normal(size=(r, n)), -rng.uniform(0, 1, r), rng.normal(size=n)
        V = _workspace(n, np.ones(n), g, dp, lower, upper)
        V[L.SIGMA] = sigma
        nz = n - m
        Ht, gt = np.empty((nz, nz)), np.empty(nz)
        Ct, bt = np.empty((nz, 2 * n + r)), np.empty(2 * n + r)
        fst = np.zeros(L.N_FST)
        hard_data_general(V, N.copy(), H, A, bound_d, Ht, gt, Ct, bt, fst)
        H_ref, g_ref, C_ref, b_ref = compact_box_qp(H, g, dp, N, lower, upper)
        C_ref, b_ref = with_rows(C_ref, b_ref, A, bound_d - A @ sigma, dp, N)
        s = 1.0 / H_ref.diagonal().max()
        assert np.allclose(Ht, H_ref * s, rtol=0, atol=1e-12)
        assert np.allclose(gt, -g_ref * s, rtol=0, atol=1e-12)
        assert np.allclose(Ct, C_ref, atol=1e-13) and np.allclose(bt, b_ref, atol=1e-13)


def test_relaxed_data_general():
    """``(H + ρJᵀJ)s``, ``−(g + ρJᵀF)s`` (NewtonStep.relaxed; solve_ct's scaling)."""
    rng = np.random.default_rng(11)
    m, n = 6, 9
    J, F = rng.normal(size=(m, n)), rng.normal(size=m)
    H, g = _spd(rng, n), rng.normal(size=n)
    V = _workspace(n, np.ones(n), g, np.zeros(n), -np.ones(n), np.ones(n))
    Hr, gr, bt = np.empty((n, n)), np.empty(n), np.empty(2 * n)
    fst = np.zeros(L.N_FST)
    fst[L.RELAX_W] = 1e6
    relaxed_data(V, J, F, np.zeros((0, n)), np.zeros(0), H, True, Hr, gr, bt, fst)
    rho = 1e6 * H.diagonal().max()
    H_ref = H + rho * (J.T @ J)
    s = 1.0 / H_ref.diagonal().max()
    assert np.allclose(Hr, H_ref * s, rtol=0, atol=1e-12)
    assert np.allclose(gr, -(g + rho * (J.T @ F)) * s, rtol=0, atol=1e-12)
    assert math.isclose(fst[L.SCALE], 1.0 / s, rel_tol=1e-14)


def test_reduce_freeze():
    """FREEZE: c = θ⁰ − θ_k; F + J_fz c; J_free; g_free + H_free,fz c; H_free,free; the
    coupled rows' right side (InverseTransformation._solve); c beyond the box: False."""
    rng = np.random.default_rng(12)
    m, n, r = 3, 6, 2
    free, fz = np.array([0, 2, 3, 5]), np.array([1, 4])
    J, F, H = rng.normal(size=(m, n)), rng.normal(size=m), _spd(rng, n)
    A, bound_d = rng.normal(size=(r, n)), -rng.uniform(0, 1, r)
    V = np.zeros((L.NV, n))
    V[L.THETA], V[L.SIGMA], V[L.G] = (
        rng.normal(size=n),
        rng.normal(size=n) * 0.01,
        rng.normal(size=n),
    )
    V[L.LOWER], V[L.UPPER] = -np.ones(n), np.ones(n)
    targets = V[L.THETA, fz] + np.array([0.01, -0.02])
    nf = free.size
    Vr, Jr, Fr, Hr = np.zeros((L.NV, nf)), np.empty((m, nf)), np.empty(m), np.empty((nf, nf))
    Ar, bound_r = np.empty((r, nf)), np.empty(r)
    args = (J, F, H, A, bound_d, free, fz, targets, Vr, Jr, Fr, Hr, Ar, bound_r)
    assert reduce_frozen(V, *args)
    c = targets - V[L.THETA, fz]
    assert np.allclose(V[L.CFZ, :2], c)
    assert np.allclose(Fr, F + J[:, fz] @ c) and np.array_equal(Jr, J[:, free])
    assert np.allclose(Vr[L.G], V[L.G, free] + H[np.ix_(free, fz)] @ c)
    assert np.array_equal(Hr, H[np.ix_(free, free)]) and np.array_equal(Ar, A[:, free])
    b_numpy = bound_d - A @ V[L.SIGMA] - A[:, fz] @ c  # ineq_f's right side
    assert np.allclose(bound_r - Ar @ Vr[L.SIGMA], b_numpy, atol=1e-14)
    V[L.UPPER, 1] = 0.005  # the held value is 0.01 away: beyond one cycle's box
    assert not reduce_frozen(V, *args)


def test_active_codes_against_limits():
    """Which bound each joint's displacement touches (``limits.active_codes``): random
    boxes with joints placed exactly at, near and inside their bounds."""
    from irlc.runtime.ik import limits

    rng = np.random.default_rng(13)
    n = 9
    for _ in range(200):
        cand = rng.uniform(0.0, 1.0, size=(4, 2, n))
        bounds = np.stack((-cand[:, 0].min(axis=0), cand[:, 1].min(axis=0)))
        pick = rng.integers(0, 4, n)
        delta = np.where(pick == 0, bounds[0], np.where(pick == 1, bounds[1], 0.0))
        delta += np.where(pick == 2, 1e-11, 0.0)  # within the tolerance of zero …
        q_start = rng.normal(size=n)
        codes = np.zeros(n, dtype=np.int64)
        found = active_codes(q_start + delta, q_start, bounds, cand, codes)
        ref = limits.active_codes((q_start + delta) - q_start, bounds, cand)
        assert found == (ref is not None)
        if ref is not None:
            assert np.array_equal(codes, ref)


def test_unconstrained_qp_against_quadprog():
    """The compact QP when nothing binds: quadprog's z and an empty active set; a binding
    or barely satisfied constraint, or an indefinite H, defers to quadprog (False)."""
    import quadprog

    rng = np.random.default_rng(14)
    hits = 0
    for _ in range(300):
        nz, nc = 5, 22
        H = _spd(rng, nz)
        a, C = rng.normal(size=nz), rng.normal(size=(nz, nc))
        b = -rng.uniform(0.0, 3.0, nc)
        z = np.empty(nz)
        ok = unconstrained_qp(H, a, C, b, z)
        ref, _, _, _, _, iact = quadprog.solve_qp(H, a, C, b, 0)
        if ok:
            hits += 1
            assert np.allclose(z, ref, rtol=0, atol=1e-12) and not np.any(iact > 0)
        else:
            assert np.any(C.T @ ref - b <= 1e-12 * (1 + np.abs(b)))  # something binds
    assert 50 < hits < 300
    H = np.diag([1.0, -1.0])
    assert not unconstrained_qp(H, np.ones(2), np.eye(2), -np.ones(2), np.empty(2))
    C, b = np.eye(2), np.array([0.5, -1.0])  # z = (0.5, ·): exactly on the first bound
    assert not unconstrained_qp(np.eye(2), np.array([0.5, 0.0]), C, b, np.empty(2))


# ---------------------------------------------------------------------- the rest, one each
def test_evaluate_against_fk_and_the_task_error(robots):
    """FK, TCP, the task error (all six components) and its norms over the task rows, at
    random configurations and targets, against Kinematics and spatial.pose_error."""
    rng = np.random.default_rng(21)
    for name, rows in (("koch11", (0, 1, 2, 3, 4, 5)), ("panda", (0, 1, 2, 5)), ("irb6", (2, 4))):
        model = robots[name]
        kin, n = Kinematics(model), model.n
        data = kin.chain_data
        rows_a = np.array(rows, dtype=np.int64)
        for _ in range(30):
            q = _random_q(model, rng)
            target = kin.tcp(_random_q(model, rng))
            V, ist, fst = np.zeros((L.NV, n)), np.zeros(L.N_IST_ALL, np.int64), np.zeros(L.N_FST)
            V[L.THETA] = q
            ist[L.NPOS] = int(np.sum(rows_a < 3))
            frames, tcp = np.empty((n + 1, 4, 4)), np.empty((4, 4))
            evaluate(data.basis, data.joints, data.ends, target, frames, np.empty((4, 4)), tcp,
                     rows_a, V, ist, fst)  # fmt: skip
            np.testing.assert_allclose(frames, kin.chain(q), rtol=0, atol=1e-12)
            np.testing.assert_allclose(tcp, kin.tcp(q), rtol=0, atol=1e-12)
            e = spatial.pose_error(kin.tcp(q), target)  # (ill-conditioned near half turns)
            np.testing.assert_array_equal(fst[L.E0 : L.E0 + 6], _pose_error(tcp, target))
            np.testing.assert_allclose(fst[L.E0 : L.E0 + 6], e, rtol=0, atol=1e-9)
            e6 = fst[L.E0 : L.E0 + 6]  # the norms over the task's position / orientation rows
            pos = [r for r in rows if r < 3]
            ori = [r for r in rows if r >= 3]
            assert fst[L.PE] == pytest.approx(np.linalg.norm(e6[pos]), rel=1e-15, abs=1e-300)
            assert fst[L.OE] == pytest.approx(np.linalg.norm(e6[ori]), rel=1e-15, abs=1e-300)


def test_matmul44_and_row_terms_against_numpy():
    rng = np.random.default_rng(22)
    for _ in range(50):
        a, b, out = rng.normal(size=(4, 4)), rng.normal(size=(4, 4)), np.empty((4, 4))
        matmul44(a, b, out)
        np.testing.assert_allclose(out, a @ b, rtol=1e-14, atol=1e-14)
        A, dp, sigma = rng.normal(size=(3, 7)), rng.normal(size=7), rng.normal(size=7)
        for r in range(3):
            got = row_terms(A, r, dp, sigma)
            np.testing.assert_allclose(got, (A[r] @ dp, A[r] @ sigma), rtol=1e-13, atol=1e-15)


def test_square_step_against_newton_step():
    """n = m (no null space): the particular step Δθ_p if it satisfies the box and the
    coupled rows, with the rows it touches — NewtonStep.hard_diagonal's answer — else no
    step; random square systems, boxes that admit and exclude it, and coupled rows."""
    rng = np.random.default_rng(23)
    n, seen = 4, {True: 0, False: 0}
    for k in range(300):
        J, F = rng.normal(size=(n, n)), rng.normal(size=n) * 0.05
        dp = np.linalg.solve(J, -F)
        lower, upper = -rng.uniform(0.0, 0.1, n), rng.uniform(0.0, 0.1, n)
        if k % 5 == 0:  # exactly at a bound: a touching row
            upper[0] = dp[0]
        A = rng.normal(size=(2, n)) if k % 3 == 0 else np.zeros((0, n))
        sigma = rng.normal(size=n) * 0.01
        b = A @ (sigma + dp) - rng.uniform(-0.01, 0.05, A.shape[0])
        ineq = None if A.shape[0] == 0 else (A, b - A @ sigma)
        step = NewtonStep(QuadprogSolver())
        ref = step.hard_diagonal(J, F, np.ones(n), np.zeros(n), np.stack((lower, upper)), ineq)
        V = _workspace(n, np.ones(n), np.zeros(n), dp, lower, upper)
        V[L.SIGMA] = sigma
        active, mult, ist = np.zeros(2 * n, np.int64), np.zeros(2 * n), np.zeros(L.N_IST, np.int64)
        ok = square_step(V, A, b, active, mult, ist)
        assert ok == (ref is not None)
        seen[ok] += 1
        if ok:
            np.testing.assert_allclose(V[L.DTHETA], ref.dtheta, rtol=0, atol=1e-12)
            assert sorted(active[: ist[L.N_ACTIVE]].tolist()) == sorted(ref.active.tolist())
    assert min(seen.values()) > 30  # both branches


def test_compact_rest_and_apply_z_against_numpy():
    """The compact QP's scaling and constraint columns (quadprog's ``solve_ct`` scaling:
    max diag H̃ = 1; ``[N, −N, (AN)ᵀ]``, ``[l − Δθ_p; Δθ_p − u; b − AΣ − AΔθ_p]``), and the
    step from its solution ``Δθ = Δθ_p + N z``."""
    rng = np.random.default_rng(24)
    for _ in range(50):
        n, nz, r = 6, 3, 2
        N, A = rng.normal(size=(n, nz)), rng.normal(size=(r, n))
        dp, sigma, b = rng.normal(size=n), rng.normal(size=n), rng.normal(size=r)
        lower, upper = -rng.uniform(0.1, 1, n), rng.uniform(0.1, 1, n)
        H = rng.normal(size=(nz, nz))
        H = H @ H.T + np.eye(nz)
        g = rng.normal(size=nz)
        V = _workspace(n, np.ones(n), np.zeros(n), dp, lower, upper)
        V[L.SIGMA] = sigma
        Ht, gt, fst = H.copy(), g.copy(), np.zeros(L.N_FST)
        Ct, bt = np.empty((nz, 2 * n + r)), np.empty(2 * n + r)
        compact_rest(V, N, A, b, Ht, gt, Ct, bt, fst)
        scale = 1.0 / np.diag(H).max()
        assert fst[L.SCALE] == pytest.approx(scale, rel=1e-15)
        np.testing.assert_allclose(Ht, H * scale, rtol=1e-14)
        np.testing.assert_allclose(gt, -g * scale, rtol=1e-14)
        np.testing.assert_allclose(Ct, np.hstack((N.T, -N.T, (A @ N).T)), rtol=1e-13, atol=1e-14)
        rhs = np.concatenate((lower - dp, dp - upper, b - A @ sigma - A @ dp))
        np.testing.assert_allclose(bt, rhs, rtol=1e-13, atol=1e-14)
        z = rng.normal(size=nz)
        Vr = _workspace(n, np.ones(n), np.zeros(n), dp, lower, upper)
        Vr[L.Z, :nz] = z
        apply_z(Vr, N, n, nz)
        np.testing.assert_allclose(Vr[L.DTHETA], dp + N @ z, rtol=1e-13, atol=1e-15)


def test_inputs_finite_is_the_numpy_paths_first_test():
    """The cycle's first test of its inputs: ``q·q`` and the sum of the target's first
    three rows finite (InverseTransformation.step: an overflow of ‖q‖² sends both paths to
    the exact check)."""
    rng = np.random.default_rng(25)
    for k in range(200):
        q, target = rng.normal(size=7), rng.normal(size=(4, 4))
        bad = k % 4
        if bad == 1:
            q[k % 7] = (np.inf, -np.inf, np.nan)[k % 3]
        elif bad == 2:
            target[k % 3, k % 4] = np.nan
        elif bad == 3:
            q[0] = 1e200  # finite, but ‖q‖² overflows
        with np.errstate(over="ignore", invalid="ignore"):
            expected = math.isfinite(float(q @ q)) and math.isfinite(float(target[:3].sum()))
        assert inputs_finite(q, target) == expected
