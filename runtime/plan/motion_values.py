"""The settings one motion runs with, each checked once against its row of the table.

For every row of :data:`irlc.lang.settings.SETTINGS` the value of a motion is the
statement's WITH value where it gives one (``WITH SPEED := 100``), else the system
variable's (``R_SPEED``; ``--ipo`` replaces ``R_IPO``). :func:`motion_values` checks each
with :func:`~irlc.lang.settings.setting_message` — the check and the words of the compiler
and the interpreter — and scales it by the program override: ``value·k^p`` with ``k =
R_OVERRIDE / 100`` and ``p`` the row's override exponent (speed ×k, acceleration ×k²,
jerk ×k³, WITH TIME ÷k: the same path in 1/k the time, docs/runtime.md).

The controller resolves them once per motion statement (and per RECONFIGURATION); the
pre-interpolator, the blender and the segment runs read the record and check nothing
again. The interpreter has checked each value when it was set (at its own line); this is
the controller's one check, for controllers driven with hand-made settings.
"""

from __future__ import annotations

from dataclasses import dataclass

from irlc.lang.settings import SETTINGS, SettingChoices, setting_message
from irlc.runtime.commands import MotionCommand, Settings
from irlc.runtime.errors import RunFailure


@dataclass(frozen=True)
class MotionValues:
    """One motion's settings in program units, checked and scaled by the override ``k``
    (the module doc); one field per row of the table, plus ``k``."""

    speed: float  # mm/s, ×k
    acc: float  # mm/s², ×k²
    speed_ori: float  # deg/s, ×k
    speed_ptp: float  # %, ×k
    acc_ptp: float  # %, ×k²
    time: float | None  # s, WITH TIME ÷ k (None: no WITH TIME)
    ipo: float  # s, the IPO cycle
    path_tol: float  # mm
    profile: str  # 'TRAPEZOID' | 'SCURVE'
    jerk: float  # mm/s³, ×k³
    override: float  # %, R_OVERRIDE as set
    approx: float  # mm, the blend distance at the motion's points
    clearance: float  # mm, R_CLEARANCE: the distance kept between links (0: only reported)
    platform: str  # R_PLATFORM: 'FREE' | 'HOLD' (the platform outside WITH PLATFORM)
    criterion: str  # R_CRITERION: 'DISTANCE' | 'ENERGY' | 'MVR' (the IK's criterion)
    k: float  # R_OVERRIDE / 100
    written_time: float | None  # s, WITH TIME as written (messages)

    @property
    def scurve(self) -> bool:
        """``R_PROFILE = 'SCURVE'``: the jerk-limited profile."""
        return self.profile == "SCURVE"


def motion_values(
    cmd: MotionCommand, settings: Settings, ipo: float | None = None, t: float | None = None
) -> MotionValues:
    """The :class:`MotionValues` of ``cmd`` under ``settings`` (``ipo``: ``--ipo``, which
    replaces ``R_IPO``); a value outside its row's range is a :class:`RunFailure` at the
    statement's line (and simulated time ``t``), in the words of the compiler."""
    checked: dict[str, object] = {}
    for row in SETTINGS:
        value = getattr(cmd, row.field, None) if row.with_word else None
        what = f"WITH {row.with_word}"
        if value is None and row.system_variable:
            value, what = getattr(settings, row.field), row.system_variable
            if row.field == "ipo" and ipo is not None:
                value, what = ipo, "--ipo"
        if value is not None:
            message = setting_message(row.field, value, what)
            if message is not None:
                raise RunFailure(message, cmd.line, t)
        checked[row.field] = value
    k = float(checked["override"]) / 100.0
    scaled = {
        row.field: None if checked[row.field] is None else row.scaled(checked[row.field], k)
        for row in SETTINGS
    }
    for row in SETTINGS:  # a word setting in any case: its upper-case word
        if isinstance(row.range, SettingChoices) and scaled[row.field] is not None:
            scaled[row.field] = str(scaled[row.field]).upper()
    time = checked["time"]
    return MotionValues(**scaled, k=k, written_time=None if time is None else float(time))  # type: ignore[arg-type]
