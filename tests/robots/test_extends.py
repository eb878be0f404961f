"""``[robot] extends``: a robot file that is another one with a few changes (robots/extends.py)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from irlc.robots import RobotFileError, load_robot, resolve_robot
from irlc.robots.loader import load_toml

PARENT = """
[robot]
name = "slide2"
description = "two joints"
chain = "axes"
units = { angle = "deg", length = "mm" }
home = [10.0, 0.0]

[assumptions]
inertials = "made up"

[[joints]]
name = "s"
kind = "prismatic"
axis = "x"
link = [0, 0, 100]
position = [0.0, 500.0]
speed = 100.0
accel = 1000.0

[[joints]]
name = "r"
kind = "revolute"
axis = "z"
link = [100, 0, 0]
position = [-90.0, 90.0]
speed = 90.0
accel = 900.0

[[coupled_limits]]
name = "r-only"
coeffs = [0, 1]
min = -45.0
max = 45.0
"""


def write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


CHILD = """
[robot]
extends = "parent.toml"
description = "the parent with a shorter slide and a wider coupled row"

[[joints]]
name = "s"
position = [0.0, 250.0]

[[coupled_limits]]
name = "r-only"
max = 80.0

[[coupled_limits]]
name = "r-new"
coeffs = [0, 1]
min = -60.0
"""


def test_child_rows_merge_by_name_and_other_values_are_inherited(tmp_path):
    write(tmp_path, "parent.toml", PARENT)
    model = load_toml(write(tmp_path, "child.toml", CHILD))
    assert model.name == "child"  # the name is not inherited
    assert model.description.startswith("the parent with")
    assert np.allclose(model.position_limits[0], [0.0, 0.25])  # mm of the parent's units
    assert np.allclose(np.degrees(model.position_limits[1]), [-90, 90])  # inherited joint
    assert model.joints[0].kind == "prismatic"  # the rest of the row is the parent's
    rows = {c["name"]: c for c in model.extra["coupled_limits"]}
    assert np.degrees([rows["r-only"]["lower"], rows["r-only"]["upper"]]) == pytest.approx(
        [-45, 80]
    )
    assert np.degrees(rows["r-new"]["lower"]) == pytest.approx(-60)
    assert model.extra["assumed"]["inertials"] == "made up"
    assert model.extra["extends"] == [str((tmp_path / "parent.toml").resolve())]
    assert np.allclose(model.home, [0.01, 0.0])


def test_a_library_name_can_be_extended_and_the_variant_is_the_parent_elsewhere():
    irb6, variant = load_robot("irb6"), load_robot("irb6_symmetric5")
    assert variant.n == irb6.n and variant.extra["drives"] == irb6.extra["drives"]
    for a, b in zip(irb6.joints, variant.joints, strict=True):
        assert a.name == b.name and np.allclose(a.origin, b.origin) and a.offset == b.offset
        assert (a.limits == b.limits) == (a.name != "A5")
    same = ["theta2+theta3", "theta2+theta3+theta4"]
    rows = {c["name"]: c for c in variant.extra["coupled_limits"]}
    book = {c["name"]: c for c in irb6.extra["coupled_limits"]}
    for name in same:
        assert (
            rows[name]["lower"] == book[name]["lower"]
            and rows[name]["upper"] == book[name]["upper"]
        )
    window = rows["theta5-theta234/k5"]
    assert np.degrees([window["lower"], window["upper"]]) == pytest.approx([-180, 180])
    assert "assumed" in window  # the parent's assumption stays with the merged row


@pytest.mark.parametrize(
    ("child", "message"),
    [
        ('[robot]\nextends = "nothere.toml"\n', "file not found: nothere.toml"),
        ('[robot]\nextends = "nosuchrobot"\n', "no library robot of that name"),
        ('[robot]\nextends = "parent.toml"\nunits = { angle = "rad" }\n', "keeps the parent's"),
        ('[robot]\nextends = "parent.toml"\n[[joints]]\nname = "zz"\n', "no joint 'zz'"),
        ('[robot]\nextends = "parent.toml"\n[[joints]]\nspeed = 1.0\n', "needs a name"),
        ("[robot]\nextends = 3\n", "expected a string"),
        ('[robot]\nextends = "child.toml"\n', "a cycle"),
    ],
)
def test_bad_extends_is_a_robot_file_error(tmp_path, child, message):
    write(tmp_path, "parent.toml", PARENT)
    path = write(tmp_path, "child.toml", child)
    with pytest.raises(RobotFileError, match=message) as info:
        load_toml(path)
    assert "child.toml" in str(info.value)


def test_a_longer_cycle_and_the_merged_values_are_checked(tmp_path):
    write(tmp_path, "a.toml", '[robot]\nextends = "b.toml"\n')
    write(tmp_path, "b.toml", '[robot]\nextends = "a.toml"\n')
    with pytest.raises(RobotFileError, match="a cycle"):
        load_toml(tmp_path / "a.toml")
    write(tmp_path, "parent.toml", PARENT)
    bad = write(tmp_path, "c.toml", CHILD.replace("[0.0, 250.0]", "[300.0, 250.0]"))
    with pytest.raises(RobotFileError, match="expected min ≤ max"):
        load_toml(bad)


def test_a_programs_robot_file_extends_only_inside_its_roots(tmp_path):
    inner = tmp_path / "cell"
    inner.mkdir()
    write(tmp_path, "parent.toml", PARENT)
    child = write(inner, "child.toml", CHILD.replace("parent.toml", "../parent.toml"))
    assert load_toml(child).n == 2  # the user's own file: anywhere
    with pytest.raises(RobotFileError, match="allow-any-path"):
        load_toml(child, roots=(inner,))
    library = write(inner, "lib.toml", '[robot]\nextends = "planar3"\n')
    assert load_toml(library, roots=(inner,)).n == 3  # a library name is always allowed


def test_cached_variant_is_read_again_when_its_parent_changes(tmp_path):
    parent = write(tmp_path, "parent.toml", PARENT)
    child = write(tmp_path, "child.toml", CHILD)
    first = resolve_robot(str(child))
    assert resolve_robot(str(child)) is first
    parent.write_text(PARENT.replace("[-90.0, 90.0]", "[-80.0, 80.0]"), encoding="utf-8")
    os.utime(parent, ns=(1, 10**18))
    again = resolve_robot(str(child))
    assert np.allclose(np.degrees(again.position_limits[1]), [-80, 80])
