"""The IRDATA interpreter (``docs/interpreter.md``): executes compiled code against a
controller. One file per concept:

* :mod:`.machine` — :class:`Interpreter`: decoding, the fetch–dispatch loop, frames and the
  operand stack, control flow, the endless-loop guard; built from the instruction sets
  below, which see it through :mod:`.context` (:class:`~.context.Machine`);
* :mod:`.state` — variable cells, frames, :class:`MachineState` (kept between REPL chunks),
  :class:`ExecutionResult`;
* :mod:`.datatypes` — the program's types at run time (constants, coercion, MAKE, fields
  and elements);
* :mod:`.data` — the data instructions (variables, system variables, operators, built-ins);
* :mod:`.io` — WAIT, WAIT FOR, digital inputs and outputs, WRITE, events;
* :mod:`.motion` — MOVE, RECONFIGURATION and the modal options, handed to the controller.
"""

from irlc.runtime.interpreter.machine import (
    DEFAULT_INSTRUCTION_BUDGET,
    Interpreter,
)
from irlc.runtime.interpreter.state import UNSET, ExecutionResult, MachineState, Ref

__all__ = [
    "DEFAULT_INSTRUCTION_BUDGET",
    "UNSET",
    "ExecutionResult",
    "Interpreter",
    "MachineState",
    "Ref",
]
