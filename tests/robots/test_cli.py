"""irlc robots / robot / fk / ik through the real entry point (exit codes of interfaces.md)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from irlc.cli import main
from irlc.robots import load_robot
from irlc.runtime import units
from irlc.runtime.model.kinematics import Kinematics


def run(capsys, *args: str) -> tuple[int, str, str]:
    code = main(list(args))
    out = capsys.readouterr()
    return code, out.out, out.err


KONF0 = [
    "-0.695",
    "-75",
    "-102",
    "115.205",
    "-98.722",
    "-76.097",
    "-0.168",
    "-21.813",
    "-90.452",
    "227.313",
    "21.119",
]


def test_fk_json(capsys):
    code, out, _ = run(capsys, "fk", "koch11", *KONF0, "--json")
    assert code == 0
    data = json.loads(out)
    assert set(data) == {
        "robot",
        "units",
        "joint_names",
        "robot_joint_names",
        "joint_units",
        "joints",
        "pose",
        "matrix",
        "outside_limits",
    }
    assert data["outside_limits"] == []  # konf_0 is inside every position limit
    assert data["units"] == {"length": "mm", "angle": "deg"}
    assert data["robot"] == "koch11" and data["joints"] == [float(v) for v in KONF0]
    assert data["joint_names"] == [f"a{i}" for i in range(1, 12)]
    assert data["robot_joint_names"] == [f"J{i}" for i in range(1, 12)]
    assert data["joint_units"][9] == "mm" and data["joint_units"][10] == "deg"
    assert np.allclose(data["pose"], [11500, 1000, 3500, 0, 0, 0], atol=0.1)
    m = np.array(data["matrix"])
    # one number, one unit: the matrix translation is the pose's position, in mm
    assert m.shape == (4, 4) and np.allclose(m[:3, 3], [11500, 1000, 3500], atol=0.1)
    np.testing.assert_allclose(m[:3, 3], data["pose"][:3], atol=1e-6)
    assert np.allclose(m[3], [0, 0, 0, 1])


def test_fk_json_matrix_is_the_independent_fk_in_mm(capsys):
    """panda's matrix equals Kinematics.tcp (metres) scaled by 1000 in the translation only."""
    q = [10, -30, 5, -120, 15, 95, 40]
    code, out, _ = run(capsys, "fk", "panda", *map(str, q), "--json")
    assert code == 0
    data = json.loads(out)
    model = load_robot("panda")
    t = Kinematics(model).tcp(units.joints_to_si(q, model.joint_kinds))
    m = np.array(data["matrix"])
    np.testing.assert_allclose(m[:3, :3], t[:3, :3], atol=1e-9)
    np.testing.assert_allclose(m[:3, 3], t[:3, 3] * 1000.0, atol=1e-6)
    assert data["robot_joint_names"][3] == "panda_joint4" and data["joint_names"][3] == "a4"


def test_fk_and_robot_text_name_joints_by_the_one_rule(capsys):
    """Program names a1 … aN first, the robot file's names beside them (mobile8: a5 is A3)."""
    code, out, _ = run(capsys, "fk", "mobile8", "100", "0", "0", "-30", "60", "0", "-30", "0")
    assert code == 0 and "a5 (A3) [deg]" in out and "a1 (X) [mm]" in out
    code, out, _ = run(capsys, "robot", "panda")
    assert code == 0
    rows = [line.split() for line in out.splitlines()]
    assert ["a4", "panda_joint4", "deg"] in [r[:3] for r in rows]
    assert "R_TOOL is composed after this tool" in out
    # Franka's jerk limits (7500 rad/s³ on joint 1, 3750 on joint 2) in deg/s³
    flat = " ".join(out.split())
    assert "jerk limits [deg/s³ | mm/s³]: a1 429718, a2 214859," in flat
    code, out, _ = run(capsys, "robot", "irb6")
    assert code == 0 and "jerk limits" not in out  # none in its file
    code, _, err = run(capsys, "fk", "mobile8", "1", "2")
    assert code == 3 and "a1 (X), a2 (Y), a3 (A1)" in err


def test_fk_planar3_values(capsys):
    code, out, _ = run(capsys, "fk", "planar3", "90", "-90", "0", "--json")
    data = json.loads(out)
    assert code == 0 and np.allclose(data["pose"], [2000, 1000, 0, 0, 0, 0], atol=1e-9)


