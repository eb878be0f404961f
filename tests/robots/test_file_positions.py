"""Robot files, URDFs and data lists found by the adversarial fuzz run of issue 11 (helper
h7): each used to end in exit 4, fill the memory, print ``nan``/``inf`` or show the
file's text; now a ``RobotFileError`` / diagnostic names the file, the line and the key."""

from __future__ import annotations

import os
import time

import pytest
from irlc.cli import main
from irlc.lang import SimpleRobot, compile_source
from irlc.lang.toml_keys import MAX_KEY_PARTS, key_line
from irlc.robots import ROBOTS_DIR, RobotFileError, load_robot

from .test_loader_errors import GOOD
from .test_urdf import BRANCHED

END = len(GOOD.splitlines())  # the line before text appended to GOOD


def _error(tmp_path, text: str, name: str = "tiny.toml") -> RobotFileError:
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    with pytest.raises(RobotFileError) as e:
        load_robot(str(p))
    assert str(p) in str(e.value)
    return e.value


def test_an_error_names_the_line_of_its_key(tmp_path) -> None:
    text = GOOD.replace("axis = [0.0, 0.0, 1.0]", 'axis = [0.0, 0.0, "z"]')
    e = _error(tmp_path, text)
    line = text.splitlines().index('axis = [0.0, 0.0, "z"]') + 1
    assert (e.key, e.line) == ("joints[2].axis[2]", line)
    assert str(e).startswith(f"{tmp_path / 'tiny.toml'}:{line}: key 'joints[2].axis[2]'")


@pytest.mark.parametrize(
    ("text", "reason", "line"),
    [
        (GOOD + 'x = "open', "Unterminated string", END + 1),  # "at end of document": the last line
        (
            GOOD + "[tool]\nxyz = [1" + "0" * 5000 + ", 0, 0]\n",
            "a number with too many digits",
            END + 2,
        ),
        (GOOD + "[tool]\nxyz = " + "[" * 2000 + "]" * 2000 + "\n", "nested too deeply", END + 2),
        (GOOD + "a." * 100_000 + "b = 1\n", f"more than {MAX_KEY_PARTS} dotted parts", END + 1),
    ],
)
def test_text_tomllib_cannot_read_is_an_error_with_a_line(tmp_path, text, reason, line) -> None:
    start = time.process_time()  # the dotted key filled gigabytes (quadratic in tomllib)
    e = _error(tmp_path, text)
    assert time.process_time() - start < 2.0
    assert e.line == line and reason in str(e) and "0000" not in str(e)


@pytest.mark.parametrize(
    ("value", "shown"),
    [("nan", "not-a-number"), ("inf", "infinity"), ("-inf", "-infinity")],
)
def test_non_finite_values_are_described_not_printed(tmp_path, value, shown) -> None:
    e = _error(tmp_path, GOOD.replace("accel = 500.0", f"accel = {value}"))
    assert f"got {shown}" in str(e) and "nan" not in str(e).replace("not-a-number", "")


def test_a_huge_hex_integer_is_described(tmp_path) -> None:
    e = _error(tmp_path, GOOD.replace("accel = 500.0", "accel = 0x" + "f" * 6000))  # exit 4
    assert "expected a finite number, got an integer of about 7225 digits" in str(e)


def test_a_joint_bound_beyond_the_range_is_refused(tmp_path, capsys) -> None:
    e = _error(tmp_path, GOOD.replace("accel = 5.0", "accel = 1e308"))  # irlc robot showed ±inf
    assert e.key == "joints[2].accel" and "outside the range of a joint bound" in str(e)


def test_a_long_key_is_shortened(tmp_path) -> None:
    e = _error(tmp_path, GOOD + "[robot2]\n" + "k" * 5000 + " = 1\n")
    assert len(str(e)) < 400


URDF_SECRET = BRANCHED.replace('name="jb"', 'name="SECRET TEXT OF THE FILE: 12345"').replace(
    '<child link="b"/><axis xyz="0 0 1"/>', '<child link="nowhere"/><axis xyz="0 0 1"/>'
)


def test_urdf_errors_name_an_element_by_its_place_and_line_not_its_text(tmp_path) -> None:
    pytest.importorskip("yourdfpy")
    e = _error(tmp_path, URDF_SECRET, "s.urdf")
    assert "SECRET" not in str(e)
    assert e.key == "joint #2 (its name is a string of 30 characters).child"
    assert e.line == 4  # the second <joint> element
    assert "no link named 'nowhere'" in str(e)  # a short word is shown: the user needs it


def test_a_programs_robot_file_may_not_name_a_urdf_outside_its_folders(tmp_path, capsys) -> None:
    pytest.importorskip("yourdfpy")
    (tmp_path / "arm.urdf").write_text(BRANCHED)
    cell = tmp_path / "cell"
    cell.mkdir()
    (cell / "arm.toml").write_text('[robot]\nurdf = "../arm.urdf"\ntip = "a"\n')
    prog = cell / "p.irl"
    prog.write_text("PROGRAM p;\nROBOT r := 'arm.toml';\nBEGIN\nENDPROGRAM\n")
    assert main(["check", str(prog)]) == 1
    err = capsys.readouterr().err
    assert "key 'robot.urdf'" in err and "outside the folders a program may read from" in err
    assert main(["check", str(prog), "--allow-any-path"]) == 0
    assert main(["robot", str(cell / "arm.toml")]) == 0  # a file the user names: anywhere


