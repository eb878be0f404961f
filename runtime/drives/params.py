"""Typed, validated drive parameters from a robot file's ``[drives]`` tables (schema:
``docs/drives.md``). All values SI, motor side unless stated.

``[drives]`` keys: ``type`` (``"dc"`` | ``"stepper"``), ``axes`` (1-based joint numbers
the drives move; default all — the other joints run ideal), ``ratio`` (motor rad per joint
rad | m; used only when the file has no ``[transmission]``), ``load_inertia`` (joint
side, for ``decoupled`` without ``[[inertials]]``). Subtables: ``[drives.dc]`` or
``[drives.stepper]`` (the chain), ``[drives.friction]``, optional ``[drives.slave]``.

A value is a number (all driven axes), a list (one per driven axis) or an inline table
``{ value = …, assumed = true, reason = "…" }`` for values no source publishes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from irlc.robots.model import RobotModel
from irlc.robots.toml_reader import Reader, RobotFileError


class DriveParamError(RobotFileError, ValueError):
    """A ``[drives]`` table is malformed: ``FILE: key 'drives.dc.R[2]': expected ...``."""


DC_KEYS = {
    "ke": "tachogenerator constant, V·s/rad",
    "kp": "velocity PI proportional gain (V/V)",
    "ki": "velocity PI integral gain, 1/s",
    "kz": "position P gain, V/rad (motor side)",
    "R": "armature resistance, Ω",
    "L": "armature inductance, H",
    "ks": "motor constant, N·m/A = V·s/rad",
    "k": "current feedback, V/A",
    "kiwzm": "current controller integral gain, 1/s",
    "i_max": "current clamp, A",
    "u_ref_max": "P and PI output saturation, V",
    "U": "power stage supply (PWM amplitude), V",
    "pwm_frequency": "PWM frequency, Hz",
    "J_m": "rotor inertia (with tacho, brake, gear input), kg·m²",
}
STEPPER_KEYS = {
    "R": "phase resistance, Ω",
    "L": "phase inductance, H",
    "L12": "mutual inductance, H",
    "psi_max": "flux amplitude Ψmax, Wb",
    "I": "rated phase current, A",
    "M_max": "holding torque amplitude, N·m",
    "teeth": "rotor teeth (step = 2π/(4·teeth))",
    "step_rate": "commanded step rate, rad/s (motor side)",
    "J_m": "rotor inertia, kg·m²",
}
FRICTION_KEYS = {"static": "N·m", "running": "N·m", "viscous": "N·m·s/rad"}
SLAVE_KEYS = {"T_pr": "s", "v_max": "rad/s", "a_max": "rad/s²"}
RATING_KEYS = {
    "following_error_max": "following-error bound, joint side rad | m (default 5° | 10 mm)",
    "torque_max": "gear's rated output torque | force, joint side N·m | N (a warning beyond)",
}
DC_RATING_KEYS = {"i_peak": "motor's peak current rating, A (a warning beyond)"}
# The robot's stated path accuracy (ISO 9283 AT_p), one value for the robot: with drives and
# no tolerance of the user's, the actual path is judged by it (docs/drives.md, "The verdict")
ACCURACY_KEYS = {
    "path_accuracy": "path accuracy, m: the largest deviation of the actual TCP path",
    "orientation_accuracy": "orientation path accuracy, rad",
}
TOP_KEYS = {
    "type",
    "axes",
    "ratio",
    "load_inertia",
    "dc",
    "stepper",
    "friction",
    "slave",
    *RATING_KEYS,
    *ACCURACY_KEYS,
}
OPTIONAL_DC = {"u_ref_max": 5.0, "pwm_frequency": 8000.0}


@dataclass(frozen=True)
class DcDrives:
    """Per-axis arrays (length = number of driven axes) of the cascade of docs/drives.md."""

    ke: np.ndarray
    kp: np.ndarray
    ki: np.ndarray
    kz: np.ndarray
    R: np.ndarray
    L: np.ndarray
    ks: np.ndarray
    k: np.ndarray
    kiwzm: np.ndarray
    i_max: np.ndarray
    u_ref_max: np.ndarray
    U: np.ndarray
    pwm_frequency: float
    J_m: np.ndarray
    i_peak: np.ndarray | None = None  # motor peak current rating, A (optional)


@dataclass(frozen=True)
class StepperDrives:
    R: np.ndarray
    L: np.ndarray
    L12: np.ndarray
    psi_max: np.ndarray
    I: np.ndarray
    M_max: np.ndarray
    teeth: np.ndarray
    step_rate: np.ndarray
    J_m: np.ndarray

    @property
    def step_angle(self) -> np.ndarray:
        """Full step ``2π / (4·teeth)`` (1.8° for 50 teeth)."""
        return 2.0 * math.pi / (4.0 * self.teeth)


@dataclass(frozen=True)
class Friction:
    """Motor-side stick/slip friction: breakaway ``static``, sliding ``running``, viscous."""

    static: np.ndarray
    running: np.ndarray
    viscous: np.ndarray


@dataclass(frozen=True)
class Slave:
    """The slave controller's trapezoid: setpoints every ``T_pr``, motor-side limits."""

    T_pr: float
    v_max: np.ndarray
    a_max: np.ndarray


