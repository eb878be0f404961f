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
from irlc.lang.diagnostics import Diagnostic, Span
from irlc.lang.irdata import ObstacleDef, Slot, Value
from irlc.lang.settings import approximation_hint
from irlc.lang.signature import RobotSignature


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
    """The symbol tables, the routine being checked and the robot's joint names."""

    def __init__(self, robot: RobotSignature | None, report: Reporter):
        self.robot = robot
        self.n = robot.joint_count if robot is not None else 0
        self.report = report
        self.globals: dict[str, Symbol] = {}
        self.locals: dict[str, Symbol] | None = None
        self.routine: RoutineInfo | None = None
        self.obstacles: dict[str, ObstacleDef] = {}
        self.joint_names: tuple[str, ...] = tuple(f"a{i}" for i in range(1, self.n + 1))
        self.joint_field_names: dict[str, tuple[str, ...]] = {}

    def main_joint(self) -> T.JointTuple:
        """The robot's MAIN_JOINT type (one REAL per joint)."""
        return T.JointTuple("MAIN_JOINT", self.n)

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