def test_a_copy_of_a_library_robot_file_is_the_library_file(tmp_path, monkeypatch) -> None:
    """v36_robot_file.irl names '../../../robots/planar3.toml': after a non-editable install
    that file lies outside the library, but holds the same bytes."""
    import irlc.robots as robots

    library = tmp_path / "site" / "robots"
    library.mkdir(parents=True)
    (library / "planar3.toml").write_bytes((ROBOTS_DIR / "planar3.toml").read_bytes())
    monkeypatch.setattr(robots, "ROBOTS_DIR", library)
    source = tmp_path / "repo" / "robots"
    source.mkdir(parents=True)
    (source / "planar3.toml").write_bytes((ROBOTS_DIR / "planar3.toml").read_bytes())
    prog = tmp_path / "repo" / "tests" / "p.irl"
    prog.parent.mkdir()
    model = robots.resolve_robot("../robots/planar3.toml", prog.parent, restricted=True)
    assert model.source == str(library / "planar3.toml") and model.n == 3
    (source / "planar3.toml").write_bytes(
        b"# edited\n" + (ROBOTS_DIR / "planar3.toml").read_bytes()
    )
    with pytest.raises(RobotFileError, match="outside the folders a program may read from"):
        robots.resolve_robot("../robots/planar3.toml", prog.parent, restricted=True)


def test_the_acceptance_program_names_a_library_file_by_a_relative_path() -> None:
    prog = ROBOTS_DIR.parent / "tests" / "lang_acceptance" / "valid" / "v36_robot_file.irl"
    if not prog.is_file():
        pytest.skip("not a source tree")
    assert main(["check", str(prog)]) == 0


ROBOT = SimpleRobot("six", ("revolute",) * 6)


@pytest.mark.parametrize(
    ("extra", "words"),
    [
        ('[inputs]\n"' + "9" * 5000 + '" = [[0.0, true]]\n', "input keys are input numbers"),
        ('[inputs]\n"١" = [[0.0, true]]\n', "input keys are input numbers"),  # a non-ASCII digit
        ("[inputs]\n1 = [[nan, true]]\n", "got not-a-number"),
        ("[inputs]\n1 = [[0x" + "f" * 6000 + ", true]]\n", "finite and >= 0, got an integer"),
        ("[poses]\np = [0x" + "f" * 6000 + ", 0, 0, 0, 0, 0]\n", "numbers must be finite"),
        ("[poses]\np = " + "[" * 2000 + "]" * 2000 + "\n", "invalid TOML: arrays or tables nested"),
    ],
)
def test_hostile_data_lists_are_diagnostics(tmp_path, extra, words) -> None:
    (tmp_path / "cell.toml").write_text(extra, encoding="utf-8")
    source = "PROGRAM t;\nROBOT r := six;\nIMPORT DATALIST cell;\nBEGIN\nENDPROGRAM\n"
    result = compile_source(source, str(tmp_path / "t.irl"), resolve_robot=lambda n: ROBOT)
    messages = [d.header() for d in result.diagnostics]
    assert any(words in m and "cell.toml:" in m for m in messages), messages
    assert all(len(m) < 400 for m in messages)


def test_key_line_finds_arrays_of_tables_inline_tables_and_dotted_keys() -> None:
    text = '[robot]\nunits = { angle = "deg" }\n[[joints]]\nx = 1\n[[joints]]\na.b = 2\n'
    assert key_line(text, "robot.units.angle") == 2
    assert key_line(text, "joints[2].a.b") == 6
    assert key_line(text, "joints[1].x") == 4
    assert key_line(text, "joints[2].x") == 5  # not written: its table
    assert key_line(text, "nowhere") is None


@pytest.mark.parametrize(
    ("old", "new", "line", "words"),
    [  # each was "cannot parse the URDF (ValueError|KeyError|TypeError)" without a position
        ('<axis xyz="0 0 1"/>', '<axis xyz="0 0"/>', 2, "axis': expected 3 numbers"),
        (
            '<link name="a"/>',
            '<link name="a"><collision><geometry><sphere/></geometry></collision></link>',
            1,
            "missing the attribute 'radius'",
        ),
        (
            '<link name="a"/>',
            '<link name="a"><collision><geometry><cone r="1"/></geometry></collision></link>',
            1,
            "expected a box, cylinder, sphere or mesh",
        ),
        ('<link name="b"/>', '<link name="b"/><link name="z"/>', 1, "a second root link"),
    ],
)
def test_a_malformed_urdf_is_positioned(tmp_path, old, new, line, words) -> None:
    pytest.importorskip("yourdfpy")
    serial = BRANCHED.replace('<link name="b"/>', "").split('<joint name="jb"')[0] + "</robot>"
    base = BRANCHED if "second root" in words else serial
    assert old in base
    e = _error(tmp_path, base.replace(old, new, 1), "m.urdf")
    assert e.line == line and words in str(e), str(e)


def test_a_study_file_tomllib_cannot_take_is_a_positioned_error(tmp_path, capsys) -> None:
    study = tmp_path / "s.toml"
    study.write_text('program = "p.irl"\nx = 1' + "0" * 5000 + "\n")  # ValueError: exit 4
    assert main(["study", str(study)]) == 3
    err = capsys.readouterr().err
    assert "s.toml:2" in err and "too many digits" in err and "0" * 50 not in err


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes")
def test_a_robot_path_that_is_a_pipe_or_a_folder_says_so(tmp_path):
    # both were "file not found"
    from irlc.robots import RobotFileError, robot_file

    os.mkfifo(tmp_path / "pipe.toml")
    (tmp_path / "dir.toml").mkdir()
    for name, reason in (("pipe.toml", "not a regular file"), ("dir.toml", "a folder, not a file"),
                         ("none.toml", "file not found")):  # fmt: skip
        with pytest.raises(RobotFileError) as err:
            robot_file(str(tmp_path / name), None)
        assert str(err.value).endswith(reason), err.value
