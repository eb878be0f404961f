"""Interpreter geometry: poses, orientations, positions, joint tuples, FK — checked against
independent 4×4 matrix computations written out here (not through irlc.runtime.model.spatial)."""

from __future__ import annotations

import math
import random

import numpy as np
import pytest
from irlc.runtime import units
from irlc.runtime import values as V
from irlc.runtime.values import JointTuple, Orientation, Pose, Position

from .test_interpreter_fakes import FakeController, failure, main_program, planar_fk, run


def rx(d: float) -> np.ndarray:
    c, s = math.cos(math.radians(d)), math.sin(math.radians(d))
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def ry(d: float) -> np.ndarray:
    c, s = math.cos(math.radians(d)), math.sin(math.radians(d))
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def rz(d: float) -> np.ndarray:
    c, s = math.cos(math.radians(d)), math.sin(math.radians(d))
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def quat_matrix(o: Orientation) -> np.ndarray:
    w, x, y, z = o.as_tuple()
    assert math.isclose(w * w + x * x + y * y + z * z, 1.0, abs_tol=1e-12)
    return np.array(
        [
            [w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z],
        ]
    )


def hom(p6) -> np.ndarray:
    x, y, z, a, b, c = p6
    t = np.eye(4)
    t[:3, :3] = rz(a) @ ry(b) @ rx(c)
    t[:3, 3] = (x, y, z)
    return t


def as_hom(p: Pose) -> np.ndarray:
    t = np.eye(4)
    t[:3, :3] = quat_matrix(p.ori)
    t[:3, 3] = p.pos.as_tuple()
    return t


def pose_const(k: int, p6) -> str:
    return f"CONST {k} POSE " + " ".join(repr(float(v)) for v in p6)


def random_pose(rng: random.Random):
    return (
        rng.uniform(-2000, 2000),
        rng.uniform(-2000, 2000),
        rng.uniform(-2000, 2000),
        rng.uniform(-180, 180),
        rng.uniform(-89, 89),
        rng.uniform(-180, 180),
    )


def evaluate(consts: list[str], ops: str, result_type: str = "POSE") -> object:
    """Run ``ops`` (leaving one value) and return what was stored in a global."""
    body = f"main: {ops}\nL1 POPG 0\nL2 END"
    code = main_program(body, decls=f"GLOBAL 0 {result_type} r", consts="\n".join(consts))
    return run(code).state.value("r")


# ------------------------------------------------------------------ composition and inverse


def test_compose_matches_the_matrix_product():
    rng = random.Random(4)
    for _ in range(25):
        p1, p2 = random_pose(rng), random_pose(rng)
        got = evaluate([pose_const(0, p1), pose_const(1, p2)], "L1 PUSHC 0\nL1 PUSHC 1\nL1 COMPOSE")
        np.testing.assert_allclose(as_hom(got), hom(p1) @ hom(p2), atol=1e-9)


def test_compose_of_a_pose_and_a_position_transforms_the_point():
    p1 = (100.0, -50.0, 20.0, 30.0, 10.0, -40.0)
    got = evaluate(
        [pose_const(0, p1), "CONST 1 POSITION 10.0 20.0 30.0"],
        "L1 PUSHC 0\nL1 PUSHC 1\nL1 COMPOSE",
        "POSITION",
    )
    expected = hom(p1) @ np.array([10.0, 20.0, 30.0, 1.0])
    np.testing.assert_allclose(got.as_tuple(), expected[:3], atol=1e-9)


def test_inverse_matches_the_matrix_inverse():
    rng = random.Random(5)
    for _ in range(10):
        p = random_pose(rng)
        got = evaluate([pose_const(0, p)], "L1 PUSHC 0\nL1 CALLB INV 1")
        np.testing.assert_allclose(as_hom(got), np.linalg.inv(hom(p)), atol=1e-9)


