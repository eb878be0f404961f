"""What an instruction set sees of the IRDATA machine (:class:`Machine`).

The interpreter is built from parts: the machine itself (:mod:`.machine`: decoding, the
dispatch loop, frames and the operand stack, control flow, the endless-loop guard) and
one instruction set per concept (:mod:`.data`, :mod:`.io`, :mod:`.motion`), each a class
whose ``op_<name>`` methods handle the instructions of its concept. A part is given the
machine and uses only this interface.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

from irlc.lang.irdata import Code
from irlc.runtime.commands import Controller, ModalOptions
from irlc.runtime.interpreter.datatypes import DataTypes
from irlc.runtime.interpreter.state import Frame, MachineState


class Machine(Protocol):
    """The machine as its instruction sets see it."""

    code: Code
    controller: Controller
    state: MachineState  # globals, settings, options, events … (kept between REPL chunks)
    types: DataTypes | None  # the program's types (once the code is loaded)
    consts: list  # the code's constants as values (once the code is loaded)
    stack: list  # the operand stack
    frames: list[Frame]  # the active routine calls
    pc: int  # the next instruction
    cur: int  # the instruction being executed
    wait_timeout: float  # s, WAIT FOR's time-out
    cell: bool  # several robots: the controller is a CellController (commands.py)

    def push(self, v: object) -> None: ...

    def pop_n(self, n: int) -> list: ...

    def condition(self, what: str) -> bool: ...

    def line(self) -> int: ...

    def call_site(self) -> tuple[str, int] | None: ...

    def time(self) -> float: ...

    def call(self, fn: Callable, *args, **kwargs): ...

    def snapshot(self) -> tuple: ...

    def robot_options(self, robot: int | None) -> ModalOptions: ...

    def robot_joints(self, robot: int | None) -> tuple[str, int] | None: ...

    def stop_advance(self, why: str) -> None: ...

    def charge_elements(self, n: int) -> None: ...

    def moved(self) -> None: ...

    def waited(self, t_before: float) -> None: ...
