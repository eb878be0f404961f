"""The IRDATA machine: executes compiled code (``docs/irdata.md``) against a controller.

A stack machine with one operand stack and a stack of frames. Globals live in the
:class:`MachineState`; a frame holds the cells of one routine activation (parameters,
then locals, numbered by their slot index). A VAR parameter's cell holds a :class:`Ref` to
the caller's cell; ``PUSHL`` / ``POPL`` read and write through it, ``REFL`` of such a cell
passes the same reference on.

Values are immutable (:mod:`irlc.runtime.values`), so pass-by-value needs no copy and
``SETF`` / ``SETI`` build a new value. Variables start *unset* (reading one is a run-time
error naming it), except ARRAY and RECORD variables, whose elements start unset one by one
(so they can be filled element-wise), and SIGNAL outputs, which start FALSE.

Motion, RECONFIGURATION and WAIT go to the :class:`~irlc.runtime.controller.Controller`
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
import re
from collections.abc import Callable
from dataclasses import dataclass, field

from irlc.lang.digital_io import output_error, pulse_error
from irlc.lang.errors import IrlcError
from irlc.lang.irdata import JOINT_TUPLE_TYPES, Code, Routine, Slot, Target, Value
from irlc.lang.settings import BY_WITH_WORD, SYSTEM_VARIABLES, reconfiguration_counts
from irlc.runtime import builtins as B
from irlc.runtime import units
from irlc.runtime import values as V
from irlc.runtime.controller import (
    WAIT_SAMPLED_CYCLES,
    Controller,
    ModalOptions,
    MotionCommand,
    Settings,
    check_setting,
)
from irlc.runtime.digital_io import Outputs
from irlc.runtime.errors import RunFailure
from irlc.runtime.values import ArrayValue, JointTuple, Orientation, Pose, Position, RecordValue

# The endless-loop guard: at most this many instructions without motion (about 0.3 s of
# CPython); a recorded cycle of waiting counts as WAIT_CYCLE_COST instructions (about its run
# time), so a loop that only waits is caught as fast, while one long WAIT (at most
# WAIT_SAMPLED_CYCLES recorded cycles) never exhausts it. Users raise it: --instruction-budget.
DEFAULT_INSTRUCTION_BUDGET = 500_000
WAIT_CYCLE_COST = 25
MAX_CALL_DEPTH = 10_000
MAX_STACK = 1_000_000
LIMIT_TOLERANCE = 1e-6  # deg | mm (per derivative) when checking a bound against the state
TIME_TOLERANCE = 1e-9  # s, when comparing simulated time with input event times


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


@dataclass
class MachineState:
    """What persists between runs of successive code chunks (REPL)."""

    globals: list = field(default_factory=list)
    global_slots: list[Slot] = field(default_factory=list)
    settings: Settings = field(default_factory=Settings)
    options: ModalOptions = field(default_factory=ModalOptions)
    events: list[dict] = field(default_factory=list)
    output: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    input_clock: float = 0.0  # s; input values are read at max(controller.time, this)
    outputs: Outputs = field(default_factory=Outputs)  # OUT[n] switches (digital_io.py)

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


class _Finished(IrlcError):
    def __init__(self, status: str):
        self.status = status


class _ControllerError(IrlcError):
    """A non-RunFailure exception raised by the controller: re-raised unchanged."""

    def __init__(self, original: BaseException):
        self.original = original


@dataclass
class _Frame:
    routine: Routine
    cells: list
    slots: list[Slot]
    return_pc: int
    stack_base: int


_ARRAY_TYPE = re.compile(r"ARRAY\[(-?\d+)\.\.(-?\d+)\]OF(.+)")
_SETTINGS_FIELDS = {  # system variable → Settings field (rows: lang/settings.py)
    name: v.field for name, v in SYSTEM_VARIABLES.items() if v.field is not None
}
_MOVE_NUMBERS = {word: s.field for word, s in BY_WITH_WORD.items()}  # WITH word → field
_LIMIT_OPTIONS = {  # option → (field of MotionCommand / ModalOptions, derivative)
    "JOINTLIMIT": ("joint_limits", 0),
    "JOINTSPEEDLIMIT": ("speed_limits", 1),
    "JOINTACCELLIMIT": ("accel_limits", 2),
}
_POSE_TARGET_KINDS = ("LIN", "LINPATH", "CIRCLE", "LININC")


def _malformed(message: str) -> RunFailure:
    return B.malformed(message)


class Interpreter:
    """Executes one :class:`Code` against ``controller``; see the module docstring."""

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
        self.state = state if state is not None else MachineState()
        if settings is not None:
            self.state.settings = settings
        self._output_cb = output.append if isinstance(output, list) else output
        self.result: ExecutionResult | None = None
        self.wait_timeout = float(wait_timeout)
        self.budget = instruction_budget
        self.pc = 0
        self._cur = 0
        self._steps = 0
        self._progress_at = 0
        self._progress_time = -math.inf
        self.stack: list = []
        self.frames: list[_Frame] = []
        self._line_buffer: list[str] = []
        self._run_output: list[str] = []
        self._run_events: list[dict] = []
        self._run_warnings: list[str] = []
        self._waitfor: tuple[int, float] | None = None  # (instruction, start time)
        self._prepared = False
        self._running = False

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
            self._stop_advance("the program ends")
        except RunFailure as e:
            if not e.line and self._running:
                e.line = self._nearest_line(self._cur) or e.line
            if e.time_s is None:
                e.time_s = self._time()
            error = e
        self._flush_line()
        self.result = ExecutionResult(
            status,
            self._run_output,
            self._run_events,
            self._run_warnings,
            error,
            self.state,
            self._steps,
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
                self._cur = cur
                self.pc = cur + 1
                self._steps += 1
                if self._steps - self._progress_at > budget:
                    raise self._budget_failure()
                handler(args)
        except _Finished as f:
            return f.status
        except _ControllerError as e:
            raise e.original from None
        except IndexError:
            raise self._bad_code("stack underflow or an operand out of range") from None
        except (TypeError, ValueError, AttributeError, KeyError, ZeroDivisionError) as e:
            raise self._bad_code(f"{type(e).__name__}: {e}") from None

    def _bad_code(self, what: str) -> RunFailure:
        op = self.code.code[self._cur].op if self._cur < len(self.code.code) else "?"
        return _malformed(f"{what} at instruction {self._cur} ({op})")

    def _progress(self) -> None:
        """Restart the instruction budget if simulated time advanced by motion."""
        t = self._time()
        if t > self._progress_time:
            self._progress_time = t
            self._progress_at = self._steps

    def _waited(self, t_before: float) -> None:
        """Charge the budget for the cycles a WAIT (or a WAIT FOR) stood still; fail at the
        waiting statement once it is used up."""
        t = self._time()
        if t > t_before:
            cycles = math.ceil((t - t_before) / self.state.settings.ipo - 1e-9)
            cycles = min(cycles, WAIT_SAMPLED_CYCLES)  # what the wait costs to simulate
            self._progress_at -= WAIT_CYCLE_COST * cycles
            self._progress_time = max(self._progress_time, t)
            if self._steps - self._progress_at > self.budget:
                raise self._budget_failure()

    def _budget_failure(self) -> RunFailure:
        return RunFailure(
            f"more than {self.budget} instructions without motion (a cycle of waiting counts "
            f"as {WAIT_CYCLE_COST}) — endless loop? If not, raise the budget: "
            "--instruction-budget N (Python: instruction_budget=N)"
        )

    def _time(self) -> float:
        return float(self.controller.time)

    def _line(self) -> int:
        return self._lines[self._cur]

    def _nearest_line(self, index: int) -> int:
        """The source line of instruction ``index``, else of the nearest instruction before
        it that records one (code read from a hand-made .ird may say ``L0``); 0 if none."""
        for k in range(min(index, len(self._lines) - 1), -1, -1):
            if self._lines[k] > 0:
                return self._lines[k]
        return 0

    def _ctl(self, fn: Callable, *args, **kwargs):
        """Call the controller; its own RunFailures pass, other exceptions are bugs there."""
        try:
            return fn(*args, **kwargs)
        except RunFailure:
            raise
        except Exception as e:  # re-raised unchanged by _execute
            raise _ControllerError(e) from e

    # ------------------------------------------------------------------ preparation

    def _prepare(self) -> None:
        code = self.code
        self._lines = [ins.line for ins in code.code] + [0]
        self._prepared = True
        self._joint_count = code.joint_count
        if len(code.joint_names) != self._joint_count:
            raise _malformed(f"{len(code.joint_names)} joint names for {self._joint_count} joints")
        self._joint_index = {n.lower(): i for i, n in enumerate(code.joint_names)}
        self._record_types = {t.index: t for t in code.types}
        self._consts = [self._constant(k, v) for k, v in enumerate(code.consts)]
        self._inputs = {n: sorted(ev) for n, ev in code.inputs.items()}
        self._routines = {r.index: r for r in code.routines}
        self._slot_tables = {r.index: self._slot_table(r) for r in code.routines}
        self._bind_globals()
        self._prog = [self._decode(ins) for ins in code.code]
        self._prog.append((self._op_fell_off, ()))
        main = next((r for r in code.routines if r.kind == "MAIN"), None)
        if main is None or main.params:
            raise _malformed("no MAIN routine without parameters")
        self._push_frame(main, [], return_pc=-1)

    def _slot_table(self, r: Routine) -> list[Slot]:
        slots = sorted(r.params + r.locals, key=lambda s: s.index)
        if [s.index for s in slots] != list(range(len(slots))):
            raise _malformed(f"the slots of routine {r.name!r} are not numbered 0..n-1")
        return slots

    def _bind_globals(self) -> None:
        st = self.state
        slots = self.code.globals
        if [s.index for s in slots] != list(range(len(slots))):
            raise _malformed("the global slots are not numbered 0..n-1")
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
        st.globals.extend(self._initial(s.type) for s in slots[len(st.globals) :])
        st.global_slots = list(slots)

    def _decode(self, ins) -> tuple[Callable, tuple]:
        if ins.op in B.BINARY:
            return self._op_binary, (B.BINARY[ins.op],)
        handler = getattr(self, "_op_" + ins.op.lower(), None)
        if handler is None:
            raise _malformed(f"unknown opcode {ins.op!r}")
        args = tuple(a.index if isinstance(a, Target) else a for a in ins.args)
        if ins.op == "MOVE":
            args = self._decode_move(args)
        return handler, args

    def _decode_move(self, args: tuple) -> tuple:
        if len(args) < 2 or not isinstance(args[1], int) or args[1] < 1:
            raise _malformed("MOVE needs a kind and a positive number of points")
        clauses = []
        for c in args[2:]:
            word = str(c)
            if word in _MOVE_NUMBERS:
                clauses.append((word, _MOVE_NUMBERS[word], 1))
            elif word in _LIMIT_OPTIONS:
                clauses.append((word, _LIMIT_OPTIONS[word][0], 2))
            elif word.startswith("RECONF:") and word[7:].isdigit() and int(word[7:]) > 0:
                clauses.append(("RECONFIGURATION", "reconfiguration", int(word[7:])))
            else:
                raise _malformed(f"unknown MOVE clause {word!r}")
        return (args[0], args[1], tuple(clauses))

    # ------------------------------------------------------------------ values and types

    def _constant(self, k: int, v: Value) -> object:
        try:
            return self._from_data(v.type, v.data)
        except (TypeError, ValueError, IndexError) as e:
            raise _malformed(f"constant {k} ({v.type}): {e}") from None

    def _from_data(self, ty: str, data: tuple) -> object:
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
        if ty in JOINT_TUPLE_TYPES and len(data) == self._joint_count:
            return JointTuple(ty, tuple(float(x) for x in data))
        raise ValueError(f"{len(data)} value(s) do not make a {ty}")

    def _initial(self, ty: str) -> object:
        if ty == "SIGNAL":
            return False
        m = _ARRAY_TYPE.fullmatch(ty)
        if m:
            low, high = int(m.group(1)), int(m.group(2))
            if high < low:
                raise _malformed(f"empty array type {ty}")
            return ArrayValue(low, tuple(self._initial(m.group(3)) for _ in range(high - low + 1)))
        if ty.startswith("RECORD#"):
            rt = self._record_type(ty)
            return RecordValue(rt.index, tuple((n, self._initial(t)) for n, t in rt.fields))
        return UNSET

    def _record_type(self, ty: str):
        rt = self._record_types.get(int(ty[7:])) if ty[7:].isdigit() else None
        if rt is None:
            raise _malformed(f"unknown record type {ty}")
        return rt

    def _coerce(self, v: object, ty: str, what: str) -> object:
        """``v`` as a value of type ``ty`` (INTEGER → REAL, joint tuples retagged)."""
        out = self._coerced(v, ty)
        if out is UNSET:
            raise _malformed(f"cannot store a {V.type_name(v)} in {what} of type {ty}")
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
        if ty in ("POSITION", "ORIENTATION", "POSE"):
            cls = {"POSITION": Position, "ORIENTATION": Orientation, "POSE": Pose}[ty]
            return v if isinstance(v, cls) else UNSET
        if ty in JOINT_TUPLE_TYPES:
            if not isinstance(v, JointTuple) or len(v.values) != self._joint_count:
                return UNSET
            return v if v.type == ty else JointTuple(ty, v.values)
        m = _ARRAY_TYPE.fullmatch(ty)
        if m:
            return self._coerced_array(v, int(m.group(1)), int(m.group(2)), m.group(3))
        if ty.startswith("RECORD#"):
            rt = self._record_type(ty)
            if not isinstance(v, RecordValue) or v.type_index != rt.index:
                return UNSET
            return self._coerced_fields(v, rt)
        raise _malformed(f"unknown type {ty}")

    def _coerced_array(self, v: object, low: int, high: int, elem: str) -> object:
        if not isinstance(v, ArrayValue) or v.low != low or len(v.items) != high - low + 1:
            return UNSET
        items = tuple(x if x is UNSET else self._coerced(x, elem) for x in v.items)
        if any(x is UNSET and y is not UNSET for x, y in zip(items, v.items, strict=True)):
            return UNSET
        return ArrayValue(low, items)

    def _coerced_fields(self, v: RecordValue, rt) -> object:
        if len(v.fields) != len(rt.fields):
            return UNSET
        fields = []
        for (name, x), (_, fty) in zip(v.fields, rt.fields, strict=True):
            y = x if x is UNSET else self._coerced(x, fty)
            if y is UNSET and x is not UNSET:
                return UNSET
            fields.append((name, y))
        return RecordValue(v.type_index, tuple(fields))

    def _joint_tuple(self, v: object, what: str) -> JointTuple:
        if not isinstance(v, JointTuple) or len(v.values) != self._joint_count:
            raise _malformed(f"{what}: expected a joint tuple of {self._joint_count} values,"
                             f" got {V.type_name(v)}")  # fmt: skip
        return v

    def _main_joint(self, v: object, what: str) -> JointTuple:
        j = self._joint_tuple(v, what)
        return j if j.type == "MAIN_JOINT" else JointTuple("MAIN_JOINT", j.values)

    def _number(self, v: object, what: str) -> float:
        if not B.is_number(v):
            raise _malformed(f"{what}: expected a number, got {V.type_name(v)}")
        return float(v)

    # ------------------------------------------------------------------ frames

    def _push_frame(self, r: Routine, args: list, return_pc: int) -> None:
        if len(self.frames) >= MAX_CALL_DEPTH:
            raise RunFailure(f"more than {MAX_CALL_DEPTH} nested calls — endless recursion?")
        slots = self._slot_tables[r.index]
        cells: list = []
        for slot, arg in zip(r.params, args, strict=True):
            if slot.by_ref:
                if not isinstance(arg, Ref):
                    raise _malformed(f"VAR parameter {slot.name!r} of {r.name!r} needs a reference")
                cells.append(arg)
            else:
                if isinstance(arg, Ref):
                    raise _malformed(f"parameter {slot.name!r} of {r.name!r} got a reference")
                cells.append(self._coerce(arg, slot.type, f"parameter {slot.name!r}"))
        cells.extend(self._initial(s.type) for s in slots[len(cells) :])
        self.frames.append(_Frame(r, cells, slots, return_pc, len(self.stack)))

    def _unset_error(self, name: str) -> RunFailure:
        return RunFailure(f"variable '{name}' is used before it has a value")

    def _pop_n(self, n: int) -> list:
        if n < 0 or len(self.stack) < n:
            raise _malformed(f"stack underflow: {n} operands needed, {len(self.stack)} present")
        if n == 0:
            return []
        out = self.stack[-n:]
        del self.stack[-n:]
        return out

    def _push(self, v: object) -> None:
        if len(self.stack) >= MAX_STACK:
            raise _malformed(f"the operand stack grew beyond {MAX_STACK} values")
        self.stack.append(v)

    # ------------------------------------------------------------------ variables

    def _op_pushc(self, args) -> None:
        self._push(self._consts[args[0]])

    def _op_pushg(self, args) -> None:
        v = self.state.globals[args[0]]
        if v is UNSET:
            raise self._unset_error(self.code.globals[args[0]].name)
        self._push(v)

    def _op_popg(self, args) -> None:
        slot = self.code.globals[args[0]]
        v = self.stack.pop()
        self.state.globals[args[0]] = self._coerce(v, slot.type, f"variable {slot.name!r}")

    def _op_pushl(self, args) -> None:
        frame = self.frames[-1]
        v = frame.cells[args[0]]
        name = frame.slots[args[0]].name
        if isinstance(v, Ref):
            name = v.slot.name
            v = v.cells[v.index]
        if v is UNSET:
            raise self._unset_error(name)
        self._push(v)

    def _op_popl(self, args) -> None:
        frame = self.frames[-1]
        v = self.stack.pop()
        cell = frame.cells[args[0]]
        if isinstance(cell, Ref):
            cell.cells[cell.index] = self._coerce(v, cell.slot.type, f"variable {cell.slot.name!r}")
        else:
            slot = frame.slots[args[0]]
            frame.cells[args[0]] = self._coerce(v, slot.type, f"variable {slot.name!r}")

    def _op_refg(self, args) -> None:
        g = args[0]
        self._push(Ref(self.state.globals, g, self.code.globals[g]))

    def _op_refl(self, args) -> None:
        frame = self.frames[-1]
        cell = frame.cells[args[0]]
        self._push(
            cell if isinstance(cell, Ref) else Ref(frame.cells, args[0], frame.slots[args[0]])
        )

    def _op_pushsys(self, args) -> None:
        name = args[0]
        st = self.state
        if name in ("R_ACT_POSE", "R_ACT_JOINT"):
            self._stop_advance(f"line {self._line()} reads {name}")
        if name == "R_ACT_POSE":
            v = self._ctl(self.controller.pose, dataclasses.replace(st.settings))
        elif name == "R_ACT_JOINT":
            q = self._ctl(self.controller.joints)
            v = JointTuple("MAIN_JOINT", tuple(float(x) for x in q))
        elif name in _SETTINGS_FIELDS:
            v = getattr(st.settings, _SETTINGS_FIELDS[name])
        else:
            raise _malformed(f"unknown system variable {name!r}")
        self._push(v)

    def _op_popsys(self, args) -> None:
        name = args[0]
        v = self.stack.pop()
        if name not in _SETTINGS_FIELDS:
            raise _malformed(f"system variable {name!r} cannot be assigned")
        if name in ("R_TOOL", "R_BASE"):
            if not isinstance(v, Pose):
                raise _malformed(f"{name} needs a POSE, got {V.type_name(v)}")
        elif SYSTEM_VARIABLES[name].type_name == "STRING":  # R_PROFILE: a word, any case
            if not isinstance(v, str):
                raise _malformed(f"{name} needs a STRING, got {V.type_name(v)}")
            v = check_setting(_SETTINGS_FIELDS[name], v, name).upper()
        else:
            v = check_setting(_SETTINGS_FIELDS[name], self._number(v, name), name)
        setattr(self.state.settings, _SETTINGS_FIELDS[name], v)

    def _op_pop(self, args) -> None:
        self.stack.pop()

    def _op_dup(self, args) -> None:
        self._push(self.stack[-1])

    # ------------------------------------------------------------------ fields and elements

    def _op_getf(self, args) -> None:
        c = self.stack.pop()
        self._push(self._get_field(c, args[0]))

    def _get_field(self, c: object, name: str) -> object:
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
        elif isinstance(c, JointTuple) and key in self._joint_index:
            return c.values[self._joint_index[key]]
        raise _malformed(f"a {V.type_name(c)} has no field {name!r}")

    def _op_setf(self, args) -> None:
        v = self.stack.pop()
        c = self.stack.pop()
        self._push(self._set_field(c, args[0], v))

    def _set_field(self, c: object, name: str, v: object) -> object:
        key = name.lower()
        if isinstance(c, RecordValue):
            rt = self._record_types.get(c.type_index)
            for k, (fname, fty) in enumerate(rt.fields if rt else ()):
                if fname.lower() == key:
                    fields = list(c.fields)
                    fields[k] = (fname, self._coerce(v, fty, f"field {fname!r}"))
                    return RecordValue(c.type_index, tuple(fields))
        elif isinstance(c, Position) and key in ("x", "y", "z"):
            return dataclasses.replace(c, **{key: self._number(v, f"field {name}")})
        elif isinstance(c, Pose) and key in ("x", "y", "z"):
            pos = dataclasses.replace(c.pos, **{key: self._number(v, f"field {name}")})
            return Pose(pos, c.ori)
        elif isinstance(c, Pose) and key == "pos":
            return Pose(self._coerce(v, "POSITION", "field pos"), c.ori)
        elif isinstance(c, Pose) and key == "ori":
            return Pose(c.pos, self._coerce(v, "ORIENTATION", "field ori"))
        elif isinstance(c, JointTuple) and key in self._joint_index:
            values = list(c.values)
            values[self._joint_index[key]] = self._number(v, f"joint {name}")
            return JointTuple(c.type, tuple(values))
        raise _malformed(f"a {V.type_name(c)} has no field {name!r}")

    def _index(self, c: object, i: object) -> int:
        """0-based position of index ``i`` in ``c`` (checked against the bounds)."""
        if not isinstance(i, int) or isinstance(i, bool):
            raise _malformed(f"an index must be an INTEGER, got {V.type_name(i)}")
        if isinstance(c, ArrayValue):
            low, n = c.low, len(c.items)
        elif isinstance(c, JointTuple):
            low, n = 1, len(c.values)
        else:
            raise _malformed(f"a {V.type_name(c)} cannot be indexed")
        if not low <= i < low + n:
            raise RunFailure(f"index {i} is out of range {low}..{low + n - 1}")
        return i - low

    def _op_geti(self, args) -> None:
        i = self.stack.pop()
        c = self.stack.pop()
        k = self._index(c, i)
        if isinstance(c, JointTuple):
            self._push(c.values[k])
            return
        v = c.items[k]
        if v is UNSET:
            raise RunFailure(f"element [{i}] is used before it has a value")
        self._push(v)

    def _op_seti(self, args) -> None:
        v = self.stack.pop()
        i = self.stack.pop()
        c = self.stack.pop()
        k = self._index(c, i)
        if isinstance(c, JointTuple):
            values = list(c.values)
            values[k] = self._number(v, f"joint [{i}]")
            self._push(JointTuple(c.type, tuple(values)))
        else:
            items = list(c.items)
            items[k] = v
            self._push(ArrayValue(c.low, tuple(items)))

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
        self._push(self._make(ty, items))

    def _make(self, ty: str, items: list) -> object:
        n = len(items)
        if ty == "POSE" and n == 6:
            return V.pose_from_zyx(*(self._number(x, "POSE") for x in items))
        if ty == "POSE" and n == 2:
            return Pose(self._coerce(items[0], "POSITION", "POSE"),
                        self._coerce(items[1], "ORIENTATION", "POSE"))  # fmt: skip
        if ty == "POSITION" and n == 3:
            return Position(*(self._number(x, "POSITION") for x in items))
        if ty == "ORIENTATION" and n == 4:
            return B.call_builtin("ORIQUAT", tuple(items))
        if ty in JOINT_TUPLE_TYPES and n == self._joint_count:
            return JointTuple(ty, tuple(self._number(x, ty) for x in items))
        m = _ARRAY_TYPE.fullmatch(ty)
        if m and n == int(m.group(2)) - int(m.group(1)) + 1:
            elem = m.group(3)
            return ArrayValue(
                int(m.group(1)), tuple(self._coerce(x, elem, "element") for x in items)
            )
        if ty.startswith("RECORD#"):
            rt = self._record_type(ty)
            if n == len(rt.fields):
                return RecordValue(rt.index, tuple(
                    (name, self._coerce(x, fty, f"field {name!r}"))
                    for (name, fty), x in zip(rt.fields, items, strict=True)))  # fmt: skip
        if n == 1 and ty in ("INTEGER", "REAL", "BOOLEAN", "CHAR", "STRING"):
            return self._coerce(items[0], ty, ty)
        raise _malformed(f"MAKE {ty} from {n} values")

    def _op_callb(self, args) -> None:
        name, argc = args
        values = tuple(self._pop_n(argc))
        if name == "FK":
            if argc != 1:
                raise _malformed(f"FK takes 1 argument, got {argc}")
            joints = self._joint_tuple(values[0], "FK")
            settings = dataclasses.replace(self.state.settings)
            self._push(B.checked_value(self._ctl(self.controller.forward, joints, settings), "FK"))
            return
        self._push(B.call_builtin(name, values))

    # ------------------------------------------------------------------ control flow

    def _op_call(self, args) -> None:
        r, argc = args
        routine = self._routines.get(r)
        if routine is None or routine.kind == "MAIN":
            raise _malformed(f"CALL of routine {r}, which is not a procedure or function")
        if argc != len(routine.params):
            raise _malformed(f"{routine.name!r} takes {len(routine.params)} arguments, got {argc}")
        values = self._pop_n(argc)
        self._push_frame(routine, values, return_pc=self.pc)
        self.pc = routine.entry

    def _op_ret(self, args) -> None:
        frame = self.frames[-1]
        if frame.routine.kind == "MAIN":
            raise _Finished("ok")
        if frame.routine.result_type is not None:
            raise RunFailure(
                f"function '{frame.routine.name}' ended without returning a value (RETURN missing)"
            )
        self._leave(frame)

    def _op_retv(self, args) -> None:
        frame = self.frames[-1]
        ty = frame.routine.result_type
        if ty is None:
            raise _malformed(f"RETV in {frame.routine.name!r}, which is not a function")
        v = self._coerce(self.stack.pop(), ty, f"the result of {frame.routine.name!r}")
        self._leave(frame)
        self._push(v)

    def _leave(self, frame: _Frame) -> None:
        self.frames.pop()
        del self.stack[frame.stack_base :]
        self.pc = frame.return_pc

    def _op_jmp(self, args) -> None:
        self.pc = args[0]

    def _condition(self, what: str) -> bool:
        b = self.stack.pop()
        if not isinstance(b, bool):
            raise _malformed(f"{what} needs a BOOLEAN, got {V.type_name(b)}")
        return b

    def _op_jf(self, args) -> None:
        if not self._condition("JF"):
            self.pc = args[0]

    def _op_jt(self, args) -> None:
        if self._condition("JT"):
            self.pc = args[0]

    def _op_halt(self, args) -> None:
        self._stop_advance(f"HALT at line {self._line()}")
        self._event("halt")
        raise _Finished("halted")

    def _op_end(self, args) -> None:
        raise _Finished("ok")

    def _op_fell_off(self, args) -> None:
        raise _malformed("execution ran past the last instruction (no END)")

    def _op_pause(self, args) -> None:
        self._stop_advance(f"PAUSE at line {self._line()}")
        self._event("pause")
        self._warn(f"line {self._line()}: PAUSE in a batch run — execution continues")

    # ------------------------------------------------------------------ time and I/O

    def _op_wait(self, args) -> None:
        s = self._number(self.stack.pop(), "WAIT")
        if s < 0:
            raise RunFailure(f"WAIT {V.format_real(s)} SEC: the time must not be negative")
        self._stop_advance(f"WAIT at line {self._line()}")
        if s > 0:
            t_before = self._time()
            self._ctl(self.controller.wait, s, self._line(), *self._snapshot())
            self._waited(t_before)

    def _now(self) -> float:
        return max(self._time(), self.state.input_clock)

    def _input(self, n: int, t: float) -> bool:
        value = False
        for time, v in self._inputs.get(n, ()):
            if time > t + TIME_TOLERANCE:
                break
            value = v
        return value

    def _next_input_change(self, t: float) -> float | None:
        """The next time an input — or an output with a PULSE's end still ahead — changes."""
        outputs = self.state.outputs
        timelines = [(events, self._input(n, t)) for n, events in self._inputs.items()]
        timelines += [(events, outputs.value(n, t)) for n, events in outputs.switches.items()]
        best = None
        for events, current in timelines:
            for time, v in events:
                if time > t + TIME_TOLERANCE and v != current:
                    best = time if best is None else min(best, time)
                    break
        return best

    def _stop_advance(self, why: str) -> None:
        """The advance run stops here: a pending approximated motion ends exactly at its
        point first (WAIT, WAIT FOR, reading an input, the end of the program)."""
        flush = getattr(self.controller, "flush", None)
        if flush is not None:
            self._ctl(flush, why)

    def _op_pushin(self, args) -> None:
        n = self.stack.pop()
        if not isinstance(n, int) or isinstance(n, bool):
            raise _malformed(f"an input number must be an INTEGER, got {V.type_name(n)}")
        self._stop_advance(f"line {self._line()} reads input {n}")
        self._push(self._input(n, self._now()))

    def _op_waitfor(self, args) -> None:
        self._stop_advance(f"WAIT FOR at line {self._line()}")
        if self._condition("WAIT FOR"):
            self._waitfor = None
            return
        now = self._now()
        if self._waitfor is None or self._waitfor[0] != self._cur:
            self._waitfor = (self._cur, now)
        start = self._waitfor[1]
        t_next = self._next_input_change(now)
        if t_next is None or t_next > start + self.wait_timeout + TIME_TOLERANCE:
            when = "no input changes any more" if t_next is None else (
                f"the next input change is at t = {V.format_real(t_next)} s")  # fmt: skip
            raise RunFailure(
                f"WAIT FOR can never become true: {when}, and the time-out is"
                f" {V.format_real(self.wait_timeout)} s"
                f" (waiting since t = {V.format_real(start)} s)"
            )
        t_before = self._time()
        dt = t_next - t_before
        if dt > 0:
            self._ctl(self.controller.wait, dt, self._line(), *self._snapshot())
        self.state.input_clock = max(self.state.input_clock, t_next)
        self._waited(t_before)
        self.pc = args[0]

    def _op_sigout(self, args) -> None:
        slot = self.code.globals[args[0]]
        v = self._coerce(self.stack.pop(), "BOOLEAN", f"signal {slot.name!r}")
        self.state.globals[args[0]] = v
        self._event("signal", name=slot.name, value=v)

    def _output_number(self) -> int:
        n = self.stack.pop()
        if not isinstance(n, int) or isinstance(n, bool):
            raise _malformed(f"an output number must be an INTEGER, got {V.type_name(n)}")
        error = output_error(n)
        if error is not None:
            raise RunFailure(error)
        return n

    def _op_outset(self, args) -> None:
        """``OUT[n] := b``: switch now (the statement's time in the advance run)."""
        v = self._coerce(self.stack.pop(), "BOOLEAN", "OUT[…]")
        n = self._output_number()
        self._drop_event(self.state.outputs.set(n, self._time(), v))
        self._event("output", output=n, value=v)

    def _op_pushout(self, args) -> None:
        n = self._output_number()
        self._push(self.state.outputs.value(n, self._time()))

    def _op_pulse(self, args) -> None:
        """``PULSE(OUT[n], d)``: TRUE now, FALSE ``d`` s later; the program goes on."""
        d = self._number(self.stack.pop(), "PULSE")
        error = pulse_error(d)
        if error is not None:
            raise RunFailure(error)
        n = self._output_number()
        now = self._time()
        end = {"kind": "output", "line": self._line(), "time_s": now + d, "output": n,
               "value": False}  # fmt: skip
        self._drop_event(self.state.outputs.pulse(n, now, d, end))
        self._event("output", output=n, value=True, pulse_s=d)
        self.state.events.append(end)  # its time is ahead: the report sorts events by time
        self._run_events.append(end)

    def _drop_event(self, event: dict | None) -> None:
        """Remove a pulse's end that an assignment overrode (``digital_io.Outputs.set``)."""
        for events in (self.state.events, self._run_events):
            for i, e in enumerate(events):
                if e is event:
                    del events[i]
                    break

    def _write(self, argc: int) -> None:
        for v in self._pop_n(argc):
            self._check_set(v)
            self._line_buffer.append(V.format_value(v))

    def _check_set(self, v: object) -> None:
        if isinstance(v, ArrayValue):
            for i, item in enumerate(v.items):
                if item is UNSET:
                    raise RunFailure(f"element [{v.low + i}] is used before it has a value")
                self._check_set(item)
        elif isinstance(v, RecordValue):
            for name, item in v.fields:
                if item is UNSET:
                    raise RunFailure(f"field '{name}' is used before it has a value")
                self._check_set(item)
        elif isinstance(v, Ref):
            raise _malformed("WRITE of a reference")

    def _op_write(self, args) -> None:
        self._write(args[0])

    def _op_writeln(self, args) -> None:
        self._write(args[0])
        self._emit("".join(self._line_buffer))
        self._line_buffer.clear()

    def _flush_line(self) -> None:
        if self._line_buffer:
            self._emit("".join(self._line_buffer))
            self._line_buffer.clear()

    def _emit(self, text: str) -> None:
        self.state.output.append(text)
        self._run_output.append(text)
        if self._output_cb is not None:
            self._output_cb(text)

    def _event(self, kind: str, **data) -> None:
        line = self._line()
        event = {"kind": kind, "line": line, "time_s": self._time(), **data}
        self.state.events.append(event)
        self._run_events.append(event)
        self._ctl(self.controller.log_event, kind, line, **data)

    def _warn(self, text: str) -> None:
        self.state.warnings.append(text)
        self._run_warnings.append(text)

    def _snapshot(self) -> tuple[Settings, ModalOptions]:
        st = self.state
        opts = dataclasses.replace(st.options, frozen=dict(st.options.frozen))
        return dataclasses.replace(st.settings), opts

    # ------------------------------------------------------------------ motion

    def _op_move(self, args) -> None:
        kind, npts, clauses = args
        fields: dict[str, object] = {}
        for word, name, count in reversed(clauses):
            operands = self._pop_n(count)
            fields[name] = self._move_clause(word, operands, kind, npts)
        targets = tuple(self._move_target(kind, t) for t in self._pop_n(npts))
        self._check_point_count(kind, npts)
        cmd = MotionCommand(kind, targets, self._line(), **fields)
        self._ctl(self.controller.move, cmd, *self._snapshot())
        self._progress()

    def _check_point_count(self, kind: str, npts: int) -> None:
        expected = {"CIRCLE": 2, "PTP": 1, "PTPINC": 1, "LININC": 1}.get(kind)
        if kind not in ("LIN", "LINPATH") and expected is None:
            raise _malformed(f"unknown motion kind {kind!r}")
        if expected is not None and npts != expected:
            raise _malformed(f"MOVE {kind} with {npts} points")

    def _move_target(self, kind: str, t: object) -> object:
        if kind in _POSE_TARGET_KINDS:
            if not isinstance(t, Pose):
                raise _malformed(f"MOVE {kind} needs POSE targets, got {V.type_name(t)}")
            return t
        if kind == "PTP" and isinstance(t, Pose):
            return t
        return self._main_joint(t, f"MOVE {kind} target")

    def _move_clause(self, word: str, operands: list, kind: str, npts: int) -> object:
        if word in _MOVE_NUMBERS:
            what = f"WITH {word}"
            return check_setting(_MOVE_NUMBERS[word], self._number(operands[0], what), what)
        if word in _LIMIT_OPTIONS:
            return self._checked_limits(word, operands[0], operands[1])
        if len(operands) not in reconfiguration_counts(kind, npts):
            raise _malformed(f"{len(operands)} RECONFIGURATION targets for {npts} points")
        return tuple(self._main_joint(k, "RECONFIGURATION") for k in operands)

    def _op_reconf(self, args) -> None:
        k = self._main_joint(self.stack.pop(), "RECONFIGURATION")
        self._ctl(self.controller.reconfigure, k, self._line(), *self._snapshot())
        self._progress()

    # ------------------------------------------------------------------ modal options

    def _joint_unit(self, i: int, derivative: int) -> str:
        kind = units.REVOLUTE if self.code.joint_kinds[i] == "R" else units.PRISMATIC
        return units.joint_unit_label(kind, derivative)

    def _joint_labels(self) -> tuple[str, ...]:
        """Joint names for messages (the naming rule: the program's name, the robot's in
        parentheses where it differs), from the controller's naming when it has one."""
        naming = getattr(self.controller, "naming", None)
        if naming is None or len(naming.program) != len(self.code.joint_names):
            return tuple(self.code.joint_names)
        return tuple(naming.label(i) for i in range(len(naming.program)))

    def _checked_limits(self, option: str, lo: object, hi: object) -> tuple[JointTuple, JointTuple]:
        lo = self._joint_tuple(lo, f"{option} lower bounds")
        hi = self._joint_tuple(hi, f"{option} upper bounds")
        derivative = _LIMIT_OPTIONS[option][1]
        names = self._joint_labels()
        fmt = V.format_real
        for i, (a, b) in enumerate(zip(lo.values, hi.values, strict=True)):
            unit = self._joint_unit(i, derivative)
            if a > b:
                raise RunFailure(
                    f"{option}: joint {names[i]} has the lower bound {fmt(a)} {unit}"
                    f" above the upper bound {fmt(b)} {unit}"
                )
            if derivative and (a > LIMIT_TOLERANCE or b < -LIMIT_TOLERANCE):
                raise RunFailure(
                    f"{option} must allow standing still: joint {names[i]} has the bounds"
                    f" [{fmt(a)}, {fmt(b)}] {unit}, which exclude 0",
                    constraint=f"joint {names[i]} {('speed', 'accel')[derivative - 1]}"
                    f" {'min' if a > 0 else 'max'} {fmt(a if a > 0 else b)} {unit}",
                )
        if derivative == 0:
            self._check_joints_inside(option, lo, hi)
        return lo, hi

    def _check_joints_inside(self, option: str, lo: JointTuple, hi: JointTuple) -> None:
        q = self._ctl(self.controller.joints)
        fmt = V.format_real
        for i, (v, a, b) in enumerate(zip(q, lo.values, hi.values, strict=True)):
            name, unit = self._joint_labels()[i], self._joint_unit(i, 0)
            if v < a - LIMIT_TOLERANCE or v > b + LIMIT_TOLERANCE:
                below = v < a
                side, bound = ("lower", a) if below else ("upper", b)
                raise RunFailure(
                    f"{option} excludes the current state: joint {name} is at {fmt(v)} {unit},"
                    f" {'below' if below else 'above'} the {side} bound {fmt(bound)} {unit}",
                    constraint=f"joint {name} position {'min' if below else 'max'}"
                    f" {fmt(bound)} {unit}",
                )

    def _op_opton(self, args) -> None:
        option, rest = args[0], args[1:]
        self._stop_advance(f"{option} switched on at line {self._line()}")
        opts = self.state.options
        if option in _LIMIT_OPTIONS:
            hi = self.stack.pop()
            lo = self.stack.pop()
            attr = _LIMIT_OPTIONS[option][0]
            if getattr(opts, attr) is not None:
                raise RunFailure(f"{option} is already on (close it with {option}END first)")
            setattr(opts, attr, self._checked_limits(option, lo, hi))
        elif option == "CYCLIC":
            if opts.cyclic_reference is not None:
                raise RunFailure("CYCLICSTART while CYCLIC is already on")
            opts.cyclic_reference = tuple(float(x) for x in self._ctl(self.controller.joints))
        elif option == "OBSTACLE":
            self._obstacle_on(rest)
            self._check_switch_on(option)
        elif option == "FREEZE":
            self._freeze_on(rest)
            self._check_switch_on(option)
        else:
            raise _malformed(f"unknown modal option {option!r}")

    def _check_switch_on(self, option: str) -> None:
        """Let the controller reject an option that cannot hold from this very statement
        (an obstacle the arm is inside, too many frozen joints); optional for controllers."""
        check = getattr(self.controller, "check_switch_on", None)
        if check is not None:
            self._ctl(check, option, self._line(), *self._snapshot())

    def _obstacle_on(self, rest: tuple) -> None:
        if len(rest) != 1:
            raise _malformed("OPTON OBSTACLE needs one obstacle name")
        obstacle = self.code.obstacle(str(rest[0]))
        if obstacle is None:
            known = ", ".join(o.name for o in self.code.obstacles) or "none"
            raise RunFailure(f"unknown obstacle '{rest[0]}' (known: {known})")
        opts = self.state.options
        if obstacle.name in opts.obstacles:
            raise RunFailure(f"OBSTACLE {obstacle.name} is already on")
        opts.obstacles = (*opts.obstacles, obstacle.name)

    def _freeze_on(self, rest: tuple) -> None:
        opts = self.state.options
        if opts.frozen:
            raise RunFailure("FREEZESTART while joints are already frozen")
        n = self._joint_count
        if not rest or any(not isinstance(j, int) or not 1 <= j <= n for j in rest):
            raise _malformed(
                f"FREEZE needs joint numbers in 1..{n}, got {' '.join(map(str, rest))}"
            )
        q = self._ctl(self.controller.joints)
        opts.frozen = {j - 1: float(q[j - 1]) for j in rest}

    def _op_optoff(self, args) -> None:
        option, rest = args[0], args[1:]
        self._stop_advance(f"{option} switched off at line {self._line()}")
        opts = self.state.options
        if option in _LIMIT_OPTIONS:
            attr = _LIMIT_OPTIONS[option][0]
            self._require_on(getattr(opts, attr) is not None, option)
            setattr(opts, attr, None)
        elif option == "CYCLIC":
            self._require_on(opts.cyclic_reference is not None, "CYCLIC")
            opts.cyclic_reference = None
        elif option == "OBSTACLE":
            if len(rest) != 1:
                raise _malformed("OPTOFF OBSTACLE needs one obstacle name")
            key = str(rest[0]).lower()
            active = [o for o in opts.obstacles if o.lower() == key]
            self._require_on(bool(active), f"OBSTACLE {rest[0]}")
            opts.obstacles = tuple(o for o in opts.obstacles if o.lower() != key)
        elif option == "FREEZE":
            self._require_on(bool(opts.frozen), "FREEZE")
            opts.frozen = {}
        else:
            raise _malformed(f"unknown modal option {option!r}")

    def _require_on(self, on: bool, what: str) -> None:
        if not on:
            raise RunFailure(f"{what} is switched off but it is not on")
