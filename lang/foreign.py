"""Habits of other robot languages (KUKA KRL, ABB RAPID) and irlc's form for each.

A programmer coming from KRL writes ``PTP left``, ``$VEL.CP = 0.25`` or ``x = 5``; one from
RAPID ``MoveL p10, v100, z10, tool0``, ``WaitTime 1`` or ``VAR num x := 0``; both write
units after numbers (``250 mm/s``). These are syntax errors here; the functions below give
the error a message and a hint in irlc's words, with the statement rewritten where it can
be (:func:`motion_form`). Approximation words (``C_DIS``, ``z50``, ``fine``) have their
hint in the settings table (:func:`irlc.lang.settings.approximation_hint`).

Each function answers ``None`` when the word is no habit it knows, so the caller keeps its
own message.
"""

from __future__ import annotations

import re

KRL_MOTIONS = {
    "PTP": "MOVE PTP",
    "LIN": "MOVE LIN",
    "CIRC": "MOVE CIRCLE",
    "SPTP": "MOVE PTP",
    "SLIN": "MOVE LIN",
    "SCIRC": "MOVE CIRCLE",
    "PTP_REL": "MOVE_INC PTP",
    "LIN_REL": "MOVE_INC LIN",
    "SPTP_REL": "MOVE_INC PTP",
    "SLIN_REL": "MOVE_INC LIN",
}
"""KRL's motion words (upper case) → irlc's motion statement."""

RAPID_MOTIONS = {
    "MOVEL": ("MOVE LIN", 1),
    "MOVEJ": ("MOVE PTP", 1),
    "MOVEC": ("MOVE CIRCLE", 2),
    "MOVEABSJ": ("MOVE PTP", 1),
    "MOVELREL": ("MOVE_INC LIN", 1),
}
"""RAPID's motion instructions (upper case) → (irlc's motion, the number of targets)."""

STATEMENTS = {
    "WAITTIME": ("RAPID", "a wait is written WAIT t SEC;", "WAIT {args} SEC;"),
    "TPWRITE": ("RAPID", "output is written WRITELN(…);", "WRITELN({args});"),
    "LOOP": ("KRL", "an endless loop is written WHILE TRUE DO … ENDWHILE;", None),
    "ENDLOOP": ("KRL", "an endless loop is written WHILE TRUE DO … ENDWHILE;", None),
    "DECL": ("KRL", "a variable is declared VAR TYPE: name; (DECL REAL x is VAR REAL: x;)", None),
    "SWITCH": ("KRL", "a selection is written CASE x OF 1: …; ELSE … ENDCASE;", None),
    "TEST": ("RAPID", "a selection is written CASE x OF 1: …; ELSE … ENDCASE;", None),
    "STOP": ("RAPID", "the program stops with HALT; (PAUSE; pauses it)", None),
    "EXIT": ("RAPID", "the program stops with HALT;", None),
    "SETDO": ("RAPID", "a digital output is switched with OUT[n] := TRUE;", None),
    "SET": ("RAPID", "a digital output is switched with OUT[n] := TRUE;", None),
    "RESET": ("RAPID", "a digital output is switched off with OUT[n] := FALSE;", None),
    "PULSEDO": ("RAPID", "a pulse is written PULSE(OUT[n], seconds);", None),
    "WAITDI": ("RAPID", "waiting for an input is written WAIT FOR IN[n];", None),
}
"""Other statement words (upper case) → (language, what irlc writes, the rewritten statement
from the arguments' text, or ``None``)."""

