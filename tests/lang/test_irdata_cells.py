"""IRDATA code of cells (docs/irdata.md, Cells): the round trip, and hostile files.

A hand-written or corrupted ``.ird`` of a cell fails when it is read, at the record and the
operand: a robot index out of range or malformed, a robot operand missing in a cell or
given where none belongs, a robot twice in a group move, a COOPERATE that is not two robots
of a cell, a bad placement, robots with one name, missing or disagreeing JOINTS records.
"""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from irlc.lang import read_code, write_code
from irlc.lang.irdata import Code, Instruction, Routine
from irlc.lang.irdata_model import MOVE_KINDS, CellRobot
from irlc.lang.irdata_robots import MOVE_CLAUSES, robot_word

from .conftest import ird_text
from .test_irdata_corrupt import corrupt, errors

SOURCE = """PROGRAM c;
ROBOT holder := six;
ROBOT welder := six AT (1400, 0, 0, 180, 0, 0);
ROBOT arm := planar3;
VAR POSE: p;
BEGIN
  MOVE welder PTP (0, 0, 0, 0, 0, 0);
  MOVE holder LIN p AND arm PTP (1, 2, 3);
  holder.R_TOOL := arm.R_ACT_POSE : FK(arm, (0, 0, 0));
  R_SPEED := 100;
  RECONFIGURATION (1, 2, 3) FOR arm;
  JOINTLIMIT (0, 0, 0), (1, 1, 1) FOR arm;
  FREEZESTART 2 FOR arm;
  COOPERATE welder IN holder WITH VERTICAL;
  COOPERATEEND;
  FREEZEEND FOR arm;
  JOINTLIMITEND FOR arm;
ENDPROGRAM
"""


@pytest.fixture(scope="module")
def ird() -> str:
    return ird_text(SOURCE)


def test_the_cell_reads_back(ird: str) -> None:
    code = read_code(ird)
    assert write_code(code) == ird
    assert [r.var for r in code.robots] == ["holder", "welder", "arm"]


I = r"(\d+ L\d+) "  # an instruction's record number and line: kept by the replacement


def column_of(text: str, line: int, token: str) -> int:
    """The column of the last ``token`` (a whole word) of a file line."""
    words = text.splitlines()[line - 1].split(" ")
    k = max(i for i, w in enumerate(words) if w == token)
    return sum(len(w) + 1 for w in words[:k]) + 1


@pytest.mark.parametrize(
    ("record", "replacement", "token", "message"),
    [
        (I + "MOVE PTP 1 ROBOT:1 ; welder", r"\1 MOVE PTP 1 ROBOT:7", "ROBOT:7",
         "MOVE: no robot 7 (the code's robots are 0..2)"),
        (I + "MOVE PTP 1 ROBOT:1 ; welder", r"\1 MOVE PTP 1 ROBOT:x", "ROBOT:x",
         "MOVE: expected ROBOT:<index>, got 'ROBOT:x'"),
        (I + "MOVE PTP 1 ROBOT:1 ; welder", r"\1 MOVE PTP 1", "PTP",
         "MOVE: a cell's motion names its robot (ROBOT:k)"),
        (I + "MOVE LIN 1 ROBOT:0 AND PTP 1 ROBOT:2 ; holder, arm",
         r"\1 MOVE LIN 1 ROBOT:0 AND PTP 1 ROBOT:0", "PTP", "MOVE: robot 0 moves twice"),
        (I + "MOVE LIN 1 ROBOT:0 AND PTP 1 ROBOT:2 ; holder, arm",
         r"\1 MOVE LIN 1 ROBOT:0 AND PTP 0 ROBOT:2", "0",
         "MOVE: expected a positive number of points, got 0"),
        (I + "MOVE LIN 1 ROBOT:0 AND PTP 1 ROBOT:2 ; holder, arm",
         r"\1 MOVE LIN 1 ROBOT:0 AND JUMP 1 ROBOT:2", "JUMP", "unknown motion kind 'JUMP'"),
        (I + "MOVE LIN 1 ROBOT:0 AND PTP 1 ROBOT:2 ; holder, arm",
         r"\1 MOVE LIN 1 ROBOT:0 SPEED ROBOT:2", "ROBOT:2", "MOVE: unknown clause 'ROBOT:2'"),
        (I + "POPSYS R_SPEED", r"\1 POPSYS R_SPEED ROBOT:0", "ROBOT:0",
         "POPSYS R_SPEED: takes no robot operand"),
        (I + "POPSYS R_TOOL ROBOT:0 ; holder", r"\1 POPSYS R_TOOL", "POPSYS",
         "POPSYS: a cell's instruction names its robot (ROBOT:k)"),
        (I + "CALLB FK 1 ROBOT:2 ; arm", r"\1 CALLB FK 1 ROBOT:2 ROBOT:2", "ROBOT:2",
         "CALLB: a robot operand ROBOT:2 out of place"),
        (I + "RECONF ROBOT:2 ; arm", r"\1 RECONF ROBOT:2 5", "5", "RECONF: unexpected operand '5'"),
        (I + "OPTON JOINTLIMIT ROBOT:2 ; arm", r"\1 OPTON JOINTLIMIT", "OPTON",
         "OPTON: a cell's instruction names its robot (ROBOT:k)"),
        (I + "OPTON FREEZE ROBOT:2 2 ; arm", r"\1 OPTON FREEZE ROBOT:2 4", "FREEZE",
         "OPTON FREEZE: expected joint numbers in 1..3"),
        (I + "OPTON FREEZE ROBOT:2 2 ; arm", r"\1 OPTON FREEZE 2 ROBOT:2", "ROBOT:2",
         "OPTON: a robot operand ROBOT:2 out of place"),
        (I + "OPTON COOPERATE ROBOT:1 ROBOT:0 VERTICAL ; welder, holder",
         r"\1 OPTON COOPERATE ROBOT:1 ROBOT:1", "COOPERATE",
         "OPTON COOPERATE: robot 1 cannot cooperate with itself"),
        (I + "OPTON COOPERATE ROBOT:1 ROBOT:0 VERTICAL ; welder, holder",
         r"\1 OPTON COOPERATE ROBOT:1 ROBOT:0 SIDEWAYS", "COOPERATE",
         "OPTON COOPERATE: expected ROBOT:w ROBOT:h [VERTICAL]"),
        (I + "OPTOFF COOPERATE ROBOT:1 ROBOT:0 ; welder, holder",
         r"\1 OPTOFF COOPERATE ROBOT:1 ROBOT:0 VERTICAL", "COOPERATE",
         "OPTOFF COOPERATE: expected ROBOT:w ROBOT:h\n"),
    ],
)  # fmt: skip
def test_a_bad_robot_operand_is_a_read_error_at_its_operand(ird, record, replacement, token,
                                                           message) -> None:  # fmt: skip
    assert_read_error(ird, record, replacement, token, message)


