"""The syntax tree → AST step of the parser: lark reductions become :mod:`irlc.lang.ast` nodes.

:class:`Builder` is lark's ``transformer=``: the LALR parser calls one method per reduced
rule, bottom-up, so the AST is built while parsing (no parse tree). Every node gets the
:class:`Span` of its first token. What the grammar accepts but the language does not
(a malformed number, an INTEGER literal out of range, ROBOT after a declaration, a
misspelled block end parsed as a call) is a :class:`SourceError` at its position.
"""

from __future__ import annotations

import re

from irlc.lang import ast, foreign
from irlc.lang.diagnostics import Diagnostic, Span
from irlc.lang.errors import IrlcError
from irlc.lang.settings import LIMIT_OPTIONS
from irlc.lang.types import INT_MAX
from irlc.lang.typos import MISSPELLED, misspelled_keyword
from irlc.lang.value_ranges import parse_integer
from lark import Token, Transformer


class SourceError(IrlcError):
    """An error at a position of the source found while lexing or building the AST."""

    def __init__(self, span: Span, message: str, hint: str | None = None):
        super().__init__(message)
        self.span, self.message, self.hint = span, message, hint

    def diagnostic(self, filename: str) -> Diagnostic:
        return Diagnostic("error", self.message, filename, self.span, self.hint)


class _MisspelledKeyword(SourceError):
    """``END_IF;`` parsed as a call: the typo's diagnostic (lang/typos.py), at the typo."""

    def __init__(self, word: str, span: Span):
        super().__init__(span, f"misspelled keyword {word}")
        self.word = word

    def diagnostic(self, filename: str) -> Diagnostic:
        typo = misspelled_keyword(self.word, self.span, filename)
        assert typo is not None
        return typo


def token_span(tok: Token) -> Span:
    """Where a token is (1-based line and column, end column exclusive)."""
    line = tok.line or 1
    col = tok.column or 1
    end_col = tok.end_column or col + 1
    return Span(line, col, tok.end_line or line, end_col)


_NUMBER_RE = re.compile(r"(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")


def _malformed_number(tok: Token) -> SourceError:
    number = _NUMBER_RE.match(tok.value)
    unit = foreign.unit_hint(tok.value[number.end() :], number[0]) if number else None
    return SourceError(
        token_span(tok),
        f"malformed number '{tok.value}'",
        unit
        or "numbers look like 12, 180., .5, 1e-3 or 2.5E+2; put a space between a number and "
        "a following word",
    )


def _span(x) -> Span:
    if isinstance(x, Token):
        return token_span(x)
    if isinstance(x, ast.Node):
        return x.span
    raise TypeError(x)


def _nodes(children) -> list:
    return [c for c in children if not isinstance(c, Token) and c is not None]


_LIMIT_OPTION = {  # the grammar's tokens of the limit options (on and off) → the option
    **{o.word: o.word for o in LIMIT_OPTIONS},
    **{o.end_word: o.word for o in LIMIT_OPTIONS},
}
_BINOPS = {"PLUS": "+", "MINUS": "-", "STAR": "*", "SLASH": "/", "COLON": ":"}


