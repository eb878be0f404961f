"""Static checks of an IRL program: names, types, arities and the rules of docs/language.md.

The checker walks the AST once, resolves every name (case-insensitively; messages use the
declared spelling), gives every expression its type (``Expr.ty``) and folds constants
(``Expr.const``, an IRDATA :class:`Value`). Tuple literals take their type from the
context. The modal redundancy statements are checked per statement list: an END needs an
earlier START of the same kind in the same list, a START is not repeated while it is open
(also from an enclosing list), and every START is closed before its list ends. ``repl``
mode skips the two pairing checks (the interpreter checks them at run time).
"""

from __future__ import annotations

import difflib
import math
import re
from dataclasses import dataclass, field

from irlc.lang import ast
from irlc.lang import types as T
from irlc.lang.approx_lint import approx_warnings
from irlc.lang.builtins import BUILTINS, POSE_FROM_NUMBERS, POSE_FROM_PARTS, SYSTEM_VARIABLES
from irlc.lang.datalist import Datalist
from irlc.lang.diagnostics import Diagnostic, Span
from irlc.lang.digital_io import is_output_syntax, output_error, pulse_error
from irlc.lang.irdata import ObstacleDef, Slot, Value, string_too_long
from irlc.lang.settings import (
    BY_SYSTEM_VARIABLE,
    BY_WITH_WORD,
    approximation_hint,
    reconfiguration_counts,
    setting_message,
)
from irlc.lang.signature import RobotSignature

MAX_ARRAY = 1_000_000
_LIMIT_TYPES = {
    "JOINTLIMIT": ("MAIN_JOINT_MIN", "MAIN_JOINT_MAX"),
    "JOINTSPEEDLIMIT": ("MAIN_JOINT_SPEED_MIN", "MAIN_JOINT_SPEED_MAX"),
    "JOINTACCELLIMIT": ("MAIN_JOINT_ACCEL_MIN", "MAIN_JOINT_ACCEL_MAX"),
}
_START_WORD = {
    "JOINTLIMIT": "JOINTLIMIT",
    "JOINTSPEEDLIMIT": "JOINTSPEEDLIMIT",
    "JOINTACCELLIMIT": "JOINTACCELLIMIT",
    "CYCLIC": "CYCLICSTART",
    "OBSTACLE": "OBSTACLE",
    "FREEZE": "FREEZESTART",
}
_END_WORD = {
    "JOINTLIMIT": "JOINTLIMITEND",
    "JOINTSPEEDLIMIT": "JOINTSPEEDLIMITEND",
    "JOINTACCELLIMIT": "JOINTACCELLIMITEND",
    "CYCLIC": "CYCLICEND",
    "OBSTACLE": "OBSTACLEEND",
    "FREEZE": "FREEZEEND",
}
_WITH_PARAMS = tuple(BY_WITH_WORD)  # SPEED ACC SPEED_ORI SPEED_PTP ACC_PTP TIME


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


@dataclass
class Checked:
    """What the code generator needs besides the annotated AST."""

    program: ast.Program
    joint_names: tuple[str, ...]
    records: list[T.Record]
    globals: list[Slot]
    global_types: list[T.Type]
    routines: list[RoutineInfo]
    obstacles: list[ObstacleDef]
    inputs: dict[int, list[tuple[float, bool]]]
    datalists: list[Datalist]


class _ListState:
    def __init__(self, outer: _ListState | None):
        self.outer = outer
        self.open: dict[str, tuple[str, Span]] = {}  # key -> (display, START span)

    def find_open(self, key: str) -> Span | None:
        s: _ListState | None = self
        while s is not None:
            if key in s.open:
                return s.open[key][1]
            s = s.outer
        return None


def _num(v: Value | None) -> float | int | None:
    if v is None or v.type not in ("INTEGER", "REAL") or not v.data:
        return None
    return v.data[0]