def test_frame_of_a_tool_in_a_base_example():
    """A tool 100 mm along the flange z axis, flange rotated 90° about world y."""
    flange = (1000.0, 0.0, 500.0, 0.0, 90.0, 0.0)
    tool = (0.0, 0.0, 100.0, 0.0, 0.0, 0.0)
    got = evaluate(
        [pose_const(0, flange), pose_const(1, tool)], "L1 PUSHC 0\nL1 PUSHC 1\nL1 COMPOSE"
    )
    # flange z axis points along world +x after Ry(90°)
    np.testing.assert_allclose(got.pos.as_tuple(), (1100.0, 0.0, 500.0), atol=1e-9)


# ------------------------------------------------------------------ orientation constructors


def test_zyx_round_trip():
    rng = random.Random(6)
    for _ in range(50):
        p = random_pose(rng)
        back = V.pose_to_zyx(V.pose_from_zyx(*p))
        np.testing.assert_allclose(back, p, atol=1e-9)


def test_zyx_constant_matches_the_explicit_rotation():
    p = (1.0, 2.0, 3.0, 30.0, -20.0, 75.0)
    got = evaluate([pose_const(0, p)], "L1 PUSHC 0")
    np.testing.assert_allclose(as_hom(got), hom(p), atol=1e-12)


@pytest.mark.parametrize(
    ("fn", "expected"),
    [
        ("ORIZYX", lambda a, b, c: rz(a) @ ry(b) @ rx(c)),
        ("ORIXYZ", lambda a, b, c: rx(a) @ ry(b) @ rz(c)),
        ("ORIZYZ", lambda a, b, c: rz(a) @ ry(b) @ rz(c)),
        # ORIRS(roll, pitch, yaw): fixed axes X then Y then Z → Rz(yaw)·Ry(pitch)·Rx(roll)
        ("ORIRS", lambda r, p, y: rz(y) @ ry(p) @ rx(r)),
    ],
)
def test_orientation_constructors(fn, expected):
    args = (25.0, -35.0, 110.0)
    consts = [f"CONST {k} REAL {v}" for k, v in enumerate(args)]
    got = evaluate(consts, f"L1 PUSHC 0\nL1 PUSHC 1\nL1 PUSHC 2\nL1 CALLB {fn} 3", "ORIENTATION")
    np.testing.assert_allclose(quat_matrix(got), expected(*args), atol=1e-12)
    assert got.w >= 0.0


def test_orirs_rotates_a_vector_about_fixed_axes_in_turn():
    """roll 90° about X then pitch 90° about the fixed Y: the y axis goes to x."""
    consts = ["CONST 0 REAL 90.0", "CONST 1 REAL 90.0", "CONST 2 REAL 0.0"]
    got = evaluate(consts, "L1 PUSHC 0\nL1 PUSHC 1\nL1 PUSHC 2\nL1 CALLB ORIRS 3", "ORIENTATION")
    v = quat_matrix(got) @ np.array([0.0, 1.0, 0.0])
    np.testing.assert_allclose(v, ry(90) @ rx(90) @ np.array([0.0, 1.0, 0.0]), atol=1e-12)
    np.testing.assert_allclose(v, (1.0, 0.0, 0.0), atol=1e-12)


def test_oriquat_is_normalised_and_zero_is_an_error():
    consts = ["CONST 0 REAL 2.0", "CONST 1 REAL 0.0", "CONST 2 REAL 0.0", "CONST 3 REAL 2.0"]
    ops = "L1 PUSHC 0\nL1 PUSHC 1\nL1 PUSHC 2\nL1 PUSHC 3\nL1 CALLB ORIQUAT 4"
    got = evaluate(consts, ops, "ORIENTATION")
    s = math.sqrt(0.5)
    np.testing.assert_allclose(got.as_tuple(), (s, 0.0, 0.0, s), atol=1e-15)
    zero = "\n".join(["CONST 0 REAL 0.0"])
    body = "main: L4 PUSHC 0\nL4 PUSHC 0\nL4 PUSHC 0\nL4 PUSHC 0\nL4 CALLB ORIQUAT 4\nL5 END"
    err = failure(main_program(body, consts=zero))
    assert err.message == "ORIQUAT: the quaternion (0, 0, 0, 0) is not a rotation"
    assert err.line == 4


