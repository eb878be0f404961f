"""What the REPL shows of one robot: ``:where``, ``:robot``, ``:limits``, ``:options``.

A :class:`RobotView` is a robot as the session sees it between entries — its model, its
joints, its joint naming, the modal options switched on for it and the settings its motions
use (the cell's, with its own ``R_TOOL`` and ``R_BASE``), and its pose as ``R_ACT_POSE``
reads it. The session (:mod:`irlc.repl`) makes one for its robot, or one per robot of a
cell (:mod:`irlc.repl_cell`); the functions here turn a view into lines, the same for both.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from irlc.lang.settings import LIMIT_OPTIONS, SETTINGS
from irlc.robots.model import RobotModel
from irlc.runtime import units, values
from irlc.runtime.commands import ModalOptions, Settings
from irlc.runtime.model.naming import JointNaming
from irlc.runtime.values import Pose


@dataclass
class Entry:
    """The outcome of one REPL entry: what to print and whether it failed (1 compile,
    2 run, 3 a file or usage problem)."""

    lines: list[str] = field(default_factory=list)
    failure: int = 0


@dataclass(frozen=True)
class RobotView:
    """One robot of the session (module doc). ``frame`` says which frame ``pose`` is in
    (empty for a robot alone, whose poses are in its R_BASE frame, as before cells)."""

    name: str  # the program's name for the robot (``r`` for the robot of --robot LIB)
    model: RobotModel
    q: np.ndarray  # SI
    naming: JointNaming
    options: ModalOptions
    settings: Settings
    pose: Pose
    frame: str = ""

    def joints(self) -> list[float]:
        """The joints in program units (deg | mm)."""
        return [float(v) for v in units.joints_from_si(self.q, self.model.joint_kinds)]

    def xyzabc(self) -> list[float]:
        """The pose as x, y, z mm and a, b, c deg ZYX."""
        return [float(v) for v in units.pose_from_si(values.pose_to_matrix(self.pose))]


def fmt(v: float) -> str:
    """Up to 3 decimals, trailing zeros dropped; snapped (:func:`units.fixed`)."""
    text = units.fixed(v, 3).rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def pose_text(values_: list[float]) -> str:
    return "(" + ", ".join(fmt(v) for v in values_) + ")"


def joints_text(view: RobotView) -> str:
    names = view.naming.program
    return "  ".join(f"{n}={fmt(v)}" for n, v in zip(names, view.joints(), strict=True))


def names_line(view: RobotView) -> list[str]:
    """``names a1 (panda_joint1), …`` where the robot file names a joint differently."""
    naming, n = view.naming, view.model.n
    if all(naming.label(j) == naming.name(j) for j in range(n)):
        return []
    return [f"  names  {naming.labels(range(n))}"]


def where_lines(view: RobotView, time: float, short: bool = False) -> list[str]:
    """``t = … s  pose (…)`` and the joints (a robot alone; ``:where``)."""
    prefix = "→ " if short else ""
    return [
        f"{prefix}t = {time:.3f} s  pose {pose_text(view.xyzabc())}  [mm, deg ZYX]",
        f"  joints {joints_text(view)}",
        *([] if short else names_line(view)),
    ]


def cell_where_lines(view: RobotView, indent: str = "  ") -> list[str]:
    """A robot of a cell: ``NAME: pose (…) [mm, deg ZYX, FRAME]`` and its joints."""
    return [
        f"{indent}{view.name}: pose {pose_text(view.xyzabc())}  [mm, deg ZYX, {view.frame}]",
        f"{indent}  joints {joints_text(view)}",
    ]


def cell_lines(robots: list[tuple[str, str, tuple[float, ...]]], current: int) -> list[str]:
    """A cell's robots (name, robot file, placement), the current one marked."""
    out = [f"cell of {len(robots)} robots (* current; :robot NAME selects):"]
    for k, (name, robot, at) in enumerate(robots):
        mark = "*" if k == current else " "
        out.append(f" {mark} {name:12} {robot:12} AT {pose_text(list(at))}  [mm, deg ZYX]")
    return out


