"""Golden code: every construct compiles to the checked-in IRDATA text (inspected by eye).

Regenerate after an intended change with ``IRLC_UPDATE_GOLDEN=1 pytest tests/lang`` and
review the diff.
"""

from __future__ import annotations

import os

import pytest
from irlc.lang import compile_source, read_code, write_code

from .conftest import GOLDEN, fake_resolver

PROGRAMS = sorted(GOLDEN.glob("*.irl"))


def _compile(path):
    cwd = os.getcwd()
    os.chdir(path.parent)  # SOURCE and DATALIST records stay relative and machine-independent
    try:
        return compile_source(
            path.read_text(encoding="utf-8"), path.name, resolve_robot=fake_resolver
        )
    finally:
        os.chdir(cwd)


@pytest.mark.parametrize("path", PROGRAMS, ids=[p.stem for p in PROGRAMS])
def test_golden(path) -> None:
    result = _compile(path)
    assert result.ok, [d.header() for d in result.diagnostics]
    assert not result.diagnostics
    text = write_code(result.code)
    expected = path.with_suffix(".ird")
    if os.environ.get("IRLC_UPDATE_GOLDEN"):
        expected.write_text(text, encoding="utf-8")
    assert text == expected.read_text(encoding="utf-8")


def test_golden_covers_every_statement_kind() -> None:
    from irlc.lang import ast
    from irlc.lang.parser import parse

    kinds: set[str] = set()
    for path in PROGRAMS:
        program, _ = parse(path.read_text(encoding="utf-8"), path.name)
        for r in [program.body, *(rt.body for rt in program.routines)]:
            kinds |= {type(s).__name__ for s in ast.statements_in_order(r)}
    statement_kinds = {
        c.__name__
        for c in vars(ast).values()
        if isinstance(c, type) and issubclass(c, ast.Stmt) and c is not ast.Stmt
    }
    assert statement_kinds <= kinds, statement_kinds - kinds


def test_golden_covers_every_opcode() -> None:
    from irlc.lang.irdata import OPCODES

    used: set[str] = set()
    for path in PROGRAMS:
        used |= {ins.op for ins in read_code(path.with_suffix(".ird").read_text()).code}
    unused_by_compiler = {"DUP"}  # in the format for hand-written code; codegen never needs it
    assert set(OPCODES) - unused_by_compiler <= used, set(OPCODES) - used