def test_orivang_matches_rodrigues_and_normalises_the_axis():
    axis = np.array([1.0, 2.0, 2.0])
    k = axis / 3.0
    angle = 50.0
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    th = math.radians(angle)
    expected = np.eye(3) + math.sin(th) * kx + (1 - math.cos(th)) * kx @ kx
    consts = ["CONST 0 POSITION 1.0 2.0 2.0", f"CONST 1 REAL {angle}"]
    got = evaluate(consts, "L1 PUSHC 0\nL1 PUSHC 1\nL1 CALLB ORIVANG 2", "ORIENTATION")
    np.testing.assert_allclose(quat_matrix(got), expected, atol=1e-12)
    err = failure(
        main_program(
            "main: L3 PUSHC 0\nL3 PUSHC 1\nL3 CALLB ORIVANG 2\nL4 END",
            consts="CONST 0 POSITION 0.0 0.0 0.0\nCONST 1 REAL 10.0",
        )
    )
    assert err.message == "ORIVANG: the rotation axis (0, 0, 0) has no direction"


def test_pose_and_position_constructors_and_fields():
    consts = [
        "CONST 0 POSITION 1.0 2.0 3.0",
        "CONST 1 REAL 10.0",
        "CONST 2 REAL 20.0",
        "CONST 3 REAL 30.0",
    ]
    ops = """L1 PUSHC 0
    L1 PUSHC 1
    L1 PUSHC 2
    L1 PUSHC 3
    L1 CALLB ORIZYX 3
    L1 CALLB POSE 2"""
    got = evaluate(consts, ops)
    np.testing.assert_allclose(as_hom(got), hom((1, 2, 3, 10, 20, 30)), atol=1e-12)
    body = """main: L1 PUSHC 0
    L1 CALLB POSE 1
    L1 PUSHC 1
    L1 SETF y
    L1 DUP
    L1 GETF pos
    L1 WRITELN 1
    L2 GETF y
    L2 PUSHC 2
    L2 PUSHC 3
    L2 PUSHC 1
    L2 CALLB POSITION 3
    L2 GETF z
    L2 WRITELN 2
    L3 END"""
    result = run(main_program(body, consts="\n".join(consts)))
    assert result.output == ["(1.0, 10.0, 3.0)", "10.010.0"]


def test_make_pose_from_six_numbers_is_mm_and_zyx_degrees():
    consts = [f"CONST {k} REAL {v}" for k, v in enumerate((100.0, 0.0, 0.0, 90.0, 0.0, 0.0))]
    ops = "\n".join(f"L1 PUSHC {k}" for k in range(6)) + "\nL1 MAKE POSE 6"
    got = evaluate(consts, ops)
    np.testing.assert_allclose(as_hom(got), hom((100, 0, 0, 90, 0, 0)), atol=1e-12)


def test_pose_to_matrix_is_in_metres_and_round_trips():
    p = V.pose_from_zyx(1500.0, -250.0, 80.0, 12.0, 34.0, -56.0)
    t = V.pose_to_matrix(p)
    expected = hom((1500.0, -250.0, 80.0, 12.0, 34.0, -56.0))
    expected[:3, 3] *= units.MM
    np.testing.assert_allclose(t, expected, atol=1e-12)
    back = V.pose_from_matrix(t)
    np.testing.assert_allclose(V.pose_to_zyx(back), V.pose_to_zyx(p), atol=1e-9)


# ------------------------------------------------------------------ positions and joint tuples