class Checker:
    def __init__(
        self,
        program: ast.Program,
        filename: str,
        robot: RobotSignature | None,
        datalists: list[Datalist],
        *,
        repl: bool = False,
    ):
        self.prog = program
        self.file = filename
        self.robot = robot
        self.n = robot.joint_count if robot is not None else 0
        self.datalists = datalists
        self.repl = repl
        self.diags: list[Diagnostic] = []
        self.globals: dict[str, Symbol] = {}
        self.locals: dict[str, Symbol] | None = None
        self.routine: RoutineInfo | None = None
        self.records: list[T.Record] = []
        self.global_slots: list[Slot] = []
        self.global_types: list[T.Type] = []
        self.routines: list[RoutineInfo] = []
        self.obstacles: dict[str, ObstacleDef] = {}
        self.inputs: dict[int, list[tuple[float, bool]]] = {}
        self.joint_names: tuple[str, ...] = tuple(f"a{i}" for i in range(1, self.n + 1))
        self.joint_field_names: dict[str, tuple[str, ...]] = {}
        self.state: _ListState | None = None
        self.labels: dict[str, ast.Label] = {}

    # ------------------------------------------------------------------ diagnostics
    def error(self, span: Span | None, msg: str, hint: str | None = None) -> None:
        self.diags.append(Diagnostic("error", msg, self.file, span, hint))

    def warning(self, span: Span | None, msg: str, hint: str | None = None) -> None:
        self.diags.append(Diagnostic("warning", msg, self.file, span, hint))

    # ------------------------------------------------------------------ entry
    def check(self) -> Checked:
        p = self.prog
        for u in p.unsupported:
            self.error(
                u.span,
                f"{u.what} is not supported by irlc",
                "irlc runs one program on one simulated robot; remove this clause",
            )
        if len(p.robot) > 1:
            self.error(
                p.robot[1].span,
                "a second ROBOT clause",
                f"the program already names its robot on line {p.robot[0].span.line}",
            )
        if p.robot:
            rc = p.robot[0]
            self.declare_global(
                rc.var, Symbol("robot", rc.var, None, f"line {rc.span.line}"), rc.span
            )
        self.find_joint_record(p.decls)
        self.add_datalists()
        self.declare_all(p.decls, is_global=True)
        for r in p.routines:
            self.declare_routine(r)
        main = RoutineInfo(0, p.name, False, [], [], None)
        self.routines.insert(0, main)
        for i, info in enumerate(self.routines):
            info.index = i
        for info in self.routines[1:]:
            self.check_routine(info)
        self.routine = main
        self.collect_labels(p.body)
        self.check_list(p.body, p.end_span, "ENDPROGRAM")
        self.routine = None
        for node, message, hint in approx_warnings(p.body):
            self.warning(node.span, message, hint)
        return Checked(
            p,
            self.joint_names,
            self.records,
            self.global_slots,
            self.global_types,
            self.routines,
            list(self.obstacles.values()),
            self.inputs,
            self.datalists,
        )

    # ------------------------------------------------------------------ declarations
    def declare_global(self, name: str, sym: Symbol, span: Span) -> bool:
        return self._declare(self.globals, name, sym, span)

    def _declare(self, scope: dict[str, Symbol], name: str, sym: Symbol, span: Span) -> bool:
        key = name.lower()
        if key.upper() in SYSTEM_VARIABLES:
            self.error(span, f"'{name}' is a system variable and cannot be redeclared")
            return False
        prev = scope.get(key)
        if prev is not None:
            also = "" if prev.name == name else f" as '{prev.name}'"
            self.error(
                span,
                f"'{name}' is already defined{also} ({prev.where})",
                "names are case-insensitive; choose another name",
            )
            return False
        if self.locals is not None and scope is self.locals:
            pass  # locals may shadow globals (Pascal)
        scope[key] = sym
        return True

    def find_joint_record(self, decls: ast.Decls) -> None:
        for td in decls.types:
            is_record = isinstance(td.type, ast.RecordTypeRef)
            if td.name.upper() not in T.JOINT_TUPLE_TYPES or not is_record:
                continue
            names: list[str] = []
            for ftype, fnames in td.type.fields:
                if not (isinstance(ftype, ast.SimpleTypeRef) and ftype.name == "REAL"):
                    self.error(ftype.span, f"the fields of {td.name.upper()} must be REAL")
                names += [n for n, _ in fnames]
            seen: set[str] = set()
            for n, s in (x for _, fl in td.type.fields for x in fl):
                if n.lower() in seen:
                    self.error(s, f"joint name '{n}' is repeated")
                seen.add(n.lower())
            if self.robot is not None and len(names) != self.n:
                self.error(
                    td.span,
                    f"{td.name.upper()} declares {len(names)} joints, but robot "
                    f"{self.robot.name} has {self.n}",
                    f"declare one REAL field per joint ({self.n})",
                )
                continue
            self.joint_field_names[td.name.upper()] = tuple(names)
            if td.name.upper() == "MAIN_JOINT":
                self.joint_names = tuple(names)

    def add_datalists(self) -> None:
        for dl in self.datalists:
            for item in dl.items:
                sym = Symbol(
                    "const",
                    item.name,
                    self.value_type(item.value),
                    f"data list {item.file}, key {item.key}",
                    value=item.value,
                )
                self._declare_item(item.name, sym, item)
            for o, item in dl.obstacles:
                sym = Symbol("obstacle", o.name, None, f"data list {item.file}, key {item.key}")
                if self._declare_item(o.name, sym, item):
                    self.obstacles[o.name.lower()] = o
            for n, timeline in dl.inputs.items():
                if n in self.inputs:
                    self.diags.append(
                        Diagnostic(
                            "error", f"input {n} is defined in two data lists", dl.path, None
                        )
                    )
                self.inputs[n] = timeline

    def _declare_item(self, name: str, sym: Symbol, item) -> bool:
        prev = self.globals.get(name.lower())
        if prev is not None:
            self.diags.append(
                Diagnostic(
                    "error",
                    f"'{name}' is defined twice: {sym.where} and {prev.where}",
                    item.file,
                    item.span,
                )
            )
            return False
        self.globals[name.lower()] = sym
        return True

    def value_type(self, v: Value) -> T.Type:
        if v.type in T.JOINT_TUPLE_TYPES:
            return T.JointTuple(v.type, self.n)
        return T.SIMPLE.get(v.type, T.ERROR)

    def declare_all(self, decls: ast.Decls, is_global: bool) -> None:
        scope = self.globals if is_global else self.locals
        assert scope is not None
        for d in decls.order:
            if isinstance(d, ast.ConstDecl):
                self.declare_const(d, scope)
            elif isinstance(d, ast.TypeDecl):
                self.declare_type(d, scope)
            elif isinstance(d, ast.VarDecl):
                self.declare_vars(d, scope, is_global)

    def _collides_with_datalist(self, scope, name: str, span: Span) -> bool:
        prev = scope.get(name.lower())
        if prev is not None and prev.where.startswith("data list"):
            self.error(
                span,
                f"'{name}' is already defined in {prev.where}",
                "rename the program's declaration or the data-list entry",
            )
            return True
        return False

    def declare_const(self, d: ast.ConstDecl, scope) -> None:
        want = self.resolve_type(d.type) if d.type is not None else None
        ty = self.expr(d.value, want)
        if want is not None:
            self.require(d.value, want, ty, f"constant '{d.name}'")
            ty = want
        v = self.coerce_const(d.value.const, ty)
        if v is None and ty != T.ERROR:
            self.error(
                d.value.span,
                f"the value of constant '{d.name}' is not a constant expression",
                "constants take numbers, strings, booleans, other constants and tuples of them",
            )
        if self._collides_with_datalist(scope, d.name, d.span):
            return
        self._declare(
            scope, d.name, Symbol("const", d.name, ty, f"line {d.span.line}", value=v), d.span
        )

    def coerce_const(self, v: Value | None, ty: T.Type) -> Value | None:
        if v is None:
            return None
        if ty == T.REAL and v.type == "INTEGER":
            return Value("REAL", (float(v.data[0]),))
        if ty == T.STRING and v.type == "CHAR":
            return Value("STRING", v.data)
        return v

    def declare_type(self, d: ast.TypeDecl, scope) -> None:
        upper = d.name.upper()
        if upper in T.JOINT_TUPLE_TYPES:
            if scope is not self.globals:
                self.error(d.span, f"{upper} can only be declared at program level")
            return  # handled by find_joint_record
        ty = self.resolve_type(d.type, name=d.name)
        if self._collides_with_datalist(scope, d.name, d.name_span):
            return
        self._declare(
            scope, d.name, Symbol("type", d.name, ty, f"line {d.name_span.line}"), d.name_span
        )

    def declare_vars(self, d: ast.VarDecl, scope, is_global: bool) -> None:
        ty = self.resolve_type(d.type)
        if ty == T.SIGNAL and not is_global:
            self.error(d.type.span, "SIGNAL variables must be declared at program level")
        for name, span in d.names:
            if self._collides_with_datalist(scope, name, span):
                continue
            sym = Symbol("var", name, ty, f"line {span.line}")
            if is_global:
                sym.storage, sym.index = "G", len(self.global_slots)
            else:
                assert self.routine is not None
                r = self.routine
                sym.storage, sym.index = "L", len(r.params) + len(r.locals)
            if not self._declare(scope, name, sym, span):
                continue
            if is_global:
                self.global_slots.append(Slot(sym.index, ty.ird(), name))
                self.global_types.append(ty)
            else:
                assert self.routine is not None
                self.routine.locals.append(Slot(sym.index, ty.ird(), name))
                self.routine.local_types.append(ty)

    def resolve_type(self, ref: ast.TypeRef, name: str | None = None) -> T.Type:
        if isinstance(ref, ast.SimpleTypeRef):
            if ref.name in T.JOINT_TUPLE_TYPES:
                return T.JointTuple(ref.name, self.n)
            return T.SIMPLE[ref.name]
        if isinstance(ref, ast.NamedTypeRef):
            sym = self.lookup(ref.name)
            if sym is None or sym.kind != "type":
                what = "not a type" if sym is not None else "unknown type"
                self.error(
                    ref.span, f"{what} '{ref.name}'", self.suggest(ref.name, kinds=("type",))
                )
                return T.ERROR
            return sym.type or T.ERROR
        if isinstance(ref, ast.ArrayTypeRef):
            return self.array_type(ref)
        if isinstance(ref, ast.RecordTypeRef):
            return self.record_type(ref, name)
        raise TypeError(ref)

    def array_type(self, ref: ast.ArrayTypeRef) -> T.Type:
        bounds = []
        for e in (ref.lo, ref.hi):
            self.expr(e, T.INTEGER)
            v = e.const
            if v is None or v.type != "INTEGER":
                self.error(e.span, "array bounds must be INTEGER constants")
                return T.ERROR
            bounds.append(v.data[0])
        lo, hi = bounds
        if hi < lo:
            self.error(ref.span, f"array bounds [{lo}..{hi}]: the upper bound is below the lower")
            return T.ERROR
        if hi - lo + 1 > MAX_ARRAY:
            self.error(ref.span, f"array of {hi - lo + 1} elements is too large (max {MAX_ARRAY})")
            return T.ERROR
        elem = self.resolve_type(ref.elem)
        if elem == T.SIGNAL:
            self.error(ref.elem.span, "SIGNAL can only be the type of a plain variable")
        return T.Array("ARRAY", lo, hi, elem)

    def record_type(self, ref: ast.RecordTypeRef, name: str | None) -> T.Type:
        fields: list[tuple[str, T.Type]] = []
        seen: set[str] = set()
        for ftype, names in ref.fields:
            ty = self.resolve_type(ftype)
            if ty == T.SIGNAL:
                self.error(ftype.span, "SIGNAL can only be the type of a plain variable")
            for n, s in names:
                if n.lower() in seen:
                    self.error(s, f"field '{n}' is repeated")
                    continue
                seen.add(n.lower())
                fields.append((n, ty))
        rec = T.Record(name or f"RECORD#{len(self.records)}", len(self.records), tuple(fields))
        self.records.append(rec)
        return rec

    def declare_routine(self, r: ast.Routine) -> None:
        info = RoutineInfo(len(self.routines) + 1, r.name, r.is_function, [], [], None, node=r)
        saved = self.locals
        self.locals = {}
        for i, prm in enumerate(r.params):
            ty = self.resolve_type(prm.type)
            if ty == T.SIGNAL:
                self.error(prm.type.span, "a parameter cannot be a SIGNAL")
            info.params.append(Slot(i, ty.ird(), prm.name, prm.by_ref))
            info.param_types.append(ty)
        if r.result is not None:
            info.result = self.resolve_type(r.result)
        self.locals = saved
        sym = Symbol("routine", r.name, None, f"line {r.span.line}", routine=info)
        if self._collides_with_datalist(self.globals, r.name, r.span):
            return
        if r.name.upper() in BUILTINS or r.name.upper() == "POSE":
            self.error(r.span, f"'{r.name}' is a built-in function and cannot be redefined")
            return
        if self.declare_global(r.name, sym, r.span):
            self.routines.append(info)

    def check_routine(self, info: RoutineInfo) -> None:
        r = info.node
        assert r is not None
        self.routine = info
        self.locals = {}
        for prm, slot, ty in zip(r.params, info.params, info.param_types, strict=True):
            sym = Symbol("param", prm.name, ty, f"line {prm.span.line}", "L", slot.index)
            self._declare(self.locals, prm.name, sym, prm.span)
        self.declare_all(r.decls, is_global=False)
        self.collect_labels(r.body)
        end_word = "ENDFCT" if r.is_function else "ENDPROC"
        self.check_list(r.body, r.end_span, end_word)
        if r.is_function and not self.returns(r.body):
            self.warning(
                r.end_span,
                f"function '{r.name}' may end without RETURN",
                "a function that ends without RETURN stops the program with a run-time error",
            )
        self.locals = None
        self.routine = None

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
                ty or T.JointTuple("MAIN_JOINT", self.n),
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

    # ------------------------------------------------------------------ expressions
    def require(self, e: ast.Expr, want: T.Type, got: T.Type, what: str) -> bool:
        if T.assignable(want, got):
            return True
        self.error(e.span, f"{what}: expected {want}, got {got}", self._type_hint(want, got))
        return False

    def _type_hint(self, want: T.Type, got: T.Type) -> str | None:
        if want == T.INTEGER and got == T.REAL:
            return "convert with ROUND(x) or TRUNC(x)"
        if isinstance(want, T.JointTuple) and isinstance(got, T.JointTuple):
            return (
                "joint-tuple types do not convert into each other; "
                "declare the variable with the type you need"
            )
        return None

    def expr(self, e: ast.Expr, want: T.Type | None = None) -> T.Type:
        method = getattr(self, f"e_{type(e).__name__.lower()}")
        ty = method(e, want)
        e.ty = ty
        return ty

    def e_num(self, e: ast.Num, want) -> T.Type:
        if isinstance(e.value, int):
            e.const = Value("INTEGER", (e.value,))
            return T.INTEGER
        e.const = Value("REAL", (e.value,))
        return T.REAL

    def e_str(self, e: ast.Str, want) -> T.Type:
        if too_long := string_too_long(len(e.value)):
            self.error(e.span, too_long)
            return T.ERROR
        if len(e.value) == 1 and want == T.CHAR:
            e.const = Value("CHAR", (e.value,))
            return T.CHAR
        e.const = Value("STRING", (e.value,))
        if len(e.value) == 1 and want is None:
            return T.STRING
        return T.STRING

    def e_bool(self, e: ast.Bool, want) -> T.Type:
        e.const = Value("BOOLEAN", (e.value,))
        return T.BOOLEAN

    def e_name(self, e: ast.Name, want) -> T.Type:
        sym = self.lookup(e.name)
        if sym is None:
            self.error(
                e.span,
                f"unknown name '{e.name}'",
                self.suggest(e.name),
            )
            return T.ERROR
        e.sym = sym
        if sym.kind == "routine":
            info = sym.routine
            assert info is not None
            if info.is_function and not info.params:
                return info.result or T.ERROR
            what = "procedure" if not info.is_function else "function with parameters"
            self.error(e.span, f"'{sym.name}' is a {what}, not a value")
            return T.ERROR
        if sym.kind in ("type", "robot", "obstacle"):
            what = {"type": "a type", "robot": "the robot", "obstacle": "an obstacle"}[sym.kind]
            hint = "use it in OBSTACLE / OBSTACLEEND" if sym.kind == "obstacle" else None
            self.error(e.span, f"'{sym.name}' is {what}, not a value", hint)
            return T.ERROR
        if sym.kind == "const":
            e.const = sym.value
        return T.value_type(sym.type or T.ERROR)

    def e_tuple(self, e: ast.Tuple, want) -> T.Type:
        arity = T.tuple_arity(want) if want is not None else None
        if want is None or want == T.ERROR or arity is None:
            if want is None:
                self.error(
                    e.span,
                    f"a tuple of {len(e.items)} values has no type here",
                    "tuples are typed by their context: assign to a typed variable, pass "
                    "to a typed parameter, or use POSE(...) / POSITION(...)",
                )
            elif want != T.ERROR:
                self.error(e.span, f"expected {want}, got a tuple of {len(e.items)} values")
            for item in e.items:
                if not isinstance(item, ast.Tuple):
                    self.expr(item, None)
            return T.ERROR
        if isinstance(want, T.JointTuple) and want.n == 0:
            arity = len(e.items)  # robot unknown: no arity check
        if len(e.items) != arity:
            self.error(
                e.span, f"{want} needs {arity} values, got {len(e.items)}", self._arity_hint(want)
            )
            return T.ERROR
        item_types = (
            T.tuple_items(want)
            if not (isinstance(want, T.JointTuple) and want.n == 0)
            else [T.REAL] * arity
        )
        consts = []
        for k, (item, it) in enumerate(zip(e.items, item_types, strict=True), start=1):
            got = self.expr(item, it)
            self.require(item, it, got, f"value {k} of the {want}")
            consts.append(self.coerce_const(item.const, it))
        if (isinstance(want, T.JointTuple) or want in (T.POSE, T.POSITION)) and all(
            c is not None and c.type in ("INTEGER", "REAL") for c in consts
        ):
            e.const = Value(want.ird(), tuple(float(c.data[0]) for c in consts))
        return want

    def _arity_hint(self, want: T.Type) -> str | None:
        if isinstance(want, T.JointTuple) and self.robot is not None:
            return f"robot {self.robot.name} has {self.n} joints: one value per joint"
        if want == T.POSE:
            return "a POSE tuple is (x, y, z, a, b, c): mm and ZYX degrees"
        return None

    def e_unary(self, e: ast.Unary, want) -> T.Type:
        t = self.expr(e.operand, want if e.op != "NOT" else T.BOOLEAN)
        c = e.operand.const
        if t == T.ERROR:
            return T.ERROR
        if e.op == "NOT":
            if t != T.BOOLEAN:
                self.error(e.span, f"NOT needs a BOOLEAN, got {t}")
                return T.ERROR
            if c is not None:
                e.const = Value("BOOLEAN", (not c.data[0],))
            return T.BOOLEAN
        if t.is_numeric:
            if c is not None:
                v = (-1 if e.op == "-" else 1) * c.data[0]
                if t == T.INTEGER and (overflow := T.integer_overflow(v)):
                    self.error(e.span, f"negation: {overflow}")
                    return T.ERROR
                e.const = Value(c.type, (v,))
            return t
        if e.op == "-" and (t == T.POSITION or isinstance(t, T.JointTuple)):
            if c is not None and c.type == t.ird():
                e.const = Value(c.type, tuple(-x for x in c.data))
            return t
        self.error(e.span, f"cannot apply unary '{e.op}' to {t}")
        return T.ERROR

    def e_binary(self, e: ast.Binary, want) -> T.Type:
        op = e.op.upper()
        if op == ":":
            lt, rt = self.compose_operands(e)
        else:
            lt, rt = self.expr(e.left, None), self.expr(e.right, None)
        if T.ERROR in (lt, rt):
            return T.ERROR
        ty = self.binary_type(e, op, lt, rt)
        if ty != T.ERROR:
            self.fold_binary(e, op, ty)
        return ty

    def compose_operands(self, e: ast.Binary) -> tuple[T.Type, T.Type]:
        """Operand types of ``a : b``; a tuple literal operand is a POSE when it can only be.

        ``p : (…)`` and ``(…) : p`` with ``p`` a POSE (or, on the right, a POSITION), and
        ``(…) : (…)``, type their tuples as POSE (6 values); other tuples have no context."""
        left, right = e.left, e.right
        if isinstance(left, ast.Tuple) and isinstance(right, ast.Tuple):
            return self.expr(left, T.POSE), self.expr(right, T.POSE)
        if isinstance(left, ast.Tuple):
            rt = self.expr(right, None)
            return self.expr(left, _pose_context(rt, (T.POSE, T.POSITION))), rt
        lt = self.expr(left, None)
        want = _pose_context(lt, (T.POSE,)) if isinstance(right, ast.Tuple) else None
        return lt, self.expr(right, want)

    def binary_type(self, e: ast.Binary, op: str, lt: T.Type, rt: T.Type) -> T.Type:
        num = lt.is_numeric and rt.is_numeric
        words = {"+": "add", "-": "subtract", "*": "multiply", "/": "divide"}
        text = {"STRING", "CHAR"}
        if op in ("+", "-"):
            if num:
                return T.INTEGER if lt == rt == T.INTEGER else T.REAL
            if op == "+" and lt.name in text and rt.name in text:
                return T.STRING
            if lt == rt and (lt == T.POSITION or isinstance(lt, T.JointTuple)):
                return lt
            self.error(e.span, f"cannot {words[op]} {lt} and {rt}", self._geo_hint(op, lt, rt))
            return T.ERROR
        if op == "*":
            if num:
                return T.INTEGER if lt == rt == T.INTEGER else T.REAL
            for a, b in ((lt, rt), (rt, lt)):
                if a.is_numeric and (b == T.POSITION or isinstance(b, T.JointTuple)):
                    return b
            self.error(e.span, f"cannot multiply {lt} and {rt}", self._geo_hint(op, lt, rt))
            return T.ERROR
        if op == "/":
            if num:
                return T.REAL
            if lt == T.POSITION and rt.is_numeric:
                return T.POSITION
            self.error(e.span, f"cannot divide {lt} by {rt}")
            return T.ERROR
        if op in ("DIV", "MOD"):
            if lt == rt == T.INTEGER:
                return T.INTEGER
            self.error(
                e.span,
                f"{op} needs INTEGER operands, got {lt} and {rt}",
                "use '/' for REAL division" if op == "DIV" else None,
            )
            return T.ERROR
        if op in ("AND", "OR", "EXOR"):
            if lt == rt == T.BOOLEAN:
                return T.BOOLEAN
            self.error(e.span, f"{op} needs BOOLEAN operands, got {lt} and {rt}")
            return T.ERROR
        if op == ":":
            if lt == T.POSE and rt in (T.POSE, T.POSITION):
                return rt
            if lt == rt == T.ORIENTATION:
                return T.ORIENTATION
            self.error(
                e.span,
                f"cannot compose {lt} and {rt}",
                "':' composes POSE:POSE, POSE:POSITION or ORIENTATION:ORIENTATION",
            )
            return T.ERROR
        # comparisons
        if num or (lt.name in text and rt.name in text) or lt == rt == T.BOOLEAN:
            return T.BOOLEAN
        geometric = (T.POSITION, T.ORIENTATION, T.POSE)
        if op in ("=", "<>") and lt == rt and (lt in geometric or isinstance(lt, T.JointTuple)):
            return T.BOOLEAN
        self.error(
            e.span,
            f"cannot compare {lt} and {rt} with '{op}'",
            "order compares numbers, strings and BOOLEANs; = and <> also compare "
            "POSITION, ORIENTATION, POSE and joint tuples of the same type",
        )
        return T.ERROR

    def _geo_hint(self, op: str, lt: T.Type, rt: T.Type) -> str | None:
        if T.POSE in (lt, rt):
            return "compose poses with ':' (p1 : p2); move a pose's position with p.pos"
        return None

    def fold_binary(self, e: ast.Binary, op: str, ty: T.Type) -> None:
        a, b = _num(e.left.const), _num(e.right.const)
        lc, rc = e.left.const, e.right.const
        if lc is None or rc is None:
            return
        try:
            if ty.is_numeric and a is not None and b is not None:
                v = _arith(op, a, b)
                if v is None:
                    return
                if isinstance(v, float) and not math.isfinite(v):
                    self.error(e.span, "the constant expression overflows")
                    return
                if ty == T.INTEGER and (overflow := _integer_overflow(op, a, b, v)):
                    self.error(e.span, overflow)
                    return
                e.const = Value(ty.name, (int(v) if ty == T.INTEGER else float(v),))
            elif ty == T.BOOLEAN:
                x, y = lc.data[0], rc.data[0]
                v = _logic(op, x, y)
                if v is not None:
                    e.const = Value("BOOLEAN", (v,))
        except ZeroDivisionError:
            self.error(e.span, "division by zero in a constant expression")

    def e_field(self, e: ast.Field, want) -> T.Type:
        bt = self.expr(e.base, None)
        if bt == T.ERROR:
            return T.ERROR
        name = e.name.lower()
        if bt == T.POSITION or bt == T.POSE:
            fields = {"x": T.REAL, "y": T.REAL, "z": T.REAL}
            if bt == T.POSE:
                fields |= {"pos": T.POSITION, "ori": T.ORIENTATION}
            if name in fields:
                e.canonical = name
                return fields[name]
            self.error(e.span, f"{bt} has no field '{e.name}'", f"fields: {', '.join(fields)}")
            return T.ERROR
        if isinstance(bt, T.JointTuple):
            names = self.joint_field_names.get(bt.name, self.joint_names)
            low = [n.lower() for n in names]
            if name in low:
                k = low.index(name)
                e.canonical = self.joint_names[k] if k < len(self.joint_names) else names[k]
                return T.REAL
            self.error(
                e.span,
                f"{bt} has no joint '{e.name}'",
                f"joints: {', '.join(names)} (or index k[1..{len(names)}])",
            )
            return T.ERROR
        if isinstance(bt, T.Record):
            f = bt.field(e.name)
            if f is not None:
                e.canonical = f[0]
                return f[1]
            self.error(
                e.span,
                f"record {bt} has no field '{e.name}'",
                f"fields: {', '.join(n for n, _ in bt.fields)}",
            )
            return T.ERROR
        self.error(e.span, f"{bt} has no fields")
        return T.ERROR

    def e_index(self, e: ast.Index, want) -> T.Type:
        if self.is_output(e):
            return self.e_output(e)
        bt = self.expr(e.base, None)
        it = self.expr(e.index, T.INTEGER)
        if bt == T.ERROR or it == T.ERROR:
            return T.ERROR
        if it != T.INTEGER:
            self.error(e.index.span, f"an index must be INTEGER, got {it}")
            return T.ERROR
        k = _num(e.index.const)
        if isinstance(bt, T.Array):
            if k is not None and not bt.lo <= k <= bt.hi:
                self.error(
                    e.index.span, f"index {k} is outside the array bounds [{bt.lo}..{bt.hi}]"
                )
            return bt.elem
        if isinstance(bt, T.JointTuple):
            if k is not None and bt.n and not 1 <= k <= bt.n:
                self.error(e.index.span, f"joint index {k} is outside 1..{bt.n}")
            return T.REAL
        self.error(e.span, f"{bt} cannot be indexed")
        return T.ERROR

    # ------------------------------------------------------------------ digital outputs
    def is_output(self, e: ast.Expr) -> bool:
        """``OUT[n]`` of the output array (lang/digital_io.py), unless ``OUT`` is declared."""
        return is_output_syntax(e) and self.lookup("OUT") is None

    def e_output(self, e: ast.Index) -> T.Type:
        """``OUT[n]``: an INTEGER ``n`` (in range when constant); reads as BOOLEAN."""
        e.output = True
        t = self.expr(e.index, T.INTEGER)
        if t not in (T.INTEGER, T.ERROR):
            self.error(e.index.span, f"an output number must be INTEGER, got {t}")
        k = _num(e.index.const)
        if k is not None and output_error(k) is not None:
            self.error(e.index.span, str(output_error(k)))
        return T.BOOLEAN

    def s_output(self, s: ast.Assign) -> None:
        """``OUT[n] := b;``"""
        assert isinstance(s.target, ast.Index)
        self.e_output(s.target)
        got = self.expr(s.value, T.BOOLEAN)
        self.require(s.value, T.BOOLEAN, got, "cannot assign to 'OUT[…]'")

    def s_pulse(self, s: ast.CallStmt) -> None:
        """``PULSE(OUT[n], t);`` with ``t`` seconds (in range when constant)."""
        s.pulse = True
        if len(s.args) != 2 or not self.is_output(s.args[0]):
            self.error(s.span, "PULSE needs an output and a duration: PULSE(OUT[n], seconds)")
            for a in s.args:
                self.expr(a, None)
            return
        self.e_output(s.args[0])  # type: ignore[arg-type]
        got = self.expr(s.args[1], T.REAL)
        if got != T.ERROR and not got.is_numeric:
            self.error(
                s.args[1].span, f"PULSE: the duration must be a number of seconds, got {got}"
            )
            return
        k = _num(s.args[1].const)
        if k is not None and pulse_error(k) is not None:
            self.error(s.args[1].span, str(pulse_error(k)))

    def e_input(self, e: ast.Input, want) -> T.Type:
        t = self.expr(e.index, T.INTEGER)
        if t not in (T.INTEGER, T.ERROR):
            self.error(e.index.span, f"an input number must be INTEGER, got {t}")
        k = _num(e.index.const)
        if k is not None and k < 0:
            self.error(e.index.span, f"input numbers are >= 0, got {k}")
        return T.BOOLEAN

    def e_call(self, e: ast.Call, want) -> T.Type:
        up = e.name.upper()
        sym = self.lookup(e.name)
        if sym is not None and sym.kind == "routine":
            e.sym = sym
            info = sym.routine
            assert info is not None
            if not info.is_function:
                self.error(e.span, f"procedure '{sym.name}' has no value; call it as a statement")
                self.args(e, info)
                return T.ERROR
            self.args(e, info)
            return info.result or T.ERROR
        if sym is not None and up not in BUILTINS and up != "POSE":
            self.error(e.span, f"'{sym.name}' is not a function")
            return T.ERROR
        if up == "POSE":
            return self.pose_call(e)
        sig = BUILTINS.get(up)
        if sig is None:
            self.error(
                e.span,
                f"unknown function '{e.name}'",
                self.suggest(e.name, kinds=("routine",)) or _builtin_hint(e.name),
            )
            for a in e.args:
                self.expr(a, None)
            return T.ERROR
        arg_types = [self.expr(a, self._builtin_want(up, k, a)) for k, a in enumerate(e.args)]
        if T.ERROR in arg_types:
            return T.ERROR
        if up == "POSITION" and arg_types == [T.POSE]:
            return T.POSITION
        if (
            up == "DIST"
            and len(arg_types) == 2
            and all(t in (T.POSE, T.POSITION) for t in arg_types)
        ):
            return T.REAL
        res = sig(arg_types, self.n)
        if isinstance(res, str):
            self.error(_blamed_span(e, res), f"{up}: {res}")
            return T.ERROR
        return res

    def _builtin_want(self, name: str, k: int, arg: ast.Expr) -> T.Type | None:
        """The context type of argument ``k`` (it types a tuple literal there)."""
        if not isinstance(arg, ast.Tuple):
            return T.REAL
        if name == "FK":
            return T.JointTuple("MAIN_JOINT", self.n)
        if name == "INV":
            return T.POSE
        if name in ("DIST", "ORIVANG") and (name == "DIST" or k == 0):
            return T.POSITION
        return None

    def pose_call(self, e: ast.Call) -> T.Type:
        if len(e.args) == 6:
            arg_types = [self.expr(a, T.REAL) for a in e.args]
            res = POSE_FROM_NUMBERS(arg_types, self.n)
            e.const = _numbers_value("POSE", [a.const for a in e.args])
        else:
            arg_types = [self.expr(a, None) for a in e.args]
            res = POSE_FROM_PARTS(arg_types, self.n)
            if len(arg_types) == 1 and arg_types[0] == T.POSITION:
                res = T.POSE
        if T.ERROR in arg_types:
            return T.ERROR
        if isinstance(res, str):
            self.error(
                _blamed_span(e, res),
                f"POSE: {res}",
                "POSE(POSITION(x, y, z), ORIZYX(a, b, c)) or POSE(x, y, z, a, b, c)",
            )
            return T.ERROR
        return res

    def args(self, e: ast.Call | ast.CallStmt, info: RoutineInfo) -> None:
        if len(e.args) != len(info.params):
            self.error(
                e.span, f"'{info.name}' takes {len(info.params)} argument(s), got {len(e.args)}"
            )
            for a in e.args:
                self.expr(a, None)
            return
        for k, (a, slot, ty) in enumerate(
            zip(e.args, info.params, info.param_types, strict=True), 1
        ):
            got = self.expr(a, ty)
            if slot.by_ref:
                if not (
                    isinstance(a, ast.Name) and a.sym is not None and a.sym.kind in ("var", "param")
                ):
                    self.error(
                        a.span, f"argument {k} of '{info.name}' is a VAR parameter: pass a variable"
                    )
                elif (
                    got != ty
                    and T.ERROR not in (got, ty)
                    and not (ty == T.SIGNAL or a.sym.type == ty)
                ):
                    self.error(
                        a.span,
                        f"argument {k} of '{info.name}': VAR parameter needs {ty}, got {got}",
                    )
            else:
                self.require(a, ty, got, f"argument {k} of '{info.name}'")

    # ------------------------------------------------------------------ statements
    def collect_labels(self, body: list[ast.Stmt]) -> None:
        self.labels = {}
        for s in ast.statements_in_order(body):
            if isinstance(s, ast.Label):
                prev = self.labels.get(s.name.lower())
                if prev is not None:
                    self.error(
                        s.span, f"label '{s.name}' is already defined on line {prev.span.line}"
                    )
                else:
                    self.labels[s.name.lower()] = s

    def check_list(self, stmts: list[ast.Stmt], end_span: Span, end_word: str) -> None:
        saved = self.state
        self.state = _ListState(saved)
        for s in stmts:
            getattr(self, f"s_{type(s).__name__.lower()}")(s)
        if not self.repl:
            for key, (display, span) in self.state.open.items():
                opt = key.split(":")[0]
                closing = _END_WORD[opt] + (f" {display.split()[-1]}" if opt == "OBSTACLE" else "")
                self.error(
                    span,
                    f"{display} is not closed before {end_word} (line {end_span.line})",
                    f"add {closing}; in the same statement list",
                )
        self.state = saved

    def s_label(self, s: ast.Label) -> None:
        pass

    def s_assign(self, s: ast.Assign) -> None:
        if self.is_output(s.target):
            self.s_output(s)
            return
        root = s.target
        while isinstance(root, ast.Field | ast.Index):
            root = root.base
        assert isinstance(root, ast.Name)
        sym = self.lookup(root.name)
        if sym is None:
            hint = self.suggest(root.name)
            self.error(root.span, f"unknown name '{root.name}'", hint)
            self.expr(s.value, None)
            return
        if sym.kind not in ("var", "param", "sysvar"):
            what = {
                "const": "a constant",
                "routine": "a routine",
                "type": "a type",
                "robot": "the robot",
                "obstacle": "an obstacle",
            }.get(sym.kind, sym.kind)
            self.error(root.span, f"cannot assign to '{sym.name}': it is {what}")
            self.expr(s.value, None)
            return
        if not sym.writable:
            self.error(root.span, f"{sym.name} is read-only")
            return
        if sym.type == T.SIGNAL and s.target is not root:
            self.error(s.target.span, "a SIGNAL is assigned as a whole")
            return
        want = self.target_type(s.target, sym)
        if want is None:
            self.expr(s.value, None)
            return
        got = self.expr(s.value, want)
        ok = self.require(s.value, want, got, f"cannot assign to '{_describe(s.target, sym)}'")
        if ok and s.target is root and sym.name in BY_SYSTEM_VARIABLE and sym.kind == "sysvar":
            self.constant_setting(BY_SYSTEM_VARIABLE[sym.name].field, s.value, sym.name)

    def target_type(self, target: ast.Expr, sym: Symbol) -> T.Type | None:
        if isinstance(target, ast.Name):
            target.sym = sym
            target.ty = sym.type
            return sym.type
        t = self.expr(target, None)
        return None if t == T.ERROR else t

    def s_callstmt(self, s: ast.CallStmt) -> None:
        sym = self.lookup(s.name)
        if sym is None and s.name.upper() == "PULSE":
            self.s_pulse(s)
            return
        if sym is None or sym.kind != "routine":
            up = s.name.upper()
            if sym is None and (up in BUILTINS or up == "POSE"):
                self.error(
                    s.span, f"'{s.name}' is a built-in function: use its value in an expression"
                )
            elif sym is None:
                self.error(
                    s.span,
                    f"unknown procedure '{s.name}'",
                    self.suggest(s.name, kinds=("routine",)),
                )
            else:
                self.error(s.span, f"'{sym.name}' is not a procedure")
            for a in s.args:
                self.expr(a, None)
            return
        s.sym = sym
        assert sym.routine is not None
        self.args(s, sym.routine)

    def s_return(self, s: ast.Return) -> None:
        r = self.routine
        if r is None or r.index == 0:
            self.error(
                s.span,
                "RETURN outside a procedure or function",
                "use HALT to stop the main program",
            )
            return
        if r.is_function:
            if s.value is None:
                self.error(s.span, f"function '{r.name}' must return a value: RETURN expr")
                return
            got = self.expr(s.value, r.result)
            self.require(s.value, r.result or T.ERROR, got, f"RETURN of '{r.name}'")
        elif s.value is not None:
            self.error(
                s.value.span,
                f"procedure '{r.name}' cannot return a value",
                "declare it as FUNCTION name(...): TYPE",
            )

    def cond(self, e: ast.Expr, what: str) -> None:
        t = self.expr(e, T.BOOLEAN)
        if t not in (T.BOOLEAN, T.ERROR):
            self.error(e.span, f"the condition of {what} must be BOOLEAN, got {t}")

    def s_if(self, s: ast.If) -> None:
        for k, (c, body) in enumerate(s.arms):
            self.cond(c, "IF" if k == 0 else "ELSIF")
            last = k == len(s.arms) - 1 and s.else_body is None
            self.check_list(
                body, s.end_span, "ENDIF" if last else "the next ELSIF/ELSE of the IF ending"
            )
        if s.else_body is not None:
            self.check_list(s.else_body, s.end_span, "ENDIF")

    def s_while(self, s: ast.While) -> None:
        self.cond(s.cond, "WHILE")
        self.check_list(s.body, s.end_span, "ENDWHILE")

    def s_repeat(self, s: ast.Repeat) -> None:
        self.check_list(s.body, s.end_span, "UNTIL")
        self.cond(s.cond, "UNTIL")

    def s_for(self, s: ast.For) -> None:
        sym = self.lookup(s.var.name)
        if sym is None:
            self.error(s.var.span, f"unknown name '{s.var.name}'", "declare it: VAR INTEGER: i;")
        elif sym.kind not in ("var", "param") or sym.type != T.INTEGER:
            self.error(s.var.span, f"the FOR variable '{sym.name}' must be an INTEGER variable")
        else:
            s.var.sym, s.var.ty = sym, T.INTEGER
        for e, what in ((s.start, "start"), (s.stop, "end")):
            t = self.expr(e, T.INTEGER)
            self.require(e, T.INTEGER, t, f"FOR {what} value")
        if s.step is not None:
            t = self.expr(s.step, T.INTEGER)
            k = _num(s.step.const)
            if t != T.ERROR and (t != T.INTEGER or k is None):
                self.error(s.step.span, "the BY step must be an INTEGER constant")
            elif k == 0:
                self.error(s.step.span, "the BY step must not be 0")
        self.check_list(s.body, s.end_span, "ENDFOR")

    def s_case(self, s: ast.Case) -> None:
        t = self.expr(s.selector, None)
        if t not in (T.INTEGER, T.CHAR, T.BOOLEAN, T.STRING, T.ERROR):
            self.error(s.selector.span, f"CASE needs an INTEGER, CHAR, STRING or BOOLEAN, got {t}")
            t = T.ERROR
        seen: dict[object, int] = {}
        for arm in s.arms:
            for lo, hi in arm.labels:
                self.case_label(t, lo, hi, seen)
            self.check_list(arm.body, s.end_span, "the next CASE label")
        if s.else_body is not None:
            self.check_list(s.else_body, s.end_span, "ENDCASE")

    def case_label(self, sel: T.Type, lo: ast.Expr, hi: ast.Expr | None, seen: dict) -> None:
        for e in (lo, hi):
            if e is None:
                continue
            lt = self.expr(e, T.CHAR if sel == T.CHAR else None)
            ok = (
                sel == T.ERROR
                or lt == sel
                or (sel == T.STRING and lt == T.CHAR)
                or (
                    sel == T.CHAR
                    and lt == T.STRING
                    and isinstance(e, ast.Str)
                    and len(e.value) == 1
                )
            )
            if not ok:
                self.error(e.span, f"CASE label of type {lt} for a {sel} selector")
                return
            if sel == T.CHAR and isinstance(e, ast.Str):
                e.const = Value("CHAR", (e.value,))
        if hi is not None and sel not in (T.INTEGER, T.CHAR, T.ERROR):
            self.error(hi.span, "ranges lo..hi are for INTEGER and CHAR labels")
            return
        lo_v = lo.const.data[0] if lo.const else None
        hi_v = hi.const.data[0] if hi is not None and hi.const else lo_v
        if hi is not None and lo_v is not None and hi_v is not None and hi_v < lo_v:
            self.error(lo.span, f"empty CASE range {lo_v}..{hi_v}")
            return
        if isinstance(lo_v, int) and isinstance(hi_v, int) and hi_v - lo_v < 10_000:
            values = range(lo_v, hi_v + 1)
        else:
            values = [lo_v] if hi is None else []
        for v in values:
            if v in seen:
                self.error(lo.span, f"CASE label {v!r} is repeated (first on line {seen[v]})")
                return
            seen[v] = lo.span.line

    def s_goto(self, s: ast.Goto) -> None:
        if s.label.lower() not in self.labels:
            known = ", ".join(lb.name for lb in self.labels.values())
            self.error(
                s.span,
                f"unknown label '{s.label}'",
                f"labels of this routine: {known}"
                if known
                else "declare a label with 'name:' before a statement in the same routine",
            )

    def s_wait(self, s: ast.Wait) -> None:
        t = self.expr(s.seconds, T.REAL)
        if self.require(s.seconds, T.REAL, t, "WAIT time"):
            k = _num(s.seconds.const)
            if k is not None and k < 0:
                self.error(s.seconds.span, f"WAIT time must not be negative, got {k}")

    def s_waitfor(self, s: ast.WaitFor) -> None:
        self.cond(s.cond, "WAIT FOR")

    def s_pause(self, s: ast.Pause) -> None:
        pass

    def s_halt(self, s: ast.Halt) -> None:
        pass

    def s_write(self, s: ast.Write) -> None:
        for a in s.args:
            self.expr(a, None)

    # ------------------------------------------------------------------ motion
    def s_move(self, s: ast.Move) -> None:
        for t in s.targets:
            self.move_target(s, t)
        seen: dict[str, Span] = {}
        for c in s.clauses:
            if c.kind in seen:
                self.error(
                    c.span,
                    f"WITH {c.word.upper()} is given twice",
                    f"first on line {seen[c.kind].line}",
                )
                continue
            seen[c.kind] = c.span
            self.with_clause(s, c)

    def move_target(self, s: ast.Move, t: ast.Expr) -> None:
        joint = T.JointTuple("MAIN_JOINT", self.n)
        if s.kind == "PTP":
            if isinstance(t, ast.Tuple):
                n = len(t.items)
                want = joint if n == self.n or n != 6 else T.POSE
                got = self.expr(t, want)
                return
            got = self.expr(t, None)
            if got not in (T.POSE, T.ERROR) and got != joint:
                self.error(t.span, f"MOVE PTP needs a POSE or a MAIN_JOINT target, got {got}")
            return
        want = joint if s.kind == "PTPINC" else T.POSE
        got = self.expr(t, want)
        word = {"PTPINC": "MOVE_INC PTP", "LININC": "MOVE_INC LIN", "LINPATH": "MOVE LIN PATH"}
        self.require(t, want, got, f"{word.get(s.kind, 'MOVE ' + s.kind)} target")

    def with_clause(self, s: ast.Move, c: ast.WithClause) -> None:
        ptp = s.kind in ("PTP", "PTPINC")
        if c.kind in _LIMIT_TYPES:
            self.limit_pair(c.kind, c.args[0], c.args[1], f"WITH {c.kind}")
            return
        if c.kind == "RECONF":
            self.reconf_clause(s, c)
            return
        if c.kind not in _WITH_PARAMS:
            self.error(
                c.span,
                f"unknown WITH option '{c.word}'",
                approximation_hint(c.word)
                or f"WITH options: {', '.join(_WITH_PARAMS)}, JOINTLIMIT, JOINTSPEEDLIMIT, "
                "JOINTACCELLIMIT, RECONFIGURATION",
            )
            self.expr(c.args[0], None)
            return
        row = BY_WITH_WORD[c.kind]
        if s.kind not in row.kinds:
            self.error(
                c.span,
                f"WITH {c.kind} sets a path speed; PTP motion uses SPEED_PTP / ACC_PTP (%)"
                if ptp
                else f"WITH {c.kind} is for PTP motion; path motion uses SPEED / ACC",
            )
        t = self.expr(c.args[0], T.REAL)
        if self.require(c.args[0], T.REAL, t, f"WITH {c.kind}"):
            self.constant_setting(row.field, c.args[0], f"WITH {c.kind}")

    def constant_setting(self, field_name: str, value: ast.Expr, what: str) -> None:
        """A constant setting outside its range (lang/settings.py) is an error at the value,
        in the run-time words; a non-constant one is checked when it runs."""
        k: float | int | str | None = _num(value.const)
        if value.const is not None and value.const.type in ("STRING", "CHAR"):
            k = value.const.data[0]  # a string setting (R_PROFILE)
        written = ast.literal_text(value)  # the value as written: -5, not -5.0
        message = setting_message(field_name, k, what, written) if k is not None else None
        if message is not None:
            self.error(value.span, message)

    def reconf_clause(self, s: ast.Move, c: ast.WithClause) -> None:
        joint = T.JointTuple("MAIN_JOINT", self.n)
        npts = len(s.targets)
        configs = c.args
        if (
            len(configs) == 1
            and isinstance(configs[0], ast.Tuple)
            and npts > 1
            and not self._numbers_only(configs[0])
        ):
            configs = configs[0].items  # (k1, k2, k3): one configuration per point
        c.args = list(configs)
        for k in configs:
            got = self.expr(k, joint)
            self.require(k, joint, got, "WITH RECONFIGURATION")
        allowed = reconfiguration_counts(s.kind, npts)
        if len(configs) not in allowed:
            plural = "s" if len(configs) != 1 else ""
            self.error(
                c.span,
                f"WITH RECONFIGURATION gives {len(configs)} configuration{plural}"
                f" for {npts} point{'s' if npts != 1 else ''}",
                "give one MAIN_JOINT configuration for the whole move, or one per point, in order"
                if len(allowed) > 1
                else "give one MAIN_JOINT configuration per point, in order",
            )
        if s.kind in ("PTP", "PTPINC") and s.targets and s.targets[0].ty == joint:
            self.error(
                c.span,
                "WITH RECONFIGURATION needs a POSE target",
                "a MAIN_JOINT target already fixes the configuration",
            )

    def _numbers_only(self, t: ast.Tuple) -> bool:
        """Whether every item of ``t`` is a number (then ``t`` is one configuration, not a
        list of them). Typed quietly: the items are typed again, with diagnostics, after."""
        mark = len(self.diags)
        numeric = all(
            not isinstance(item, ast.Tuple) and self.expr(item, None).is_numeric for item in t.items
        )
        del self.diags[mark:]
        return numeric

    def limit_pair(self, option: str, lo: ast.Expr, hi: ast.Expr, what: str) -> None:
        lo_name, hi_name = _LIMIT_TYPES[option]
        lo_t, hi_t = T.JointTuple(lo_name, self.n), T.JointTuple(hi_name, self.n)
        got_lo, got_hi = self.expr(lo, lo_t), self.expr(hi, hi_t)
        if got_lo == hi_t and got_hi == lo_t:
            self.error(
                lo.span,
                f"{what} takes {lo_name} then {hi_name}: the arguments are swapped",
                f"write {what.split()[-1]} {_text(hi)}, {_text(lo)}",
            )
            return
        ok = self.require(lo, lo_t, got_lo, f"{what}, first argument")
        ok = self.require(hi, hi_t, got_hi, f"{what}, second argument") and ok
        if not ok or lo.const is None or hi.const is None:
            return
        for k, (a, b) in enumerate(zip(lo.const.data, hi.const.data, strict=False)):
            if a > b:
                name = self.joint_names[k] if k < len(self.joint_names) else str(k + 1)
                self.error(
                    lo.span,
                    f"{what}: minimum {_fmt(a)} of joint {k + 1} ({name}) is "
                    f"above the maximum {_fmt(b)}",
                )
                return

    # ------------------------------------------------------------------ redundancy
    def s_modalon(self, s: ast.ModalOn) -> None:
        assert self.state is not None
        if s.option in _LIMIT_TYPES:
            self.limit_pair(s.option, s.args[0], s.args[1], s.option)
        elif s.option == "FREEZE":
            self.freeze_joints(s)
        opened = self.modal_key(s)
        if opened is None:
            return
        key, display = opened
        prev = self.state.find_open(key)
        if prev is not None:
            self.error(
                s.span,
                f"{display} is already on (since line {prev.line})",
                f"close it with {_END_WORD[s.option]} first",
            )
        self.state.open[key] = (display, s.span)

    def s_modaloff(self, s: ast.ModalOff) -> None:
        assert self.state is not None
        closed = self.modal_key(s)
        if closed is None:
            return
        key, display = closed
        if key in self.state.open:
            del self.state.open[key]
            return
        if self.repl:
            return
        outer = self.state.outer.find_open(key) if self.state.outer else None
        end = _END_WORD[s.option] + (f" {s.name}" if s.name else "")
        if outer is not None:
            self.error(
                s.span,
                f"{end} closes {display} of line {outer.line} from another statement list",
                "START and END must be in the same statement list (same block)",
            )
        elif s.option == "OBSTACLE":
            active = [d for d, _ in self.state.open.values() if d.startswith("OBSTACLE ")]
            self.error(
                s.name_span or s.span,
                f"OBSTACLEEND {s.name}: obstacle '{s.name}' is not active here",
                f"active obstacles: {', '.join(a.split()[1] for a in active)}"
                if active
                else f"switch it on first with OBSTACLE {s.name};",
            )
        else:
            self.error(s.span, f"{end} without an earlier {display} in the same statement list")

    def modal_key(self, s: ast.ModalOn | ast.ModalOff) -> tuple[str, str] | None:
        """``(key, display)`` of the option a START/END names; None: unknown obstacle."""
        if s.option != "OBSTACLE":
            return s.option, _START_WORD[s.option]
        assert s.name is not None
        o = self.obstacles.get(s.name.lower())
        if o is None:
            self.unknown_obstacle(s.name, s.name_span or s.span)
            return None
        return f"OBSTACLE:{o.name.lower()}", f"OBSTACLE {o.name}"

    def unknown_obstacle(self, name: str, span: Span) -> None:
        known = sorted(o.name for o in self.obstacles.values())
        hint = (
            f"known obstacles: {', '.join(known)}"
            if known
            else "define obstacles in an imported data list: [obstacles.NAME]"
        )
        self.error(span, f"unknown obstacle '{name}'", hint)

    def freeze_joints(self, s: ast.ModalOn) -> None:
        seen: set[int] = set()
        for e in s.args:
            t = self.expr(e, T.INTEGER)
            k = _num(e.const)
            if t == T.ERROR:
                continue
            if t != T.INTEGER or k is None:
                self.error(e.span, "FREEZESTART takes joint numbers (INTEGER constants)")
            elif self.n and not 1 <= k <= self.n:
                name = self.robot.name if self.robot else "the robot"
                self.error(e.span, f"joint {k} does not exist: {name} has joints 1..{self.n}")
            elif k in seen:
                self.error(e.span, f"joint {k} is listed twice")
            else:
                seen.add(int(k))

    def s_reconfigure(self, s: ast.Reconfigure) -> None:
        joint = T.JointTuple("MAIN_JOINT", self.n)
        got = self.expr(s.target, joint)
        self.require(s.target, joint, got, "RECONFIGURATION")

    # ------------------------------------------------------------------ flow
    def returns(self, body: list[ast.Stmt]) -> bool:
        for s in body:
            if isinstance(s, ast.Return | ast.Halt):
                return True
            if isinstance(s, ast.If) and s.else_body is not None:
                branches = [b for _, b in s.arms] + [s.else_body]
                if all(self.returns(b) for b in branches):
                    return True
            if isinstance(s, ast.Case) and s.else_body is not None:
                branches = [a.body for a in s.arms] + [s.else_body]
                if all(self.returns(b) for b in branches):
                    return True
            if isinstance(s, ast.Repeat) and self.returns(s.body):
                return True
        return False