def assert_read_error(ird: str, record: str, replacement: str, token: str, message: str) -> None:
    """The corrupted record fails to read at ``token`` with ``message`` (a message ending
    in a newline: exactly that message)."""
    text, line = corrupt(ird, record, replacement)
    column = column_of(text, line, token)
    found = errors(text)
    assert any((ln, col) == (line, column) and (msg + "\n").startswith(message)
               for ln, col, msg in found), found  # fmt: skip


@pytest.mark.parametrize(
    ("record", "replacement", "token", "message"),
    [
        (r"(\d+) ROBOT welder six 6 RRRRRR AT .*", r"\1 ROBOT welder six 6 RRRRRR AT 1 2 3", "AT",
         "ROBOT: expected 'AT x y z a b c' after the joint kinds"),
        (r"(\d+) ROBOT welder six 6 RRRRRR AT .*", r"\1 ROBOT welder six 6 RRRRRR 1 2 3 4 5 6 7",
         "1", "ROBOT: expected 'AT x y z a b c'"),
        (r"(\d+) ROBOT welder six 6 RRRRRR AT .*", r"\1 ROBOT welder six 6 RRRRRR AT 1 2 nan 0 0 0",
         "1", "ROBOT: AT needs 6 finite numbers"),
        (r"(\d+) ROBOT welder six 6 RRRRRR AT .*", r"\1 ROBOT welder six 6 RRRRRR AT 1 2e7 0 0 0 0",
         "1", "ROBOT: AT: 2e+07 mm is outside the physical range of a coordinate"),
        (r"(\d+) ROBOT welder six 6 RRRRRR AT .*", r"\1 ROBOT HOLDER six 6 RRRRRR", "HOLDER",
         "ROBOT: robot 'HOLDER' is named twice (line 5)"),
        (r"(\d+) JOINTS a1 a2 a3", r"\1 JOINTS a1 a3 a2", "JOINTS",
         "JOINTS: joint 2 of robot arm is 'a3', of robot holder 'a2'"),
        (r"(\d+) JOINTS a1 a2 a3", r"\1 JOINTS a1 a2", "JOINTS",
         "JOINTS: 2 name(s) for the ROBOT record's 3 joint(s)"),
        (r"(\d+) CONST (\d+) MAIN_JOINT 1.0 2.0 3.0", r"\1 CONST \2 MAIN_JOINT 1 2 3 4",
         "MAIN_JOINT", "MAIN_JOINT: expected 3 or 6 numbers, got 4"),
    ],
)  # fmt: skip
def test_a_bad_robot_record_is_a_read_error(ird, record, replacement, token, message) -> None:
    assert_read_error(ird, record, replacement, token, message)


