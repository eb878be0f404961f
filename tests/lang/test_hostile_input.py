"""Hostile compiler input (issue 11): every bad program is a positioned error in bounded time.

Each test reproduces one crash or hang the adversarial run found; the fuzz tests in
``test_fuzz.py`` keep the classes fixed.
"""

from __future__ import annotations

import time

from .conftest import compile_text


def _only_error(text: str):
    result = compile_text(text, "t.irl")
    assert not result.ok
    return result.errors[0]


def test_syntax_error_after_a_long_word_is_reported_in_linear_time() -> None:
    # _previous_token retried its pattern at every position of the 40,000-letter name (9 s).
    text = (
        "PROGRAM p; ROBOT r := koch11; VAR REAL: "
        + "x" * 40000
        + "; BEGIN x := 1 x := 2 ENDPROGRAM"
    )
    start = time.perf_counter()
    err = _only_error(text)
    assert time.perf_counter() - start < 2.0
    assert err.span is not None and err.span.line == 1
    assert "unexpected name 'x'" in err.message
