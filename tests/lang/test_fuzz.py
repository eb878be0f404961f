"""Property: whatever the input, the compiler returns diagnostics with valid positions.

Random token sequences and mutations (delete / duplicate / swap tokens, random bytes) of
valid programs never raise; a failed compile always has an error whose position lies in
the text (1 <= line <= lines + 1, column >= 1) — or names a data-list file.
"""

from __future__ import annotations

import re

from hypothesis import given
from hypothesis import strategies as st

from ..fuzz_budget import fuzz_settings
from .conftest import GOLDEN, HERE, compile_text

SEEDS = [p.read_text(encoding="utf-8") for p in sorted(GOLDEN.glob("*.irl"))]
TOKEN = re.compile(r"'(?:[^']|'')*'|\"[^\"]*\"|\{[^}]*\}|\w+|:=|\.\.|<>|<=|>=|\S")
SEED_TOKENS = [TOKEN.findall(s) for s in SEEDS]
VOCAB = sorted({t for toks in SEED_TOKENS for t in toks} | {"(*", "*)", "{", "}", "'", "#", "\n"})
FILE = str(GOLDEN / "fuzz.irl")  # data lists of the seeds resolve next to it


def _check(text: str) -> None:
    result = compile_text(text, FILE)
    n_lines = text.count("\n") + 1
    if result.ok:
        return
    assert result.errors
    for d in result.diagnostics:
        if d.file != FILE:
            assert d.file.endswith(".toml")
            continue
        assert d.span is not None, d
        assert 1 <= d.span.line <= n_lines + 1, (d, n_lines)
        assert d.span.column >= 1, d


def _mutate(tokens: list[str], ops: list[tuple[int, int, int]]) -> str:
    toks = list(tokens)
    for kind, i, j in ops:
        if not toks:
            break
        i, j = i % len(toks), j % len(toks)
        if kind == 0:
            del toks[i]
        elif kind == 1:
            toks.insert(i, toks[i])
        else:
            toks[i], toks[j] = toks[j], toks[i]
    return " ".join(toks)


_settings = fuzz_settings(200)


@_settings
@given(st.lists(st.sampled_from(VOCAB), max_size=60))
def test_random_token_sequences(tokens: list[str]) -> None:
    _check(" ".join(tokens))


@_settings
@given(
    st.integers(0, len(SEEDS) - 1),
    st.lists(
        st.tuples(st.integers(0, 2), st.integers(0, 10**6), st.integers(0, 10**6)),
        min_size=1,
        max_size=4,
    ),
)
def test_token_mutations(seed: int, ops) -> None:
    _check(_mutate(SEED_TOKENS[seed], ops))


@_settings
@given(st.integers(0, len(SEEDS) - 1), st.integers(0, 10**6), st.binary(min_size=1, max_size=8))
def test_random_bytes(seed: int, where: int, junk: bytes) -> None:
    text = SEEDS[seed]
    k = where % (len(text) + 1)
    _check(text[:k] + junk.decode("latin-1") + text[k:])


def test_seed_programs_compile() -> None:
    for text in SEEDS:
        assert compile_text(text, FILE).ok


assert HERE.is_dir()
