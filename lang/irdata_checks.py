"""Checks of an ``.ird`` file's header tables that the record grammar cannot make
(``docs/irdata.md``): every type word names a type (a RECORD type that exists, an ARRAY
with bounds in order and a bounded number of cells), record types do not contain
themselves, constants have the shape of their type, obstacles have their kind's fields in
the physical range, input timelines run forward. Each problem is reported by
:mod:`irlc.lang.irdata_reader` at the record's line, so a hand-written or corrupted file
fails when it is read, not half-way through a run."""

from __future__ import annotations

import math
import re

from irlc.lang import platform
from irlc.lang.geometry_range import OBSTACLE_KEYS, obstacle_field_problem
from irlc.lang.irdata_model import (
    JOINT_TUPLE_TYPES,
    VALUE_TYPES,
    ObstacleDef,
    Value,
    shown_word,
)

SCALAR_TYPES = (*VALUE_TYPES, "SIGNAL")
MAX_CELLS = 1_000_000
"""The most cells one variable of an ``.ird`` file may have (an array's elements, nested
arrays and records counted through): the compiler's largest array (``MAX_ARRAY``,
lang/checker/declarations.py). A bigger one would fill the memory before the run starts."""
_ARRAY = re.compile(r"ARRAY\[(-?[0-9]{1,19})\.\.(-?[0-9]{1,19})\]OF(.+)")
_RECORD = re.compile(r"RECORD#([0-9]{1,9})")
_CONST_SIZES = {"POSITION": 3, "ORIENTATION": 4, "POSE": 6}


class TypeTable:
    """The record types of one code (``TYPE`` records, by index) and the cells per type."""

    def __init__(self, fields: dict[int, tuple[tuple[str, str], ...]]):
        self.fields = fields
        self._cells: dict[str, int | str] = {}

    def problem(self, ty: str, *, signal: bool = False) -> str | None:
        """Why ``ty`` is not a type of this code (``signal``: SIGNAL allowed), else None."""
        cells = self.cells(ty, ())
        if isinstance(cells, str):
            return cells
        if ty == "SIGNAL" and not signal:
            return "SIGNAL can only be the type of a global variable"
        return None

    def cells(self, ty: str, seen: tuple[int, ...]) -> int | str:
        """The number of cells of ``ty`` (a scalar: 1), or why it is not a type."""
        if ty in self._cells:
            return self._cells[ty]
        out = self._count(ty, seen)
        if isinstance(out, int) and out > MAX_CELLS:
            out = f"type {shown_word(ty)} has {out} cells (at most {MAX_CELLS:,})"
        self._cells[ty] = out
        return out

    def _count(self, ty: str, seen: tuple[int, ...]) -> int | str:
        if ty in SCALAR_TYPES or ty in JOINT_TUPLE_TYPES:
            return 1
        if m := _ARRAY.fullmatch(ty):
            low, high = int(m.group(1)), int(m.group(2))
            if high < low:
                return f"array type {shown_word(ty)}: the upper bound is below the lower"
            if high - low + 1 > MAX_CELLS:
                return f"array type {shown_word(ty)} has more than {MAX_CELLS:,} elements"
            if m.group(3) == "SIGNAL":
                return "an array of SIGNAL is not a type"
            elem = self.cells(m.group(3), seen)
            return elem if isinstance(elem, str) else elem * (high - low + 1)
        if m := _RECORD.fullmatch(ty):
            k = int(m.group(1))
            if k not in self.fields:
                return f"unknown record type {shown_word(ty)}"
            if k in seen:
                return f"record type {ty} contains itself"
            total = 0
            for _, field_type in self.fields[k]:
                if field_type == "SIGNAL":
                    return "a record field of type SIGNAL is not a type"
                n = self.cells(field_type, (*seen, k))
                if isinstance(n, str):
                    return n
                total += n
            return max(total, 1)
        return f"unknown type {shown_word(ty)}"


def const_problem(value: Value, joint_counts: tuple[int, ...]) -> str | None:
    """Why a ``CONST`` value does not have the shape of its type, else None (a joint
    tuple has one value per joint of a robot of the code: one of ``joint_counts``)."""
    ty, data = value.type, value.data
    if ty == "CHAR":
        return None if len(data[0]) == 1 else "CHAR: expected one character"
    if ty in ("STRING", "BOOLEAN", "INTEGER"):
        return None
    if ty == "REAL":
        return None if len(data) == 1 else f"REAL: expected one number, got {len(data)}"
    k = platform.constant_count(ty)
    if k is not None:  # a platform target (a data list's [platform]): k numbers
        return None if len(data) == k else f"{ty}: expected {k} numbers, got {len(data)}"
    if ty in JOINT_TUPLE_TYPES:
        if len(data) in joint_counts or not joint_counts:
            return None
        sizes = " or ".join(str(n) for n in joint_counts)
        return f"{ty}: expected {sizes} numbers, got {len(data)}"
    size = _CONST_SIZES.get(ty)
    if size is None:
        return f"a constant cannot be of type {shown_word(ty)}"
    if len(data) != size:
        return f"{ty}: expected {size} numbers, got {len(data)}"
    if ty == "ORIENTATION" and math.sqrt(sum(x * x for x in data)) < 1e-12:
        return "ORIENTATION: the quaternion (0, 0, 0, 0) is not a rotation"
    return None


def obstacle_problem(o: ObstacleDef) -> str | None:
    """Why an ``OBSTACLE`` record is not a valid obstacle of its kind (the data-list rule:
    :data:`OBSTACLE_KEYS`, :func:`obstacle_field_problem`), else None."""
    spec = OBSTACLE_KEYS.get(o.kind)
    if spec is None:
        return f"unknown kind {shown_word(o.kind)} (kinds: {', '.join(OBSTACLE_KEYS)})"
    sizes = {k: n for k, n, _ in spec}
    keys = [k for k, _ in o.fields]
    for key, nums in o.fields:
        if key not in sizes:
            return f"unknown key {shown_word(key)} for a {o.kind}"
        if keys.count(key) > 1:
            return f"key '{key}' given twice"
        if len(nums) != sizes[key]:
            return f"'{key}' needs {sizes[key]} number(s), got {len(nums)}"
        if key == "radius" and nums[0] <= 0:
            return f"'radius' must be positive, got {nums[0]:g}"
        if problem := obstacle_field_problem(key, nums):
            return f"'{key}': {problem}"
    missing = [k for k, _, required in spec if required and k not in keys]
    return f"a {o.kind} needs '{missing[0]}'" if missing else None


def timeline_problem(events: list[tuple[float, bool]]) -> str | None:
    """Why an ``INPUT`` timeline is not valid (times ≥ 0, not decreasing), else None."""
    for k, (t, _) in enumerate(events):
        if t < 0:
            return f"event times must be >= 0, got {t:g}"
        if k and t < events[k - 1][0]:
            return f"event times must not decrease ({events[k - 1][0]:g} then {t:g})"
    return None
