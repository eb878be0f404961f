"""Interpreter: MOVE records, system variables, modal options, WAIT, WAIT FOR, signals."""

from __future__ import annotations

import pytest
from irlc.lang.diagnostics import CompileError
from irlc.runtime.commands import Settings
from irlc.runtime.errors import RunFailure
from irlc.runtime.values import JointTuple, Pose

from .test_interpreter_fakes import HEADER, FakeController, code_of, failure, main_program, run

JOINT_CONSTS = """CONST 0 MAIN_JOINT 10.0 20.0 30.0
CONST 1 MAIN_JOINT_MIN -90.0 -90.0 0.0
CONST 2 MAIN_JOINT_MAX 90.0 90.0 500.0
CONST 3 POSE 1000.0 0.0 0.0 0.0 0.0 0.0
CONST 4 POSE 1200.0 100.0 0.0 0.0 0.0 0.0
CONST 5 REAL 250.0
CONST 6 REAL 2.5
CONST 7 MAIN_JOINT 0.0 0.0 0.0
CONST 8 MAIN_JOINT_SPEED_MIN -10.0 -10.0 -5.0
CONST 9 MAIN_JOINT_SPEED_MAX 10.0 10.0 5.0
CONST 10 INTEGER 150
CONST 11 MAIN_JOINT_MIN 15.0 -90.0 0.0
CONST 12 MAIN_JOINT_SPEED_MIN 1.0 -10.0 -5.0
CONST 13 MAIN_JOINT_MAX 90.0 90.0 20.0"""


def program(body: str, **kwargs):
    return main_program(body, consts=JOINT_CONSTS, **kwargs)


# ------------------------------------------------------------------ MOVE


def test_move_ptp_to_joints():
    ctl = FakeController()
    run(program("main: L4 PUSHC 0\nL4 MOVE PTP 1\nL5 END"), ctl)
    ((cmd, settings, _),) = ctl.moves
    assert cmd.kind == "PTP" and cmd.line == 4
    assert cmd.targets == (JointTuple("MAIN_JOINT", (10.0, 20.0, 30.0)),)
    assert cmd.speed is None and cmd.joint_limits is None
    assert settings == Settings()
    assert ctl.q == [10.0, 20.0, 30.0]


def test_move_lin_with_clauses_in_record_order():
    body = """main: L7 PUSHC 3
    L7 PUSHC 4
    L7 PUSHC 5
    L7 PUSHC 6
    L7 PUSHC 1
    L7 PUSHC 2
    L7 PUSHC 7
    L7 PUSHC 0
    L7 MOVE LIN 2 SPEED TIME JOINTLIMIT RECONF:2
    L8 END"""
    ctl = FakeController()
    run(program(body), ctl)
    ((cmd, _, _),) = ctl.moves
    assert cmd.kind == "LIN" and cmd.line == 7
    assert [t.pos.x for t in cmd.targets] == [1000.0, 1200.0]
    assert cmd.speed == 250.0 and cmd.time == 2.5
    assert cmd.joint_limits[0].values == (-90.0, -90.0, 0.0)
    assert cmd.joint_limits[1].type == "MAIN_JOINT_MAX"
    assert [k.values for k in cmd.reconfiguration] == [(0.0, 0.0, 0.0), (10.0, 20.0, 30.0)]


def test_move_with_speed_ptp_above_100_percent_is_an_error():
    err = failure(program("main: L3 PUSHC 0\nL3 PUSHC 10\nL3 MOVE PTP 1 SPEED_PTP\nL4 END"))
    assert err.message == "WITH SPEED_PTP := 150.0: the value must be in (0, 100] %"
    assert err.line == 3


def test_move_with_a_limit_that_excludes_the_current_joints():
    ctl = FakeController(joints=(10.0, 0.0, 0.0))
    err = failure(
        program("main: L3 PUSHC 3\nL3 PUSHC 11\nL3 PUSHC 2\nL3 MOVE LIN 1 JOINTLIMIT\nL4 END"), ctl
    )
    assert err.message == (
        "JOINTLIMIT excludes the current state: joint a1 is at 10.0 deg,"
        " below the lower bound 15.0 deg"
    )
    assert ctl.moves == []