@dataclass(frozen=True)
class DriveParams:
    type: str  # "dc" | "stepper"
    axes: tuple[int, ...]  # 0-based joints with drives; the others run ideal
    chain: DcDrives | StepperDrives
    friction: Friction
    ratio: np.ndarray  # fallback plain ratio (motor rad per joint SI unit), per driven axis
    load_inertia: np.ndarray | None
    slave: Slave | None
    assumed: dict[str, str] = field(default_factory=dict)  # key → reason
    following_error_max: np.ndarray | None = None  # joint side rad | m, per driven axis
    torque_max: np.ndarray | None = None  # gear rating, joint side N·m | N, per driven axis
    path_accuracy: float | None = None  # m (ISO 9283 AT_p), judges a drive run's path
    orientation_accuracy: float | None = None  # rad, judges its orientation

    @property
    def count(self) -> int:
        return len(self.axes)


class DriveReader(Reader):
    """The robot file reader (:class:`~irlc.robots.toml_reader.Reader`: the same typed
    values and messages) for the ``[drives]`` tables: failures are
    :class:`DriveParamError`; :meth:`values` reads one value per driven axis."""

    def __init__(self, model: RobotModel, count: int):
        super().__init__(model.source or f"robot {model.name}")
        self.count = count
        self.assumed: dict[str, str] = {}  # key → reason

    def fail(self, key: str, message: str) -> DriveParamError:
        return DriveParamError(self.file, key, message)

    def values(self, raw: Any, key: str, positive: bool = True, zero_ok: bool = False):
        """A number, a list (one per driven axis; ``key[i]``, 1-based) or
        ``{value, assumed, reason}``; positive (``zero_ok``: non-negative) unless
        ``positive`` is false."""
        raw = self.unwrapped(raw, key)
        items = raw if isinstance(raw, list) else [raw] * self.count
        if len(items) != self.count:
            raise self.fail(
                key,
                f"expected a number or {self.count} numbers (one per driven "
                f"axis), got {len(items)}",
            )
        read = self.number if not positive else self.non_negative if zero_ok else self.positive
        out = np.empty(self.count)
        for i, v in enumerate(items):
            out[i] = read(v, f"{key}[{i + 1}]" if isinstance(raw, list) else key)
        return out

    def scalar(self, raw: Any, key: str) -> float:
        """One positive number for the robot (not per axis), or ``{value, assumed,
        reason}``."""
        return self.positive(self.unwrapped(raw, key), key)

    def unwrapped(self, raw: Any, key: str) -> Any:
        """``raw``'s value: ``raw`` itself, or of ``{value, assumed, reason}`` its ``value``
        (an assumed value's reason is noted under ``key``)."""
        if not isinstance(raw, dict):
            return raw
        self.table(raw, key, {"value", "assumed", "reason"})
        if "value" not in raw:
            raise self.fail(f"{key}.value", "missing")
        assumed, reason = self.assumption(raw, key)
        if assumed:
            self.assumed[key] = reason
        return raw["value"]

    def group(self, t: dict, key: str, spec: dict, optional: dict, zero_ok=()) -> dict:
        self.table(t, key, set(spec))
        out = {}
        for name in spec:
            if name not in t:
                if name in optional:
                    out[name] = np.full(self.count, optional[name])
                    continue
                raise self.fail(f"{key}.{name}", f"missing; expected {spec[name]}")
            out[name] = self.values(t[name], f"{key}.{name}", zero_ok=name in zero_ok)
        return out


