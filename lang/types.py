"""The types of the IRL dialect and their IRDATA names.

Scalars ``INTEGER REAL BOOLEAN CHAR STRING``; geometric ``POSITION ORIENTATION POSE``;
``SIGNAL`` (a digital output, read as BOOLEAN); the seven joint-tuple types with one
value per robot joint; ``ARRAY [lo..hi] OF T``; records. ``ERROR`` stands for an
expression that already produced a diagnostic (it is compatible with everything, so
one mistake gives one message).
"""

from __future__ import annotations

from dataclasses import dataclass

from irlc.lang.irdata_model import JOINT_TUPLE_TYPES as JOINT_TUPLE_TYPES
from irlc.lang.value_ranges import INT_MAX as INT_MAX  # re-exported: T.…
from irlc.lang.value_ranges import INT_MIN as INT_MIN
from irlc.lang.value_ranges import integer_overflow as integer_overflow


@dataclass(frozen=True)
class Type:
    name: str

    def ird(self) -> str:
        """The type's name in IRDATA records."""
        return self.name

    def __str__(self) -> str:
        return self.name

    @property
    def is_numeric(self) -> bool:
        return self.name in ("INTEGER", "REAL")


@dataclass(frozen=True)
class JointTuple(Type):
    n: int = 0  # values (one per joint); 0: any (a cell whose robots differ in joint count)


@dataclass(frozen=True)
class Array(Type):
    lo: int = 0
    hi: int = 0
    elem: Type = None  # type: ignore[assignment]

    def ird(self) -> str:
        return f"ARRAY[{self.lo}..{self.hi}]OF{self.elem.ird()}"

    def __str__(self) -> str:
        return f"ARRAY [{self.lo}..{self.hi}] OF {self.elem}"

    @property
    def length(self) -> int:
        return self.hi - self.lo + 1


@dataclass(frozen=True)
class Record(Type):
    index: int = 0
    fields: tuple[tuple[str, Type], ...] = ()

    def ird(self) -> str:
        return f"RECORD#{self.index}"

    def __str__(self) -> str:
        return self.name

    def field(self, name: str) -> tuple[str, Type] | None:
        key = name.lower()
        return next(((n, t) for n, t in self.fields if n.lower() == key), None)


INTEGER = Type("INTEGER")
REAL = Type("REAL")
BOOLEAN = Type("BOOLEAN")
CHAR = Type("CHAR")
STRING = Type("STRING")
POSITION = Type("POSITION")
ORIENTATION = Type("ORIENTATION")
POSE = Type("POSE")
SIGNAL = Type("SIGNAL")
ERROR = Type("<error>")

SIMPLE = {
    t.name: t for t in (INTEGER, REAL, BOOLEAN, CHAR, STRING, POSITION, ORIENTATION, POSE, SIGNAL)
}


def elements(t: Type) -> int:
    """How many elements a value of ``t`` holds: an ARRAY its length times its element's,
    a RECORD the sum of its fields' (at least 1), anything else 1
    (``value_ranges.MAX_ELEMENTS``)."""
    if isinstance(t, Array):
        return t.length * elements(t.elem)
    if isinstance(t, Record):
        return max(1, sum(elements(ft) for _, ft in t.fields))
    return 1


def value_type(t: Type) -> Type:
    """The type of a variable's value when read (a SIGNAL reads as BOOLEAN)."""
    return BOOLEAN if t == SIGNAL else t


def assignable(target: Type, source: Type) -> bool:
    """May a value of ``source`` be stored where ``target`` is expected?"""
    if ERROR in (target, source) or target == source:
        return True
    if target == REAL and source == INTEGER:
        return True
    if target == STRING and source == CHAR:
        return True
    if target == SIGNAL and source == BOOLEAN:
        return True
    if isinstance(target, Array) and isinstance(source, Array):
        return target.length == source.length and assignable(target.elem, source.elem)
    if isinstance(target, JointTuple) and isinstance(source, JointTuple):
        # a cell of robots with different joint counts: any arity (n = 0), checked where
        # the tuple meets a robot
        return target.name == source.name and 0 in (target.n, source.n)
    return False


def tuple_arity(t: Type) -> int | None:
    """How many items a tuple literal of type ``t`` has (None: not tuple-constructible)."""
    if isinstance(t, JointTuple):
        return t.n
    if t == POSE:
        return 6
    if t == POSITION:
        return 3
    if isinstance(t, Array):
        return t.length
    if isinstance(t, Record):
        return len(t.fields)
    return None


def tuple_items(t: Type) -> list[Type]:
    """The expected type of each item of a tuple literal of type ``t``."""
    if isinstance(t, JointTuple):
        return [REAL] * t.n
    if t == POSE:
        return [REAL] * 6
    if t == POSITION:
        return [REAL] * 3
    if isinstance(t, Array):
        return [t.elem] * t.length
    if isinstance(t, Record):
        return [ft for _, ft in t.fields]
    return []