def test_move_lin_to_joints_is_malformed():
    err = failure(program("main: L3 PUSHC 0\nL3 MOVE LIN 1\nL4 END"))
    assert "MOVE LIN needs POSE targets, got MAIN_JOINT" in err.message


def test_move_ptpinc_and_circle():
    body = """main: L1 PUSHC 0
    L1 MOVE PTPINC 1
    L2 PUSHC 3
    L2 PUSHC 4
    L2 MOVE CIRCLE 2
    L3 END"""
    ctl = FakeController(joints=(1.0, 1.0, 1.0))
    run(program(body), ctl)
    assert [m[0].kind for m in ctl.moves] == ["PTPINC", "CIRCLE"]
    assert ctl.q == [11.0, 21.0, 31.0]
    assert ctl.moves[1][0].targets[0].pos.x == 1000.0


def test_controller_failure_gets_the_line_and_time():
    ctl = FakeController()
    ctl.fail_move = RunFailure("target unreachable")
    ctl.t = 4.25
    err = failure(program("main: L1 PUSHC 0\nL1 MOVE PTP 1\nL2 END"), ctl)
    assert (err.message, err.line, err.time_s) == ("target unreachable", 1, 4.25)


def test_other_controller_exceptions_are_not_disguised():
    class Broken(FakeController):
        def move(self, cmd, settings, options):
            raise ZeroDivisionError("bug in the controller")

    with pytest.raises(ZeroDivisionError, match="bug in the controller"):
        run(program("main: L1 PUSHC 0\nL1 MOVE PTP 1\nL2 END"), Broken())


# ------------------------------------------------------------------ system variables


def test_system_variables_reach_the_controller_as_a_snapshot():
    body = """main: L1 PUSHC 5
    L1 POPSYS R_SPEED
    L2 PUSHC 4
    L2 POPSYS R_TOOL
    L3 PUSHC 3
    L3 MOVE LIN 1
    L4 PUSHC 6
    L4 POPSYS R_SPEED
    L5 PUSHSYS R_SPEED
    L5 PUSHSYS R_IPO
    L5 WRITELN 2
    L6 END"""
    ctl = FakeController()
    result = run(program(body), ctl)
    ((_, settings, _),) = ctl.moves
    assert settings.speed == 250.0  # not changed by the later R_SPEED := 2.5
    assert isinstance(settings.tool, Pose) and settings.tool.pos.x == 1200.0
    assert result.output == ["2.50.01"]
    assert result.state.settings.speed == 2.5


@pytest.mark.parametrize(
    ("var", "const", "message"),
    [
        ("R_SPEED_PTP", 10, "R_SPEED_PTP := 150.0: the value must be in (0, 100] %"),
        ("R_IPO", 5, "R_IPO := 250.0: the value must be in [1e-05, 1] s"),
    ],
)
def test_bad_system_variable_values(var, const, message):
    err = failure(program(f"main: L2 PUSHC {const}\nL2 POPSYS {var}\nL3 END"))
    assert err.message == message
    assert err.line == 2


def test_settings_passed_in_are_used():
    body = "main: L1 PUSHSYS R_IPO\nL1 WRITELN 1\nL2 END"
    assert run(program(body), settings=Settings(ipo=0.004)).output == ["0.004"]


# ------------------------------------------------------------------ modal options


