"""Cells of several robots (docs/language.md §10): the front end's syntax, checks and code.

A cell here: ``holder`` and ``welder`` (fake 6-joint robots ``six``) and ``arm`` (the
3-joint ``planar3``), so joint tuples meet robots of two joint counts.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from irlc.lang import read_code, write_code
from irlc.lang.irdata_robots import move_parts, robot_operand

from .conftest import compile_text

CELL = (
    "PROGRAM c;\n"
    "ROBOT holder := six;\n"
    "ROBOT welder := six AT (1400, 0, 0, 180, 0, 0);\n"
    "ROBOT arm := planar3 AT POSE(0, 900, 0, -90, 0, 0);\n"
)  # 4 header lines: with no declarations the first statement is on line 6
PAIR = "PROGRAM c;\nROBOT holder := six;\nROBOT welder := six;\n"  # two of one kind


def cell(stmts: str, decls: str = "", header: str = CELL) -> str:
    return f"{header}{decls}BEGIN\n{stmts}\nENDPROGRAM\n"


def compiled(text: str, **kw):
    result = compile_text(text, **kw)
    assert result.ok, [d.header() for d in result.diagnostics]
    return result.code


def code_lines(text: str) -> list[str]:
    """The instructions of a program's code without record numbers and comments."""
    lines = write_code(compiled(text)).splitlines()
    start = next(i for i, t in enumerate(lines) if t.endswith(" CODE"))
    return [" ".join(t.split(" ; ")[0].split()[2:]) for t in lines[start + 1 :]]


def error_at(text: str, line: int, column: int, fragment: str, **kw) -> None:
    result = compile_text(text, **kw)
    assert result.code is None
    hits = [d for d in result.errors if (d.line, d.column) == (line, column)]
    assert any(fragment in d.message for d in hits), [d.header() for d in result.diagnostics]


# ------------------------------------------------------------------ one robot: unchanged


ONE = "PROGRAM t;\nROBOT r := six;\n"
PLAIN = """\
VAR POSE: p; MAIN_JOINT: k;
BEGIN
  MOVE PTP (0, 0, 0, 0, 0, 0);
  MOVE LIN p AND LIN p;
  JOINTLIMIT (0, 0, 0, 0, 0, 0), (1, 1, 1, 1, 1, 1);
  CYCLICSTART; FREEZESTART 1, 2; RECONFIGURATION k; FREEZEEND; CYCLICEND;
  JOINTLIMITEND;
  R_TOOL := R_ACT_POSE : FK(k);
  R_BASE.z := 5;
ENDPROGRAM
"""


def test_a_one_robot_program_may_name_its_robot_and_compiles_to_the_same_code() -> None:
    plain = PLAIN.replace("  MOVE LIN p AND LIN p;\n", "")
    named = (
        plain.replace("MOVE PTP", "MOVE r PTP")
        .replace("(1, 1, 1, 1, 1, 1);", "(1, 1, 1, 1, 1, 1) FOR r;")
        .replace("CYCLICSTART;", "CYCLICSTART FOR r;")
        .replace("FREEZESTART 1, 2;", "FREEZESTART 1, 2 FOR r;")
        .replace("RECONFIGURATION k;", "RECONFIGURATION k FOR r;")
        .replace("FREEZEEND;", "FREEZEEND FOR r;")
        .replace("CYCLICEND;", "CYCLICEND FOR r;")
        .replace("JOINTLIMITEND;", "JOINTLIMITEND FOR r;")
        .replace("R_TOOL := R_ACT_POSE : FK(k)", "r.R_TOOL := r.R_ACT_POSE : FK(r, k)")
        .replace("R_BASE.z", "r.R_BASE.z")
    )
    assert named != plain
    assert write_code(compiled(ONE + named)) == write_code(compiled(ONE + plain))


def test_a_one_robot_program_names_no_other_robot() -> None:
    error_at(ONE + "BEGIN\n  MOVE welder PTP (0, 0, 0, 0, 0, 0);\nENDPROGRAM\n", 4, 8,
             "unknown robot 'welder'")  # fmt: skip
    error_at(ONE + "BEGIN\n  CYCLICSTART FOR x;\nENDPROGRAM\n", 4, 19, "unknown robot 'x'")


