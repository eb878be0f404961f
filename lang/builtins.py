"""Built-in functions and system variables: their signatures for the checker.

Angles are in degrees. Each built-in maps the argument types to a result type, or to
an error message (``str``) that the checker reports at the call.
"""

from __future__ import annotations

from collections.abc import Callable

from irlc.lang import types as T
from irlc.lang.settings import SYSTEM_VARIABLES as SETTING_SYSTEM_VARIABLES

Sig = Callable[[list[T.Type], int], "T.Type | str"]  # (argument types, joint count)

_SYSVAR_TYPES: dict[str | None, T.Type | None] = {
    "REAL": T.REAL,
    "STRING": T.STRING,
    "POSE": T.POSE,
    None: None,
}
# name: (type, writable); None = MAIN_JOINT of the robot. The names: lang/settings.py.
SYSTEM_VARIABLES: dict[str, tuple[T.Type | None, bool]] = {
    v.name: (_SYSVAR_TYPES[v.type_name], v.writable) for v in SETTING_SYSTEM_VARIABLES.values()
}


def _fixed(params: tuple[T.Type, ...], result: T.Type) -> Sig:
    def sig(args: list[T.Type], n: int) -> T.Type | str:
        if len(args) != len(params):
            return f"takes {len(params)} argument{'s' if len(params) != 1 else ''}, got {len(args)}"
        for i, (want, got) in enumerate(zip(params, args, strict=True), start=1):
            if not T.assignable(want, got):
                return f"argument {i}: expected {want}, got {got}"
        return result

    return sig


def _numeric_same(args: list[T.Type], n: int) -> T.Type | str:
    if len(args) != 1:
        return f"takes 1 argument, got {len(args)}"
    if not args[0].is_numeric and args[0] != T.ERROR:
        return f"expected INTEGER or REAL, got {args[0]}"
    return args[0]


def _min_max(args: list[T.Type], n: int) -> T.Type | str:
    if len(args) < 2:
        return f"takes at least 2 arguments, got {len(args)}"
    for i, a in enumerate(args, start=1):
        if not a.is_numeric and a != T.ERROR:
            return f"argument {i}: expected INTEGER or REAL, got {a}"
    return T.INTEGER if all(a == T.INTEGER for a in args) else T.REAL


def _inv(args: list[T.Type], n: int) -> T.Type | str:
    if len(args) != 1:
        return f"takes 1 argument, got {len(args)}"
    if args[0] in (T.POSE, T.ORIENTATION, T.ERROR):
        return args[0]
    return f"expected POSE or ORIENTATION, got {args[0]}"


def _fk(args: list[T.Type], n: int) -> T.Type | str:
    if len(args) != 1:
        return f"takes 1 argument, got {len(args)}"
    if args[0] == T.ERROR or (isinstance(args[0], T.JointTuple) and args[0].name == "MAIN_JOINT"):
        return T.POSE
    return f"expected MAIN_JOINT, got {args[0]}"


R, P = T.REAL, T.POSITION
BUILTINS: dict[str, Sig] = {
    "SIN": _fixed((R,), R),
    "COS": _fixed((R,), R),
    "TAN": _fixed((R,), R),
    "ASIN": _fixed((R,), R),
    "ACOS": _fixed((R,), R),
    "ATAN": _fixed((R,), R),
    "ATAN2": _fixed((R, R), R),
    "SQRT": _fixed((R,), R),
    "ABS": _numeric_same,
    "MIN": _min_max,
    "MAX": _min_max,
    "ROUND": _fixed((R,), T.INTEGER),
    "TRUNC": _fixed((R,), T.INTEGER),
    "DIST": _fixed((P, P), R),
    "INV": _inv,
    "FK": _fk,
    "POSITION": _fixed((R, R, R), P),
    "ORIZYX": _fixed((R, R, R), T.ORIENTATION),
    "ORIXYZ": _fixed((R, R, R), T.ORIENTATION),
    "ORIZYZ": _fixed((R, R, R), T.ORIENTATION),
    "ORIRS": _fixed((R, R, R), T.ORIENTATION),
    "ORIQUAT": _fixed((R, R, R, R), T.ORIENTATION),
    "ORIVANG": _fixed((P, R), T.ORIENTATION),
}
# POSE(...) is special: POSE(POSITION, ORIENTATION) is CALLB POSE 2; POSE(x, y, z, a, b, c)
# is MAKE POSE 6 (see checker/codegen).
POSE_FROM_PARTS = _fixed((P, T.ORIENTATION), T.POSE)
POSE_FROM_NUMBERS = _fixed((R,) * 6, T.POSE)
