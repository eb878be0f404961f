"""The kinematic chain of a robot file: ``[robot].chain`` and the ``[[joints]]`` rows.

* ``"dh"``: standard DH rows ``A_i = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i)``; the joint variable
  (θ for revolute, d for prismatic) is ``q_i + offset_i``. Since ``Rz`` and ``Tz``
  commute, the fixed part ``F_i = Tz(d) Rz(θ) Tx(a) Rx(α)`` (without the variable)
  becomes ``origin_{i+1}`` and ``F_n`` the start of the flange.
* ``"axes"``: per joint an ``axis`` (in the joint frame), an optional ``origin``
  transform, and a ``link`` vector from this joint to the next one (to the flange for
  the last joint), expressed in the frame the joint moves.

Each row also carries the joint's limits (:mod:`irlc.robots.limits`), ``offset`` and
``weight`` (the redundancy resolution's, default ``n − i``).
"""

from __future__ import annotations

import numpy as np
from irlc.lang.joint_kinds import KINDS
from irlc.robots.limits import read_joint_limits
from irlc.robots.model import Joint
from irlc.robots.toml_reader import Reader, show
from irlc.runtime.model.spatial import rot_x, rot_z, transform

AXIS_NAMES = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}
AXIS_NAMES.update({"-" + k: tuple(-c for c in v) for k, v in list(AXIS_NAMES.items())})

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


def read_chain(rd: Reader, robot: dict, doc: dict, assumed: dict) -> tuple[list[Joint], dict]:
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
        kind = rd.string(row["kind"], f"{key}.kind", KINDS)
        j_assumed, reason = rd.assumption(row, key)
        if j_assumed:
            assumed[key] = reason
        if chain == "dh":
            axis, this_origin, after = dh_row(rd, row, key, kind)
        else:
            axis, this_origin, after = axes_row(rd, row, key)
        limits = read_joint_limits(rd, row, key, kind)
        offset = rd.number(row.get("offset", 0.0), f"{key}.offset") * rd.scale(kind)
        weight = rd.positive(row.get("weight", n - i), f"{key}.weight")
        joints.append(
            Joint(name, kind, origin @ this_origin, axis, limits, offset=offset, weight=weight)
        )
        origin = after
    return joints, {"flange": origin}


def dh_row(rd: Reader, row: dict, key: str, kind: str):
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
    rd.in_range(f"{key}.dh.a", "point", a)
    d = theta = 0.0
    if kind == "revolute":
        d = rd.number(dh.get("d", 0.0), f"{key}.dh.d") * rd.length
        rd.in_range(f"{key}.dh.d", "point", d)
    else:
        theta = rd.number(dh.get("theta", 0.0), f"{key}.dh.theta") * rd.angle
    after = (
        transform(None, (0.0, 0.0, d))
        @ transform(rot_z(theta))
        @ transform(None, (a, 0.0, 0.0))
        @ transform(rot_x(alpha))
    )
    return np.array([0.0, 0.0, 1.0]), np.eye(4), after


def axes_row(rd: Reader, row: dict, key: str):
    if "dh" in row:
        raise rd.fail(f"{key}.dh", "not used with chain = 'axes' (give axis, link, origin)")
    if "axis" not in row:
        raise rd.fail(f"{key}.axis", "missing; expected 'x', 'y', 'z' (or '-x', ...) or 3 numbers")
    raw = row["axis"]
    if isinstance(raw, str):
        if raw not in AXIS_NAMES:
            raise rd.fail(f"{key}.axis", f"expected one of x, y, z, -x, -y, -z, got {show(raw)}")
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
    rd.in_range(f"{key}.link", "point", link)
    return axis, this_origin, transform(None, link)
