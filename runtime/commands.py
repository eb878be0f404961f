"""The interface between the interpreter and the simulated robot controller.

The interpreter executes IRDATA code and hands over one :class:`MotionCommand` per
motion statement, together with the current :class:`Settings` (system variables) and
:class:`ModalOptions` (the redundancy options switched on by START/END records). The
controller (pre-interpolator → interpolator → inverse transformation → recorder)
executes it synchronously, advancing simulated time, and raises
:class:`~irlc.runtime.errors.RunFailure` when the motion is impossible.

Everything here is in program units (mm, deg, s; joints deg | mm); the controller
converts to SI with :mod:`irlc.runtime.units`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Protocol

from irlc.lang.settings import BY_FIELD, setting_message
from irlc.lang.settings import SETTING_RANGES as SETTING_RANGES
from irlc.lang.settings import SettingRange as SettingRange
from irlc.lang.settings import setting_error as setting_error
from irlc.runtime.errors import RunFailure
from irlc.runtime.values import IDENTITY, JointTuple, Pose, Position

WAIT_SAMPLED_CYCLES = 1000
"""A WAIT records one sample per IPO cycle for this many cycles, then only its last cycle:
the robot stands still, and a long WAIT must not fill the memory with equal samples. The
endless-loop guard charges a WAIT for these recorded cycles only."""


@dataclass(frozen=True)
class MotionCommand:
    kind: str  # PTP LIN CIRCLE LINPATH PTPINC LININC (see docs/irdata.md)
    targets: tuple  # Pose | JointTuple(MAIN_JOINT) per point; deltas for *INC
    line: int
    speed: float | None = None  # mm/s
    acc: float | None = None  # mm/s²
    speed_ori: float | None = None  # deg/s
    speed_ptp: float | None = None  # % of each joint's max speed
    acc_ptp: float | None = None  # % of each joint's max acceleration
    time: float | None = None  # s, fixed motion time
    approx: float | None = None  # mm, WITH APPROX (blend distance at the points)
    joint_limits: tuple[JointTuple, JointTuple] | None = None  # WITH JOINTLIMIT min, max
    speed_limits: tuple[JointTuple, JointTuple] | None = None
    accel_limits: tuple[JointTuple, JointTuple] | None = None
    reconfiguration: tuple[JointTuple, ...] | None = None  # one, or one per point
    platform_target: tuple[float, ...] | None = None  # WITH PLATFORM: mm, per coordinate
    call: tuple[str, int] | None = None  # in a routine: (its name, the line of its call)


def _default(name: str) -> float:
    value = BY_FIELD[name].default
    assert isinstance(value, float), name
    return value


def _default_word(name: str) -> str:
    value = BY_FIELD[name].default
    assert isinstance(value, str), name
    return value


@dataclass
class Settings:
    """System variables (defaults for later motion); start values from lang/settings.py."""

    speed: float = _default("speed")  # R_SPEED, mm/s
    acc: float = _default("acc")  # R_ACC, mm/s²
    speed_ori: float = _default("speed_ori")  # R_SPEED_ORI, deg/s
    speed_ptp: float = _default("speed_ptp")  # R_SPEED_PTP, %
    acc_ptp: float = _default("acc_ptp")  # R_ACC_PTP, %
    tool: Pose = field(default_factory=lambda: Pose(Position(0.0, 0.0, 0.0), IDENTITY))
    base: Pose = field(default_factory=lambda: Pose(Position(0.0, 0.0, 0.0), IDENTITY))
    ipo: float = _default("ipo")  # R_IPO, s
    path_tol: float = _default("path_tol")  # R_PATH_TOL, mm (start: --path-tolerance)
    profile: str = _default_word("profile")  # R_PROFILE: 'TRAPEZOID' | 'SCURVE'
    jerk: float = _default("jerk")  # R_JERK, mm/s³ (S-curve path jerk)
    override: float = _default("override")  # R_OVERRIDE, % (start: --override)
    approx: float = _default("approx")  # R_APPROX, mm (0: exact stop)
    clearance: float = _default("clearance")  # R_CLEARANCE, mm (0: only reported)
    platform: str = _default_word("platform")  # R_PLATFORM: 'FREE' | 'HOLD'
    criterion: str = _default_word("criterion")  # R_CRITERION: 'DISTANCE' | 'ENERGY' | 'MVR'


# The range table of the numeric settings is lang/settings.py (one row per setting; the
# checker reads the same rows for constants). Re-exported here for the runtime.


def check_setting(field_name: str, value: float, what: str) -> float:
    """``value`` if admissible for the setting ``field_name`` (see ``SETTING_RANGES``),
    else :class:`RunFailure` ``"<what> := <value>: the value must be …"``."""
    message = setting_message(field_name, value, what)
    if message is not None:
        raise RunFailure(message)
    return value


@dataclass
class ModalOptions:
    """Redundancy options switched on by the START records of the code."""

    joint_limits: tuple[JointTuple, JointTuple] | None = None
    speed_limits: tuple[JointTuple, JointTuple] | None = None
    accel_limits: tuple[JointTuple, JointTuple] | None = None
    cyclic_reference: tuple[float, ...] | None = None  # joints at CYCLICSTART
    obstacles: tuple[str, ...] = ()  # active obstacle names, in order of activation
    frozen: dict[int, float] = field(default_factory=dict)  # 0-based joint → value


@dataclass(frozen=True)
class RobotMotion:
    """One robot's part of a cell's motion statement (``MOVE holder LIN p AND welder PTP
    j``): the robot (its ``ROBOT:k`` index) and its command."""

    robot: int
    command: MotionCommand


class Controller(Protocol):
    """What the interpreter needs from the simulated robot."""

    @property
    def time(self) -> float: ...

    def joints(self) -> tuple[float, ...]:
        """Current commanded joints (R_ACT_JOINT)."""

    def pose(self, settings: Settings) -> Pose:
        """Current commanded TCP pose (R_TOOL applied) in the R_BASE frame (R_ACT_POSE)."""

    def forward(self, joints: JointTuple, settings: Settings) -> Pose:
        """FK built-in: TCP pose of ``joints`` in the R_BASE frame."""

    def move(self, cmd: MotionCommand, settings: Settings, options: ModalOptions) -> None: ...

    def reconfigure(
        self, target: JointTuple, line: int, settings: Settings, options: ModalOptions
    ) -> None: ...

    def wait(self, seconds: float, line: int, settings: Settings, options: ModalOptions) -> None:
        """Stand still for ``seconds`` of simulated time (samples are still recorded)."""

    def check_switch_on(
        self, option: str, line: int, settings: Settings, options: ModalOptions
    ) -> None:
        """Optional: called right after OBSTACLE or FREEZESTART is switched on, so that an
        impossible option (arm already inside the obstacle, too few free joints) fails at
        its own statement. Controllers without it are checked at the next motion."""

    def flush(self, reason: str) -> None:
        """Optional: the advance run stops here (WAIT, WAIT FOR, an input or R_ACT_*
        read, an option switched, the end of the program): a pending approximated motion
        ends with an exact stop at its point; ``reason`` is reported with the point.
        Controllers without approximate positioning need not have it."""

    def log_event(self, kind: str, line: int, **data) -> None:
        """Signals, PAUSE, HALT and other timestamped events for the report."""


class CellController(Protocol):
    """What the interpreter needs from a cell of several robots (code with several
    ``ROBOT`` records, docs/irdata.md "Cells"). Where a method of :class:`Controller` takes
    ``settings, options``, this one takes every robot's: ``settings[k]`` are the cell's
    settings with robot ``k``'s own tool and base (``R_TOOL``, ``R_BASE``),
    ``options[k]`` the redundancy options switched on for robot ``k``; ``robot`` is the
    ``ROBOT:k`` operand of the instruction."""

    @property
    def time(self) -> float: ...

    def joints(self, robot: int) -> tuple[float, ...]:
        """Robot ``robot``'s commanded joints (``robot.R_ACT_JOINT``)."""

    def pose(
        self, settings: Sequence[Settings], options: Sequence[ModalOptions], robot: int
    ) -> Pose:
        """Its TCP in the frame its MOVE poses are in (``robot.R_ACT_POSE``)."""

    def forward(
        self,
        joints: JointTuple,
        settings: Sequence[Settings],
        options: Sequence[ModalOptions],
        robot: int,
    ) -> Pose:
        """``FK(robot, joints)`` in the same frame."""

    def move_group(
        self,
        parts: Sequence[RobotMotion],
        settings: Sequence[Settings],
        options: Sequence[ModalOptions],
    ) -> None:
        """A motion statement: one part, or a group move's parts (start and end together)."""

    def reconfigure(
        self,
        target: JointTuple,
        line: int,
        settings: Sequence[Settings],
        options: Sequence[ModalOptions],
        robot: int,
    ) -> None: ...

    def wait(
        self,
        seconds: float,
        line: int,
        settings: Sequence[Settings],
        options: Sequence[ModalOptions],
    ) -> None:
        """Every robot stands still for ``seconds``."""

    def check_switch_on(
        self,
        option: str,
        line: int,
        settings: Sequence[Settings],
        options: Sequence[ModalOptions],
        robot: int,
    ) -> None: ...

    def cooperate(
        self,
        worker: int,
        holder: int,
        vertical: bool,
        line: int,
        settings: Sequence[Settings],
        options: Sequence[ModalOptions],
    ) -> None:
        """``COOPERATE worker IN holder [WITH VERTICAL]``: from now on the worker's poses
        are in the holder's tool frame and their motions one chain."""

    def end_cooperation(self, worker: int, holder: int, line: int) -> None:
        """``COOPERATEEND``."""

    def flush(self, reason: str) -> None: ...

    def log_event(self, kind: str, line: int, **data) -> None: ...