def test_a_group_move_in_a_one_robot_program_is_an_error() -> None:
    error_at(ONE + PLAIN, 6, 3, "a group move (… AND …) moves several robots of a cell")
    result = compile_text(ONE + PLAIN)
    assert [d.line for d in result.errors] == [6]  # one error: not one per part too
    hint = "write each part as a statement of its own: MOVE LIN …; MOVE LIN …;"
    assert result.errors[0].hint == hint


def test_a_part_of_a_group_without_its_robot_is_one_error_naming_the_cells_robots() -> None:
    result = compile_text(cell("  MOVE holder PTP (0, 0, 0, 0, 0, 0) AND PTP (0, 0, 0, 0, 0, 0);"))
    (error,) = result.errors
    assert (error.line, error.column) == (6, 42)  # the second part's PTP
    assert error.message == "each part of a group move names its robot"
    assert error.hint == "write MOVE holder PTP … AND welder …"


def test_at_on_one_robot_is_written_on_its_robot_record() -> None:
    text = "PROGRAM t;\nROBOT r := six AT (10, 0, -5, 90, 0, 0);\nBEGIN\nENDPROGRAM\n"
    ird = write_code(compiled(text))
    assert "ROBOT r six 6 RRRRRR AT 10.0 0.0 -5.0 90.0 0.0 0.0\n" in ird
    assert not read_code(ird).is_cell


# ------------------------------------------------------------------ robots and placements


def test_robots_their_placements_and_joints_in_the_code() -> None:
    code = compiled(cell("  HALT;"))
    assert code.is_cell
    robots = code.robots
    assert [(r.var, r.robot, r.joint_kinds) for r in robots] == [
        ("holder", "six", "RRRRRR"),
        ("welder", "six", "RRRRRR"),
        ("arm", "planar3", "RRR"),
    ]
    assert [r.at for r in robots] == [
        None,
        (1400.0, 0.0, 0.0, 180.0, 0.0, 0.0),
        (0.0, 900.0, 0.0, -90.0, 0.0, 0.0),
    ]
    assert robots[2].joint_names == ("a1", "a2", "a3")
    assert robots[1].position == ("test.irl", 3, 17)  # where the cell's robot is named


def test_at_takes_a_constant_pose_of_the_program_or_a_data_list() -> None:
    header = "PROGRAM c;\nROBOT a := six AT base;\nROBOT b := six AT (2 * 700, -(1), 0, 0, 0, 0);\n"
    code = compiled(cell("  HALT;", "CONST POSE: base = (0, 0, 500, 0, 0, 90);\n", header))
    assert [r.at for r in code.robots] == [
        (0.0, 0.0, 500.0, 0.0, 0.0, 90.0),
        (1400.0, -1.0, 0.0, 0.0, 0.0, 0.0),
    ]


@pytest.mark.parametrize(
    ("at", "column", "fragment"),
    [
        ("5", 19, "AT of robot b: expected POSE, got INTEGER"),
        ("(1, 2, 3)", 19, "POSE needs 6 values, got 3"),
        ("p", 19, "AT of robot b must be a constant POSE"),
        ("POSE(POSITION(1, 2, 3), ORIZYX(0, 0, 0))", 19, "must be a constant POSE"),
        ("(2e6, 0, 0, 0, 0, 0)", 19, "outside the physical range of a coordinate"),
        ("nowhere", 19, "unknown name 'nowhere'"),
    ],
)
def test_an_at_that_is_not_a_constant_pose_is_an_error(at: str, column: int, fragment: str):
    header = f"PROGRAM c;\nROBOT a := six;\nROBOT b := six AT {at};\n"
    error_at(cell("  HALT;", "VAR POSE: p;\n", header), 3, column, fragment)


def test_at_is_not_reserved_and_another_word_there_is_an_error() -> None:
    compiled(cell("  at := 1;", "VAR INTEGER: at;\n"))
    error_at("PROGRAM c;\nROBOT a := six ATT (0, 0, 0, 0, 0, 0);\nBEGIN\nENDPROGRAM\n", 2, 16,
             "expected AT or ';' after the robot, got 'ATT'")  # fmt: skip


def test_two_robots_with_one_name_are_an_error() -> None:
    text = "PROGRAM c;\nROBOT a := six;\nROBOT b := six;\nROBOT A := planar3;\nBEGIN\nENDPROGRAM\n"
    error_at(text, 4, 7, "'A' is already defined as 'a' (line 2)")
    twice = compile_text("PROGRAM c;\nROBOT a := six;\nROBOT a := six;\nBEGIN\nENDPROGRAM\n")
    assert [d.message for d in twice.errors] == ["'a' is already defined (line 2)"]  # one error


