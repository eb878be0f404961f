"""Hover texts (Markdown): what a name at the cursor is.

A setting (``R_SPEED``, ``WITH SPEED``): its meaning, unit, admissible values and start
value, from the one settings table (:mod:`irlc.lang.settings`). A variable, parameter or
constant: its type (and a constant's value); a data-list entry: its value and where it is
taught; a routine: its signature; an obstacle: its shape; the ``ROBOT`` clause: the robot's
joints with their units and limits (:mod:`irlc.robots`); a robot's name in a cell, its own
variables and joint values used with it (:mod:`irlc.lsp.robots`).
"""

from __future__ import annotations

from pathlib import Path

from irlc.lang import platform
from irlc.lang import settings as S
from irlc.lang.cell import ProgramRobot
from irlc.lang.checker import Symbol
from irlc.lang.irdata import Value
from irlc.lang.types import Record
from irlc.lsp import robots
from irlc.lsp.index import (
    CellRobotRef,
    DatalistRef,
    Index,
    LabelRef,
    OptionRef,
    RobotRef,
    RobotVariableRef,
    SymbolRef,
    Target,
    ValueRef,
)


def hover_text(
    target: Target, index: Index, program: Path, allow_any_path: bool,
    robot: ProgramRobot | None = None,
) -> str | None:  # fmt: skip
    """What ``target`` is; ``robot``: the robot its value is used with (a joint tuple's)."""
    if isinstance(target, SymbolRef):
        text = symbol_text(target.symbol, index)
        value = target.symbol.value
        if robot is not None and value is not None and target.symbol.kind != "sysvar":
            names = index.checked.joint_names
            used = robots.joint_values_text(value, robot, names, program, allow_any_path)
            text += f"\n\n{used}" if used else ""
        return text
    if isinstance(target, CellRobotRef):
        return robots.cell_robot_text(
            target.robot, index.checked.robots, index.checked.joint_names, program,
            allow_any_path,
        )  # fmt: skip
    if isinstance(target, RobotVariableRef):
        return robots.robot_variable_text(target.robot, target.name, target.type)
    if isinstance(target, OptionRef):
        if target.word == platform.WORD:
            return platform.MEANING
        if target.word == "VERTICAL":
            return robots.VERTICAL_MEANING
        setting = S.BY_WITH_WORD.get(target.word)
        return setting_text(setting, with_form=True) if setting else None
    if isinstance(target, RobotRef):
        return robots.robot_text(target.name, program, allow_any_path, index.checked.joint_names)
    if isinstance(target, DatalistRef):
        return datalist_text(target.name, index)
    if isinstance(target, LabelRef):
        where = f" (line {target.span.line})" if target.span else ""
        return f"label `{target.name}`{where}"
    if isinstance(target, ValueRef):
        return f"`{target.text}`: {target.type}"
    return None


def setting_text(s: S.Setting, with_form: bool = False) -> str:
    """A setting's row of the settings table, in words."""
    title = f"WITH {s.with_word}" if with_form else s.system_variable
    lines = [f"**{title}** — {s.meaning}", ""]
    if s.unit:
        lines.append(f"- unit: {s.unit}")
    lines.append(f"- admissible values: {s.range.interval()}")
    if s.default is not None:
        start = f"'{s.default}'" if isinstance(s.default, str) else f"{s.default:g}"
        lines.append(f"- start value: {start}")
    if s.system_variable and with_form:
        lines.append(f"- for every following motion: `{s.system_variable} := …;`")
    if s.with_word and not with_form:
        lines.append(f"- for one motion: `WITH {s.with_word} := …`")
    if s.kinds:
        kinds = ", ".join(S.KIND_WORDS[k] for k in s.kinds)
        lines.append(f"- WITH {s.with_word} is accepted by: {kinds}")
    return "\n".join(lines)


