"""The data instructions: variables, system variables, fields and elements, operators,
MAKE and built-in calls (``docs/irdata.md``).

A mixin of :class:`~irlc.runtime.interpreter.machine.Interpreter`: the handlers work on the
machine's operand stack, frames and :class:`MachineState`; what a value of a type is, is
:class:`~irlc.runtime.interpreter.datatypes.DataTypes` (``self.types``). A VAR parameter's
cell holds a :class:`Ref` to the caller's cell; ``PUSHL`` / ``POPL`` read and write through
it, ``REFL`` of such a cell passes the same reference on.
"""

from __future__ import annotations

import dataclasses

from irlc.lang.settings import SYSTEM_VARIABLES
from irlc.runtime import values as V
from irlc.runtime.commands import check_setting
from irlc.runtime.errors import RunFailure
from irlc.runtime.interpreter import builtins as B
from irlc.runtime.interpreter.datatypes import number
from irlc.runtime.interpreter.state import UNSET, Ref
from irlc.runtime.values import ArrayValue, JointTuple, Pose

SETTINGS_FIELDS = {  # system variable → Settings field (rows: lang/settings.py)
    name: v.field for name, v in SYSTEM_VARIABLES.items() if v.field is not None
}
# Work proportional to an array's length (copying it to store one element; the cells of a
# call's large locals, machine._hold) is charged to the endless-loop guard: one instruction
# per ELEMENTS_PER_STEP elements (about the same CPU time), so a loop over a large array
# is stopped as soon as one over a small one.
ELEMENTS_PER_STEP = 128
_ACTUAL = ("R_ACT_POSE", "R_ACT_JOINT")  # read from the controller: stop the advance run


def unset_error(name: str) -> RunFailure:
    return RunFailure(f"variable '{name}' is used before it has a value")


class DataOps:
    """``PUSHC`` … ``CALLB``; see the module docstring."""

    # ------------------------------------------------------------------ variables

    def _op_pushc(self, args) -> None:
        self._push(self._consts[args[0]])

    def _op_pushg(self, args) -> None:
        v = self.state.globals[args[0]]
        if v is UNSET:
            raise unset_error(self.code.globals[args[0]].name)
        self._push(v)

    def _op_popg(self, args) -> None:
        slot = self.code.globals[args[0]]
        v = self.stack.pop()
        self.state.globals[args[0]] = self.types.coerce(v, slot.type, f"variable {slot.name!r}")

    def _op_pushl(self, args) -> None:
        frame = self.frames[-1]
        v = frame.cells[args[0]]
        name = frame.slots[args[0]].name
        if isinstance(v, Ref):
            name = v.slot.name
            v = v.cells[v.index]
        if v is UNSET:
            raise unset_error(name)
        self._push(v)

    def _op_popl(self, args) -> None:
        frame = self.frames[-1]
        v = self.stack.pop()
        cell = frame.cells[args[0]]
        coerce = self.types.coerce
        if isinstance(cell, Ref):
            cell.cells[cell.index] = coerce(v, cell.slot.type, f"variable {cell.slot.name!r}")
        else:
            slot = frame.slots[args[0]]
            frame.cells[args[0]] = coerce(v, slot.type, f"variable {slot.name!r}")

    def _op_refg(self, args) -> None:
        g = args[0]
        self._push(Ref(self.state.globals, g, self.code.globals[g]))

    def _op_refl(self, args) -> None:
        frame = self.frames[-1]
        cell = frame.cells[args[0]]
        self._push(
            cell if isinstance(cell, Ref) else Ref(frame.cells, args[0], frame.slots[args[0]])
        )

    def _op_pop(self, args) -> None:
        self.stack.pop()

    def _op_dup(self, args) -> None:
        self._push(self.stack[-1])

    # ------------------------------------------------------------------ system variables

    def _op_pushsys(self, args) -> None:
        name = args[0]
        st = self.state
        if name in _ACTUAL:
            self._stop_advance(f"line {self._line()} reads {name}")
        if name == "R_ACT_POSE":
            v = self._ctl(self.controller.pose, dataclasses.replace(st.settings))
        elif name == "R_ACT_JOINT":
            q = self._ctl(self.controller.joints)
            v = JointTuple("MAIN_JOINT", tuple(float(x) for x in q))
        elif name in SETTINGS_FIELDS:
            v = getattr(st.settings, SETTINGS_FIELDS[name])
        else:
            raise B.malformed(f"unknown system variable {name!r}")
        self._push(v)

    def _op_popsys(self, args) -> None:
        name = args[0]
        v = self.stack.pop()
        if name not in SETTINGS_FIELDS:
            raise B.malformed(f"system variable {name!r} cannot be assigned")
        if name in ("R_TOOL", "R_BASE"):
            if not isinstance(v, Pose):
                raise B.malformed(f"{name} needs a POSE, got {V.type_name(v)}")
        elif SYSTEM_VARIABLES[name].type_name == "STRING":  # R_PROFILE: a word, any case
            if not isinstance(v, str):
                raise B.malformed(f"{name} needs a STRING, got {V.type_name(v)}")
            v = check_setting(SETTINGS_FIELDS[name], v, name).upper()
        else:
            v = check_setting(SETTINGS_FIELDS[name], number(v, name), name)
        if SETTINGS_FIELDS[name] == "clearance" and v > 0:  # interim (issue 26)
            raise RunFailure(f"{name} := {v:g}: this runtime cannot keep a clearance yet")
        setattr(self.state.settings, SETTINGS_FIELDS[name], v)

    # ------------------------------------------------------------------ fields and elements

    def _op_getf(self, args) -> None:
        c = self.stack.pop()
        self._push(self.types.get_field(c, args[0]))

    def _op_setf(self, args) -> None:
        v = self.stack.pop()
        c = self.stack.pop()
        self._push(self.types.set_field(c, args[0], v))

    def _op_geti(self, args) -> None:
        i = self.stack.pop()
        c = self.stack.pop()
        self._push(self.types.get_item(c, i))

    def _op_seti(self, args) -> None:
        v = self.stack.pop()
        i = self.stack.pop()
        c = self.stack.pop()
        if isinstance(c, ArrayValue):  # the copy costs its length
            self._charge_elements(len(c.items))
        self._push(self.types.set_item(c, i, v))

    # ------------------------------------------------------------------ operators

    def _op_binary(self, args) -> None:
        b = self.stack.pop()
        a = self.stack.pop()
        self._push(args[0](a, b))

    def _op_neg(self, args) -> None:
        self._push(B.neg(self.stack.pop()))

    def _op_not(self, args) -> None:
        self._push(B.logical_not(self.stack.pop()))

    def _op_make(self, args) -> None:
        ty, n = args
        items = self._pop_n(n)
        self._push(self.types.make(ty, items))

    def _op_callb(self, args) -> None:
        name, argc = args
        values = tuple(self._pop_n(argc))
        if name == "FK":
            if argc != 1:
                raise B.malformed(f"FK takes 1 argument, got {argc}")
            joints = self.types.joint_tuple(values[0], "FK")
            settings = dataclasses.replace(self.state.settings)
            self._push(B.checked_value(self._ctl(self.controller.forward, joints, settings), "FK"))
            return
        self._push(B.call_builtin(name, values))
