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

import math
from dataclasses import dataclass, field
from typing import Protocol

from irlc.runtime.errors import RunFailure
from irlc.runtime.values import IDENTITY, JointTuple, Pose, Position, format_real


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
    joint_limits: tuple[JointTuple, JointTuple] | None = None  # WITH JOINTLIMIT min, max
    speed_limits: tuple[JointTuple, JointTuple] | None = None
    accel_limits: tuple[JointTuple, JointTuple] | None = None
    reconfiguration: tuple[JointTuple, ...] | None = None  # one, or one per point


@dataclass
class Settings:
    """System variables (defaults for later motion)."""

    speed: float = 500.0  # R_SPEED, mm/s
    acc: float = 1000.0  # R_ACC, mm/s²
    speed_ori: float = 45.0  # R_SPEED_ORI, deg/s
    speed_ptp: float = 50.0  # R_SPEED_PTP, %
    acc_ptp: float = 50.0  # R_ACC_PTP, %
    tool: Pose = field(default_factory=lambda: Pose(Position(0.0, 0.0, 0.0), IDENTITY))
    base: Pose = field(default_factory=lambda: Pose(Position(0.0, 0.0, 0.0), IDENTITY))
    ipo: float = 0.01  # R_IPO, s
    path_tol: float = 0.05  # R_PATH_TOL, mm (the run's --path-tolerance sets the start value)


@dataclass(frozen=True)
class SettingRange:
    """Admissible values of a numeric setting: ``(low, high]``, or ``[low, high]`` when
    ``closed``."""

    low: float
    high: float
    unit: str = ""
    closed: bool = False

    def __contains__(self, v: float) -> bool:
        return (self.low <= v if self.closed else self.low < v) and v <= self.high

    def __str__(self) -> str:
        if self.high == math.inf and self.low == 0.0 and not self.closed:
            return "positive"
        left = "[" if self.closed else "("
        return f"in {left}{self.low:g}, {self.high:g}]{' ' + self.unit if self.unit else ''}"


# THE range table of the numeric settings (Settings fields; WITH TIME is a motion's own).
# R_IPO: below 10 µs a run would take millions of cycles per simulated second.
SETTING_RANGES: dict[str, SettingRange] = {
    "speed": SettingRange(0.0, math.inf, "mm/s"),
    "acc": SettingRange(0.0, math.inf, "mm/s²"),
    "speed_ori": SettingRange(0.0, math.inf, "deg/s"),
    "speed_ptp": SettingRange(0.0, 100.0, "%"),
    "acc_ptp": SettingRange(0.0, 100.0, "%"),
    "time": SettingRange(0.0, math.inf, "s"),
    "ipo": SettingRange(1e-5, 1.0, "s", closed=True),
    "path_tol": SettingRange(0.0, math.inf, "mm"),
}


def setting_error(field_name: str, value: object) -> str | None:
    """``None`` if ``value`` is admissible for the setting, else why not
    (``"the value must be in (0, 100] %"``)."""
    allowed = SETTING_RANGES[field_name]
    if isinstance(value, float | int) and not isinstance(value, bool) and value in allowed:
        return None
    return f"the value must be {allowed}"


def check_setting(field_name: str, value: float, what: str) -> float:
    """``value`` if admissible for the setting ``field_name`` (see ``SETTING_RANGES``),
    else :class:`RunFailure` ``"<what> := <value>: the value must be …"``."""
    error = setting_error(field_name, value)
    if error is not None:
        shown = repr(value)
        if isinstance(value, float | int):  # as written in programs unless that rounds it
            shown = format_real(float(value))
            shown = shown if float(shown) == value else f"{value:g}"
        raise RunFailure(f"{what} := {shown}: {error}")
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

    def log_event(self, kind: str, line: int, **data) -> None:
        """Signals, PAUSE, HALT and other timestamped events for the report."""
