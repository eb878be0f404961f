"""FK and Jacobians against finite differences and the closed forms of robots.md."""

from __future__ import annotations

import math

import numpy as np
import pytest
from irlc.fidelity.kinematics_rows import l1_end_pose_deviation
from irlc.robots import list_robots, load_robot
from irlc.runtime import units
from irlc.runtime.model import spatial
from irlc.runtime.model.kinematics import Kinematics

ROBOTS = list_robots()


def random_configs(model, count: int, seed: int = 0) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    lim = model.position_limits
    return [rng.uniform(lim[:, 0], lim[:, 1]) for _ in range(count)]


def fd_jacobian(kin: Kinematics, q: np.ndarray, h: float = 1e-6) -> np.ndarray:
    """Central differences of the TCP pose: position, and the rotation vector of R·R0ᵀ."""
    t0 = kin.tcp(q)
    jac = np.empty((6, len(q)))
    for i in range(len(q)):
        dq = np.zeros(len(q))
        dq[i] = h
        tp, tm = kin.tcp(q + dq), kin.tcp(q - dq)
        jac[:, i] = (spatial.pose_error(tp, t0) - spatial.pose_error(tm, t0)) / (2 * h)
    return jac


@pytest.mark.parametrize("name", ROBOTS)
def test_jacobian_matches_finite_differences(name):
    model = load_robot(name)
    kin = Kinematics(model)
    for q in random_configs(model, 5):
        t, jac = kin.tcp_and_jacobian(q)
        scale = max(1.0, float(np.abs(jac).max()))
        assert np.allclose(jac, fd_jacobian(kin, q), atol=1e-6 * scale)
        assert np.allclose(t, kin.tcp(q))
        assert np.allclose(jac, kin.jacobian(q))


@pytest.mark.parametrize("name", ROBOTS)
def test_point_jacobian_of_every_link(name):
    """3×n Jacobian of a point fixed on link k: finite differences of that point."""
    model = load_robot(name)
    kin = Kinematics(model)
    rng = np.random.default_rng(1)
    q = random_configs(model, 1, seed=2)[0]
    frames = kin.link_frames(q)
    h = 1e-6
    for link in range(model.n + 1):
        local = rng.normal(size=3) * 0.3
        point = kin.link_point(frames, link, local)
        jac = kin.point_jacobian(q, link, point)
        assert np.allclose(jac, kin.point_jacobian_at(frames, link, point))
        fd = np.empty((3, model.n))
        for i in range(model.n):
            dq = np.zeros(model.n)
            dq[i] = h
            fp = kin.link_point(kin.link_frames(q + dq), link, local)
            fm = kin.link_point(kin.link_frames(q - dq), link, local)
            fd[:, i] = (fp - fm) / (2 * h)
        assert np.allclose(jac, fd, atol=1e-6 * max(1.0, np.abs(fd).max()))
        assert np.all(jac[:, link:] == 0.0)


def test_link_frames_are_rigid_and_start_at_base():
    model = load_robot("koch11")
    frames = Kinematics(model).link_frames(random_configs(model, 1)[0])
    assert frames.shape == (12, 4, 4)
    assert np.allclose(frames[0], model.base)
    for f in frames:
        assert np.allclose(f[:3, :3] @ f[:3, :3].T, np.eye(3), atol=1e-12)


def test_frames_are_not_shared_between_calls():
    model = load_robot("planar3")
    kin = Kinematics(model)
    a = kin.link_frames(np.zeros(3))
    kin.link_frames(np.ones(3))
    assert np.allclose(a[-1][:3, 3], [2.0, 0.0, 0.0])


