"""INTEGER is signed 64-bit at compile time as at run time: literals and constant folding.

The expected messages are not written down here: they come from the runtime's own
arithmetic (``irlc.runtime.interpreter.builtins``) applied to the same operands, so the compiler is
checked against the rule it must agree with.
"""

from __future__ import annotations

from collections.abc import Callable

import pytest
from irlc.runtime.errors import RunFailure
from irlc.runtime.interpreter import builtins as rt

from .conftest import compile_text

INT_MAX = 2**63 - 1
INT_MIN = -(2**63)


def program(expr: str) -> str:
    """``expr`` starts on line 5, column 11."""
    return (
        "PROGRAM t;\nROBOT r := six;\nCONST m = -9223372036854775807 - 1;\nBEGIN\n"
        f"  WRITELN({expr});\nENDPROGRAM\n"
    )


def runtime_message(fn: Callable[..., object], *args: int) -> str:
    with pytest.raises(RunFailure) as e:
        fn(*args)
    return str(e.value)


@pytest.mark.parametrize(
    ("expr", "column", "fn", "args"),
    [
        ("9223372036854775807 + 1", 31, rt.add, (INT_MAX, 1)),
        ("-9223372036854775807 - 2", 32, rt.sub, (-INT_MAX, 2)),
        ("4611686018427387904 * 2", 31, rt.mul, (2**62, 2)),
        ("m DIV -1", 13, rt.idiv, (INT_MIN, -1)),
        ("m MOD -1", 13, rt.mod, (INT_MIN, -1)),
        ("-m", 11, rt.neg, (INT_MIN,)),
        ("(1 + 9223372036854775807) * 1.5", 14, rt.add, (1, INT_MAX)),
    ],
    ids=["add", "sub", "mul", "div", "mod", "neg", "inside_real_expr"],
)
def test_folding_overflow_is_a_compile_error_worded_like_the_runtime(
    expr: str, column: int, fn: Callable[..., object], args: tuple[int, ...]
) -> None:
    result = compile_text(program(expr))
    assert result.code is None
    assert [(d.line, d.column, d.message) for d in result.errors] == [
        (5, column, runtime_message(fn, *args))
    ]


@pytest.mark.parametrize("text", ["9223372036854775808", "99999999999999999999999"])
def test_integer_literal_out_of_range(text: str) -> None:
    result = compile_text(program(text))
    assert result.code is None
    (d,) = result.errors
    assert (d.line, d.column) == (5, 11)
    assert d.message == runtime_message(rt.checked, int(text)).removeprefix("arithmetic: ")
    assert d.hint and str(INT_MAX) in d.hint


@pytest.mark.parametrize(
    ("expr", "value"),
    [
        ("9223372036854775807", INT_MAX),
        ("-9223372036854775807 - 1", INT_MIN),
        ("m + 9223372036854775807", -1),
        ("m DIV 2", rt.idiv(INT_MIN, 2)),
        ("m MOD 7", rt.mod(INT_MIN, 7)),
        ("-(m + 1)", INT_MAX),
        ("9223372036854775807 * 2.0", 2.0 * INT_MAX),
    ],
)
def test_values_at_the_bounds_fold_exactly(expr: str, value: int | float) -> None:
    result = compile_text(program(expr))
    assert result.ok, [d.header() for d in result.diagnostics]
    consts = [c.data[0] for c in result.code.consts]
    assert value in consts and type(value) in {type(c) for c in consts if c == value}