def test_jointlimit_block_on_and_off():
    body = """main: L1 PUSHC 1
    L1 PUSHC 2
    L1 OPTON JOINTLIMIT
    L2 PUSHC 8
    L2 PUSHC 9
    L2 OPTON JOINTSPEEDLIMIT
    L3 PUSHC 0
    L3 MOVE PTP 1
    L4 OPTOFF JOINTLIMIT
    L5 PUSHC 7
    L5 MOVE PTP 1
    L6 OPTOFF JOINTSPEEDLIMIT
    L7 END"""
    ctl = FakeController()
    result = run(program(body), ctl)
    first, second = ctl.moves[0][2], ctl.moves[1][2]
    assert first.joint_limits[0].values == (-90.0, -90.0, 0.0)
    assert first.speed_limits[1].values == (10.0, 10.0, 5.0)
    assert second.joint_limits is None and second.speed_limits is not None
    assert result.state.options.speed_limits is None


def test_jointlimit_that_excludes_the_current_state_names_joint_value_and_bound():
    ctl = FakeController(joints=(0.0, 0.0, 42.0))
    err = failure(program("main: L1 PUSHC 1\nL1 PUSHC 13\nL1 OPTON JOINTLIMIT\nL2 END"), ctl)
    assert err.message == (
        "JOINTLIMIT excludes the current state: joint a3 is at 42.0 mm,"
        " above the upper bound 20.0 mm"
    )
    assert err.constraint == "joint a3 position max 20.0 mm"
    assert err.line == 1


def test_speed_limit_must_contain_zero():
    err = failure(program("main: L2 PUSHC 12\nL2 PUSHC 9\nL2 OPTON JOINTSPEEDLIMIT\nL3 END"))
    assert err.message == (
        "JOINTSPEEDLIMIT must allow standing still: joint a1 has the bounds [1.0, 10.0] deg/s,"
        " which exclude 0"
    )


def test_limit_with_lower_above_upper():
    err = failure(program("main: L2 PUSHC 2\nL2 PUSHC 1\nL2 OPTON JOINTACCELLIMIT\nL3 END"))
    assert err.message == (
        "JOINTACCELLIMIT: joint a1 has the lower bound 90.0 deg/s²"
        " above the upper bound -90.0 deg/s²"
    )


def test_option_twice_and_off_when_not_on_are_errors():
    err = failure(program("main: L1 OPTON CYCLIC\nL2 OPTON CYCLIC\nL3 END"))
    assert (err.message, err.line) == ("CYCLICSTART while CYCLIC is already on", 2)
    err = failure(program("main: L4 OPTOFF JOINTLIMIT\nL5 END"))
    assert (err.message, err.line) == ("JOINTLIMIT is switched off but it is not on", 4)
    twice = "L1 PUSHC 1\nL1 PUSHC 2\nL1 OPTON JOINTLIMIT\n"
    err = failure(program(f"main: {twice}{twice.replace('L1', 'L2')}L3 END"))
    assert err.message == "JOINTLIMIT is already on (close it with JOINTLIMITEND first)"


def test_cyclic_reference_is_the_configuration_at_cyclicstart():
    body = """main: L1 PUSHC 0
    L1 MOVE PTP 1
    L2 OPTON CYCLIC
    L3 PUSHC 3
    L3 MOVE LIN 1
    L4 OPTOFF CYCLIC
    L5 END"""
    ctl = FakeController()
    result = run(program(body), ctl)
    assert ctl.moves[0][2].cyclic_reference is None
    assert ctl.moves[1][2].cyclic_reference == (10.0, 20.0, 30.0)
    assert result.state.options.cyclic_reference is None


OBSTACLES = (
    "OBSTACLE sciana_1 box center 10500.0 -2500.0 2000.0 size 4000.0 200.0 4000.0\n"
    "OBSTACLE okno sphere center 0.0 0.0 0.0 radius 100.0"
)


def obstacle_program(body: str):
    text = f"{OBSTACLES}\n{JOINT_CONSTS}\nROUTINE 0 t MAIN 0 0 @main\nCODE\n{body}"
    return code_of(text)