def test_fk_beyond_the_position_limits_warns_and_lists_the_joints(capsys):
    """Regression: fk computed joint values beyond the robot's limits without a word."""
    from irlc.robots import load_robot

    lim = np.degrees(load_robot("planar3").position_limits)  # ±180° each, from the file
    q = (10.0, lim[1, 1] + 20.0, lim[2, 0] - 120.0)
    code, out, err = run(capsys, "fk", "planar3", *map(str, q), "--json")
    assert code == 0
    assert json.loads(out)["outside_limits"] == [
        {"joint": "a2", "value": q[1], "bound": lim[1, 1], "side": "max", "unit": "deg"},
        {"joint": "a3", "value": q[2], "bound": lim[2, 0], "side": "min", "unit": "deg"},
    ]
    warnings = [line for line in err.splitlines() if line.startswith("irlc: warning: ")]
    assert len(warnings) == 2
    assert f"joint a2 (J2) is at {q[1]:g} deg, above the upper bound {lim[1, 1]:g} deg" in err
    on_the_bound = run(capsys, "fk", "planar3", "0", str(lim[1, 1]), str(lim[2, 0]))
    assert on_the_bound[0] == 0 and "warning" not in on_the_bound[2]  # a bound is inside


def test_fk_and_ik_seed_refuse_joint_values_beyond_1e9(capsys):
    """Regression: `fk planar3 1e308 0 0` printed the joint as a 300-digit number."""
    code, out, err = run(capsys, "fk", "planar3", "1e308", "0", "0")
    assert (code, out) == (3, "")
    assert "joint value 1 (a1) = 1e+308 deg is out of range (|value| ≤ 1e9 deg)" in err
    code, _, err = run(capsys, "ik", "planar3", "1000", "0", "0", "0", "0", "0", "--seed", "0",
                       "0", "-2e9")  # fmt: skip
    assert code == 3 and "seed value 3 (a3) = -2e+09 deg is out of range" in err
    assert run(capsys, "fk", "planar3", "1e9", "0", "0")[0] == 0  # the bound itself is fine


def test_fk_table(capsys):
    code, out, _ = run(capsys, "fk", "planar3", "0", "0", "0")
    assert code == 0 and "x [mm]" in out and "3000.0000" in out


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["fk", "planar3", "1", "2"], "has 3 joints"),
        (["fk", "planar3", "1", "x", "2"], "'x' is not a number"),
        (["fk", "planar3", "1", "nan", "2"], "not a finite number"),
        (["fk", "nobot", "1"], "unknown robot"),
        (["ik", "planar3", "1", "2", "3"], "x y z a b c"),
        (["ik", "planar3", "1000", "0", "0", "0", "0", "0", "--seed", "1"], "has 3 joints"),
        (["robot", "nobot"], "unknown robot"),
    ],
)
def test_usage_errors_exit_3(capsys, args, words):
    code, out, err = run(capsys, *args)
    assert code == 3
    assert words in err
    assert "Traceback" not in out + err


def test_robots_and_robot(capsys):
    code, out, _ = run(capsys, "robots")
    assert code == 0 and "koch11" in out and "RRRRRRRRRPR" in out
    code, out, _ = run(capsys, "robot", "koch11")
    assert code == 0 and "J10" in out and "limit sets" in out


def test_robot_irb6_states_the_5_1b_assumptions(capsys):
    """`irlc robot irb6` shows the θ5 window with its assumed k5, and why a4 has no box of
    its own beyond (5.1b)."""
    code, out, _ = run(capsys, "robot", "irb6")
    text = " ".join(out.split())
    assert code == 0
    assert "coupled limit theta5-theta234/k5" in text and "k5 = 1 assumed" in text
    assert "assumed: k5" in text
    assert "note on a4: Position: (5.1b) bounds θ4 only through" in text
    assert "closed-form IK: parallel_5r (irlc ik --branch: front-elbow-up," in text


ik = pytest.importorskip("irlc.runtime.ik")
needs_ik = pytest.mark.skipif(not hasattr(ik, "solve_pose"), reason="solve_pose not yet available")


