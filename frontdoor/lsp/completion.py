"""Completion: what may be written at the cursor, each item with its kind.

The text before the cursor on its line picks the context:

* ``WITH …`` — the WITH options: the settings' WITH words (the settings table,
  :mod:`irlc.lang.settings`) and ``JOINTLIMIT``, ``JOINTSPEEDLIMIT``, ``JOINTACCELLIMIT``,
  ``RECONFIGURATION``;
* ``ROBOT r := …`` — the robots of the library; ``IMPORT DATALIST …`` — the data lists
  next to the program and in the library; ``OBSTACLE …`` / ``OBSTACLEEND …`` — the
  obstacles of the imported data lists;
* ``MOVE …``, ``MOVE_INC …``, ``AND …`` in a group move, ``… FOR …`` after a redundancy
  construct, ``COOPERATE …``, ``COOPERATE a IN …`` — the program's robots (a cell's, by
  their names: docs/language.md §10; with one robot after MOVE also the motion kinds);
  ``COOPERATE a IN b WITH …`` — ``VERTICAL``;
* ``name.…`` — the fields of ``name``'s type (a POSE's ``x y z pos ori``, a record's, a
  joint tuple's joints), a robot's own system variables (``holder.R_TOOL``);
* anywhere else — the names in scope (variables, parameters, constants and data-list
  entries, types, procedures and functions, obstacles: the routine's own first), the
  system variables (``R_…``: the settings table's, with unit and range), the built-in
  functions, the statements (as snippets where the client takes them) and the keywords.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from irlc.lang import settings as S
from irlc.lang import types as T
from irlc.lang.builtins import BUILTINS
from irlc.lang.cell import ROBOT_VARIABLES
from irlc.lang.checker import Symbol
from irlc.lang.datalist import folders
from irlc.lang.grammar import keywords
from irlc.lsp.hover import setting_text, signature
from irlc.lsp.index import Index
from irlc.lsp.robots import ROBOT_VARIABLE_MEANINGS, placement_text
from lsprotocol import types

K = types.CompletionItemKind
UNSUPPORTED = {"SYSTEM", "SPECIFICATION", "STANDARD_IN", "STANDARD_OUT", "FROM", "EXPORT"}
WITH_CLAUSES = ("JOINTLIMIT", "JOINTSPEEDLIMIT", "JOINTACCELLIMIT", "RECONFIGURATION")
MOTION_KINDS = ("PTP", "LIN", "LIN PATH", "CIRCLE")
_MOVE = r"\bMOVE(?:_INC)?\b"
_PART_ROBOT = re.compile(r"\b(?:MOVE(?:_INC)?|AND)\s+([A-Za-z_]\w*)\s+(?:PTP|LIN|CIRC)", re.I)
# the constructs that take a FOR robot suffix (docs/language.md §10)
_FOR_ROBOT = re.compile(
    r"\b(?:JOINT(?:SPEED|ACCEL)?LIMIT(?:END)?|CYCLIC(?:START|END)|OBSTACLE(?:END)?"
    r"|FREEZE(?:START|END)|RECONFIGURATION)\b[^;]*\bFOR\s+\w*$", re.I)  # fmt: skip

# label → (snippet, plain text): the statements, as the language reference writes them
STATEMENTS: dict[str, tuple[str, str]] = {
    "MOVE PTP": ("MOVE PTP ${1:target};", "MOVE PTP "),
    "MOVE LIN": ("MOVE LIN ${1:target};", "MOVE LIN "),
    "MOVE LIN PATH": ("MOVE LIN PATH (${1:p1}, ${2:p2});", "MOVE LIN PATH ("),
    "MOVE CIRCLE": ("MOVE CIRCLE ${1:via}, ${2:target};", "MOVE CIRCLE "),
    "MOVE_INC LIN": ("MOVE_INC LIN (${1:0, 0, 0, 0, 0, 0});", "MOVE_INC LIN "),
    "MOVE_INC PTP": ("MOVE_INC PTP (${1:deltas});", "MOVE_INC PTP "),
    "IF … ENDIF": ("IF ${1:condition} THEN\n\t$0\nENDIF;", "IF "),
    "WHILE … ENDWHILE": ("WHILE ${1:condition} DO\n\t$0\nENDWHILE;", "WHILE "),
    "REPEAT … UNTIL": ("REPEAT\n\t$0\nUNTIL ${1:condition};", "REPEAT"),
    "FOR … ENDFOR": ("FOR ${1:i} := ${2:1} TO ${3:10} DO\n\t$0\nENDFOR;", "FOR "),
    "CASE … ENDCASE": ("CASE ${1:selector} OF\n\t${2:1}: $0\nENDCASE;", "CASE "),
    "WAIT … SEC": ("WAIT ${1:1.0} SEC;", "WAIT "),
    "WAIT FOR": ("WAIT FOR ${1:IN[1]};", "WAIT FOR "),
    "WRITELN": ("WRITELN(${1:'text'});", "WRITELN("),
    "OUT[n] :=": ("OUT[${1:1}] := ${2:TRUE};", "OUT["),
    "PULSE": ("PULSE(OUT[${1:1}], ${2:0.5});", "PULSE(OUT["),
    "JOINTLIMIT … JOINTLIMITEND": ("JOINTLIMIT ${1:jmin}, ${2:jmax};\n$0\nJOINTLIMITEND;",
                                   "JOINTLIMIT "),
    "JOINTSPEEDLIMIT … JOINTSPEEDLIMITEND": (
        "JOINTSPEEDLIMIT ${1:jsmin}, ${2:jsmax};\n$0\nJOINTSPEEDLIMITEND;", "JOINTSPEEDLIMIT "),
    "JOINTACCELLIMIT … JOINTACCELLIMITEND": (
        "JOINTACCELLIMIT ${1:jamin}, ${2:jamax};\n$0\nJOINTACCELLIMITEND;", "JOINTACCELLIMIT "),
    "CYCLICSTART … CYCLICEND": ("CYCLICSTART;\n$0\nCYCLICEND;", "CYCLICSTART;"),
    "OBSTACLE … OBSTACLEEND": ("OBSTACLE ${1:name};\n$0\nOBSTACLEEND ${1:name};", "OBSTACLE "),
    "FREEZESTART … FREEZEEND": ("FREEZESTART ${1:1};\n$0\nFREEZEEND;", "FREEZESTART "),
    "RECONFIGURATION": ("RECONFIGURATION ${1:configuration};", "RECONFIGURATION "),
    "PROCEDURE … ENDPROC": ("PROCEDURE ${1:name}();\nBEGIN\n\t$0\nENDPROC;", "PROCEDURE "),
    "FUNCTION … ENDFCT": (
        "FUNCTION ${1:name}(${2:REAL: x}): ${3:REAL};\nBEGIN\n\tRETURN $0;\nENDFCT;", "FUNCTION "),
}  # fmt: skip

SYMBOL_KINDS = {
    "var": K.Variable,
    "param": K.Variable,
    "const": K.Constant,
    "type": K.Struct,
    "robot": K.Module,
    "obstacle": K.Value,
}


@dataclass(frozen=True)
class Context:
    """Where the cursor is: the program's file, the text before it on its line, its line."""

    program: Path
    before: str
    line: int
    datalist_path: tuple[str, ...] = ()
    snippets: bool = False  # the client takes snippets
    markdown: bool = False  # the client takes Markdown documentation


