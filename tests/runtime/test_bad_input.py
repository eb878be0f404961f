"""Bad input to ``irlc run``: clear message, right exit code, no traceback/internal error."""

from __future__ import annotations

from pathlib import Path

import pytest
from irlc.cli import main
from irlc.robots import ROBOTS_DIR, list_robots, loader

PROGRAM = """\
PROGRAM p;
ROBOT r := {robot};
VAR MAIN_JOINT: k;
BEGIN
  k.a1 := 3;
  k.a2 := k.a1 + 1;
ENDPROGRAM
"""
KNOWN = ", ".join(list_robots())


def run(capsys, *args) -> tuple[int, str, str]:
    code = main([str(a) for a in args])
    out = capsys.readouterr()
    assert "Traceback" not in out.err and "internal error" not in out.err
    return code, out.out, out.err


def write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


def test_non_utf8_ird_is_a_usage_error(tmp_path, capsys):
    bad = tmp_path / "garbage.ird"
    bad.write_bytes(b"IRDATA 1\n\x80\x81 nonsense\n")
    code, _, err = run(capsys, "run", bad)
    assert code == 3 and f"{bad}: not a UTF-8 text file (byte 0x80 on line 2)" in err


def test_non_utf8_compare_file_is_a_usage_error(tmp_path, capsys):
    prog = write(tmp_path, "p.irl", "PROGRAM p;\nROBOT r := planar3;\nBEGIN\nENDPROGRAM\n")
    bad = tmp_path / "garbage.json"
    bad.write_bytes(b'{"status": "\xff"}')
    code, _, err = run(capsys, "run", prog, "--compare", bad)
    assert code == 3 and "--compare" in err and "garbage.json: not a UTF-8 text file" in err


def test_unknown_override_robot_is_a_usage_error(tmp_path, capsys):
    prog = write(tmp_path, "p.irl", PROGRAM.format(robot="planar3"))
    code, out, err = run(capsys, "run", prog, "--robot", "nosuch")
    assert code == 3 and out == ""
    assert err.strip() == f"irlc: error: unknown robot 'nosuch' (known: {KNOWN})"


def test_broken_override_robot_file_is_a_usage_error(tmp_path, capsys):
    prog = write(tmp_path, "p.irl", PROGRAM.format(robot="planar3"))
    write(tmp_path, "broken.toml", "[robot\n")
    code, _, err = run(capsys, "run", prog, "--robot", "broken.toml")
    assert code == 3 and "broken.toml:1: not valid TOML" in err  # the file and its line


def test_unknown_program_robot_gives_one_diagnostic(tmp_path, capsys):
    prog = write(tmp_path, "p.irl", PROGRAM.format(robot="nosuch"))
    code, _, err = run(capsys, "run", prog)
    flat = " ".join(err.split())  # rich wraps long lines
    assert code == 1
    assert flat.count("error:") == 1 and f"{prog}:2:12: error: cannot use robot 'nosuch'" in flat
    assert "has no joint" not in err


def test_loader_bug_is_not_a_diagnostic(tmp_path, capsys, monkeypatch):
    prog = write(tmp_path, "p.irl", PROGRAM.format(robot="planar3"))

    def bug(*args):
        raise ZeroDivisionError("bug in the loader")

    monkeypatch.setattr(loader, "build_model", bug)
    monkeypatch.setattr("irlc.robots._cache", {})
    assert main(["run", str(prog)]) == 4  # internal error, not exit 1 with a diagnostic
    assert "ZeroDivisionError: bug in the loader" in capsys.readouterr().err


def test_run_reads_the_robot_file_once(tmp_path, capsys, monkeypatch):
    write(tmp_path, "arm.toml", (ROBOTS_DIR / "planar3.toml").read_text(encoding="utf-8"))
    prog = write(
        tmp_path,
        "p.irl",
        "PROGRAM p;\nROBOT r := 'arm.toml';\nBEGIN\n  MOVE PTP (0, 80, -80);\nENDPROGRAM\n",
    )
    reads = []
    real = loader.build_model
    monkeypatch.setattr(loader, "build_model", lambda *a: reads.append(a[1]) or real(*a))
    monkeypatch.chdir(ROBOTS_DIR)  # the program's folder must be used, not the cwd
    code, _, _ = run(capsys, "run", prog, "--quiet")
    assert code == 0 and reads == [str(tmp_path / "arm.toml")]


def test_ird_failure_names_the_source_without_reading_the_code_again(tmp_path, capsys, monkeypatch):
    prog = write(
        tmp_path,
        "p.irl",
        "PROGRAM p;\nROBOT r := planar3;\nBEGIN\n"
        "  MOVE LIN POSE(4000, 0, 0, 0, 0, 0);\nENDPROGRAM\n",  # beyond the 3 m reach
    )
    assert main(["compile", str(prog)]) == 0
    capsys.readouterr()
    import irlc.lang.irdata as irdata

    calls = []
    real = irdata.read_code
    monkeypatch.setattr(irdata, "read_code", lambda *a: calls.append(1) or real(*a))
    code, _, err = run(capsys, "run", prog.with_suffix(".ird"), "--quiet")
    assert code == 2 and len(calls) == 1
    assert " ".join(err.split()).startswith(f"{prog}:4:3: error: run-time failure")


@pytest.mark.parametrize("robot", ["PLANAR3", "planar3"])
def test_library_names_are_case_insensitive_on_the_command_line(tmp_path, capsys, robot):
    prog = write(tmp_path, "p.irl", "PROGRAM p;\nBEGIN\nENDPROGRAM\n")
    code, _, _ = run(capsys, "run", prog, "--robot", robot, "--quiet")
    assert code == 0
