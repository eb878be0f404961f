"""The ranges of IRL's values: INTEGER is signed 64-bit, a STRING holds at most
:data:`MAX_STRING` characters, a variable's type and one scope's variables at most
:data:`MAX_ELEMENTS` elements. The one owner of these ranges and of their messages, for
the compiler (literals, constant folding, declarations), the ``.ird`` reader and the
runtime.
"""

from __future__ import annotations

INT_MIN, INT_MAX = -(2**63), 2**63 - 1  # INTEGER is signed 64-bit, as in the runtime
MAX_STRING = 65_535
"""The most characters a STRING holds: a longer literal, .ird constant or concatenation
result is an error (a loop doubling a string would otherwise fill the memory)."""


MAX_ELEMENTS = 1_000_000
"""The most elements a type holds: nested arrays multiply, records add their fields'
elements; a scalar, a POSE or a joint tuple is one."""

MAX_SCOPE_ELEMENTS = 2 * MAX_ELEMENTS
"""The most elements the variables of one scope hold together: the program's globals; one
routine's parameters passed by value and its locals."""

MAX_LIVE_ELEMENTS = 8 * MAX_ELEMENTS
"""The most elements the globals and the variables of every active call hold together at
run time (a recursion of routines with large locals would otherwise fill the memory)."""


def elements_too_many(n: int, what: str, most: int = MAX_ELEMENTS) -> str | None:
    """The words for ``what`` holding ``n`` elements, beyond ``most``; else ``None``."""
    if n <= most:
        return None
    return f"{what} would hold {n} elements (at most {most})"


def string_too_long(n: int) -> str | None:
    """The words for a STRING of ``n`` characters beyond :data:`MAX_STRING`; else ``None``."""
    if n <= MAX_STRING:
        return None
    return f"a STRING of {n} characters is too long (at most {MAX_STRING})"


def integer_overflow(x: int) -> str | None:
    """The runtime's words for an INTEGER outside ``[INT_MIN, INT_MAX]``; ``None`` if inside."""
    if INT_MIN <= x <= INT_MAX:
        return None
    return f"INTEGER overflow ({x} is outside the 64-bit range)"


_ECHO_DIGITS = 40  # a longer literal is named by its length in messages, not echoed


def parse_integer(text: str) -> int | str:
    """A decimal integer literal ``[+-]?[0-9]+``: its value, or the overflow message.

    Leading zeros are dropped first and a literal of more than 40 significant digits (far
    outside ``[INT_MIN, INT_MAX]``) is refused before ``int()``, which refuses strings of
    over 4,300 digits; its message names its length instead of echoing it.
    """
    sign = "-" if text.startswith("-") else ""
    digits = text.lstrip("+-").lstrip("0") or "0"
    if len(digits) > _ECHO_DIGITS:
        return f"INTEGER overflow (a {len(digits)}-digit number is outside the 64-bit range)"
    return integer_overflow(value := int(sign + digits)) or value