def drive_params(model: RobotModel) -> DriveParams | None:
    """The robot's validated ``[drives]`` tables, or ``None`` if it has none (all ideal)."""
    raw = model.extra.get("drives")
    if raw is None:
        return None
    rd = DriveReader(model, 0)
    rd.table(raw, "drives")
    axes = _axes(raw, model, rd)
    rd.count = len(axes)
    rd.table(raw, "drives", TOP_KEYS)
    kind = raw.get("type", "dc")
    if kind not in ("dc", "stepper"):
        raise rd.fail("drives.type", f"expected one of dc, stepper, got {kind!r}")
    if kind not in raw:
        raise rd.fail(f"drives.{kind}", f"missing; [drives] type = {kind!r} needs [drives.{kind}]")
    other = "stepper" if kind == "dc" else "dc"
    if other in raw:
        raise rd.fail(f"drives.{other}", f"not used with type = {kind!r}")
    chain = _dc(rd, raw["dc"]) if kind == "dc" else _stepper(rd, raw["stepper"])
    fr = rd.group(
        raw.get("friction", {}),
        "drives.friction",
        FRICTION_KEYS,
        dict.fromkeys(FRICTION_KEYS, 0.0),
        zero_ok=set(FRICTION_KEYS),
    )
    friction = Friction(**fr)
    bad = np.flatnonzero(friction.running > friction.static)
    if bad.size:
        raise rd.fail(
            "drives.friction.running",
            f"axis {bad[0] + 1}: running friction exceeds static friction (breakaway)",
        )
    ratio = rd.values(raw.get("ratio", 1.0), "drives.ratio", positive=False)
    if np.any(ratio == 0.0):
        raise rd.fail("drives.ratio", "expected non-zero ratios")
    load = None
    if "load_inertia" in raw:
        load = rd.values(raw["load_inertia"], "drives.load_inertia", zero_ok=True)
    slave = None
    if "slave" in raw:
        if kind != "dc":
            raise rd.fail("drives.slave", "the slave controller belongs to dc drives")
        s = rd.table(raw["slave"], "drives.slave", set(SLAVE_KEYS))
        if "T_pr" not in s:
            raise rd.fail("drives.slave.T_pr", "missing; expected the setpoint period in s")
        t_pr = float(rd.values(s["T_pr"], "drives.slave.T_pr")[0])
        v = rd.values(s.get("v_max", math.inf), "drives.slave.v_max")
        a = rd.values(s.get("a_max", math.inf), "drives.slave.a_max")
        slave = Slave(t_pr, v, a)
    rated = {
        key: rd.values(raw[key], f"drives.{key}") if key in raw else None for key in RATING_KEYS
    }
    stated = {key: rd.scalar(raw[key], f"drives.{key}") if key in raw else None
              for key in ACCURACY_KEYS}  # fmt: skip
    return DriveParams(
        kind, axes, chain, friction, ratio, load, slave, dict(rd.assumed), **rated, **stated
    )


def _axes(raw: dict, model: RobotModel, rd: DriveReader) -> tuple[int, ...]:
    value = raw.get("axes", "all")
    if value == "all":
        return tuple(range(model.n))
    ok = (
        isinstance(value, list)
        and value
        and all(isinstance(v, int) and not isinstance(v, bool) and 1 <= v <= model.n for v in value)
    )
    if not ok or len(set(value)) != len(value):
        raise rd.fail(
            "drives.axes", f'expected "all" or distinct joint numbers 1..{model.n}, got {value!r}'
        )
    return tuple(sorted(v - 1 for v in value))


def _dc(rd: DriveReader, t: Any) -> DcDrives:
    rd.table(t, "drives.dc", set(DC_KEYS) | set(DC_RATING_KEYS))
    i_peak = rd.values(t["i_peak"], "drives.dc.i_peak") if "i_peak" in t else None
    g = rd.group({k: v for k, v in t.items() if k != "i_peak"}, "drives.dc", DC_KEYS, OPTIONAL_DC)
    g["i_peak"] = i_peak
    freq = g.pop("pwm_frequency")
    if np.ptp(freq) != 0.0:
        raise rd.fail("drives.dc.pwm_frequency", "one PWM frequency for all axes")
    return DcDrives(pwm_frequency=float(freq[0]), **g)


def _stepper(rd: DriveReader, t: Any) -> StepperDrives:
    g = rd.group(t, "drives.stepper", STEPPER_KEYS, {})
    bad = np.flatnonzero(g["L12"] >= g["L"])
    if bad.size:
        raise rd.fail(
            "drives.stepper.L12",
            f"axis {bad[0] + 1}: mutual inductance must be smaller than the self inductance",
        )
    return StepperDrives(**g)
