"""Load and validate a robot description file (TOML) into a :class:`RobotModel`.

The format is documented in ``docs/robots.md``. Every value is checked; a bad file raises
:class:`RobotFileError` naming the file, the key (``joints[3].axis``) and the expected
shape. File units are ``[robot].units`` (default: ``angle = "deg"``, ``length = "m"``);
joint values follow the joint kind (revolute → angle unit, prismatic → length unit).
Everything is converted to SI here, once.

Chains (``[robot].chain``):

* ``"dh"``: standard DH rows ``A_i = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i)``; the joint variable
  (θ for revolute, d for prismatic) is ``q_i + offset_i``. Since ``Rz`` and ``Tz``
  commute, the fixed part ``F_i = Tz(d) Rz(θ) Tx(a) Rx(α)`` (without the variable)
  becomes ``origin_{i+1}`` and ``F_n`` the start of the flange.
* ``"axes"``: per joint an ``axis`` (in the joint frame), an optional ``origin``
  transform, and a ``link`` vector from this joint to the next one (to the flange for
  the last joint), expressed in the frame the joint moves.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path
from typing import Any

import numpy as np
from irlc.files import read_user_text
from irlc.lang.errors import IrlcError
from irlc.lang.file_access import describe
from irlc.robots.model import Capsule, Inertial, Joint, Limits, RobotModel, Sphere

ANGLE_UNITS = {"deg": math.pi / 180.0, "rad": 1.0}
LENGTH_UNITS = {"m": 1.0, "mm": 1e-3}
AXIS_NAMES = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}
AXIS_NAMES.update({"-" + k: tuple(-c for c in v) for k, v in list(AXIS_NAMES.items())})

TOP_KEYS = {
    "robot",
    "base",
    "flange",
    "tool",
    "joints",
    "geometry",
    "inertials",
    "limit_sets",
    "coupled_limits",
    "transmission",
    "reachability",
    "assumptions",
    "drives",
    "ik",
}
TASK_COMPONENTS = ("x", "y", "z", "rx", "ry", "rz")
ROBOT_KEYS = {
    "name",
    "description",
    "chain",
    "units",
    "gravity",
    "home",
    "source",
    "notes",
    "urdf",
    "tip",
    "assumed",
    "reason",
}
JOINT_KEYS = {
    "name",
    "kind",
    "axis",
    "origin",
    "link",
    "dh",
    "offset",
    "position",
    "speed",
    "accel",
    "jerk",
    "weight",
    "assumed",
    "reason",
}
TRANSFORM_KEYS = {"xyz", "zyx", "matrix", "assumed", "reason"}


class RobotFileError(IrlcError, LookupError):
    """A robot description file is malformed: ``FILE: key 'K': expected ..., got ...``.

    A ``LookupError``: the robot cannot be had, which is what the compiler's robot
    resolvers raise (``irlc.lang.signature``)."""

    def __init__(self, file: str, key: str, message: str):
        self.file, self.key, self.message = file, key, message
        super().__init__(f"{file}: key '{key}': {message}" if key else f"{file}: {message}")


class MissingExtraError(RobotFileError):
    """The file needs an optional extra of irlc that is not installed (``extra``: its name,
    as in ``pip install 'irlc[EXTRA]'``)."""

    def __init__(self, file: str, extra: str, package: str, what: str):
        self.extra, self.package = extra, package
        super().__init__(
            file, "", f"{what} needs the optional package {package}: pip install 'irlc[{extra}]'"
        )


class Reader:
    """Typed access to a parsed TOML tree with error messages that name file and key."""

    def __init__(self, file: str, angle: float = ANGLE_UNITS["deg"], length: float = 1.0):
        self.file = file
        self.angle = angle
        self.length = length

    def fail(self, key: str, message: str) -> RobotFileError:
        return RobotFileError(self.file, key, message)

    def table(self, value: Any, key: str, allowed: set[str] | None = None) -> dict:
        if not isinstance(value, dict):
            raise self.fail(key, f"expected a table, got {_show(value)}")
        if allowed is not None:
            unknown = sorted(set(value) - allowed)
            if unknown:
                raise self.fail(
                    _join(key, unknown[0]),
                    f"unknown key; expected one of {', '.join(sorted(allowed))}",
                )
        return value

    def number(self, value: Any, key: str) -> float:
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise self.fail(key, f"expected a number, got {_show(value)}")
        if not math.isfinite(value):
            raise self.fail(key, f"expected a finite number, got {value}")
        return float(value)

    def positive(self, value: Any, key: str) -> float:
        v = self.number(value, key)
        if v <= 0.0:
            raise self.fail(key, f"expected a positive number, got {v:g}")
        return v

    def string(self, value: Any, key: str, choices: tuple[str, ...] | None = None) -> str:
        if not isinstance(value, str):
            raise self.fail(key, f"expected a string, got {_show(value)}")
        if choices is not None and value not in choices:
            raise self.fail(key, f"expected one of {', '.join(choices)}, got {_show(value)}")
        return value

    def boolean(self, value: Any, key: str) -> bool:
        if not isinstance(value, bool):
            raise self.fail(key, f"expected true or false, got {_show(value)}")
        return value

    def vector(self, value: Any, key: str, size: int) -> np.ndarray:
        if not isinstance(value, list) or len(value) != size:
            raise self.fail(key, f"expected {size} numbers, got {_show(value)}")
        return np.array([self.number(v, f"{key}[{i}]") for i, v in enumerate(value)])

    def numbers(self, value: Any, key: str) -> np.ndarray:
        if not isinstance(value, list):
            raise self.fail(key, f"expected a list of numbers, got {_show(value)}")
        return np.array([self.number(v, f"{key}[{i}]") for i, v in enumerate(value)])

    def array_of_tables(self, value: Any, key: str) -> list[dict]:
        if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
            raise self.fail(key, f"expected an array of tables ([[{key}]]), got {_show(value)}")
        return value

    def transform(self, value: Any, key: str) -> np.ndarray:
        """``{xyz = [..], zyx = [a, b, c]}`` (R = Rz(a)Ry(b)Rx(c)) or ``{matrix = 4×4}``."""
        t = self.table(value, key, TRANSFORM_KEYS)
        self.assumption(t, key)
        if "matrix" in t:
            if "xyz" in t or "zyx" in t:
                raise self.fail(key, "give either matrix or xyz/zyx, not both")
            rows = t["matrix"]
            if not isinstance(rows, list) or len(rows) != 4:
                raise self.fail(_join(key, "matrix"), f"expected 4 rows of 4, got {_show(rows)}")
            m = np.array([self.vector(r, f"{key}.matrix[{i}]", 4) for i, r in enumerate(rows)])
            m[:3, 3] *= self.length
            _check_rigid(self, m, _join(key, "matrix"))
            _in_range(self, _join(key, "matrix"), "point", m[:3, 3])
            return m
        out = np.eye(4)
        if "zyx" in t:
            a, b, c = self.vector(t["zyx"], _join(key, "zyx"), 3) * self.angle
            out[:3, :3] = _rz(a) @ _ry(b) @ _rx(c)
        if "xyz" in t:
            out[:3, 3] = self.vector(t["xyz"], _join(key, "xyz"), 3) * self.length
            _in_range(self, _join(key, "xyz"), "point", out[:3, 3])
        return out

    def assumption(self, t: dict, key: str) -> tuple[bool, str]:
        """``assumed = true`` must come with a non-empty ``reason``."""
        assumed = self.boolean(t.get("assumed", False), _join(key, "assumed"))
        reason = t.get("reason", "")
        reason = self.string(reason, _join(key, "reason"))
        if assumed and not reason.strip():
            raise self.fail(_join(key, "reason"), "assumed = true needs a reason (a string)")
        return assumed, reason


def _join(key: str, sub: str) -> str:
    return f"{key}.{sub}" if key else sub


def _show(value: Any) -> str:
    return describe(value)  # never the text of the file (irlc.lang.file_access)


def _rx(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _ry(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _rz(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _trans(v) -> np.ndarray:
    t = np.eye(4)
    t[:3, 3] = v
    return t


def _rot4(r: np.ndarray) -> np.ndarray:
    t = np.eye(4)
    t[:3, :3] = r
    return t


def _check_rigid(rd: Reader, m: np.ndarray, key: str) -> None:
    r = m[:3, :3]
    if not np.allclose(r @ r.T, np.eye(3), atol=1e-6) or np.linalg.det(r) < 0.0:
        raise rd.fail(key, "expected a rigid transform (orthonormal rotation, det +1)")
    if not np.allclose(m[3], [0.0, 0.0, 0.0, 1.0]):
        raise rd.fail(key, "expected last row [0, 0, 0, 1]")


# ----------------------------------------------------------------------------- entry


def load_toml(path: str | Path) -> RobotModel:
    """Parse and validate one TOML robot file (raises :class:`RobotFileError`)."""
    path = Path(path)
    file = str(path)
    text = read_user_text(path, lambda f, reason: RobotFileError(f, "", reason))
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise RobotFileError(file, "", f"not valid TOML: {e}") from None
    return build_model(doc, file, path.parent)


def _read_ik(rd: Reader, table: Any) -> dict:
    """``[ik] task = ["x", "y"]``: the pose-error components the inverse transformation
    controls (default all six; a planar arm controls only its plane's position)."""
    ik = rd.table(table, "ik", {"task"})
    if "task" not in ik:
        return {}
    task = ik["task"]
    if not isinstance(task, list) or not task:
        raise rd.fail("ik.task", f"expected a non-empty list of {', '.join(TASK_COMPONENTS)}")
    names = [rd.string(c, f"ik.task[{i}]", TASK_COMPONENTS) for i, c in enumerate(task)]
    if len(set(names)) != len(names):
        raise rd.fail("ik.task", "a component is listed twice")
    return {"task": names}


def build_model(doc: dict, file: str, folder: Path) -> RobotModel:
    rd = Reader(file)
    rd.table(doc, "", TOP_KEYS)
    if "robot" not in doc:
        raise rd.fail("robot", "missing table [robot]")
    robot = rd.table(doc["robot"], "robot", ROBOT_KEYS)
    _read_units(rd, robot)
    assumed = _read_assumptions(rd, doc)
    if "urdf" in robot:
        joints, fixed = _from_urdf(rd, robot, folder, doc)
    else:
        joints, fixed = _read_chain(rd, robot, doc, assumed)
    n = len(joints)
    name = rd.string(robot.get("name", Path(file).stem), "robot.name")
    base = rd.transform(doc["base"], "base") if "base" in doc else np.eye(4)
    flange = fixed["flange"]
    if "flange" in doc:
        flange = flange @ rd.transform(doc["flange"], "flange")
    tool = rd.transform(doc["tool"], "tool") if "tool" in doc else fixed.get("tool", np.eye(4))
    gravity = fixed.get("gravity", np.array([0.0, 0.0, -9.81]))
    if "gravity" in robot:
        gravity = rd.vector(robot["gravity"], "robot.gravity", 3)
    home = _read_home(rd, robot, joints, fixed.get("home"))
    geometry = fixed.get("geometry", ())
    if "geometry" in doc:
        geometry = _read_geometry(rd, doc["geometry"], n, assumed)
    inertials = fixed.get("inertials", ())
    if "inertials" in doc:
        inertials = _read_inertials(rd, doc["inertials"], n, geometry, assumed)
    extra: dict[str, Any] = {"assumed": assumed, "units": {"angle": rd.angle, "length": rd.length}}
    if "urdf_extra" in fixed:
        assumed.update(fixed["urdf_extra"]["assumed"])
        extra["urdf_notes"] = fixed["urdf_extra"]["urdf_notes"]
        extra["urdf"] = fixed["urdf_extra"]["urdf"]
    if "drives" in doc:  # owned by the drives area: stored unvalidated
        extra["drives"] = doc["drives"]
    if "coupled_limits" in doc:
        extra["coupled_limits"] = _read_coupled(rd, doc["coupled_limits"], joints)
    if "transmission" in doc:
        extra["transmission"] = _read_transmission(rd, doc["transmission"], joints, assumed)
    if "reachability" in doc:
        extra["reachability"] = _read_reachability(rd, doc["reachability"], n)
    if "ik" in doc:
        extra["ik"] = _read_ik(rd, doc["ik"])
    for k in ("source", "notes"):
        if k in robot:
            extra[k] = rd.string(robot[k], f"robot.{k}")
    limit_sets = _read_limit_sets(rd, doc.get("limit_sets", {}), joints)
    return RobotModel(
        name=name,
        joints=tuple(joints),
        base=base,
        flange=flange,
        tool=tool,
        home=home,
        gravity=gravity,
        geometry=tuple(geometry),
        inertials=tuple(inertials),
        limit_sets=limit_sets,
        extra=extra,
        source=file,
        description=rd.string(robot.get("description", ""), "robot.description"),
    )


def _read_units(rd: Reader, robot: dict) -> None:
    units = rd.table(robot.get("units", {}), "robot.units", {"angle", "length"})
    angle = rd.string(units.get("angle", "deg"), "robot.units.angle", tuple(ANGLE_UNITS))
    length = rd.string(units.get("length", "m"), "robot.units.length", tuple(LENGTH_UNITS))
    rd.angle, rd.length = ANGLE_UNITS[angle], LENGTH_UNITS[length]


def _read_assumptions(rd: Reader, doc: dict) -> dict[str, str]:
    """``[assumptions]``: section name → reason; marks every entry of that section."""
    table = rd.table(doc.get("assumptions", {}), "assumptions")
    return {k: rd.string(v, f"assumptions.{k}") for k, v in table.items()}


def _scale(rd: Reader, kind: str) -> float:
    return rd.angle if kind == "revolute" else rd.length


# ----------------------------------------------------------------------------- chain


def _read_chain(rd: Reader, robot: dict, doc: dict, assumed: dict) -> tuple[list[Joint], dict]:
    chain = rd.string(robot.get("chain"), "robot.chain", ("dh", "axes"))
    if "joints" not in doc:
        raise rd.fail("joints", "missing: expected an array of tables [[joints]]")
    rows = rd.array_of_tables(doc["joints"], "joints")
    if not rows:
        raise rd.fail("joints", "expected at least one [[joints]] entry")
    n = len(rows)
    joints: list[Joint] = []
    origin = np.eye(4)  # fixed transform before the next joint
    names: set[str] = set()
    for i, row in enumerate(rows):
        key = f"joints[{i + 1}]"
        rd.table(row, key, JOINT_KEYS)
        name = rd.string(row.get("name", f"J{i + 1}"), f"{key}.name")
        if name in names:
            raise rd.fail(f"{key}.name", "duplicate joint name (an earlier joint has it)")
        names.add(name)
        if "kind" not in row:
            raise rd.fail(f"{key}.kind", "missing; expected 'revolute' or 'prismatic'")
        kind = rd.string(row["kind"], f"{key}.kind", ("revolute", "prismatic"))
        j_assumed, reason = rd.assumption(row, key)
        if j_assumed:
            assumed[key] = reason
        if chain == "dh":
            axis, this_origin, after = _dh_row(rd, row, key, kind)
        else:
            axis, this_origin, after = _axes_row(rd, row, key)
        limits = _read_joint_limits(rd, row, key, kind)
        offset = rd.number(row.get("offset", 0.0), f"{key}.offset") * _scale(rd, kind)
        weight = rd.positive(row.get("weight", n - i), f"{key}.weight")
        joints.append(
            Joint(name, kind, origin @ this_origin, axis, limits, offset=offset, weight=weight)
        )
        origin = after
    return joints, {"flange": origin}


def _dh_row(rd: Reader, row: dict, key: str, kind: str):
    for k in ("axis", "link", "origin"):
        if k in row:
            raise rd.fail(
                f"{key}.{k}", "not used with chain = 'dh' (give dh = {alpha, a, d|theta})"
            )
    if "dh" not in row:
        raise rd.fail(
            f"{key}.dh",
            "missing; expected a table {alpha, a, d} (revolute) or {alpha, a, theta} (prismatic)",
        )
    variable = "theta" if kind == "revolute" else "d"
    fixed_name = "d" if kind == "revolute" else "theta"
    dh = rd.table(row["dh"], f"{key}.dh", {"alpha", "a", fixed_name, variable})
    if variable in dh:
        raise rd.fail(
            f"{key}.dh.{variable}",
            f"is the variable of a {kind} joint; use {key}.offset for a constant shift",
        )
    for k in ("alpha", "a"):
        if k not in dh:
            raise rd.fail(f"{key}.dh.{k}", "missing; expected a number")
    alpha = rd.number(dh["alpha"], f"{key}.dh.alpha") * rd.angle
    a = rd.number(dh["a"], f"{key}.dh.a") * rd.length
    _in_range(rd, f"{key}.dh.a", "point", a)
    d = theta = 0.0
    if kind == "revolute":
        d = rd.number(dh.get("d", 0.0), f"{key}.dh.d") * rd.length
        _in_range(rd, f"{key}.dh.d", "point", d)
    else:
        theta = rd.number(dh.get("theta", 0.0), f"{key}.dh.theta") * rd.angle
    after = _trans((0.0, 0.0, d)) @ _rot4(_rz(theta)) @ _trans((a, 0.0, 0.0)) @ _rot4(_rx(alpha))
    return np.array([0.0, 0.0, 1.0]), np.eye(4), after


def _axes_row(rd: Reader, row: dict, key: str):
    if "dh" in row:
        raise rd.fail(f"{key}.dh", "not used with chain = 'axes' (give axis, link, origin)")
    if "axis" not in row:
        raise rd.fail(f"{key}.axis", "missing; expected 'x', 'y', 'z' (or '-x', ...) or 3 numbers")
    raw = row["axis"]
    if isinstance(raw, str):
        if raw not in AXIS_NAMES:
            raise rd.fail(f"{key}.axis", f"expected one of x, y, z, -x, -y, -z, got {_show(raw)}")
        axis = np.array(AXIS_NAMES[raw])
    else:
        axis = rd.vector(raw, f"{key}.axis", 3)
        axis = axis / max(float(np.max(np.abs(axis))), 1e-300)  # the norm cannot overflow
        norm = float(np.linalg.norm(axis))
        if norm < 1e-9:
            raise rd.fail(f"{key}.axis", "expected a non-zero vector")
        axis = axis / norm
    this_origin = rd.transform(row["origin"], f"{key}.origin") if "origin" in row else np.eye(4)
    link = rd.vector(row.get("link", [0.0, 0.0, 0.0]), f"{key}.link", 3) * rd.length
    _in_range(rd, f"{key}.link", "point", link)
    return axis, this_origin, _trans(link)


def _pair(rd: Reader, value: Any, key: str, scale: float) -> tuple[float, float]:
    """``[min, max]`` or a positive number ``v`` meaning ``[-v, v]``; checks min ≤ max."""
    if isinstance(value, list):
        lo, hi = rd.vector(value, key, 2)
    else:
        v = rd.positive(value, key)
        lo, hi = -v, v
    if lo > hi:
        raise rd.fail(key, f"expected min ≤ max, got [{lo:g}, {hi:g}]")
    return lo * scale, hi * scale


def _read_joint_limits(rd: Reader, row: dict, key: str, kind: str) -> Limits:
    s = _scale(rd, kind)
    for k in ("position", "speed", "accel"):
        if k not in row:
            raise rd.fail(f"{key}.{k}", "missing; expected [min, max] (or a number v for ±v)")
    pos = _pair(rd, row["position"], f"{key}.position", s)
    speed = _pair(rd, row["speed"], f"{key}.speed", s)
    accel = _pair(rd, row["accel"], f"{key}.accel", s)
    for k, (lo, hi) in (("speed", speed), ("accel", accel)):
        if not lo < 0.0 < hi:
            raise rd.fail(
                f"{key}.{k}", "expected min < 0 < max (the joint must be able to move both ways)"
            )
    jerk = rd.positive(row["jerk"], f"{key}.jerk") * s if "jerk" in row else None
    return Limits(pos, speed, accel, jerk)


def _read_home(rd: Reader, robot: dict, joints: list[Joint], default) -> np.ndarray | None:
    if "home" not in robot:
        return default
    values = rd.vector(robot["home"], "robot.home", len(joints))
    home = np.array([v * _scale(rd, j.kind) for v, j in zip(values, joints, strict=True)])
    for i, (h, j) in enumerate(zip(home, joints, strict=True)):
        lo, hi = j.limits.position
        if not lo - 1e-12 <= h <= hi + 1e-12:
            raise rd.fail(
                f"robot.home[{i}]", f"joint {j.name} home value is outside its position limits"
            )
    return home


# ----------------------------------------------------------------------------- limits


def _read_limit_sets(rd: Reader, table: Any, joints: list[Joint]) -> dict[str, tuple[Limits, ...]]:
    """``[limit_sets.NAME]`` with ``position`` / ``speed`` / ``accel`` = n pairs each (file
    units); what a set leaves out is taken from the robot's own limits."""
    sets = rd.table(table, "limit_sets")
    out: dict[str, tuple[Limits, ...]] = {}
    for name, body in sets.items():
        key = f"limit_sets.{name}"
        body = rd.table(body, key, {"position", "speed", "accel", "description", "source"})
        per_kind: dict[str, list] = {}
        for k in ("position", "speed", "accel"):
            if k not in body:
                continue
            rows = body[k]
            if not isinstance(rows, list) or len(rows) != len(joints):
                raise rd.fail(
                    f"{key}.{k}",
                    f"expected {len(joints)} entries ([min, max] or a number), got {_show(rows)}",
                )
            per_kind[k] = [
                _pair(rd, r, f"{key}.{k}[{i}]", _scale(rd, j.kind))
                for i, (r, j) in enumerate(zip(rows, joints, strict=True))
            ]
        if not per_kind:
            raise rd.fail(key, "expected at least one of position, speed, accel")
        out[name] = tuple(
            Limits(
                per_kind["position"][i] if "position" in per_kind else j.limits.position,
                per_kind["speed"][i] if "speed" in per_kind else j.limits.speed,
                per_kind["accel"][i] if "accel" in per_kind else j.limits.accel,
                j.limits.jerk,
            )
            for i, j in enumerate(joints)
        )
    return out


def _read_coupled(rd: Reader, value: Any, joints: list[Joint]) -> list[dict]:
    """``[[coupled_limits]]``: ``min ≤ Σ c_j q_j ≤ max`` over joints of one kind (file units).

    Stored in SI: ``{name, kind, coeffs (n,), lower, upper, text}`` (``kind``: the joints'
    kind, which gives the bounds' unit); ``lower``/``upper`` may be
    ``-inf``/``inf`` when ``min``/``max`` is absent."""
    rows = rd.array_of_tables(value, "coupled_limits")
    out = []
    for i, row in enumerate(rows):
        key = f"coupled_limits[{i + 1}]"
        rd.table(row, key, {"name", "coeffs", "min", "max", "text", "assumed", "reason"})
        rd.assumption(row, key)
        coeffs = rd.vector(row.get("coeffs"), f"{key}.coeffs", len(joints))
        used = [j.kind for j, c in zip(joints, coeffs, strict=True) if c != 0.0]
        if not used:
            raise rd.fail(f"{key}.coeffs", "expected at least one non-zero coefficient")
        if len(set(used)) > 1:
            raise rd.fail(f"{key}.coeffs", "expected joints of one kind only (units must match)")
        s = _scale(rd, used[0])
        if "min" not in row and "max" not in row:
            raise rd.fail(key, "expected min, max or both")
        lo = rd.number(row["min"], f"{key}.min") * s if "min" in row else -math.inf
        hi = rd.number(row["max"], f"{key}.max") * s if "max" in row else math.inf
        if lo > hi:
            raise rd.fail(key, f"expected min ≤ max, got [{lo / s:g}, {hi / s:g}]")
        name = rd.string(row.get("name", f"coupled_{i + 1}"), f"{key}.name")
        text = rd.string(row.get("text", ""), f"{key}.text")
        out.append(
            {
                "name": name,
                "kind": used[0],
                "coeffs": coeffs,
                "lower": lo,
                "upper": hi,
                "text": text,
            }
        )
    return out


# ----------------------------------------------------------------------------- transmission


def _read_transmission(rd: Reader, value: Any, joints: list[Joint], assumed: dict) -> list[dict]:
    """``[transmission]`` with ``[[transmission.joints]]`` (one per joint), stored in SI.

    * ``type = "ratio"``: ``q_i = θs_i / ratio + Σ factor·q_j`` (``couple = [[j, factor]]``,
      1-based ``j < i``); the default ``ratio = 1`` is a direct drive.
    * ``type = "screw_lever"``: a ball screw of ``lead`` (length per motor turn) changes
      the distance ``s`` between two lever pivots ``a`` and ``b`` apart from the joint
      axis: ``s(φ) = √(a² + b² − 2ab·cos(φ + phi0))`` with ``φ = Σ factor·q_j`` over
      ``angle = [[j, factor], ...]`` (must include ``i``); ``θs = 2π (s(φ) − s(0)) / lead``.
    """
    t = rd.table(value, "transmission", {"joints", "assumed", "reason", "description"})
    t_assumed, reason = rd.assumption(t, "transmission")
    if t_assumed:
        assumed["transmission"] = reason
    rows = rd.array_of_tables(t.get("joints"), "transmission.joints")
    if len(rows) != len(joints):
        raise rd.fail(
            "transmission.joints",
            f"expected {len(joints)} entries (one per joint), got {len(rows)}",
        )
    return [_transmission_row(rd, row, i, joints, assumed) for i, row in enumerate(rows)]


def _index_pairs(rd: Reader, value: Any, key: str, i: int, n: int, allow_self: bool) -> list:
    if not isinstance(value, list):
        raise rd.fail(key, f"expected a list of [joint, factor] pairs, got {_show(value)}")
    pairs = []
    for k, p in enumerate(value):
        if not isinstance(p, list) or len(p) != 2 or not isinstance(p[0], int):
            raise rd.fail(
                f"{key}[{k}]", f"expected [joint (1-based integer), factor], got {_show(p)}"
            )
        j = p[0] - 1
        if not (0 <= j < i or (allow_self and j == i)):
            raise rd.fail(
                f"{key}[{k}]",
                f"expected a joint number in 1..{i + allow_self} "
                f"(only earlier joints may couple), got {p[0]}",
            )
        pairs.append((j, rd.number(p[1], f"{key}[{k}][1]")))
    return pairs


def _transmission_row(rd: Reader, row: dict, i: int, joints: list[Joint], assumed: dict) -> dict:
    key = f"transmission.joints[{i + 1}]"
    rd.table(row, key)
    kind = rd.string(row.get("type", "ratio"), f"{key}.type", ("ratio", "screw_lever"))
    a_flag, reason = rd.assumption(row, key)
    if a_flag:
        assumed[key] = reason
    if kind == "ratio":
        rd.table(row, key, {"type", "ratio", "couple", "assumed", "reason"})
        ratio = rd.number(row.get("ratio", 1.0), f"{key}.ratio")
        if ratio == 0.0:
            raise rd.fail(f"{key}.ratio", "expected a non-zero number")
        couple = _index_pairs(rd, row.get("couple", []), f"{key}.couple", i, len(joints), False)
        for j, _ in couple:
            if joints[j].kind != joints[i].kind:
                raise rd.fail(f"{key}.couple", "coupled joints must be of the same kind")
        # ratios are SI whatever [robot].units says: motor rad per joint rad (or per metre)
        return {"type": "ratio", "ratio": ratio, "couple": couple}
    rd.table(row, key, {"type", "lead", "a", "b", "phi0", "angle", "assumed", "reason"})
    if joints[i].kind != "revolute":
        raise rd.fail(f"{key}.type", "screw_lever drives a revolute joint")
    out: dict[str, Any] = {"type": "screw_lever"}
    for k in ("lead", "a", "b"):
        if k not in row:
            raise rd.fail(f"{key}.{k}", "missing; expected a positive length")
        out[k] = rd.positive(row[k], f"{key}.{k}") * rd.length
    out["phi0"] = rd.number(row.get("phi0", 90.0), f"{key}.phi0") * rd.angle
    angle = _index_pairs(rd, row.get("angle", [[i + 1, 1.0]]), f"{key}.angle", i, len(joints), True)
    if not any(j == i and f != 0.0 for j, f in angle):
        raise rd.fail(f"{key}.angle", f"must include joint {i + 1} itself with a non-zero factor")
    out["angle"] = angle
    if not 0.0 < out["phi0"] < math.pi:
        raise rd.fail(f"{key}.phi0", "expected an angle strictly between 0 and 180 deg")
    return out


def _read_reachability(rd: Reader, value: Any, n: int) -> dict:
    t = rd.table(value, "reachability", {"type", "plane_joint", "text"})
    kind = rd.string(t.get("type", "vertical_plane"), "reachability.type", ("vertical_plane",))
    j = t.get("plane_joint", 1)
    if not isinstance(j, int) or isinstance(j, bool) or not 1 <= j <= n:
        raise rd.fail("reachability.plane_joint", f"expected a joint number 1..{n}, got {_show(j)}")
    return {
        "type": kind,
        "plane_joint": j - 1,
        "text": rd.string(t.get("text", ""), "reachability.text"),
    }


# ----------------------------------------------------------------------------- geometry


def geometry_problem(what: str, values_m, unit: str = "m") -> str | None:
    """Why robot geometry (SI metres) is outside the physical range of geometry that
    obstacles share (``irdata.GEOMETRY_*``: points within ±1 km, lengths 1 µm … 1 km),
    else ``None``; the message speaks ``unit`` (the file's length unit). ``what`` is
    ``"point"`` or ``"length"``. Beyond it the inertia of a solid (r⁵) overflows or its
    volume underflows to zero."""
    from irlc.lang.irdata import GEOMETRY_MAX_MM, GEOMETRY_MIN_LENGTH_MM

    top, low, scale = GEOMETRY_MAX_MM * 1e-3, GEOMETRY_MIN_LENGTH_MM * 1e-3, LENGTH_UNITS[unit]
    for v in np.asarray(values_m, dtype=float).ravel():
        if what == "length" and not low <= v <= top:
            return (
                f"{v / scale:g} {unit} is outside the physical range of a length "
                f"({low / scale:g} to {top / scale:g} {unit})"
            )
        if what == "point" and not abs(v) <= top:
            return (
                f"{v / scale:g} {unit} is outside the physical range of a coordinate "
                f"(within ±{top / scale:g} {unit})"
            )
    return None


MASS_RANGE_KG = (1e-9, 1e9)  # a link's mass: a microgram grain to a million tonnes
INERTIA_MAX_KG_M2 = 1e15  # |entry| of an inertia: that mass spread over ±1 km (geometry)


def inertial_problem(mass: float | None, inertia=None) -> str | None:
    """Why a link's mass (kg) or inertia entries (kg·m²) are outside the physical range,
    else ``None`` (``None`` arguments are not checked). Beyond it the combined inertia of
    a link (m·d², ρ·V) overflows to inf and NaN."""
    low, high = MASS_RANGE_KG
    if mass is not None and not low <= mass <= high:
        return f"a mass of {mass:g} kg is outside the physical range ({low:g} to {high:g} kg)"
    top = INERTIA_MAX_KG_M2
    if inertia is not None and not np.all(np.abs(np.asarray(inertia, dtype=float)) <= top):
        return f"an inertia entry is outside the physical range (within ±{top:g} kg·m²)"
    return None


def _read_geometry(rd: Reader, value: Any, n: int, assumed: dict) -> list[Capsule | Sphere]:
    rows = rd.array_of_tables(value, "geometry")
    out: list[Capsule | Sphere] = []
    for i, row in enumerate(rows):
        key = f"geometry[{i + 1}]"
        rd.table(row, key, {"link", "shape", "a", "b", "center", "radius", "assumed", "reason"})
        if rd.assumption(row, key)[0]:
            assumed[key] = row["reason"]
        link = _link_index(rd, row.get("link"), f"{key}.link", n)
        shape = rd.string(row.get("shape"), f"{key}.shape", ("capsule", "sphere"))
        radius = rd.positive(row.get("radius"), f"{key}.radius") * rd.length
        _in_range(rd, f"{key}.radius", "length", radius)
        if shape == "capsule":
            for k in ("a", "b"):
                if k not in row:
                    raise rd.fail(f"{key}.{k}", "missing; expected 3 numbers (segment end)")
            a = rd.vector(row["a"], f"{key}.a", 3) * rd.length
            b = rd.vector(row["b"], f"{key}.b", 3) * rd.length
            _in_range(rd, f"{key}.a", "point", a)
            _in_range(rd, f"{key}.b", "point", b)
            out.append(Capsule(link, a, b, radius))
        else:
            if "center" not in row:
                raise rd.fail(f"{key}.center", "missing; expected 3 numbers")
            c = rd.vector(row["center"], f"{key}.center", 3) * rd.length
            _in_range(rd, f"{key}.center", "point", c)
            out.append(Sphere(link, c, radius))
    return out


def _in_range(rd: Reader, key: str, what: str, values_m) -> None:
    unit = next(name for name, scale in LENGTH_UNITS.items() if scale == rd.length)
    if problem := geometry_problem(what, np.atleast_1d(values_m), unit):
        raise rd.fail(key, problem)


def _link_index(rd: Reader, value: Any, key: str, n: int) -> int:
    if not isinstance(value, int) or isinstance(value, bool) or not 0 <= value <= n:
        raise rd.fail(key, f"expected a link number 0..{n} (0 = base), got {_show(value)}")
    return value


def _read_inertials(rd: Reader, value: Any, n: int, geometry, assumed: dict) -> list[Inertial]:
    """``[[inertials]]``: ``link``, ``mass`` (kg), ``com`` (length unit) and ``inertia``
    ``[ixx, iyy, izz, ixy, ixz, iyz]`` (kg·m², about the com) — or
    ``inertia = "from_geometry"``: a uniform solid filling the link's collision shapes."""
    rows = rd.array_of_tables(value, "inertials")
    default_reason = assumed.get("inertials", "")
    out = []
    seen: set[int] = set()
    for i, row in enumerate(rows):
        key = f"inertials[{i + 1}]"
        rd.table(row, key, {"link", "mass", "com", "inertia", "assumed", "reason"})
        flag, _ = rd.assumption(row, key)
        flag = flag or (bool(default_reason) and "assumed" not in row)
        link = _link_index(rd, row.get("link"), f"{key}.link", n)
        if link in seen:
            raise rd.fail(f"{key}.link", f"link {link} already has an inertial entry")
        seen.add(link)
        mass = rd.positive(row.get("mass"), f"{key}.mass")
        if problem := inertial_problem(mass):
            raise rd.fail(f"{key}.mass", problem)
        raw = row.get("inertia")
        if raw == "from_geometry":
            shapes = [g for g in geometry if g.link == link]
            if not shapes:
                raise rd.fail(f"{key}.inertia", f"'from_geometry' but link {link} has no geometry")
            com, inertia = solid_inertia(shapes, mass)
            if "com" in row:
                raise rd.fail(f"{key}.com", "not used with inertia = 'from_geometry'")
        else:
            com = rd.vector(row.get("com"), f"{key}.com", 3) * rd.length
            _in_range(rd, f"{key}.com", "point", com)
            inertia = _inertia_matrix(rd, raw, f"{key}.inertia")
        out.append(Inertial(link, mass, com, inertia, assumed=flag))
    return out


def _inertia_matrix(rd: Reader, raw: Any, key: str) -> np.ndarray:
    ixx, iyy, izz, ixy, ixz, iyz = rd.vector(raw, key, 6)
    if problem := inertial_problem(None, [ixx, iyy, izz, ixy, ixz, iyz]):
        raise rd.fail(key, problem)
    m = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
    ev = np.linalg.eigvalsh(m)
    if ev[0] < -1e-12 or ev[0] + ev[1] < ev[2] - 1e-9 * max(1.0, ev[2]):
        raise rd.fail(key, "expected a physical inertia (positive, triangle inequality)")
    return m


def solid_inertia(shapes, mass: float) -> tuple[np.ndarray, np.ndarray]:
    """Centre of mass and inertia (about it) of uniform solids filling ``shapes``."""
    parts = []  # (volume, com, inertia per unit density about own com)
    for g in shapes:
        if isinstance(g, Sphere):
            v = 4.0 / 3.0 * math.pi * g.radius**3
            parts.append((v, g.center, 0.4 * v * g.radius**2 * np.eye(3)))
            continue
        r, axis = g.radius, g.b - g.a
        h = float(np.linalg.norm(axis))
        u = axis / h if h > 0 else np.array([0.0, 0.0, 1.0])
        m_cyl = math.pi * r * r * h
        m_hs = 2.0 / 3.0 * math.pi * r**3
        i_ax = m_cyl * r * r / 2.0 + 2 * m_hs * 0.4 * r * r
        i_perp = m_cyl * (r * r / 4 + h * h / 12) + 2 * m_hs * (
            0.4 * r * r + h * h / 4 + 3 * h * r / 8
        )
        inertia = i_perp * (np.eye(3) - np.outer(u, u)) + i_ax * np.outer(u, u)
        parts.append((m_cyl + 2 * m_hs, (g.a + g.b) / 2, inertia))
    volume = sum(p[0] for p in parts)
    rho = mass / volume
    com = sum(p[0] * p[1] for p in parts) / volume
    total = np.zeros((3, 3))
    for v, c, inertia in parts:
        d = c - com
        total += rho * (inertia + v * (float(d @ d) * np.eye(3) - np.outer(d, d)))
    return com, total


# ----------------------------------------------------------------------------- URDF-backed


def _from_urdf(rd: Reader, robot: dict, folder: Path, doc: dict) -> tuple[list[Joint], dict]:
    """``[robot] urdf = "file.urdf"``: chain, limits, inertials, geometry from the URDF; the
    TOML may override name, home, tool, base, weights (``[[joints]]`` with name + weight)."""
    from irlc.robots import urdf_import

    rel = rd.string(robot["urdf"], "robot.urdf")
    tip = rd.string(robot["tip"], "robot.tip") if "tip" in robot else None
    path = (folder / rel).resolve()
    if not path.is_file():
        raise rd.fail("robot.urdf", f"file not found: {path}")
    model = urdf_import.load_urdf(path, tip=tip)
    joints = list(model.joints)
    if "joints" in doc:
        rows = rd.array_of_tables(doc["joints"], "joints")
        if len(rows) != len(joints):
            raise rd.fail(
                "joints", f"expected {len(joints)} entries to match the URDF, got {len(rows)}"
            )
        from dataclasses import replace

        for i, row in enumerate(rows):
            key = f"joints[{i + 1}]"
            rd.table(row, key, {"name", "weight", "accel", "jerk", "assumed", "reason"})
            rd.assumption(row, key)
            if "name" in row and row["name"] != joints[i].name:
                raise rd.fail(f"{key}.name", f"expected {joints[i].name!r} (URDF order)")
            if "weight" in row:
                joints[i] = replace(joints[i], weight=rd.positive(row["weight"], f"{key}.weight"))
            if "accel" in row:
                accel = _pair(rd, row["accel"], f"{key}.accel", _scale(rd, joints[i].kind))
                limits = replace(joints[i].limits, accel=accel)
                joints[i] = replace(joints[i], limits=limits)
                model.extra["assumed"].pop(f"joint '{joints[i].name}' acceleration", None)
            if "jerk" in row:
                jerk = rd.positive(row["jerk"], f"{key}.jerk") * _scale(rd, joints[i].kind)
                joints[i] = replace(joints[i], limits=replace(joints[i].limits, jerk=jerk))
    fixed = {
        "urdf_extra": model.extra,
        "flange": model.flange,
        "tool": model.tool,
        "home": model.home,
        "geometry": model.geometry,
        "inertials": model.inertials,
    }
    return joints, fixed
