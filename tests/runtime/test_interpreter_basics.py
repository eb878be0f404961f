"""Interpreter: scalars, operators, variables, control flow, routines, output, errors."""

from __future__ import annotations

import pytest
from irlc.lang.irdata import Code, Instruction, Routine, Slot, Value
from irlc.runtime.interpreter import Interpreter

from .test_interpreter_fakes import FakeController, failure, main_program, run


def out(code: Code, **kwargs) -> list[str]:
    return run(code, **kwargs).output


def calc(consts: list[str], op: str) -> str:
    """``consts`` pushed in order, then ``op``, then WRITELN."""
    cs = "\n".join(f"CONST {k} {c}" for k, c in enumerate(consts))
    pushes = "\n".join(f"L1 PUSHC {k}" for k in range(len(consts)))
    body = f"main: {pushes}\nL1 {op}\nL2 WRITELN 1\nL3 END"
    return out(main_program(body, consts=cs))[0]


def calc_error(consts: list[str], op: str):
    cs = "\n".join(f"CONST {k} {c}" for k, c in enumerate(consts))
    pushes = "\n".join(f"L7 PUSHC {k}" for k in range(len(consts)))
    return failure(main_program(f"main: {pushes}\nL7 {op}\nL8 WRITELN 1\nL9 END", consts=cs))


# ------------------------------------------------------------------ arithmetic (Pascal rules)


@pytest.mark.parametrize(
    ("consts", "op", "expected"),
    [
        (["INTEGER 7", "INTEGER 2"], "ADD", "9"),
        (["INTEGER 7", "INTEGER 2"], "SUB", "5"),
        (["INTEGER 7", "INTEGER 2"], "MUL", "14"),
        (["INTEGER 7", "INTEGER 2"], "DIV", "3.5"),  # / is always REAL
        (["INTEGER 6", "INTEGER 2"], "DIV", "3.0"),
        (["INTEGER 7", "INTEGER 2"], "IDIV", "3"),
        (["INTEGER -7", "INTEGER 2"], "IDIV", "-3"),  # truncation toward zero
        (["INTEGER 7", "INTEGER -2"], "IDIV", "-3"),
        (["INTEGER 7", "INTEGER 3"], "MOD", "1"),
        (["INTEGER -7", "INTEGER 3"], "MOD", "-1"),  # sign of the dividend
        (["INTEGER 7", "INTEGER -3"], "MOD", "1"),
        (["INTEGER 2", "REAL 0.5"], "ADD", "2.5"),  # mixed → REAL
        (["REAL 0.1", "REAL 0.2"], "ADD", "0.3"),  # printed rounded to 6 decimals
        (["REAL 2.0", "INTEGER 3"], "MUL", "6.0"),
        (["STRING 'ab'", "CHAR 'c'"], "ADD", "abc"),
    ],
)
def test_arithmetic(consts, op, expected):
    assert calc(consts, op) == expected


def test_unary_and_logic():
    assert calc(["INTEGER 4"], "NEG") == "-4"
    assert calc(["REAL 1.5"], "NEG") == "-1.5"
    assert calc(["BOOLEAN TRUE"], "NOT") == "FALSE"
    assert calc(["BOOLEAN TRUE", "BOOLEAN FALSE"], "AND") == "FALSE"
    assert calc(["BOOLEAN TRUE", "BOOLEAN FALSE"], "OR") == "TRUE"
    assert calc(["BOOLEAN TRUE", "BOOLEAN TRUE"], "XOR") == "FALSE"
    assert calc(["BOOLEAN TRUE", "BOOLEAN FALSE"], "XOR") == "TRUE"


@pytest.mark.parametrize(
    ("a", "b", "results"),  # EQ NE LT GT LE GE
    [
        ("INTEGER 2", "REAL 2.0", "TRUE FALSE FALSE FALSE TRUE TRUE"),
        ("INTEGER 1", "INTEGER 2", "FALSE TRUE TRUE FALSE TRUE FALSE"),
        ("STRING 'b'", "STRING 'a'", "FALSE TRUE FALSE TRUE FALSE TRUE"),
    ],
)
def test_comparisons(a, b, results):
    got = [calc([a, b], op) for op in ("EQ", "NE", "LT", "GT", "LE", "GE")]
    assert got == results.split()


