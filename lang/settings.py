"""The motion settings: one row per setting, read by the checker, the IRDATA reader and the
runtime (interpreter, controller, pre-interpolator).

A numeric setting has a field (of ``runtime.controller.Settings`` and ``MotionCommand``),
a system variable (``R_SPEED := v;``, IRDATA ``PUSHSYS/POPSYS R_SPEED``) with its value
at program start, and/or a WITH word (``WITH SPEED := v``, IRDATA ``MOVE LIN 1 SPEED``), a
unit (program units: mm, deg, s, %), the motion kinds that accept the WITH form, and its
admissible range

    v ∈ (low, high]      or, when ``closed``,      v ∈ [low, high],

and its override exponent ``p``: the program override ``R_OVERRIDE`` scales the motion in
time by ``k = R_OVERRIDE / 100``, so a speed is used as ``v·k``, an acceleration ``v·k²``, a
jerk ``v·k³`` and a motion time ``v/k`` (``v·k^p``; 0: not scaled).

The same range is checked when a constant is compiled (``R_SPEED := -5;`` is a compile
error at its line and column) and when a value is assigned or used at run time (a
the runtime's ``RunFailure`` at its line), with the same words:
``R_SPEED := -5.0: the value must be in (0, 100000] mm/s``. The runtime checks each value
once per motion (``runtime/plan/motion_values.py``), with the same function. A new setting
is one row here plus its behaviour in the controller.

The joint-limit options (``JOINTLIMIT``, ``JOINTSPEEDLIMIT``, ``JOINTACCELLIMIT``) are the
rows of :data:`LIMIT_OPTIONS`: their words, tuple types, the field that holds them and the
derivative they bound; the parser's words, the checker, the IRDATA reader and writer, the
interpreter, the pre-interpolator and the REPL read them from there.

A string setting (``R_PROFILE``) has a :class:`SettingChoices` in place of the range: the
value must be one of its words (any case; ``R_PROFILE := 'scurve'`` is ``'SCURVE'``), and
its system variable is a STRING.

Upper bounds are physical sanity bounds (100 m/s, 1000 m/s², a day for one motion — far
above any robot), not robot limits: the robot's own joint limits apply on top. ``R_IPO``
below 10 µs would need millions of cycles per simulated second.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

KIND_WORDS = {
    "PTP": "MOVE PTP",
    "LIN": "MOVE LIN",
    "CIRCLE": "MOVE CIRCLE",
    "LINPATH": "MOVE LIN PATH",
    "PTPINC": "MOVE_INC PTP",
    "LININC": "MOVE_INC LIN",
}
"""The IRDATA motion kinds and how their statement is written (messages, reports)."""
ALL_KINDS = tuple(KIND_WORDS)  # IRDATA motion kinds
PTP_KINDS = ("PTP", "PTPINC")  # joint interpolation: SPEED_PTP, ACC_PTP (%)
PATH_KINDS = ("LIN", "CIRCLE", "LINPATH", "LININC")  # Cartesian path: SPEED, ACC, SPEED_ORI


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
        return f"in {self.interval()}{' ' + self.unit if self.unit else ''}"

    def interval(self) -> str:
        """``(0, 100]``, ``[1e-05, 1]``, ``(0, ∞)``; a whole upper bound in digits."""
        left = "[" if self.closed else "("
        if self.high == math.inf:
            return f"{left}{self.low:g}, ∞)"
        high = f"{self.high:.0f}" if self.high.is_integer() else f"{self.high:g}"
        return f"{left}{self.low:g}, {high}]"


@dataclass(frozen=True)
class SettingChoices:
    """Admissible values of a string setting: one of ``words`` (upper case; a value is
    compared in upper case)."""

    words: tuple[str, ...]
    unit: str = ""

    def __contains__(self, v: object) -> bool:
        return isinstance(v, str) and v.upper() in self.words

    def __str__(self) -> str:
        return "one of " + self.interval()

    def interval(self) -> str:
        return ", ".join(f"'{w}'" for w in self.words)


@dataclass(frozen=True)
class Setting:
    """One motion setting (see the module doc)."""

    field: str  # Settings / MotionCommand field
    system_variable: str | None  # R_… word (program and IRDATA), None: WITH only
    with_word: str | None  # WITH … word (program and IRDATA MOVE clause), None: no WITH form
    range: SettingRange | SettingChoices  # admissible values, with the unit (program units)
    kinds: tuple[str, ...] = ()  # motion kinds whose WITH form accepts it
    meaning: str = ""
    default: float | str | None = None  # the system variable's value at program start
    override_power: int = 0  # R_OVERRIDE scales the value by k^p (module doc)

    @property
    def unit(self) -> str:
        return self.range.unit

    def scaled(self, value, k: float):
        """``value`` as a motion uses it at override ``k = R_OVERRIDE / 100``: the number
        ``value·k^p`` (``value / k`` for a time), a word as it is."""
        if isinstance(value, str):
            return value
        p = self.override_power
        return float(value) * k**p if p >= 0 else float(value) / k**-p

    @property
    def type_name(self) -> str:
        """The IRL type of its values: STRING for a choice, else REAL."""
        return "STRING" if isinstance(self.range, SettingChoices) else "REAL"


def _positive(unit: str, high: float) -> SettingRange:
    return SettingRange(0.0, high, unit)


# THE table of the settings (with their start values; runtime.commands.Settings reads
# them; the last column: the override exponent p, module doc).
SETTINGS: tuple[Setting, ...] = (
    Setting("speed", "R_SPEED", "SPEED", _positive("mm/s", 1e5), PATH_KINDS,
            "path speed", 500.0, 1),
    Setting("acc", "R_ACC", "ACC", _positive("mm/s²", 1e6), PATH_KINDS,
            "path acceleration", 1000.0, 2),
    Setting("speed_ori", "R_SPEED_ORI", "SPEED_ORI", _positive("deg/s", 1e5), PATH_KINDS,
            "orientation speed", 45.0, 1),
    Setting("speed_ptp", "R_SPEED_PTP", "SPEED_PTP", _positive("%", 100.0), PTP_KINDS,
            "PTP speed, % of each joint's maximum", 50.0, 1),
    Setting("acc_ptp", "R_ACC_PTP", "ACC_PTP", _positive("%", 100.0), PTP_KINDS,
            "PTP acceleration, % of each joint's maximum", 50.0, 2),
    Setting("time", None, "TIME", _positive("s", 86400.0), ALL_KINDS,
            "fixed motion time (overrides the speeds)", None, -1),
    Setting("ipo", "R_IPO", None, SettingRange(1e-5, 1.0, "s", closed=True), (),
            "interpolation (IPO) cycle", 0.01),
    # at least 10 × the IK's convergence tolerance (1e-9 m, runtime/ik/params.py): below
    # it a deviation of round-off size failed the run, blamed on the speed
    Setting("path_tol", "R_PATH_TOL", None, SettingRange(1e-5, math.inf, "mm", closed=True), (),
            "path tolerance (start value: --path-tolerance)", 0.05),
    Setting("profile", "R_PROFILE", None, SettingChoices(("TRAPEZOID", "SCURVE")), (),
            "velocity profile: trapezoid, or jerk-limited S-curve", "TRAPEZOID"),
    Setting("jerk", "R_JERK", None, _positive("mm/s³", 1e7), (),
            "path jerk of the S-curve (PTP: runtime.md)", 10000.0, 3),
    Setting("override", "R_OVERRIDE", None, SettingRange(1.0, 100.0, "%", closed=True), (),
            "program override (start value: --override): speeds ×k, accelerations ×k², "
            "WITH TIME ÷k, k = R_OVERRIDE/100", 100.0),
    Setting("approx", "R_APPROX", "APPROX", SettingRange(0.0, 1e5, "mm", closed=True),
            ALL_KINDS, "approximate positioning: blend distance at the point (0: exact stop)",
            0.0),
    Setting("clearance", "R_CLEARANCE", None, SettingRange(0.0, 1e5, "mm", closed=True), (),
            "distance kept between robots' links and non-adjacent links of one robot "
            "(0: only reported)", 0.0),
    Setting("platform", "R_PLATFORM", None, SettingChoices(("FREE", "HOLD")), (),
            "the platform outside WITH PLATFORM: FREE (the redundancy moves it) or HOLD "
            "(it stands, as FREEZE of its joints)", "FREE"),
    Setting("criterion", "R_CRITERION", None, SettingChoices(("DISTANCE", "ENERGY", "MVR")),
            (), "criterion of the redundancy: weighted joint displacement, kinetic energy, "
            "or the manipulator velocity ratio (docs/ik.md)", "DISTANCE"),
)  # fmt: skip

BY_FIELD: dict[str, Setting] = {s.field: s for s in SETTINGS}
BY_SYSTEM_VARIABLE: dict[str, Setting] = {
    s.system_variable: s for s in SETTINGS if s.system_variable
}
BY_WITH_WORD: dict[str, Setting] = {s.with_word: s for s in SETTINGS if s.with_word}
SETTING_RANGES: dict[str, SettingRange | SettingChoices] = {s.field: s.range for s in SETTINGS}


@dataclass(frozen=True)
class SystemVariable:
    """A system variable: its IRL type (``None``: the robot's MAIN_JOINT), whether a program
    may assign it, and the ``Settings`` field that holds it (``None``: read from the
    controller)."""

    name: str
    type_name: str | None
    writable: bool
    field: str | None


SYSTEM_VARIABLES: dict[str, SystemVariable] = {
    v.name: v
    for v in (
        *(SystemVariable(s.system_variable, s.type_name, True, s.field)
          for s in SETTINGS if s.system_variable),
        SystemVariable("R_TOOL", "POSE", True, "tool"),  # TCP in the flange frame
        SystemVariable("R_BASE", "POSE", True, "base"),  # program base frame in the world
        SystemVariable("R_ACT_POSE", "POSE", False, None),
        SystemVariable("R_ACT_JOINT", None, False, None),
    )
}  # fmt: skip


@dataclass(frozen=True)
class LimitOption:
    """A joint-limit option: modal (``WORD lo, hi; … WORDEND;``, IRDATA ``OPTON WORD`` /
    ``OPTOFF WORD``) or for one motion (``WITH WORD lo, hi``, IRDATA ``MOVE … WORD``); its
    bounds are a (minimum, maximum) pair of joint tuples of ``types``, bounding the
    ``derivative``-th derivative of each joint (0 position, 1 speed, 2 acceleration)."""

    word: str
    field: str  # the (min, max) pair's field of MotionCommand and ModalOptions
    derivative: int
    types: tuple[str, str]  # joint-tuple types of the minimum and the maximum
    meaning: str

    @property
    def end_word(self) -> str:
        """The word that switches the modal option off (``JOINTLIMITEND``)."""
        return self.word + "END"


LIMIT_OPTIONS: tuple[LimitOption, ...] = (
    LimitOption("JOINTLIMIT", "joint_limits", 0, ("MAIN_JOINT_MIN", "MAIN_JOINT_MAX"),
                "joint position limits"),
    LimitOption("JOINTSPEEDLIMIT", "speed_limits", 1,
                ("MAIN_JOINT_SPEED_MIN", "MAIN_JOINT_SPEED_MAX"), "joint speed limits"),
    LimitOption("JOINTACCELLIMIT", "accel_limits", 2,
                ("MAIN_JOINT_ACCEL_MIN", "MAIN_JOINT_ACCEL_MAX"), "joint acceleration limits"),
)  # fmt: skip
BY_LIMIT_WORD: dict[str, LimitOption] = {o.word: o for o in LIMIT_OPTIONS}
LIMIT_TUPLE_TYPES: tuple[str, ...] = tuple(t for o in LIMIT_OPTIONS for t in o.types)
"""The joint-tuple types of limit bounds (``MAIN_JOINT_MIN`` … ``MAIN_JOINT_ACCEL_MAX``)."""


def setting_error(field_name: str, value: object) -> str | None:
    """``None`` if ``value`` is admissible for the setting, else why not
    (``"the value must be in (0, 100] %"``)."""
    allowed = SETTING_RANGES[field_name]
    if isinstance(allowed, SettingChoices):
        return None if value in allowed else f"the value must be {allowed}"
    number = isinstance(value, float | int) and not isinstance(value, bool)
    if number and value in allowed:
        return None
    if not number:  # a study's or an expectation's "fast" or true: not a range question
        return f"expected a number, got {_kind(value)}; the value must be {allowed}"
    return f"the value must be {allowed}"


def _kind(value: object) -> str:
    """What a value that is no number is, for a message (``true``, ``"fast"``, a list)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        text = value if len(value) <= 40 else value[:37] + "..."
        return f'"{text}"'
    return {list: "a list", dict: "a table"}.get(type(value), type(value).__name__)


def shown_value(value: object) -> str:
    """A setting's value as a message shows it: as WRITE prints a REAL (6 decimals,
    ``150.0``) unless that rounds it, then ``%g``."""
    if isinstance(value, str):
        return "'" + value.replace("'", "''") + "'"
    if not isinstance(value, float | int):
        return repr(value)
    r = round(float(value), 6)
    shown = "0.0" if r == 0.0 else repr(r)
    return shown if float(shown) == value else f"{value:g}"


def setting_message(
    field_name: str, value: object, what: str, written: str | None = None
) -> str | None:
    """``None`` if admissible, else ``"<what> := <value>: the value must be …"`` (the one
    wording of compile-time and run-time range errors); ``written``: the value as the
    program wrote it (a literal, ``-5``), shown instead of :func:`shown_value`."""
    error = setting_error(field_name, value)
    if error is None:
        return None
    return f"{what} := {written if written is not None else shown_value(value)}: {error}"


def _shown_default(value: float | str) -> str:
    return f"'{value}'" if isinstance(value, str) else f"{value:g}"


_OVERRIDE_WORDS = {0: "—", 1: "×k", 2: "×k²", 3: "×k³", -1: "÷k"}


def ranges_table() -> str:
    """The settings and their ranges as a Markdown table (docs/language.md lists it)."""
    rows = [
        "| system variable | start value | WITH | unit | admissible values | WITH accepted by "
        "| R_OVERRIDE |",
        "|---|---|---|---|---|---|---|",
    ]
    for s in SETTINGS:
        kinds = ", ".join(KIND_WORDS[k].removeprefix("MOVE ") for k in s.kinds) or "—"
        kinds = "all motion" if s.kinds == ALL_KINDS else kinds
        start = "—" if s.default is None else _shown_default(s.default)
        rows.append(
            f"| {s.system_variable or '—'} | {start} | "
            f"{s.with_word or '—'} | {s.unit} | "
            f"{s.range.interval()} | {kinds} | {_OVERRIDE_WORDS[s.override_power]} |"
        )
    return "\n".join(rows) + "\n"


# Approximate positioning as other robot languages write it (KRL C_DIS/C_PTP/C_VEL/C_ORI,
# RAPID zones z50/fine, FANUC CNT50, a ZONE option): each gets the one hint below.
_FOREIGN_APPROX = re.compile(r"^(C_(DIS|PTP|VEL|ORI|SPL|LIN)|ZONE|FINE|Z\d+|CNT\d+)$", re.I)
APPROX_HINT = "approximate positioning is written WITH APPROX := mm (or R_APPROX := mm;)"


def approximation_hint(word: str) -> str | None:
    """The APPROX hint for another language's approximation word (``C_DIS``, ``z50``), else
    ``None``."""
    return APPROX_HINT if _FOREIGN_APPROX.match(word) else None


def reconfiguration_counts(kind: str, points: int) -> tuple[int, ...]:
    """How many configurations ``WITH RECONFIGURATION`` may give for a motion of ``kind``
    through ``points`` points: one per point; a LIN through several points may also give
    one for the whole move (its reference is spread along the path by arc length).
    CIRCLE (via, target) and LIN PATH need one per point (docs/language.md §6)."""
    if kind == "LIN" and points > 1:
        return (1, points)
    return (points,)