def symbol_text(sym: Symbol, index: Index) -> str:
    if sym.kind == "sysvar":
        setting = S.BY_SYSTEM_VARIABLE.get(sym.name)
        if setting is not None:
            return setting_text(setting)
        access = "read and written" if sym.writable else "read-only"
        return f"**{sym.name}**: {sym.type} — system variable ({access})"
    if sym.kind == "routine" and sym.routine is not None:
        return f"```irl\n{signature(sym)}\n```\ndeclared on line {_line(sym)}"
    if sym.kind == "obstacle":
        return obstacle_text(sym, index)
    if sym.kind == "robot":
        return f"`{sym.name}`: the robot variable of the ROBOT clause (only a name)"
    if sym.kind == "type":
        shown = type_text(sym.type).removeprefix(f"{sym.name} (").removesuffix(")")
        return f"```irl\nTYPE {sym.name} = {shown}\n```"
    if sym.file is not None:  # a data-list entry
        value = value_text(sym.value, index) if sym.value is not None else "(failed its check)"
        return (
            f"**{sym.name}**: {sym.type} = {value}\n\n"
            f"data list `{Path(sym.file).name}`, key `{sym.where.rpartition('key ')[2]}`"
        )
    what = {"var": "variable", "param": "parameter", "const": "constant"}.get(sym.kind, sym.kind)
    text = f"**{sym.name}**: {type_text(sym.type)} — {what}, declared on line {_line(sym)}"
    if sym.kind == "const" and sym.value is not None:
        text += f"\n\nvalue: {value_text(sym.value, index)}"
    return text


def _line(sym: Symbol) -> str:
    return str(sym.span.line) if sym.span else "?"


def type_text(ty) -> str:
    if isinstance(ty, Record):
        fields = "; ".join(f"{t}: {n}" for n, t in ty.fields)
        return f"{ty.name} (RECORD {fields}; ENDRECORD)"
    return str(ty)


def signature(sym: Symbol) -> str:
    info = sym.routine
    assert info is not None
    params = "; ".join(
        f"{'VAR ' if slot.by_ref else ''}{ty}: {slot.name}"
        for slot, ty in zip(info.params, info.param_types, strict=True)
    )
    head = f"FUNCTION {sym.name}" if info.is_function else f"PROCEDURE {sym.name}"
    result = f": {info.result}" if info.is_function and info.result is not None else ""
    return f"{head}({params}){result};"


def value_text(v: Value, index: Index) -> str:
    """A constant's value in program units; a joint tuple joint by joint."""
    numbers = ", ".join(_number(x) for x in v.data)
    if v.type == "POSE":
        return f"({numbers}) — x, y, z mm; a, b, c deg (ZYX)"
    names = index.checked.joint_names
    if v.type.startswith("MAIN_JOINT") and len(names) == len(v.data):
        pairs = ", ".join(f"{n} {_number(x)}" for n, x in zip(names, v.data, strict=True))
        return f"({numbers})\n\n{pairs} (deg | mm per joint)"
    if v.type.startswith("MAIN_JOINT"):  # a cell of robots with different joint counts
        fit = robots.fitting_robots(len(v.data), index.checked.robots)
        return f"({numbers})" + (f"\n\n{fit}" if fit else "")
    if len(v.data) == 1:
        return _number(v.data[0]) if isinstance(v.data[0], float | int) else repr(v.data[0])
    return f"({numbers})"


def _number(x) -> str:
    return f"{x:g}" if isinstance(x, float | int) and not isinstance(x, bool) else str(x)


def obstacle_text(sym: Symbol, index: Index) -> str:
    o = next((o for o in index.checked.obstacles if o.name.lower() == sym.name.lower()), None)
    if o is None:
        return f"obstacle `{sym.name}`"
    fields = "; ".join(f"{k} ({', '.join(_number(x) for x in v)})" for k, v in o.fields)
    where = f"\n\ndata list `{Path(sym.file).name}`" if sym.file else ""
    return f"**{o.name}**: obstacle, {o.kind} — {fields} (mm, deg){where}"


def datalist_text(name: str, index: Index) -> str:
    dl = next((d for d in index.checked.datalists if d.name.lower() == name.lower()), None)
    if dl is None:
        return f"data list `{name}`"
    sections: dict[str, list[str]] = {}
    for item in dl.items:
        sections.setdefault(item.key.split(".")[0], []).append(item.name)
    if dl.obstacles:
        sections["obstacles"] = [o.name for o, _ in dl.obstacles]
    if dl.inputs:
        sections["inputs"] = [str(n) for n in sorted(dl.inputs)]
    lines = [f"data list `{Path(dl.path).name}` ({dl.shown_path})", ""]
    lines += [f"- {section}: {', '.join(names)}" for section, names in sections.items()]
    return "\n".join(lines)
