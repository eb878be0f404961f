"""The program's data types at run time: building, converting and taking apart values.

One :class:`DataTypes` per code object: it knows the code's RECORD types and the robot's
joints (how many, their names as fields of a joint tuple) and nothing of the machine's
state. Values are immutable (:mod:`irlc.runtime.values`), so ``set_field`` / ``set_item``
build a new value. ARRAY and RECORD variables start with every element :data:`UNSET`
(filled element-wise), SIGNAL outputs FALSE, everything else unset.

Coercion (storing a value in a typed cell): INTEGER → REAL widens, a joint tuple is
retagged (AXIS ↔ MAIN_JOINT …) when its length fits, everything else must match exactly.
"""

from __future__ import annotations

import dataclasses
import math
import re

from irlc.lang import platform
from irlc.lang.irdata import JOINT_TUPLE_TYPES, RecordType, Value
from irlc.runtime import values as V
from irlc.runtime.errors import RunFailure
from irlc.runtime.interpreter import builtins as B
from irlc.runtime.interpreter.state import UNSET
from irlc.runtime.values import ArrayValue, JointTuple, Orientation, Pose, Position, RecordValue

ARRAY_TYPE = re.compile(r"ARRAY\[(-?\d+)\.\.(-?\d+)\]OF(.+)")
_GEOMETRIC = {"POSITION": Position, "ORIENTATION": Orientation, "POSE": Pose}


def number(v: object, what: str) -> float:
    """``v`` as a float; a non-number is malformed code (the checker types operands)."""
    if not B.is_number(v):
        raise B.malformed(f"{what}: expected a number, got {V.type_name(v)}")
    return float(v)