def test_obstacles_on_and_off():
    body = """main: L1 OPTON OBSTACLE sciana_1
    L2 OPTON OBSTACLE OKNO
    L3 PUSHC 3
    L3 MOVE LIN 1
    L4 OPTOFF OBSTACLE sciana_1
    L5 PUSHC 3
    L5 MOVE LIN 1
    L6 END"""
    ctl = FakeController()
    run(obstacle_program(body), ctl)
    assert ctl.moves[0][2].obstacles == ("sciana_1", "okno")
    assert ctl.moves[1][2].obstacles == ("okno",)


def test_unknown_repeated_and_inactive_obstacles():
    err = failure(obstacle_program("main: L3 OPTON OBSTACLE wall\nL4 END"))
    assert (err.message, err.line) == ("unknown obstacle 'wall' (known: sciana_1, okno)", 3)
    err = failure(obstacle_program("main: L1 OPTON OBSTACLE okno\nL2 OPTON OBSTACLE okno\nL3 END"))
    assert err.message == "OBSTACLE okno is already on"
    err = failure(obstacle_program("main: L1 OPTOFF OBSTACLE okno\nL3 END"))
    assert err.message == "OBSTACLE okno is switched off but it is not on"


def test_freeze_holds_the_current_values_of_the_named_joints():
    body = """main: L1 PUSHC 0
    L1 MOVE PTP 1
    L2 OPTON FREEZE 1 3
    L3 PUSHC 3
    L3 MOVE LIN 1
    L4 OPTOFF FREEZE
    L5 END"""
    ctl = FakeController()
    result = run(program(body), ctl)
    assert ctl.moves[1][2].frozen == {0: 10.0, 2: 30.0}
    assert result.state.options.frozen == {}
    with pytest.raises(CompileError, match=r"OPTON FREEZE: expected joint numbers in 1\.\.3"):
        program("main: L1 OPTON FREEZE 4\nL2 END")  # the .ird reader refuses it, positioned


def test_options_given_to_the_controller_are_snapshots():
    body = "main: L1 OPTON FREEZE 2\nL2 PUSHC 3\nL2 MOVE LIN 1\nL3 OPTOFF FREEZE\nL4 END"
    ctl = FakeController(joints=(1.0, 2.0, 3.0))
    run(program(body), ctl)
    assert ctl.moves[0][2].frozen == {1: 2.0}


def test_reconfiguration_statement():
    ctl = FakeController()
    run(program("main: L1 OPTON CYCLIC\nL6 PUSHC 0\nL6 RECONF\nL7 END"), ctl)
    ((target, line, options),) = ctl.reconfs
    assert target.values == (10.0, 20.0, 30.0) and line == 6
    assert options.cyclic_reference == (0.0, 0.0, 0.0)


# ------------------------------------------------------------------ WAIT, inputs, signals


def test_wait_advances_simulated_time_and_rejects_negative_times():
    ctl = FakeController()
    run(program("main: L1 PUSHC 6\nL1 WAIT\nL2 END"), ctl)
    assert ctl.waits == [(2.5, 1)] and ctl.t == 2.5
    err = failure(program("main: L1 PUSHC 6\nL1 NEG\nL1 WAIT\nL2 END"))
    assert err.message == "WAIT -2.5 SEC: the time must not be negative"


def input_program(inputs: str, body: str, decls: str = ""):
    text = f"{inputs}\nCONST 0 INTEGER 2\nCONST 1 STRING 'go'\nCONST 2 INTEGER 3\n{decls}\n"
    text += f"ROUTINE 0 t MAIN 0 0 @main\nCODE\n{body}"
    return code_of(text, HEADER)


WAIT_FOR_IN2 = """main: cond: L5 PUSHC 0
L5 PUSHIN
L5 WAITFOR @cond
L6 PUSHC 1
L6 WRITELN 1
L7 END"""


@pytest.mark.parametrize("ipo", [None, 0.01, 0.004])
def test_wait_for_advances_to_the_input_event(ipo):
    code = input_program("INPUT 2 0.0 FALSE 1.0 FALSE 3.5 TRUE", WAIT_FOR_IN2)
    ctl = FakeController(ipo=ipo)
    result = run(code, ctl)
    assert result.output == ["go"]
    assert ctl.t == pytest.approx(3.5, abs=ipo or 1e-12)
    assert all(line == 5 for _, line in ctl.waits)