def test_a_robot_name_is_not_a_value_nor_a_variable() -> None:
    error_at(cell("  x := holder;", "VAR REAL: x;\n"), 7, 8, "'holder' is a robot, not a value")
    error_at(cell("  VAR_X := 1;\n  holder := 1;", "VAR REAL: var_x;\n"), 8, 3,
             "cannot assign to 'holder'")  # fmt: skip


def test_robot_override_is_refused_for_a_cell() -> None:
    error_at(cell("  HALT;"), 3, 1, "--robot six cannot be used with a cell", robot_override="six")


def test_every_robot_of_a_cell_is_resolved() -> None:
    text = "PROGRAM c;\nROBOT a := six;\nROBOT b := nine;\nROBOT c := ten;\nBEGIN\nENDPROGRAM\n"
    result = compile_text(text)
    assert [(d.line, d.column) for d in result.errors] == [(3, 12), (4, 12)]
    assert "cannot use robot 'nine'" in result.errors[0].message


# ------------------------------------------------------------------ motion


def test_a_motion_names_its_robot_and_the_code_says_which() -> None:
    lines = code_lines(cell(
        "  MOVE welder PTP (0, 0, 0, 0, 0, 0) WITH SPEED_PTP := 20;\n"
        "  MOVE arm LIN p, p WITH SPEED := 200;\n"
        "  MOVE_INC holder LIN (0, 0, 10, 0, 0, 0);\n"
        "  MOVE_INC arm PTP (0, 0, 5);\n"
        "  MOVE holder CIRC p, p;\n"
        "  MOVE welder LIN PATH (p, p, p);",
        "VAR POSE: p;\n",
    ))  # fmt: skip
    moves = [t for t in lines if t.startswith("MOVE")]
    assert moves == [
        "MOVE PTP 1 ROBOT:1 SPEED_PTP",
        "MOVE LIN 2 ROBOT:2 SPEED",
        "MOVE LININC 1 ROBOT:0",
        "MOVE PTPINC 1 ROBOT:2",
        "MOVE CIRCLE 2 ROBOT:0",
        "MOVE LINPATH 3 ROBOT:1",
    ]


def test_a_motion_without_a_robot_in_a_cell_lists_the_robots() -> None:
    result = compile_text(cell("  MOVE LIN p;", "VAR POSE: p;\n"))
    (d,) = result.errors
    assert (d.line, d.column) == (7, 3)
    assert d.message == "MOVE LIN in a cell names its robot (holder, welder, arm)"
    assert d.hint == "write MOVE holder LIN …"


@pytest.mark.parametrize(
    ("stmt", "column", "fragment"),
    [
        ("  MOVE crane PTP (0, 0, 0);", 8, "unknown robot 'crane'"),
        ("  MOVE p LIN p;", 8, "'p' is not a robot"),
        ("  MOVE_INC PTP (0, 0, 0);", 3, "MOVE_INC PTP in a cell names its robot"),
    ],
)
def test_a_motion_names_a_robot_of_the_cell(stmt: str, column: int, fragment: str) -> None:
    error_at(cell(stmt, "VAR POSE: p;\n"), 7, column, fragment)


def test_a_misspelt_robot_gets_the_closest_name() -> None:
    (d,) = compile_text(cell("  MOVE weldr PTP (0, 0, 0, 0, 0, 0);")).errors
    assert d.message == "unknown robot 'weldr'"
    assert d.hint == "did you mean 'welder'? robots of this program: holder, welder, arm"


def test_a_group_move_pushes_each_part_then_one_move() -> None:
    lines = code_lines(cell(
        "  MOVE holder LIN p WITH SPEED := 100 AND welder PTP (0, 0, 0, 0, 0, 0)"
        " AND arm PTP (1, 2, 3) WITH TIME := 2;",
        "VAR POSE: p;\n",
    ))  # fmt: skip
    assert lines[:6] == [
        "PUSHG 0",
        "PUSHC 0",
        "PUSHC 1",
        "PUSHC 2",
        "PUSHC 3",
        "MOVE LIN 1 ROBOT:0 SPEED AND PTP 1 ROBOT:1 AND PTP 1 ROBOT:2 TIME",
    ]