def robot_lines(view: RobotView) -> list[str]:
    """``:robot``: the robot's joints, kinds and units, and its tool."""
    m = view.model
    out = [f"robot {m.name}: {m.n} joints  {m.description}".rstrip()]
    for i, j in enumerate(m.joints):
        out.append(f"  {view.naming.label(i):20} {j.kind:9} [{units.joint_unit(j.kind)}]")
    tool = ", ".join(fmt(v) for v in units.pose_from_si(m.tool))
    out.append(f"  tool ({tool}) [mm, deg]; R_TOOL is composed after it")
    return out


def tool_line(view: RobotView) -> str:
    """The active tool: the robot file's, then R_TOOL (mm, deg ZYX)."""

    def pose(t) -> str:
        return pose_text(units.pose_from_si(t))

    file_tool = view.model.tool
    r_tool = values.pose_to_matrix(view.settings.tool)
    return (
        f"R_TOOL {pose(r_tool)} after the robot file's tool {pose(file_tool)}: "
        f"TCP tool {pose(file_tool @ r_tool)}  [mm, deg]"
    )


def limits_lines(view: RobotView) -> list[str]:
    """``:limits``: the robot's joint limits and the active program limits."""
    m, prog, naming = view.model, view.options.joint_limits, view.naming
    width = max(len(naming.label(j)) for j in range(m.n))
    out = [f"{'joint':{width}}  position min..max    speed max    accel max   program position"]
    scale = units.joint_scale(m.joint_kinds)
    for j, joint in enumerate(m.joints):
        name = f"{naming.label(j):{width}}"
        lo, hi = (v / scale[j] for v in joint.limits.position)
        sp = joint.limits.speed[1] / scale[j]
        ac = joint.limits.accel[1] / scale[j]
        p = f"{fmt(prog[0].values[j])}..{fmt(prog[1].values[j])}" if prog else "-"
        unit = units.joint_unit(joint.kind)
        out.append(f"{name:6} {fmt(lo):>9}..{fmt(hi):<9} {fmt(sp):>8} {fmt(ac):>12}"
                   f"   {p}  [{unit}]")  # fmt: skip
    return out


def options_lines(view: RobotView) -> list[str]:
    """``:options``: the active modal options, then every setting of the table
    (lang/settings.py) and the tool."""
    o = view.options
    out = []
    for option in LIMIT_OPTIONS:
        pair = getattr(o, option.field)
        if pair:
            lo = ", ".join(fmt(v) for v in pair[0].values)
            hi = ", ".join(fmt(v) for v in pair[1].values)
            out.append(f"{option.word} min ({lo}) max ({hi})")
    if o.cyclic_reference is not None:
        out.append("CYCLIC reference (" + ", ".join(fmt(v) for v in o.cyclic_reference) + ")")
    for name in o.obstacles:
        out.append(f"OBSTACLE {name}")
    if o.frozen:
        frozen = ", ".join(f"{view.naming.name(j)}={fmt(v)}" for j, v in sorted(o.frozen.items()))
        out.append(f"FREEZE {frozen}")
    active = bool(out)
    out += settings_lines(view.settings)
    out.append(tool_line(view))
    return out if active else ["no modal options active", *out]


def settings_lines(settings, width: int = 88) -> list[str]:
    """The system variables of the settings table (lang/settings.py), one ``NAME value
    unit`` each, in the table's order, as lines of at most ``width`` characters."""
    items = []
    for row in SETTINGS:
        if row.system_variable:
            value = getattr(settings, row.field)
            shown = value if isinstance(value, str) else f"{value:g}"
            items.append(f"{row.system_variable} {shown}{' ' + row.unit if row.unit else ''}")
    lines = [items[0]]
    for item in items[1:]:
        if len(lines[-1]) + 2 + len(item) <= width:
            lines[-1] += "  " + item
        else:
            lines.append(item)
    return lines
