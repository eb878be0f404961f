"""IRDATA code in memory: the format's words (version, opcodes, system variables, motion
kinds, modal options) and the tables of a compiled program (``docs/irdata.md``)."""

from __future__ import annotations

from dataclasses import dataclass, field

from irlc.lang.settings import ALL_KINDS, BY_LIMIT_WORD, LIMIT_TUPLE_TYPES
from irlc.lang.settings import SYSTEM_VARIABLES as SETTING_VARIABLES

FORMAT_VERSION = 1
MAGIC = f"IRDATA {FORMAT_VERSION}"

VALUE_TYPES = ("INTEGER", "REAL", "BOOLEAN", "CHAR", "STRING", "POSITION", "ORIENTATION", "POSE")
"""The scalar value types a constant or variable of the code may have (besides the joint
tuples and, for variables, SIGNAL)."""
JOINT_TUPLE_TYPES = ("MAIN_JOINT", *LIMIT_TUPLE_TYPES)  # limit bounds: lang/settings.py
SYSTEM_VARIABLES = tuple(SETTING_VARIABLES)  # names; their rows: lang/settings.py
MOVE_KINDS = ALL_KINDS
MODAL_OPTIONS = (*BY_LIMIT_WORD, "CYCLIC", "OBSTACLE", "FREEZE", "COOPERATE")

# Operand signatures: i = integer, w = word, t = jump target, * = any number of int/word.
OPCODES: dict[str, str] = {
    "PUSHC": "i", "PUSHG": "i", "POPG": "i", "PUSHL": "i", "POPL": "i",
    "REFG": "i", "REFL": "i", "PUSHSYS": "w*", "POPSYS": "w*", "POP": "", "DUP": "",
    "GETF": "w", "SETF": "w", "GETI": "", "SETI": "",
    "ADD": "", "SUB": "", "MUL": "", "DIV": "", "IDIV": "", "MOD": "", "NEG": "", "NOT": "",
    "EQ": "", "NE": "", "LT": "", "GT": "", "LE": "", "GE": "",
    "AND": "", "OR": "", "XOR": "", "COMPOSE": "",
    "MAKE": "wi", "CALLB": "wi*", "CALL": "ii", "RET": "", "RETV": "",
    "JMP": "t", "JF": "t", "JT": "t", "HALT": "", "PAUSE": "", "END": "",
    "WAIT": "", "WAITFOR": "t", "PUSHIN": "", "SIGOUT": "i", "WRITE": "i", "WRITELN": "i",
    "OUTSET": "", "PUSHOUT": "", "PULSE": "",
    "MOVE": "wi*", "RECONF": "*", "OPTON": "w*", "OPTOFF": "w*",
}  # fmt: skip
# (the variadic tails of CALLB, PUSHSYS, POPSYS and RECONF hold a ROBOT:k operand only:
# lang/irdata_robots.py)


def shown_word(word: str, limit: int = 32) -> str:
    """A word of an ``.ird`` file for a message: quoted, or its start and its length when
    long (a corrupted file may hold a word of any length)."""
    if len(word) <= limit:
        return repr(word)
    return f"{word[:limit]!r}… (a word of {len(word)} characters)"


@dataclass(frozen=True)
class Target:
    """A jump or entry target: the index of an instruction in ``Code.code``."""

    index: int


Operand = int | str | Target


@dataclass(frozen=True)
class Instruction:
    op: str
    args: tuple[Operand, ...] = ()
    line: int = 0  # source line (0: generated)


@dataclass(frozen=True)
class Value:
    """A constant in program units: ``type`` is an IRDATA type name, ``data`` its fields."""

    type: str
    data: tuple


@dataclass(frozen=True)
class Slot:
    index: int
    type: str
    name: str
    by_ref: bool = False


@dataclass
class Routine:
    index: int
    name: str
    kind: str  # "MAIN" | "PROC" | "FUNC:<TYPE>"
    entry: int  # index into Code.code
    params: list[Slot] = field(default_factory=list)
    locals: list[Slot] = field(default_factory=list)

    @property
    def result_type(self) -> str | None:
        return self.kind[5:] if self.kind.startswith("FUNC:") else None


