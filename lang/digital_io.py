"""Digital outputs ``OUT[n]``: the one place of their numbers' range and of ``PULSE``'s
duration, read by the checker (constants, at compile time) and the interpreter (run time).

``OUT[n] := TRUE;`` / ``FALSE;`` switch output ``n`` (a timestamped event, a trace column
``out_<n>``), ``OUT[n]`` reads it back, ``PULSE(OUT[n], t);`` sets it TRUE now and FALSE
``t`` seconds later without waiting (like KRL's ``PULSE($OUT[n], TRUE, t)``). ``OUT`` is
not a reserved word: a program that declares its own ``OUT`` uses that.
"""

from __future__ import annotations

from irlc.lang import ast
from irlc.lang.settings import SettingRange

OUTPUT_LOW, OUTPUT_HIGH = 1, 4096  # like KRL's $OUT[1..4096]
PULSE_RANGE = SettingRange(0.0, 86400.0, "s")  # a pulse of (0, one day] seconds


def output_error(n: object) -> str | None:
    """``None`` if ``n`` names an output, else why not."""
    if isinstance(n, int) and not isinstance(n, bool) and OUTPUT_LOW <= n <= OUTPUT_HIGH:
        return None
    return f"output numbers are {OUTPUT_LOW}..{OUTPUT_HIGH}, got {n}"


def pulse_error(t: object) -> str | None:
    """``None`` if ``t`` is an admissible pulse duration (s), else why not."""
    if isinstance(t, int | float) and not isinstance(t, bool) and t in PULSE_RANGE:
        return None
    return f"PULSE: the duration must be {PULSE_RANGE}, got {t}"


def is_output_syntax(node: ast.Expr) -> bool:
    """``OUT[…]`` as written (the checker decides whether ``OUT`` is the output array or
    a declared name)."""
    return (
        isinstance(node, ast.Index)
        and isinstance(node.base, ast.Name)
        and node.base.name.upper() == "OUT"
    )
