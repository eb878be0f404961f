"""The time and I/O instructions: WAIT, WAIT FOR, digital inputs and outputs, SIGNAL
outputs, WRITE / WRITELN, and the run's events (``docs/irdata.md``, ``docs/interpreter.md``).

A mixin of :class:`~irlc.runtime.interpreter.machine.Interpreter` (the handlers use its
operand stack, :class:`MachineState` and controller). Simulated time is the controller's.
An input's value at time ``t`` is the last change at or before ``t`` (a tolerance of
:data:`TIME_TOLERANCE`); inputs are read at ``max(controller time, state.input_clock)``, so
a WAIT FOR that jumps to an input change moves the input clock even when the controller
has no motion to simulate. Text written by WRITE stays on an open line until WRITELN (or
the end of the run) emits it.
"""

from __future__ import annotations

from irlc.lang.digital_io import output_error, pulse_error
from irlc.runtime import values as V
from irlc.runtime.errors import RunFailure
from irlc.runtime.interpreter import builtins as B
from irlc.runtime.interpreter.datatypes import number
from irlc.runtime.interpreter.state import UNSET, Ref
from irlc.runtime.outputs.digital_io import value_at
from irlc.runtime.values import ArrayValue, RecordValue

TIME_TOLERANCE = 1e-9  # s, when comparing simulated time with input event times
MAX_OUTPUT_CHARS = 10_000_000  # the most characters one run writes (WRITE, WRITELN)
MAX_EVENTS = 200_000  # the most events (signals, outputs, PAUSE, …) and warnings of a run


class IoOps:
    """``WAIT`` … ``WRITELN``; see the module docstring."""

    # ------------------------------------------------------------------ waiting

    def _op_wait(self, args) -> None:
        s = number(self.stack.pop(), "WAIT")
        if s < 0:
            raise RunFailure(f"WAIT {V.format_real(s)} SEC: the time must not be negative")
        self._stop_advance(f"WAIT at line {self._line()}")
        if s > 0:
            t_before = self._time()
            self._ctl(self.controller.wait, s, self._line(), *self._snapshot())
            self._waited(t_before)

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

    def _stop_advance(self, why: str) -> None:
        """The advance run stops here: a pending approximated motion ends exactly at its
        point first (WAIT, WAIT FOR, reading an input, the end of the program)."""
        flush = getattr(self.controller, "flush", None)
        if flush is not None:
            self._ctl(flush, why)

    # ------------------------------------------------------------------ inputs

    def _now(self) -> float:
        return max(self._time(), self.state.input_clock)

    def _input(self, n: int, t: float) -> bool:
        return value_at(self._inputs.get(n, ()), t)

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

    def _op_pushin(self, args) -> None:
        n = self.stack.pop()
        if not isinstance(n, int) or isinstance(n, bool):
            raise B.malformed(f"an input number must be an INTEGER, got {V.type_name(n)}")
        self._stop_advance(f"line {self._line()} reads input {n}")
        self._push(self._input(n, self._now()))

    # ------------------------------------------------------------------ outputs

    def _op_sigout(self, args) -> None:
        slot = self.code.globals[args[0]]
        v = self.types.coerce(self.stack.pop(), "BOOLEAN", f"signal {slot.name!r}")
        self.state.globals[args[0]] = v
        self._event("signal", name=slot.name, value=v)

    def _output_number(self) -> int:
        n = self.stack.pop()
        if not isinstance(n, int) or isinstance(n, bool):
            raise B.malformed(f"an output number must be an INTEGER, got {V.type_name(n)}")
        error = output_error(n)
        if error is not None:
            raise RunFailure(error)
        return n

    def _op_outset(self, args) -> None:
        """``OUT[n] := b``: switch now (the statement's time in the advance run)."""
        v = self.types.coerce(self.stack.pop(), "BOOLEAN", "OUT[…]")
        n = self._output_number()
        self._drop_event(self.state.outputs.set(n, self._time(), v))
        self._event("output", output=n, value=v)

    def _op_pushout(self, args) -> None:
        n = self._output_number()
        self._push(self.state.outputs.value(n, self._time()))

    def _op_pulse(self, args) -> None:
        """``PULSE(OUT[n], d)``: TRUE now, FALSE ``d`` s later; the program goes on."""
        d = number(self.stack.pop(), "PULSE")
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
        """Remove a pulse's end that an assignment overrode (``digital_io.Outputs.set``),
        searching from the newest event (it is among the last)."""
        if event is None:
            return
        for events in (self.state.events, self._run_events):
            for i in range(len(events) - 1, -1, -1):
                if events[i] is event:
                    del events[i]
                    break

    # ------------------------------------------------------------------ text output

    def _write(self, argc: int) -> None:
        """The values' text onto the open line; a run writes at most
        :data:`MAX_OUTPUT_CHARS` characters (checked before a value's text is built)."""
        for v in self._pop_n(argc):
            _check_set(v)
            if self._written + V.text_bound(v) > MAX_OUTPUT_CHARS:
                raise RunFailure(
                    f"the program's output would exceed {MAX_OUTPUT_CHARS} characters"
                    " — endless loop?"
                )
            text = V.format_value(v)
            self._written += len(text)
            self._line_buffer.append(text)

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

    # ------------------------------------------------------------------ events and warnings

    def _count_event(self) -> None:
        """A run logs at most :data:`MAX_EVENTS` events and warnings."""
        if len(self._run_events) + len(self._run_warnings) >= MAX_EVENTS:
            raise RunFailure(
                f"more than {MAX_EVENTS} events (signals, outputs, PAUSE …) and warnings"
                " in one run — endless loop?"
            )

    def _event(self, kind: str, **data) -> None:
        self._count_event()
        line = self._line()
        event = {"kind": kind, "line": line, "time_s": self._time(), **data}
        self.state.events.append(event)
        self._run_events.append(event)
        self._ctl(self.controller.log_event, kind, line, **data)

    def _warn(self, text: str) -> None:
        self._count_event()
        self.state.warnings.append(text)
        self._run_warnings.append(text)


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