def test_every_robot_has_its_joints_record(ird: str) -> None:
    text, line = corrupt(ird, r"(\d+) JOINTS a1 a2 a3", r"\1 UNITS mm deg s")
    found = errors(text)
    assert (line - 1, 13, "no JOINTS record for the ROBOT record's 3 joint(s)") in found
    text, _ = corrupt(ird, r"(\d+) PROGRAM c", r"\1 JOINTS a1")
    assert (3, 3, "JOINTS: no ROBOT record before it") in errors(text)


def test_cooperate_needs_a_cell() -> None:
    text = ird_text("PROGRAM t;\nROBOT r := six;\nBEGIN\nENDPROGRAM\n")
    text, line = corrupt(text, r"(\d+) L4 END", r"\1 L4 OPTON COOPERATE")
    assert (line, 12, "OPTON COOPERATE: COOPERATE needs a cell of two or more robots") in errors(
        text
    )


# ------------------------------------------------------------------ round trip (hypothesis)

_OPTIONS = ("JOINTLIMIT", "JOINTSPEEDLIMIT", "JOINTACCELLIMIT", "CYCLIC")


@st.composite
def cell_codes(draw) -> Code:
    """Code of 1–4 robots (1–7 joints each, placed or not) with random robot instructions."""
    counts = draw(st.lists(st.integers(1, 7), min_size=1, max_size=4))
    coordinate = st.floats(-1e5, 1e5, allow_nan=False).map(lambda x: round(x, 3))
    robots = []
    for k, n in enumerate(counts):
        kinds = draw(st.text("RP", min_size=n, max_size=n))
        at = draw(st.none() | st.tuples(*[coordinate] * 6))
        robots.append(CellRobot(f"r{k}", f"bot{k}", kinds, tuple(f"a{j}" for j in range(1, n + 1)),
                                at))  # fmt: skip
    cell = len(robots) > 1

    def word(k: int) -> list[str]:
        return [robot_word(k)] if cell else []

    code: list[Instruction] = []
    for _ in range(draw(st.integers(0, 12))):
        choice = draw(st.sampled_from(("move", "option", "freeze", "sys", "fk", "reconf", "coop")))
        k = draw(st.integers(0, len(robots) - 1))
        if choice == "move":
            movers = draw(st.permutations(range(len(robots))))[: draw(st.integers(1, 3))]
            args: list = []
            for m in movers if cell else [0]:
                clauses = draw(st.lists(st.sampled_from(MOVE_CLAUSES), max_size=3, unique=True))
                kind = draw(st.sampled_from(MOVE_KINDS))
                args += [*(["AND"] if args else []), kind, draw(st.integers(1, 3)), *word(m)]
                args += clauses + draw(st.sampled_from(([], ["RECONF:1"], ["RECONF:2"])))
            code.append(Instruction("MOVE", tuple(args), 3))
        elif choice == "option":
            op = draw(st.sampled_from(("OPTON", "OPTOFF")))
            code.append(Instruction(op, (draw(st.sampled_from(_OPTIONS)), *word(k)), 4))
        elif choice == "freeze":
            joints = draw(st.lists(st.integers(1, counts[k]), min_size=1, max_size=3))
            code.append(Instruction("OPTON", ("FREEZE", *word(k), *joints), 5))
        elif choice == "sys":
            name = draw(st.sampled_from(("R_TOOL", "R_BASE", "R_ACT_POSE", "R_ACT_JOINT")))
            code.append(Instruction("PUSHSYS", (name, *word(k)), 6))
        elif choice == "fk":
            code.append(Instruction("CALLB", ("FK", 1, *word(k)), 7))
        elif choice == "reconf":
            code.append(Instruction("RECONF", tuple(word(k)), 8))
        elif cell:
            h = (k + 1) % len(robots)
            vertical = draw(st.sampled_from(((), ("VERTICAL",))))
            code.append(Instruction("OPTON", ("COOPERATE", *word(k), robot_word(h), *vertical), 9))
            code.append(Instruction("OPTOFF", ("COOPERATE", *word(k), robot_word(h)), 10))
    code.append(Instruction("END", (), 11))
    first = robots[0]
    return Code(
        "p", "p.irl", first.var, first.robot, first.joint_kinds, first.joint_names,
        at=first.at, other_robots=robots[1:], routines=[Routine(0, "p", "MAIN", 0)], code=code,
    )  # fmt: skip


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(cell_codes())
def test_cell_code_round_trips(code: Code) -> None:
    text = write_code(code)
    again = read_code(text, "x.ird")
    assert write_code(again) == text
    assert again.code == code.code
    strip = [(r.var, r.robot, r.joint_kinds, r.joint_names, r.at) for r in code.robots]
    assert [(r.var, r.robot, r.joint_kinds, r.joint_names, r.at) for r in again.robots] == strip
    assert again.is_cell == (len(code.robots) > 1)