# ---------------------------------------------------------------------- helpers


def _arith(op: str, a, b):
    if op == "+":
        return a + b
    if op == "-":
        return a - b
    if op == "*":
        return a * b
    if op == "/":
        return a / b
    if op == "DIV":
        q = abs(a) // abs(b)
        return q if (a >= 0) == (b > 0) else -q
    if op == "MOD":
        if b == 0:
            raise ZeroDivisionError
        q = abs(a) // abs(b)
        q = q if (a >= 0) == (b > 0) else -q
        return a - q * b
    return None


_RUNTIME_OP_NAMES = {"+": "addition", "-": "subtraction", "*": "multiplication", "DIV": "DIV"}


def _integer_overflow(op: str, a: int, b: int, v: int) -> str | None:
    """The runtime's message if folding ``a op b = v`` overflows (MOD overflows in its DIV)."""
    if op == "MOD":
        op, v = "DIV", _arith("DIV", a, b)
    overflow = T.integer_overflow(v)
    return f"{_RUNTIME_OP_NAMES.get(op, op)}: {overflow}" if overflow else None


def _logic(op: str, x, y):
    if op == "AND":
        return x and y
    if op == "OR":
        return x or y
    if op == "EXOR":
        return x != y
    if op in ("=", "<>", "<", ">", "<=", ">="):
        return {"=": x == y, "<>": x != y, "<": x < y, ">": x > y, "<=": x <= y, ">=": x >= y}[op]
    return None