def test_geometric_equality_treats_q_and_minus_q_alike():
    # ORIQUAT(-1,0,0,0) is normalised to w ≥ 0: equal to the identity
    assert calc(["ORIENTATION 1.0 0.0 0.0 0.0", "ORIENTATION -1.0 0.0 0.0 0.0"], "EQ") == "TRUE"
    assert calc(["POSITION 1.0 2.0 3.0", "POSITION 1.0 2.0 3.5"], "NE") == "TRUE"


@pytest.mark.parametrize(
    ("consts", "op", "message"),
    [
        (["REAL 1.0", "INTEGER 0"], "DIV", "division by zero"),
        (["INTEGER 1", "INTEGER 0"], "IDIV", "division by zero in DIV"),
        (["INTEGER 1", "INTEGER 0"], "MOD", "division by zero in MOD"),
        (["REAL 1e300", "REAL 1e300"], "MUL", "not a finite number"),
        (["INTEGER 9223372036854775807", "INTEGER 1"], "ADD", "INTEGER overflow"),
        (["REAL 1.5"], "CALLB ASIN 1", "ASIN(1.5): the argument is outside [-1, 1]"),
        (["REAL -1.01"], "CALLB ACOS 1", "ACOS(-1.01)"),
        (["REAL -4.0"], "CALLB SQRT 1", "SQRT(-4.0): the argument is negative"),
        (["REAL 90.0"], "CALLB TAN 1", "TAN(90.0) is undefined"),
        (["REAL 1.0", "INTEGER 2"], "IDIV", "malformed"),
        (["STRING 'ab'", "REAL 2.0"], "SUB", "cannot subtract STRING and REAL"),
    ],
)
def test_run_time_errors_of_operators_carry_line_and_time(consts, op, message):
    err = calc_error(consts, op)
    assert message in err.message
    assert err.line == 7
    assert err.time_s == 0.0


# ------------------------------------------------------------------ built-in scalar functions


@pytest.mark.parametrize(
    ("call", "args", "expected"),
    [
        ("SIN", ["REAL 30.0"], "0.5"),
        ("SIN", ["INTEGER 180"], "0.0"),  # exact at multiples of 90°
        ("COS", ["REAL 60.0"], "0.5"),
        ("COS", ["REAL -270.0"], "0.0"),
        ("TAN", ["REAL 45.0"], "1.0"),
        ("ASIN", ["REAL 0.5"], "30.0"),
        ("ACOS", ["REAL 0.5"], "60.0"),
        ("ATAN", ["REAL 1.0"], "45.0"),
        ("ATAN2", ["REAL 1.0", "REAL -1.0"], "135.0"),
        ("SQRT", ["INTEGER 16"], "4.0"),
        ("ABS", ["INTEGER -3"], "3"),
        ("ABS", ["REAL -3.25"], "3.25"),
        ("MIN", ["INTEGER 3", "INTEGER -2", "INTEGER 5"], "-2"),
        ("MAX", ["INTEGER 3", "REAL 4.5"], "4.5"),
        ("ROUND", ["REAL 2.5"], "3"),  # halves away from zero
        ("ROUND", ["REAL -2.5"], "-3"),
        ("ROUND", ["REAL 2.4999"], "2"),
        ("TRUNC", ["REAL -2.7"], "-2"),
    ],
)
def test_scalar_builtins(call, args, expected):
    assert calc(args, f"CALLB {call} {len(args)}") == expected


def test_acos_accepts_rounding_just_above_one():
    assert calc(["REAL 1.0000000000001"], "CALLB ACOS 1") == "0.0"


# ------------------------------------------------------------------ WRITE formatting