def complete(context: Context, index: Index | None) -> list[types.CompletionItem]:
    before = context.before
    if (robots := robot_context(before, index)) is not None:
        return robots
    if re.search(r"\bWITH\s+\w*$", before, re.I):
        return with_options(context.markdown)
    if re.search(r"\bROBOT\s+\w+\s*:=\s*\w*$", before, re.I):
        return robot_names()
    if re.search(r"\bIMPORT\s+DATALIST\s+\w*$", before, re.I):
        return datalist_names(context)
    if re.search(r"\bOBSTACLE(END)?\s+\w*$", before, re.I):
        return _names(index, context.line, kinds=("obstacle",))
    if m := re.search(r"([A-Za-z_]\w*)\s*\.\s*\w*$", before):
        if index is not None and m.group(1).lower() in index.robots:
            return robot_variables(m.group(1))
        return fields(index, context.line, m.group(1))
    return [*_names(index, context.line), *system_variables(context.markdown), *builtins(),
            *statements(context.snippets), *keyword_items()]  # fmt: skip


def robot_context(before: str, index: Index | None) -> list[types.CompletionItem] | None:
    """The items where a robot of the program is named (module doc), else ``None``."""
    if re.search(r"\bCOOPERATE\s+\w+\s+IN\s+\w+\s+WITH\s+\w*$", before, re.I):
        return [
            types.CompletionItem(
                label="VERTICAL",
                kind=K.Keyword,
                detail="the working robot's tool z axis stays vertical",
            )
        ]
    robots = list(index.checked.robots) if index is not None else []
    if m := re.search(r"\bCOOPERATE\s+(?:(\w+)\s+IN\s+)?\w*$", before, re.I):
        worker = (m.group(1) or "").lower()
        return program_robots([r for r in robots if r.var.lower() != worker])
    if _FOR_ROBOT.search(before):
        return program_robots(robots)
    if re.search(_MOVE + r"\s+\w*$", before, re.I):
        if len(robots) > 1:
            return program_robots(robots)
        kinds = [types.CompletionItem(label=k, kind=K.Keyword, sort_text=f"0{k}")
                 for k in MOTION_KINDS]  # fmt: skip
        return kinds + program_robots(robots, rank="1")
    if (m := re.search(_MOVE + r"[^;]*\bAND\s+\w*$", before, re.I)) and len(robots) > 1:
        moving = {name.lower() for name in _PART_ROBOT.findall(m.group(0))}
        return program_robots([r for r in robots if r.var.lower() not in moving])
    return None


