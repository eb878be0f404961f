"""``diagnostics.line_span``: where a run-time failure points (the statement's line text)."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st
from irlc.lang.diagnostics import Diagnostic, Span, line_span, render

SOURCE = "PROGRAM p;\nBEGIN\n  WAIT x SEC;   \n\n\tMOVE PTP home;\nENDPROGRAM\n"


def test_known_lines():
    assert line_span(SOURCE, 3) == Span(3, 3, 3, 14)  # "WAIT x SEC;" without the blanks
    assert line_span(SOURCE, 5) == Span(5, 2, 5, 16)  # a tab is one column, as the lexer's
    assert line_span(SOURCE, 1) == Span(1, 1, 1, 11)
    assert line_span(SOURCE, 4) == Span(4, 1)  # blank: column 1
    assert line_span(SOURCE, 99) == Span(99, 1)  # past the end (a changed file)
    assert line_span(None, 3) == Span(3, 1)  # no text (an .ird without its .irl)


def test_the_caret_underlines_the_statement():
    diag = Diagnostic("error", "run-time failure", "p.irl", line_span(SOURCE, 3))
    assert render(diag, SOURCE).splitlines() == [
        "p.irl:3:3: error: run-time failure",
        "    WAIT x SEC;   ",
        "    ^~~~~~~~~~~",
    ]


@given(st.text(alphabet=" \tab;", max_size=12), st.text(alphabet=" \tab;", max_size=12))
def test_the_span_is_the_stripped_text(before: str, line: str):
    source = f"{before}\n{line}\nEND"
    span = line_span(source, 2)
    text = line.expandtabs(1)
    if not text.strip():
        assert span == Span(2, 1)
    else:
        assert text[span.column - 1 : span.end_column - 1] == text.strip()
