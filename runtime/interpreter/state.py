"""What the IRDATA machine holds: variable cells, frames, and the state kept between runs.

A variable cell holds a value (:mod:`irlc.runtime.values`), :data:`UNSET` before its first
assignment, or — for a VAR parameter — a :class:`Ref` to the caller's cell. A frame holds
the cells of one routine activation (parameters, then locals, numbered by slot index).
:class:`MachineState` is what carries over from one run to the next (the REPL's chunks).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from irlc.lang.errors import IrlcError
from irlc.lang.irdata import Routine, Slot
from irlc.runtime.commands import ModalOptions, Settings
from irlc.runtime.errors import RunFailure
from irlc.runtime.outputs.digital_io import Outputs
from irlc.runtime.values import IDENTITY, Pose, Position


class _Unset:
    __slots__ = ()

    def __repr__(self) -> str:
        return "<unset>"


UNSET = _Unset()


class Ref:
    """A reference to a variable cell (argument of a VAR parameter)."""

    __slots__ = ("cells", "index", "slot")

    def __init__(self, cells: list, index: int, slot: Slot):
        self.cells = cells
        self.index = index
        self.slot = slot


def _identity() -> Pose:
    return Pose(Position(0.0, 0.0, 0.0), IDENTITY)


@dataclass
class RobotContext:
    """A cell's robot in the machine: its own system variables (``holder.R_TOOL``,
    ``holder.R_BASE``: lang/cell.py's ``ROBOT_VARIABLES``) and the redundancy options
    switched on for it (``JOINTLIMIT … FOR holder``)."""

    tool: Pose = field(default_factory=_identity)
    base: Pose = field(default_factory=_identity)
    options: ModalOptions = field(default_factory=ModalOptions)


@dataclass
class MachineState:
    """What persists between runs of successive code chunks (REPL). ``robots``: a cell's
    robots (empty for code of one robot, whose tool, base and options are ``settings``'
    and ``options``)."""

    globals: list = field(default_factory=list)
    global_slots: list[Slot] = field(default_factory=list)
    settings: Settings = field(default_factory=Settings)
    options: ModalOptions = field(default_factory=ModalOptions)
    events: list[dict] = field(default_factory=list)
    output: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    input_clock: float = 0.0  # s; input values are read at max(controller.time, this)
    outputs: Outputs = field(default_factory=Outputs)  # OUT[n] switches (digital_io.py)
    robots: list[RobotContext] = field(default_factory=list)  # a cell's, in ROBOT:k order

    def value(self, name: str) -> object | None:
        """The value of global ``name`` (case-insensitive); None when unknown or unset."""
        key = name.lower()
        for slot, v in zip(self.global_slots, self.globals, strict=False):
            if slot.name.lower() == key:
                return None if v is UNSET else v
        return None


@dataclass
class ExecutionResult:
    status: str  # "ok" (END) | "halted" (HALT) | "failed" (error is set)
    output: list[str]
    events: list[dict]
    warnings: list[str]
    error: RunFailure | None
    state: MachineState
    instructions: int

    @property
    def ok(self) -> bool:
        return self.error is None


@dataclass
class Frame:
    """One routine activation: its cells, where to return, and the operand stack's height
    at the call (restored on return)."""

    routine: Routine
    cells: list
    slots: list[Slot]
    return_pc: int
    stack_base: int


class Finished(IrlcError):
    """END, HALT or the MAIN routine's RET: the run stops with ``status``."""

    def __init__(self, status: str):
        self.status = status


class ControllerError(IrlcError):
    """A non-RunFailure exception raised by the controller: re-raised unchanged."""

    def __init__(self, original: BaseException):
        self.original = original
