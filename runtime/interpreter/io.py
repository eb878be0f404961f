"""The time and I/O instructions: WAIT, WAIT FOR, digital inputs and outputs, SIGNAL
outputs, WRITE / WRITELN, and the run's events (``docs/irdata.md``, ``docs/interpreter.md``).

A part of the interpreter (:class:`IoInstructions`; the handlers use the machine's operand
stack, :class:`MachineState` and controller through :class:`~irlc.runtime.interpreter.
context.Machine`); it keeps this run's output, events and warnings. Simulated time is the
controller's.
An input's value at time ``t`` is the last change at or before ``t`` (a tolerance of
:data:`TIME_TOLERANCE`); inputs are read at ``max(controller time, state.input_clock)``, so
a WAIT FOR that jumps to an input change moves the input clock even when the controller
has no motion to simulate. Text written by WRITE stays on an open line until WRITELN (or
the end of the run) emits it.
"""

from __future__ import annotations

from collections.abc import Callable

from irlc.lang.digital_io import output_error, pulse_error
from irlc.runtime import values as V
from irlc.runtime.errors import RunFailure
from irlc.runtime.interpreter import builtins as B
from irlc.runtime.interpreter.context import Machine
from irlc.runtime.interpreter.datatypes import number
from irlc.runtime.interpreter.state import UNSET, Ref
from irlc.runtime.outputs.digital_io import value_at
from irlc.runtime.values import ArrayValue, RecordValue

TIME_TOLERANCE = 1e-9  # s, when comparing simulated time with input event times
MAX_OUTPUT_CHARS = 10_000_000  # the most characters one run writes (WRITE, WRITELN)
MAX_EVENTS = 200_000  # the most events (signals, outputs, PAUSE, …) and warnings of a run


