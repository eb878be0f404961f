"""The names a program sees: symbols, the global and the routine's local scope, lookup.

Names are case-insensitive: a scope maps the lower-case name to its :class:`Symbol`, and
messages use the declared spelling (``Symbol.name``). A routine's locals (parameters first)
shadow the globals (Pascal); system variables are found after both and cannot be declared.
The :class:`Reporter` collects the checker's diagnostics in the order they are found.
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass, field

from irlc.lang import ast
from irlc.lang import types as T
from irlc.lang.builtins import SYSTEM_VARIABLES
from irlc.lang.cell import ROBOT_VARIABLES, ProgramRobot, common_joint_count, robot_list
from irlc.lang.diagnostics import Diagnostic, Span
from irlc.lang.irdata import ObstacleDef, Slot, Value
from irlc.lang.settings import approximation_hint
from irlc.lang.signature import RobotSignature

RobotNamed = ast.Move | ast.ModalOn | ast.ModalOff | ast.Reconfigure
"""The statements that name a robot in a cell."""


@dataclass(eq=False)
class RoutineInfo:
    index: int
    name: str
    is_function: bool
    params: list[Slot]
    param_types: list[T.Type]
    result: T.Type | None
    locals: list[Slot] = field(default_factory=list)
    local_types: list[T.Type] = field(default_factory=list)
    node: ast.Routine | None = None
    elements: int = 0  # of its parameters passed by value and its locals (T.elements)
    symbols: dict[str, Symbol] = field(default_factory=dict)  # its scope: parameters, locals

    @property
    def kind(self) -> str:
        return f"FUNC:{self.result.ird()}" if self.is_function and self.result else "PROC"


@dataclass(eq=False)
class Symbol:
    kind: str  # var | param | const | type | routine | robot | sysvar | obstacle
    name: str  # declared spelling
    type: T.Type | None
    where: str  # "line 12" or "data list FILE (key K)"
    storage: str = ""  # "G" global slot | "L" local slot
    index: int = -1
    value: Value | None = None
    writable: bool = True
    routine: RoutineInfo | None = None
    span: Span | None = None  # where it is declared (its name), for editors
    file: str | None = None  # the file declaring it when not the program (a data list)
    robot: int | None = None  # a robot's index; a system variable's robot in a cell


class Reporter:
    """The checker's diagnostics, in the order they are found, for one source file."""

    def __init__(self, filename: str):
        self.file = filename
        self.diags: list[Diagnostic] = []

    def error(self, span: Span | None, msg: str, hint: str | None = None) -> None:
        self.diags.append(Diagnostic("error", msg, self.file, span, hint))

    def warning(self, span: Span | None, msg: str, hint: str | None = None) -> None:
        self.diags.append(Diagnostic("warning", msg, self.file, span, hint))