def test_write_formats_every_kind_of_value():
    consts = "\n".join(
        [
            "CONST 0 INTEGER 42",
            "CONST 1 REAL 2000.0",
            "CONST 2 REAL 0.333333333",
            "CONST 3 BOOLEAN TRUE",
            "CONST 4 STRING 'it''s'",
            "CONST 5 POSITION 1.0 2.5 -3.0",
            "CONST 6 POSE 100.0 200.0 300.0 90.0 0.0 0.0",
            "CONST 7 MAIN_JOINT 10.0 -75.0 120.5",
            "CONST 8 REAL -0.0000001",
            "CONST 9 REAL 1e20",
            "CONST 10 STRING ' '",
        ]
    )
    body = """main: L1 PUSHC 0
    L1 PUSHC 10
    L1 PUSHC 1
    L1 PUSHC 10
    L1 PUSHC 2
    L1 WRITE 5
    L2 PUSHC 3
    L2 PUSHC 4
    L2 WRITELN 2
    L3 PUSHC 5
    L3 WRITELN 1
    L4 PUSHC 6
    L4 WRITELN 1
    L5 PUSHC 7
    L5 PUSHC 8
    L5 PUSHC 9
    L5 WRITELN 3
    L6 PUSHC 4
    L6 WRITE 1
    L7 END"""
    lines: list[str] = []
    result = run(main_program(body, consts=consts), output=lines.append)
    assert result.output == [
        "42 2000.0 0.333333TRUEit's",
        "(1.0, 2.5, -3.0)",
        "(100.0, 200.0, 300.0, 90.0, 0.0, 0.0)",
        "(10.0, -75.0, 120.5)0.01e+20",
        "it's",  # an open WRITE line is flushed at the end
    ]
    assert lines == result.output


def test_output_may_be_a_list():
    lines: list[str] = []
    code = main_program("main: L1 PUSHC 0\nL1 WRITELN 1\nL2 END", consts="CONST 0 INTEGER 1")
    Interpreter(code, FakeController(), output=lines).run()
    assert lines == ["1"]


# ------------------------------------------------------------------ variables


def test_unset_global_is_an_error_naming_it():
    code = main_program("main: L3 PUSHG 0\nL3 WRITELN 1\nL4 END", decls="GLOBAL 0 POSE poz_1")
    err = failure(code)
    assert err.message == "variable 'poz_1' is used before it has a value"
    assert err.line == 3


def test_integer_stored_in_real_variable_becomes_real():
    code = main_program(
        "main: L1 PUSHC 0\nL1 POPG 0\nL2 PUSHG 0\nL2 WRITELN 1\nL3 END",
        decls="GLOBAL 0 REAL v",
        consts="CONST 0 INTEGER 3",
    )
    assert out(code) == ["3.0"]


def test_storing_a_wrong_type_is_malformed_code():
    code = main_program(
        "main: L1 PUSHC 0\nL1 POPG 0\nL2 END",
        decls="GLOBAL 0 INTEGER i",
        consts="CONST 0 POSE 1.0 2.0 3.0 0.0 0.0 0.0",
    )
    err = failure(code)
    assert "cannot store a POSE in variable 'i' of type INTEGER" in err.message
    assert "malformed" in err.message


def test_dup_pop_and_stack_underflow():
    code = main_program(
        "main: L1 PUSHC 0\nL1 DUP\nL1 ADD\nL1 DUP\nL1 POP\nL1 WRITELN 1\nL2 END",
        consts="CONST 0 INTEGER 21",
    )
    assert out(code) == ["42"]
    err = failure(main_program("main: L5 ADD\nL6 END"))
    assert "malformed" in err.message and "stack underflow" in err.message
    assert err.line == 5


def test_running_past_the_end_is_malformed():
    err = failure(main_program("main: L1 PUSHC 0\nL1 POP", consts="CONST 0 INTEGER 1"))
    assert "ran past the last instruction" in err.message


# ------------------------------------------------------------------ control flow


def test_while_loop_sums_1_to_100():
    decls = "GLOBAL 0 INTEGER i\nGLOBAL 1 INTEGER s"
    consts = "CONST 0 INTEGER 1\nCONST 1 INTEGER 0\nCONST 2 INTEGER 100"
    body = """main: L1 PUSHC 0
    L1 POPG 0
    L2 PUSHC 1
    L2 POPG 1
    top: L3 PUSHG 0
    L3 PUSHC 2
    L3 LE
    L3 JF @done
    L4 PUSHG 1
    L4 PUSHG 0
    L4 ADD
    L4 POPG 1
    L5 PUSHG 0
    L5 PUSHC 0
    L5 ADD
    L5 POPG 0
    L5 JMP @top
    done: L6 PUSHG 1
    L6 WRITELN 1
    L7 END"""
    assert out(main_program(body, decls=decls, consts=consts)) == ["5050"]


