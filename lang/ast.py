"""The abstract syntax tree of an IRL program; every node carries a :class:`Span`.

Expressions get their type from the checker (attribute ``ty``, ``None`` before checking)
and, where they name something, the resolved symbol (``sym``). Names keep the spelling
written at that place; resolution is case-insensitive.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

from irlc.lang.diagnostics import Span


@dataclass(eq=False)
class Node:
    span: Span


# ------------------------------------------------------------------ expressions


@dataclass(eq=False)
class Expr(Node):
    ty: Any = field(default=None, init=False, repr=False)
    const: Any = field(default=None, init=False, repr=False)  # folded value (checker)


@dataclass(eq=False)
class Num(Expr):
    value: int | float
    text: str


@dataclass(eq=False)
class Str(Expr):
    value: str


@dataclass(eq=False)
class Bool(Expr):
    value: bool


@dataclass(eq=False)
class Name(Expr):
    name: str
    sym: Any = field(default=None, init=False, repr=False)


@dataclass(eq=False)
class Call(Expr):
    """``f(args)``: a user function, a built-in, ``POSE(...)`` or ``POSITION(...)``."""

    name: str
    args: list[Expr]
    sym: Any = field(default=None, init=False, repr=False)
    robot: Any = field(default=None, init=False, repr=False)  # FK(robot, k): the robot


@dataclass(eq=False)
class Tuple(Expr):
    """``(a, b, ...)``: typed by its context (``ty`` is set when a context was known)."""

    items: list[Expr]


@dataclass(eq=False)
class Field(Expr):
    base: Expr
    name: str
    canonical: str = field(default="", init=False, repr=False)  # operand of GETF/SETF
    sym: Any = field(default=None, init=False, repr=False)  # robot.R_TOOL: the variable


@dataclass(eq=False)
class Index(Expr):
    base: Expr
    index: Expr
    output: bool = field(default=False, init=False, repr=False)  # OUT[n] (checker)


@dataclass(eq=False)
class Unary(Expr):
    op: str  # "-", "+", "NOT"
    operand: Expr


@dataclass(eq=False)
class Binary(Expr):
    op: str  # "+", "-", "*", "/", "DIV", "MOD", "AND", "OR", "EXOR", ":", "=", "<>", ...
    left: Expr
    right: Expr


@dataclass(eq=False)
class Input(Expr):
    """``IN[n]``: a digital input."""

    index: Expr


# ------------------------------------------------------------------ types


@dataclass(eq=False)
class TypeRef(Node):
    pass


@dataclass(eq=False)
class SimpleTypeRef(TypeRef):
    name: str  # canonical upper-case: INTEGER, POSE, MAIN_JOINT_MIN, ...


@dataclass(eq=False)
class NamedTypeRef(TypeRef):
    name: str


@dataclass(eq=False)
class ArrayTypeRef(TypeRef):
    lo: Expr
    hi: Expr
    elem: TypeRef


@dataclass(eq=False)
class RecordTypeRef(TypeRef):
    fields: list[tuple[TypeRef, list[tuple[str, Span]]]]


# ------------------------------------------------------------------ statements


@dataclass(eq=False)
class Stmt(Node):
    """A statement. Those that name a robot carry ``resolved``: the indices of the robots
    the checker found (the statement's robot; COOPERATE: the cooperating robot, then the
    holding one), in the order of the program's ROBOT clauses."""


@dataclass(eq=False)
class Label(Stmt):
    name: str


@dataclass(eq=False)
class Assign(Stmt):
    target: Expr  # Name, Field or Index
    value: Expr


@dataclass(eq=False)
class CallStmt(Stmt):
    name: str
    args: list[Expr]
    sym: Any = field(default=None, init=False, repr=False)
    pulse: bool = field(default=False, init=False, repr=False)  # PULSE(OUT[n], t) (checker)


@dataclass(eq=False)
class Return(Stmt):
    value: Expr | None


@dataclass(eq=False)
class If(Stmt):
    arms: list[tuple[Expr, list[Stmt]]]
    else_body: list[Stmt] | None
    end_span: Span


@dataclass(eq=False)
class While(Stmt):
    cond: Expr
    body: list[Stmt]
    end_span: Span


@dataclass(eq=False)
class Repeat(Stmt):
    body: list[Stmt]
    cond: Expr
    end_span: Span


@dataclass(eq=False)
class For(Stmt):
    var: Name
    start: Expr
    stop: Expr
    step: Expr | None
    body: list[Stmt]
    end_span: Span


@dataclass(eq=False)
class CaseArm(Node):
    labels: list[tuple[Expr, Expr | None]]  # (value, upper bound of a range or None)
    body: list[Stmt]


@dataclass(eq=False)
class Case(Stmt):
    selector: Expr
    arms: list[CaseArm]
    else_body: list[Stmt] | None
    end_span: Span


@dataclass(eq=False)
class Goto(Stmt):
    label: str


@dataclass(eq=False)
class Wait(Stmt):
    seconds: Expr


@dataclass(eq=False)
class WaitFor(Stmt):
    cond: Expr


@dataclass(eq=False)
class Pause(Stmt):
    pass


@dataclass(eq=False)
class Halt(Stmt):
    pass


