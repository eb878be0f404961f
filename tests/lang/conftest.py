"""Shared helpers of the language tests: a fake robot resolver (no robot files needed)."""

from __future__ import annotations

from pathlib import Path

import pytest
from irlc.lang import SimpleRobot, compile_source, write_code

HERE = Path(__file__).parent
GOLDEN = HERE / "golden"
ROBOTS = {
    "six": SimpleRobot("six", ("revolute",) * 6),
    "koch11": SimpleRobot("koch11", ("revolute",) * 9 + ("prismatic", "revolute")),
    "planar3": SimpleRobot("planar3", ("R", "R", "R")),
}


def fake_resolver(name: str) -> SimpleRobot:
    try:
        return ROBOTS[name.lower()]
    except KeyError:
        raise LookupError(f"unknown robot; known robots: {', '.join(ROBOTS)}") from None


def compile_text(text: str, filename: str = "test.irl", **kw):
    kw.setdefault("resolve_robot", fake_resolver)
    return compile_source(text, filename, **kw)


def ird_text(source: str) -> str:
    """The IRDATA text of a program that compiles (with the fake robots)."""
    result = compile_text(source)
    assert result.ok, [d.header() for d in result.diagnostics]
    return write_code(result.code)


@pytest.fixture
def resolver():
    return fake_resolver