def case_program(value: int) -> Code:
    """CASE i OF 1: WRITELN('one'); 2, 3: WRITELN('two or three'); ELSE WRITELN('other')."""
    consts = "\n".join(
        [
            f"CONST 0 INTEGER {value}",
            "CONST 1 INTEGER 1",
            "CONST 2 INTEGER 2",
            "CONST 3 INTEGER 3",
            "CONST 4 STRING 'one'",
            "CONST 5 STRING 'two or three'",
            "CONST 6 STRING 'other'",
        ]
    )
    body = """main: L1 PUSHC 0
    L1 POPG 0
    L2 PUSHG 0
    L2 DUP
    L2 PUSHC 1
    L2 EQ
    L2 JT @one
    L2 DUP
    L2 PUSHC 2
    L2 EQ
    L2 JT @two
    L2 DUP
    L2 PUSHC 3
    L2 EQ
    L2 JT @two
    L2 POP
    L5 PUSHC 6
    L5 WRITELN 1
    L5 JMP @end
    one: L3 POP
    L3 PUSHC 4
    L3 WRITELN 1
    L3 JMP @end
    two: L4 POP
    L4 PUSHC 5
    L4 WRITELN 1
    end: L6 END"""
    return main_program(body, decls="GLOBAL 0 INTEGER i", consts=consts)


@pytest.mark.parametrize(
    ("value", "text"), [(1, "one"), (2, "two or three"), (3, "two or three"), (7, "other")]
)
def test_case_jump_table(value, text):
    result = run(case_program(value))
    assert result.output == [text]
    assert result.status == "ok"


def test_halt_stops_with_status_halted_and_an_event():
    code = main_program(
        "main: L1 PUSHC 0\nL1 WRITELN 1\nL2 HALT\nL3 PUSHC 0\nL3 WRITELN 1\nL4 END",
        consts="CONST 0 STRING 'x'",
    )
    ctl = FakeController()
    result = run(code, ctl)
    assert result.status == "halted"
    assert result.output == ["x"]
    assert ctl.events == [{"kind": "halt", "line": 2, "time_s": 0.0}]


def test_pause_logs_an_event_and_a_warning_and_continues():
    code = main_program(
        "main: L4 PAUSE\nL5 PUSHC 0\nL5 WRITELN 1\nL6 END", consts="CONST 0 INTEGER 1"
    )
    ctl = FakeController()
    result = run(code, ctl)
    assert result.output == ["1"]
    assert [e["kind"] for e in result.events] == ["pause"]
    assert ctl.events[0]["line"] == 4
    assert result.warnings == ["line 4: PAUSE in a batch run — execution continues"]


def test_endless_loop_hits_the_instruction_budget():
    err = failure(main_program("main: L9 JMP @main"), instruction_budget=1000)
    assert err.message == (
        "more than 1000 instructions without motion or waiting (a motion that does not "
        "move counts as 250) — "
        "endless loop? If not, raise the budget: --instruction-budget N "
        "(Python: instruction_budget=N)"
    )
    assert err.line == 9


def test_default_budget_is_small_enough_to_report_within_seconds():
    """The default guard: 500 000 instructions (~0.3 s of CPython), not 50 M (~30 s)."""
    from irlc.runtime.interpreter import DEFAULT_INSTRUCTION_BUDGET

    assert DEFAULT_INSTRUCTION_BUDGET == 500_000
    result = Interpreter(main_program("main: L9 JMP @main"), FakeController()).run(check=False)
    assert "endless loop?" in result.error.message
    assert result.instructions == DEFAULT_INSTRUCTION_BUDGET + 1


