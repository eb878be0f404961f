"""Fuzz robot files, URDFs and data lists (issue 11): a malformed file is a
``RobotFileError`` (robots) or a diagnostic naming the file (data lists), never another
exception."""

from __future__ import annotations

import re

import pytest
from hypothesis import given
from hypothesis import strategies as st
from irlc.lang import SimpleRobot, compile_source
from irlc.robots import RobotFileError, load_robot

from ..fuzz_budget import fuzz_settings
from .test_loader_errors import GOOD

HOSTILE_NUMBERS = ["1e308", "-1e308", "1e-320", "0", "-1", "nan", "inf", "1e300", "0.0", "2"]
HOSTILE_VALUES = [*HOSTILE_NUMBERS, '"x"', "[]", "[1, 2]", "[1e308, 0, 0]", "true", "{}"]
URDF = (
    '<robot name="f"><link name="r"/><link name="a"><collision><geometry>'
    '<sphere radius="0.1"/></geometry></collision><inertial><mass value="1"/>'
    '<inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>'
    '<link name="b"/><joint name="ja" type="revolute"><parent link="r"/><child link="a"/>'
    '<origin xyz="0 0 1" rpy="0 0 0"/><axis xyz="0 0 1"/>'
    '<limit lower="-1" upper="1" velocity="1" effort="1"/></joint>'
    '<joint name="jb" type="prismatic"><parent link="a"/><child link="b"/>'
    '<axis xyz="1 0 0"/><limit lower="0" upper="1" velocity="1" effort="1"/></joint></robot>'
)
_ATTR = re.compile(r'="([^"]*)"')
URDF_VALUES = [*HOSTILE_NUMBERS, "", "r", "a", "b", "nowhere", "fixed", "floating", "1 2", "0 0 0"]
GEOMETRY_ROW = '\n[[geometry]]\nlink = {link}\nshape = "{shape}"\n{key} = {value}\nradius = {r}\n'


def _load(tmp_path, name: str, text: str) -> None:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    try:
        load_robot(str(path))
    except RobotFileError as e:
        assert str(path) in str(e)


@fuzz_settings(60)
@given(
    st.sampled_from(["0", "1", "2", "5", "-1", '"a"']),
    st.sampled_from(["sphere", "capsule", "box"]),
    st.sampled_from(["center", "a", "b"]),
    st.sampled_from(HOSTILE_VALUES),
    st.sampled_from(HOSTILE_VALUES),
    st.booleans(),
)
def test_fuzz_robot_geometry(tmp_path_factory, link, shape, key, value, r, inertial) -> None:
    text = GOOD + GEOMETRY_ROW.format(link=link, shape=shape, key=key, value=value, r=r)
    if inertial:
        text += '\n[[inertials]]\nlink = 1\nmass = 1.0\ninertia = "from_geometry"\n'
    _load(tmp_path_factory.mktemp("robot"), "tiny.toml", text)


@fuzz_settings(200)
@given(st.lists(st.tuples(st.integers(0, 10**6), st.sampled_from(URDF_VALUES)), max_size=4))
def test_fuzz_urdf_attributes(tmp_path_factory, edits) -> None:
    pytest.importorskip("yourdfpy")
    text = URDF
    for where, value in edits:
        spots = list(_ATTR.finditer(text))
        m = spots[where % len(spots)]
        text = text[: m.start(1)] + value + text[m.end(1) :]
    _load(tmp_path_factory.mktemp("urdf"), "f.urdf", text)


ROBOT = SimpleRobot("six", ("revolute",) * 6)
SOURCE = "PROGRAM t;\nROBOT r := six;\nIMPORT DATALIST cell;\nBEGIN\nENDPROGRAM\n"
SECTIONS = {
    "obstacles.o": ["kind", "center", "radius", "size", "rotation", "a", "b", "point", "normal"],
    "poses": ["p"],
    "joints": ["k"],
    "limits": ["m"],
    "inputs": ["1", "x"],
}
KINDS = ['"sphere"', '"box"', '"capsule"', '"plane"', '"point"', "[1, 2]", "1", '"cone"']


@fuzz_settings(300)
@given(
    st.sampled_from(sorted(SECTIONS)),
    st.data(),
    st.lists(st.sampled_from([*HOSTILE_VALUES, "[[0.5, true]]", "[0, 0, 0, 0, 0, 0]"]), max_size=6),
)
def test_fuzz_data_lists(tmp_path_factory, section, data, values) -> None:
    keys = SECTIONS[section]
    lines = [f"[{section}]"]
    if section == "obstacles.o":
        lines.append(f"kind = {data.draw(st.sampled_from(KINDS))}")
    for value in values:
        lines.append(f"{data.draw(st.sampled_from(keys))} = {value}")
    folder = tmp_path_factory.mktemp("dl")
    (folder / "cell.toml").write_text("\n".join(lines) + "\n", encoding="utf-8")
    result = compile_source(SOURCE, str(folder / "t.irl"), resolve_robot=lambda n: ROBOT)
    for d in result.errors:
        assert d.file.endswith(("cell.toml", "t.irl")), d


FIELDS = [
    ("link = [1.0, 0.0, 0.0]", "link = [{v}, 0.0, 0.0]"),
    ("speed = 90.0", "speed = {v}"),
    ("accel = 500.0", "accel = {v}"),
    ("position = [-90.0, 90.0]", "position = [-{v}, {v}]"),
    ("home = [0.0, 0.0]", "home = [{v}, 0.0]"),
    ("axis = [0.0, 0.0, 1.0]", "axis = [0.0, {v}, {v}]"),
]
PROGRAM = (
    "PROGRAM p;\nROBOT r := 'tiny.toml';\nBEGIN\n  MOVE PTP (10, 0.1);\n"
    "  MOVE LIN POSE(0.5, 0.2, 0.1, 0, 0, 0);\nENDPROGRAM\n"
)


@fuzz_settings(25)
@given(st.sampled_from(FIELDS), st.sampled_from(["1e308", "1e-320", "1e300", "0.0", "1e6"]))
def test_fuzz_robot_numbers_through_a_run(tmp_path_factory, field, value) -> None:
    from irlc.cli import main

    folder = tmp_path_factory.mktemp("run")
    (folder / "tiny.toml").write_text(GOOD.replace(field[0], field[1].format(v=value)))
    (folder / "p.irl").write_text(PROGRAM)
    code = main(["run", str(folder / "p.irl"), "-q", "--trace", str(folder / "t.csv")])
    assert code in (0, 1, 2, 3)
