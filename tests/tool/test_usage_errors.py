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
