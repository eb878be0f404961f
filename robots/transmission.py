"""The drive train of a robot file: ``[transmission]``, how each motor moves its joint
(a ratio with couplings to earlier joints, or a ball screw on a lever), stored in SI for
:mod:`irlc.runtime.model.motor_maps`.
"""

from __future__ import annotations

import math
from typing import Any

from irlc.robots.model import Joint
from irlc.robots.toml_reader import Reader, show


def read_transmission(rd: Reader, value: Any, joints: list[Joint], assumed: dict) -> list[dict]:
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
        raise rd.fail(key, f"expected a list of [joint, factor] pairs, got {show(value)}")
    pairs = []
    for k, p in enumerate(value):
        if not isinstance(p, list) or len(p) != 2 or not isinstance(p[0], int):
            raise rd.fail(
                f"{key}[{k}]", f"expected [joint (1-based integer), factor], got {show(p)}"
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
