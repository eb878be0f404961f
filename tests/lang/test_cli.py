"""``irlc check / compile / disasm``: exit codes 0/1/3, diagnostics format, no traceback."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from irlc.cli import main
from irlc.lang import read_code

ROOT = Path(__file__).resolve().parents[2]
SQUARE = ROOT / "programs" / "square.irl"


def _run(capsys, *args: str) -> tuple[int, str, str]:
    code = main(list(args))
    out, err = capsys.readouterr()
    assert "Traceback" not in out + err
    return code, out, err


def test_check_ok(capsys) -> None:
    code, out, _ = _run(capsys, "check", str(SQUARE))
    assert code == 0
    assert "ok" in out


def test_check_compile_error_format(tmp_path: Path, capsys) -> None:
    prog = tmp_path / "bad.irl"
    prog.write_text(
        "PROGRAM bad;\nROBOT r := koch11;\nVAR POSE: p;\nBEGIN\n  p := p + 1.0;\nENDPROGRAM\n"
    )
    code, _, err = _run(capsys, "check", str(prog))
    assert code == 1
    lines = err.splitlines()
    assert re.fullmatch(rf"{re.escape(str(prog))}:5:10: error: cannot add POSE and REAL", lines[0])
    assert lines[1] == "    p := p + 1.0;"
    assert lines[2] == "           ^"
    assert any(line.startswith("  hint: ") for line in lines)


def test_check_missing_file_is_usage_error(tmp_path: Path, capsys) -> None:
    code, _, err = _run(capsys, "check", str(tmp_path / "none.irl"))
    assert code == 3
    assert "no such file" in err


def test_unknown_robot_option_is_usage_error(capsys) -> None:
    code, _, err = _run(capsys, "check", str(SQUARE), "--robot", "no_such_robot")
    assert code == 3
    assert "no_such_robot" in err


def test_unknown_robot_in_program_is_compile_error(tmp_path: Path, capsys) -> None:
    prog = tmp_path / "r.irl"
    prog.write_text("PROGRAM r;\nROBOT r := no_such_robot;\nBEGIN\nENDPROGRAM\n")
    code, _, err = _run(capsys, "check", str(prog))
    assert code == 1
    assert f"{prog}:2:12: error: cannot use robot 'no_such_robot'" in err


def test_robot_override_warns(tmp_path: Path, capsys) -> None:
    prog = tmp_path / "p.irl"
    prog.write_text("PROGRAM p;\nROBOT r := koch11;\nBEGIN\n  WAIT 1 SEC;\nENDPROGRAM\n")
    code, _, err = _run(capsys, "check", str(prog), "--robot", "planar3")
    assert code == 0
    assert "warning: --robot planar3 overrides the program's robot koch11" in err


def test_datalist_path_option(tmp_path: Path, capsys) -> None:
    (tmp_path / "lists").mkdir()
    (tmp_path / "lists" / "cell.toml").write_text("[poses]\nhome = [0, 0, 1000, 0, 0, 0]\n")
    prog = tmp_path / "p.irl"
    prog.write_text(
        "PROGRAM p;\nROBOT r := planar3;\nIMPORT DATALIST cell;\nBEGIN\n"
        "  R_TOOL := home;\nENDPROGRAM\n"
    )
    assert _run(capsys, "check", str(prog))[0] == 1
    assert _run(capsys, "check", str(prog), "--datalist-path", str(tmp_path / "lists"))[0] == 0
    # a folder that does not exist is a typo, for every command (run and repl ignored it)
    for command in (["check", str(prog)], ["run", str(prog), "-q"], ["repl"]):
        code, _, err = _run(capsys, *command, "--datalist-path", str(tmp_path / "lsts"))
        assert code == 3 and "lsts" in err and ("does not exist" in err or "no such" in err), err


def test_compile_default_output_and_disasm(tmp_path: Path, capsys) -> None:
    src = tmp_path / "square.irl"
    src.write_text(SQUARE.read_text())
    (tmp_path / "square_cell.toml").write_text((ROOT / "programs" / "square_cell.toml").read_text())
    code, out, _ = _run(capsys, "compile", str(src))
    assert code == 0
    ird = tmp_path / "square.ird"
    assert ird.is_file() and "wrote" in out
    assert read_code(ird.read_text()).program == "square"
    assert not list(tmp_path.glob(".*.tmp"))  # the temporary file was renamed
    code, out, _ = _run(capsys, "disasm", str(ird))
    assert code == 0
    assert "MOVE PTP konf_0;" in out  # the source line is interleaved
    assert re.search(r"L\d+ MOVE LIN 1", out)


def test_compile_output_option(tmp_path: Path, capsys) -> None:
    out_file = tmp_path / "x.ird"
    code, _, _ = _run(capsys, "compile", str(SQUARE), "-o", str(out_file))
    assert code == 0 and out_file.read_text().startswith("IRDATA 1\n")


def test_compile_error_writes_nothing(tmp_path: Path, capsys) -> None:
    prog = tmp_path / "bad.irl"
    prog.write_text("PROGRAM bad;\nROBOT r := koch11;\nBEGIN\n  CYCLICEND:;\nENDPROGRAM\n")
    code, _, err = _run(capsys, "compile", str(prog))
    assert code == 1
    assert "stray ':'" in err and "hint:" in err
    assert not (tmp_path / "bad.ird").exists()


@pytest.mark.parametrize("text", ["", "IRDATA 1\n1 PROGRAM x\n", "IRDATA 1\n1 BOGUS\n2 CODE\n"])
def test_disasm_malformed_code(tmp_path: Path, capsys, text: str) -> None:
    f = tmp_path / "bad.ird"
    f.write_text(text)
    code, _, err = _run(capsys, "disasm", str(f))
    assert code == 1
    assert f"{f}:" in err


def test_disasm_missing_file(tmp_path: Path, capsys) -> None:
    assert _run(capsys, "disasm", str(tmp_path / "none.ird"))[0] == 3


def test_an_output_never_overwrites_the_program_or_another_output(tmp_path: Path, capsys) -> None:
    # `irlc compile p.irl -o p.irl` replaced the source with IRDATA ("wrote p.irl"), and
    # `--report same.json --export-trajectory same.json` let one silently win
    prog = tmp_path / "p.irl"
    prog.write_text("PROGRAM p;\nROBOT r := planar3;\nBEGIN\nENDPROGRAM\n", encoding="utf-8")
    text = prog.read_text()
    same = tmp_path / "sub" / ".." / "p.irl"
    (tmp_path / "sub").mkdir()
    for args, words in (
        (["compile", str(prog), "-o", str(same)], "that is the program"),
        (["run", str(prog), "-q", "--trace", str(prog)], "that is the program"),
        (["run", str(prog), "-q", "--report", str(tmp_path / "r.json"),
          "--export-trajectory", str(tmp_path / "r.json")], "that is the file of --report"),
    ):  # fmt: skip
        code, _, err = _run(capsys, *args)
        assert code == 3 and words in " ".join(err.split()), err
    assert prog.read_text() == text and not (tmp_path / "r.json").exists()