def test_and_in_an_expression_is_still_the_logical_and() -> None:
    lines = code_lines(cell(
        "  b := b AND c;\n  MOVE holder LIN p WITH TIME := 2 AND { a comment }\n"
        "    // and another\n    welder LIN p;",
        "VAR BOOLEAN: b, c; POSE: p;\n",
    ))  # fmt: skip
    assert "AND" in lines and "MOVE LIN 1 ROBOT:0 TIME AND LIN 1 ROBOT:1" in lines


def test_a_group_of_incremental_moves() -> None:
    lines = code_lines(cell("  MOVE_INC holder LIN (0, 0, 1, 0, 0, 0) AND arm PTP (0, 0, 1);"))
    assert lines[-2] == "MOVE LININC 1 ROBOT:0 AND PTPINC 1 ROBOT:2"


def test_a_robot_moves_once_in_a_group() -> None:
    error_at(cell("  MOVE holder LIN p AND arm LIN p AND Holder PTP p;", "VAR POSE: p;\n"),
             7, 39, "robot holder moves twice in one group move")  # fmt: skip


def test_each_part_of_a_group_names_its_robot() -> None:
    error_at(cell("  MOVE holder LIN p AND LIN p;", "VAR POSE: p;\n"), 7, 25,
             "each part of a group move names its robot")  # fmt: skip


# ------------------------------------------------------------------ joint tuples per robot


def test_joint_tuples_are_checked_against_the_robot_they_are_used_with() -> None:
    decls = "CONST MAIN_JOINT: six_k = (0, 0, 0, 0, 0, 0);\nVAR MAIN_JOINT: k; POSE: p;\n"
    compiled(cell("  MOVE arm PTP (1, 2, 3);\n  MOVE holder PTP six_k;\n  k := six_k;\n"
                  "  MOVE welder PTP k;\n  k := (1, 2, 3);\n  MOVE arm PTP k;", decls))  # fmt: skip
    for stmt, column, fragment in [
        ("  MOVE arm PTP (1, 2, 3, 4, 5, 6, 7);", 16, "MAIN_JOINT needs 3 values, got 7"),
        ("  MOVE arm PTP six_k;", 16, "MAIN_JOINT for robot arm needs 3 values, got 6"),
        ("  MOVE_INC arm PTP six_k;", 20, "MAIN_JOINT for robot arm needs 3 values"),
        ("  RECONFIGURATION six_k FOR arm;", 19, "MAIN_JOINT for robot arm needs 3"),
        ("  MOVE arm LIN p WITH RECONFIGURATION six_k;", 39, "robot arm needs 3 values"),
        ("  p := FK(arm, six_k);", 16, "FK: MAIN_JOINT for robot arm needs 3 values, got 6"),
        ("  k := (1, 2, 3, 4);", 8, "a MAIN_JOINT of 4 values fits no robot of the cell"),
    ]:
        error_at(cell(stmt, decls), 8, column, fragment)


def test_limits_are_checked_against_their_robot() -> None:
    decls = (
        "CONST MAIN_JOINT_MIN: lo = (0, 0, 0);\nCONST MAIN_JOINT_MAX: hi = (1, 1, 1);\n"
        "VAR POSE: p;\n"
    )
    compiled(cell("  JOINTLIMIT lo, hi FOR arm;\n  JOINTLIMITEND FOR arm;", decls))
    error_at(
        cell("  JOINTLIMIT lo, hi FOR holder;\n  JOINTLIMITEND FOR holder;", decls),
        9,
        14,
        "JOINTLIMIT, first argument: MAIN_JOINT_MIN for robot holder needs 6 values",
    )
    error_at(cell("  MOVE holder LIN p WITH JOINTLIMIT lo, hi;", decls), 9, 37,
             "for robot holder needs 6 values, got 3")  # fmt: skip


def test_a_cells_robots_with_one_joint_count_keep_the_arity_in_the_type() -> None:
    error_at(cell("  k := (1, 2, 3);", "VAR MAIN_JOINT: k;\n", PAIR), 6, 8,
             "MAIN_JOINT needs 6 values, got 3")  # fmt: skip


def test_a_data_list_of_a_mixed_cell_has_joint_values_of_its_robots(tmp_path) -> None:
    (tmp_path / "cl.toml").write_text("[joints]\nk3 = [1, 2, 3]\nk6 = [1, 2, 3, 4, 5, 6]\n"
                                      "k4 = [1, 2, 3, 4]\n")  # fmt: skip
    text = cell("  MOVE arm PTP k3;\n  MOVE holder PTP k6;", header=CELL + "IMPORT DATALIST cl;\n")
    result = compile_text(text, str(tmp_path / "c.irl"))
    (d,) = result.errors
    assert d.file.endswith("cl.toml") and d.line == 4
    assert "expected 3 or 6 numbers (one value per joint), got 4" in d.message


