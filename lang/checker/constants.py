"""Constant folding: the value of an operator applied to constant operands.

An expression whose operands are constants gets its value at compile time (``Expr.const``,
an IRDATA :class:`Value`), computed as the interpreter would: INTEGER DIV and MOD truncate
towards zero (``a = (a DIV b)·b + a MOD b``), INTEGER results outside the INTEGER range
and non-finite REAL results are errors with the run-time wording.
"""

from __future__ import annotations

import math

from irlc.lang import types as T
from irlc.lang.irdata import Value


def number(v: Value | None) -> float | int | None:
    """The number a constant holds, or ``None`` (not a constant, or not a number)."""
    if v is None or v.type not in ("INTEGER", "REAL") or not v.data:
        return None
    return v.data[0]


def coerce(v: Value | None, ty: T.Type) -> Value | None:
    """Constant ``v`` as a value of type ``ty`` (INTEGER → REAL, CHAR → STRING)."""
    if v is None:
        return None
    if ty == T.REAL and v.type == "INTEGER":
        return Value("REAL", (float(v.data[0]),))
    if ty == T.STRING and v.type == "CHAR":
        return Value("STRING", v.data)
    return v


def numbers_value(ty: str, consts: list[Value | None]) -> Value | None:
    """A tuple constant of type ``ty`` when every item is a number constant, else ``None``."""
    if all(c is not None and c.type in ("INTEGER", "REAL") for c in consts):
        return Value(ty, tuple(float(c.data[0]) for c in consts))  # type: ignore[union-attr]
    return None


def fold_binary(op: str, ty: T.Type, lc: Value, rc: Value) -> Value | str | None:
    """The constant ``lc op rc`` of type ``ty``; an error message (overflow, division by
    zero); ``None`` when the operator is not folded."""
    a, b = number(lc), number(rc)
    try:
        if ty.is_numeric and a is not None and b is not None:
            v = _arith(op, a, b)
            if v is None:
                return None
            if isinstance(v, float) and not math.isfinite(v):
                return "the constant expression overflows"
            if ty == T.INTEGER and (overflow := _integer_overflow(op, a, b, v)):
                return overflow
            return Value(ty.name, (int(v) if ty == T.INTEGER else float(v),))
        if ty == T.BOOLEAN:
            x, y = lc.data[0], rc.data[0]
            v = _logic(op, x, y)
            if v is not None:
                return Value("BOOLEAN", (v,))
    except ZeroDivisionError:
        return "division by zero in a constant expression"
    return None


def _arith(op: str, a, b):
    if op == "+":
        return a + b
    if op == "-":
        return a - b
    if op == "*":
        return a * b
    if op == "/":
        return a / b
    if op == "DIV":
        q = abs(a) // abs(b)
        return q if (a >= 0) == (b > 0) else -q
    if op == "MOD":
        if b == 0:
            raise ZeroDivisionError
        q = abs(a) // abs(b)
        q = q if (a >= 0) == (b > 0) else -q
        return a - q * b
    return None


_RUNTIME_OP_NAMES = {"+": "addition", "-": "subtraction", "*": "multiplication", "DIV": "DIV"}


def _integer_overflow(op: str, a: int, b: int, v: int) -> str | None:
    """The runtime's message if folding ``a op b = v`` overflows (MOD overflows in its DIV)."""
    if op == "MOD":
        op, v = "DIV", _arith("DIV", a, b)
    overflow = T.integer_overflow(v)
    return f"{_RUNTIME_OP_NAMES.get(op, op)}: {overflow}" if overflow else None


def _logic(op: str, x, y):
    if op == "AND":
        return x and y
    if op == "OR":
        return x or y
    if op == "EXOR":
        return x != y
    if op in ("=", "<>", "<", ">", "<=", ">="):
        return {"=": x == y, "<>": x != y, "<": x < y, ">": x > y, "<=": x <= y, ">=": x >= y}[op]
    return None