class Builder(Transformer):
    """Builds AST nodes bottom-up while the LALR parser reduces (lark ``transformer=``)."""

    # ---------------------------------------------------------------- program
    def start(self, c):
        prog_tok, name = c[0], c[1]
        robots, datalists, unsupported = [], [], []
        decls = ast.Decls()
        routines: list[ast.Routine] = []
        body: list[ast.Stmt] = []
        end_span = _span(c[0])
        first_decl: Span | None = None
        for x in c[2:]:
            if isinstance(x, (ast.RobotClause, ast.DatalistClause)) and first_decl is not None:
                what = "ROBOT" if isinstance(x, ast.RobotClause) else "IMPORT DATALIST"
                raise SourceError(
                    x.span,
                    f"{what} must come before the declarations",
                    f"move it up, right after the PROGRAM line (first declaration: line "
                    f"{first_decl.line})",
                )
            if isinstance(x, (ast.Decls, ast.Routine)) and first_decl is None:
                first_decl = x.order[0].span if isinstance(x, ast.Decls) and x.order else x.span
            if isinstance(x, ast.RobotClause):
                robots.append(x)
            elif isinstance(x, ast.DatalistClause):
                datalists.append(x)
            elif isinstance(x, ast.Unsupported):
                unsupported.append(x)
            elif isinstance(x, ast.Decls):
                _merge(decls, x)
            elif isinstance(x, ast.Routine):
                routines.append(x)
                decls.order.append(x)
            elif isinstance(x, list):
                body = x
            elif isinstance(x, Token) and x.type == "ENDPROGRAM":
                end_span = _span(x)
        return ast.Program(
            _span(prog_tok),
            name.value,
            robots,
            datalists,
            unsupported,
            decls,
            routines,
            body,
            end_span,
        )

    def robot_clause(self, c):
        kw, var, target, word, at = c[0], c[1], c[2], c[3], c[4]
        robot = target.value
        if target.type == "STRING":
            robot = _unquote(robot)
        if word is not None and word.value.upper() != "AT":
            raise SourceError(
                _span(word),
                f"expected AT or ';' after the robot, got '{word.value}'",
                "ROBOT name := robot AT (x, y, z, a, b, c); places the robot in the cell",
            )
        return ast.RobotClause(_span(kw), var.value, robot, _span(target), at, _span(var))

    def datalist_clause(self, c):
        return ast.DatalistClause(_span(c[2]), c[2].value)

    def system_spec(self, c):
        return ast.Unsupported(_span(c[0]), "SYSTEM SPECIFICATION")

    def standard_in(self, c):
        return ast.Unsupported(_span(c[0]), "STANDARD_IN")

    def standard_out(self, c):
        return ast.Unsupported(_span(c[0]), "STANDARD_OUT")

    def from_import(self, c):
        return ast.Unsupported(_span(c[0]), "FROM ... IMPORT")

    def export(self, c):
        return ast.Unsupported(_span(c[0]), "EXPORT ... TO")

    # ---------------------------------------------------------------- declarations
    def const_section(self, c):
        return _section("consts", c)

    def const_plain(self, c):
        name, value = c[0], _nodes(c)[-1]
        return ast.ConstDecl(_span(name), name.value, None, value)

    def const_typed(self, c):
        ty = c[0]
        name = next(t for t in c[1:] if isinstance(t, Token) and t.type == "NAME")
        return ast.ConstDecl(_span(name), name.value, ty, c[-1])

    def type_section(self, c):
        return _section("types", c)

    def type_alias(self, c):
        name = c[0]
        return ast.TypeDecl(_span(name), name.value, _nodes(c)[-1], _span(name))

    def type_record(self, c):
        rec = c[0]
        target = c[-1]
        if isinstance(target, ast.SimpleTypeRef):
            return ast.TypeDecl(rec.span, target.name, rec, target.span)
        return ast.TypeDecl(rec.span, target.value, rec, _span(target))

    def var_section(self, c):
        return _section("vars", c)

    def var_decl(self, c):
        ty, names = _nodes(c)
        return ast.VarDecl(ty.span, ty, names)

    def name_list(self, c):
        return [(t.value, _span(t)) for t in c if isinstance(t, Token) and t.type == "NAME"]

    def type(self, c):
        x = c[0]
        if isinstance(x, Token):
            return ast.NamedTypeRef(_span(x), x.value)
        return x

    def simple_type(self, c):
        t = c[0]
        name = "STRING" if t.type == "STRING_T" else t.type
        return ast.SimpleTypeRef(_span(t), name)

    joint_type = simple_type

    def array_type(self, c):
        lo, hi, elem = _nodes(c)
        return ast.ArrayTypeRef(_span(c[0]), lo, hi, elem)

    def record_type(self, c):
        return ast.RecordTypeRef(_span(c[0]), _nodes(c))

    def field_decl(self, c):
        ty, names = _nodes(c)
        return (ty, names)

    def procedure(self, c):
        return self._routine(c, is_function=False)

    def function(self, c):
        return self._routine(c, is_function=True)

    def _routine(self, c, is_function: bool) -> ast.Routine:
        kw, name = c[0], c[1]
        params: list[ast.Param] = []
        result = None
        decls = ast.Decls()
        body: list[ast.Stmt] = []
        end_span = _span(kw)
        seen_begin = False
        for x in c[2:]:
            if isinstance(x, Token):
                if x.type == "BEGIN":
                    seen_begin = True
                elif x.type in ("ENDPROC", "ENDFCT"):
                    end_span = _span(x)
            elif isinstance(x, ast.Decls):
                _merge(decls, x)
            elif isinstance(x, list) and (not x or isinstance(x[0], ast.Param)) and not seen_begin:
                params = x
            elif isinstance(x, list):
                body = x
            elif isinstance(x, ast.TypeRef):
                result = x
        return ast.Routine(
            _span(name), name.value, is_function, params, result, decls, body, end_span
        )

    def params(self, c):
        return [p for group in _nodes(c) for p in group]

    def param_group(self, c):
        by_ref = c[0] is not None
        ty, names = _nodes(c)
        return [ast.Param(span, name, ty, by_ref) for name, span in names]

    # ---------------------------------------------------------------- statements
    def stmt_list(self, c):
        out: list[ast.Stmt] = []
        for s in c:
            if isinstance(s, list):
                out.extend(s)
            elif s is not None and not isinstance(s, Token):
                out.append(s)
        return out

    def empty(self, c):
        return None

    def labeled(self, c):
        name, stmt = c[0], c[-1]
        label = ast.Label(_span(name), name.value)
        if stmt is None or isinstance(stmt, Token):
            return [label]
        return [label, *(stmt if isinstance(stmt, list) else [stmt])]

    def assign(self, c):
        target, value = _nodes(c)
        return ast.Assign(target.span, target, value)

    def call_noargs(self, c):
        if c[0].value.upper() in MISSPELLED:
            raise _MisspelledKeyword(c[0].value, _span(c[0]))
        return ast.CallStmt(_span(c[0]), c[0].value, [])

    def call(self, c):
        args = c[1] if len(c) > 1 and c[1] is not None else []
        return ast.CallStmt(_span(c[0]), c[0].value, args)

    def return_(self, c):
        return ast.Return(_span(c[0]), c[1])

    def if_(self, c):
        cond, body = c[1], c[3]
        arms = [(cond, body)]
        else_body = None
        end = _span(c[-1])
        rest = c[4:-1]
        for x in rest:
            if isinstance(x, tuple):
                arms.append(x)
            elif isinstance(x, list):
                else_body = x
        return ast.If(_span(c[0]), arms, else_body, end)

    def elsif(self, c):
        return (c[1], c[3])

    def while_(self, c):
        return ast.While(_span(c[0]), c[1], c[3], _span(c[4]))

    def repeat(self, c):
        return ast.Repeat(_span(c[0]), c[1], c[3], _span(c[2]))

    def for_(self, c):
        # FOR NAME := expr TO expr [BY expr] DO stmt_list ENDFOR
        var = ast.Name(_span(c[1]), c[1].value)
        start, stop = c[2], c[4]
        step = c[6]
        body = c[8]
        return ast.For(_span(c[0]), var, start, stop, step, body, _span(c[9]))

    def case(self, c):
        selector = c[1]
        arms = [x for x in c if isinstance(x, ast.CaseArm)]
        else_body = None
        for i, x in enumerate(c):
            if isinstance(x, Token) and x.type == "ELSE":
                else_body = c[i + 1]
        return ast.Case(_span(c[0]), selector, arms, else_body, _span(c[-1]))

    def case_arm(self, c):
        labels = [x for x in c if isinstance(x, tuple)]
        body = c[-1]
        return ast.CaseArm(labels[0][0].span, labels, body)

    def case_label(self, c):
        return (c[0], c[2] if len(c) > 2 else None)

    def case_const(self, c):
        minus, tok = c[0], c[1]
        node = self._literal(tok)
        if minus is not None:
            if not isinstance(node, ast.Num):
                raise SourceError(_span(minus), "'-' before a non-number case label")
            node = ast.Num(_span(minus), -node.value, "-" + node.text)
        return node

    def goto(self, c):
        return ast.Goto(_span(c[1]), c[1].value)

    def wait(self, c):
        return ast.Wait(_span(c[0]), c[1])

    def wait_for(self, c):
        return ast.WaitFor(_span(c[0]), c[2])

    def pause(self, c):
        return ast.Pause(_span(c[0]))

    def halt(self, c):
        return ast.Halt(_span(c[0]))

    def write(self, c):
        return ast.Write(_span(c[0]), c[1] or [], False)

    def writeln(self, c):
        return ast.Write(_span(c[0]), c[1] or [] if len(c) > 1 else [], True)

    # motion: a statement of one part is a Move, of several (… AND …) a MoveGroup
    def move(self, c):
        parts = [x for x in c if isinstance(x, ast.Move)]
        parts[0].span = _span(c[0])  # the statement's position: its MOVE keyword
        if len(parts) == 1:
            return parts[0]
        return ast.MoveGroup(_span(c[0]), parts)

    move_inc = move

    def _move(self, c, kind: str, targets: list) -> ast.Move:
        robot, kw = c[0], c[1]
        clauses = [x for x in c if isinstance(x, ast.WithClause)]
        where = _span(robot if robot is not None else kw)
        name, name_span = (robot.value, _span(robot)) if robot is not None else (None, None)
        return ast.Move(where, kind, targets, clauses, name, name_span)

    def move_ptp(self, c):
        return self._move(c, "PTP", [c[2]])

    def move_lin(self, c):
        return self._move(c, "LIN", c[2])

    def move_path(self, c):
        return self._move(c, "LINPATH", c[3])

    def move_circle(self, c):
        return self._move(c, "CIRCLE", [c[2], c[3]])

    def move_inc_lin(self, c):
        return self._move(c, "LININC", [c[2]])

    def move_inc_ptp(self, c):
        return self._move(c, "PTPINC", [c[2]])

    def with_param(self, c):
        word = c[1]
        return ast.WithClause(_span(word), word.value.upper(), [c[2]], word.value)

    def with_limit(self, c):
        return ast.WithClause(_span(c[1]), c[1].type, [c[2], c[3]], c[1].value)

    def with_reconf(self, c):
        return ast.WithClause(_span(c[1]), "RECONF", c[2], c[1].value)

    # modal redundancy options; ``FOR robot`` (c[-1]) names the robot in a cell
    def for_robot(self, c):
        return c[1]

    def limit_on(self, c):
        on = ast.ModalOn(_span(c[0]), _LIMIT_OPTION[c[0].type], [c[1], c[2]])
        return _for_robot(on, c[-1])

    def limit_off(self, c):
        return _for_robot(ast.ModalOff(_span(c[0]), _LIMIT_OPTION[c[0].type]), c[-1])

    def cyclic_on(self, c):
        return _for_robot(ast.ModalOn(_span(c[0]), "CYCLIC", []), c[-1])

    def cyclic_off(self, c):
        return _for_robot(ast.ModalOff(_span(c[0]), "CYCLIC"), c[-1])

    def obstacle_on(self, c):
        on = ast.ModalOn(_span(c[0]), "OBSTACLE", [], c[1].value, _span(c[1]))
        return _for_robot(on, c[-1])

    def obstacle_off(self, c):
        off = ast.ModalOff(_span(c[0]), "OBSTACLE", c[1].value, _span(c[1]))
        return _for_robot(off, c[-1])

    def freeze_on(self, c):
        return _for_robot(ast.ModalOn(_span(c[0]), "FREEZE", c[1]), c[-1])

    def freeze_off(self, c):
        return _for_robot(ast.ModalOff(_span(c[0]), "FREEZE"), c[-1])

    def reconf(self, c):
        return _for_robot(ast.Reconfigure(_span(c[0]), c[1]), c[-1])

    def cooperate_on(self, c):
        # COOPERATE robot IN holder [WITH word]
        robot, holder, word = c[1], c[3], c[-1]
        on = ast.ModalOn(_span(c[0]), "COOPERATE", [], holder.value, _span(holder))
        on.robot, on.robot_span = robot.value, _span(robot)
        if word is not None:
            on.word, on.word_span = word.value, _span(word)
        return on

    def cooperate_off(self, c):
        return ast.ModalOff(_span(c[0]), "COOPERATE")

    def designator(self, c):
        node: ast.Expr = ast.Name(_span(c[0]), c[0].value)
        for sel in c[1:]:
            kind, arg, span = sel
            node = ast.Field(span, node, arg) if kind == "field" else ast.Index(span, node, arg)
        return node

    def field_sel(self, c):
        return ("field", c[0].value, _span(c[0]))

    def index_sel(self, c):
        return ("index", c[0], c[0].span)

    # ---------------------------------------------------------------- expressions
    def expr_list(self, c):
        return list(c)

    def compare(self, c):
        left, op, right = c
        return ast.Binary(_span(op), op.value, left, right)

    def binop(self, c):
        left, op, right = c
        return ast.Binary(_span(op), _BINOPS.get(op.type, op.value.upper()), left, right)

    def unop(self, c):
        op, operand = c
        return ast.Unary(_span(op), op.value.upper(), operand)

    def field(self, c):
        return ast.Field(_span(c[1]), c[0], c[1].value)

    def index(self, c):
        return ast.Index(c[1].span, c[0], c[1])

    def _literal(self, tok: Token) -> ast.Expr:
        if tok.type == "NUMBER":
            return self.number([tok])
        if tok.type == "STRING":
            return self.string([tok])
        return self.boolean([tok])

    def number(self, c):
        tok = c[0]
        text = tok.value
        if not _NUMBER_RE.fullmatch(text):  # NUMBER swallows trailing letters: '1e', '12abc'
            raise _malformed_number(tok)
        if re.fullmatch(r"\d+", text):
            value = parse_integer(text)
            if isinstance(value, str):
                raise SourceError(
                    _span(tok),
                    value,
                    f"INTEGER literals go up to {INT_MAX} (write {-INT_MAX} - 1 for the "
                    "smallest INTEGER); a larger number needs a REAL literal such as 1e20",
                )
            return ast.Num(_span(tok), value, text)
        value = float(text)
        if value == float("inf"):
            raise SourceError(_span(tok), f"number {text} is too large")
        return ast.Num(_span(tok), value, text)

    def string(self, c):
        return ast.Str(_span(c[0]), _unquote(c[0].value))

    def boolean(self, c):
        return ast.Bool(_span(c[0]), c[0].type == "TRUE")

    def name(self, c):
        return ast.Name(_span(c[0]), c[0].value)

    def funcall(self, c):
        name = c[0]
        args = c[1] if len(c) > 1 and c[1] is not None else []
        spelled = name.value.upper() if name.type in ("POSE", "POSITION") else name.value
        return ast.Call(_span(name), spelled, args)

    def input(self, c):
        return ast.Input(_span(c[0]), c[1])

    def tuple(self, c):
        paren, first, rest = c
        return ast.Tuple(_span(paren), [first, *rest])


def _for_robot(stmt, robot: Token | None):
    """``stmt`` with the robot of its ``FOR robot`` suffix (``None``: no suffix)."""
    if robot is not None:
        stmt.robot, stmt.robot_span = robot.value, _span(robot)
    return stmt


def _section(kind: str, c) -> ast.Decls:
    """A CONST / TYPE / VAR section: its declarations (``kind`` = the Decls list)."""
    items = _nodes(c)
    return ast.Decls(**{kind: items}, order=list(items))


def _unquote(text: str) -> str:
    q = text[0]
    return text[1:-1].replace(q + q, q)


def _merge(into: ast.Decls, d: ast.Decls) -> None:
    into.consts += d.consts
    into.types += d.types
    into.vars += d.vars
    into.order += d.order