def test_joint_names_of_a_cell_name_every_robots_joints() -> None:
    rec = "TYPE RECORD REAL: s, l, e, w1, w2, w3; ENDRECORD = MAIN_JOINT;\n"
    code = compiled(cell("  HALT;", rec, PAIR))
    assert [r.joint_names for r in code.robots] == [("s", "l", "e", "w1", "w2", "w3")] * 2
    error_at(cell("  HALT;", rec), 5, 6, "MAIN_JOINT declares 6 joints, but robot planar3 (arm)")


# ------------------------------------------------------------------ redundancy constructs


def test_every_redundancy_construct_names_its_robot() -> None:
    lines = code_lines(cell(
        "  JOINTLIMIT (0, 0, 0), (1, 1, 1) FOR arm;\n"
        "  JOINTLIMIT (0, 0, 0, 0, 0, 0), (1, 1, 1, 1, 1, 1) FOR holder;\n"
        "  CYCLICSTART FOR welder;\n  FREEZESTART 3 FOR arm;\n"
        "  RECONFIGURATION (1, 2, 3) FOR arm;\n"
        "  FREEZEEND FOR arm;\n  CYCLICEND FOR welder;\n"
        "  JOINTLIMITEND FOR holder;\n  JOINTLIMITEND FOR arm;",
    ))  # fmt: skip
    assert [t for t in lines if not t.startswith("PUSHC")] == [
        "OPTON JOINTLIMIT ROBOT:2",
        "OPTON JOINTLIMIT ROBOT:0",
        "OPTON CYCLIC ROBOT:1",
        "OPTON FREEZE ROBOT:2 3",
        "RECONF ROBOT:2",
        "OPTOFF FREEZE ROBOT:2",
        "OPTOFF CYCLIC ROBOT:1",
        "OPTOFF JOINTLIMIT ROBOT:0",
        "OPTOFF JOINTLIMIT ROBOT:2",
        "END",
    ]


def test_an_obstacle_is_switched_on_for_a_robot(tmp_path) -> None:
    (tmp_path / "ob.toml").write_text('[obstacles.wall]\nkind = "point"\ncenter = [0, 0, 0]\n')
    text = cell("  OBSTACLE wall FOR arm;\n  OBSTACLE wall FOR holder;\n"
                "  OBSTACLEEND wall FOR arm;\n  OBSTACLEEND wall FOR holder;",
                header=CELL + "IMPORT DATALIST ob;\n")  # fmt: skip
    code = compiled(text, filename=str(tmp_path / "c.irl"))
    assert [f"{i.op} {' '.join(map(str, i.args))}" for i in code.code[:4]] == [
        "OPTON OBSTACLE ROBOT:2 wall",
        "OPTON OBSTACLE ROBOT:0 wall",
        "OPTOFF OBSTACLE ROBOT:2 wall",
        "OPTOFF OBSTACLE ROBOT:0 wall",
    ]


@pytest.mark.parametrize(
    ("stmts", "line", "column", "fragment"),
    [
        ("  CYCLICSTART;\n  CYCLICEND;", 6, 3, "CYCLICSTART in a cell names its robot"),
        ("  FREEZESTART 1;", 6, 3, "FREEZESTART in a cell names its robot"),
        ("  RECONFIGURATION (1, 2, 3);", 6, 3, "RECONFIGURATION in a cell names its robot"),
        ("  CYCLICSTART FOR gripper;", 6, 19, "unknown robot 'gripper'"),
        ("  CYCLICSTART FOR arm;\n  CYCLICEND FOR holder;", 7, 3,
         "CYCLICEND FOR holder without an earlier CYCLICSTART FOR holder"),
        ("  CYCLICSTART FOR arm;\n  CYCLICSTART FOR Arm;", 7, 3,
         "CYCLICSTART FOR arm is already on (since line 6)"),
        ("  CYCLICSTART FOR arm;", 6, 3, "CYCLICSTART FOR arm is not closed before ENDPROGRAM"),
        ("  FREEZESTART 4 FOR arm;\n  FREEZEEND FOR arm;", 6, 15,
         "joint 4 does not exist: robot arm (planar3) has joints 1..3"),
        ("  IF TRUE THEN CYCLICEND FOR arm ENDIF;", 6, 16, "CYCLICEND FOR arm without"),
    ],
)  # fmt: skip
def test_redundancy_construct_errors(stmts: str, line: int, column: int, fragment: str) -> None:
    error_at(cell(stmts), line, column, fragment)


