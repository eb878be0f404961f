"""lark's grammar cache: keyed on the grammar, per user, and the lexer callbacks survive it."""

from __future__ import annotations

import logging
from pathlib import Path

import pytest
from irlc.lang import ast, grammar, parser


@pytest.fixture
def fresh_parser(monkeypatch: pytest.MonkeyPatch, tmp_path: Path):
    """``grammar.lark_parser`` rebuilt with the cache under ``tmp_path``; restored afterwards."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    grammar.lark_parser.cache_clear()
    yield tmp_path
    grammar.lark_parser.cache_clear()


RESERVED = "PROGRAM t;\nVAR INTEGER: then;\nBEGIN\nENDPROGRAM\n"
COMMENT = "PROGRAM t;\nBEGIN\n  { never closed\nENDPROGRAM\n"
GOOD = "PROGRAM t;\nVAR INTEGER: i;\nBEGIN\n  i := 1 + 2;\nENDPROGRAM\n"


def _check_parser() -> None:
    program, diags = parser.parse(GOOD, "t.irl")
    assert not diags and isinstance(program, ast.Program)  # the transformer built the AST
    _, (d,) = parser.parse(RESERVED, "t.irl")
    assert (d.line, d.column, d.message) == (2, 14, "'then' is a reserved word")
    _, (d,) = parser.parse(COMMENT, "t.irl")
    assert (d.line, d.column) == (3, 3) and "unterminated comment" in d.message


def test_cache_is_written_then_loaded_with_callbacks_working(
    fresh_parser: Path, caplog: pytest.LogCaptureFixture
) -> None:
    caplog.set_level(logging.DEBUG, logger="lark")
    _check_parser()  # builds the tables and saves them
    (cache,) = (fresh_parser / "irlc").iterdir()
    assert "Loading grammar from cache" not in caplog.text
    grammar.lark_parser.cache_clear()
    _check_parser()  # loads them: the transformer and lexer callbacks are attached again
    assert f"Loading grammar from cache: {cache}" in caplog.text


def test_cache_name_follows_the_grammar(fresh_parser: Path) -> None:
    text = 'start: A\nA: "a"\n'
    first = grammar.grammar_cache_file(text)
    assert isinstance(first, str) and Path(first).parent == fresh_parser / "irlc"
    assert grammar.grammar_cache_file(text) == first
    assert grammar.grammar_cache_file(text + 'B: "b"\n') != first


def test_no_writable_cache_directory_still_parses(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    blocker = tmp_path / "not-a-directory"
    blocker.write_text("")
    monkeypatch.setenv("XDG_CACHE_HOME", str(blocker))
    grammar.lark_parser.cache_clear()
    try:
        assert grammar.grammar_cache_file('start: A\nA: "a"\n') is False
        _check_parser()
    finally:
        grammar.lark_parser.cache_clear()


def test_a_corrupt_cache_file_is_rebuilt(fresh_parser: Path) -> None:
    _check_parser()
    (cache,) = (fresh_parser / "irlc").iterdir()
    cache.write_bytes(b"garbage\n")
    grammar.lark_parser.cache_clear()
    _check_parser()
    assert cache.stat().st_size > 1000  # lark saw the wrong hash, rebuilt and rewrote it