@dataclass(eq=False)
class Write(Stmt):
    args: list[Expr]
    newline: bool


@dataclass(eq=False)
class WithClause(Node):
    """``WITH name := v`` (kind = SPEED, ACC, ...) or a limit / reconfiguration clause."""

    kind: str  # SPEED ACC SPEED_ORI SPEED_PTP ACC_PTP TIME JOINTLIMIT ... RECONF
    args: list[Expr]
    word: str = ""  # the option name as written (WITH name := v)


@dataclass(eq=False)
class Move(Stmt):
    """A motion of one robot; in a cell ``robot`` names it (``MOVE welder LIN p``)."""

    kind: str  # PTP LIN LINPATH CIRCLE PTPINC LININC
    targets: list[Expr]
    clauses: list[WithClause]
    robot: str | None = None
    robot_span: Span | None = None
    resolved: tuple[int, ...] = field(default=(), init=False, repr=False)  # (checker)


@dataclass(eq=False)
class MoveGroup(Stmt):
    """``MOVE holder LIN h AND welder PTP w``: the parts start and end together."""

    parts: list[Move]


@dataclass(eq=False)
class ModalOn(Stmt):
    """JOINTLIMIT / JOINTSPEEDLIMIT / JOINTACCELLIMIT / CYCLIC / OBSTACLE / FREEZE on
    (``FOR robot``: ``robot``), or ``COOPERATE robot IN name [WITH word]``."""

    option: str
    args: list[Expr]
    name: str | None = None  # obstacle name; COOPERATE: the holding robot
    name_span: Span | None = None
    robot: str | None = None  # FOR robot; COOPERATE: the cooperating robot
    robot_span: Span | None = None
    word: str | None = None  # COOPERATE … WITH word (VERTICAL)
    word_span: Span | None = None
    resolved: tuple[int, ...] = field(default=(), init=False, repr=False)  # (checker)


@dataclass(eq=False)
class ModalOff(Stmt):
    option: str
    name: str | None = None
    name_span: Span | None = None
    robot: str | None = None  # FOR robot
    robot_span: Span | None = None
    resolved: tuple[int, ...] = field(default=(), init=False, repr=False)  # (checker)


@dataclass(eq=False)
class Reconfigure(Stmt):
    target: Expr
    robot: str | None = None  # FOR robot
    robot_span: Span | None = None
    resolved: tuple[int, ...] = field(default=(), init=False, repr=False)  # (checker)


# ------------------------------------------------------------------ declarations


@dataclass(eq=False)
class ConstDecl(Node):
    name: str
    type: TypeRef | None
    value: Expr


@dataclass(eq=False)
class TypeDecl(Node):
    """``TYPE name = type;`` or (IRL form) ``TYPE RECORD ... ENDRECORD = name;``."""

    name: str
    type: TypeRef
    name_span: Span


@dataclass(eq=False)
class VarDecl(Node):
    type: TypeRef
    names: list[tuple[str, Span]]


@dataclass(eq=False)
class Param(Node):
    name: str
    type: TypeRef
    by_ref: bool


@dataclass(eq=False)
class Decls:
    consts: list[ConstDecl] = field(default_factory=list)
    types: list[TypeDecl] = field(default_factory=list)
    vars: list[VarDecl] = field(default_factory=list)
    order: list[Node] = field(default_factory=list)  # declarations in source order


@dataclass(eq=False)
class Routine(Node):
    name: str
    is_function: bool
    params: list[Param]
    result: TypeRef | None
    decls: Decls
    body: list[Stmt]
    end_span: Span


@dataclass(eq=False)
class RobotClause(Node):
    var: str
    robot: str  # library name or path
    robot_span: Span
    at: Expr | None = None  # AT pose: the robot's base in the cell frame
    var_span: Span | None = None


@dataclass(eq=False)
class DatalistClause(Node):
    name: str


@dataclass(eq=False)
class Unsupported(Node):
    what: str  # "SYSTEM SPECIFICATION", "FROM ... IMPORT", ...


@dataclass(eq=False)
class Program(Node):
    name: str
    robot: list[RobotClause]
    datalists: list[DatalistClause]
    unsupported: list[Unsupported]
    decls: Decls
    routines: list[Routine]
    body: list[Stmt]
    end_span: Span


def statements_in_order(body: list[Stmt]) -> Iterator[Stmt]:
    """Every statement of ``body`` in source order, each nested body (IF and CASE arms,
    loop bodies) right after its statement."""
    for s in body:
        yield s
        if isinstance(s, If):
            for _, arm in s.arms:
                yield from statements_in_order(arm)
            if s.else_body:
                yield from statements_in_order(s.else_body)
        elif isinstance(s, Case):
            for arm in s.arms:
                yield from statements_in_order(arm.body)
            if s.else_body:
                yield from statements_in_order(s.else_body)
        elif isinstance(s, While | Repeat | For):
            yield from statements_in_order(s.body)


def literal_text(e: Expr) -> str | None:
    """A number literal as the program wrote it (``-5``, ``1E300``), with a sign written
    before it; ``None`` for any other expression."""
    sign = ""
    while isinstance(e, Unary) and e.op in ("-", "+"):
        sign += e.op
        e = e.operand
    return sign + e.text if isinstance(e, Num) else None