class DataTypes:
    """The types of one code object (see the module docstring)."""

    def __init__(
        self,
        record_types: list[RecordType],
        joint_names: list[str],
        joint_counts: tuple[int, ...] = (),
    ):
        self.record_types = {t.index: t for t in record_types}
        self.joint_count = len(joint_names)
        # a cell's robots may differ in their joint counts: a joint tuple has one of them
        # (checked against its robot where it meets one: :meth:`joint_tuple`'s ``count``)
        self.joint_counts = frozenset(joint_counts or (self.joint_count,))
        self.joint_index = {n.lower(): i for i, n in enumerate(joint_names)}
        self._elements: dict[str, int] = {}  # type → elements (a cache of elements())
        self._counting: set[str] = set()  # the types elements() is inside of

    # ------------------------------------------------------------------ constants and cells

    def constant(self, k: int, v: Value) -> object:
        """Constant ``k`` of the code's table as a value."""
        try:
            return self.from_data(v.type, v.data)
        except (TypeError, ValueError, IndexError) as e:
            raise B.malformed(f"constant {k} ({v.type}): {e}") from None

    def from_data(self, ty: str, data: tuple) -> object:
        if any(isinstance(x, float) and not math.isfinite(x) for x in data):
            raise ValueError("not a finite number")
        if ty == "INTEGER":
            return int(data[0])
        if ty == "REAL":
            return float(data[0])
        if ty in ("BOOLEAN", "SIGNAL"):
            return bool(data[0])
        if ty in ("STRING", "CHAR"):
            return str(data[0])
        if ty == "POSITION" and len(data) == 3:
            return Position(*(float(x) for x in data))
        if ty == "ORIENTATION" and len(data) == 4:
            return V.orientation_from_quat(*(float(x) for x in data))
        if ty == "POSE" and len(data) == 6:
            return V.pose_from_zyx(*data)
        if ty in JOINT_TUPLE_TYPES and len(data) in self.joint_counts:
            return JointTuple(ty, tuple(float(x) for x in data))
        if platform.constant_count(ty) == len(data):  # a platform target (data list)
            return ArrayValue(1, tuple(float(x) for x in data), "REAL")
        raise ValueError(f"{len(data)} value(s) do not make a {ty}")

    def initial(self, ty: str) -> object:
        """The value a fresh cell of type ``ty`` holds (values are immutable, so the items
        of an array share one initial value: O(length) pointers, no per-item work)."""
        if ty == "SIGNAL":
            return False
        m = ARRAY_TYPE.fullmatch(ty)
        if m:
            low, n, elem = self._array_shape(m)
            return ArrayValue(low, (self.initial(elem),) * n, elem)
        if ty.startswith("RECORD#"):
            rt = self.record_type(ty)
            return RecordValue(rt.index, tuple((n, self.initial(t)) for n, t in rt.fields))
        return UNSET

    @staticmethod
    def _array_shape(m: re.Match) -> tuple[int, int, str]:
        """``(low, length, element type)`` of a matched ``ARRAY[lo..hi]OFT``."""
        low, high = int(m.group(1)), int(m.group(2))
        if high < low:
            raise B.malformed(f"empty array type {m.group(0)}")
        return low, high - low + 1, m.group(3)

    def elements(self, ty: str) -> int:
        """How many elements a cell of ``ty`` holds (``lang.types.elements``: an ARRAY its
        length times its element's, a RECORD its fields' sum but at least 1, anything else
        1); a type nested in itself (a hand-written ``.ird``) is malformed."""
        known = self._elements.get(ty)
        if known is not None:
            return known
        if ty in self._counting:
            raise B.malformed(f"type {ty} contains itself")
        self._counting.add(ty)
        try:
            m = ARRAY_TYPE.fullmatch(ty)
            if m:
                _, n, elem = self._array_shape(m)
                count = n * self.elements(elem)
            elif ty.startswith("RECORD#"):
                count = max(1, sum(self.elements(t) for _, t in self.record_type(ty).fields))
            else:
                count = 1
        finally:
            self._counting.discard(ty)
        self._elements[ty] = count
        return count

    def record_type(self, ty: str) -> RecordType:
        rt = self.record_types.get(int(ty[7:])) if ty[7:].isdigit() else None
        if rt is None:
            raise B.malformed(f"unknown record type {ty}")
        return rt

    # ------------------------------------------------------------------ coercion

    def coerce(self, v: object, ty: str, what: str) -> object:
        """``v`` as a value of type ``ty`` (INTEGER → REAL, joint tuples retagged)."""
        out = self._coerced(v, ty)
        if out is UNSET:
            raise B.malformed(f"cannot store a {V.type_name(v)} in {what} of type {ty}")
        return out

    def _coerced(self, v: object, ty: str) -> object:
        if ty == "REAL":
            return float(v) if B.is_number(v) else UNSET
        if ty == "INTEGER":
            return v if isinstance(v, int) and not isinstance(v, bool) else UNSET
        if ty in ("BOOLEAN", "SIGNAL"):
            return v if isinstance(v, bool) else UNSET
        if ty in ("STRING", "CHAR"):
            ok = isinstance(v, str) and (ty == "STRING" or len(v) == 1)
            return v if ok else UNSET
        if ty in _GEOMETRIC:
            return v if isinstance(v, _GEOMETRIC[ty]) else UNSET
        if ty in JOINT_TUPLE_TYPES:
            if not isinstance(v, JointTuple) or len(v.values) not in self.joint_counts:
                return UNSET
            return v if v.type == ty else JointTuple(ty, v.values)
        m = ARRAY_TYPE.fullmatch(ty)
        if m:
            return self._coerced_array(v, int(m.group(1)), int(m.group(2)), m.group(3))
        if ty.startswith("RECORD#"):
            rt = self.record_type(ty)
            if not isinstance(v, RecordValue) or v.type_index != rt.index:
                return UNSET
            return self._coerced_fields(v, rt)
        raise B.malformed(f"unknown type {ty}")

    def _coerced_array(self, v: object, low: int, high: int, elem: str) -> object:
        if not isinstance(v, ArrayValue) or v.low != low or len(v.items) != high - low + 1:
            return UNSET
        if v.elem == elem:  # its items were stored as ``elem`` (initial, MAKE, set_item)
            return v
        items = tuple(x if x is UNSET else self._coerced(x, elem) for x in v.items)
        if any(x is UNSET and y is not UNSET for x, y in zip(items, v.items, strict=True)):
            return UNSET
        return ArrayValue(low, items, elem)

    def _coerced_fields(self, v: RecordValue, rt: RecordType) -> object:
        if len(v.fields) != len(rt.fields):
            return UNSET
        fields = []
        for (name, x), (_, fty) in zip(v.fields, rt.fields, strict=True):
            y = x if x is UNSET else self._coerced(x, fty)
            if y is UNSET and x is not UNSET:
                return UNSET
            fields.append((name, y))
        return RecordValue(v.type_index, tuple(fields))

    def joint_tuple(self, v: object, what: str, robot: tuple[str, int] | None = None) -> JointTuple:
        """``v`` if it is a joint tuple of the code's joint count; with ``robot``
        (``(name, joints)``, a cell's robot it is used with) of that robot's count — a
        run-time failure naming the robot (a variable's length is known only here)."""
        if robot is not None and isinstance(v, JointTuple):
            name, count = robot
            if len(v.values) != count:
                raise RunFailure(
                    f"{what} for robot {name} needs {count} values, got a {v.type} of "
                    f"{len(v.values)}"
                )
            return v
        if not isinstance(v, JointTuple) or len(v.values) != self.joint_count:
            raise B.malformed(f"{what}: expected a joint tuple of {self.joint_count} values,"
                              f" got {V.type_name(v)}")  # fmt: skip
        return v

    def main_joint(self, v: object, what: str, robot: tuple[str, int] | None = None) -> JointTuple:
        j = self.joint_tuple(v, what, robot)
        return j if j.type == "MAIN_JOINT" else JointTuple("MAIN_JOINT", j.values)

    # ------------------------------------------------------------------ building (MAKE)

    def make(self, ty: str, items: list) -> object:
        """A value of type ``ty`` from its ``items`` (the ``MAKE`` instruction)."""
        n = len(items)
        if ty == "POSE" and n == 6:
            return V.pose_from_zyx(*(number(x, "POSE") for x in items))
        if ty == "POSE" and n == 2:
            return Pose(self.coerce(items[0], "POSITION", "POSE"),
                        self.coerce(items[1], "ORIENTATION", "POSE"))  # fmt: skip
        if ty == "POSITION" and n == 3:
            return Position(*(number(x, "POSITION") for x in items))
        if ty == "ORIENTATION" and n == 4:
            return B.call_builtin("ORIQUAT", tuple(items))
        if ty in JOINT_TUPLE_TYPES and n in self.joint_counts:
            return JointTuple(ty, tuple(number(x, ty) for x in items))
        m = ARRAY_TYPE.fullmatch(ty)
        if m and n == int(m.group(2)) - int(m.group(1)) + 1:
            elem = m.group(3)
            return ArrayValue(
                int(m.group(1)), tuple(self.coerce(x, elem, "element") for x in items), elem
            )
        if ty.startswith("RECORD#"):
            rt = self.record_type(ty)
            if n == len(rt.fields):
                return RecordValue(rt.index, tuple(
                    (name, self.coerce(x, fty, f"field {name!r}"))
                    for (name, fty), x in zip(rt.fields, items, strict=True)))  # fmt: skip
        if n == 1 and ty in ("INTEGER", "REAL", "BOOLEAN", "CHAR", "STRING"):
            return self.coerce(items[0], ty, ty)
        raise B.malformed(f"MAKE {ty} from {n} values")

    # ------------------------------------------------------------------ fields and elements

    def get_field(self, c: object, name: str) -> object:
        key = name.lower()
        if isinstance(c, RecordValue):
            for fname, v in c.fields:
                if fname.lower() == key:
                    if v is UNSET:
                        raise RunFailure(f"field '{fname}' is used before it has a value")
                    return v
        elif isinstance(c, Position) and key in ("x", "y", "z"):
            return getattr(c, key)
        elif isinstance(c, Pose) and key in ("x", "y", "z", "pos", "ori"):
            return c.ori if key == "ori" else (c.pos if key == "pos" else getattr(c.pos, key))
        elif isinstance(c, JointTuple) and key in self.joint_index:
            return c.values[self._joint(c, key, name)]
        raise B.malformed(f"a {V.type_name(c)} has no field {name!r}")

    def _joint(self, c: JointTuple, key: str, name: str) -> int:
        """The index of joint field ``name`` in ``c`` (a cell's shorter robot's tuple has
        no field for the longer robot's last joints: a run-time failure)."""
        j = self.joint_index[key]
        if j >= len(c.values):
            raise RunFailure(f"a {c.type} of {len(c.values)} values has no joint {name}")
        return j

    def set_field(self, c: object, name: str, v: object) -> object:
        key = name.lower()
        if isinstance(c, RecordValue):
            rt = self.record_types.get(c.type_index)
            for k, (fname, fty) in enumerate(rt.fields if rt else ()):
                if fname.lower() == key:
                    fields = list(c.fields)
                    fields[k] = (fname, self.coerce(v, fty, f"field {fname!r}"))
                    return RecordValue(c.type_index, tuple(fields))
        elif isinstance(c, Position) and key in ("x", "y", "z"):
            return dataclasses.replace(c, **{key: number(v, f"field {name}")})
        elif isinstance(c, Pose) and key in ("x", "y", "z"):
            pos = dataclasses.replace(c.pos, **{key: number(v, f"field {name}")})
            return Pose(pos, c.ori)
        elif isinstance(c, Pose) and key == "pos":
            return Pose(self.coerce(v, "POSITION", "field pos"), c.ori)
        elif isinstance(c, Pose) and key == "ori":
            return Pose(c.pos, self.coerce(v, "ORIENTATION", "field ori"))
        elif isinstance(c, JointTuple) and key in self.joint_index:
            values = list(c.values)
            values[self._joint(c, key, name)] = number(v, f"joint {name}")
            return JointTuple(c.type, tuple(values))
        raise B.malformed(f"a {V.type_name(c)} has no field {name!r}")

    @staticmethod
    def index(c: object, i: object) -> int:
        """0-based position of index ``i`` in ``c`` (checked against the bounds)."""
        if not isinstance(i, int) or isinstance(i, bool):
            raise B.malformed(f"an index must be an INTEGER, got {V.type_name(i)}")
        if isinstance(c, ArrayValue):
            low, n = c.low, len(c.items)
        elif isinstance(c, JointTuple):
            low, n = 1, len(c.values)
        else:
            raise B.malformed(f"a {V.type_name(c)} cannot be indexed")
        if not low <= i < low + n:
            raise RunFailure(f"index {i} is out of range {low}..{low + n - 1}")
        return i - low

    def get_item(self, c: object, i: object) -> object:
        k = self.index(c, i)
        if isinstance(c, JointTuple):
            return c.values[k]
        v = c.items[k]
        if v is UNSET:
            raise RunFailure(f"element [{i}] is used before it has a value")
        return v

    def set_item(self, c: object, i: object, v: object) -> object:
        k = self.index(c, i)
        if isinstance(c, JointTuple):
            values = list(c.values)
            values[k] = number(v, f"joint [{i}]")
            return JointTuple(c.type, tuple(values))
        if c.elem is not None:
            v = self.coerce(v, c.elem, f"element [{i}]")
        items = list(c.items)
        items[k] = v
        return ArrayValue(c.low, tuple(items), c.elem)