def _numbers_value(ty: str, consts: list[Value | None]) -> Value | None:
    if all(c is not None and c.type in ("INTEGER", "REAL") for c in consts):
        return Value(ty, tuple(float(c.data[0]) for c in consts))  # type: ignore[union-attr]
    return None


def _pose_context(other: T.Type, fits: tuple[T.Type, ...]) -> T.Type | None:
    """The type of a tuple operand of ':' whose other operand has type ``other``."""
    if other == T.ERROR:
        return T.ERROR  # already reported: check the items quietly
    return T.POSE if other in fits else None


def _fmt(x: float) -> str:
    return f"{x:g}"


def _text(e: ast.Expr) -> str:
    if isinstance(e, ast.Name):
        return e.name
    return "..."


def _describe(target: ast.Expr, sym: Symbol) -> str:
    if isinstance(target, ast.Name):
        return sym.name
    if isinstance(target, ast.Field):
        return f"{_describe(target.base, sym)}.{target.name}"
    if isinstance(target, ast.Index):
        return f"{_describe(target.base, sym)}[...]"
    return sym.name


_ARGUMENT_N = re.compile(r"argument (\d+):")


def _blamed_span(call: ast.Call, message: str) -> Span:
    """Where a built-in's type error points: the argument it names, else the call."""
    m = _ARGUMENT_N.match(message)
    if m and 1 <= int(m.group(1)) <= len(call.args):
        return call.args[int(m.group(1)) - 1].span
    if message.startswith("expected") and len(call.args) == 1:
        return call.args[0].span
    return call.span


def _builtin_hint(name: str) -> str | None:
    names = [*BUILTINS, "POSE"]
    close = difflib.get_close_matches(name.upper(), names, n=1, cutoff=0.7)
    return f"did you mean {close[0]}?" if close else None
