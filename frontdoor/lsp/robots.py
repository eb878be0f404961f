"""Hover texts about robots: a robot of the library, a robot of the program by its name,
a robot's own system variables, and joint values against the robot they are used with.

A robot's name in a cell (``ROBOT holder := as6 AT (…)``, ``MOVE holder …``, ``FOR holder``,
``holder.R_TOOL``) shows the robot it stands for: its library name or file, its joint count
and its placement (``AT``: mm and ZYX degrees, as written), then the robot's joints with
their limits — the table of a robot of the library (:func:`robot_text`). A joint tuple used
with a robot (``MOVE holder PTP k``, ``JOINTLIMIT lo, hi FOR holder``, ``FK(holder, k)``)
is shown joint by joint in that robot's joint names and units, and a MAIN_JOINT value
outside the robot's position range is named (the compiler counts the values; their range
is checked when the program runs).
"""

from __future__ import annotations

from pathlib import Path

from irlc.lang import types as T
from irlc.lang.cell import ROBOT_VARIABLES, ProgramRobot
from irlc.lang.irdata import Value
from irlc.runtime import units

VERTICAL_MEANING = (
    "**WITH VERTICAL** — the working robot's tool z axis stays vertical in the cell (two "
    "orientation rows of the common joint problem). It must be vertical when COOPERATE "
    "starts: the rows hold the axis, they do not turn it."
)

ROBOT_VARIABLE_MEANINGS = {
    "R_TOOL": "its tool: the TCP in the flange frame (mm, deg ZYX)",
    "R_BASE": "its program base frame (mm, deg ZYX): its MOVE poses are in it",
    "R_ACT_POSE": "its actual TCP pose, in the frame its MOVE poses are in (mm, deg ZYX)",
    "R_ACT_JOINT": "its actual joint values (deg | mm per joint)",
}
assert set(ROBOT_VARIABLE_MEANINGS) == set(ROBOT_VARIABLES)


def load_model(text: str, program: Path, allow_any_path: bool):
    """The robot file ``text`` names, as the compiler resolves it; a message if it fails."""
    from irlc.robots import RobotFileError, resolve_robot

    try:
        return resolve_robot(text, program.parent, restricted=not allow_any_path)
    except RobotFileError as e:
        return f"robot `{text}`: cannot be used: {e}"


def robot_text(name: str, program: Path, allow_any_path: bool, names=()) -> str:
    """The robot's joints: program and file names, units, position / speed / acceleration
    limits in program units."""
    model = load_model(name, program, allow_any_path)
    if isinstance(model, str):
        return model
    rows = [
        f"**{model.name}** — {model.description}" if model.description else f"**{model.name}**",
        "",
        f"{model.n} joints (deg: revolute, mm: prismatic; speeds /s, accelerations /s²)",
        "",
        "| joint | in file | unit | position | speed | accel |",
        "|---|---|---|---|---|---|",
    ]
    names = tuple(names) if len(names) == model.n else default_names(model.n)
    for i, j in enumerate(model.joints):
        lim = j.limits
        rows.append(
            f"| {names[i]} | {j.name} | {units.joint_unit(j.kind)} | "
            f"{_range(lim.position, j.kind)} | {_range(lim.speed, j.kind)} | "
            f"{_range(lim.accel, j.kind)} |"
        )
    return "\n".join(rows)


def default_names(n: int) -> tuple[str, ...]:
    return tuple(f"a{i}" for i in range(1, n + 1))


def robot_joint_names(robot: ProgramRobot, program_names: tuple[str, ...]) -> tuple[str, ...]:
    """The names of ``robot``'s joints in the program: the program's (a MAIN_JOINT record)
    when it has that many, else ``a1 … aN``."""
    return program_names if len(program_names) == robot.n else default_names(robot.n)


def placement_text(robot: ProgramRobot) -> str:
    """``AT (x, y, z mm; a, b, c deg ZYX)``, or where a robot without ``AT`` is."""
    if robot.at is None:
        return "at the cell frame (no AT)"
    x, y, z, a, b, c = (_number(v) for v in robot.at)
    return f"AT ({x}, {y}, {z} mm; {a}, {b}, {c} deg ZYX) in the cell frame"


