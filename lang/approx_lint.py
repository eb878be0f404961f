"""Compile-time warnings where approximate positioning (``WITH APPROX``, ``R_APPROX``)
has no effect.

The controller blends an approximated motion into the next one only if nothing stops
its *advance run* in between (docs/language.md, "Approximate positioning"). These
statements stop it, so the approximated point before them is reached with an exact stop:

* ``WAIT … SEC`` and ``WAIT FOR`` (any), ``PAUSE``, ``HALT``;
* reading an input ``IN[n]`` (e.g. ``IF IN[1] THEN``) or ``R_ACT_POSE`` / ``R_ACT_JOINT``;
* ``RECONFIGURATION``, switching an option on or off (JOINTLIMIT …, CYCLIC,
  OBSTACLE, FREEZE, COOPERATE), and assigning ``R_TOOL``, ``R_BASE`` (also a robot's:
  ``holder.R_TOOL``) or ``R_IPO``;
* the end of the program (for an explicit ``WITH APPROX`` on the last motion).

Writing a signal or WRITE does not stop it. The walk follows the statements in source
order (into the bodies of IF, loops and CASE); a routine call is not followed. The
motion is "approximated" when it has ``WITH APPROX`` with a constant other than 0, or,
without a WITH APPROX, when the last constant assigned to ``R_APPROX`` before it in
source order was not 0 (an assignment of a non-constant counts as on).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, fields

from irlc.lang import ast
from irlc.lang.settings import BY_FIELD, SYSTEM_VARIABLES

# The system variables by their role in lang/settings.py (not by spelling): the modal
# approximation distance; those whose assignment stops the advance run (the frames and the
# IPO cycle); those read from the controller (the actual pose and joints).
_APPROX_VARIABLE = BY_FIELD["approx"].system_variable
_STOPPING_FIELDS = ("tool", "base", "ipo")
_STOPPING_VARIABLES = tuple(
    v.name for v in SYSTEM_VARIABLES.values() if v.field in _STOPPING_FIELDS
)
_ACTUAL_VARIABLES = tuple(
    v.name for v in SYSTEM_VARIABLES.values() if not v.writable and v.field is None
)


@dataclass
class _Approximated:
    move: ast.Move
    explicit: bool  # WITH APPROX (not the modal R_APPROX)


def approx_warnings(body: list[ast.Stmt]) -> list[tuple[ast.Node, str, str]]:
    """``(node, message, hint)`` for every statement that ends an approximation."""
    out: list[tuple[ast.Node, str, str]] = []
    modal = False
    pending: _Approximated | None = None
    for s in ast.statements_in_order(body):
        if pending is not None:
            why = _stops(s)
            if why:
                out.append(_warning(s, pending.move, why))
                pending = None
        if isinstance(s, ast.Assign) and _is_name(s.target, _APPROX_VARIABLE):
            modal = _nonzero(s.value)
        if isinstance(s, ast.Move):
            pending = _approximated(s, modal)
        elif isinstance(s, ast.MoveGroup):  # a group is approximated when a part is
            parts = (_approximated(part, modal) for part in s.parts)
            pending = next((a for a in parts if a is not None), None)
    if pending is not None and pending.explicit:
        m = pending.move
        message = "WITH APPROX has no effect: the program ends after this motion"
        out.append((m, message, "the last point of a program is reached with an exact stop"))
    return out


def _warning(s: ast.Stmt, move: ast.Move, why: str) -> tuple[ast.Node, str, str]:
    return (
        s,
        f"{why} stops the advance run: the approximated motion on line {move.span.line} "
        "ends with an exact stop",
        "write WITH APPROX := 0 on that motion to make the exact stop explicit, or move "
        "the statement",
    )


def _approximated(m: ast.Move, modal: bool) -> _Approximated | None:
    for c in m.clauses:
        if c.kind == "APPROX":
            return _Approximated(m, True) if _nonzero(c.args[0]) else None
    return _Approximated(m, False) if modal else None


def _stops(s: ast.Stmt) -> str | None:
    """Why ``s`` stops the advance run after an approximated motion (None: it does
    not)."""
    name = type(s).__name__
    if isinstance(s, ast.Wait | ast.WaitFor | ast.Pause | ast.Halt):
        return {"Wait": "WAIT", "WaitFor": "WAIT FOR", "Pause": "PAUSE", "Halt": "HALT"}[name]
    if isinstance(s, ast.Reconfigure):
        return "RECONFIGURATION"
    if isinstance(s, ast.Assign) and isinstance(s.target, ast.Name | ast.Field):
        name = _variable_name(s.target)
        if name in _STOPPING_VARIABLES:
            return f"changing {name}"
    if isinstance(s, ast.ModalOn | ast.ModalOff):
        return f"switching {s.option} {'on' if isinstance(s, ast.ModalOn) else 'off'}"
    for e in _own_exprs(s):
        for node in _walk(e):
            if isinstance(node, ast.Input):
                return "reading an input (IN[…])"
            if isinstance(node, ast.Name | ast.Field) and _variable_name(node) in _ACTUAL_VARIABLES:
                return f"reading {_variable_name(node)}"
    return None


def _variable_name(e: ast.Name | ast.Field) -> str:
    """The system variable ``e`` may be: ``R_TOOL`` or a robot's ``holder.R_TOOL`` (a Field
    the checker marked); '' for another field."""
    if isinstance(e, ast.Name):
        return e.name.upper()
    return e.sym.name if e.sym is not None else ""


def _own_exprs(s: ast.Stmt) -> list[ast.Expr]:
    """The expressions a statement evaluates itself (not those of nested bodies)."""
    if isinstance(s, ast.If):
        return [cond for cond, _ in s.arms]
    if isinstance(s, ast.While | ast.Repeat):
        return [s.cond]
    if isinstance(s, ast.Case):
        return [s.selector]
    if isinstance(s, ast.For):
        return [e for e in (s.start, s.stop, s.step) if e is not None]
    out = []
    for f in fields(s):
        v = getattr(s, f.name)
        if isinstance(v, ast.Expr):
            out.append(v)
        elif isinstance(v, list):
            out += [x for x in v if isinstance(x, ast.Expr)]
            for x in v:
                if isinstance(x, ast.WithClause):
                    out += x.args
    return out


def _walk(e: object) -> Iterator[object]:
    if not isinstance(e, ast.Node):
        return
    yield e
    for f in fields(e):
        if f.name in ("span", "ty", "const"):
            continue
        v = getattr(e, f.name)
        items = v if isinstance(v, list | tuple) else [v]
        for x in items:
            if isinstance(x, tuple):
                for y in x:
                    yield from _walk(y)
            else:
                yield from _walk(x)


def _is_name(e: ast.Expr, name: str) -> bool:
    return isinstance(e, ast.Name) and e.name.upper() == name


def _nonzero(e: ast.Expr) -> bool:
    """A constant 0 switches approximation off; anything else (a non-constant) on."""
    const = getattr(e, "const", None)  # a folded constant: irdata.Value(type, (v,))
    data = getattr(const, "data", None)
    value = data[0] if isinstance(data, tuple) and len(data) == 1 else None
    if value is None and isinstance(e, ast.Num):
        value = e.value
    return not (isinstance(value, int | float) and not isinstance(value, bool) and value == 0)
