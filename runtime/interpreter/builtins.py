"""Operators and built-in functions of the IRDATA machine (everything except FK).

Numbers follow Pascal: INTEGER op INTEGER stays INTEGER for ``+ − *``. Division has two
IRDATA operations (docs/irdata.md): ``DIV`` is IRL's ``/`` and always REAL; ``IDIV`` is
IRL's ``DIV``, the integer quotient truncated toward zero (its messages use the IRL name
``DIV``); ``MOD`` is ``a − (a IDIV b)·b`` (the sign of the dividend). INTEGER is 64-bit
signed; results outside that range, and REAL results that are not finite, are run-time
errors, so no NaN or infinity is ever stored. Angles are in degrees. Functions raise
:class:`~irlc.runtime.errors.RunFailure` without a line; the interpreter adds line and time.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from irlc.lang.irdata import integer_overflow, string_too_long
from irlc.runtime import units
from irlc.runtime import values as V
from irlc.runtime.errors import RunFailure
from irlc.runtime.values import JointTuple, Orientation, Pose, Position

DOMAIN_TOLERANCE = 1e-12  # ASIN / ACOS accept |x| ≤ 1 + this (rounding of computed values)


def is_number(v: object) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool)


def _is_int(v: object) -> bool:
    return isinstance(v, int) and not isinstance(v, bool)


def malformed(message: str) -> RunFailure:
    return RunFailure(f"{message} (the IRDATA code is malformed)")


def checked(x: float | int, what: str = "arithmetic") -> float | int:
    """Reject integer overflow and non-finite reals."""
    if isinstance(x, int):
        overflow = integer_overflow(x)  # the one INTEGER range: lang/value_ranges.py
        if overflow is not None:
            raise RunFailure(f"{what}: {overflow}")
        return x
    if not math.isfinite(x):
        raise RunFailure(f"{what}: the result is not a finite number")
    return x


def checked_value(v: object, what: str) -> object:
    """:func:`checked` for any value: numbers and the numbers inside geometric values."""
    if is_number(v):
        return checked(v, what)
    if isinstance(v, Position):
        _checked_tuple(v.as_tuple(), what)
    elif isinstance(v, Pose):
        _checked_tuple(v.pos.as_tuple(), what)
    elif isinstance(v, JointTuple):
        _checked_tuple(v.values, what)
    return v


def _joint_pair(op: str, a: JointTuple, b: JointTuple) -> None:
    if len(a.values) != len(b.values):
        raise malformed(f"{op}: joint tuples of {len(a.values)} and {len(b.values)} values")


def _type_error(verb: str, a: object, b: object) -> RunFailure:
    return malformed(f"cannot {verb} {V.type_name(a)} and {V.type_name(b)}")


def _checked_tuple(values: tuple[float, ...], what: str) -> tuple[float, ...]:
    for v in values:
        checked(v, what)
    return values


# --------------------------------------------------------------------------- arithmetic


def add(a: object, b: object) -> object:
    if is_number(a) and is_number(b):
        return checked(a + b, "addition")
    if isinstance(a, Position) and isinstance(b, Position):
        return V.Position(*_checked_tuple(V.position_add(a, b).as_tuple(), "addition"))
    if isinstance(a, JointTuple) and isinstance(b, JointTuple):
        _joint_pair("addition", a, b)
        return JointTuple(a.type, _checked_tuple(V.joint_add(a, b).values, "addition"))
    if isinstance(a, str) and isinstance(b, str):
        if too_long := string_too_long(len(a) + len(b)):
            raise RunFailure(f"string concatenation: {too_long}")
        return a + b
    raise _type_error("add", a, b)


def sub(a: object, b: object) -> object:
    if is_number(a) and is_number(b):
        return checked(a - b, "subtraction")
    if isinstance(a, Position) and isinstance(b, Position):
        return V.Position(*_checked_tuple(V.position_sub(a, b).as_tuple(), "subtraction"))
    if isinstance(a, JointTuple) and isinstance(b, JointTuple):
        _joint_pair("subtraction", a, b)
        return JointTuple(a.type, _checked_tuple(V.joint_sub(a, b).values, "subtraction"))
    raise _type_error("subtract", a, b)


def _scale(s: float, v: object, what: str) -> object:
    if isinstance(v, Position):
        return V.Position(*_checked_tuple(V.position_scale(s, v).as_tuple(), what))
    if isinstance(v, JointTuple):
        return JointTuple(v.type, _checked_tuple(V.joint_scale(s, v).values, what))
    return None


def mul(a: object, b: object) -> object:
    if is_number(a) and is_number(b):
        return checked(a * b, "multiplication")
    scaled = None
    if is_number(a):
        scaled = _scale(a, b, "multiplication")
    elif is_number(b):
        scaled = _scale(b, a, "multiplication")
    if scaled is None:
        raise _type_error("multiply", a, b)
    return scaled


def div(a: object, b: object) -> object:
    """IRDATA ``DIV`` (IRL's ``/``): REAL division (also POSITION / number, joint tuple /
    number)."""
    if not is_number(b):
        raise _type_error("divide", a, b)
    if b == 0:
        raise RunFailure("division by zero")
    if is_number(a):
        return checked(a / b, "division")
    scaled = _scale(1.0 / b, a, "division")
    if scaled is None:
        raise _type_error("divide", a, b)
    return scaled


def _int_operands(op: str, a: object, b: object) -> tuple[int, int]:
    if not (_is_int(a) and _is_int(b)):
        names = f"{V.type_name(a)} and {V.type_name(b)}"
        raise malformed(f"{op} needs two INTEGER operands, got {names}")
    if b == 0:
        raise RunFailure(f"division by zero in {op}")
    return a, b


def idiv(a: object, b: object) -> int:
    """IRDATA ``IDIV`` (IRL's ``DIV``): integer quotient truncated toward zero."""
    x, y = _int_operands("DIV", a, b)
    q = abs(x) // abs(y)
    return checked(q if (x < 0) == (y < 0) else -q, "DIV")


def mod(a: object, b: object) -> int:
    """``MOD``: ``a − (a IDIV b)·b``, the sign of the dividend."""
    x, y = _int_operands("MOD", a, b)
    return x - idiv(x, y) * y


def neg(a: object) -> object:
    if is_number(a):
        return checked(-a, "negation")
    scaled = _scale(-1.0, a, "negation")
    if scaled is None:
        raise malformed(f"cannot negate {V.type_name(a)}")
    return scaled


def logical_not(a: object) -> bool:
    if not isinstance(a, bool):
        raise malformed(f"NOT needs a BOOLEAN, got {V.type_name(a)}")
    return not a


def _bools(op: str, a: object, b: object) -> None:
    if not (isinstance(a, bool) and isinstance(b, bool)):
        raise malformed(f"{op} needs BOOLEAN operands, got {V.type_name(a)} and {V.type_name(b)}")


def logical_and(a: object, b: object) -> bool:
    _bools("AND", a, b)
    return a and b


def logical_or(a: object, b: object) -> bool:
    _bools("OR", a, b)
    return a or b


def logical_xor(a: object, b: object) -> bool:
    _bools("EXOR", a, b)
    return a != b


def compose(a: object, b: object) -> object:
    """``a : b``: POSE:POSE → POSE, POSE:POSITION → POSITION, ORIENTATION:ORIENTATION."""
    if isinstance(a, Pose) and isinstance(b, Pose):
        return checked_value(V.compose(a, b), "composition")
    if isinstance(a, Pose) and isinstance(b, Position):
        return checked_value(V.transform_point(a, b), "composition")
    if isinstance(a, Orientation) and isinstance(b, Orientation):
        return V.quat_multiply(a, b)
    raise _type_error("compose", a, b)


# --------------------------------------------------------------------------- comparison


def _ordered(a: object, b: object) -> bool:
    return (is_number(a) and is_number(b)) or (isinstance(a, str) and isinstance(b, str))


def equal(a: object, b: object) -> bool:
    if _ordered(a, b) or (isinstance(a, bool) and isinstance(b, bool)):
        return a == b
    geometric = (Position, Orientation, Pose, JointTuple)
    if isinstance(a, geometric) and type(a) is type(b):
        return V.geometric_equal(a, b)
    raise _type_error("compare", a, b)


def _order(op: str, a: object, b: object) -> None:
    if not (_ordered(a, b) or (isinstance(a, bool) and isinstance(b, bool))):
        raise malformed(f"{op}: cannot order {V.type_name(a)} and {V.type_name(b)}")


COMPARISONS: dict[str, Callable[[object, object], bool]] = {
    "EQ": equal,
    "NE": lambda a, b: not equal(a, b),
}


def _make_order(op: str, fn: Callable[[object, object], bool]) -> Callable[[object, object], bool]:
    def compare(a: object, b: object) -> bool:
        _order(op, a, b)
        return fn(a, b)

    return compare


COMPARISONS["LT"] = _make_order("<", lambda a, b: a < b)
COMPARISONS["GT"] = _make_order(">", lambda a, b: a > b)
COMPARISONS["LE"] = _make_order("<=", lambda a, b: a <= b)
COMPARISONS["GE"] = _make_order(">=", lambda a, b: a >= b)

BINARY: dict[str, Callable[[object, object], object]] = {
    "ADD": add,
    "SUB": sub,
    "MUL": mul,
    "DIV": div,
    "IDIV": idiv,
    "MOD": mod,
    "AND": logical_and,
    "OR": logical_or,
    "XOR": logical_xor,
    "COMPOSE": compose,
    **COMPARISONS,
}


# --------------------------------------------------------------------------- built-in functions


def _numbers(name: str, args: tuple) -> tuple[float, ...]:
    for a in args:
        if not is_number(a):
            raise malformed(f"{name}: expected numbers, got {V.type_name(a)}")
    return args


def _trig_exact(x: float) -> tuple[float, float]:
    """``(sin x, cos x)`` of ``x`` degrees, exact at multiples of 90°."""
    r = math.fmod(x, 360.0)
    quarter = r / 90.0
    if quarter == int(quarter):
        k = int(quarter) % 4
        return ((0.0, 1.0, 0.0, -1.0)[k], (1.0, 0.0, -1.0, 0.0)[k])
    rad = r * units.DEG
    return math.sin(rad), math.cos(rad)


def _sin(x: float) -> float:
    return _trig_exact(x)[0]


def _cos(x: float) -> float:
    return _trig_exact(x)[1]


def _tan(x: float) -> float:
    s, c = _trig_exact(x)
    if c == 0.0:
        raise RunFailure(f"TAN({V.format_real(x)}) is undefined (an odd multiple of 90 degrees)")
    return s / c


def _inverse_trig(name: str, fn: Callable[[float], float]) -> Callable[[float], float]:
    def f(x: float) -> float:
        if abs(x) > 1.0 + DOMAIN_TOLERANCE:
            raise RunFailure(f"{name}({V.format_real(x)}): the argument is outside [-1, 1]")
        return fn(max(-1.0, min(1.0, x))) / units.DEG

    return f


def _sqrt(x: float) -> float:
    if x < 0:
        raise RunFailure(f"SQRT({V.format_real(x)}): the argument is negative")
    return math.sqrt(x)


def _round(x: float) -> int:
    """Pascal ROUND: halves away from zero."""
    r = math.floor(abs(x) + 0.5)
    return checked(int(r) if x >= 0 else -int(r), "ROUND")


def _min_max(name: str, fn: Callable) -> Callable:
    def f(*args: float) -> float | int:
        if not args:
            raise malformed(f"{name} needs at least one argument")
        _numbers(name, args)
        r = fn(args)
        return r if all(isinstance(a, int) for a in args) else float(r)

    return f


_SCALAR_FUNCTIONS: dict[str, tuple[int, Callable]] = {
    "SIN": (1, _sin),
    "COS": (1, _cos),
    "TAN": (1, _tan),
    "ASIN": (1, _inverse_trig("ASIN", math.asin)),
    "ACOS": (1, _inverse_trig("ACOS", math.acos)),
    "ATAN": (1, lambda x: math.atan(x) / units.DEG),
    "ATAN2": (2, lambda y, x: math.atan2(y, x) / units.DEG),
    "SQRT": (1, _sqrt),
    "ROUND": (1, _round),
    "TRUNC": (1, lambda x: checked(int(x), "TRUNC")),
    "ORIZYX": (3, V.orientation_from_zyx),
    "ORIXYZ": (3, V.orientation_from_xyz),
    "ORIZYZ": (3, V.orientation_from_zyz),
    "ORIRS": (3, V.orientation_from_rpy),
}


def _abs(v: object) -> object:
    if not is_number(v):
        raise malformed(f"ABS: expected a number, got {V.type_name(v)}")
    return abs(v)


def _point(name: str, v: object) -> Position:
    if isinstance(v, Pose):
        return v.pos
    if isinstance(v, Position):
        return v
    raise malformed(f"{name}: expected a POSITION, got {V.type_name(v)}")


def _dist(a: object, b: object) -> float:
    return checked(V.distance(_point("DIST", a), _point("DIST", b)), "DIST")


def _inv(p: object) -> object:
    if isinstance(p, Pose):
        return V.inverse(p)
    if isinstance(p, Orientation):
        return V.orientation_inverse(p)
    raise malformed(f"INV: expected a POSE, got {V.type_name(p)}")


def _position(*args: object) -> Position:
    if len(args) == 1:
        return _point("POSITION", args[0])
    if len(args) == 3:
        return Position(*(float(a) for a in _numbers("POSITION", args)))
    raise malformed(f"POSITION: expected 3 numbers, got {len(args)} arguments")


def _pose(*args: object) -> Pose:
    if len(args) == 6:
        return V.pose_from_zyx(*_numbers("POSE", args))
    if len(args) in (1, 2) and isinstance(args[0], Position):
        ori = args[1] if len(args) == 2 else V.IDENTITY
        if isinstance(ori, Orientation):
            return Pose(args[0], ori)
    raise malformed("POSE: expected (POSITION, ORIENTATION) or 6 numbers")


def _oriquat(*args: object) -> Orientation:
    if len(args) != 4:
        raise malformed(f"ORIQUAT: expected 4 numbers, got {len(args)}")
    try:
        return V.orientation_from_quat(*_numbers("ORIQUAT", args))
    except ValueError as e:
        raise RunFailure(f"ORIQUAT: {e}") from None


def _orivang(*args: object) -> Orientation:
    if len(args) != 2 or not isinstance(args[0], Position) or not is_number(args[1]):
        raise malformed("ORIVANG: expected (POSITION axis, angle)")
    try:
        return V.orientation_from_axis_angle(args[0], args[1])
    except ValueError as e:
        raise RunFailure(f"ORIVANG: {e}") from None


_GENERAL_FUNCTIONS: dict[str, Callable[..., object]] = {
    "ABS": _abs,
    "MIN": _min_max("MIN", min),
    "MAX": _min_max("MAX", max),
    "DIST": lambda *a: _dist(*a) if len(a) == 2 else _arity("DIST", 2, len(a)),
    "INV": lambda *a: _inv(*a) if len(a) == 1 else _arity("INV", 1, len(a)),
    "POSITION": _position,
    "POSE": _pose,
    "ORIQUAT": _oriquat,
    "ORIVANG": _orivang,
}

BUILTIN_NAMES = frozenset(_SCALAR_FUNCTIONS) | frozenset(_GENERAL_FUNCTIONS) | {"FK"}


def _arity(name: str, expected: int, got: int):
    raise malformed(f"{name} takes {expected} argument(s), got {got}")


def call_builtin(name: str, args: tuple) -> object:
    """Evaluate built-in ``name`` (not FK) on ``args``; the result is checked finite."""
    scalar = _SCALAR_FUNCTIONS.get(name)
    if scalar is not None:
        arity, fn = scalar
        if len(args) != arity:
            _arity(name, arity, len(args))
        return checked_value(fn(*_numbers(name, args)), name)
    general = _GENERAL_FUNCTIONS.get(name)
    if general is None:
        raise malformed(f"unknown built-in function {name!r}")
    return checked_value(general(*args), name)
