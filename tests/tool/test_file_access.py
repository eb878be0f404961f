"""Files a program names must lie inside its allowed roots (issue 11, lang/file_access.py).

``ROBOT r := 'file'`` may name a file in the program's folder (or below) or the robot
library; ``IMPORT DATALIST`` one in the program's folder, a ``--datalist-path`` folder or the
library. ``..``, absolute paths and symbolic links are judged after resolving them. A
refusal is a positioned compile error (exit 1; exit 3 for compiled code's robot) that never
shows the file's text; ``--allow-any-path`` / ``allow_any_path=True`` lifts the rule.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st
from irlc.cli import main
from irlc.robots import ROBOTS_DIR

from ..fuzz_budget import fuzz_settings

SECRET = "TOP-SECRET-VALUE-42"


def _layout(tmp_path: Path) -> tuple[Path, Path]:
    """``tmp/prog/`` (the program's folder) and ``tmp/outside/`` with a valid robot file,
    a valid data list, and a malformed 'robot' holding a secret."""
    prog, outside = tmp_path / "prog", tmp_path / "outside"
    prog.mkdir()
    outside.mkdir()
    (outside / "arm.toml").write_text((ROBOTS_DIR / "planar3.toml").read_text())
    (outside / "cell.toml").write_text("[poses]\np = [1500, 0, 0, 0, 0, 0]\n")
    (outside / "secret.toml").write_text(f'password = "{SECRET}"\n[joints\n')
    return prog, outside


def _program(prog: Path, robot: str, extra: str = "") -> Path:
    path = prog / "p.irl"
    path.write_text(f"PROGRAM p;\nROBOT r := {robot};\n{extra}BEGIN\nENDPROGRAM\n")
    return path


def _check(capsys, *args: str) -> tuple[int, str]:
    code = main(["check", *args])
    captured = capsys.readouterr()
    return code, captured.err + captured.out


@pytest.mark.parametrize("how", ["dotdot", "absolute", "symlink", "missing", "nul", "loop"])
def test_a_robot_file_outside_the_program_folder_is_refused_at_its_clause(
    tmp_path, capsys, how
) -> None:
    prog, outside = _layout(tmp_path)
    name = {
        "dotdot": "'../outside/arm.toml'",
        "absolute": f"'{outside / 'arm.toml'}'",
        "symlink": "'link.toml'",
        "missing": "'../outside/nosuch.toml'",
        "nul": "'arm\x00.toml'",  # was an internal error (ValueError: embedded null byte)
        "loop": "'loop.toml'",
    }[how]
    if how == "symlink":
        os.symlink(outside / "arm.toml", prog / "link.toml")
    if how == "loop":
        os.symlink(prog / "loop.toml", prog / "loop.toml")
    path = _program(prog, name)
    code, text = _check(capsys, str(path))
    assert code == 1, text
    assert f"{path}:2:12: error: cannot use robot" in text
    assert "outside the folders a program may read from" in text
    assert "--allow-any-path" in text
    if how in ("dotdot", "absolute", "symlink"):  # refused before looking at the file
        code, text = _check(capsys, str(path), "--allow-any-path")
        assert code == 0, text


def test_refused_secret_file_is_not_echoed_and_allowed_read_names_only_keys(
    tmp_path, capsys
) -> None:
    prog, _ = _layout(tmp_path)
    path = _program(prog, "'../outside/secret.toml'")
    code, text = _check(capsys, str(path))
    assert code == 1 and SECRET not in text
    code, text = _check(capsys, str(path), "--allow-any-path")  # read: malformed TOML
    assert code == 1 and SECRET not in text


@pytest.mark.parametrize(
    ("file", "body"),
    [
        ("arm.toml", f'name = "{SECRET}"\njoints = "{SECRET}"\n'),
        ("arm.toml", f'[[joints]]\nname = "a"\ntype = "revolute"\naxis = "{SECRET}"\n'),
        ("cell.toml", f'[poses]\np = "{SECRET}"\n[obstacles.o]\nkind = "{SECRET}"\n'),
        ("cell.toml", f'[poses]\np = [1, 2, "{SECRET}"]\n[limits]\nm = {{ t = "{SECRET}" }}\n'),
    ],
)
def test_errors_name_the_key_never_the_text_of_the_file(tmp_path, capsys, file, body) -> None:
    prog, _ = _layout(tmp_path)
    (prog / file).write_text(body)
    robot = "'arm.toml'" if file == "arm.toml" else "planar3"
    path = _program(prog, robot, "IMPORT DATALIST cell;\n" if file == "cell.toml" else "")
    code, text = _check(capsys, str(path))
    assert code == 1, text
    assert "key '" in text and SECRET not in text, text


@pytest.mark.parametrize("robot", ["'cell/arm.toml'", "'{abs}'", "'../prog/cell/arm.toml'"])
def test_robot_files_inside_the_program_folder_and_the_library_are_allowed(
    tmp_path, capsys, robot
) -> None:
    prog, _ = _layout(tmp_path)
    (prog / "cell").mkdir()
    (prog / "cell" / "arm.toml").write_text((ROBOTS_DIR / "planar3.toml").read_text())
    path = _program(prog, robot.format(abs=prog / "cell" / "arm.toml"))
    assert _check(capsys, str(path))[0] == 0
    library = _program(prog, f"'{ROBOTS_DIR / 'planar3.toml'}'")
    assert _check(capsys, str(library))[0] == 0


def test_a_data_list_linked_from_outside_is_refused_unless_its_folder_is_searched(
    tmp_path, capsys
) -> None:
    prog, outside = _layout(tmp_path)
    os.symlink(outside / "cell.toml", prog / "cell.toml")
    path = _program(prog, "planar3", "IMPORT DATALIST cell;\n")
    code, text = _check(capsys, str(path))
    assert code == 1, text
    assert f"{path}:3:17: error: data list 'cell.toml' is outside the folders" in text
    assert _check(capsys, str(path), "--datalist-path", str(outside))[0] == 0
    assert _check(capsys, str(path), "--allow-any-path")[0] == 0


def test_run_compile_and_compiled_code_honour_the_rule(tmp_path, capsys) -> None:
    prog, _ = _layout(tmp_path)
    path = _program(prog, "'../outside/arm.toml'")
    assert main(["run", str(path), "-q"]) == 1
    assert main(["compile", str(path)]) == 1
    assert main(["compile", str(path), "--allow-any-path"]) == 0
    ird = path.with_suffix(".ird")
    capsys.readouterr()
    assert main(["run", str(ird), "-q"]) == 3  # the code's robot record: an environment error
    assert "outside the folders" in capsys.readouterr().err
    assert main(["run", str(ird), "-q", "--allow-any-path"]) == 0


def test_the_user_may_name_any_robot_file_on_the_command_line(tmp_path, capsys) -> None:
    prog, outside = _layout(tmp_path)
    path = _program(prog, "planar3")
    code, text = _check(capsys, str(path), "--robot", str(outside / "arm.toml"))
    assert code == 0, text


def test_the_api_takes_the_users_robot_file_from_anywhere(tmp_path) -> None:
    from irlc import compile_program

    prog, outside = _layout(tmp_path)
    path = _program(prog, "planar3")
    code = compile_program(path, robot=str(outside / "arm.toml"))
    assert code.joint_kinds == "RRR"


def test_api_and_repl_take_allow_any_path(tmp_path) -> None:
    from irlc import compile_program
    from irlc.lang import CompileError
    from irlc.repl import Session

    prog, outside = _layout(tmp_path)
    path = _program(prog, "'../outside/arm.toml'")
    with pytest.raises(CompileError, match="outside the folders"):
        compile_program(path)
    assert compile_program(path, allow_any_path=True).joint_kinds == "RRR"
    os.symlink(outside / "cell.toml", prog / "cell.toml")
    refused = Session("planar3", cwd=prog).enter("IMPORT DATALIST cell;")
    assert refused.failure == 1 and any("outside the folders" in t for t in refused.lines)
    allowed = Session("planar3", cwd=prog, allow_any_path=True).enter("IMPORT DATALIST cell;")
    assert allowed.failure == 0, allowed.lines


def test_golden_tests_take_allow_any_path(tmp_path, capsys) -> None:
    prog, _ = _layout(tmp_path)
    _program(prog, "'../outside/arm.toml'")
    assert main(["test", str(prog), "--update"]) == 0  # the refusal is what it records
    assert "compile_error" in (prog / "p.expected.json").read_text()
    assert main(["test", str(prog), "--update", "--allow-any-path"]) == 0
    assert "compile_error" not in (prog / "p.expected.json").read_text()
    assert main(["test", str(prog)]) == 1  # without the option the run differs again
    capsys.readouterr()


@pytest.fixture(scope="module")
def tree(tmp_path_factory) -> Path:
    """``prog/`` with a robot below it and links in and out; ``outside/`` beside it."""
    base = tmp_path_factory.mktemp("paths")
    prog, outside = _layout(base)
    (prog / "cell").mkdir()
    (prog / "cell" / "arm.toml").write_text((ROBOTS_DIR / "planar3.toml").read_text())
    for name, target in [
        ("link_out.toml", outside / "arm.toml"),
        ("link_in.toml", prog / "cell" / "arm.toml"),
        ("loop.toml", prog / "loop.toml"),
        ("dirlink", outside),
    ]:
        os.symlink(target, prog / name)
    return prog


SEGMENTS = ["..", ".", "", "cell", "outside", "prog", "dirlink", "arm.toml", "link_out.toml",
            "link_in.toml", "loop.toml", "planar3.toml", "robots", "x\x00"]  # fmt: skip


@fuzz_settings(200)
@given(st.lists(st.sampled_from(SEGMENTS), min_size=1, max_size=6), st.booleans())
def test_fuzz_program_paths_never_leave_the_allowed_folders(tree, segments, absolute) -> None:
    """Any path a program names: a refusal, a missing file, or a file that — resolved —
    lies in the program's folder or the library; never an exception."""
    from irlc.lang import compile_source
    from irlc.robots import resolver

    text = "/".join(segments)
    text = str(tree / text) if absolute else text
    if not text.lower().endswith((".toml", ".urdf")) and "/" not in text:
        text += "/x.toml"  # a path, not a library name
    source = f"PROGRAM p;\nROBOT r := '{text}';\nBEGIN\nENDPROGRAM\n"
    result = compile_source(source, str(tree / "p.irl"), resolve_robot=resolver(tree))
    if result.ok:
        real = (tree / text).resolve()
        assert real.is_relative_to(tree.resolve()) or real.is_relative_to(ROBOTS_DIR.resolve())
    else:
        (error,) = result.errors
        assert (error.span.line, error.span.column) == (2, 12), error


def test_an_expectation_cannot_lift_the_confinement(tmp_path, capsys) -> None:
    """``"allow_any_path": true`` in NAME.expected.json lifted the rule with no word from
    the user (a test folder is input too): now the case is an ERROR saying so, and only
    the command line's --allow-any-path allows the file outside."""
    import json

    prog, _ = _layout(tmp_path)
    _program(prog, "'../outside/arm.toml'")
    assert main(["test", str(prog), "--update", "--allow-any-path"]) == 0
    expected = prog / "p.expected.json"
    data = json.loads(expected.read_text())
    data["options"] = {"allow_any_path": True}
    expected.write_text(json.dumps(data))
    capsys.readouterr()
    assert main(["test", str(prog)]) == 1
    out = capsys.readouterr().out
    assert "ERROR" in out and "cannot lift the file confinement" in out, out
    assert main(["test", str(prog), "--allow-any-path"]) == 0
    capsys.readouterr()