def test_a_loop_that_only_waits_does_not_spend_the_guard():
    """Waiting is progress, as motion is: ``WHILE TRUE DO WAIT 0.5 SEC; ENDWHILE`` restarts
    the count at every WAIT (the controller's cycle and time budgets bound it; this fake
    has none), so only the run's limit of RUN_BUDGETS budgets stops it — 3 instructions an
    iteration, about 40 · 1000 / 3 WAITs. On main it failed as an endless loop at its
    first WAIT (50 cycles · 25 > 1000)."""
    from irlc.runtime.interpreter.machine import RUN_BUDGETS

    code = main_program("main: L2 PUSHC 0\nL2 WAIT\nL3 JMP @main", consts="CONST 0 REAL 0.5")
    ctl = FakeController(ipo=0.01)
    result = Interpreter(code, ctl, instruction_budget=1000).run(check=False)
    assert f"more than {RUN_BUDGETS * 1000} instructions in the run" in result.error.message
    assert len(ctl.waits) == pytest.approx(RUN_BUDGETS * 1000 / 3, abs=2)


def test_motion_after_waiting_restarts_the_budget():
    """A WAIT then a MOVE per iteration: motion restarts the count, the loop runs on."""
    consts = "CONST 0 REAL 0.5\nCONST 1 INTEGER 0\nCONST 2 INTEGER 1\nCONST 3 INTEGER 30"
    consts += "\nCONST 4 MAIN_JOINT 1.0 2.0 3.0"
    body = """main: L1 PUSHC 1
    L1 POPG 0
    top: L2 PUSHG 0
    L2 PUSHC 3
    L2 LT
    L2 JF @done
    L3 PUSHC 0
    L3 WAIT
    L4 PUSHC 4
    L4 MOVE PTP 1
    L5 PUSHG 0
    L5 PUSHC 2
    L5 ADD
    L5 POPG 0
    L5 JMP @top
    done: L6 END"""
    ctl = FakeController(ipo=0.01)
    code = main_program(body, decls="GLOBAL 0 INTEGER i", consts=consts)
    result = Interpreter(code, ctl, instruction_budget=3000).run(check=False)
    assert result.error is None and len(ctl.waits) == 30


def test_waiting_zero_seconds_is_no_progress():
    code = main_program("main: L2 PUSHC 0\nL2 WAIT\nL3 JMP @main", consts="CONST 0 REAL 0.0")
    err = failure(code, instruction_budget=100)
    assert "endless loop?" in err.message


# ------------------------------------------------------------------ routines

SWAP = """ROUTINE 1 swap PROC 2 1 @swap
PARAM 1 0 VAR INTEGER a
PARAM 1 1 VAR INTEGER b
LOCAL 1 2 INTEGER tmp"""

SWAP_BODY = """swap: L10 PUSHL 0
L10 POPL 2
L11 PUSHL 1
L11 POPL 0
L12 PUSHL 2
L12 POPL 1
L13 RET"""


def test_var_parameters_write_through_references():
    decls = "GLOBAL 0 INTEGER x\nGLOBAL 1 INTEGER y"
    consts = "CONST 0 INTEGER 1\nCONST 1 INTEGER 2"
    body = f"""main: L1 PUSHC 0
    L1 POPG 0
    L2 PUSHC 1
    L2 POPG 1
    L3 REFG 0
    L3 REFG 1
    L3 CALL 1 2
    L4 PUSHG 0
    L4 PUSHG 1
    L4 WRITELN 2
    L5 END
    {SWAP_BODY}"""
    assert out(main_program(body, decls=decls, consts=consts, routines=SWAP)) == ["21"]


def test_var_parameter_passed_on_to_a_nested_call():
    """outer(VAR INTEGER p) calls swap(p, local) — REFL of a VAR cell passes the reference."""
    routines = (
        SWAP
        + """
    ROUTINE 2 outer PROC 1 1 @outer
    PARAM 2 0 VAR INTEGER p
    LOCAL 2 1 INTEGER k"""
    )
    body = f"""main: L1 PUSHC 0
    L1 POPG 0
    L2 REFG 0
    L2 CALL 2 1
    L3 PUSHG 0
    L3 WRITELN 1
    L4 END
    outer: L20 PUSHC 1
    L20 POPL 1
    L21 REFL 0
    L21 REFL 1
    L21 CALL 1 2
    L22 RET
    {SWAP_BODY}"""
    consts = "CONST 0 INTEGER 5\nCONST 1 INTEGER 9"
    code = main_program(body, decls="GLOBAL 0 INTEGER x", consts=consts, routines=routines)
    assert out(code) == ["9"]


