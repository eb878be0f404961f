"""The trace's column names: the one owner.

``runtime/outputs/results.py`` builds the trace header from these templates, and the checker
refuses joint names whose columns would coincide with another column of the trace (a
joint called ``a`` gave ``a_deg`` twice: its angle and the TCP's ``a`` angle, and irlc
then misread its own trace). Per joint ``NAME`` of unit ``U`` (``deg`` | ``mm``)::

    NAME_U  NAME_speed_U_s  NAME_accel_U_s2  NAME_cmd_U  NAME_current_A  NAME_motor_rad

besides the fixed ``t_s``, ``line``, the pose ``x_mm … c_deg``, ``path_error_mm``,
``orientation_error_deg``, ``kinetic_energy_j`` (robots with inertials), ``mvr``,
``partial``, ``clearance_OBSTACLE_mm`` per obstacle and ``platform_C_mm`` per platform
coordinate.
Names are compared without regard to case (IRL names are case-insensitive).

A cell's trace (several robots) has ``t_s`` and ``line``, then each robot's columns of a
program of that robot prefixed by its name and ``_`` (:func:`prefixed`: ``holder_a1_deg``,
``welder_x_mm``, ``holder_clearance_wall_mm``), then :data:`CELL_CLEARANCE`; the checker
refuses a cell whose prefixed columns coincide (:func:`first_cell_clash`: a robot ``h``
with a joint ``x_a1`` and a robot ``h_x`` with a joint ``a1`` both give ``h_x_a1_deg``).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

from irlc.lang.joint_kinds import kind_letter

_UNIT = {"R": "deg", "P": "mm"}
_DERIVATIVE = ("", "_s", "_s2")

POSE = ("x_mm", "y_mm", "z_mm", "a_deg", "b_deg", "c_deg")
KINETIC_ENERGY = "kinetic_energy_j"
MVR = "mvr"
FIXED = {
    "t_s": "the time",
    "line": "the program line",
    **{c: f"the TCP's {c[0]}" for c in POSE},
    "path_error_mm": "the path error",
    "orientation_error_deg": "the orientation error",
    KINETIC_ENERGY: "the links' kinetic energy",
    MVR: "the manipulator velocity ratio",
    "partial": "the mark of a failed run",
}
"""The columns every trace has (``partial`` only a failed run's, ``kinetic_energy_j`` only a
robot's with inertials), with what they hold."""


def unit(kind: str, derivative: int = 0) -> str:
    """``deg``, ``deg_s``, ``deg_s2`` / ``mm``, … for a joint ``kind`` (word or letter)."""
    return _UNIT[kind_letter(kind)] + _DERIVATIVE[derivative]


def position(name: str, kind: str) -> str:
    return f"{name}_{unit(kind)}"


def speed(name: str, kind: str) -> str:
    return f"{name}_speed_{unit(kind, 1)}"


def accel(name: str, kind: str) -> str:
    return f"{name}_accel_{unit(kind, 2)}"


def command(name: str, kind: str) -> str:
    """The commanded value beside a drive run's actual one."""
    return f"{name}_cmd_{unit(kind)}"


def current(name: str) -> str:
    return f"{name}_current_A"


def motor(name: str) -> str:
    return f"{name}_motor_rad"


def clearance(obstacle: str) -> str:
    return f"clearance_{obstacle}_mm"


def platform(coordinate: str) -> str:
    """A platform coordinate's column (``platform_x_mm``; robots with a ``[platform]``)."""
    return f"platform_{coordinate}_mm"


PLATFORM = {platform(c): f"the platform's {c}" for c in ("x", "y", "z")}
"""The columns of a robot with a platform (one per coordinate it has)."""


def prefixed(robot: str, column: str) -> str:
    """A column of robot ``robot`` in a cell's trace: ``holder_a1_deg``."""
    return f"{robot}_{column}"


CELL_CLEARANCE = (
    "clearance_mm",
    "clearance_robot_a",
    "clearance_link_a",
    "clearance_robot_b",
    "clearance_link_b",
)
"""A cell's columns after the robots': the smallest distance between links (robots' and
within one, mm) and its pair (robot numbers 0, 1, … in the ROBOT clauses' order; links)."""


def robot_columns(names: Sequence[str], kinds: Sequence[str], obstacles: Iterable[str]):
    """Every column a program of one robot can have besides ``t_s`` and ``line``, with
    what it holds (a cell prefixes them)."""
    out = {c: meaning for c, meaning in FIXED.items() if c not in ("t_s", "line", "partial")}
    out.update({clearance(o): f"obstacle {o}'s clearance" for o in obstacles})
    for name, kind in zip(names, kinds, strict=True):
        out.update({c: f"a column of joint '{name}'" for c in joint_columns(name, kind)})
    return out


def first_cell_clash(
    robots: Sequence[tuple[str, Sequence[str], Sequence[str]]], obstacles: Iterable[str] = ()
) -> tuple[int, str, str] | None:
    """``(robot, column, what else is called so)`` for the first robot (0-based, given as
    ``(name, joint names, kinds)``) one of whose prefixed columns another column of a
    cell's trace shares (module doc), or ``None``."""
    obstacles = tuple(obstacles)
    owner = {c.lower(): f"the cell's {c}" for c in ("t_s", "line", "partial", *CELL_CLEARANCE)}
    for r, (robot, names, kinds) in enumerate(robots):
        mine = {
            prefixed(robot, c): what for c, what in robot_columns(names, kinds, obstacles).items()
        }
        for column in mine:
            other = owner.get(column.lower())
            if other is not None:
                return r, column, other
        owner.update({c.lower(): f"{what} of robot {robot}" for c, what in mine.items()})
    return None


def joint_columns(name: str, kind: str) -> tuple[str, ...]:
    """Every column a joint can have (drives and motor maps included)."""
    return (
        position(name, kind),
        speed(name, kind),
        accel(name, kind),
        command(name, kind),
        current(name),
        motor(name),
    )


def first_clash(
    names: Sequence[str], kinds: Sequence[str], obstacles: Iterable[str] = ()
) -> tuple[int, str, str] | None:
    """``(joint, column, what else is called so)`` for the first joint (0-based) one of
    whose columns another column shares, or ``None`` when all are distinct."""
    owner = {c.lower(): meaning for c, meaning in (FIXED | PLATFORM).items()}
    owner.update({clearance(o).lower(): f"obstacle {o}'s clearance" for o in obstacles})
    for j, (name, kind) in enumerate(zip(names, kinds, strict=True)):
        for column in joint_columns(name, kind):
            other = owner.get(column.lower())
            if other is not None:
                return j, column, other
        owner.update({c.lower(): f"a column of joint '{name}'" for c in joint_columns(name, kind)})
    return None