@dataclass(frozen=True)
class ObstacleDef:
    """An obstacle from a data list: ``fields`` maps key → numbers (mm / deg), in order."""

    name: str
    kind: str
    fields: tuple[tuple[str, tuple[float, ...]], ...]

    def get(self, key: str) -> tuple[float, ...] | None:
        return dict(self.fields).get(key)


@dataclass(frozen=True)
class RecordType:
    index: int
    fields: tuple[tuple[str, str], ...]  # (name, type)


@dataclass(frozen=True)
class CellRobot:
    """A robot of the code: a ``ROBOT`` record and the ``JOINTS`` record after it."""

    var: str  # the program's name for the robot
    robot: str  # library name or file
    joint_kinds: str  # one letter per joint: R | P
    joint_names: tuple[str, ...]
    at: tuple[float, ...] | None = None  # AT x y z a b c (mm, ZYX deg); None: the identity
    # (file, line, column) of its robot operand: the ROBOT record of a read file, or the
    # ROBOT clause of a compiled program (robots after the first); None when not known
    position: tuple[str, int, int] | None = None

    @property
    def joint_count(self) -> int:
        return len(self.joint_kinds)


@dataclass
class Code:
    """The code of a program. Its first robot is ``robot_var``, ``robot``, ``joint_kinds``,
    ``joint_names``, ``at``; a cell's further robots are ``other_robots`` (robot 1, 2, …;
    :attr:`robots` lists them all, :attr:`is_cell` says whether there are several)."""

    program: str
    source: str
    robot_var: str
    robot: str
    joint_kinds: str  # one letter per joint: R | P
    joint_names: tuple[str, ...]
    datalists: list[tuple[str, str]] = field(default_factory=list)
    consts: list[Value] = field(default_factory=list)
    obstacles: list[ObstacleDef] = field(default_factory=list)
    inputs: dict[int, list[tuple[float, bool]]] = field(default_factory=dict)
    types: list[RecordType] = field(default_factory=list)
    globals: list[Slot] = field(default_factory=list)
    routines: list[Routine] = field(default_factory=list)
    code: list[Instruction] = field(default_factory=list)
    # Where the ROBOT record was read from: (file, line, column of the robot operand); not
    # part of the format. Empty for code the compiler made (its ROBOT clause was resolved).
    robot_record: tuple[str, int, int] | None = None
    at: tuple[float, ...] | None = None  # the first robot's placement (AT), None: identity
    other_robots: list[CellRobot] = field(default_factory=list)  # a cell's robots 1, 2, …

    @property
    def joint_count(self) -> int:
        return len(self.joint_kinds)

    @property
    def robots(self) -> list[CellRobot]:
        """Every robot of the code, robot 0 first (the ``ROBOT:k`` operands' order)."""
        first = CellRobot(
            self.robot_var, self.robot, self.joint_kinds, self.joint_names, self.at,
            self.robot_record,
        )  # fmt: skip
        return [first, *self.other_robots]

    @property
    def is_cell(self) -> bool:
        """Whether the code runs several robots (docs/irdata.md, Cells)."""
        return bool(self.other_robots)

    def robot_problem(self, message: str) -> str:
        """``message`` about the code's robot, positioned at its ROBOT record when the code
        was read from a file (``x.ird:3:9: the code's ROBOT record: …``), else saying the
        code records no position for it."""
        robot = f"cannot use robot {shown_word(self.robot)}"
        if self.robot_record is None:
            return f"{robot} (the code records no position for its ROBOT record): {message}"
        file, line, col = self.robot_record
        return f"{file}:{line}:{col}: {robot} (the code's ROBOT record): {message}"

    def obstacle(self, name: str) -> ObstacleDef | None:
        key = name.lower()
        return next((o for o in self.obstacles if o.name.lower() == key), None)