FACT = """ROUTINE 1 fact FUNC:INTEGER 1 0 @fact
PARAM 1 0 INTEGER n"""

FACT_BODY = """fact: L10 PUSHL 0
L10 PUSHC 1
L10 LE
L10 JF @rec
L11 PUSHC 1
L11 RETV
rec: L12 PUSHL 0
L12 PUSHL 0
L12 PUSHC 1
L12 SUB
L12 CALL 1 1
L12 MUL
L12 RETV"""


def test_recursive_function():
    body = f"main: L1 PUSHC 0\nL1 CALL 1 1\nL1 WRITELN 1\nL2 END\n{FACT_BODY}"
    code = main_program(body, consts="CONST 0 INTEGER 20\nCONST 1 INTEGER 1", routines=FACT)
    assert out(code) == ["2432902008176640000"]


def test_endless_recursion_is_reported():
    routines = "ROUTINE 1 f PROC 0 0 @f"
    body = "main: L1 CALL 1 0\nL2 END\nf: L5 CALL 1 0\nL6 RET"
    err = failure(main_program(body, routines=routines))
    assert "nested calls — endless recursion?" in err.message
    assert err.line == 5


def test_function_falling_off_its_end_is_an_error():
    routines = "ROUTINE 1 half FUNC:REAL 1 0 @f\nPARAM 1 0 REAL x"
    body = "main: L1 PUSHC 0\nL1 CALL 1 1\nL1 WRITELN 1\nL2 END\nf: L8 RET"
    err = failure(main_program(body, consts="CONST 0 REAL 1.0", routines=routines))
    assert err.message == "function 'half' ended without returning a value (RETURN missing)"
    assert err.line == 8


def test_function_result_is_coerced_to_its_type_and_locals_start_unset():
    routines = """ROUTINE 1 f FUNC:REAL 1 1 @f
    PARAM 1 0 INTEGER n
    LOCAL 1 1 REAL tmp"""
    body = """main: L1 PUSHC 0
    L1 CALL 1 1
    L1 WRITELN 1
    L2 PUSHC 0
    L2 CALL 2 1
    L3 END
    f: L10 PUSHL 0
    L10 RETV
    g: L20 PUSHL 1
    L20 RET"""
    routines += "\nROUTINE 2 g PROC 1 1 @g\nPARAM 2 0 INTEGER n\nLOCAL 2 1 REAL local_v"
    result = run(main_program(body, consts="CONST 0 INTEGER 4", routines=routines), check=False)
    assert result.output == ["4.0"]
    assert result.error.message == "variable 'local_v' is used before it has a value"
    assert result.error.line == 20


# ------------------------------------------------------------------ arrays and records


def test_arrays_with_declared_bounds_fill_element_wise():
    decls = "GLOBAL 0 ARRAY[0..2]OFREAL a"
    consts = "CONST 0 INTEGER 0\nCONST 1 INTEGER 1\nCONST 2 INTEGER 2\nCONST 3 INTEGER 7"
    body = """main: L1 PUSHG 0
    L1 PUSHC 0
    L1 PUSHC 3
    L1 SETI
    L1 POPG 0
    L2 PUSHG 0
    L2 PUSHC 0
    L2 GETI
    L2 WRITELN 1
    L3 PUSHG 0
    L3 PUSHC 1
    L3 GETI
    L4 END"""
    result = run(main_program(body, decls=decls, consts=consts), check=False)
    assert result.output == ["7.0"]  # INTEGER 7 stored into an ARRAY OF REAL
    assert result.error.message == "element [1] is used before it has a value"
    assert result.error.line == 3


def test_array_make_and_index_out_of_range():
    decls = "GLOBAL 0 ARRAY[1..3]OFINTEGER a"
    consts = "CONST 0 INTEGER 10\nCONST 1 INTEGER 20\nCONST 2 INTEGER 30\nCONST 3 INTEGER 4"
    body = """main: L1 PUSHC 0
    L1 PUSHC 1
    L1 PUSHC 2
    L1 MAKE ARRAY[1..3]OFINTEGER 3
    L1 POPG 0
    L2 PUSHG 0
    L2 WRITELN 1
    L3 PUSHG 0
    L3 PUSHC 3
    L3 GETI
    L4 END"""
    result = run(main_program(body, decls=decls, consts=consts), check=False)
    assert result.output == ["(10, 20, 30)"]
    assert result.error.message == "index 4 is out of range 1..3"
    assert result.error.line == 3


