"""Joint limits of a robot file: each joint's ``position`` / ``speed`` / ``accel`` /
``jerk``, ``[robot].home`` inside them, named ``[limit_sets.NAME]``, and
``[[coupled_limits]]`` (``min ≤ Σ c_j q_j ≤ max``). Bounds are given in file units (a
pair ``[min, max]`` or a number ``v`` for ``±v``) and stored in SI.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from irlc.robots.model import Joint, Limits
from irlc.robots.toml_reader import Reader, show

MAX_LIMIT_SI = 1e9
"""The largest magnitude of a joint bound in SI (m or rad, per s, s², s³): a bound beyond
it is a typo, and converted to mm it could overflow to infinity in the output."""


def limit_problem(values_si, scale: float) -> str | None:
    """Why a bound (SI) is beyond :data:`MAX_LIMIT_SI`, in file units (``scale``: the SI
    size of one), else None."""
    for v in np.atleast_1d(values_si):
        if not abs(v) <= MAX_LIMIT_SI:
            top = MAX_LIMIT_SI / scale
            return f"{v / scale:g} is outside the range of a joint bound (within ±{top:g})"
    return None


def read_pair(rd: Reader, value: Any, key: str, scale: float) -> tuple[float, float]:
    """``[min, max]`` or a positive number ``v`` meaning ``[-v, v]``; checks min ≤ max and
    the range (:func:`limit_problem`)."""
    if isinstance(value, list):
        lo, hi = rd.vector(value, key, 2)
    else:
        v = rd.positive(value, key)
        lo, hi = -v, v
    if lo > hi:
        raise rd.fail(key, f"expected min ≤ max, got [{lo:g}, {hi:g}]")
    if problem := limit_problem([lo * scale, hi * scale], scale):
        raise rd.fail(key, problem)
    return lo * scale, hi * scale


def read_rate(rd: Reader, value: Any, key: str, scale: float) -> float:
    """A positive bound (``jerk``) in SI, in the range of :func:`limit_problem`."""
    v = rd.positive(value, key) * scale
    if problem := limit_problem([v], scale):
        raise rd.fail(key, problem)
    return v


def read_joint_limits(rd: Reader, row: dict, key: str, kind: str) -> Limits:
    s = rd.scale(kind)
    for k in ("position", "speed", "accel"):
        if k not in row:
            raise rd.fail(f"{key}.{k}", "missing; expected [min, max] (or a number v for ±v)")
    pos = read_pair(rd, row["position"], f"{key}.position", s)
    speed = read_pair(rd, row["speed"], f"{key}.speed", s)
    accel = read_pair(rd, row["accel"], f"{key}.accel", s)
    for k, (lo, hi) in (("speed", speed), ("accel", accel)):
        if not lo < 0.0 < hi:
            raise rd.fail(
                f"{key}.{k}", "expected min < 0 < max (the joint must be able to move both ways)"
            )
    jerk = read_rate(rd, row["jerk"], f"{key}.jerk", s) if "jerk" in row else None
    return Limits(pos, speed, accel, jerk)


def read_home(rd: Reader, robot: dict, joints: list[Joint], default) -> np.ndarray | None:
    if "home" not in robot:
        return default
    values = rd.vector(robot["home"], "robot.home", len(joints))
    home = np.array([v * rd.scale(j.kind) for v, j in zip(values, joints, strict=True)])
    for i, (h, j) in enumerate(zip(home, joints, strict=True)):
        lo, hi = j.limits.position
        if not lo - 1e-12 <= h <= hi + 1e-12:
            raise rd.fail(
                f"robot.home[{i}]", f"joint {j.name} home value is outside its position limits"
            )
    return home


def read_limit_sets(rd: Reader, table: Any, joints: list[Joint]) -> dict[str, tuple[Limits, ...]]:
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
                    f"expected {len(joints)} entries ([min, max] or a number), got {show(rows)}",
                )
            per_kind[k] = [
                read_pair(rd, r, f"{key}.{k}[{i}]", rd.scale(j.kind))
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


def read_coupled(rd: Reader, value: Any, joints: list[Joint]) -> list[dict]:
    """``[[coupled_limits]]``: ``min ≤ Σ c_j q_j ≤ max`` over joints of one kind (file units).

    Stored in SI: ``{name, kind, coeffs (n,), lower, upper, text}`` (``kind``: the joints'
    kind, which gives the bounds' unit; ``assumed``: the reason, for a row marked
    ``assumed = true``); ``lower``/``upper`` may be ``-inf``/``inf`` when ``min``/``max``
    is absent."""
    rows = rd.array_of_tables(value, "coupled_limits")
    out = []
    for i, row in enumerate(rows):
        key = f"coupled_limits[{i + 1}]"
        rd.table(row, key, {"name", "coeffs", "min", "max", "text", "assumed", "reason"})
        row_assumed, row_reason = rd.assumption(row, key)
        coeffs = rd.vector(row.get("coeffs"), f"{key}.coeffs", len(joints))
        used = [j.kind for j, c in zip(joints, coeffs, strict=True) if c != 0.0]
        if not used:
            raise rd.fail(f"{key}.coeffs", "expected at least one non-zero coefficient")
        if len(set(used)) > 1:
            raise rd.fail(f"{key}.coeffs", "expected joints of one kind only (units must match)")
        s = rd.scale(used[0])
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
                **({"assumed": row_reason} if row_assumed else {}),
            }
        )
    return out