def test_the_same_option_for_two_robots_is_two_blocks() -> None:
    compiled(cell("  CYCLICSTART FOR arm;\n  CYCLICSTART FOR holder;\n"
                  "  CYCLICEND FOR arm;\n  CYCLICEND FOR holder;"))  # fmt: skip


# ------------------------------------------------------------------ COOPERATE


def test_cooperate_names_both_robots_in_the_code() -> None:
    lines = code_lines(cell(
        "  COOPERATE welder IN holder WITH vertical;\n    MOVE welder LIN p;\n  COOPERATEEND;\n"
        "  COOPERATE arm IN welder;\n  COOPERATEEND;",
        "VAR POSE: p;\n",
    ))  # fmt: skip
    assert lines == [
        "OPTON COOPERATE ROBOT:1 ROBOT:0 VERTICAL",
        "PUSHG 0",
        "MOVE LIN 1 ROBOT:1",
        "OPTOFF COOPERATE ROBOT:1 ROBOT:0",
        "OPTON COOPERATE ROBOT:2 ROBOT:1",
        "OPTOFF COOPERATE ROBOT:2 ROBOT:1",
        "END",
    ]


def test_cooperations_of_different_robots_nest_and_end_innermost_first() -> None:
    four = PAIR + "ROBOT a := six;\nROBOT b := six;\n"
    lines = code_lines(cell("  COOPERATE welder IN holder;\n  COOPERATE a IN b;\n"
                            "  COOPERATEEND;\n  COOPERATEEND;", header=four))  # fmt: skip
    assert lines[2:4] == ["OPTOFF COOPERATE ROBOT:2 ROBOT:3", "OPTOFF COOPERATE ROBOT:1 ROBOT:0"]


@pytest.mark.parametrize(
    ("stmts", "line", "column", "fragment"),
    [
        ("  COOPERATE welder IN welder;\n  COOPERATEEND;", 6, 23,
         "robot welder cannot cooperate with itself"),
        ("  COOPERATE welder IN crane;\n  COOPERATEEND;", 6, 23, "unknown robot 'crane'"),
        ("  COOPERATE welder IN holder;\n  COOPERATE arm IN holder;\n  COOPERATEEND;"
         "\n  COOPERATEEND;", 7, 3,
         "robot holder already cooperates (COOPERATE welder IN holder, line 6)"),
        ("  COOPERATE welder IN holder;\n  COOPERATE holder IN arm;\n  COOPERATEEND;"
         "\n  COOPERATEEND;", 7, 3, "robot holder already cooperates"),
        ("  COOPERATEEND;", 6, 3, "COOPERATEEND without an earlier COOPERATE"),
        ("  COOPERATE welder IN holder;", 6, 3,
         "COOPERATE welder IN holder is not closed before ENDPROGRAM"),
        ("  COOPERATE welder IN holder;\n  IF TRUE THEN COOPERATEEND ENDIF;\n  COOPERATEEND;",
         7, 16, "COOPERATEEND closes COOPERATE welder IN holder of line 6 from another"),
        ("  COOPERATE welder IN holder WITH HORIZONTAL;\n  COOPERATEEND;", 6, 35,
         "unknown COOPERATE option 'HORIZONTAL'"),
    ],
)  # fmt: skip
def test_cooperate_errors(stmts: str, line: int, column: int, fragment: str) -> None:
    error_at(cell(stmts), line, column, fragment)


def test_cooperate_needs_a_cell() -> None:
    error_at(ONE + "BEGIN\n  COOPERATE r IN r;\n  COOPERATEEND;\nENDPROGRAM\n", 4, 3,
             "COOPERATE needs a cell of two or more robots")  # fmt: skip


def test_cooperate_is_a_reserved_word() -> None:
    error_at(cell("  HALT;", "VAR REAL: cooperate;\n"), 5, 11, "'cooperate' is a reserved word")


# ------------------------------------------------------------------ a robot's own variables