def test_records_fields_and_make():
    header_types = "TYPE 0 RECORD n:INTEGER v:REAL"
    decls = f"{header_types}\nGLOBAL 0 RECORD#0 r"
    consts = "CONST 0 INTEGER 3\nCONST 1 INTEGER 5"
    body = """main: L1 PUSHG 0
    L1 PUSHC 0
    L1 SETF n
    L1 POPG 0
    L2 PUSHG 0
    L2 GETF N
    L2 WRITELN 1
    L3 PUSHC 0
    L3 PUSHC 1
    L3 MAKE RECORD#0 2
    L3 POPG 0
    L4 PUSHG 0
    L4 WRITELN 1
    L5 END"""
    assert out(main_program(body, decls=decls, consts=consts)) == ["3", "(n: 3, v: 5.0)"]


def test_unset_record_field_is_an_error():
    decls = "TYPE 0 RECORD n:INTEGER v:REAL\nGLOBAL 0 RECORD#0 r"
    err = failure(main_program("main: L2 PUSHG 0\nL2 GETF v\nL3 END", decls=decls))
    assert err.message == "field 'v' is used before it has a value"


# ------------------------------------------------------------------ hand-built Code objects


def test_hand_built_code_object_runs_without_the_reader():
    code = Code(
        program="h",
        source="h.irl",
        robot_var="r",
        robot="fake",
        joint_kinds="RRP",
        joint_names=("a1", "a2", "a3"),
        consts=[Value("INTEGER", (6,)), Value("INTEGER", (7,))],
        globals=[Slot(0, "INTEGER", "x")],
        routines=[Routine(0, "h", "MAIN", 0)],
        code=[
            Instruction("PUSHC", (0,), 1),
            Instruction("PUSHC", (1,), 1),
            Instruction("MUL", (), 1),
            Instruction("POPG", (0,), 1),
            Instruction("PUSHG", (0,), 2),
            Instruction("WRITELN", (1,), 2),
            Instruction("END", (), 3),
        ],
    )
    result = Interpreter(code, FakeController()).run()
    assert result.output == ["42"]
    assert result.state.value("X") == 42
    assert result.instructions == 7


# ------------------------------------------------------------------ malformed hand-written code


PROC_P = "ROUTINE 1 p PROC 0 0 @p"


@pytest.mark.parametrize(
    ("body", "routines", "message"),
    [
        ("main: L3 PUSHC 0\nL3 CALL 1 1\nL4 END\np: L9 RET", PROC_P, "'p' takes 0 arguments"),
        ("main: L3 PUSHL 4\nL4 END", "", "operand out of range at instruction 0 (PUSHL)"),
        ("main: L3 PUSHC 0\nL3 GETF q\nL4 END", "", "a INTEGER has no field 'q'"),
        ("main: L3 PUSHC 0\nL3 CALLB FK 1\nL4 END", "", "FK: expected a joint tuple of 3 values"),
        ("main: L3 PUSHC 0\nL3 CALLB NOPE 1\nL4 END", "", "unknown built-in function 'NOPE'"),
        ("main: L3 PUSHC 0\nL3 JF @main\nL4 END", "", "JF needs a BOOLEAN, got INTEGER"),
        ("main: L2 CALL 1 0\nL4 END\np: L3 PUSHC 0\nL3 RETV", PROC_P, "RETV in 'p'"),
    ],
)
def test_malformed_code_is_a_run_failure_not_a_traceback(body, routines, message):
    err = failure(main_program(body, consts="CONST 0 INTEGER 1", routines=routines))
    assert message in err.message
    assert "malformed" in err.message
    assert err.line == 3


def test_bad_constant_in_a_hand_built_code_object():
    code = main_program("main: L1 END", consts="CONST 0 INTEGER 1")
    code.consts[0] = Value("POSE", (1.0, 2.0))
    err = failure(code)
    assert err.message == (
        "constant 0 (POSE): 2 value(s) do not make a POSE (the IRDATA code is malformed)"
    )
    assert err.line is None
