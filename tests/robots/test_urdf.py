"""URDF import: same FK as the TOML description, panda vs published parameters and peers."""

from __future__ import annotations

import math

import numpy as np
import pytest
from irlc.robots import ROBOTS_DIR, RobotFileError, load_robot
from irlc.robots.urdf_import import load_urdf
from irlc.runtime.model import spatial
from irlc.runtime.model.kinematics import Kinematics

pytest.importorskip("yourdfpy")

PANDA_URDF = ROBOTS_DIR / "urdf" / "panda.urdf"


def _rpy_of(alpha: float) -> str:
    return f"{alpha} 0 0"


def as6_urdf() -> str:
    """AS arm as URDF: DH row i becomes the fixed origin of joint i+1 (rpy = Rx(α))."""
    rows = [
        (90, 0, 0.765),
        (-90, 0, 0),
        (90, -0.035, 0.51),
        (-90, 0, 0),
        (90, 0, 0.315),
        (-90, 0, 0),
    ]
    limits = [(0, 330), (-90, 90), (-90, 90), (-90, 90), (0, 330), (-90, 90)]
    parts = ['<robot name="as6_urdf">', '<link name="base"/>']
    prev_origin = ("0 0 0", "0 0 0")
    for i, ((alpha, a, d), (lo, hi)) in enumerate(zip(rows, limits, strict=True), 1):
        parts.append(
            f'<link name="l{i}"><collision><origin xyz="0 0 {d / 2}"/><geometry>'
            f'<cylinder radius="0.05" length="{abs(d) + 0.01}"/></geometry></collision>'
            f'<inertial><origin xyz="0 0 0.1"/><mass value="2"/>'
            f'<inertia ixx="0.1" iyy="0.1" izz="0.05" ixy="0" ixz="0" iyz="0"/></inertial></link>'
        )
        parent = "base" if i == 1 else f"l{i - 1}"
        parts.append(
            f'<joint name="j{i}" type="revolute"><parent link="{parent}"/><child link="l{i}"/>'
            f'<origin xyz="{prev_origin[0]}" rpy="{prev_origin[1]}"/><axis xyz="0 0 1"/>'
            f'<limit lower="{math.radians(lo)}" upper="{math.radians(hi)}" '
            'velocity="3.14" effort="1"/></joint>'
        )
        prev_origin = (f"{a} 0 {d}", _rpy_of(math.radians(alpha)))
    # DH row 6's fixed part then the tool as fixed joints to a tip link
    parts.append('<link name="flange"/><link name="tcp"/>')
    parts.append(
        f'<joint name="f" type="fixed"><parent link="l6"/><child link="flange"/>'
        f'<origin xyz="{prev_origin[0]}" rpy="{prev_origin[1]}"/></joint>'
    )
    parts.append(
        '<joint name="t" type="fixed"><parent link="flange"/><child link="tcp"/>'
        '<origin xyz="0 0 0.2235"/></joint>'
    )
    parts.append("</robot>")
    return "\n".join(parts)


def test_as6_urdf_equals_toml(tmp_path):
    """Tz(d)·Tx(a)·Rx(α) is URDF origin xyz=(a,0,d), rpy=(α,0,0): same FK as the DH file."""
    p = tmp_path / "as6.urdf"
    p.write_text(as6_urdf())
    from_urdf = load_robot(str(p))
    from_toml = load_robot("as6")
    ku, kt = Kinematics(from_urdf), Kinematics(from_toml)
    rng = np.random.default_rng(0)
    lim = from_toml.position_limits
    for _ in range(20):
        q = rng.uniform(lim[:, 0], lim[:, 1])
        assert np.allclose(ku.tcp(q), kt.tcp(q), atol=1e-12)
        assert np.allclose(ku.jacobian(q), kt.jacobian(q), atol=1e-12)
    assert from_urdf.joint_names == ("j1", "j2", "j3", "j4", "j5", "j6")
    assert np.allclose(from_urdf.position_limits, from_toml.position_limits)
    assert np.allclose(from_urdf.speed_limits[:, 1], 3.14)
    assert np.allclose(from_urdf.accel_limits[:, 1], 5 * 3.14)  # assumed 5 × velocity
    assert "joint 'j1' acceleration" in from_urdf.extra["assumed"]
    assert len(from_urdf.geometry) == 6 and len(from_urdf.inertials) == 6


def modified_dh_panda(q: np.ndarray) -> np.ndarray:
    """Franka's published (Craig) parameters: Rx(α)·Tx(a)·Rz(θ)·Tz(d); flange d = 0.107."""
    table = [
        (0, 0, 0.333),
        (-math.pi / 2, 0, 0),
        (math.pi / 2, 0, 0.316),
        (math.pi / 2, 0.0825, 0),
        (-math.pi / 2, -0.0825, 0.384),
        (math.pi / 2, 0, 0),
        (math.pi / 2, 0.088, 0),
    ]
    t = np.eye(4)
    for (alpha, a, d), th in zip(table, q, strict=True):
        t = (
            t
            @ spatial.transform(spatial.rot_x(alpha))
            @ spatial.transform(None, (a, 0, 0))
            @ spatial.transform(spatial.rot_z(th))
            @ spatial.transform(None, (0, 0, d))
        )
    return t @ spatial.transform(None, (0, 0, 0.107))


