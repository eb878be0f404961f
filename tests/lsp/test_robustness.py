"""The language server's parts on texts as they are while typed: every example program
cut, with a piece deleted or a half statement inserted at random places (seeded). Nothing
may raise — the server must answer whatever the text — and what is answered is consistent:
an occurrence found at a position covers it, a hover is text, an outline range holds its
name. (The protocol itself is tested end to end in test_server.py.)"""

from __future__ import annotations

import random
from pathlib import Path

import pytest

pytest.importorskip("pygls", reason="the language server is the optional extra irlc[lsp]")
from irlc.lang.diagnostics import Span
from irlc.lsp.analysis import ProgramAnalysis, Settings
from irlc.lsp.completion import Context, complete
from irlc.lsp.hover import hover_text
from irlc.lsp.navigation import definition, document_symbols
from irlc.lsp.positions import contains

ROOT = Path(__file__).resolve().parents[2]
PIECES = [" MOVE ", ";", "(", "WITH ", "p1.", "{", "'", "END", "IF x THEN", "ROBOT r := "]


def _edited(text: str, rng: random.Random) -> str:
    cut = rng.randrange(len(text))
    mode = rng.choice(["truncate", "delete", "insert"])
    if mode == "truncate":
        return text[:cut]
    if mode == "delete":
        return text[:cut] + text[cut + rng.randrange(1, 30) :]
    return text[:cut] + rng.choice(PIECES) + text[cut:]


@pytest.mark.parametrize("program", sorted((ROOT / "programs").glob("*.irl")), ids=lambda p: p.stem)
def test_half_typed_programs_are_answered(program):
    rng = random.Random(program.stem)
    text = program.read_text(encoding="utf-8")
    previous = None
    for _ in range(8):
        edited = _edited(text, rng)
        analysis = ProgramAnalysis.of(program, edited, Settings(), {}, previous)
        previous = analysis
        index = analysis.index()
        lines = edited.split("\n")
        for _ in range(15):
            line = rng.randrange(1, len(lines) + 1)
            column = rng.randrange(1, len(lines[line - 1]) + 2)
            before = lines[line - 1][: column - 1]
            items = complete(Context(program, before, line), analysis.names_index())
            assert all(item.label for item in items)
            found = index.at(line, column) if index is not None else None
            if found is None:
                continue
            assert contains(found.span, line, column)
            text_shown = hover_text(found.target, index, program, False)
            assert text_shown is None or isinstance(text_shown, str)
            definition(found.target, program, (), False, lambda path, span: (path, span))
        tree = analysis.analysis.program or (index.program if index is not None else None)
        if tree is not None:
            for symbol in document_symbols(tree, lambda span: span):
                assert isinstance(symbol.range, Span) and symbol.name