KOCH11_ARMS = np.array(
    [[0, 0, 1.3], [-0.2, 0, 0.6], [6, 0, -0.3], [-4, 0, -0.3], [4, 0, -0.7], [-4.6, 0, -0.2],
     [0, 0, 0.4], [0, 0, 0.6], [0, 0, 0], [0, 0, 0], [0, 1.0, 0], [0, 0, -1.5]]
)  # the book's arm table (robots.md), arm 1 … arm 11, tool  # fmt: skip
KONF0 = {  # deg; joint 10 in mm
    "koch11": [-0.695, -75, -102, 115.205, -98.722, -76.097, -0.168, -21.813, -90.452, 227.313,
               21.119],
    "koch11_v1": [2.158, -75, -102, 110.633, -91.115, -121.5, 99.792, 47.095, -76.742, 18.11,
                  39.975],
}  # fmt: skip


@pytest.mark.parametrize("name", ["koch11", "koch11_v1"])
def test_koch11_zero_pose_tcp_in_robot_frame(name):
    model = load_robot(name)
    t = Kinematics(model).tcp(np.zeros(11))
    in_robot = spatial.inverse(model.base) @ t
    assert np.allclose(in_robot[:3, 3], [1.2, 1.0, -0.1], atol=1e-12)
    # sum of the arm table of robots.md plus the tool, independent of the loader's chain
    assert np.allclose(in_robot[:3, 3], KOCH11_ARMS.sum(axis=0))


def test_koch11_zero_pose_tcp_in_the_world_is_the_books():
    """The revised reconstruction has no base turn: the book's (1200, 1000, −100) mm."""
    pose = units.pose_from_si(Kinematics(load_robot("koch11")).tcp(np.zeros(11)))
    assert np.allclose(pose, [1200, 1000, -100, 0, 0, 0], atol=1e-9)