def test_panda_flange_matches_published_dh():
    model = load_robot("panda")
    kin = Kinematics(model)
    rng = np.random.default_rng(1)
    lim = model.position_limits
    for _ in range(20):
        q = rng.uniform(lim[:, 0], lim[:, 1])
        assert np.allclose(
            kin.flange_from_frames(kin.link_frames(q)), modified_dh_panda(q), atol=1e-12
        )


def test_panda_ready_pose_tcp():
    """Ready pose: the hand TCP at (0.307, 0, 0.487) m pointing down (Franka's O_T_EE)."""
    model = load_robot("panda")
    t = Kinematics(model).tcp(model.home_q())
    assert np.allclose(t[:3, 3], [0.30689, 0.0, 0.48688], atol=1e-5)
    assert np.allclose(t[:3, 2], [0, 0, -1], atol=1e-9)


def test_panda_against_yourdfpy_fk():
    """Another implementation of the same file: yourdfpy's own scene graph."""
    import yourdfpy

    urdf = yourdfpy.URDF.load(str(PANDA_URDF), load_meshes=False)
    model = load_urdf(PANDA_URDF)  # tip auto: panda_hand_tcp
    kin = Kinematics(model)
    rng = np.random.default_rng(2)
    lim = model.position_limits
    for _ in range(10):
        q = rng.uniform(lim[:, 0], lim[:, 1])
        urdf.update_cfg(q)
        expected = urdf.get_transform("panda_hand_tcp", "panda_link0")
        assert np.allclose(kin.tcp(q), expected, atol=1e-12)


@pytest.mark.peer
def test_panda_against_pinocchio():
    pin = pytest.importorskip("pinocchio")
    pmodel = pin.buildModelFromUrdf(str(PANDA_URDF))
    data = pmodel.createData()
    frame = pmodel.getFrameId("panda_link8")
    model = load_robot("panda")
    kin = Kinematics(model)
    rng = np.random.default_rng(3)
    lim = model.position_limits
    for _ in range(10):
        q = rng.uniform(lim[:, 0], lim[:, 1])
        pin.framesForwardKinematics(pmodel, data, q)
        assert np.allclose(
            kin.flange_from_frames(kin.link_frames(q)), data.oMf[frame].homogeneous, atol=1e-10
        )


def test_panda_merges_hand_and_converts_shapes():
    model = load_robot(ROBOTS_DIR / "urdf" / "panda.toml")  # the URDF-backed source
    link7 = next(i for i in model.inertials if i.link == 7)
    assert math.isclose(link7.mass, 0.735522 + 0.73)
    notes = model.extra["urdf_notes"]
    assert any("box → bounding capsule" in n for n in notes)
    assert any(g.link == 7 for g in model.geometry)
    assert model.n == 7 and np.allclose(model.accel_limits[:, 1], [15, 7.5, 10, 12.5, 15, 20, 20])


BRANCHED = """<robot name="b"><link name="r"/><link name="a"/><link name="b"/>
<joint name="ja" type="revolute"><parent link="r"/><child link="a"/><axis xyz="0 0 1"/>
<limit lower="-1" upper="1" velocity="1" effort="1"/></joint>
<joint name="jb" type="revolute"><parent link="r"/><child link="b"/><axis xyz="0 0 1"/>
<limit lower="-1" upper="1" velocity="1" effort="1"/></joint></robot>"""


@pytest.mark.parametrize(
    ("text", "words"),
    [
        (BRANCHED, "choose the tip"),
        (
            BRANCHED.replace(
                'type="revolute"><parent link="r"/><child link="b"/>',
                'type="floating"><parent link="r"/><child link="b"/>',
            ),
            "floating",
        ),
        (BRANCHED.replace("</joint></robot>", '<mimic joint="ja"/></joint></robot>'), "mimic"),
        # yourdfpy recovers from the broken XML; either way a clear error, not a traceback
        ("<robot name='x'><link name='r'/>", "cannot parse|no movable joint"),
    ],
)
def test_unsupported_urdf(tmp_path, text, words):
    p = tmp_path / "bad.urdf"
    p.write_text(text)
    with pytest.raises(RobotFileError, match=words) as err:
        load_robot(str(p))
    assert str(p) in str(err.value)


def test_branched_with_tip(tmp_path):
    p = tmp_path / "b.urdf"
    p.write_text(BRANCHED)
    assert load_urdf(p, tip="b").joint_names == ("jb",)


@pytest.mark.peer
def test_panda_against_mujoco():
    mujoco = pytest.importorskip("mujoco")
    mjm = mujoco.MjModel.from_xml_path(str(PANDA_URDF))
    data = mujoco.MjData(mjm)
    body = mujoco.mj_name2id(mjm, mujoco.mjtObj.mjOBJ_BODY, "panda_link7")
    model = load_robot("panda")
    kin = Kinematics(model)
    rng = np.random.default_rng(4)
    lim = model.position_limits
    for _ in range(10):
        q = rng.uniform(lim[:, 0], lim[:, 1])
        data.qpos[:] = q
        mujoco.mj_kinematics(mjm, data)
        frame = kin.link_frames(q)[7]
        assert np.allclose(frame[:3, 3], data.xpos[body], atol=1e-9)
        assert np.allclose(frame[:3, :3], data.xmat[body].reshape(3, 3), atol=1e-9)
