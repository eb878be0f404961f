"""Checked AST → IRDATA code (``docs/irdata.md``): a stack machine with explicit jumps.

Layout: routine 0 (the main program) first, ending in ``END``; then each procedure /
function in declaration order, each ending in ``RET`` (for a function, reaching that
``RET`` is a run-time error: it ended without RETURN). Folded constants become ``PUSHC``
of a deduplicated pool. Hidden temporaries (the end value of a FOR loop, the selector
of a CASE) get slots named ``$for<line>`` / ``$case<line>``.

Lowering (``<e>`` = code of e, ``Lx`` = a jump target):

* ``IF c THEN a ELSIF d THEN b ELSE e ENDIF`` →
  ``<c> JF L1 <a> JMP Lend L1: <d> JF L2 <b> JMP Lend L2: <e> Lend:``
* ``WHILE c DO a ENDWHILE`` → ``Ltop: <c> JF Lend <a> JMP Ltop Lend:``
* ``REPEAT a UNTIL c`` → ``Ltop: <a> <c> JF Ltop``
* ``FOR i := a TO b BY s DO x ENDFOR`` (s a constant) →
  ``<a> POP i <b> POP t Ltop: i t LE|GE JF Lend <x> i s ADD POP i JMP Ltop Lend:``
* ``CASE e OF ...`` → ``<e> POP t``, per label ``t k EQ JT Larm`` (ranges
  ``t lo GE t hi LE AND JT Larm``), then ``JMP Lelse``
* ``WAIT FOR c`` → ``L: <c> WAITFOR L``
* ``v.f[i] := e`` → rebuild the root with ``GETF``/``GETI`` and ``SETF``/``SETI``, store it
* ``MOVE a LIN p AND b PTP k`` (a cell) → ``<p> <a's clauses> <k> <b's clauses>
  MOVE LIN 1 ROBOT:0 … AND PTP 1 ROBOT:1 …``; in a cell every robot-bound instruction
  carries ``ROBOT:k`` (lang/irdata_robots.py), code of one robot none
"""

from __future__ import annotations

from dataclasses import dataclass

from irlc.lang import ast, platform
from irlc.lang import types as T
from irlc.lang.cell import ProgramRobot
from irlc.lang.checker import Checked, RoutineInfo, Symbol
from irlc.lang.checker.statements import assignment_root
from irlc.lang.irdata import Code, Instruction, RecordType, Routine, Slot, Target, Value
from irlc.lang.irdata_model import VALUE_TYPES, CellRobot
from irlc.lang.irdata_robots import robot_word
from irlc.lang.settings import BY_LIMIT_WORD
from irlc.lang.signature import kind_letters

_BINOP = {
    "+": "ADD",
    "-": "SUB",
    "*": "MUL",
    "/": "DIV",
    "DIV": "IDIV",
    "MOD": "MOD",
    "AND": "AND",
    "OR": "OR",
    "EXOR": "XOR",
    ":": "COMPOSE",
    "=": "EQ",
    "<>": "NE",
    "<": "LT",
    ">": "GT",
    "<=": "LE",
    ">=": "GE",
}
_CONST_TYPES = (*VALUE_TYPES, *T.JOINT_TUPLE_TYPES)


@dataclass(eq=False)
class _Label:
    index: int = -1


