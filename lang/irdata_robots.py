"""The robots in IRDATA instructions: the ``ROBOT:k`` operand and the parts of a group
``MOVE`` (docs/irdata.md, Cells).

In a cell (code with several ``ROBOT`` records, robot ``k`` the k-th of them from 0) every
instruction that acts on one robot names it with the operand word ``ROBOT:k`` right after
its fixed operands:

=====================================  ====================================================
``MOVE KIND npts ROBOT:k clause…``      each part of ``MOVE part AND part …`` names its own
``RECONF ROBOT:k``                      self-motion of robot k
``OPTON OPT ROBOT:k …``                 every modal option, on and off (``OPTOFF OPT ROBOT:k``)
``OPTON COOPERATE ROBOT:w ROBOT:h``     robot w works in robot h's tool frame (``VERTICAL``)
``PUSHSYS NAME ROBOT:k`` (``POPSYS``)   a robot's own system variable (cell.ROBOT_VARIABLES)
``CALLB FK 1 ROBOT:k``                  the forward kinematics of robot k
=====================================  ====================================================

Code of one robot leaves the operand out (``ROBOT:0`` is accepted). :func:`move_parts` and
:func:`robot_operand` decode the operands for the runtime; :func:`instruction_problems` is
the reader's check of them.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass

from irlc.lang import platform
from irlc.lang.cell import ROBOT_VARIABLES
from irlc.lang.settings import BY_LIMIT_WORD, BY_WITH_WORD

ROBOT_PREFIX = "ROBOT:"
_ROBOT_WORD = re.compile(r"ROBOT:([0-9]{1,9})")
ROBOT_POSITION = {"RECONF": 0, "OPTON": 1, "OPTOFF": 1, "PUSHSYS": 1, "POPSYS": 1, "CALLB": 2}
"""Where an instruction other than MOVE has its ``ROBOT:k`` operand (index into its
operands): right after its fixed operands."""
PART_SEPARATOR = "AND"  # between the parts of a group MOVE
VERTICAL = "VERTICAL"  # OPTON COOPERATE … VERTICAL: the tool's z axis stays vertical
MOVE_CLAUSES = (*BY_WITH_WORD, *BY_LIMIT_WORD, platform.WORD)
"""The clause words of a MOVE besides ``RECONF:k``."""


def robot_word(index: int) -> str:
    """The operand naming robot ``index``: ``ROBOT:1``."""
    return f"{ROBOT_PREFIX}{index}"


def robot_index(word: object) -> int | None:
    """``k`` of a ``ROBOT:k`` operand, else ``None``."""
    m = _ROBOT_WORD.fullmatch(str(word))
    return int(m.group(1)) if m else None


def takes_robot(op: str, args: Sequence[object]) -> bool:
    """Whether the instruction acts on one robot (names it in a cell): MOVE, RECONF,
    OPTON/OPTOFF, PUSHSYS/POPSYS of a robot's variable, CALLB FK."""
    if op in ("MOVE", "RECONF", "OPTON", "OPTOFF"):
        return True
    if op in ("PUSHSYS", "POPSYS"):
        return bool(args) and args[0] in ROBOT_VARIABLES
    return op == "CALLB" and bool(args) and args[0] == "FK"


def robot_operand(op: str, args: Sequence[object]) -> tuple[int | None, tuple[object, ...]]:
    """An instruction's robot (``None``: not named) and its other operands, for every
    instruction but MOVE (:func:`move_parts`)."""
    position = ROBOT_POSITION.get(op)
    if position is not None and len(args) > position:
        k = robot_index(args[position])
        if k is not None:
            return k, (*args[:position], *args[position + 1 :])
    return None, tuple(args)


@dataclass(frozen=True)
class MovePart:
    """One robot's motion in a ``MOVE``: ``KIND npts [ROBOT:k] clause…``. ``start`` is the
    index of its KIND among the instruction's operands."""

    robot: int | None
    kind: str
    points: int
    clauses: tuple[str, ...]
    start: int


def move_parts(args: Sequence[object]) -> tuple[list[MovePart], list[tuple[int, str]]]:
    """The parts of a MOVE's operands (one, or several joined by ``AND``) and the problems
    found: ``(operand index, message)``. The stack holds the first part's targets and clause
    operands, then the next part's, and so on."""
    parts: list[MovePart] = []
    problems: list[tuple[int, str]] = []
    i = 0
    while True:
        kind = str(args[i]) if i < len(args) else ""
        npts = args[i + 1] if i + 1 < len(args) else None
        if not isinstance(npts, int) or npts < 1:
            where = max(0, min(i + 1, len(args) - 1))
            got = npts if i + 1 < len(args) else "nothing"
            problems.append((where, f"MOVE: expected a positive number of points, got {got}"))
            return parts, problems
        j = i + 2
        robot = robot_index(args[j]) if j < len(args) else None
        j += robot is not None
        clauses = []
        while j < len(args) and args[j] != PART_SEPARATOR:
            word = str(args[j])
            if not _clause_word(word):
                problems.append((j, f"MOVE: unknown clause {word!r}"))
            clauses.append(word)
            j += 1
        parts.append(MovePart(robot, kind, npts, tuple(clauses), i))
        if j >= len(args):
            return parts, problems
        i = j + 1