def _rot(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rodrigues: R = I + sin θ K + (1 − cos θ) K²."""
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


def test_koch11_is_the_revised_reconstruction():
    """An independent chain product of issue 16's description: joint i at the END of arm i
    (arm 1 a fixed column), axes J1 +z, J2 +y, J3 +y, J4 −y, J5 −y, J6 +y, J7 +z, J8 +x,
    J9 +y, J10 prismatic +y, J11 −z, tool hanging from J11; equals the loader's FK."""
    x, y, z = np.eye(3)
    axes = [z, y, y, -y, -y, y, z, x, y, y, -z]
    model = load_robot("koch11")
    kin = Kinematics(model)
    for q in random_configs(model, 10):
        r, p = np.eye(3), KOCH11_ARMS[0].astype(float)
        for i, a in enumerate(axes):
            if i == 9:
                p = p + r @ (a * q[i])
            else:
                r = r @ _rot(a, q[i])
            p = p + r @ KOCH11_ARMS[i + 1]
        t = kin.tcp(q)
        assert np.allclose(t[:3, 3], p, atol=1e-12)
        assert np.allclose(t[:3, :3], r, atol=1e-12)


@pytest.mark.parametrize("name", ["koch11", "koch11_v1"])
def test_koch11_konf0_reaches_the_square_corner(name):
    """konf_0 (printed to 0.001°) → (11500, 1000, 3500) mm, (0, 0, 0)°, and is the home.

    The residual with the printed digits is ≈ 0.06 mm and 0.001°; 0.0005° of rounding at a
    6 m lever is 0.05 mm, so we accept 0.1 mm / 0.002°."""
    model = load_robot(name)
    konf0 = units.joints_to_si(KONF0[name], model.joint_kinds)
    pose = units.pose_from_si(Kinematics(model).tcp(konf0))
    assert np.allclose(pose[:3], [11500, 1000, 3500], atol=0.1)
    assert np.allclose(pose[3:], [0, 0, 0], atol=0.002)
    assert np.allclose(model.home_q(), konf0)


def test_koch11_konf0_is_inside_the_base_set_with_the_books_constants():
    """θ2 = −75°, θ3 = −102°, J11 ∈ [0, 60] and every joint inside set 6.1."""
    model = load_robot("koch11")
    q = units.joints_from_si(model.home_q(), model.joint_kinds)
    assert q[1] == pytest.approx(-75) and q[2] == pytest.approx(-102) and 0 <= q[10] <= 60
    box = np.array([lim.position for lim in model.limit_sets["base"]])
    assert np.all(model.home_q() >= box[:, 0]) and np.all(model.home_q() <= box[:, 1])


def test_irb6_wrist_point_closed_form():
    model = load_robot("irb6")
    kin = Kinematics(model)
    l2, l3, lam5, lam1 = 0.45, 0.67, 0.095, 0.70
    for q in random_configs(model, 20):
        t1, t2, t3, t4 = q[:4]
        s1, c1 = math.sin(t1), math.cos(t1)
        c23, s23 = math.cos(t2 + t3), math.sin(t2 + t3)
        c234, s234 = math.cos(t2 + t3 + t4), math.sin(t2 + t3 + t4)
        d = [
            l2 * s1 * math.sin(t2) - l3 * s1 * c23 - lam5 * s1 * c234,
            -l2 * c1 * math.sin(t2) + l3 * c1 * c23 + lam5 * c1 * c234,
            lam1 + l2 * math.cos(t2) + l3 * s23 + lam5 * s234,
        ]
        flange = kin.flange_from_frames(kin.link_frames(q))
        assert np.allclose(flange[:3, 3], d, atol=1e-12)


def test_irb6_track_is_irb6_on_a_slide():
    """A_0 = [[1,0,0,0],[0,0,1,0],[0,−1,0,λ0],[0,0,0,1]] times the IRb-6 chain."""
    track, arm = load_robot("irb6_track"), load_robot("irb6")
    kt, ka = Kinematics(track), Kinematics(arm)
    rng = np.random.default_rng(3)
    for _ in range(10):
        lam0 = rng.uniform(0.0, 0.851)
        qa = rng.uniform(-0.5, 0.5, 5)
        a0 = np.array([[1, 0, 0, 0], [0, 0, 1, 0], [0, -1, 0, lam0], [0, 0, 0, 1]], dtype=float)
        assert np.allclose(kt.tcp(np.r_[lam0, qa]), a0 @ ka.tcp(qa), atol=1e-12)


def test_l1_closed_form_end_pose():
    """X = Trans(λ2, λ3+λ4−l1, λ1)·Rx(−90°)·Rz(θ4)·Ry(−θ5)·Rz(θ6)·Trans(0, 0, 0.1535), written
    out in irlc.fidelity.kinematics_rows (docs/fidelity.md, Table 4.1): mm."""
    assert l1_end_pose_deviation() < 1e-9


def test_planar3_unit_links():
    kin = Kinematics(load_robot("planar3"))
    for q in random_configs(kin.model, 10):
        a = np.cumsum(q)
        t = kin.tcp(q)
        assert np.allclose(t[:2, 3], [np.cos(a).sum(), np.sin(a).sum()])
        assert math.isclose(spatial.matrix_to_zyx(t[:3, :3])[0], math.remainder(a[-1], 2 * math.pi))


def test_as6_zero_pose():
    """Hand product of the AS DH rows at θ = 0 (independent of the loader)."""

    def dh(alpha, a, d):
        return (
            spatial.transform(None, (0, 0, d))
            @ spatial.transform(None, (a, 0, 0))
            @ spatial.transform(spatial.rot_x(math.radians(alpha)))
        )

    rows = [
        (90, 0, 0.765),
        (-90, 0, 0),
        (90, -0.035, 0.51),
        (-90, 0, 0),
        (90, 0, 0.315),
        (-90, 0, 0),
    ]
    t = np.eye(4)
    for r in rows:
        t = t @ dh(*r)
    t = t @ spatial.transform(None, (0, 0, 0.2235))
    assert np.allclose(Kinematics(load_robot("as6")).tcp(np.zeros(6)), t, atol=1e-12)


def test_tool_override():
    model = load_robot("planar3")
    tool = spatial.transform(None, (0.5, 0.0, 0.0))
    kin = Kinematics(model, tool=tool)
    assert np.allclose(kin.tcp(np.zeros(3))[:3, 3], [3.5, 0, 0])
    kin.tool = np.eye(4)
    assert np.allclose(kin.tcp(np.zeros(3))[:3, 3], [3.0, 0, 0])
