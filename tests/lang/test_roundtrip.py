"""compile → write → read → write is byte-identical for every shipped and test program."""

from __future__ import annotations

from pathlib import Path

import pytest
from irlc.lang import compile_file, read_code, write_code

from .conftest import GOLDEN, fake_resolver

ROOT = Path(__file__).resolve().parents[2]
SHIPPED = sorted((ROOT / "programs").glob("*.irl"))
TESTS = sorted(GOLDEN.glob("*.irl"))


def _library_resolver(name: str):
    from irlc.cli.lang_cmds import library_resolver

    return library_resolver(name)


@pytest.mark.parametrize("path", SHIPPED + TESTS, ids=[p.stem for p in SHIPPED + TESTS])
def test_round_trip(path: Path) -> None:
    resolver = _library_resolver if path in SHIPPED else fake_resolver
    result = compile_file(path, resolve_robot=resolver)
    assert result.ok, [d.header() for d in result.diagnostics]
    text = write_code(result.code)
    again = read_code(text, "x.ird")
    assert write_code(again) == text
    assert again.code == result.code.code
    assert again.consts == result.code.consts
    assert [r.entry for r in again.routines] == [r.entry for r in result.code.routines]


def test_shipped_programs_exist() -> None:
    names = {p.stem for p in SHIPPED}
    assert {
        "square",
        "square_limits",
        "square_j11",
        "square_speed",
        "square_accel",
        "square_cyclic",
        "square_freeze",
        "obstacle_line",
        "obstacle_line_avoid",
        "combined",
    } <= names