def test_a_robots_own_system_variables_name_it() -> None:
    lines = code_lines(cell(
        "  holder.R_TOOL := (0, 0, 100, 0, 0, 0);\n  welder.R_BASE.z := 5;\n"
        "  p := arm.R_ACT_POSE;\n  k := Welder.r_act_joint;\n  p := FK(arm, (0, 0, 0));\n"
        "  R_SPEED := 300;  R_CLEARANCE := 25;",
        "VAR POSE: p; MAIN_JOINT: k;\n",
    ))  # fmt: skip
    assert [t for t in lines if not t.startswith(("PUSHC", "POPG", "SETF"))] == [
        "POPSYS R_TOOL ROBOT:0",
        "PUSHSYS R_BASE ROBOT:1",
        "POPSYS R_BASE ROBOT:1",
        "PUSHSYS R_ACT_POSE ROBOT:2",
        "PUSHSYS R_ACT_JOINT ROBOT:1",
        "CALLB FK 1 ROBOT:2",
        "POPSYS R_SPEED",
        "POPSYS R_CLEARANCE",
        "END",
    ]


@pytest.mark.parametrize(
    ("stmt", "column", "fragment"),
    [
        ("  R_TOOL := p;", 3, "R_TOOL belongs to one robot of the cell (holder, welder, arm)"),
        ("  p := R_ACT_POSE;", 8, "R_ACT_POSE belongs to one robot of the cell"),
        ("  holder.R_SPEED := 5;", 10, "R_SPEED is a setting of the whole program"),
        ("  x := arm.speed;", 12, "robot arm has no variable 'speed'"),
        ("  arm.R_ACT_POSE := p;", 7, "R_ACT_POSE is read-only"),
        ("  p := FK((0, 0, 0));", 8, "FK in a cell names its robot"),
        ("  p := FK(p, (0, 0, 0));", 11, "'p' is not a robot"),
        ("  R_CLEARANCE := -1;", 18, "R_CLEARANCE := -1: the value must be in [0, 100000] mm"),
    ],
)
def test_robot_variable_errors(stmt: str, column: int, fragment: str) -> None:
    error_at(cell(stmt, "VAR POSE: p; REAL: x;\n"), 7, column, fragment)


# ------------------------------------------------------------------ code round trip


def test_the_code_of_a_cell_reads_back_as_written() -> None:
    text = cell(
        "  MOVE holder LIN p AND welder PTP (0, 0, 0, 0, 0, 0) AND arm PTP (1, 2, 3);\n"
        "  COOPERATE welder IN holder WITH VERTICAL;\n    MOVE welder LIN p;\n  COOPERATEEND;\n"
        "  FREEZESTART 1, 3 FOR arm;\n  FREEZEEND FOR arm;\n  p := FK(arm, (0, 0, 0));",
        "VAR POSE: p;\n",
    )
    code = compiled(text)
    ird = write_code(code)
    again = read_code(ird, "c.ird")
    assert write_code(again) == ird
    assert again.code == code.code and again.robots[1:] != code.robots[1:]  # positions differ
    assert [(r.var, r.at) for r in again.robots] == [(r.var, r.at) for r in code.robots]
    assert again.other_robots[0].position == ("c.ird", 7, 16)


def test_move_parts_and_robot_operands_decode_the_instructions() -> None:
    code = compiled(cell(
        "  MOVE holder LIN p WITH SPEED := 1 AND arm LIN p WITH RECONFIGURATION (1, 2, 3);"
        "\n  FREEZESTART 2, 3 FOR arm;\n  FREEZEEND FOR arm;",
        "VAR POSE: p;\n",
    ))  # fmt: skip
    move = next(i for i in code.code if i.op == "MOVE")
    parts, problems = move_parts(move.args)
    assert not problems
    assert [(p.robot, p.kind, p.points, p.clauses) for p in parts] == [
        (0, "LIN", 1, ("SPEED",)),
        (2, "LIN", 1, ("RECONF:1",)),
    ]
    freeze = next(i for i in code.code if i.op == "OPTON")
    assert robot_operand(freeze.op, freeze.args) == (2, ("FREEZE", 2, 3))


# ------------------------------------------------------------------ the command line


PROGRAMS = Path(__file__).resolve().parents[2] / "programs"


def _cli(capsys, *args: str) -> tuple[int, str, str]:
    from irlc.cli import main

    code = main(list(args))
    out, err = capsys.readouterr()
    assert "Traceback" not in out + err
    return code, out, err


