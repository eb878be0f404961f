"""Fuzz robot files, URDFs and data lists (issue 11): a malformed file is a
``RobotFileError`` (robots) or a diagnostic naming the file (data lists), never another
exception."""

from __future__ import annotations

import itertools
import re

import pytest
from hypothesis import given
from hypothesis import strategies as st
from irlc.lang import SimpleRobot, compile_source
from irlc.robots import ROBOTS_DIR, RobotFileError, load_robot

from ..fuzz_budget import fuzz_settings, warm_up_kernels
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


@pytest.fixture(scope="module")
def warm() -> None:
    warm_up_kernels()  # the kernels' one-time compile is no case's hang


@fuzz_settings(25)
@given(st.sampled_from(FIELDS), st.sampled_from(["1e308", "1e-320", "1e300", "0.0", "1e6"]))
def test_fuzz_robot_numbers_through_a_run(tmp_path_factory, warm, field, value) -> None:
    from irlc.cli import main

    folder = tmp_path_factory.mktemp("run")
    (folder / "tiny.toml").write_text(GOOD.replace(field[0], field[1].format(v=value)))
    (folder / "p.irl").write_text(PROGRAM)
    code = main(["run", str(folder / "p.irl"), "-q", "--trace", str(folder / "t.csv")])
    assert code in (0, 1, 2, 3)


LIBRARY_TOML = sorted(ROBOTS_DIR.glob("*.toml"))
LIBRARY_LINES = [p.read_text(encoding="utf-8").split("\n") for p in LIBRARY_TOML]
_ASSIGNMENT = re.compile(r"^(\s*[\w\"'.-]+\s*=\s*)(.+)$")
_count = itertools.count()


def _mutate_toml(lines: list[str], ops) -> str:
    """Line-level edits of a robot file: 0 delete, 1 duplicate, 2 a hostile value after
    ``key =``, 3 swap two lines."""
    out = list(lines)
    for kind, i, j, value in ops:
        i, j = i % len(out), j % len(out)
        if kind == 0 and len(out) > 1:
            del out[i]
        elif kind == 1:
            out.insert(i, out[i])
        elif kind == 2:
            spots = [k for k, line in enumerate(out) if _ASSIGNMENT.match(line)]
            if spots:
                k = spots[i % len(spots)]
                m = _ASSIGNMENT.match(out[k])
                out[k] = m.group(1) + value if m else out[k]
        else:
            out[i], out[j] = out[j], out[i]
    return "\n".join(out)


@fuzz_settings(100)
@given(
    st.integers(0, len(LIBRARY_TOML) - 1),
    st.lists(
        st.tuples(
            st.integers(0, 3),
            st.integers(0, 10**6),
            st.integers(0, 10**6),
            st.sampled_from([*HOSTILE_VALUES, "[0.0, 0.0]", "-90.0", '"x"', "{ a = 1 }", "["]),
        ),
        min_size=1,
        max_size=4,
    ),
)
def test_fuzz_library_robot_files_mutated(tmp_path_factory, seed, ops) -> None:
    """Every library robot file, its lines deleted, duplicated, swapped or given hostile
    values: it loads, or the error names the file (a ``RobotFileError``)."""
    folder = tmp_path_factory.getbasetemp() / "mutated_robots"
    folder.mkdir(exist_ok=True)
    path = folder / f"r{next(_count)}.toml"  # a new name each case: the loader's cache
    path.write_text(_mutate_toml(LIBRARY_LINES[seed], ops), encoding="utf-8")
    try:
        load_robot(str(path))
    except RobotFileError as e:
        assert str(path) in str(e)
    finally:
        path.unlink()


@pytest.mark.parametrize(
    ("line", "new", "key", "words"),
    [  # found by the mutation fuzz: NaN inertia (inf * 0) and an overflowing eigen-check
        ("mass = 1.0", "mass = 1e308", "inertials[1].mass", "a mass of 1e+308 kg is outside"),
        ("mass = 1.0", "mass = 1e-320", "inertials[1].mass", "is outside the physical range"),
    ],
)
def test_fuzz_regression_link_mass_out_of_range(tmp_path, line, new, key, words) -> None:
    text = (ROBOTS_DIR / "planar3.toml").read_text(encoding="utf-8").replace(line, new, 1)
    path = tmp_path / "arm.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(RobotFileError) as info:
        load_robot(str(path))
    assert f"key '{key}'" in str(info.value) and words in str(info.value)


def test_fuzz_regression_inertia_and_com_out_of_range(tmp_path) -> None:
    good = (ROBOTS_DIR / "panda.toml").read_text(encoding="utf-8")
    rows = [k for k, line in enumerate(good.split("\n")) if line.startswith("inertia = [")]
    for replacement in ("inertia = [1e308, 1e308, 1e308, 0, 0, 0]", "com = [1e300, 0, 0]"):
        lines = good.split("\n")
        if replacement.startswith("com"):
            rows = [k for k, line in enumerate(lines) if line.startswith("com = [")]
        lines[rows[0]] = replacement
        path = tmp_path / "arm.toml"
        path.write_text("\n".join(lines), encoding="utf-8")
        with pytest.raises(RobotFileError, match="outside the physical range"):
            load_robot(str(path))


def test_fuzz_regression_urdf_without_warnings_or_quoted_values(tmp_path) -> None:
    """The URDF fuzz's numpy warnings (a NaN origin in the parser's transforms) stay
    inside; a parse error does not quote the file ("could not convert string to float:
    'SECRET'")."""
    import warnings

    pytest.importorskip("yourdfpy")
    nan_origin = URDF.replace('rpy="0 0 0"', 'rpy="nan 0 0"')
    bad_mass = URDF.replace('<mass value="1"/>', '<mass value="SECRET"/>')
    mass_words = "f.urdf:1: key '<mass> value': expected 1 number(s), got a string of 6"
    for text, words in ((nan_origin, "expected finite numbers"), (bad_mass, mass_words)):
        path = tmp_path / "f.urdf"
        path.write_text(text, encoding="utf-8")
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            with pytest.raises(RobotFileError) as info:
                load_robot(str(path))
        assert words in str(info.value) and "SECRET" not in str(info.value)
