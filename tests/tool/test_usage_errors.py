"""click's own usage errors in irlc's form: one line ``irlc: error: …``, exit 3."""

from __future__ import annotations

import pytest
from irlc.cli import main


@pytest.mark.parametrize(
    ("args", "line"),
    [
        (
            ["run", "--frob", "p.irl"],
            "irlc: error: no such option '--frob'. Did you mean '--robot'? — usage: "
            "irlc run [OPTIONS] PROGRAM (see irlc run --help)",
        ),
        (
            ["fk"],
            "irlc: error: missing argument 'ROBOT' — usage: irlc fk [OPTIONS] ROBOT [Q]... "
            "(see irlc fk --help)",
        ),
        (
            ["run", "--ipo", "abc", "p.irl"],
            "irlc: error: invalid value for '--ipo': 'abc' is not a valid float — usage: "
            "irlc run [OPTIONS] PROGRAM (see irlc run --help)",
        ),
        (
            ["test", "a", "b"],
            "irlc: error: got unexpected extra argument (b) — usage: irlc test [OPTIONS] "
            "[DIRECTORY] (see irlc test --help)",
        ),
    ],
)
def test_a_usage_error_is_one_line_with_the_usage(capsys, args, line):
    assert main(args) == 3
    out = capsys.readouterr()
    assert out.out == "" and out.err == line + "\n"


@pytest.mark.parametrize(
    ("word", "hint"),
    [("chek", "did you mean 'check'?"), ("robtos", "did you mean 'robots'?"),
     ("xyzzy", "commands: check, compile, disasm, fk, ik, lsp, repl, robot, robots, run, "
               "study, test, warmup")],
)  # fmt: skip
def test_a_misspelt_command_is_not_taken_for_a_program(tmp_path, monkeypatch, capsys, word, hint):
    """Regression (new-user walk): `irlc chek p.irl` said "got unexpected extra argument
    (p.irl)" — `chek` was taken for the program of the bare form `irlc PROGRAM`."""
    monkeypatch.chdir(tmp_path)
    assert main([word, "p.irl"]) == 3
    err = capsys.readouterr().err
    assert err == f"irlc: error: no such command or program file '{word}' ({hint})\n"
    (tmp_path / word).write_text("PROGRAM p;\nBEGIN\nENDPROGRAM\n", encoding="utf-8")
    assert main([word, "--robot", "planar3", "-q"]) == 0  # a file of that name still runs
