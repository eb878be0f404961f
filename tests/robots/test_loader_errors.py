"""Broken robot files: each error names the file and the key, never a traceback."""

from __future__ import annotations

import math

import pytest
from irlc.robots import RobotFileError, load_robot

GOOD = """
[robot]
name = "tiny"
chain = "axes"
home = [0.0, 0.0]

[[joints]]
name = "A"
kind = "revolute"
axis = "z"
link = [1.0, 0.0, 0.0]
position = [-90.0, 90.0]
speed = 90.0
accel = 500.0

[[joints]]
name = "B"
kind = "prismatic"
axis = [0.0, 0.0, 1.0]
position = [-0.5, 0.5]
speed = [-1.0, 1.0]
accel = 5.0
"""


def write(tmp_path, text: str):
    p = tmp_path / "tiny.toml"
    p.write_text(text)
    return p


def test_jerk_is_optional_and_in_the_joint_unit(tmp_path):
    m = load_robot(
        str(write(tmp_path, GOOD.replace("accel = 5.0\n", "accel = 5.0\njerk = 50.0\n")))
    )
    assert m.joints[0].limits.jerk is None  # A: none given
    assert m.joints[1].limits.jerk == 50.0  # B: prismatic, m/s³ in this file (SI)
    m = load_robot(
        str(write(tmp_path, GOOD.replace("accel = 500.0\n", "accel = 500.0\njerk = 1800\n")))
    )
    assert m.jerk_limits[0] == pytest.approx(math.radians(1800.0))  # deg/s³ → rad/s³


def test_good_file_loads(tmp_path):
    m = load_robot(str(write(tmp_path, GOOD)))
    assert m.joint_names == ("A", "B")
    assert m.joint_kinds == ("revolute", "prismatic")
    assert list(m.weights) == [2.0, 1.0]  # default w_i = n − i + 1


CASES = [
    # (replace old → new, key expected in the message, words expected)
    ('axis = "z"', 'axis = "w"', "joints[1].axis", "expected one of"),
    ("axis = [0.0, 0.0, 1.0]", "axis = [0.0, 1.0]", "joints[2].axis", "expected 3 numbers"),
    ('kind = "revolute"', 'kind = "spherical"', "joints[1].kind", "expected one of"),
    ("position = [-90.0, 90.0]", "position = [90.0, -90.0]", "joints[1].position", "min ≤ max"),
    ("speed = 90.0", "speed = -90.0", "joints[1].speed", "positive"),
    ("accel = 500.0\n", "", "joints[1].accel", "missing"),
    ("accel = 500.0\n", "accel = 500.0\njerk = 0.0\n", "joints[1].jerk", "positive number"),
    ("accel = 5.0\n", "accel = 5.0\njerk = [1.0, 2.0]\n", "joints[2].jerk", "a number"),
    ('name = "A"\n', 'name = "A"\ncolour = "red"\n', "joints[1].colour", "unknown key"),
    ('chain = "axes"', 'chain = "screw"', "robot.chain", "expected one of"),
    ("home = [0.0, 0.0]", "home = [0.0]", "robot.home", "expected 2 numbers"),
    ("home = [0.0, 0.0]", "home = [120.0, 0.0]", "robot.home[0]", "outside"),
    ("home = [0.0, 0.0]", 'home = [0.0, "x"]', "robot.home[1]", "expected a number"),
    ('name = "B"', 'name = "A"', "joints[2].name", "duplicate"),
    (
        "link = [1.0, 0.0, 0.0]",
        "link = [1.0, 0.0, 0.0]\ndh = { alpha = 0, a = 1 }",
        "joints[1].dh",
        "not used",
    ),
]


@pytest.mark.parametrize(("old", "new", "key", "words"), CASES)
def test_bad_file_names_file_and_key(tmp_path, old, new, key, words):
    assert old in GOOD
    path = write(tmp_path, GOOD.replace(old, new, 1))
    with pytest.raises(RobotFileError) as err:
        load_robot(str(path))
    text = str(err.value)
    assert str(path) in text
    assert f"key '{key}'" in text
    assert words in text