class _Gen:
    def __init__(self, checked: Checked):
        self.c = checked
        self.code: list[list] = []  # [op, args(list), line]
        self.consts: list[Value] = []
        self.const_index: dict[tuple, int] = {}
        self.globals = list(checked.globals)
        self.routine: RoutineInfo | None = None
        self.labels: dict[str, _Label] = {}

    # ------------------------------------------------------------------ emit helpers
    def emit(self, line: int, op: str, *args) -> None:
        self.code.append([op, list(args), line])

    def mark(self, label: _Label) -> None:
        label.index = len(self.code)

    def const(self, v: Value) -> int:
        key = (v.type, v.data)
        k = self.const_index.get(key)
        if k is None:
            k = len(self.consts)
            self.consts.append(v)
            self.const_index[key] = k
        return k

    def temp(self, name: str, ty: str) -> tuple[str, int]:
        """A hidden slot in the current routine (global for the main program)."""
        r = self.routine
        if r is None or r.index == 0:
            slot = Slot(len(self.globals), ty, name)
            self.globals.append(slot)
            return "G", slot.index
        slot = Slot(len(r.params) + len(r.locals), ty, name)
        r.locals.append(slot)
        return "L", slot.index

    def load(self, line: int, storage: tuple[str, int]) -> None:
        self.emit(line, "PUSHG" if storage[0] == "G" else "PUSHL", storage[1])

    def store(self, line: int, storage: tuple[str, int]) -> None:
        self.emit(line, "POPG" if storage[0] == "G" else "POPL", storage[1])

    # ------------------------------------------------------------------ program
    def run(self, source: str) -> Code:
        p = self.c.program
        entries: list[int] = []
        for info in self.c.routines:
            self.routine = info
            entries.append(len(self.code))
            body = p.body if info.index == 0 else info.node.body  # type: ignore[union-attr]
            self.labels = {}
            self.stmts(body)
            if info.index == 0:
                self.emit(p.end_span.line, "END")
            else:
                self.emit(info.node.end_span.line, "RET")  # type: ignore[union-attr]
        first, *others = [self.cell_robot(r, source) for r in self.c.robots]
        code = Code(
            program=p.name,
            source=source,
            robot_var=first.var,
            robot=first.robot,
            joint_kinds=first.joint_kinds,
            joint_names=first.joint_names,
            at=first.at,
            other_robots=others,
            datalists=[(d.name, d.shown_path) for d in self.c.datalists],
            consts=self.consts,
            obstacles=list(self.c.obstacles),
            inputs=dict(self.c.inputs),
            types=[
                RecordType(r.index, tuple((n, t.ird()) for n, t in r.fields))
                for r in self.c.records
            ],
            globals=self.globals,
        )
        for info, entry in zip(self.c.routines, entries, strict=True):
            code.routines.append(
                Routine(
                    info.index,
                    info.name,
                    "MAIN" if info.index == 0 else info.kind,
                    entry,
                    list(info.params),
                    list(info.locals),
                )
            )
        code.code = [self.finish(ins) for ins in self.code]
        return code

    def cell_robot(self, r: ProgramRobot, source: str) -> CellRobot:
        """The ROBOT and JOINTS records of robot ``r`` (a cell's joint names are the
        program's for every robot: its MAIN_JOINT record's, else a1 … aN)."""
        clause = r.clause
        position = None
        if clause is not None and r.index > 0:
            position = (source, clause.robot_span.line, clause.robot_span.column)
        names = tuple(self.c.joint_names[: r.n])
        return CellRobot(r.var, r.text, kind_letters(r.signature), names, r.at, position)

    def robot_words(self, s: ast.Stmt) -> list[str]:
        """The ``ROBOT:k`` operands of a statement that names robots (in a cell only: code
        of one robot leaves them out)."""
        return [robot_word(k) for k in s.resolved] if len(self.c.robots) > 1 else []

    def finish(self, ins: list) -> Instruction:
        op, args, line = ins
        out = []
        for a in args:
            if isinstance(a, _Label):
                assert a.index >= 0, "unplaced jump label"
                out.append(Target(a.index))
            else:
                out.append(a)
        return Instruction(op, tuple(out), line)

    # ------------------------------------------------------------------ statements
    def stmts(self, body: list[ast.Stmt]) -> None:
        for s in body:
            getattr(self, f"s_{type(s).__name__.lower()}")(s)

    def label_for(self, name: str) -> _Label:
        return self.labels.setdefault(name.lower(), _Label())

    def s_label(self, s: ast.Label) -> None:
        self.mark(self.label_for(s.name))

    def s_goto(self, s: ast.Goto) -> None:
        self.emit(s.span.line, "JMP", self.label_for(s.label))

    def s_assign(self, s: ast.Assign) -> None:
        line = s.span.line
        if isinstance(s.target, ast.Index) and s.target.output:  # OUT[n] := b: n b OUTSET
            self.expr(s.target.index, T.INTEGER)
            self.expr(s.value, T.BOOLEAN)
            self.emit(line, "OUTSET")
            return
        root = assignment_root(s.target)
        path: list[ast.Expr] = []
        node = s.target
        while node is not root:
            assert isinstance(node, ast.Field | ast.Index)
            path.insert(0, node)
            node = node.base
        assert isinstance(root, ast.Name | ast.Field) and root.sym is not None
        sym: Symbol = root.sym
        want = sym.type if not path else path[-1].ty
        if not path:
            self.expr(s.value, want)
            if sym.kind == "sysvar":
                self.emit(line, "POPSYS", sym.name, *self.sysvar_robot(sym))
            elif sym.type == T.SIGNAL:
                self.emit(line, "SIGOUT", sym.index)
            else:
                self.store(line, (sym.storage, sym.index))
            return
        self.rebuild(line, root, path, 0, s.value, want)
        if sym.kind == "sysvar":
            self.emit(line, "POPSYS", sym.name, *self.sysvar_robot(sym))
        else:
            self.store(line, (sym.storage, sym.index))

    def sysvar_robot(self, sym: Symbol) -> list[str]:
        """A robot's own system variable in a cell: its ``ROBOT:k`` operand."""
        return [robot_word(sym.robot)] if sym.robot is not None else []

    def rebuild(self, line, root, path, k, value, want) -> None:
        """Push a copy of ``root.path[:k]`` with ``path[k:]`` replaced by ``value``."""
        if k == len(path):
            self.expr(value, want)
            return
        self.expr(root if k == 0 else path[k - 1])
        sel = path[k]
        if isinstance(sel, ast.Index):
            self.expr(sel.index)
            self.rebuild(line, root, path, k + 1, value, want)
            self.emit(line, "SETI")
        else:
            self.rebuild(line, root, path, k + 1, value, want)
            self.emit(line, "SETF", sel.canonical)

    def s_callstmt(self, s: ast.CallStmt) -> None:
        if s.pulse:  # PULSE(OUT[n], t): n t PULSE
            self.expr(s.args[0].index, T.INTEGER)
            self.expr(s.args[1], T.REAL)
            self.emit(s.span.line, "PULSE")
            return
        info = s.sym.routine
        self.call_args(s.args, info)
        self.emit(s.span.line, "CALL", info.index, len(s.args))
        if info.is_function:
            self.emit(s.span.line, "POP")

    def call_args(self, args: list[ast.Expr], info: RoutineInfo) -> None:
        for a, slot, ty in zip(args, info.params, info.param_types, strict=True):
            if slot.by_ref:
                sym = a.sym
                self.emit(a.span.line, "REFG" if sym.storage == "G" else "REFL", sym.index)
            else:
                self.expr(a, ty)

    def s_return(self, s: ast.Return) -> None:
        if s.value is None:
            self.emit(s.span.line, "RET")
        else:
            self.expr(s.value, self.routine.result)  # type: ignore[union-attr]
            self.emit(s.span.line, "RETV")

    def s_if(self, s: ast.If) -> None:
        end = _Label()
        for k, (cond, body) in enumerate(s.arms):
            nxt = _Label()
            self.expr(cond)
            self.emit(cond.span.line, "JF", nxt)
            self.stmts(body)
            if k < len(s.arms) - 1 or s.else_body is not None:
                self.emit(s.end_span.line, "JMP", end)
            self.mark(nxt)
        if s.else_body is not None:
            self.stmts(s.else_body)
        self.mark(end)

    def s_while(self, s: ast.While) -> None:
        top, end = _Label(), _Label()
        self.mark(top)
        self.expr(s.cond)
        self.emit(s.span.line, "JF", end)
        self.stmts(s.body)
        self.emit(s.end_span.line, "JMP", top)
        self.mark(end)

    def s_repeat(self, s: ast.Repeat) -> None:
        top = _Label()
        self.mark(top)
        self.stmts(s.body)
        self.expr(s.cond)
        self.emit(s.end_span.line, "JF", top)

    def s_for(self, s: ast.For) -> None:
        line = s.span.line
        var = (s.var.sym.storage, s.var.sym.index)
        step = s.step.const.data[0] if s.step is not None else 1
        self.expr(s.start, T.INTEGER)
        self.store(line, var)
        self.expr(s.stop, T.INTEGER)
        limit = self.temp(f"$for{line}", "INTEGER")
        self.store(line, limit)
        top, end = _Label(), _Label()
        self.mark(top)
        self.load(line, var)
        self.load(line, limit)
        self.emit(line, "LE" if step > 0 else "GE")
        self.emit(line, "JF", end)
        self.stmts(s.body)
        self.load(s.end_span.line, var)
        self.emit(s.end_span.line, "PUSHC", self.const(Value("INTEGER", (step,))))
        self.emit(s.end_span.line, "ADD")
        self.store(s.end_span.line, var)
        self.emit(s.end_span.line, "JMP", top)
        self.mark(end)

    def s_case(self, s: ast.Case) -> None:
        line = s.span.line
        self.expr(s.selector)
        sel_type = s.selector.ty.ird() if s.selector.ty not in (None, T.ERROR) else "INTEGER"
        sel = self.temp(f"$case{line}", sel_type)
        self.store(line, sel)
        arm_labels = []
        for arm in s.arms:
            target = _Label()
            arm_labels.append(target)
            for lo, hi in arm.labels:
                ln = lo.span.line
                if hi is None:
                    self.load(ln, sel)
                    self.emit(ln, "PUSHC", self.const(lo.const))
                    self.emit(ln, "EQ")
                else:
                    self.load(ln, sel)
                    self.emit(ln, "PUSHC", self.const(lo.const))
                    self.emit(ln, "GE")
                    self.load(ln, sel)
                    self.emit(ln, "PUSHC", self.const(hi.const))
                    self.emit(ln, "LE")
                    self.emit(ln, "AND")
                self.emit(ln, "JT", target)
        other, end = _Label(), _Label()
        self.emit(line, "JMP", other)
        for arm, target in zip(s.arms, arm_labels, strict=True):
            self.mark(target)
            self.stmts(arm.body)
            self.emit(s.end_span.line, "JMP", end)
        self.mark(other)
        if s.else_body is not None:
            self.stmts(s.else_body)
        self.mark(end)

    def s_wait(self, s: ast.Wait) -> None:
        self.expr(s.seconds, T.REAL)
        self.emit(s.span.line, "WAIT")

    def s_waitfor(self, s: ast.WaitFor) -> None:
        top = _Label()
        self.mark(top)
        self.expr(s.cond)
        self.emit(s.span.line, "WAITFOR", top)

    def s_pause(self, s: ast.Pause) -> None:
        self.emit(s.span.line, "PAUSE")

    def s_halt(self, s: ast.Halt) -> None:
        self.emit(s.span.line, "HALT")

    def s_write(self, s: ast.Write) -> None:
        for a in s.args:
            self.expr(a)
        self.emit(s.span.line, "WRITELN" if s.newline else "WRITE", len(s.args))

    # ------------------------------------------------------------------ motion / options
    def s_move(self, s: ast.Move) -> None:
        self.emit(s.span.line, "MOVE", *self.move_part(s))

    def s_movegroup(self, g: ast.MoveGroup) -> None:
        """The parts' operands in order, then one MOVE: ``part AND part …``."""
        words: list = []
        for part in g.parts:
            words += [*(["AND"] if words else []), *self.move_part(part)]
        self.emit(g.span.line, "MOVE", *words)

    def move_part(self, s: ast.Move) -> list:
        """Push a motion's targets and clause operands; its words ``KIND npts [ROBOT:k]
        clause…``."""
        for t in s.targets:
            self.expr(t, t.ty)
        words = []
        for c in s.clauses:
            if c.kind == "RECONF":
                for k in c.args:
                    self.expr(k, k.ty)
                words.append(f"RECONF:{len(c.args)}")
            else:  # (WITH PLATFORM: a REAL, or an ARRAY of the platform's coordinates)
                for a in c.args:
                    keep = c.kind.startswith("JOINT") or isinstance(a.ty, T.Array)
                    self.expr(a, a.ty if keep else T.REAL)
                words.append(c.kind)
        return [s.kind, len(s.targets), *self.robot_words(s), *words]

    def s_modalon(self, s: ast.ModalOn) -> None:
        line = s.span.line
        robot = self.robot_words(s)
        if s.option in BY_LIMIT_WORD:
            for a in s.args:
                self.expr(a, a.ty)
            self.emit(line, "OPTON", s.option, *robot)
        elif s.option == "CYCLIC":
            self.emit(line, "OPTON", "CYCLIC", *robot)
        elif s.option == "OBSTACLE":
            self.emit(line, "OPTON", "OBSTACLE", *robot, self.obstacle_name(s.name))
        elif s.option == "FREEZE":
            self.emit(line, "OPTON", "FREEZE", *robot, *(int(a.const.data[0]) for a in s.args))
        elif s.option == "COOPERATE":  # ROBOT:w ROBOT:h [VERTICAL]
            self.emit(line, "OPTON", "COOPERATE", *robot, *(["VERTICAL"] if s.word else []))

    def s_modaloff(self, s: ast.ModalOff) -> None:
        robot = self.robot_words(s)
        if s.option == "OBSTACLE":
            self.emit(s.span.line, "OPTOFF", "OBSTACLE", *robot, self.obstacle_name(s.name))
        else:
            self.emit(s.span.line, "OPTOFF", s.option, *robot)

    def obstacle_name(self, name: str | None) -> str:
        assert name is not None
        return next(o.name for o in self.c.obstacles if o.name.lower() == name.lower())

    def s_reconfigure(self, s: ast.Reconfigure) -> None:
        self.expr(s.target, s.target.ty)
        self.emit(s.span.line, "RECONF", *self.robot_words(s))

    # ------------------------------------------------------------------ expressions
    def expr(self, e: ast.Expr, want: T.Type | None = None) -> None:
        line = e.span.line
        v = e.const
        if v is not None and (v.type in _CONST_TYPES or platform.constant_count(v.type)):
            if want == T.REAL and v.type == "INTEGER":
                v = Value("REAL", (float(v.data[0]),))
            elif want == T.STRING and v.type == "CHAR":
                v = Value("STRING", v.data)
            self.emit(line, "PUSHC", self.const(v))
            return
        getattr(self, f"e_{type(e).__name__.lower()}")(e)

    def e_name(self, e: ast.Name) -> None:
        sym: Symbol = e.sym
        if sym.kind == "sysvar":
            self.emit(e.span.line, "PUSHSYS", sym.name)
        elif sym.kind == "routine":
            self.emit(e.span.line, "CALL", sym.routine.index, 0)  # type: ignore[union-attr]
        else:
            self.load(e.span.line, (sym.storage, sym.index))

    def e_tuple(self, e: ast.Tuple) -> None:
        items = T.tuple_items(e.ty) if e.ty is not None else []
        for item, it in zip(e.items, items or [None] * len(e.items), strict=False):
            self.expr(item, it)
        self.emit(e.span.line, "MAKE", e.ty.ird(), len(e.items))

    def e_field(self, e: ast.Field) -> None:
        if e.sym is not None:  # robot.R_TOOL: a robot's own system variable
            self.emit(e.span.line, "PUSHSYS", e.sym.name, *self.sysvar_robot(e.sym))
            return
        self.expr(e.base)
        self.emit(e.span.line, "GETF", e.canonical)

    def e_index(self, e: ast.Index) -> None:
        if e.output:  # OUT[n]: n PUSHOUT
            self.expr(e.index, T.INTEGER)
            self.emit(e.span.line, "PUSHOUT")
            return
        self.expr(e.base)
        self.expr(e.index)
        self.emit(e.span.line, "GETI")

    def e_unary(self, e: ast.Unary) -> None:
        self.expr(e.operand)
        if e.op == "-":
            self.emit(e.span.line, "NEG")
        elif e.op == "NOT":
            self.emit(e.span.line, "NOT")

    def e_binary(self, e: ast.Binary) -> None:
        self.expr(e.left)
        self.expr(e.right)
        self.emit(e.span.line, _BINOP[e.op.upper()])

    def e_input(self, e: ast.Input) -> None:
        self.expr(e.index)
        self.emit(e.span.line, "PUSHIN")

    def e_call(self, e: ast.Call) -> None:
        line = e.span.line
        if e.sym is not None:
            info = e.sym.routine
            self.call_args(e.args, info)
            self.emit(line, "CALL", info.index, len(e.args))
            return
        up = e.name.upper()
        if e.robot is not None:  # FK(robot, k): the joints, the robot as an operand
            self.expr(e.args[1], e.args[1].ty)
            cell = len(self.c.robots) > 1
            self.emit(line, "CALLB", "FK", 1, *([robot_word(e.robot.index)] if cell else []))
            return
        if up == "POSE" and len(e.args) == 6:
            for a in e.args:
                self.expr(a, T.REAL)
            self.emit(line, "MAKE", "POSE", 6)
            return
        for a in e.args:
            self.expr(a, a.ty)
        self.emit(line, "CALLB", up, len(e.args))


def generate(checked: Checked, source: str) -> Code:
    """Generate the IRDATA code of a program that checked without errors."""
    return _Gen(checked).run(source)