@needs_ik
def test_ik_json_converges_to_an_fk_pose(capsys):
    model = load_robot("planar3")
    q = units.joints_to_si([20, 40, -30], model.joint_kinds)
    pose = units.pose_from_si(Kinematics(model).tcp(q))
    code, out, _ = run(
        capsys, "ik", "planar3", *map(str, pose), "--seed", "10", "30", "-20", "--json"
    )
    data = json.loads(out)
    assert code == 0
    assert set(data) >= {
        "robot",
        "pose",
        "joints",
        "converged",
        "position_error_mm",
        "orientation_error_deg",
    }
    assert data["converged"] is True and data["position_error_mm"] < 1e-3
    assert data["units"] == {"length": "mm", "angle": "deg"}
    assert data["joint_names"] == ["a1", "a2", "a3"]
    assert len(data["robot_joint_names"]) == 3
    reached = units.pose_from_si(
        Kinematics(model).tcp(units.joints_to_si(data["joints"], model.joint_kinds))
    )
    assert np.allclose(reached[:3], pose[:3], atol=1e-3)


@needs_ik
def test_ik_unreachable_exits_2(capsys):
    code, out, _ = run(capsys, "ik", "planar3", "5000", "0", "0", "0", "0", "0", "--json")
    assert code == 2
    data = json.loads(out)
    assert data["converged"] is False and data["pose"] == [5000, 0, 0, 0, 0, 0]
    model = load_robot("planar3")  # reached_pose: the FK of the joints found, not the target
    q = units.joints_to_si(data["joints"], model.joint_kinds)
    reached = units.pose_from_si(Kinematics(model).tcp(q))
    np.testing.assert_allclose(data["reached_pose"], reached, atol=1e-6)
    assert np.hypot(*(np.array(data["pose"][:2]) - reached[:2])) == pytest.approx(
        data["position_error_mm"], rel=1e-3
    )
    code, out, _ = run(capsys, "ik", "planar3", "5000", "0", "0", "0", "0", "0")
    rows = {line.split("│")[1].strip(): line.split("│")[2].strip() for line in out.splitlines()
            if line.count("│") == 3}  # fmt: skip
    assert code == 2 and rows["target x [mm]"] == "5000.0000" and "x [mm]" not in rows
    assert float(rows["reached x [mm]"]) == pytest.approx(reached[0], abs=1e-4)


@needs_ik
def test_ik_five_axis_out_of_plane_explains_why(capsys):
    """A pose whose approach vector leaves the IRb-6's vertical plane cannot be reached."""
    code, out, _ = run(capsys, "ik", "irb6", "600", "300", "900", "30", "40", "0", "--json")
    data = json.loads(out)
    assert code == 2 and data["converged"] is False
    assert "vertical plane" in data["message"]


ROBOTS = __import__("pathlib").Path(__file__).resolve().parents[2] / "robots"


@pytest.mark.parametrize(
    ("robot", "old", "new", "who"),
    [  # l1's transmission couples its wrist: every run reads the steppers' data
        ("l1", "\nR = 1.0\n", "\nR = -1.0\n", "even with ideal drives"),
        ("koch11", "R = { value = 0.06", "R = { value = -0.06", "irlc run --drives refuses"),
    ],
)
def test_robot_warns_about_drive_data_run_would_refuse(tmp_path, capsys, robot, old, new, who):
    """irlc robot showed a robot whose drive data irlc run then refused (l1: even with
    ideal drives): it now says so, with the file, line and key; the library's robots have
    no such warning."""
    text = (ROBOTS / f"{robot}.toml").read_text()
    assert old in text
    path = tmp_path / f"{robot}_bad.toml"
    path.write_text(text.replace(old, new, 1))
    code, _, err = run(capsys, "robot", str(path))
    assert code == 0 and "irlc: warning:" in err and who in err, err
    assert f"{path.name}:" in err and "drives." in err
    program = tmp_path / "p.irl"
    program.write_text(
        f"PROGRAM p;\nROBOT r := '{path.name}';\nBEGIN\n  WAIT 0.1 SEC;\nENDPROGRAM\n"
    )
    drives = [] if "ideal" in who else ["--drives", "decoupled"]
    code, _, err = run(capsys, "run", "-q", str(program), *drives)
    assert code == 3 and "drives." in err, err  # what the warning foretold
    for name in ("l1", "koch11", "irb6"):
        code, _, err = run(capsys, "robot", name)
        assert code == 0 and "warning" not in err