def _clause_word(word: str) -> bool:
    if word in MOVE_CLAUSES:
        return True
    return word.startswith("RECONF:") and re.fullmatch(r"[1-9][0-9]{0,5}", word[7:]) is not None


def instruction_robots(op: str, args: Sequence[object]) -> list[int]:
    """Every robot an instruction names, in operand order (the writer's comment)."""
    return [k for a in args if (k := robot_index(a)) is not None] if op in (
        *ROBOT_POSITION, "MOVE"
    ) else []  # fmt: skip


def instruction_problems(op: str, args: Sequence[object], robots: int) -> list[tuple[int, str]]:
    """The reader's checks of the robot operands of one instruction in code of ``robots``
    robots: ``(operand index, message)`` per problem (-1: the opcode). A ``ROBOT:k`` word
    names an existing robot, stands where the instruction takes one, and is there in a
    cell; a group MOVE moves each robot once. (COOPERATE's operands: :func:`cooperate_problem`.)"""
    problems: list[tuple[int, str]] = []
    for i, a in enumerate(args):
        k = robot_index(a)
        if k is not None and k >= robots:
            last = f"0..{robots - 1}" if robots > 1 else "0 (one robot)"
            problems.append((i, f"{op}: no robot {k} (the code's robots are {last})"))
        elif k is None and str(a).startswith(ROBOT_PREFIX):
            problems.append((i, f"{op}: expected ROBOT:<index>, got {str(a)[:40]!r}"))
    if problems:
        return problems
    if op == "MOVE":
        return _move_problems(args, robots)
    position = ROBOT_POSITION.get(op)
    cooperate = op in ("OPTON", "OPTOFF") and bool(args) and args[0] == "COOPERATE"
    for i, a in enumerate(args):
        placed = i == position or (cooperate and i == 2)
        if robot_index(a) is not None and not placed:
            problems.append(
                (
                    i,
                    f"{op}: a robot operand {a} out of place"
                    if position is not None
                    else f"{op}: takes no robot operand",
                )
            )
    if position is None or problems:
        return problems
    robot, rest = robot_operand(op, args)
    if not takes_robot(op, args) and robot is not None:
        problems.append((position, f"{op} {args[0]}: takes no robot operand"))
    elif takes_robot(op, args) and robot is None and robots > 1:
        problems.append((-1, f"{op}: a cell's instruction names its robot (ROBOT:k)"))
    expected = _OPERANDS.get(op)
    if expected is not None and len(rest) > expected:
        problems.append((len(args) - 1, f"{op}: unexpected operand {str(args[-1])[:40]!r}"))
    return problems


_OPERANDS = {"RECONF": 0, "PUSHSYS": 1, "POPSYS": 1, "CALLB": 2}  # besides ROBOT:k


def _move_problems(args: Sequence[object], robots: int) -> list[tuple[int, str]]:
    parts, problems = move_parts(args)
    seen: set[int] = set()
    for part in parts:
        if part.robot is None and robots > 1:
            problems.append((part.start, "MOVE: a cell's motion names its robot (ROBOT:k)"))
        k = part.robot or 0
        if k in seen:
            problems.append((part.start, f"MOVE: robot {k} moves twice in one group move"))
        seen.add(k)
    return problems


def cooperate_problem(
    op: str, robot: int | None, rest: Sequence[object], robots: int
) -> str | None:
    """The operands of ``OPTON COOPERATE ROBOT:w ROBOT:h [VERTICAL]`` / ``OPTOFF COOPERATE
    ROBOT:w ROBOT:h`` after the option (``robot`` = w, ``rest`` the rest), else None."""
    if robots < 2:
        return "COOPERATE needs a cell of two or more robots"
    holder = robot_index(rest[0]) if rest else None
    options = tuple(str(x) for x in rest[1:])
    allowed = ((), (VERTICAL,)) if op == "OPTON" else ((),)
    if robot is None or holder is None or options not in allowed:
        tail = f" [{VERTICAL}]" if op == "OPTON" else ""
        return f"expected ROBOT:w ROBOT:h{tail}"
    if robot == holder:
        return f"robot {robot} cannot cooperate with itself"
    return None