def test_wait_for_a_condition_over_two_inputs():
    """WAIT FOR IN[2] AND IN[3]: IN[2] rises at 1 s, IN[3] at 2 s, IN[2] falls at 2.5 s."""
    body = """main: c: L5 PUSHC 0
    L5 PUSHIN
    L5 PUSHC 2
    L5 PUSHIN
    L5 AND
    L5 WAITFOR @c
    L6 END"""
    code = input_program("INPUT 2 1.0 TRUE 2.5 FALSE\nINPUT 3 2.0 TRUE", body)
    ctl = FakeController()
    run(code, ctl)
    assert ctl.t == 2.0
    assert [w for w, _ in ctl.waits] == [1.0, 1.0]


def test_wait_for_that_can_never_become_true():
    code = input_program("INPUT 2 0.0 FALSE", WAIT_FOR_IN2)
    err = failure(code)
    assert err.message.startswith("WAIT FOR can never become true: no input changes any more")
    assert err.line == 5


def test_wait_for_times_out_when_the_change_comes_too_late():
    code = input_program("INPUT 2 100.0 TRUE", WAIT_FOR_IN2)
    ctl = FakeController()
    err = failure(code, ctl, wait_timeout=60.0)
    assert err.message == (
        "WAIT FOR can never become true: the next input change is at t = 100.0 s,"
        " and the time-out is 60.0 s (waiting since t = 0.0 s)"
    )
    assert ctl.waits == []
    assert run(code, FakeController(), wait_timeout=120.0).output == ["go"]


def test_input_without_a_timeline_is_false_and_true_conditions_do_not_wait():
    body = """main: L1 PUSHC 2
    L1 PUSHIN
    L1 WRITELN 1
    c: L2 PUSHC 2
    L2 PUSHIN
    L2 NOT
    L2 WAITFOR @c
    L3 END"""
    ctl = FakeController()
    assert run(input_program("", body), ctl).output == ["FALSE"]
    assert ctl.waits == []


def test_signal_outputs_are_stored_and_logged():
    body = """main: L1 PUSHG 0
    L1 WRITELN 1
    L2 PUSHC 6
    L2 WAIT
    L3 PUSHC 14
    L3 SIGOUT 0
    L4 PUSHG 0
    L4 WRITELN 1
    L5 END"""
    consts = JOINT_CONSTS + "\nCONST 14 BOOLEAN TRUE"
    ctl = FakeController()
    result = run(main_program(body, decls="GLOBAL 0 SIGNAL gripper", consts=consts), ctl)
    assert result.output == ["FALSE", "TRUE"]  # outputs start FALSE
    signal = {"kind": "signal", "line": 3, "time_s": 2.5, "name": "gripper", "value": True}
    assert ctl.events == [signal]
    assert result.events == ctl.events


def test_motion_resets_the_instruction_budget():
    """A loop of 40 MOVEs runs ~10 instructions between motions: fine under a budget of 50."""
    decls = "GLOBAL 0 INTEGER i"
    consts = JOINT_CONSTS + "\nCONST 14 INTEGER 0\nCONST 15 INTEGER 1\nCONST 16 INTEGER 40"
    body = """main: L1 PUSHC 14
    L1 POPG 0
    top: L2 PUSHG 0
    L2 PUSHC 16
    L2 LT
    L2 JF @done
    L3 PUSHC 3
    L3 MOVE LIN 1
    L4 PUSHG 0
    L4 PUSHC 15
    L4 ADD
    L4 POPG 0
    L4 JMP @top
    done: L5 END"""
    ctl = FakeController()
    result = run(main_program(body, decls=decls, consts=consts), ctl, instruction_budget=50)
    assert len(ctl.moves) == 40
    assert result.instructions > 50
