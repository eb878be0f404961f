"""Invalid programs: each gives an error at the expected line and column with the message."""

from __future__ import annotations

import pytest

from .conftest import HERE, compile_text
from .invalid_cases import CASES

PROGRAM_FILE = str(HERE / "invalid" / "t.irl")  # data lists of the cases live next to it


@pytest.mark.parametrize(
    ("source", "line", "column", "fragment"), [c[1:] for c in CASES], ids=[c[0] for c in CASES]
)
def test_invalid_program(source: str, line: int, column: int, fragment: str) -> None:
    result = compile_text(source, PROGRAM_FILE)
    if line == 0:  # a warning-only case: compiles, with a warning
        assert result.ok and result.warnings, result.diagnostics
        return
    assert result.code is None
    hits = [
        d for d in result.errors if d.line == line and d.column == column and fragment in d.message
    ]
    assert hits, [d.header() for d in result.diagnostics]
    if fragment.startswith(("key ", "invalid TOML", "'home' is defined twice")):
        assert hits[0].file.endswith(".toml")  # data-list errors name the data-list file
    else:
        assert hits[0].file == PROGRAM_FILE


def test_at_least_forty_cases() -> None:
    assert len(CASES) >= 40
    assert len({c[0] for c in CASES}) == len(CASES)
