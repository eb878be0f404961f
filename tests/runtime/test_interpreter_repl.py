"""Interpreter: incremental execution with a carried-over MachineState (the REPL's use)."""

from __future__ import annotations

import pytest
from irlc.runtime.errors import RunFailure
from irlc.runtime.interpreter import Interpreter, MachineState

from .test_interpreter_fakes import FakeController, main_program

CONSTS = """CONST 0 INTEGER 5
CONST 1 REAL 120.0
CONST 2 MAIN_JOINT_MIN -90.0 -90.0 0.0
CONST 3 MAIN_JOINT_MAX 90.0 90.0 500.0
CONST 4 INTEGER 1
CONST 5 STRING 'x = '"""

# chunk 1:  VAR INTEGER: x;  x := 5; R_SPEED := 120; JOINTLIMIT jmin, jmax; WRITE('x = ', x);
CHUNK1 = main_program(
    """main: L1 PUSHC 0
    L1 POPG 0
    L2 PUSHC 1
    L2 POPSYS R_SPEED
    L3 PUSHC 2
    L3 PUSHC 3
    L3 OPTON JOINTLIMIT
    L4 PUSHC 5
    L4 PUSHG 0
    L4 WRITE 2
    L5 END""",
    decls="GLOBAL 0 INTEGER x",
    consts=CONSTS,
)

# chunk 2 adds  VAR REAL: y;  y := x + 1; WRITELN(y); JOINTLIMITEND;
CHUNK2 = main_program(
    """main: L1 PUSHG 0
    L1 PUSHC 4
    L1 ADD
    L1 POPG 1
    L2 PUSHG 1
    L2 PUSHSYS R_SPEED
    L2 WRITELN 2
    L3 OPTOFF JOINTLIMIT
    L4 END""",
    decls="GLOBAL 0 INTEGER x\nGLOBAL 1 REAL y",
    consts=CONSTS,
)


def test_values_settings_and_options_persist_between_chunks():
    ctl = FakeController()
    printed: list[str] = []
    first = Interpreter(CHUNK1, ctl, output=printed.append).run()
    assert first.output == ["x = 5"]  # an open WRITE line is flushed at the end of a chunk
    assert first.state.options.joint_limits is not None
    second = Interpreter(CHUNK2, ctl, state=first.state, output=printed.append).run()
    assert second.output == ["6.0120.0"]
    assert second.state is first.state
    assert second.state.value("y") == 6.0
    assert second.state.options.joint_limits is None
    assert second.state.output == ["x = 5", "6.0120.0"]
    assert printed == second.state.output


def test_a_failed_chunk_keeps_what_it_did_before_failing():
    ctl = FakeController()
    state = Interpreter(CHUNK1, ctl).run().state
    # JOINTLIMIT again while it is on: fails, x := 7 before it stays
    chunk = main_program(
        """main: L1 PUSHC 6
        L1 POPG 0
        L2 PUSHC 2
        L2 PUSHC 3
        L2 OPTON JOINTLIMIT
        L3 END""",
        decls="GLOBAL 0 INTEGER x",
        consts=CONSTS + "\nCONST 6 INTEGER 7",
    )
    interp = Interpreter(chunk, ctl, state=state)
    with pytest.raises(RunFailure, match="JOINTLIMIT is already on") as info:
        interp.run()
    assert info.value.line == 2
    assert interp.result.status == "failed"
    assert state.value("x") == 7
    assert Interpreter(CHUNK2, ctl, state=state).run().output == ["8.0120.0"]


def test_a_chunk_that_does_not_extend_the_declarations_is_refused():
    state = Interpreter(CHUNK1, FakeController()).run().state
    other = main_program("main: L1 END", decls="GLOBAL 0 REAL x", consts=CONSTS)
    with pytest.raises(RunFailure, match="global 0 is REAL 'x' in the code but INTEGER 'x'"):
        Interpreter(other, FakeController(), state=state).run()
    fewer = main_program("main: L1 END", consts=CONSTS)
    with pytest.raises(RunFailure, match="does not extend the previous declarations"):
        Interpreter(fewer, FakeController(), state=state).run()


def test_fresh_state_defaults_and_single_use():
    state = MachineState()
    interp = Interpreter(CHUNK1, FakeController(), state=state)
    interp.run()
    assert state.settings.speed == 120.0
    with pytest.raises(RuntimeError):
        interp.run()
    assert state.value("nope") is None
