"""IRDATA code: the in-memory model, the writer and the reader (assembler).

The format is documented in ``docs/irdata.md``. ``write_code(read_code(text)) == text``
for every text the writer produced (byte-identical round trip).

This module is the one import point; each concept has its own module:

- :mod:`irlc.lang.irdata_model`: the format's words and the code tables (``Code``, …);
- :mod:`irlc.lang.irdata_writer`: ``Code`` → ``.ird`` text (:func:`write_code`);
- :mod:`irlc.lang.irdata_reader`: ``.ird`` text → ``Code`` (:func:`read_code`);
- :mod:`irlc.lang.value_ranges`: the INTEGER and STRING ranges and their messages;
- :mod:`irlc.lang.geometry_range`: the obstacle fields and the physical range of geometry.
"""

from __future__ import annotations

from irlc.lang.geometry_range import (
    GEOMETRY_MAX_MM,
    GEOMETRY_MIN_LENGTH_MM,
    OBSTACLE_KEYS,
    OBSTACLE_KINDS,
    geometry_problem,
    obstacle_field_problem,
    obstacle_range_problem,
)
from irlc.lang.irdata_model import (
    FORMAT_VERSION,
    JOINT_TUPLE_TYPES,
    MAGIC,
    MODAL_OPTIONS,
    MOVE_KINDS,
    OPCODES,
    SYSTEM_VARIABLES,
    Code,
    Instruction,
    ObstacleDef,
    Operand,
    RecordType,
    Routine,
    Slot,
    Target,
    Value,
)
from irlc.lang.irdata_reader import read_code
from irlc.lang.irdata_writer import format_value, write_code
from irlc.lang.value_ranges import (
    INT_MAX,
    INT_MIN,
    MAX_STRING,
    integer_overflow,
    parse_integer,
    string_too_long,
)

__all__ = [
    "FORMAT_VERSION",
    "GEOMETRY_MAX_MM",
    "GEOMETRY_MIN_LENGTH_MM",
    "INT_MAX",
    "INT_MIN",
    "JOINT_TUPLE_TYPES",
    "MAGIC",
    "MAX_STRING",
    "MODAL_OPTIONS",
    "MOVE_KINDS",
    "OBSTACLE_KEYS",
    "OBSTACLE_KINDS",
    "OPCODES",
    "SYSTEM_VARIABLES",
    "Code",
    "Instruction",
    "ObstacleDef",
    "Operand",
    "RecordType",
    "Routine",
    "Slot",
    "Target",
    "Value",
    "format_value",
    "geometry_problem",
    "integer_overflow",
    "obstacle_field_problem",
    "obstacle_range_problem",
    "parse_integer",
    "read_code",
    "string_too_long",
    "write_code",
]
