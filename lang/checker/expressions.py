"""Expression typing: the type of every expression (``Expr.ty``) and its constant value.

:class:`ExpressionTyper` gives each expression its type from its operands and, for tuple
literals, from the context type ``want`` (a tuple has no type of its own: ``(1, 2, 3)`` is a
POSITION where one is expected, a MAIN_JOINT where a joint tuple is). Constant operands are
folded (:mod:`.constants`), so ``Expr.const`` holds the compile-time value where there is
one. Calls of routines and built-ins are checked against their signatures; ``OUT[n]`` is the
digital output array unless the program declares ``OUT``.
"""

from __future__ import annotations

import difflib
import re

from irlc.lang import ast
from irlc.lang import types as T
from irlc.lang.builtins import BUILTINS, POSE_FROM_NUMBERS, POSE_FROM_PARTS
from irlc.lang.cell import ROBOT_VARIABLES, ProgramRobot, robot_list
from irlc.lang.checker import constants
from irlc.lang.checker.constants import number, numbers_value
from irlc.lang.checker.scope import Reporter, RoutineInfo, Scope, Symbol
from irlc.lang.diagnostics import Span
from irlc.lang.digital_io import is_output_syntax, output_error
from irlc.lang.irdata import Value, string_too_long


class ExpressionTyper:
    """Types expressions in the current scope; reports through ``report``."""

    def __init__(self, scope: Scope, report: Reporter):
        self.scope = scope
        self.report = report

    def require(self, e: ast.Expr, want: T.Type, got: T.Type, what: str) -> bool:
        if T.assignable(want, got):
            return True
        self.report.error(e.span, f"{what}: expected {want}, got {got}", self._type_hint(want, got))
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

    def after_error(self, e: ast.Expr) -> None:
        """Check ``e`` whose context is in error (an unknown robot or target): a tuple there
        gets no second error for having no type."""
        self.expr(e, T.ERROR if isinstance(e, ast.Tuple) else None)

    def e_num(self, e: ast.Num, want) -> T.Type:
        if isinstance(e.value, int):
            e.const = Value("INTEGER", (e.value,))
            return T.INTEGER
        e.const = Value("REAL", (e.value,))
        return T.REAL

    def e_str(self, e: ast.Str, want) -> T.Type:
        if too_long := string_too_long(len(e.value)):
            self.report.error(e.span, too_long)
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
        sym = self.scope.lookup(e.name)
        if sym is None:
            self.report.error(
                e.span,
                f"unknown name '{e.name}'",
                self.scope.suggest(e.name),
            )
            return T.ERROR
        e.sym = sym
        if self.scope.robot_variable_problem(sym, e.span):
            return T.ERROR
        if sym.kind == "routine":
            info = sym.routine
            assert info is not None
            if info.is_function and not info.params:
                return info.result or T.ERROR
            what = "procedure" if not info.is_function else "function with parameters"
            self.report.error(e.span, f"'{sym.name}' is a {what}, not a value")
            return T.ERROR
        if sym.kind in ("type", "robot", "obstacle"):
            robot = "a robot" if self.scope.cell else "the robot"
            what = {"type": "a type", "robot": robot, "obstacle": "an obstacle"}[sym.kind]
            hint = "use it in OBSTACLE / OBSTACLEEND" if sym.kind == "obstacle" else None
            self.report.error(e.span, f"'{sym.name}' is {what}, not a value", hint)
            return T.ERROR
        if sym.kind == "const":
            e.const = sym.value
        return T.value_type(sym.type or T.ERROR)

    def e_tuple(self, e: ast.Tuple, want) -> T.Type:
        arity = T.tuple_arity(want) if want is not None else None
        if want is None or want == T.ERROR or arity is None:
            if want is None:
                self.report.error(
                    e.span,
                    f"a tuple of {len(e.items)} values has no type here",
                    "tuples are typed by their context: assign to a typed variable, pass "
                    "to a typed parameter, or use POSE(...) / POSITION(...)",
                )
            elif want != T.ERROR:
                self.report.error(e.span, f"expected {want}, got a tuple of {len(e.items)} values")
            for item in e.items:
                if not isinstance(item, ast.Tuple):
                    self.expr(item, None)
            return T.ERROR
        if isinstance(want, T.JointTuple) and want.n == 0:  # a cell whose robots differ
            arity = len(e.items)
            counts = sorted({r.n for r in self.scope.robots})
            if arity not in counts:
                shown = ", ".join(f"{r.var}: {r.n}" for r in self.scope.robots)
                self.report.error(
                    e.span,
                    f"a {want} of {arity} values fits no robot of the cell ({shown} joints)",
                    "one value per joint of the robot it is used with",
                )
                return T.ERROR
        if len(e.items) != arity:
            self.report.error(
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
            consts.append(constants.coerce(item.const, it))
        if (isinstance(want, T.JointTuple) or want in (T.POSE, T.POSITION)) and all(
            c is not None and c.type in ("INTEGER", "REAL") for c in consts
        ):
            e.const = Value(want.ird(), tuple(float(c.data[0]) for c in consts))
        return want

    def _arity_hint(self, want: T.Type) -> str | None:
        if isinstance(want, T.JointTuple) and self.scope.robot is not None:
            return f"robot {self.scope.robot.name} has {self.scope.n} joints: one value per joint"
        if isinstance(want, T.JointTuple):  # a cell: the robots with that many joints
            names = [r.var for r in self.scope.robots if r.n == want.n]
            robots = (
                f"robot {names[0]} has" if len(names) == 1 else f"robots {', '.join(names)} have"
            )
            return f"{robots} {want.n} joints: one value per joint"
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
                self.report.error(e.span, f"NOT needs a BOOLEAN, got {t}")
                return T.ERROR
            if c is not None:
                e.const = Value("BOOLEAN", (not c.data[0],))
            return T.BOOLEAN
        if t.is_numeric:
            if c is not None:
                v = (-1 if e.op == "-" else 1) * c.data[0]
                if t == T.INTEGER and (overflow := T.integer_overflow(v)):
                    self.report.error(e.span, f"negation: {overflow}")
                    return T.ERROR
                e.const = Value(c.type, (v,))
            return t
        if e.op == "-" and (t == T.POSITION or isinstance(t, T.JointTuple)):
            if c is not None and c.type == t.ird():
                e.const = Value(c.type, tuple(-x for x in c.data))
            return t
        self.report.error(e.span, f"cannot apply unary '{e.op}' to {t}")
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
            self.report.error(
                e.span, f"cannot {words[op]} {lt} and {rt}", self._geo_hint(op, lt, rt)
            )
            return T.ERROR
        if op == "*":
            if num:
                return T.INTEGER if lt == rt == T.INTEGER else T.REAL
            for a, b in ((lt, rt), (rt, lt)):
                if a.is_numeric and (b == T.POSITION or isinstance(b, T.JointTuple)):
                    return b
            self.report.error(e.span, f"cannot multiply {lt} and {rt}", self._geo_hint(op, lt, rt))
            return T.ERROR
        if op == "/":
            if num:
                return T.REAL
            if lt == T.POSITION and rt.is_numeric:
                return T.POSITION
            self.report.error(e.span, f"cannot divide {lt} by {rt}")
            return T.ERROR
        if op in ("DIV", "MOD"):
            if lt == rt == T.INTEGER:
                return T.INTEGER
            self.report.error(
                e.span,
                f"{op} needs INTEGER operands, got {lt} and {rt}",
                "use '/' for REAL division" if op == "DIV" else None,
            )
            return T.ERROR
        if op in ("AND", "OR", "EXOR"):
            if lt == rt == T.BOOLEAN:
                return T.BOOLEAN
            self.report.error(e.span, f"{op} needs BOOLEAN operands, got {lt} and {rt}")
            return T.ERROR
        if op == ":":
            if lt == T.POSE and rt in (T.POSE, T.POSITION):
                return rt
            if lt == rt == T.ORIENTATION:
                return T.ORIENTATION
            self.report.error(
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
        self.report.error(
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
        lc, rc = e.left.const, e.right.const
        if lc is None or rc is None:
            return
        folded = constants.fold_binary(op, ty, lc, rc)
        if isinstance(folded, str):
            self.report.error(e.span, folded)
        elif folded is not None:
            e.const = folded

    def e_field(self, e: ast.Field, want) -> T.Type:
        if (robot_variable := self.robot_field(e)) is not None:
            return T.value_type(robot_variable.type or T.ERROR)
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
            self.report.error(
                e.span, f"{bt} has no field '{e.name}'", f"fields: {', '.join(fields)}"
            )
            return T.ERROR
        if isinstance(bt, T.JointTuple):
            names = self.scope.joint_field_names.get(bt.name, self.scope.joint_names)
            low = [n.lower() for n in names]
            if name in low:
                k = low.index(name)
                e.canonical = (
                    self.scope.joint_names[k] if k < len(self.scope.joint_names) else names[k]
                )
                return T.REAL
            self.report.error(
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
            self.report.error(
                e.span,
                f"record {bt} has no field '{e.name}'",
                f"fields: {', '.join(n for n, _ in bt.fields)}",
            )
            return T.ERROR
        self.report.error(e.span, f"{bt} has no fields")
        return T.ERROR

    def e_index(self, e: ast.Index, want) -> T.Type:
        if self.is_output(e):
            return self.e_output(e)
        bt = self.expr(e.base, None)
        it = self.expr(e.index, T.INTEGER)
        if bt == T.ERROR or it == T.ERROR:
            return T.ERROR
        if it != T.INTEGER:
            self.report.error(e.index.span, f"an index must be INTEGER, got {it}")
            return T.ERROR
        k = number(e.index.const)
        if isinstance(bt, T.Array):
            if k is not None and not bt.lo <= k <= bt.hi:
                self.report.error(
                    e.index.span, f"index {k} is outside the array bounds [{bt.lo}..{bt.hi}]"
                )
            return bt.elem
        if isinstance(bt, T.JointTuple):
            if k is not None and bt.n and not 1 <= k <= bt.n:
                self.report.error(e.index.span, f"joint index {k} is outside 1..{bt.n}")
            return T.REAL
        self.report.error(e.span, f"{bt} cannot be indexed")
        return T.ERROR

    def is_output(self, e: ast.Expr) -> bool:
        """``OUT[n]`` of the output array (lang/digital_io.py), unless ``OUT`` is declared."""
        return is_output_syntax(e) and self.scope.lookup("OUT") is None

    def e_output(self, e: ast.Index) -> T.Type:
        """``OUT[n]``: an INTEGER ``n`` (in range when constant); reads as BOOLEAN."""
        e.output = True
        t = self.expr(e.index, T.INTEGER)
        if t not in (T.INTEGER, T.ERROR):
            self.report.error(e.index.span, f"an output number must be INTEGER, got {t}")
        k = number(e.index.const)
        if k is not None and output_error(k) is not None:
            self.report.error(e.index.span, str(output_error(k)))
        return T.BOOLEAN

    def e_input(self, e: ast.Input, want) -> T.Type:
        t = self.expr(e.index, T.INTEGER)
        if t not in (T.INTEGER, T.ERROR):
            self.report.error(e.index.span, f"an input number must be INTEGER, got {t}")
        k = number(e.index.const)
        if k is not None and k < 0:
            self.report.error(e.index.span, f"input numbers are >= 0, got {k}")
        return T.BOOLEAN

    def e_call(self, e: ast.Call, want) -> T.Type:
        up = e.name.upper()
        sym = self.scope.lookup(e.name)
        if sym is not None and sym.kind == "routine":
            e.sym = sym
            info = sym.routine
            assert info is not None
            if not info.is_function:
                self.report.error(
                    e.span, f"procedure '{sym.name}' has no value; call it as a statement"
                )
                self.args(e, info)
                return T.ERROR
            self.args(e, info)
            return info.result or T.ERROR
        if sym is not None and up not in BUILTINS and up != "POSE":
            self.report.error(e.span, f"'{sym.name}' is not a function")
            return T.ERROR
        if up == "POSE":
            return self.pose_call(e)
        if up == "FK" and (len(e.args) == 2 or self.scope.cell):
            return self.fk_call(e)
        sig = BUILTINS.get(up)
        if sig is None:
            self.report.error(
                e.span,
                f"unknown function '{e.name}'",
                self.scope.suggest(e.name, kinds=("routine",)) or _builtin_hint(e.name),
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
        res = sig(arg_types, self.scope.n)
        if isinstance(res, str):
            self.report.error(_blamed_span(e, res), f"{up}: {res}")
            return T.ERROR
        return res

    def fk_call(self, e: ast.Call) -> T.Type:
        """``FK(robot, k)``: the forward kinematics of a robot (in a cell it is named)."""
        robot = None
        if len(e.args) == 2 and isinstance(e.args[0], ast.Name):
            robot = self.scope.find_robot(e.args[0].name, e.args[0].span)
        elif self.scope.cell:
            self.report.error(
                e.span,
                f"FK in a cell names its robot ({robot_list(self.scope.robots)})",
                f"write FK({self.scope.robots[0].var}, joints)",
            )
        else:
            self.report.error(e.span, f"FK: takes 1 argument, got {len(e.args)}")
        if robot is None:
            for a in e.args[1:] if len(e.args) == 2 else e.args:
                self.after_error(a)
            return T.ERROR
        e.robot = robot
        got = self.robot_tuple(e.args[1], "MAIN_JOINT", robot, "FK")
        return T.ERROR if got == T.ERROR else T.POSE

    def robot_tuple(self, e: ast.Expr, name: str, robot: ProgramRobot, what: str) -> T.Type:
        """``e`` as a joint tuple of type ``name`` used with ``robot``: a tuple literal gets
        the robot's arity as context; a constant's values are counted (a mixed cell's
        joint tuples have no arity of their own: a variable's is checked when it runs)."""
        want = T.JointTuple(name, robot.n)
        got = self.expr(e, want)
        if not self.require(e, want, got, what) or not self.robot_arity(e, robot, what):
            return T.ERROR
        return got

    def robot_arity(self, e: ast.Expr, robot: ProgramRobot, what: str) -> bool:
        """Whether a typed joint-tuple constant ``e`` has one value per joint of ``robot``
        (an error at ``e`` if not; a value that is not constant passes)."""
        c = e.const
        if c is None or c.type not in T.JOINT_TUPLE_TYPES or len(c.data) == robot.n:
            return True
        self.report.error(
            e.span,
            f"{what}: {c.type} for robot {robot.var} needs {robot.n} values, got {len(c.data)}",
            f"robot {robot.var} ({robot.signature.name}) has {robot.n} joints",
        )
        return False

    def robot_field(self, e: ast.Field) -> Symbol | None:
        """``robot.R_TOOL`` (a robot's own system variable, ``cell.ROBOT_VARIABLES``): its
        symbol, also set as ``e.sym``; ``None`` when ``e`` does not start with a robot's
        name. Another name after a robot is an error (the symbol's type is then ERROR)."""
        if e.sym is not None or not isinstance(e.base, ast.Name):
            return e.sym
        owner = self.scope.lookup(e.base.name)
        if owner is None or owner.kind != "robot":
            return None
        e.base.sym = owner
        robot = self.scope.robots[owner.index]
        up = e.name.upper()
        if up in ROBOT_VARIABLES:
            e.sym = self.scope.robot_variable(robot, up)
            return e.sym
        other = self.scope.lookup(up)
        self.report.error(
            e.span,
            f"{up} is a setting of the whole program, not of robot {robot.var}: write {up}"
            if other is not None and other.kind == "sysvar"
            else f"robot {robot.var} has no variable '{e.name}'",
            "a robot's own variables: " + ", ".join(f"{robot.var}.{v}" for v in ROBOT_VARIABLES),
        )
        e.sym = Symbol("sysvar", up, T.ERROR, "system variable", writable=False)
        return e.sym

    def _builtin_want(self, name: str, k: int, arg: ast.Expr) -> T.Type | None:
        """The context type of argument ``k`` (it types a tuple literal there)."""
        if not isinstance(arg, ast.Tuple):
            return T.REAL
        if name == "FK":
            return self.scope.main_joint()
        if name == "INV":
            return T.POSE
        if name in ("DIST", "ORIVANG") and (name == "DIST" or k == 0):
            return T.POSITION
        return None

    def pose_call(self, e: ast.Call) -> T.Type:
        if len(e.args) == 6:
            arg_types = [self.expr(a, T.REAL) for a in e.args]
            res = POSE_FROM_NUMBERS(arg_types, self.scope.n)
            e.const = numbers_value("POSE", [a.const for a in e.args])
        else:
            arg_types = [self.expr(a, None) for a in e.args]
            res = POSE_FROM_PARTS(arg_types, self.scope.n)
            if len(arg_types) == 1 and arg_types[0] == T.POSITION:
                res = T.POSE
        if T.ERROR in arg_types:
            return T.ERROR
        if isinstance(res, str):
            self.report.error(
                _blamed_span(e, res),
                f"POSE: {res}",
                "POSE(POSITION(x, y, z), ORIZYX(a, b, c)) or POSE(x, y, z, a, b, c)",
            )
            return T.ERROR
        return res

    def args(self, e: ast.Call | ast.CallStmt, info: RoutineInfo) -> None:
        if len(e.args) != len(info.params):
            self.report.error(
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
                    self.report.error(
                        a.span, f"argument {k} of '{info.name}' is a VAR parameter: pass a variable"
                    )
                elif (
                    got != ty
                    and T.ERROR not in (got, ty)
                    and not (ty == T.SIGNAL or a.sym.type == ty)
                ):
                    self.report.error(
                        a.span,
                        f"argument {k} of '{info.name}': VAR parameter needs {ty}, got {got}",
                    )
            else:
                self.require(a, ty, got, f"argument {k} of '{info.name}'")


def _pose_context(other: T.Type, fits: tuple[T.Type, ...]) -> T.Type | None:
    """The type of a tuple operand of ':' whose other operand has type ``other``."""
    if other == T.ERROR:
        return T.ERROR  # already reported: check the items quietly
    return T.POSE if other in fits else None


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
