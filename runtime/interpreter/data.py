"""The data instructions: variables, system variables, fields and elements, operators,
MAKE and built-in calls (``docs/irdata.md``).

A part of the interpreter (:class:`DataInstructions`): the handlers work on the machine's
operand stack, frames and :class:`MachineState` (:class:`~irlc.runtime.interpreter.context.
Machine`); what a value of a type is, is
:class:`~irlc.runtime.interpreter.datatypes.DataTypes` (``self.types``). A VAR parameter's
cell holds a :class:`Ref` to the caller's cell; ``PUSHL`` / ``POPL`` read and write through
it, ``REFL`` of such a cell passes the same reference on.
"""

from __future__ import annotations

import dataclasses

from irlc.lang.cell import ROBOT_VARIABLES
from irlc.lang.irdata_robots import robot_operand
from irlc.lang.settings import SYSTEM_VARIABLES
from irlc.runtime import values as V
from irlc.runtime.commands import check_setting
from irlc.runtime.errors import RunFailure
from irlc.runtime.interpreter import builtins as B
from irlc.runtime.interpreter.context import Machine
from irlc.runtime.interpreter.datatypes import DataTypes, number
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


class DataInstructions:
    """``PUSHC`` … ``CALLB``; see the module docstring."""

    def __init__(self, machine: Machine):
        self.m = machine
        # the machine's containers (the same objects for the whole run) and its push
        self.stack, self.frames, self.state = machine.stack, machine.frames, machine.state
        self.code = machine.code
        self.push = machine.push
        self.pop_n = machine.pop_n
        self.types: DataTypes | None = None
        self.consts: list = []

    def prepare(self, types: DataTypes) -> None:
        """The code is loaded: its types and constants."""
        self.types, self.consts = types, self.m.consts

    # ------------------------------------------------------------------ variables

    def op_pushc(self, args) -> None:
        self.push(self.consts[args[0]])

    def op_pushg(self, args) -> None:
        v = self.state.globals[args[0]]
        if v is UNSET:
            raise unset_error(self.code.globals[args[0]].name)
        self.push(v)

    def op_popg(self, args) -> None:
        slot = self.code.globals[args[0]]
        v = self.stack.pop()
        self.state.globals[args[0]] = self.types.coerce(v, slot.type, f"variable {slot.name!r}")

    def op_pushl(self, args) -> None:
        frame = self.frames[-1]
        v = frame.cells[args[0]]
        name = frame.slots[args[0]].name
        if isinstance(v, Ref):
            name = v.slot.name
            v = v.cells[v.index]
        if v is UNSET:
            raise unset_error(name)
        self.push(v)

    def op_popl(self, args) -> None:
        frame = self.frames[-1]
        v = self.stack.pop()
        cell = frame.cells[args[0]]
        coerce = self.types.coerce
        if isinstance(cell, Ref):
            cell.cells[cell.index] = coerce(v, cell.slot.type, f"variable {cell.slot.name!r}")
        else:
            slot = frame.slots[args[0]]
            frame.cells[args[0]] = coerce(v, slot.type, f"variable {slot.name!r}")

    def op_refg(self, args) -> None:
        g = args[0]
        self.push(Ref(self.state.globals, g, self.code.globals[g]))

    def op_refl(self, args) -> None:
        frame = self.frames[-1]
        cell = frame.cells[args[0]]
        self.push(
            cell if isinstance(cell, Ref) else Ref(frame.cells, args[0], frame.slots[args[0]])
        )

    def op_pop(self, args) -> None:
        self.stack.pop()

    def op_dup(self, args) -> None:
        self.push(self.stack[-1])

    # ------------------------------------------------------------------ system variables

    def decode_pushsys(self, args: tuple) -> tuple:
        """``PUSHSYS NAME [ROBOT:k]`` → ``(NAME, robot)`` (``None``: not a cell's robot)."""
        robot, rest = robot_operand("PUSHSYS", args)
        return rest[0], robot if self.m.cell else None

    def decode_popsys(self, args: tuple) -> tuple:
        robot, rest = robot_operand("POPSYS", args)
        return rest[0], robot if self.m.cell else None

    def op_pushsys(self, args) -> None:
        name, robot = args
        st = self.state
        m = self.m
        if name in _ACTUAL:
            m.stop_advance(f"line {m.line()} reads {name}")
        if m.cell and name in ROBOT_VARIABLES:  # a robot's own: holder.R_ACT_POSE …
            v = self._robot_variable(name, robot or 0)
        elif name == "R_ACT_POSE":
            v = m.call(m.controller.pose, dataclasses.replace(st.settings))
        elif name == "R_ACT_JOINT":
            q = m.call(m.controller.joints)
            v = JointTuple("MAIN_JOINT", tuple(float(x) for x in q))
        elif name in SETTINGS_FIELDS:
            v = getattr(st.settings, SETTINGS_FIELDS[name])
        else:
            raise B.malformed(f"unknown system variable {name!r}")
        self.push(v)

    def _robot_variable(self, name: str, robot: int) -> object:
        """A cell's robot's ``R_TOOL``, ``R_BASE`` (the machine's), ``R_ACT_POSE``,
        ``R_ACT_JOINT`` (the controller's)."""
        m = self.m
        if name == "R_ACT_POSE":
            return m.call(m.controller.pose, *m.snapshot(), robot)
        if name == "R_ACT_JOINT":
            q = m.call(m.controller.joints, robot)
            return JointTuple("MAIN_JOINT", tuple(float(x) for x in q))
        return getattr(self.state.robots[robot], SETTINGS_FIELDS[name])

    def op_popsys(self, args) -> None:
        name, robot = args
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
        target = self.state.settings
        if self.m.cell and name in ROBOT_VARIABLES:
            target = self.state.robots[robot or 0]
        setattr(target, SETTINGS_FIELDS[name], v)

    # ------------------------------------------------------------------ fields and elements

    def op_getf(self, args) -> None:
        c = self.stack.pop()
        self.push(self.types.get_field(c, args[0]))

    def op_setf(self, args) -> None:
        v = self.stack.pop()
        c = self.stack.pop()
        self.push(self.types.set_field(c, args[0], v))

    def op_geti(self, args) -> None:
        i = self.stack.pop()
        c = self.stack.pop()
        self.push(self.types.get_item(c, i))

    def op_seti(self, args) -> None:
        v = self.stack.pop()
        i = self.stack.pop()
        c = self.stack.pop()
        if isinstance(c, ArrayValue):  # the copy costs its length
            self.m.charge_elements(len(c.items))
        self.push(self.types.set_item(c, i, v))

    # ------------------------------------------------------------------ operators

    def op_binary(self, args) -> None:
        b = self.stack.pop()
        a = self.stack.pop()
        self.push(args[0](a, b))

    def op_neg(self, args) -> None:
        self.push(B.neg(self.stack.pop()))

    def op_not(self, args) -> None:
        self.push(B.logical_not(self.stack.pop()))

    def op_make(self, args) -> None:
        ty, n = args
        items = self.pop_n(n)
        self.push(self.types.make(ty, items))

    def decode_callb(self, args: tuple) -> tuple:
        """``CALLB NAME argc [ROBOT:k]`` → ``(NAME, argc, robot)`` (``FK`` of a cell's
        robot names it; ``None``: code of one robot)."""
        robot, rest = robot_operand("CALLB", args)
        return rest[0], rest[1], robot if self.m.cell else None

    def op_callb(self, args) -> None:
        name, argc, robot = args
        values = tuple(self.pop_n(argc))
        if name == "FK":
            if argc != 1:
                raise B.malformed(f"FK takes 1 argument, got {argc}")
            m = self.m
            joints = self.types.joint_tuple(values[0], "FK", m.robot_joints(robot))
            if m.cell:
                fk = m.call(m.controller.forward, joints, *m.snapshot(), robot or 0)
            else:
                settings = dataclasses.replace(self.state.settings)
                fk = m.call(m.controller.forward, joints, settings)
            self.push(B.checked_value(fk, "FK"))
            return
        self.push(B.call_builtin(name, values))