SYSTEM_VARIABLES = {
    "$VEL.CP": ("R_SPEED", "m/s", "mm/s", 1000.0),
    "$VEL.ORI1": ("R_SPEED_ORI", "deg/s", "deg/s", 1.0),
    "$VEL.ORI2": ("R_SPEED_ORI", "deg/s", "deg/s", 1.0),
    "$ACC.CP": ("R_ACC", "m/s²", "mm/s²", 1000.0),
    "$VEL_AXIS": ("R_SPEED_PTP", "%", "%, one value for all joints", 1.0),
    "$ACC_AXIS": ("R_ACC_PTP", "%", "%, one value for all joints", 1.0),
    "$APO.CDIS": ("R_APPROX", "mm", "mm", 1.0),
    "$APO.CPTP": ("R_APPROX", "%", "mm (a TCP distance)", None),
    "$TOOL": ("R_TOOL", None, "a POSE, mm and deg", None),
    "$BASE": ("R_BASE", None, "a POSE, mm and deg", None),
    "$OV_PRO": ("R_OVERRIDE", "%", "%", 1.0),
    "$POS_ACT": ("R_ACT_POSE", None, "a POSE, read only", None),
    "$AXIS_ACT": ("R_ACT_JOINT", None, "a MAIN_JOINT, read only", None),
    "$OUT": ("OUT", None, "", None),
    "$IN": ("IN", None, "", None),
}
"""KRL's system variables → (irlc's name, KRL's unit, irlc's unit or form, the factor from
KRL's unit to irlc's — ``None`` when there is no plain one)."""

UNITS = {
    "MM": 1.0,
    "DEG": 1.0,
    "S": 1.0,
    "M": 1000.0,
    "CM": 10.0,
    "RAD": 57.29577951308232,
    "MS": 0.001,
    "MIN": 60.0,
    "DEGREE": 1.0,
    "DEGREES": 1.0,
    "SECONDS": 1.0,
    "PERCENT": 1.0,
}
"""Unit words written after a number → the factor to irlc's unit (mm, deg, s)."""

_UNIT_TEXT = "numbers carry no unit here: mm, deg and s (mm/s, deg/s, %) are implied"


def statement_message(word: str) -> str:
    return f"'{word}' is not a statement of this dialect"


def motion_form(word: str, args: str, robot: str | None = None) -> str | None:
    """irlc's statement for another language's motion ``word`` with the text of its
    arguments (``"left, v100, z10, tool0"``), e.g. ``MOVE LIN left WITH SPEED := 100 WITH
    APPROX := 10``; with ``robot`` (a cell's ``MOVE a LIN_REL p``) the statement names it
    (``MOVE_INC a LIN p``); ``None`` for no motion word."""
    upper = word.upper()
    if upper in KRL_MOTIONS:
        parts = args.split()
        approx = [p for p in parts if re.fullmatch(r"C_(DIS|PTP|VEL|ORI|SPL)", p, re.I)]
        target = " ".join(p for p in parts if p not in approx) or "target"
        motion = _named(KRL_MOTIONS[upper], robot)
        return motion + f" {target}" + (" WITH APPROX := mm" if approx else "")
    if upper not in RAPID_MOTIONS:
        return None
    motion, targets = RAPID_MOTIONS[upper]
    motion = _named(motion, robot)
    items = _split_arguments(args)
    shown = ", ".join(items[:targets]) or "target"
    clauses = []
    rest = items[targets:]
    if rest and not motion.endswith(" PTP") and (speed := re.fullmatch(r"v(\d+)", rest[0], re.I)):
        clauses.append(f"WITH SPEED := {speed[1]}")
    if len(rest) > 1 and (zone := re.fullmatch(r"z(\d+)", rest[1], re.I)):
        clauses.append(f"WITH APPROX := {zone[1]}")
    return " ".join([motion, shown, *clauses])


def _named(motion: str, robot: str | None) -> str:
    """``"MOVE LIN"`` with a cell's robot named after its first word: ``"MOVE a LIN"``."""
    if robot is None:
        return motion
    first, rest = motion.split(" ", 1)
    return f"{first} {robot} {rest}"


def motion_hint(word: str, args: str, robot: str | None = None) -> str | None:
    """The hint for a motion word of KRL or RAPID: the statement rewritten (naming
    ``robot``, see :func:`motion_form`) and the words that differ."""
    form = motion_form(word, args, robot)
    if form is None:
        return None
    if word.upper() in KRL_MOTIONS:
        why = "KRL's PTP, LIN, CIRC are MOVE PTP, MOVE LIN, MOVE CIRCLE here"
    else:
        why = (
            "RAPID's speed data vN is WITH SPEED := N (mm/s; a PTP's speed is SPEED_PTP, % of "
            "the joints'), its zone zN WITH APPROX := N (mm), fine the exact stop (the "
            "default), the tool R_TOOL"
        )
    return f"write {form}; ({why})"