@pytest.mark.parametrize("name", ["cooperating", "two_robots"])
def test_the_example_cells_check_compile_and_disassemble(name, tmp_path, capsys) -> None:
    program = PROGRAMS / f"{name}.irl"
    assert _cli(capsys, "check", str(program))[0] == 0
    out = tmp_path / f"{name}.ird"
    assert _cli(capsys, "compile", str(program), "-o", str(out))[0] == 0
    code = read_code(out.read_text(encoding="utf-8"))
    assert code.is_cell and len(code.robots) == 2
    status, listing, _ = _cli(capsys, "disasm", str(out))
    assert status == 0 and "ROBOT:1" in listing


def test_robot_option_is_refused_for_a_cell(capsys) -> None:
    status, _, err = _cli(capsys, "check", str(PROGRAMS / "cooperating.irl"), "--robot", "as6")
    assert status == 1
    assert "cooperating.irl:12:1: error: --robot as6 cannot be used with a cell: the program " \
        "names 2 robots (holder, welder)" in err  # fmt: skip


def test_a_cell_runs_from_its_program_and_from_its_code(tmp_path, capsys):
    program = PROGRAMS / "two_robots.irl"
    status, out, _ = _cli(capsys, "run", str(program), "--json")
    assert status == 0
    report = json.loads(out)
    assert [r["name"] for r in report["robots"]] == ["ceiling", "floor"]
    code = tmp_path / "two.ird"
    _cli(capsys, "compile", str(program), "-o", str(code))
    status, out, _ = _cli(capsys, "run", str(code), "--json")
    assert status == 0 and json.loads(out)["samples"] == report["samples"]


def test_an_approximated_group_move_warns_where_the_advance_run_stops() -> None:
    result = compile_text(cell(
        "  MOVE holder LIN p AND welder LIN p WITH APPROX := 10;\n  arm.R_TOOL := p;\n"
        "  MOVE holder LIN p WITH APPROX := 10;\n  p := welder.R_ACT_POSE;\n"
        "  MOVE holder LIN p AND welder LIN p;",
        "VAR POSE: p;\n",
    ))  # fmt: skip
    assert result.ok
    assert [(w.line, w.message.split(":")[0]) for w in result.warnings] == [
        (8, "changing R_TOOL stops the advance run"),
        (10, "reading R_ACT_POSE stops the advance run"),
    ]


def test_a_cell_whose_prefixed_trace_columns_coincide_does_not_compile() -> None:
    """Robot h's joint a1_speed and robot h_a1's joint speed both give h_a1_speed_deg."""
    result = compile_text(
        "PROGRAM c;\nROBOT h := six;\nROBOT h_a1 := six AT (0, 2000, 0, 0, 0, 0);\n"
        "TYPE RECORD REAL: a1_speed, speed, c2, d2, e2, f2; ENDRECORD = MAIN_JOINT;\n"
        "BEGIN\nENDPROGRAM\n"
    )
    assert [(e.line, e.column, e.message) for e in result.errors] == [
        (3, 7, "robot h_a1 gives the trace column h_a1_speed_deg, which is also a column of "
         "joint 'a1_speed' of robot h")
    ]  # fmt: skip
    assert compile_text(
        "PROGRAM c;\nROBOT h := six;\nROBOT g := six AT (0, 2000, 0, 0, 0, 0);\nBEGIN\nENDPROGRAM\n"
    ).ok


@pytest.mark.parametrize(
    ("stmt", "column", "fragment"),
    [
        ("  R_TOOL := (0, 0, 100, 0, 0, 0);", 3, "R_TOOL belongs to one robot of the cell"),
        ("  weldr.R_TOOL := (0, 0, 100, 0, 0, 0);", 3, "unknown name 'weldr'"),
        ("  x := FK(nobody, (1, 2, 3, 4, 5, 6)).x;", 11, "unknown robot 'nobody'"),
        ("  x := FK((1, 2, 3, 4, 5, 6)).x;", 8, "FK in a cell names its robot"),
        ("  y := (1, 2, 3, 4, 5, 6);", 3, "unknown name 'y'"),
    ],
)
def test_a_tuple_after_an_error_in_its_context_is_not_a_second_error(stmt, column, fragment):
    """Before, each of these also said "a tuple of 6 values has no type here"."""
    result = compile_text(cell(stmt, "VAR REAL: x;\n"))
    (error,) = result.errors
    assert (error.line, error.column) == (7, column)
    assert fragment in error.message
