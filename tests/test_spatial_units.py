"""Spatial math and unit conversion against closed forms and independent constructions."""

from __future__ import annotations

import math

import numpy as np
import pytest
from irlc.runtime import units
from irlc.runtime.model import spatial

rng = np.random.default_rng(7)


def _random_rotation() -> np.ndarray:
    q = rng.normal(size=4)
    return spatial.quat_to_matrix(q / np.linalg.norm(q))


def test_zyx_matches_elementary_rotations():
    a, b, c = 0.3, -0.7, 1.1
    ca, sa, cb, sb, cc, sc = (math.cos(a), math.sin(a), math.cos(b), math.sin(b),
                              math.cos(c), math.sin(c))  # fmt: skip
    # Closed form of Rz(a) Ry(b) Rx(c) (e.g. Craig, Introduction to Robotics, eq. 2.64).
    expected = np.array(
        [
            [ca * cb, ca * sb * sc - sa * cc, ca * sb * cc + sa * sc],
            [sa * cb, sa * sb * sc + ca * cc, sa * sb * cc - ca * sc],
            [-sb, cb * sc, cb * cc],
        ]
    )
    assert np.allclose(spatial.zyx_to_matrix(a, b, c), expected, atol=1e-15)


@pytest.mark.parametrize("_", range(20))
def test_zyx_round_trip(_):
    a, b, c = rng.uniform(-math.pi, math.pi), rng.uniform(-1.5, 1.5), rng.uniform(-math.pi, math.pi)
    assert np.allclose(spatial.matrix_to_zyx(spatial.zyx_to_matrix(a, b, c)), (a, b, c))


@pytest.mark.parametrize("_", range(20))
def test_quaternion_round_trip_and_rotation_vector(_):
    r = _random_rotation()
    assert np.allclose(spatial.quat_to_matrix(spatial.matrix_to_quat(r)), r, atol=1e-12)
    w = spatial.rotation_vector(r)
    angle = np.linalg.norm(w)
    assert np.allclose(spatial.axis_angle(w / angle, angle), r, atol=1e-9)


def test_rotation_vector_near_pi():
    axis = np.array([1.0, 2.0, -2.0]) / 3.0
    r = spatial.axis_angle(axis, math.pi - 1e-7)
    w = spatial.rotation_vector(r)
    assert np.allclose(spatial.axis_angle(w / np.linalg.norm(w), np.linalg.norm(w)), r, atol=1e-6)


@pytest.mark.parametrize("_", range(20))
def test_quaternion_algebra_matches_the_matrices(_):
    """The tuple algebra the interpreter's ORIENTATION values use, against rotation
    matrices built independently (Rodrigues, matrix products)."""
    p, q = rng.normal(size=4), rng.normal(size=4)
    p, q = spatial.quat_unit(*p), spatial.quat_unit(*q)
    assert p[0] >= 0.0 and math.isclose(math.fsum(c * c for c in p), 1.0, rel_tol=1e-15)
    rp, rq = spatial.quat_to_matrix(p), spatial.quat_to_matrix(q)
    pq = spatial.quat_multiply(p, q)
    assert pq[0] >= 0.0
    assert np.allclose(spatial.quat_to_matrix(pq), rp @ rq, atol=1e-12)
    assert np.allclose(spatial.quat_to_matrix(spatial.quat_conjugate(p)), rp.T, atol=1e-12)
    v = tuple(rng.normal(size=3))
    assert np.allclose(spatial.quat_rotate(p, v), rp @ np.array(v), atol=1e-12)
    axis, angle = rng.normal(size=3) * 5.0, rng.uniform(-2 * math.pi, 2 * math.pi)
    got = spatial.quat_from_axis_angle(tuple(axis), angle)
    assert got[0] >= 0.0
    expected = spatial.axis_angle(axis / np.linalg.norm(axis), angle)
    assert np.allclose(spatial.quat_to_matrix(got), expected, atol=1e-12)


def test_slerp_halfway_is_half_angle():
    q0 = spatial.matrix_to_quat(np.eye(3))
    q1 = spatial.matrix_to_quat(spatial.rot_z(1.0))
    mid = spatial.slerp(q0, q1, 0.5)
    assert np.allclose(spatial.quat_to_matrix(mid), spatial.rot_z(0.5))
    assert spatial.quat_angle(q0, q1) == pytest.approx(1.0)


def test_pose_error_is_zero_at_target_and_first_order_in_rotation():
    t = spatial.transform(_random_rotation(), (0.1, 0.2, 0.3))
    assert np.allclose(spatial.pose_error(t, t), 0.0)
    w = np.array([1e-4, -2e-4, 3e-4])
    t2 = t.copy()
    t2[:3, :3] = spatial.axis_angle(w / np.linalg.norm(w), np.linalg.norm(w)) @ t[:3, :3]
    assert np.allclose(spatial.pose_error(t2, t)[3:], w, atol=1e-12)


def test_inverse_transform():
    t = spatial.transform(_random_rotation(), (1.0, -2.0, 0.5))
    assert np.allclose(spatial.inverse(t) @ t, np.eye(4))


def test_units_round_trip_pose_and_joints():
    pose = (11500.0, 1000.0, 3500.0, -85.0, 10.0, 5.0)
    t = units.pose_to_si(*pose)
    assert np.allclose(t[:3, 3], (11.5, 1.0, 3.5))
    assert np.allclose(units.pose_from_si(t), pose)
    kinds = ("revolute", "prismatic")
    si = units.joints_to_si((90.0, 18.11), kinds)
    assert np.allclose(si, (math.pi / 2, 0.01811))
    assert np.allclose(units.joints_from_si(si, kinds), (90.0, 18.11))


@pytest.mark.parametrize("sign", [1.0, -1.0])
@pytest.mark.parametrize("noise", [0.0, 1e-17, 3e-16])
def test_a_half_turn_is_plus_180_whatever_the_round_off(sign, noise):
    """Regression (adversarial probe): a constant c = 180° flipped between +180° and −180°
    in the trace with the sign of a round-off entry of R (``atan2(±0, −1)``)."""
    r = spatial.zyx_to_matrix(math.radians(30.0), math.radians(10.0), math.pi)
    r[2, 1] = math.copysign(noise, sign)  # ±round-off (or ±0) where sin(c) is zero
    a, b, c = spatial.matrix_to_zyx(r)
    assert c == math.pi
    assert (a, b) == pytest.approx((math.radians(30.0), math.radians(10.0)), abs=1e-12)
    zyz = spatial.matrix_to_zyz(spatial.zyz_to_matrix(-math.pi, 0.5, -math.pi))
    assert zyz[0] == zyz[2] == math.pi  # the same convention for Φ and Ψ: (−180°, 180°]
    # beyond round-off an angle keeps its sign
    assert spatial.matrix_to_zyx(spatial.zyx_to_matrix(0, 0, -math.pi + 1e-9))[2] < 0
