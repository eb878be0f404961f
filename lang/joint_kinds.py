"""The two joint kinds, their one-letter codes and their program units: the one owner.

A joint is ``revolute`` (its value an angle: deg in programs, rad inside) or ``prismatic``
(a length: mm in programs, m inside). The IRDATA ``ROBOT`` record spells the kinds as one
letter per joint, ``R`` or ``P`` (``docs/irdata.md``). Robot files, the compiler, the
interpreter and the runtime convert between the word and the letter here; ``irlc.lang``
imports neither the runtime nor the robot library, so the owner lives at this lowest layer.
"""

from __future__ import annotations

from collections.abc import Iterable

REVOLUTE = "revolute"
PRISMATIC = "prismatic"
KINDS = (REVOLUTE, PRISMATIC)
_LETTERS = {"R": REVOLUTE, "P": PRISMATIC}


def kind_letter(kind: str) -> str:
    """``"R"`` or ``"P"``: the first letter of ``kind`` (``"revolute"``, ``"R"``, …),
    upper-cased; ``ValueError`` for any other kind."""
    letter = str(kind)[:1].upper()
    if letter not in _LETTERS:
        raise ValueError(f"unknown joint kind {kind!r}")
    return letter


def kind_letters(kinds: Iterable[str]) -> str:
    """``"RRP…"``: :func:`kind_letter` of each joint, as in the IRDATA ``ROBOT`` record."""
    return "".join(kind_letter(k) for k in kinds)


def kind_from_letter(letter: str) -> str:
    """``"revolute"`` for ``"R"``, ``"prismatic"`` for ``"P"``; ``ValueError`` otherwise."""
    kind = _LETTERS.get(letter)
    if kind is None:
        raise ValueError(f"unknown joint kind letter {letter!r}")
    return kind


def is_revolute(kind: str) -> bool:
    """Whether a joint of ``kind`` (word or letter) turns: its value is an angle."""
    return kind_letter(kind) == "R"
