"""Declarations: constants, types, variables, routines and the data lists' entries.

:class:`Declarations` enters every declaration into the scope and builds the tables the
code generator needs: the record types, the global slots and their types, the routines
(their parameter and local slots) and the input timelines of the data lists. A joint-tuple
type declared as a RECORD of REAL fields names the robot's joints (``MAIN_JOINT``) or the
fields of that tuple type; a data-list entry is a constant and may not clash with a
declaration of the program.
"""

from __future__ import annotations

from irlc.lang import ast, platform, trace_columns
from irlc.lang import types as T
from irlc.lang.builtins import BUILTINS
from irlc.lang.checker import constants
from irlc.lang.checker.expressions import ExpressionTyper
from irlc.lang.checker.scope import Reporter, RoutineInfo, Scope, Symbol
from irlc.lang.datalist import Datalist
from irlc.lang.diagnostics import Diagnostic, Span
from irlc.lang.irdata import Slot, Value
from irlc.lang.value_ranges import MAX_SCOPE_ELEMENTS, elements_too_many


class Declarations:
    """Declares into ``scope``; owns the program's records, global slots, routines, inputs."""

    def __init__(self, scope: Scope, typer: ExpressionTyper, report: Reporter):
        self.scope = scope
        self.typer = typer
        self.report = report
        self.records: list[T.Record] = []
        self.global_slots: list[Slot] = []
        self.global_types: list[T.Type] = []
        self.global_elements = 0  # of the global variables (T.elements)
        self.routines: list[RoutineInfo] = []
        self.inputs: dict[int, list[tuple[float, bool]]] = {}
        self.joint_spans: list[Span] = []  # of the MAIN_JOINT record's field names

    def find_joint_record(self, decls: ast.Decls) -> None:
        for td in decls.types:
            is_record = isinstance(td.type, ast.RecordTypeRef)
            if td.name.upper() not in T.JOINT_TUPLE_TYPES or not is_record:
                continue
            names: list[str] = []
            for ftype, fnames in td.type.fields:
                if not (isinstance(ftype, ast.SimpleTypeRef) and ftype.name == "REAL"):
                    self.report.error(ftype.span, f"the fields of {td.name.upper()} must be REAL")
                names += [n for n, _ in fnames]
            seen: set[str] = set()
            for n, s in (x for _, fl in td.type.fields for x in fl):
                if n.lower() in seen:
                    self.report.error(s, f"joint name '{n}' is repeated")
                seen.add(n.lower())
            other = next((r for r in self.scope.robots if r.n != len(names)), None)
            if other is not None:
                robot = other.signature.name + (f" ({other.var})" if self.scope.cell else "")
                self.report.error(
                    td.span,
                    f"{td.name.upper()} declares {len(names)} joints, but robot "
                    f"{robot} has {other.n}",
                    f"declare one REAL field per joint ({other.n})"
                    if not self.scope.cell
                    else "the joint names of a cell name every robot's joints: declare them "
                    "only when the robots have the same number of joints",
                )
                continue
            self.scope.joint_field_names[td.name.upper()] = tuple(names)
            if td.name.upper() == "MAIN_JOINT":
                self.scope.joint_names = tuple(names)
                self.joint_spans = [s for _, fl in td.type.fields for _, s in fl]

    def check_trace_columns(self) -> None:
        """MAIN_JOINT names whose trace columns would coincide with another column (a joint
        ``a``: ``a_deg`` is also the TCP's angle a), and a cell's robots whose prefixed
        columns coincide (``h`` with a joint ``x_a1`` and ``h_x`` with ``a1``):
        :mod:`irlc.lang.trace_columns`."""
        names = self.scope.joint_names
        obstacles = [o.name for o in self.scope.obstacles.values()]
        robots = self.scope.robots
        if self.joint_spans and all(r.n == len(names) for r in robots):
            for robot in robots:
                clash = trace_columns.first_clash(names, robot.signature.joint_kinds, obstacles)
                if clash is not None:
                    j, column, other = clash
                    self.report.error(
                        self.joint_spans[j],
                        f"joint name '{names[j]}' gives the trace column {column}, which is "
                        f"also {other}",
                        "choose another name for this joint",
                    )
                    return
        if len(robots) < 2 or len({r.var.lower() for r in robots}) < len(robots):
            return  # a duplicate robot name is reported where it is declared
        cell = [(r.var, _robot_joint_names(names, r.n), r.signature.joint_kinds) for r in robots]
        clash = trace_columns.first_cell_clash(cell, obstacles)
        if clash is not None:
            r, column, other = clash
            robot = robots[r]
            clause = robot.clause
            span = (clause.var_span or clause.span) if clause is not None else None
            self.report.error(
                span,
                f"robot {robot.var} gives the trace column {column}, which is also {other}",
                "choose another name for the robot",
            )

    def add_datalists(self, datalists: list[Datalist]) -> None:
        for dl in datalists:
            for name in dl.rejected:  # reported by the data list: its uses say nothing more
                if name.lower() not in self.scope.globals:
                    where = f"data list {dl.path} (an entry that failed its check)"
                    self.scope.globals[name.lower()] = Symbol("const", name, T.ERROR, where)
            for item in dl.items:
                sym = Symbol(
                    "const",
                    item.name,
                    self.value_type(item.value),
                    f"data list {item.file}, key {item.key}",
                    value=item.value,
                    span=item.span,
                    file=item.file,
                )
                self._declare_item(item.name, sym, item)
            for o, item in dl.obstacles:
                where = f"data list {item.file}, key {item.key}"
                sym = Symbol("obstacle", o.name, None, where, span=item.span, file=item.file)
                if self._declare_item(o.name, sym, item):
                    self.scope.obstacles[o.name.lower()] = o
            for n, timeline in dl.inputs.items():
                if n in self.inputs:
                    self.report.diags.append(
                        Diagnostic(
                            "error", f"input {n} is defined in two data lists", dl.path, None
                        )
                    )
                self.inputs[n] = timeline

    def _declare_item(self, name: str, sym: Symbol, item) -> bool:
        prev = self.scope.globals.get(name.lower())
        if prev is not None:
            self.report.diags.append(
                Diagnostic(
                    "error",
                    f"'{name}' is defined twice: {sym.where} and {prev.where}",
                    item.file,
                    item.span,
                )
            )
            return False
        self.scope.globals[name.lower()] = sym
        return True

    def value_type(self, v: Value) -> T.Type:
        if v.type in T.JOINT_TUPLE_TYPES:
            return T.JointTuple(v.type, self.scope.n)
        k = platform.constant_count(v.type)  # a data list's [platform] entry
        if k is not None:
            return platform.target_type(k)
        return T.SIMPLE.get(v.type, T.ERROR)

    def declare_all(self, decls: ast.Decls, is_global: bool) -> None:
        scope = self.scope.globals if is_global else self.scope.locals
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
            self.report.error(
                span,
                f"'{name}' is already defined in {prev.where}",
                "rename the program's declaration or the data-list entry",
            )
            return True
        return False

    def declare_const(self, d: ast.ConstDecl, scope) -> None:
        want = self.resolve_type(d.type) if d.type is not None else None
        ty = self.typer.expr(d.value, want)
        if want is not None:
            self.typer.require(d.value, want, ty, f"constant '{d.name}'")
            ty = want
        v = constants.coerce(d.value.const, ty)
        if v is None and ty != T.ERROR:
            self.report.error(
                d.value.span,
                f"the value of constant '{d.name}' is not a constant expression",
                "constants take numbers, strings, booleans, other constants and tuples of them",
            )
        if self._collides_with_datalist(scope, d.name, d.span):
            return
        self.scope.declare(
            scope, d.name, Symbol("const", d.name, ty, f"line {d.span.line}", value=v), d.span
        )

    def declare_type(self, d: ast.TypeDecl, scope) -> None:
        upper = d.name.upper()
        if upper in T.JOINT_TUPLE_TYPES:
            if scope is not self.scope.globals:
                self.report.error(d.span, f"{upper} can only be declared at program level")
            return  # handled by find_joint_record
        ty = self.resolve_type(d.type, name=d.name)
        if self._collides_with_datalist(scope, d.name, d.name_span):
            return
        self.scope.declare(
            scope, d.name, Symbol("type", d.name, ty, f"line {d.name_span.line}"), d.name_span
        )

    def declare_vars(self, d: ast.VarDecl, scope, is_global: bool) -> None:
        ty = self.resolve_type(d.type)
        if ty == T.SIGNAL and not is_global:
            self.report.error(d.type.span, "SIGNAL variables must be declared at program level")
        for name, span in d.names:
            if self._collides_with_datalist(scope, name, span):
                continue
            self._room_for(ty, is_global, span)
            sym = Symbol("var", name, ty, f"line {span.line}")
            if is_global:
                sym.storage, sym.index = "G", len(self.global_slots)
            else:
                assert self.scope.routine is not None
                r = self.scope.routine
                sym.storage, sym.index = "L", len(r.params) + len(r.locals)
            if not self.scope.declare(scope, name, sym, span):
                continue
            if is_global:
                self.global_slots.append(Slot(sym.index, ty.ird(), name))
                self.global_types.append(ty)
            else:
                assert self.scope.routine is not None
                self.scope.routine.locals.append(Slot(sym.index, ty.ird(), name))
                self.scope.routine.local_types.append(ty)

    def _room_for(self, ty: T.Type, is_global: bool, span: Span) -> None:
        """Report a variable of ``ty`` that does not fit into its scope's
        :data:`MAX_SCOPE_ELEMENTS` (the program's globals; a routine's parameters passed by
        value and its locals), the first one only."""
        if ty == T.ERROR:
            return
        n = T.elements(ty)
        if is_global:
            held, self.global_elements = self.global_elements, self.global_elements + n
            what = "the program's variables"
        else:
            r = self.scope.routine
            assert r is not None
            held, r.elements = r.elements, r.elements + n
            what = f"the variables of '{r.name}'"
        if held > MAX_SCOPE_ELEMENTS:  # reported at an earlier variable
            return
        problem = elements_too_many(held + n, what, MAX_SCOPE_ELEMENTS)
        if problem is not None:
            self.report.error(span, problem, "nested arrays multiply, records add their fields")

    def resolve_type(self, ref: ast.TypeRef, name: str | None = None) -> T.Type:
        if isinstance(ref, ast.SimpleTypeRef):
            if ref.name in T.JOINT_TUPLE_TYPES:
                return T.JointTuple(ref.name, self.scope.n)
            return T.SIMPLE[ref.name]
        if isinstance(ref, ast.NamedTypeRef):
            sym = self.scope.lookup(ref.name)
            if sym is None or sym.kind != "type":
                what = "not a type" if sym is not None else "unknown type"
                self.report.error(
                    ref.span, f"{what} '{ref.name}'", self.scope.suggest(ref.name, kinds=("type",))
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
            self.typer.expr(e, T.INTEGER)
            v = e.const
            if v is None or v.type != "INTEGER":
                self.report.error(e.span, "array bounds must be INTEGER constants")
                return T.ERROR
            bounds.append(v.data[0])
        lo, hi = bounds
        if hi < lo:
            self.report.error(
                ref.span, f"array bounds [{lo}..{hi}]: the upper bound is below the lower"
            )
            return T.ERROR
        elem = self.resolve_type(ref.elem)
        if elem == T.SIGNAL:
            self.report.error(ref.elem.span, "SIGNAL can only be the type of a plain variable")
        problem = elements_too_many((hi - lo + 1) * T.elements(elem), "this array")
        if problem is not None:
            self.report.error(ref.span, problem, "nested arrays multiply, records add their fields")
            return T.ERROR
        return T.Array("ARRAY", lo, hi, elem)

    def record_type(self, ref: ast.RecordTypeRef, name: str | None) -> T.Type:
        fields: list[tuple[str, T.Type]] = []
        seen: set[str] = set()
        for ftype, names in ref.fields:
            ty = self.resolve_type(ftype)
            if ty == T.SIGNAL:
                self.report.error(ftype.span, "SIGNAL can only be the type of a plain variable")
            for n, s in names:
                if n.lower() in seen:
                    self.report.error(s, f"field '{n}' is repeated")
                    continue
                seen.add(n.lower())
                fields.append((n, ty))
        problem = elements_too_many(sum(T.elements(t) for _, t in fields), "this RECORD")
        if problem is not None:
            self.report.error(ref.span, problem, "nested arrays multiply, records add their fields")
            return T.ERROR
        rec = T.Record(name or f"RECORD#{len(self.records)}", len(self.records), tuple(fields))
        self.records.append(rec)
        return rec

    def declare_routine(self, r: ast.Routine) -> None:
        info = RoutineInfo(len(self.routines) + 1, r.name, r.is_function, [], [], None, node=r)
        saved = self.scope.locals
        self.scope.locals = {}
        for i, prm in enumerate(r.params):
            ty = self.resolve_type(prm.type)
            if ty == T.SIGNAL:
                self.report.error(prm.type.span, "a parameter cannot be a SIGNAL")
            if not prm.by_ref:  # a VAR parameter holds no elements of its own
                info.elements += T.elements(ty)
                what = f"the parameters of '{r.name}'"
                problem = elements_too_many(info.elements, what, MAX_SCOPE_ELEMENTS)
                if problem is not None:
                    self.report.error(prm.span, problem, "pass large arrays as VAR parameters")
                    ty, info.elements = T.ERROR, info.elements - T.elements(ty)
            info.params.append(Slot(i, ty.ird(), prm.name, prm.by_ref))
            info.param_types.append(ty)
        if r.result is not None:
            info.result = self.resolve_type(r.result)
        self.scope.locals = saved
        sym = Symbol("routine", r.name, None, f"line {r.span.line}", routine=info)
        if self._collides_with_datalist(self.scope.globals, r.name, r.span):
            return
        if r.name.upper() in BUILTINS or r.name.upper() == "POSE":
            self.report.error(r.span, f"'{r.name}' is a built-in function and cannot be redefined")
            return
        if self.scope.declare_global(r.name, sym, r.span):
            self.routines.append(info)


def _robot_joint_names(names: tuple[str, ...], n: int) -> tuple[str, ...]:
    """A cell's robot's joint names: the program's (MAIN_JOINT record), else ``a1 … aN``."""
    return tuple(names) if len(names) == n else tuple(f"a{i + 1}" for i in range(n))