class Scope:
    """The symbol tables, the routine being checked, the robots and their joint names.

    ``n`` is the joint count of the program's robots, 0 in a cell whose robots differ in it:
    there a joint tuple takes any number of values, checked where it meets a robot."""

    def __init__(self, robots: list[ProgramRobot], report: Reporter):
        self.robots = robots
        self.cell = len(robots) > 1
        self.n = common_joint_count(robots) or 0
        self.report = report
        self.globals: dict[str, Symbol] = {}
        self.locals: dict[str, Symbol] | None = None
        self.routine: RoutineInfo | None = None
        self.obstacles: dict[str, ObstacleDef] = {}
        most = max((r.n for r in robots), default=0)
        self.joint_names: tuple[str, ...] = tuple(f"a{i}" for i in range(1, most + 1))
        self.joint_field_names: dict[str, tuple[str, ...]] = {}

    @property
    def robot(self) -> RobotSignature | None:
        """The program's robot when it has one (``None`` in a cell)."""
        return self.robots[0].signature if len(self.robots) == 1 else None

    def main_joint(self) -> T.JointTuple:
        """The MAIN_JOINT type (one REAL per joint; any number in a mixed cell)."""
        return T.JointTuple("MAIN_JOINT", self.n)

    # ------------------------------------------------------------------ robots
    def find_robot(self, name: str, span: Span) -> ProgramRobot | None:
        """The robot called ``name``; an error at ``span`` if there is none."""
        robot = next((r for r in self.robots if r.var.lower() == name.lower()), None)
        if robot is None:
            sym = self.lookup(name)
            what = f"'{sym.name}' is not a robot" if sym is not None else f"unknown robot '{name}'"
            hint = f"robots of this program: {robot_list(self.robots)}"
            names = [r.var for r in self.robots]
            close = difflib.get_close_matches(name.lower(), [n.lower() for n in names], 1, 0.6)
            if close:
                hint = f"did you mean '{names[[n.lower() for n in names].index(close[0])]}'? {hint}"
            self.report.error(span, what, hint)
        return robot

    def robot_of(self, s: RobotNamed, what: str, example: str) -> ProgramRobot | None:
        """The robot a statement names (its ``robot``, at ``robot_span``); without a name
        the program's one robot, an error in a cell (``what``: the statement's words,
        ``example``: how it names a robot, ``{}`` for the name)."""
        if s.robot is not None:
            return self.find_robot(s.robot, s.robot_span or s.span)
        if not self.cell:
            return self.robots[0]
        self.report.error(
            s.span,
            f"{what} in a cell names its robot ({robot_list(self.robots)})",
            "write " + example.format(self.robots[0].var),
        )
        return None

    def robot_variable(self, robot: ProgramRobot, name: str) -> Symbol:
        """``robot.NAME``: a system variable of one robot (:data:`ROBOT_VARIABLES`)."""
        sym = self.lookup(name)
        assert sym is not None and sym.kind == "sysvar", name
        sym.robot = robot.index if self.cell else None
        return sym

    def robot_variable_problem(self, sym: Symbol, span: Span) -> bool:
        """A robot's own system variable without its robot in a cell: reported (True)."""
        if not self.cell or sym.kind != "sysvar" or sym.name not in ROBOT_VARIABLES:
            return False
        if sym.robot is not None:  # robot.R_TOOL
            return False
        self.report.error(
            span,
            f"{sym.name} belongs to one robot of the cell ({robot_list(self.robots)})",
            f"write {self.robots[0].var}.{sym.name}",
        )
        return True

    # ------------------------------------------------------------------ declare
    def declare_global(self, name: str, sym: Symbol, span: Span) -> bool:
        return self.declare(self.globals, name, sym, span)

    def declare(self, scope: dict[str, Symbol], name: str, sym: Symbol, span: Span) -> bool:
        """Add ``sym`` to ``scope`` (locals may shadow globals); False: reported clash."""
        key = name.lower()
        if key.upper() in SYSTEM_VARIABLES:
            self.report.error(span, f"'{name}' is a system variable and cannot be redeclared")
            return False
        prev = scope.get(key)
        if prev is not None:
            also = "" if prev.name == name else f" as '{prev.name}'"
            self.report.error(
                span,
                f"'{name}' is already defined{also} ({prev.where})",
                "names are case-insensitive; choose another name",
            )
            return False
        if sym.span is None:
            sym.span = span
        scope[key] = sym
        return True

    # ------------------------------------------------------------------ lookup
    def lookup(self, name: str) -> Symbol | None:
        key = name.lower()
        if self.locals is not None and key in self.locals:
            return self.locals[key]
        if key in self.globals:
            return self.globals[key]
        up = name.upper()
        if up in SYSTEM_VARIABLES:
            ty, writable = SYSTEM_VARIABLES[up]
            return Symbol(
                "sysvar",
                up,
                ty or self.main_joint(),
                "system variable",
                writable=writable,
            )
        return None

    def suggest(self, name: str, kinds: tuple[str, ...] | None = None) -> str | None:
        """A hint for an unknown name: approximate positioning's foreign words (C_DIS,
        ZONE, z50, …), else the closest known name."""
        hint = approximation_hint(name)
        if hint is not None:
            return hint
        pool = []
        for scope in (self.locals or {}, self.globals):
            pool += [s.name for s in scope.values() if kinds is None or s.kind in kinds]
        if kinds is None or "sysvar" in kinds:
            pool += list(SYSTEM_VARIABLES)
        close = difflib.get_close_matches(name.lower(), [p.lower() for p in pool], n=1, cutoff=0.75)
        if close:
            spelled = next(p for p in pool if p.lower() == close[0])
            return f"did you mean '{spelled}'?"
        return None
