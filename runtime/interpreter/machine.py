"""The IRDATA machine: executes compiled code (``docs/irdata.md``) against a controller.

A stack machine with one operand stack and a stack of frames. Globals live in the
:class:`MachineState`; a frame holds the cells of one routine activation (parameters,
then locals, numbered by their slot index). This module is the machine itself: decoding
the instructions into handlers once, the fetch–dispatch loop, frames and the operand stack,
control flow, and the endless-loop guard. The other instructions are handled by parts
beside it, one concept each, that see the machine through the small interface of
:class:`~irlc.runtime.interpreter.context.Machine`: :class:`~.data.DataInstructions`
(variables, fields, operators, built-ins), :class:`~.io.IoInstructions` (WAIT, inputs
and outputs, WRITE, events) and :class:`~.motion.MotionInstructions` (MOVE,
RECONFIGURATION, the modal options); what a value of a type is, is :mod:`.datatypes`.
An instruction ``OP`` is handled by the method ``op_op`` of the machine or of a part;
an optional ``decode_op`` beside it turns its operands into the handler's arguments
once, when the code is loaded.

Values are immutable (:mod:`irlc.runtime.values`), so pass-by-value needs no copy and
``SETF`` / ``SETI`` build a new value. Variables start *unset* (reading one is a run-time
error naming it), except ARRAY and RECORD variables, whose elements start unset one by one
(so they can be filled element-wise), and SIGNAL outputs, which start FALSE.

Motion, RECONFIGURATION and WAIT go to the :class:`~irlc.runtime.commands.Controller`
with a snapshot of the current :class:`Settings` (system variables) and
:class:`ModalOptions` (the redundancy options). Simulated time is the controller's.

Run-time errors are :class:`RunFailure` with the instruction's source line and the
simulated time. :meth:`Interpreter.run` raises them (``run(check=False)`` returns an
:class:`ExecutionResult` with ``status == "failed"`` and ``error`` set instead); the output
and events up to the failure are kept either way (``interpreter.result``, ``state``).
Code that would make Python fail (stack underflow, wrong operand types in a hand-written
``.ird``) is reported as malformed code.

Incremental execution (the REPL): each entered chunk is compiled as a whole program
whose declarations are the accumulated ones (same order, so the same global slot
indices) and whose main code is only the new statements. Run it with the state of the
previous chunk::

    first = Interpreter(code1, controller).run()
    second = Interpreter(code2, controller, state=first.state).run()

Globals, system variables (Settings), modal options, events, output and the simulated
input clock carry over; new globals (a longer ``code.globals``) are appended unset. A
global whose name or type changed at the same slot index is an error (the chunk does not
extend the previous declarations). ``ExecutionResult.output`` / ``events`` hold only this
run's; ``state.output`` / ``state.events`` all of them. A line left open by WRITE is
flushed at the end of every run.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

from irlc.lang.irdata import Code, Routine, Slot, Target
from irlc.lang.value_ranges import MAX_LIVE_ELEMENTS
from irlc.runtime import values as V
from irlc.runtime.commands import Controller, ModalOptions, Settings
from irlc.runtime.errors import RunFailure
from irlc.runtime.interpreter import builtins as B
from irlc.runtime.interpreter.data import ELEMENTS_PER_STEP, DataInstructions
from irlc.runtime.interpreter.datatypes import DataTypes
from irlc.runtime.interpreter.io import IoInstructions
from irlc.runtime.interpreter.motion import MotionInstructions
from irlc.runtime.interpreter.state import (
    ControllerError,
    ExecutionResult,
    Finished,
    Frame,
    MachineState,
    Ref,
    RobotContext,
)

# The endless-loop guard: at most this many instructions without motion or waiting (about
# 0.3 s of CPython); a motion statement that does not move (its target is where the robot
# is) counts as STILL_MOTION_COST (planning a motion costs what ~250 instructions do), so a
# loop that only "moves" in place is caught as fast. Waiting advances simulated time like
# motion and restarts the count: a loop of WAITs is bounded by the run's cycle and time
# budgets (each recorded cycle counts), not taken for an endless loop (a valid
# FOR i := 1 TO 3600 DO WAIT 1 SEC; ENDFOR; was stopped at t = 200 s as "endless loop?").
# Users raise it: --instruction-budget.
DEFAULT_INSTRUCTION_BUDGET = 500_000
STILL_MOTION_COST = 250
# A run executes at most RUN_BUDGETS instruction budgets in all (20 M instructions by default,
# ≈ 10–25 s of CPython): motion restarts the guard's count, so without this a loop with a
# short motion and 400,000 instructions per pass would run for hours within the cycle budget.
RUN_BUDGETS = 40
MAX_CALL_DEPTH = 10_000
MAX_STACK = 1_000_000


def _copied(options: ModalOptions) -> ModalOptions:
    return dataclasses.replace(options, frozen=dict(options.frozen))


class Interpreter:
    """Executes one :class:`Code` against ``controller``; see the module docstring. The
    machine of the parts (:class:`~irlc.runtime.interpreter.context.Machine`)."""

    def __init__(
        self,
        code: Code,
        controller: Controller,
        *,
        settings: Settings | None = None,
        output: Callable[[str], None] | list[str] | None = None,
        wait_timeout: float = 60.0,
        instruction_budget: int = DEFAULT_INSTRUCTION_BUDGET,
        state: MachineState | None = None,
    ):
        if not (wait_timeout > 0 and math.isfinite(wait_timeout)):
            raise ValueError(f"wait_timeout must be a positive number of seconds: {wait_timeout}")
        if instruction_budget < 1:
            raise ValueError(f"instruction_budget must be positive: {instruction_budget}")
        self.code = code
        self.controller = controller
        self.cell = code.is_cell  # several robots: a CellController (commands.py)
        self.state = state if state is not None else MachineState()
        if settings is not None:
            self.state.settings = settings
        self.result: ExecutionResult | None = None
        self.wait_timeout = float(wait_timeout)
        self.budget = instruction_budget
        self.pc = 0
        self.cur = 0  # the instruction being executed
        self._steps = 0
        self._progress_at = 0
        self._progress_time = -math.inf
        self.stack: list = []
        self.frames: list[Frame] = []
        self.types: DataTypes | None = None  # (when the code is loaded)
        self.consts: list = []
        self._element_steps = 0  # budget charged for work on array elements
        self._prepared = False
        self._running = False
        self.io = IoInstructions(self, output.append if isinstance(output, list) else output)
        self.data = DataInstructions(self)
        self.motion = MotionInstructions(self)
        self._parts = (self, self.data, self.io, self.motion)

    # ------------------------------------------------------------------ running

    def run(self, *, check: bool = True) -> ExecutionResult:
        """Execute the code once (an Interpreter is single-use).

        On a run-time error: with ``check`` (default) raise the :class:`RunFailure` (line and
        simulated time filled in; ``self.result`` holds the partial result); otherwise
        return the result with ``status == "failed"`` and ``error`` set.
        """
        if self._prepared:
            raise RuntimeError("Interpreter.run() may be called only once")
        status, error = "failed", None
        try:
            self._prepare()
            self._running = True
            status = self._execute()
            self.stop_advance("the program ends")
        except RunFailure as e:
            if not e.line and self._running:
                e.line = self._nearest_line(self.cur) or e.line
            if e.time_s is None:
                e.time_s = self.time()
            error = e
        io = self.io
        io.flush_line()
        self.result = ExecutionResult(
            status, io.run_output, io.run_events, io.run_warnings, error, self.state, self._steps
        )
        if check and error is not None:
            raise error
        return self.result

    def _execute(self) -> str:
        prog = self._prog
        budget = self.budget
        try:
            while True:
                cur = self.pc
                handler, args = prog[cur]
                self.cur = cur
                self.pc = cur + 1
                self._steps += 1
                if self._steps - self._progress_at > budget:
                    raise self._budget_failure()
                handler(args)
        except Finished as f:
            return f.status
        except ControllerError as e:
            raise e.original from None
        except IndexError:
            raise self._bad_code("stack underflow or an operand out of range") from None
        except OverflowError:  # a float operation that raises instead of giving inf
            raise RunFailure("a number is out of range (the result is not finite)") from None
        except (TypeError, ValueError, AttributeError, KeyError, ZeroDivisionError) as e:
            raise self._bad_code(f"{type(e).__name__}: {e}") from None

    def _bad_code(self, what: str) -> RunFailure:
        op = self.code.code[self.cur].op if self.cur < len(self.code.code) else "?"
        return B.malformed(f"{what} at instruction {self.cur} ({op})")

    # ------------------------------------------------------------------ the parts' interface

    def moved(self) -> None:
        """Restart the instruction budget if simulated time advanced by motion; else charge
        the motion statement that did not move (STILL_MOTION_COST)."""
        t = self.time()
        if t > self._progress_time:
            self._progress_time = t
            # the count restarts, never past the run's limit (RUN_BUDGETS budgets in all)
            self._progress_at = min(self._steps, (RUN_BUDGETS - 1) * self.budget)
        else:
            self._steps += STILL_MOTION_COST

    def waited(self, t_before: float) -> None:
        """A WAIT (or a WAIT FOR) that advanced simulated time is progress, as motion is:
        the count restarts (the controller's cycle and time budgets bound the waiting)."""
        t = self.time()
        if t > t_before:
            self._progress_time = max(self._progress_time, t)
            self._progress_at = min(self._steps, (RUN_BUDGETS - 1) * self.budget)

    def _budget_failure(self) -> RunFailure:
        if self._steps > RUN_BUDGETS * self.budget:
            return RunFailure(
                f"more than {RUN_BUDGETS * self.budget} instructions in the run ({RUN_BUDGETS}"
                f" times the endless-loop guard's {self.budget}{self._array_work()}) — an"
                " endless loop with motion? If not, raise the guard: --instruction-budget N"
                " (Python: instruction_budget=N)"
            )
        return RunFailure(
            f"more than {self.budget} instructions without motion or waiting (a motion that "
            f"does not move counts as {STILL_MOTION_COST}{self._array_work()}) — endless "
            "loop? If not, raise the budget: "
            "--instruction-budget N (Python: instruction_budget=N)"
        )

    def _array_work(self) -> str:
        """The budget's rule for arrays, for its message when arrays were charged."""
        if not self._element_steps:
            return ""
        return f", work on an array as its elements / {ELEMENTS_PER_STEP}"

    def charge_elements(self, n: int) -> None:
        """Charge work on ``n`` elements to the budget (data.ELEMENTS_PER_STEP)."""
        steps = n // ELEMENTS_PER_STEP
        self._steps += steps
        self._element_steps += steps

    def time(self) -> float:
        """Simulated time (s): the controller's."""
        return float(self.controller.time)

    def line(self) -> int:
        """The source line of the instruction being executed."""
        return self._lines[self.cur]

    def call_site(self) -> tuple[str, int] | None:
        """``(routine, line of its call)`` when the current instruction is in a routine
        (the cycle-time table shows a routine's motion with its call site)."""
        frame = self.frames[-1] if self.frames else None
        if frame is None or frame.routine.kind == "MAIN":
            return None
        return frame.routine.name, self._nearest_line(frame.return_pc - 1)

    def _nearest_line(self, index: int) -> int:
        """The source line of instruction ``index``, else of the nearest instruction before
        it that records one (code read from a hand-made .ird may say ``L0``); 0 if none."""
        for k in range(min(index, len(self._lines) - 1), -1, -1):
            if self._lines[k] > 0:
                return self._lines[k]
        return 0

    def call(self, fn: Callable, *args, **kwargs):
        """Call the controller; its own RunFailures pass, other exceptions are bugs there."""
        try:
            return fn(*args, **kwargs)
        except RunFailure:
            raise
        except Exception as e:  # re-raised unchanged by _execute
            raise ControllerError(e) from e

    # ------------------------------------------------------------------ preparation

    def _prepare(self) -> None:
        code = self.code
        self._lines = [ins.line for ins in code.code] + [0]
        self._prepared = True
        if len(code.joint_names) != code.joint_count:
            raise B.malformed(f"{len(code.joint_names)} joint names for {code.joint_count} joints")
        robots = code.robots
        names = max((r.joint_names for r in robots), key=len)  # the k-th is alike in all
        self.types = DataTypes(code.types, code.joint_names if not self.cell else names,
                               tuple(r.joint_count for r in robots))  # fmt: skip
        if self.cell and len(self.state.robots) != len(robots):
            self.state.robots = [RobotContext() for _ in robots]
        self.consts = [self.types.constant(k, v) for k, v in enumerate(code.consts)]
        self.data.prepare(self.types)
        self._routines = {r.index: r for r in code.routines}
        self._slot_tables = {r.index: self._slot_table(r) for r in code.routines}
        self._frame_elements = {  # elements a call's cells hold (VAR parameters: none)
            r.index: sum(self.types.elements(s.type) for s in r.params + r.locals if not s.by_ref)
            for r in code.routines
        }
        self._live = 0  # elements the globals and the active calls' cells hold
        self._bind_globals()
        self._prog = [self._decode(ins) for ins in code.code]
        self._prog.append((self._fell_off, ()))
        main = next((r for r in code.routines if r.kind == "MAIN"), None)
        if main is None or main.params:
            raise B.malformed("no MAIN routine without parameters")
        self._push_frame(main, [], return_pc=-1)

    def _slot_table(self, r: Routine) -> list[Slot]:
        slots = sorted(r.params + r.locals, key=lambda s: s.index)
        if [s.index for s in slots] != list(range(len(slots))):
            raise B.malformed(f"the slots of routine {r.name!r} are not numbered 0..n-1")
        return slots

    def _bind_globals(self) -> None:
        st = self.state
        slots = self.code.globals
        if [s.index for s in slots] != list(range(len(slots))):
            raise B.malformed("the global slots are not numbered 0..n-1")
        if len(slots) < len(st.globals):
            raise RunFailure(
                f"the code declares {len(slots)} globals but the session state has"
                f" {len(st.globals)}: it does not extend the previous declarations"
            )
        for old, new in zip(st.global_slots, slots, strict=False):
            if old.name.lower() != new.name.lower() or old.type != new.type:
                raise RunFailure(
                    f"global {new.index} is {new.type} {new.name!r} in the code but"
                    f" {old.type} {old.name!r} in the session state"
                )
        self._hold(sum(self.types.elements(s.type) for s in slots), "the global variables")
        st.globals.extend(self.types.initial(s.type) for s in slots[len(st.globals) :])
        st.global_slots = list(slots)

    def _decode(self, ins) -> tuple[Callable, tuple]:
        if ins.op in B.BINARY:
            return self.data.op_binary, (B.BINARY[ins.op],)
        name = ins.op.lower()
        for part in self._parts:  # the machine (control flow), then the instruction sets
            handler = getattr(part, "op_" + name, None)
            if handler is not None:
                break
        else:
            raise B.malformed(f"unknown opcode {ins.op!r}")
        args = tuple(a.index if isinstance(a, Target) else a for a in ins.args)
        decode = getattr(part, "decode_" + name, None)
        if decode is not None:
            args = decode(args)
        return handler, args

    # ------------------------------------------------------------------ frames

    def _hold(self, n: int, what: str, hint: str = "") -> None:
        """``n`` more elements live (:data:`MAX_LIVE_ELEMENTS` at most), charged to the
        budget like copies of them."""
        if self._live + n > MAX_LIVE_ELEMENTS:
            raise RunFailure(
                f"{what} would hold {self._live + n} elements with the variables already in"
                f" use (at most {MAX_LIVE_ELEMENTS}){hint}"
            )
        self._live += n
        self.charge_elements(n)

    def _push_frame(self, r: Routine, args: list, return_pc: int) -> None:
        if len(self.frames) >= MAX_CALL_DEPTH:
            raise RunFailure(f"more than {MAX_CALL_DEPTH} nested calls — endless recursion?")
        self._hold(
            self._frame_elements[r.index], f"the call of '{r.name}'", " — endless recursion?"
        )
        slots = self._slot_tables[r.index]
        cells: list = []
        for slot, arg in zip(r.params, args, strict=True):
            if slot.by_ref:
                if not isinstance(arg, Ref):
                    raise B.malformed(
                        f"VAR parameter {slot.name!r} of {r.name!r} needs a reference"
                    )
                cells.append(arg)
            else:
                if isinstance(arg, Ref):
                    raise B.malformed(f"parameter {slot.name!r} of {r.name!r} got a reference")
                cells.append(self.types.coerce(arg, slot.type, f"parameter {slot.name!r}"))
        cells.extend(self.types.initial(s.type) for s in slots[len(cells) :])
        self.frames.append(Frame(r, cells, slots, return_pc, len(self.stack)))

    def pop_n(self, n: int) -> list:
        """The top ``n`` operands (the deepest first), removed from the stack."""
        if n < 0 or len(self.stack) < n:
            raise B.malformed(f"stack underflow: {n} operands needed, {len(self.stack)} present")
        if n == 0:
            return []
        out = self.stack[-n:]
        del self.stack[-n:]
        return out

    def push(self, v: object) -> None:
        if len(self.stack) >= MAX_STACK:
            raise B.malformed(f"the operand stack grew beyond {MAX_STACK} values")
        self.stack.append(v)

    # ------------------------------------------------------------------ control flow

    def op_call(self, args) -> None:
        r, argc = args
        routine = self._routines.get(r)
        if routine is None or routine.kind == "MAIN":
            raise B.malformed(f"CALL of routine {r}, which is not a procedure or function")
        if argc != len(routine.params):
            raise B.malformed(f"{routine.name!r} takes {len(routine.params)} arguments, got {argc}")
        values = self.pop_n(argc)
        self._push_frame(routine, values, return_pc=self.pc)
        self.pc = routine.entry

    def op_ret(self, args) -> None:
        frame = self.frames[-1]
        if frame.routine.kind == "MAIN":
            raise Finished("ok")
        if frame.routine.result_type is not None:
            raise RunFailure(
                f"function '{frame.routine.name}' ended without returning a value (RETURN missing)"
            )
        self._leave(frame)

    def op_retv(self, args) -> None:
        frame = self.frames[-1]
        ty = frame.routine.result_type
        if ty is None:
            raise B.malformed(f"RETV in {frame.routine.name!r}, which is not a function")
        v = self.types.coerce(self.stack.pop(), ty, f"the result of {frame.routine.name!r}")
        self._leave(frame)
        self.push(v)

    def _leave(self, frame: Frame) -> None:
        self.frames.pop()
        self._live -= self._frame_elements[frame.routine.index]
        del self.stack[frame.stack_base :]
        self.pc = frame.return_pc

    def op_jmp(self, args) -> None:
        self.pc = args[0]

    def condition(self, what: str) -> bool:
        """The BOOLEAN popped from the stack (malformed code: anything else)."""
        b = self.stack.pop()
        if not isinstance(b, bool):
            raise B.malformed(f"{what} needs a BOOLEAN, got {V.type_name(b)}")
        return b

    def op_jf(self, args) -> None:
        if not self.condition("JF"):
            self.pc = args[0]

    def op_jt(self, args) -> None:
        if self.condition("JT"):
            self.pc = args[0]

    def op_halt(self, args) -> None:
        self.stop_advance(f"HALT at line {self.line()}")
        self.io.event("halt")
        raise Finished("halted")

    def op_end(self, args) -> None:
        raise Finished("ok")

    def _fell_off(self, args) -> None:
        raise B.malformed("execution ran past the last instruction (no END)")

    def op_pause(self, args) -> None:
        self.stop_advance(f"PAUSE at line {self.line()}")
        self.io.event("pause")
        self.io.warn(f"line {self.line()}: PAUSE in a batch run — execution continues")

    def stop_advance(self, why: str) -> None:
        """The advance run stops here: a pending approximated motion ends exactly at its
        point first (WAIT, WAIT FOR, reading an input or R_ACT_…, options, HALT, PAUSE,
        the end of the program)."""
        flush = getattr(self.controller, "flush", None)
        if flush is not None:
            self.call(flush, why)

    def snapshot(self) -> tuple:
        """Copies of the settings and modal options for the controller (a motion handed
        over keeps them): ``(settings, options)``; in a cell every robot's,
        ``((settings_0, …), (options_0, …))`` — robot ``k``'s settings are the cell's with
        its own tool and base (:class:`~irlc.runtime.commands.CellController`)."""
        st = self.state
        if not self.cell:
            return dataclasses.replace(st.settings), _copied(st.options)
        settings = tuple(
            dataclasses.replace(st.settings, tool=r.tool, base=r.base) for r in st.robots
        )
        return settings, tuple(_copied(r.options) for r in st.robots)

    def robot_options(self, robot: int | None) -> ModalOptions:
        """The modal options an instruction of ``robot`` switches (``None``: code of one
        robot, or its robot 0 named: ``state.options``)."""
        if not self.cell:
            return self.state.options
        return self.state.robots[robot or 0].options

    def robot_joints(self, robot: int | None) -> tuple[str, int] | None:
        """``(name, joint count)`` of a cell's robot an instruction names, for the
        length check of a joint tuple it is used with; ``None`` in code of one robot."""
        if not self.cell:
            return None
        r = self.code.robots[robot or 0]
        return r.var, r.joint_count