@pytest.mark.parametrize(
    ("extra", "key", "words"),
    [
        ("[base]\nxyz = [1, 2]\n", "base.xyz", "expected 3 numbers"),
        (
            "[tool]\nmatrix = [[1, 0, 0, 0], [0, 2, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n",
            "tool.matrix",
            "rigid",
        ),
        ("[tool]\nxyz = [0, 0, 1]\nassumed = true\n", "tool.reason", "needs a reason"),
        (
            '[[geometry]]\nlink = 5\nshape = "sphere"\ncenter = [0, 0, 0]\nradius = 0.1\n',
            "geometry[1].link",
            "0..2",
        ),
        (
            '[[geometry]]\nlink = 1\nshape = "capsule"\na = [0, 0, 0]\nradius = 0.1\n',
            "geometry[1].b",
            "missing",
        ),
        (
            "[[inertials]]\nlink = 1\nmass = 1.0\ncom = [0, 0, 0]\ninertia = [1, 1, 5, 0, 0, 0]\n",
            "inertials[1].inertia",
            "triangle",
        ),
        (
            "[[inertials]]\nlink = 1\nmass = -1.0\ncom = [0, 0, 0]\ninertia = [1, 1, 1, 0, 0, 0]\n",
            "inertials[1].mass",
            "positive",
        ),
        ("[[coupled_limits]]\ncoeffs = [1, 1]\nmin = 0\n", "coupled_limits[1].coeffs", "one kind"),
        (
            "[[coupled_limits]]\ncoeffs = [1, 0]\nmin = 10\nmax = 0\n",
            "coupled_limits[1]",
            "min ≤ max",
        ),
        (
            "[transmission]\n[[transmission.joints]]\nratio = 2.0\n",
            "transmission.joints",
            "expected 2 entries",
        ),
        (
            "[transmission]\n[[transmission.joints]]\nratio = 2.0\n[[transmission.joints]]\n"
            "couple = [[2, 0.5]]\n",
            "transmission.joints[2].couple[0]",
            "earlier joints",
        ),
        ("[limit_sets.small]\nposition = [[0, 1]]\n", "limit_sets.small.position", "expected 2"),
        ("[wheels]\ncount = 4\n", "wheels", "unknown key"),
    ],
)
def test_bad_sections(tmp_path, extra, key, words):
    path = write(tmp_path, GOOD + "\n" + extra)
    with pytest.raises(RobotFileError) as err:
        load_robot(str(path))
    text = str(err.value)
    assert str(path) in text and f"key '{key}'" in text and words in text


def test_not_toml_and_missing_robot_table(tmp_path):
    with pytest.raises(RobotFileError, match="not valid TOML"):
        load_robot(str(write(tmp_path, "[robot\n")))
    with pytest.raises(RobotFileError, match="key 'robot'"):
        load_robot(str(write(tmp_path, "[base]\nxyz = [0, 0, 0]\n")))


def test_unknown_name_and_missing_file():
    with pytest.raises(RobotFileError, match=r"unknown robot 'no_such_robot' \(known: .*koch11"):
        load_robot("no_such_robot")
    with pytest.raises(RobotFileError, match="file not found"):
        load_robot("/nonexistent/robot.toml")


def test_drives_table_is_kept_unvalidated(tmp_path):
    m = load_robot(
        str(write(tmp_path, GOOD + '\n[drives]\nmodel = "anything"\n[drives.axis1]\nR = 1\n'))
    )
    assert m.extra["drives"] == {"model": "anything", "axis1": {"R": 1}}


def test_assumed_values_are_recorded(tmp_path):
    text = GOOD + '\n[assumptions]\ninertials = "guessed"\n[tool]\nxyz = [0, 0, 0.1]\n'
    m = load_robot(str(write(tmp_path, text)))
    assert m.extra["assumed"]["inertials"] == "guessed"