class IoInstructions:
    """``WAIT`` … ``WRITELN``; see the module docstring. ``output`` receives each finished
    line of WRITE/WRITELN (besides ``run_output``)."""

    def __init__(self, machine: Machine, output: Callable[[str], None] | None = None):
        self.m = machine
        self.stack, self.state, self.code = machine.stack, machine.state, machine.code
        self.pop_n, self.push = machine.pop_n, machine.push
        self.output = output
        self.inputs = {n: sorted(ev) for n, ev in machine.code.inputs.items()}
        self.run_output: list[str] = []  # this run's (state.output: all runs')
        self.run_events: list[dict] = []
        self.run_warnings: list[str] = []
        self.line_buffer: list[str] = []  # the open line of WRITE
        self.written = 0  # characters of WRITE output (MAX_OUTPUT_CHARS)
        self.waitfor: tuple[int, float] | None = None  # (instruction, start time)

    # ------------------------------------------------------------------ waiting

    def op_wait(self, args) -> None:
        s = number(self.stack.pop(), "WAIT")
        if s < 0:
            raise RunFailure(f"WAIT {V.format_real(s)} SEC: the time must not be negative")
        m = self.m
        m.stop_advance(f"WAIT at line {m.line()}")
        if s > 0:
            t_before = m.time()
            m.call(m.controller.wait, s, m.line(), *m.snapshot())
            m.waited(t_before)

    def op_waitfor(self, args) -> None:
        m = self.m
        m.stop_advance(f"WAIT FOR at line {m.line()}")
        if m.condition("WAIT FOR"):
            self.waitfor = None
            return
        now = self._now()
        if self.waitfor is None or self.waitfor[0] != m.cur:
            self.waitfor = (m.cur, now)
        start = self.waitfor[1]
        t_next = self._next_input_change(now)
        if t_next is None or t_next > start + m.wait_timeout + TIME_TOLERANCE:
            when = "no input changes any more" if t_next is None else (
                f"the next input change is at t = {V.format_real(t_next)} s")  # fmt: skip
            raise RunFailure(
                f"WAIT FOR can never become true: {when}, and the time-out is"
                f" {V.format_real(m.wait_timeout)} s"
                f" (waiting since t = {V.format_real(start)} s)"
            )
        t_before = m.time()
        dt = t_next - t_before
        if dt > 0:
            m.call(m.controller.wait, dt, m.line(), *m.snapshot())
        self.state.input_clock = max(self.state.input_clock, t_next)
        m.waited(t_before)
        m.pc = args[0]

    # ------------------------------------------------------------------ inputs

    def _now(self) -> float:
        return max(self.m.time(), self.state.input_clock)

    def _input(self, n: int, t: float) -> bool:
        return value_at(self.inputs.get(n, ()), t)

    def _next_input_change(self, t: float) -> float | None:
        """The next time an input — or an output with a PULSE's end still ahead — changes."""
        outputs = self.state.outputs
        timelines = [(events, self._input(n, t)) for n, events in self.inputs.items()]
        timelines += [(events, outputs.value(n, t)) for n, events in outputs.switches.items()]
        best = None
        for events, current in timelines:
            for time, v in events:
                if time > t + TIME_TOLERANCE and v != current:
                    best = time if best is None else min(best, time)
                    break
        return best

    def op_pushin(self, args) -> None:
        n = self.stack.pop()
        if not isinstance(n, int) or isinstance(n, bool):
            raise B.malformed(f"an input number must be an INTEGER, got {V.type_name(n)}")
        self.m.stop_advance(f"line {self.m.line()} reads input {n}")
        self.push(self._input(n, self._now()))

    # ------------------------------------------------------------------ outputs

    def op_sigout(self, args) -> None:
        slot = self.code.globals[args[0]]
        v = self.m.types.coerce(self.stack.pop(), "BOOLEAN", f"signal {slot.name!r}")
        self.state.globals[args[0]] = v
        self.event("signal", name=slot.name, value=v)

    def _output_number(self) -> int:
        n = self.stack.pop()
        if not isinstance(n, int) or isinstance(n, bool):
            raise B.malformed(f"an output number must be an INTEGER, got {V.type_name(n)}")
        error = output_error(n)
        if error is not None:
            raise RunFailure(error)
        return n

    def op_outset(self, args) -> None:
        """``OUT[n] := b``: switch now (the statement's time in the advance run)."""
        v = self.m.types.coerce(self.stack.pop(), "BOOLEAN", "OUT[…]")
        n = self._output_number()
        self._drop_event(self.state.outputs.set(n, self.m.time(), v))
        self.event("output", output=n, value=v)

    def op_pushout(self, args) -> None:
        n = self._output_number()
        self.push(self.state.outputs.value(n, self.m.time()))

    def op_pulse(self, args) -> None:
        """``PULSE(OUT[n], d)``: TRUE now, FALSE ``d`` s later; the program goes on."""
        d = number(self.stack.pop(), "PULSE")
        error = pulse_error(d)
        if error is not None:
            raise RunFailure(error)
        n = self._output_number()
        now = self.m.time()
        end = {"kind": "output", "line": self.m.line(), "time_s": now + d, "output": n,
               "value": False}  # fmt: skip
        self._drop_event(self.state.outputs.pulse(n, now, d, end))
        self.event("output", output=n, value=True, pulse_s=d)
        self.state.events.append(end)  # its time is ahead: the report sorts events by time
        self.run_events.append(end)

    def _drop_event(self, event: dict | None) -> None:
        """Remove a pulse's end that an assignment overrode (``digital_io.Outputs.set``),
        searching from the newest event (it is among the last)."""
        if event is None:
            return
        for events in (self.state.events, self.run_events):
            for i in range(len(events) - 1, -1, -1):
                if events[i] is event:
                    del events[i]
                    break

    # ------------------------------------------------------------------ text output

    def _write(self, argc: int) -> None:
        """The values' text onto the open line; a run writes at most
        :data:`MAX_OUTPUT_CHARS` characters (checked before a value's text is built)."""
        for v in self.pop_n(argc):
            _check_set(v)
            if self.written + V.text_bound(v) > MAX_OUTPUT_CHARS:
                raise RunFailure(
                    f"the program's output would exceed {MAX_OUTPUT_CHARS} characters"
                    " — endless loop?"
                )
            text = V.format_value(v)
            self.written += len(text)
            self.line_buffer.append(text)

    def op_write(self, args) -> None:
        self._write(args[0])

    def op_writeln(self, args) -> None:
        self._write(args[0])
        self._emit("".join(self.line_buffer))
        self.line_buffer.clear()

    def flush_line(self) -> None:
        """Emit the line WRITE left open (the end of a run)."""
        if self.line_buffer:
            self._emit("".join(self.line_buffer))
            self.line_buffer.clear()

    def _emit(self, text: str) -> None:
        self.state.output.append(text)
        self.run_output.append(text)
        if self.output is not None:
            self.output(text)

    # ------------------------------------------------------------------ events and warnings

    def _count_event(self) -> None:
        """A run logs at most :data:`MAX_EVENTS` events and warnings."""
        if len(self.run_events) + len(self.run_warnings) >= MAX_EVENTS:
            raise RunFailure(
                f"more than {MAX_EVENTS} events (signals, outputs, PAUSE …) and warnings"
                " in one run — endless loop?"
            )

    def event(self, kind: str, **data) -> None:
        """Log an event of the run at the current line and time (also the controller's)."""
        self._count_event()
        m = self.m
        line = m.line()
        event = {"kind": kind, "line": line, "time_s": m.time(), **data}
        self.state.events.append(event)
        self.run_events.append(event)
        m.call(m.controller.log_event, kind, line, **data)

    def warn(self, text: str) -> None:
        """A warning of the run."""
        self._count_event()
        self.state.warnings.append(text)
        self.run_warnings.append(text)


def _check_set(v: object) -> None:
    """Fail on an element or field of ``v`` that has no value (WRITE prints whole values)."""
    if isinstance(v, ArrayValue):
        for i, item in enumerate(v.items):
            if item is UNSET:
                raise RunFailure(f"element [{v.low + i}] is used before it has a value")
            _check_set(item)
    elif isinstance(v, RecordValue):
        for name, item in v.fields:
            if item is UNSET:
                raise RunFailure(f"field '{name}' is used before it has a value")
            _check_set(item)
    elif isinstance(v, Ref):
        raise B.malformed("WRITE of a reference")