def program_robots(robots, rank: str = "0") -> list[types.CompletionItem]:
    """The program's robots by name, each with its robot and placement."""
    return [
        types.CompletionItem(
            label=r.var,
            kind=K.Module,
            sort_text=f"{rank}{r.index:03d}",
            detail=f"robot {r.text} ({r.n} joints) {placement_text(r)}",
        )
        for r in robots
    ]


def robot_variables(robot: str) -> list[types.CompletionItem]:
    """``robot.…``: the robot's own system variables."""
    return [types.CompletionItem(label=v, kind=K.Variable,
                                 detail=f"{robot}.{v}: {ROBOT_VARIABLE_MEANINGS[v]}")
            for v in ROBOT_VARIABLES]  # fmt: skip


def with_options(markdown: bool) -> list[types.CompletionItem]:
    items = [
        types.CompletionItem(
            label=s.with_word,
            kind=K.Property,
            detail=f"{s.meaning} [{s.unit}] {s.range.interval()}".replace(" []", ""),
            documentation=_documentation(setting_text(s, with_form=True), markdown),
            insert_text=f"{s.with_word} := ",
            sort_text=f"0{s.with_word}",
        )
        for s in S.SETTINGS
        if s.with_word
    ]
    items += [
        types.CompletionItem(label=w, kind=K.Keyword, insert_text=f"{w} ", sort_text=f"1{w}")
        for w in WITH_CLAUSES
    ]
    return items


def robot_names() -> list[types.CompletionItem]:
    from irlc.robots import list_robots

    return [types.CompletionItem(label=n, kind=K.Module, detail="robot of the library")
            for n in list_robots()]  # fmt: skip


def datalist_names(context: Context) -> list[types.CompletionItem]:
    seen: dict[str, str] = {}
    for folder in folders(context.program.parent, context.datalist_path):
        try:
            found = sorted(folder.glob("*.toml"))
        except OSError:
            continue
        for path in found:
            seen.setdefault(path.stem, str(folder))
    return [types.CompletionItem(label=n, kind=K.File, detail=f"data list in {where}")
            for n, where in seen.items() if re.fullmatch(r"[A-Za-z_]\w*", n)]  # fmt: skip