def statement_hint(word: str, args: str) -> str | None:
    """The hint for another statement word of KRL or RAPID (``WaitTime 1`` → ``write WAIT 1
    SEC;``), else ``None``."""
    motion = motion_hint(word, args)
    if motion is not None:
        return motion
    known = STATEMENTS.get(word.upper())
    if known is None:
        return None
    language, what, form = known
    if form is not None and args.strip():
        return f"write {form.format(args=args.strip())} ({language}'s {word}: {what})"
    return f"{what} ({word} is {language}'s)"


def system_variable(text: str) -> tuple[str, str] | None:
    """``(message, hint)`` for a KRL system variable at the start of ``text`` (``$VEL.CP =
    0.25``), else ``None``."""
    match = re.match(r"\$([A-Za-z_][A-Za-z0-9_]*)(\.[A-Za-z_][A-Za-z0-9_]*)?", text)
    if match is None:
        return None
    whole = match[0].upper()
    key = whole if whole in SYSTEM_VARIABLES else "$" + match[1].upper()
    written = match[0]
    if key not in SYSTEM_VARIABLES:
        return (
            f"'{written}' is not a name here (KRL's system variables start with '$')",
            "irlc's system variables start with R_: R_SPEED, R_ACC, R_SPEED_PTP, R_TOOL, "
            "R_BASE, R_APPROX, R_OVERRIDE, R_ACT_POSE, … (docs/language.md §6)",
        )
    name, krl_unit, unit, factor = SYSTEM_VARIABLES[key]
    message = f"'{written}' is KRL's; irlc's system variables have no '$'"
    rest = text[match.end() :]
    value = re.match(r"\s*:?=\s*([-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?)\s*(;|$)", rest)
    if value is not None and factor is not None:
        converted = _number(float(value[1]) * factor)
        return message, (
            f"write {name} := {converted}; ({written} in {krl_unit} is {name} in {unit})"
        )
    if name in ("OUT", "IN"):
        index = re.match(r"\[\s*(\d+)\s*\]", rest)
        shown = f"{name}[{index[1]}]" if index else f"{name}[n]"
        form = f"write {shown} := TRUE;" if name == "OUT" else f"read {shown}"
        return message, f"{form} (KRL's {key}[n] is {name}[n] here)"
    unit_text = f" in {unit}" if krl_unit is not None and unit != krl_unit else f", {unit}"
    return message, f"KRL's {key} is {name} here{unit_text} (assigned with ':=')"


def unit_hint(unit: str, number: str | None) -> str | None:
    """The hint for a unit word written after a number (``250 mm``), else ``None``."""
    factor = UNITS.get(unit.upper())
    if factor is None:
        return None
    if number is None:
        return f"{_UNIT_TEXT}: write the number alone"
    try:
        value = float(number)
    except ValueError:
        return f"{_UNIT_TEXT}: write the number alone"
    if factor == 1.0:
        return f"{_UNIT_TEXT}: write {number}"
    irlc_unit = "deg" if unit.upper() == "RAD" else "s" if unit.upper() in ("MS", "MIN") else "mm"
    return f"{_UNIT_TEXT}: {number} {unit} is {_number(value * factor)} ({irlc_unit})"


def percent_hint() -> str:
    return "percentages are plain numbers: SPEED_PTP := 50 means 50 % (no '%' sign)"


def operator_hint(operator: str) -> str | None:
    """Hints for C-like operators: ``==``, ``!=``, ``+=`` …"""
    if operator == "==":
        return "'=' compares and ':=' assigns ('==' is C's)"
    if operator == "!=":
        return "'not equal' is written '<>'"
    if operator in ("+=", "-=", "*=", "/="):
        return f"write x := x {operator[0]} value (there is no '{operator}')"
    return None


def _split_arguments(args: str) -> list[str]:
    """RAPID arguments split at the commas outside brackets; ``\\WObj:=…`` switches dropped."""
    items, depth, start = [], 0, 0
    text = args.split("\\", 1)[0]
    for i, ch in enumerate(text):
        if ch in "([":
            depth += 1
        elif ch in ")]":
            depth -= 1
        elif ch == "," and depth == 0:
            items.append(text[start:i].strip())
            start = i + 1
    items.append(text[start:].strip())
    return [item for item in items if item]


def _number(value: float) -> str:
    return f"{value:.6g}"