def cell_robot_text(
    robot: ProgramRobot,
    robots: list[ProgramRobot],
    program_names: tuple[str, ...],
    program: Path,
    allow_any_path: bool,
) -> str:
    """A robot of the program by its name: what it is, where it stands, its joints."""
    line = robot.clause.var_span.line if robot.clause and robot.clause.var_span else None
    where = f" (ROBOT clause on line {line})" if line else ""
    role = f"robot {robot.index + 1} of {len(robots)} of the cell" if len(robots) > 1 else (
        "the program's robot")  # fmt: skip
    head = [
        f"**{robot.var}** — {role}{where}",
        "",
        f"- robot: `{robot.text}`, {robot.n} joints",
        f"- placement: {placement_text(robot)}",
        "",
    ]
    names = robot_joint_names(robot, program_names)
    return "\n".join([*head, robot_text(robot.text, program, allow_any_path, names)])


def robot_variable_text(robot: ProgramRobot, name: str, ty) -> str:
    access = "read and written" if name in ("R_TOOL", "R_BASE") else "read-only"
    meaning = ROBOT_VARIABLE_MEANINGS.get(name, "")
    shown = ty if ty is not None else "MAIN_JOINT"
    return (
        f"**{robot.var}.{name}**: {shown} — robot {robot.var}'s own system variable "
        f"({access}): {meaning}"
    )


def joint_values_text(
    v: Value, robot: ProgramRobot, program_names: tuple[str, ...], program: Path,
    allow_any_path: bool,
) -> str | None:  # fmt: skip
    """A joint tuple's values as ``robot``'s joints (names, units) and, for MAIN_JOINT, the
    values outside the robot's position range; ``None`` when ``v`` is not a joint tuple."""
    if v.type not in T.JOINT_TUPLE_TYPES:
        return None
    model = load_model(robot.text, program, allow_any_path)
    head = f"used with robot {robot.var} ({robot.text}, {robot.n} joints)"
    if len(v.data) != robot.n:
        return f"{head}: {len(v.data)} values for {robot.n} joints"
    names = robot_joint_names(robot, program_names)
    if isinstance(model, str):
        return f"{head}: {model}"
    kinds = [j.kind for j in model.joints]
    shown = ", ".join(f"{n} {_number(x)} {units.joint_unit(k)}"
                      for n, x, k in zip(names, v.data, kinds, strict=True))  # fmt: skip
    lines = [f"{head}: {shown}"]
    if v.type == "MAIN_JOINT":
        outside = [
            f"{n} {_number(x)} {units.joint_unit(j.kind)} is outside its range "
            f"{_range(j.limits.position, j.kind)} ({model.name} joint {j.name})"
            for n, x, j in zip(names, v.data, model.joints, strict=True)
            if not _within(float(x), j.limits.position, j.kind)
        ]
        lines += [f"- ⚠ {o}" for o in outside] or [f"- within {model.name}'s joint ranges"]
    return "\n\n".join([lines[0], "\n".join(lines[1:])]) if len(lines) > 1 else lines[0]


def fitting_robots(n: int, robots: list[ProgramRobot]) -> str | None:
    """In a cell of robots with different joint counts: which robots a tuple of ``n``
    values fits (``None`` with one robot or one joint count)."""
    if len({r.n for r in robots}) < 2:
        return None
    fit = [f"{r.var} ({r.text})" for r in robots if r.n == n]
    return f"{n} values: fits robot {', '.join(fit)}" if fit else f"{n} values: fits no robot"


def _within(value: float, bounds: tuple[float, float], kind: str) -> bool:
    lo, hi = (float(b) for b in units.joints_from_si(bounds, [kind] * 2))
    tolerance = 1e-9 * max(1.0, abs(lo), abs(hi))
    return lo - tolerance <= value <= hi + tolerance


def _range(bounds: tuple[float, float], kind: str) -> str:
    lo, hi = (float(v) for v in units.joints_from_si(bounds, [kind] * 2))
    return f"±{hi:.6g}" if f"{-lo:.6g}" == f"{hi:.6g}" else f"{lo:.6g} … {hi:.6g}"


def _number(x) -> str:
    return f"{x:g}" if isinstance(x, float | int) and not isinstance(x, bool) else str(x)