def fields(index: Index | None, line: int, base: str) -> list[types.CompletionItem]:
    sym = index.visible(line).get(base.lower()) if index is not None else None
    ty = sym.type if sym is not None else None
    pairs: list[tuple[str, object]] = []
    if ty in (T.POSITION, T.POSE):
        pairs = [(n, T.REAL) for n in "xyz"]
        if ty == T.POSE:
            pairs += [("pos", T.POSITION), ("ori", T.ORIENTATION)]
    elif isinstance(ty, T.Record):
        pairs = list(ty.fields)
    elif isinstance(ty, T.JointTuple) and index is not None:
        pairs = [(n, T.REAL) for n in index.checked.joint_names]
    return [types.CompletionItem(label=n, kind=K.Field, detail=str(t)) for n, t in pairs]


def _names(index: Index | None, line: int, kinds=None) -> list[types.CompletionItem]:
    if index is None:
        return []
    routine = index.routine_at(line)
    local = routine.symbols if routine is not None else {}
    items = []
    for key, sym in index.visible(line).items():
        if kinds is not None and sym.kind not in kinds:
            continue
        items.append(_symbol_item(sym, "0" if key in local else "1"))
    return items


def _symbol_item(sym: Symbol, rank: str) -> types.CompletionItem:
    if sym.kind == "routine" and sym.routine is not None:
        kind = K.Function if sym.routine.is_function else K.Method
        detail = signature(sym)
    else:
        kind = SYMBOL_KINDS.get(sym.kind, K.Variable)
        detail = f"{sym.type} — {sym.kind}" if sym.type is not None else sym.kind
        if sym.file is not None:
            detail = f"{sym.type} — data list {Path(sym.file).name}"
    return types.CompletionItem(label=sym.name, kind=kind, detail=detail,
                                sort_text=f"{rank}{sym.name.lower()}")  # fmt: skip


def system_variables(markdown: bool) -> list[types.CompletionItem]:
    items = []
    for v in S.SYSTEM_VARIABLES.values():
        setting = S.BY_SYSTEM_VARIABLE.get(v.name)
        if setting is not None:
            detail = f"{setting.meaning} [{setting.unit}] {setting.range.interval()}"
            doc = _documentation(setting_text(setting), markdown)
        else:
            access = "" if v.writable else "read-only "
            detail = f"{v.type_name or 'MAIN_JOINT'} — {access}system variable"
            doc = None
        item = types.CompletionItem(
            label=v.name, kind=K.Variable, sort_text=f"2{v.name}",
            detail=detail.replace(" []", ""), documentation=doc,
        )  # fmt: skip
        items.append(item)
    return items


def builtins() -> list[types.CompletionItem]:
    names = [*BUILTINS, "POSE"]
    return [types.CompletionItem(label=n, kind=K.Function, detail="built-in function",
                                 insert_text=f"{n}(", sort_text=f"3{n}")
            for n in names]  # fmt: skip


def statements(snippets: bool) -> list[types.CompletionItem]:
    fmt = types.InsertTextFormat.Snippet if snippets else types.InsertTextFormat.PlainText
    return [types.CompletionItem(label=label, kind=K.Snippet if snippets else K.Keyword,
                                 detail="statement", insert_text=snippet if snippets else plain,
                                 insert_text_format=fmt, sort_text=f"4{label}")
            for label, (snippet, plain) in STATEMENTS.items()]  # fmt: skip


def keyword_items() -> list[types.CompletionItem]:
    return [types.CompletionItem(label=w, kind=K.Keyword, sort_text=f"5{w}")
            for w in sorted(keywords() - UNSUPPORTED)]  # fmt: skip


def _documentation(text: str, markdown: bool) -> types.MarkupContent | str:
    """Markdown where the client takes it, else the same text as plain text."""
    return types.MarkupContent(kind=types.MarkupKind.Markdown, value=text) if markdown else text
