"""Fuzz the TOML text of robot files and data lists with what ``tomllib`` itself cannot
take (issue 11, helper h7): deep nesting (RecursionError), numbers of thousands of digits
(ValueError), keys of thousands of dotted parts (memory quadratic in their length), long
keys and values. Each is a ``RobotFileError`` / diagnostic with a line, in bounded time,
and its message does not repeat the text."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st
from irlc.lang import SimpleRobot, compile_source
from irlc.robots import RobotFileError, load_robot

from ..fuzz_budget import fuzz_settings
from .test_loader_errors import GOOD

FRAGMENTS = [
    lambda n: "k = " + "[" * n + "]" * n,
    lambda n: "k = " + "{a = " * n + "1" + "}" * n,
    lambda n: "k = 1" + "0" * (n * 10),
    lambda n: "k = 0x" + "f" * (n * 10),
    lambda n: "a." * n + "b = 1",
    lambda n: "[" + "t." * n + "u]",
    lambda n: "k = [" + ", ".join(["1e308"] * n) + "]",
    lambda n: "SECRET" * n + " = 1",
    lambda n: 'k = "' + "SECRET" * n + '"',
    lambda n: "k = nan",
    lambda n: "k = -inf",
]
ROBOT = SimpleRobot("six", ("revolute",) * 6)


def _shows_no_text(message: str) -> None:
    # a key is named (its first 40 characters); a value or a longer run of text never
    assert len(message) < 600 and "SECRET" * 8 not in message and "0" * 50 not in message


@fuzz_settings(60)
@given(
    st.sampled_from(FRAGMENTS),
    st.sampled_from([1, 10, 100, 400, 600, 2_000, 10_000]),
    st.sampled_from(["", "[robot]\n", "[[joints]]\n", "[tool]\n"]),
)
def test_fuzz_toml_text_of_a_robot_file(tmp_path_factory, fragment, n, table) -> None:
    path = tmp_path_factory.mktemp("robot") / "tiny.toml"
    path.write_text(GOOD + table + fragment(n) + "\n", encoding="utf-8")
    try:
        load_robot(str(path))
    except RobotFileError as e:
        assert str(path) in str(e)
        assert e.line is not None or e.key, str(e)
        _shows_no_text(str(e))


@fuzz_settings(60)
@given(
    st.sampled_from(FRAGMENTS),
    st.sampled_from([1, 10, 100, 600, 2_000, 10_000]),
    st.sampled_from(["", "[poses]\n", "[inputs]\n", "[obstacles.o]\n"]),
)
def test_fuzz_toml_text_of_a_data_list(tmp_path_factory, fragment, n, table) -> None:
    folder = tmp_path_factory.mktemp("dl")
    (folder / "cell.toml").write_text(table + fragment(n) + "\n", encoding="utf-8")
    source = "PROGRAM t;\nROBOT r := six;\nIMPORT DATALIST cell;\nBEGIN\nENDPROGRAM\n"
    result = compile_source(source, str(folder / "t.irl"), resolve_robot=lambda name: ROBOT)
    for d in result.diagnostics:
        if d.file.endswith("cell.toml") and "invalid TOML" in d.message:
            assert d.span is not None, d
        _shows_no_text(d.header())