def test_position_arithmetic_and_dist():
    consts = ["CONST 0 POSITION 1.0 2.0 3.0", "CONST 1 POSITION 4.0 6.0 3.0", "CONST 2 INTEGER 2"]
    body = """main: L1 PUSHC 1
    L1 PUSHC 0
    L1 SUB
    L1 PUSHC 2
    L1 MUL
    L1 WRITELN 1
    L2 PUSHC 0
    L2 PUSHC 1
    L2 ADD
    L2 NEG
    L2 WRITELN 1
    L3 PUSHC 0
    L3 PUSHC 1
    L3 CALLB DIST 2
    L3 WRITELN 1
    L4 END"""
    assert run(main_program(body, consts="\n".join(consts))).output == [
        "(6.0, 8.0, 0.0)",
        "(-5.0, -8.0, -6.0)",
        "5.0",
    ]


def test_joint_tuple_fields_indices_and_arithmetic():
    consts = [
        "CONST 0 MAIN_JOINT 10.0 20.0 30.0",
        "CONST 1 MAIN_JOINT 1.0 2.0 3.0",
        "CONST 2 REAL 0.5",
        "CONST 3 INTEGER 2",
        "CONST 4 REAL -7.0",
        "CONST 5 INTEGER 4",
    ]
    body = """main: L1 PUSHC 0
    L1 PUSHC 1
    L1 SUB
    L1 PUSHC 2
    L1 MUL
    L1 WRITELN 1
    L2 PUSHC 0
    L2 GETF A2
    L2 PUSHC 0
    L2 PUSHC 3
    L2 GETI
    L2 WRITELN 2
    L3 PUSHC 0
    L3 PUSHC 3
    L3 PUSHC 4
    L3 SETI
    L3 PUSHC 4
    L3 SETF a3
    L3 WRITELN 1
    L4 PUSHC 0
    L4 PUSHC 5
    L4 GETI
    L5 END"""
    result = run(main_program(body, consts="\n".join(consts)), check=False)
    assert result.output == ["(4.5, 9.0, 13.5)", "20.020.0", "(10.0, -7.0, -7.0)"]
    assert result.error.message == "index 4 is out of range 1..3"
    assert result.error.line == 4


# ------------------------------------------------------------------ forward kinematics


def test_fk_goes_through_the_controller():
    q = (30.0, 45.0, 120.0)
    consts = f"CONST 0 MAIN_JOINT {q[0]} {q[1]} {q[2]}"
    body = "main: L1 PUSHC 0\nL1 CALLB FK 1\nL1 POPG 0\nL2 END"
    got = run(main_program(body, decls="GLOBAL 0 POSE p", consts=consts)).state.value("p")
    x, y, z, yaw = planar_fk(q)
    np.testing.assert_allclose(as_hom(got), hom((x, y, z, yaw, 0.0, 0.0)), atol=1e-9)
    # closed form of this arm written out once more: 1000 cos 30° + 500 cos 75°
    assert got.pos.x == pytest.approx(
        1000 * math.cos(math.radians(30)) + 500 * math.cos(math.radians(75))
    )


def test_actual_pose_and_joints_come_from_the_controller():
    body = """main: L1 PUSHSYS R_ACT_JOINT
    L1 POPG 0
    L2 PUSHSYS R_ACT_POSE
    L2 POPG 1
    L3 END"""
    ctl = FakeController(joints=(90.0, -90.0, 5.0))
    state = run(main_program(body, decls="GLOBAL 0 MAIN_JOINT k\nGLOBAL 1 POSE p"), ctl).state
    assert state.value("k") == JointTuple("MAIN_JOINT", (90.0, -90.0, 5.0))
    np.testing.assert_allclose(state.value("p").pos.as_tuple(), (500.0, 1000.0, 5.0), atol=1e-9)


def test_orientation_compose_is_the_quaternion_product():
    a, b = V.orientation_from_zyx(20, 30, 40), V.orientation_from_zyx(-50, 10, 5)
    got = V.quat_multiply(a, b)
    np.testing.assert_allclose(quat_matrix(got), quat_matrix(a) @ quat_matrix(b), atol=1e-12)
    moved = V.transform_point(Pose(Position(0, 0, 0), a), Position(1, 0, 0))
    np.testing.assert_allclose(moved.as_tuple(), quat_matrix(a) @ np.array([1.0, 0, 0]), atol=1e-12)
