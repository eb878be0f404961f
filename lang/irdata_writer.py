"""IRDATA code → the ``.ird`` text (``docs/irdata.md``): numbered records, jump targets as
``@<record>``, a comment naming each operand's constant, variable or routine. Deterministic:
the same code gives the same bytes."""

from __future__ import annotations

import re

from irlc.lang.irdata_model import MAGIC, Code, Instruction, Operand, Routine, Slot, Target, Value
from irlc.lang.irdata_robots import instruction_robots


def _num(v: float | int) -> str:
    if isinstance(v, bool):
        return "TRUE" if v else "FALSE"
    if isinstance(v, int):
        return str(v)
    return repr(float(v))


# The characters str.splitlines() breaks a line at: a string holding one is written in the
# escaped form E'…', where each of them is \uXXXX and a backslash is \\ (docs/irdata.md).
_LINE_BREAKS = "\n\r\x0b\x0c\x1c\x1d\x1e\x85\u2028\u2029"
_NEEDS_ESCAPE = re.compile(f"[{_LINE_BREAKS}]")
_ESCAPED = re.compile(f"[\\\\{_LINE_BREAKS}]")


def _quote(s: str) -> str:
    """``'text'`` (a quote doubled), or ``E'text'`` with escapes when a line break is in it."""
    body = s.replace("'", "''")
    if not _NEEDS_ESCAPE.search(s):
        return "'" + body + "'"
    return "E'" + _ESCAPED.sub(lambda m: _escape(m.group()), body) + "'"


def _escape(ch: str) -> str:
    return "\\\\" if ch == "\\" else f"\\u{ord(ch):04x}"


def format_value(v: Value) -> str:
    if v.type in ("STRING", "CHAR"):
        return f"{v.type} {_quote(v.data[0])}"
    if v.type == "BOOLEAN":
        return f"BOOLEAN {'TRUE' if v.data[0] else 'FALSE'}"
    return " ".join([v.type, *(_num(x) for x in v.data)])


def _short_value(v: Value) -> str:
    text = format_value(v).split(" ", 1)[1] if v.data else ""
    return text if len(text) <= 48 else text[:45] + "..."


def _slot(s: Slot) -> str:
    return f"{'VAR ' if s.by_ref else ''}{s.type} {s.name}"


def _header_records(code: Code, entry_recno) -> list[str]:
    recs = [f"PROGRAM {code.program}", f"SOURCE {_quote(code.source)}"]
    for robot in code.robots:
        name = robot.robot if _is_word(robot.robot) else _quote(robot.robot)
        at = "" if robot.at is None else " AT " + " ".join(_num(x) for x in robot.at)
        recs.append(f"ROBOT {robot.var} {name} {robot.joint_count} {robot.joint_kinds}{at}")
        recs.append("JOINTS " + " ".join(robot.joint_names))
    recs.append("UNITS mm deg s")
    recs += [f"DATALIST {name} {_quote(path)}" for name, path in code.datalists]
    recs += [f"CONST {k} {format_value(v)}" for k, v in enumerate(code.consts)]
    for o in code.obstacles:
        parts = [f"OBSTACLE {o.name} {o.kind}"]
        parts += [f"{key} " + " ".join(_num(x) for x in vals) for key, vals in o.fields]
        recs.append(" ".join(parts))
    for n in sorted(code.inputs):
        events = " ".join(f"{_num(float(t))} {'TRUE' if v else 'FALSE'}" for t, v in code.inputs[n])
        recs.append(f"INPUT {n} {events}".rstrip())
    for t in code.types:
        recs.append(f"TYPE {t.index} RECORD " + " ".join(f"{n}:{ty}" for n, ty in t.fields))
    recs += [f"GLOBAL {g.index} {g.type} {g.name}" for g in code.globals]
    for r in code.routines:
        recs.append(
            f"ROUTINE {r.index} {r.name} {r.kind} {len(r.params)} {len(r.locals)} "
            f"@{entry_recno(r.entry)}"
        )
        recs += [f"PARAM {r.index} {p.index} {_slot(p)}" for p in r.params]
        recs += [f"LOCAL {r.index} {s.index} {s.type} {s.name}" for s in r.locals]
    recs.append("CODE")
    return recs


def _is_word(s: str) -> bool:
    return re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", s) is not None


def _comment(code: Code, ins: Instruction, routine: Routine | None) -> str:
    op, a = ins.op, ins.args
    if op in ("PUSHC",) and 0 <= a[0] < len(code.consts):
        return _short_value(code.consts[a[0]])
    if op in ("PUSHG", "POPG", "REFG", "SIGOUT") and 0 <= a[0] < len(code.globals):
        return code.globals[a[0]].name
    if op in ("PUSHL", "POPL", "REFL") and routine is not None:
        slots = routine.params + routine.locals
        if 0 <= a[0] < len(slots):
            return slots[a[0]].name
    if op == "CALL" and 0 <= a[0] < len(code.routines):
        return code.routines[a[0]].name
    robots = code.robots
    named = [robots[k].var for k in instruction_robots(op, a) if k < len(robots)]
    return ", ".join(named)


def write_code(code: Code) -> str:
    """Serialise ``code`` to the IRDATA text format (deterministic)."""
    header_len = len(_header_records(code, lambda i: 0))
    first_code_recno = header_len + 1

    def recno(index: int) -> int:
        return first_code_recno + index

    lines = [MAGIC, f"; irlc IRDATA code of program {code.program}"]
    n = 0
    for rec in _header_records(code, recno):
        n += 1
        lines.append(f"{n} {rec}")
    owner = _routine_of_instruction(code)
    for i, ins in enumerate(code.code):
        n += 1
        ops = [_operand(a, recno) for a in ins.args]
        text = " ".join([str(n), f"L{ins.line}", ins.op, *ops])
        comment = _comment(code, ins, owner[i])
        lines.append(f"{text} ; {comment}" if comment else text)
    return "\n".join(lines) + "\n"


def _operand(a: Operand, recno) -> str:
    if isinstance(a, Target):
        return f"@{recno(a.index)}"
    return str(a)


def _routine_of_instruction(code: Code) -> list[Routine | None]:
    """The routine each instruction belongs to (routines are laid out contiguously)."""
    owner: list[Routine | None] = [None] * len(code.code)
    starts = sorted(code.routines, key=lambda r: r.entry)
    for k, r in enumerate(starts):
        end = starts[k + 1].entry if k + 1 < len(starts) else len(code.code)
        for i in range(r.entry, end):
            owner[i] = r
    return owner
