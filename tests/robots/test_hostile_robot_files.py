"""Hostile robot files (issue 11): every malformed TOML or URDF is a RobotFileError naming
the file and the key, never a KeyError, IndexError, OverflowError or ZeroDivisionError."""

from __future__ import annotations

import pytest
from irlc.robots import RobotFileError, load_robot

from .test_loader_errors import GOOD
from .test_urdf import BRANCHED

SERIAL = BRANCHED.replace('<link name="b"/>', "").split('<joint name="jb"')[0] + "</robot>"

pytest.importorskip("yourdfpy")

GEOMETRY = '[[geometry]]\nlink = 1\nshape = "sphere"\ncenter = [0, 0, 0]\nradius = {r}\n'
INERTIAL = '[[inertials]]\nlink = 1\nmass = 1.0\ninertia = "from_geometry"\n'


@pytest.mark.parametrize(
    ("extra", "key", "words"),
    [
        # r⁵ overflowed in solid_inertia (OverflowError)
        (
            GEOMETRY.format(r="1e308") + INERTIAL,
            "geometry[1].radius",
            r"1e\+308 m is outside the physical range of a length \(1e-06 to 1000 m\)",
        ),
        # the volume underflowed to zero (ZeroDivisionError)
        (
            GEOMETRY.format(r="1e-320") + INERTIAL,
            "geometry[1].radius",
            r"9.99989e-321 m is outside",
        ),
        (
            '[[geometry]]\nlink = 1\nshape = "capsule"\na = [0, 0, 0]\nb = [0, 0, 1e300]\n'
            "radius = 0.1\n",
            "geometry[1].b",
            r"1e\+300 m is outside the physical range of a coordinate",
        ),
        (  # the trace writer met a non-finite x_mm (NonFiniteError, exit 4)
            "link = [1.0, 0.0, 0.0] => link = [1e308, 0.0, 0.0]",
            "joints[1].link",
            r"1e\+308 m is outside the physical range of a coordinate",
        ),
        ("[tool]\nxyz = [0, 0, 1e300]\n", "tool.xyz", r"1e\+300 m is outside"),
    ],
)
def test_robot_geometry_outside_the_physical_range(tmp_path, extra, key, words) -> None:
    p = tmp_path / "tiny.toml"
    p.write_text(GOOD + extra if extra.startswith("[") else GOOD.replace(*extra.split(" => ")))
    with pytest.raises(RobotFileError, match=words) as err:
        load_robot(str(p))
    assert err.value.file == str(p) and err.value.key == key


@pytest.mark.parametrize(
    ("text", "key", "words"),
    [
        (  # a child link that is never declared: KeyError in _convert (urdf_import.py:98)
            BRANCHED.replace('<child link="b"/>', '<child link="nowhere"/>'),
            "joint 'jb'.child",
            "no link named 'nowhere'",
        ),
        (  # a joint whose parent is undeclared: KeyError in _path (urdf_import.py:158)
            BRANCHED.replace(
                '<parent link="r"/><child link="b"/>', '<parent link="-1"/><child link="b"/>'
            ),
            "joint 'jb'.parent",
            "no link named a string of 2 characters",  # file text is described, not shown
        ),
        (  # a cycle a → b → a below the root: IndexError in _chain (no leaf)
            BRANCHED.replace(
                '<parent link="r"/><child link="b"/>', '<parent link="a"/><child link="b"/>'
            ).replace(
                "</robot>",
                '<joint name="jc" type="fixed"><parent link="b"/><child link="a"/></joint></robot>',
            ),
            "joint 'jc'.child",
            "already hangs from joint 'ja'",
        ),
        (
            SERIAL.replace(
                '<link name="a"/>',
                '<link name="a"><collision><geometry>'
                '<sphere radius="1e308"/></geometry></collision></link>',
            ),
            "link 'a'.collision.sphere.radius",
            "outside the physical range",
        ),
        (  # an empty axis: a ValueError in the axis normalisation (found by the fuzz test)
            SERIAL.replace('<axis xyz="0 0 1"/>', '<axis xyz=""/>'),
            "joint 'ja'.axis",
            "expected 3 numbers",
        ),
        (
            SERIAL.replace('lower="-1"', 'lower="nan"'),
            "joint 'ja'.limit",
            "expected finite numbers",
        ),
    ],
)
def test_malformed_urdf_names_file_and_key(tmp_path, text, key, words) -> None:
    p = tmp_path / "bad.urdf"
    p.write_text(text)
    with pytest.raises(RobotFileError, match=words) as err:
        load_robot(str(p))
    assert err.value.file == str(p) and err.value.key == key


def test_a_huge_axis_vector_is_normalised_without_overflow(tmp_path) -> None:
    p = tmp_path / "tiny.toml"
    p.write_text(GOOD.replace("axis = [0.0, 0.0, 1.0]", "axis = [0.0, 1e308, 1e308]"))
    axis = load_robot(str(p)).joints[1].axis
    assert axis == pytest.approx([0.0, 0.5**0.5, 0.5**0.5])
