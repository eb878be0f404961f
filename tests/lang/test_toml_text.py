"""The one TOML writer (lang/toml_text.py): ``tomllib`` reads back what it writes —
random documents of strings (any characters, control and non-ASCII ones included), 64-bit
integers, floats (``nan``, ``inf``, subnormals), booleans, arrays, inline tables, tables and
arrays of tables nested in each other — and its three users (robot export, teach, study)
write through it."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from irlc.lang import toml_text
from irlc.lang.toml_text import INT_RANGE, InlineTable, dumps, key, number, string, value

TEXT = st.text(max_size=20)  # every code point but surrogates, control characters included
SCALARS = st.one_of(
    TEXT,
    st.booleans(),
    st.integers(*INT_RANGE),
    st.floats(allow_nan=True, allow_infinity=True),
)
VALUES = st.recursive(
    SCALARS,
    lambda inner: st.one_of(
        st.lists(inner, max_size=4),
        st.dictionaries(TEXT, inner, max_size=4),
    ),
    max_leaves=25,
)
DOCS = st.dictionaries(TEXT, VALUES, max_size=6)


def same(a, b) -> bool:
    """Equal data, NaN equal to NaN; a float and an equal integer differ (TOML keeps the
    kind)."""
    if isinstance(a, float) and isinstance(b, float):
        return (math.isnan(a) and math.isnan(b)) or a == b
    if type(a) is not type(b):
        return False
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if isinstance(a, list):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b, strict=True))
    return a == b


@settings(max_examples=300, deadline=None)
@given(DOCS)
def test_tomllib_reads_back_what_dumps_writes(doc):
    assert same(tomllib.loads(dumps(doc)), doc)


@settings(max_examples=200, deadline=None)
@given(DOCS, st.text(max_size=40))
def test_a_header_is_comment_lines(doc, header):
    text = dumps(doc, header=header)
    assert same(tomllib.loads(text), doc)


@settings(max_examples=300, deadline=None)
@given(st.floats(allow_nan=False, allow_infinity=False, min_value=-1e12, max_value=1e12))
def test_decimals_round_and_drop_trailing_zeros(x):
    text = number(x, 6)
    got = tomllib.loads(f"v = {text}")["v"]
    assert float(got) == round(x, 6) or math.isclose(float(got), x, abs_tol=5e-7)
    assert not text.startswith("-0") or text.startswith("-0.")  # no negative zero
    assert text == "0" or not text.endswith(("0", ".")) or "." not in text


@settings(max_examples=200, deadline=None)
@given(TEXT, TEXT)
def test_keys_and_strings_round_trip(k, s):
    assert tomllib.loads(f"{key(k)} = {string(s)}") == {k: s}


def test_known_texts():
    assert number(-0.0) == "0.0" and number(0.1) == "0.1" and number(1e-5) == "1e-05"
    assert number(90.0, 6) == "90" and number(-1e-9, 6) == "0" and number(12.5, 6) == "12.5"
    assert number(math.inf) == "inf" and number(-math.inf) == "-inf" and number(math.nan) == "nan"
    assert key("x") == "x" and key("a b") == '"a b"' and key("a.b") == '"a.b"' and key("") == '""'
    assert string('say "hi"\n\x7f') == '"say \\"hi\\"\\n\\u007F"'
    assert value([1, 2.5, True, "s", InlineTable(x=1)]) == '[1, 2.5, true, "s", { x = 1 }]'
    doc = {"a": 1, "t": {"b": [1, 2]}, "rows": [{"n": 1}, {"n": 2}], "o": InlineTable(z=0.5)}
    assert (
        dumps(doc)
        == "a = 1\no = { z = 0.5 }\n\n[t]\nb = [1, 2]\n\n[[rows]]\nn = 1\n\n[[rows]]\nn = 2\n"
    )
    assert dumps({"t": {}}, header="made by a test") == "# made by a test\n\n[t]\n"


def test_what_toml_cannot_hold_is_refused():
    with pytest.raises(ValueError, match="non-finite"):
        number(math.nan, finite=True)
    with pytest.raises(ValueError, match="non-finite"):
        dumps({"x": [1.0, math.inf]}, finite=True)
    with pytest.raises(ValueError, match="64-bit"):
        number(2**63)
    with pytest.raises(ValueError, match="cannot write"):
        value(object())


def test_the_three_writers_are_this_one():
    """The robot export, :teach and a study's data lists write through lang/toml_text.py
    (one writer: no second escaping or number format)."""
    from irlc import teach
    from irlc.robots import toml_export
    from irlc.study import plan

    assert toml_export.dumps is toml_text.dumps
    assert teach.toml_text is toml_text
    assert "irlc.lang.toml_text" in Path(plan.__file__).read_text(encoding="utf-8")
    assert teach.array([90.0, -1e-9, 12.5]) == "[90, 0, 12.5]"
