"""Write a :class:`RobotModel` as a self-contained TOML description (``chain = "axes"``).

Why: a robot imported from URDF needs the optional ``yourdfpy`` at every load; written
out once in the core format, the same model loads on a core install. The writer is the
inverse of :mod:`irlc.robots.loader` for the sections it covers, so
``load_toml(write(m)) == m`` up to the round-off of the deg ↔ rad conversion (~1e-16).

Mapping (file units: deg for angles, m for lengths, as every shipped robot file):

* joint ``i``: ``origin`` = the model's ``origin_i`` (pose of joint ``i``'s frame in link
  ``i−1``'s frame) as ``{xyz, zyx}`` with ``R = Rz(a)·Ry(b)·Rx(c)`` — or as a 4×4
  ``matrix`` near the ZYX singularity ``|b| = 90°`` —, ``link = 0`` (the whole fixed
  transform sits in the next joint's ``origin``), the unit ``axis``, limits, weight and
  offset;
* ``[flange]``, ``[tool]``, ``[base]``: the model's transforms; the loader composes
  ``flange = Tz(link_n) · [flange]`` with ``link_n = 0``;
* ``[[geometry]]`` (capsules, spheres) and ``[[inertials]]`` (mass, com, inertia about the
  com as ``[ixx, iyy, izz, ixy, ixz, iyz]``) per link;
* ``[assumptions]``: the model's ``extra["assumed"]`` and, for a URDF import, its
  conversion notes.

Limit sets, coupled limits, transmissions, drives, reachability and ``[ik]`` are not
written (a model that has them raises :class:`ValueError`): the shipped URDF robot has none.

Command line (regenerates the shipped core copy of a URDF robot; needs ``irlc[urdf]``)::

    python -m irlc.robots.toml_export robots/urdf/panda.toml robots/panda.toml
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
from irlc.lang.toml_text import InlineTable, dumps
from irlc.robots.model import Capsule, RobotModel
from irlc.runtime.model.spatial import matrix_to_zyx

DEG = 180.0 / math.pi
NOT_WRITTEN = ("coupled_limits", "transmission", "drives", "reachability", "ik")


def _vec(values) -> list[float]:
    return [float(v) for v in values]


def _transform(t: np.ndarray) -> InlineTable:
    """A rigid transform as ``xyz``, ``zyx`` (deg) — or ``matrix`` near gimbal lock, where
    ZYX angles lose digits."""
    if abs(t[2, 0]) > 1.0 - 1e-6:
        return InlineTable(matrix=[_vec(row) for row in t])
    zyx = [a * DEG for a in matrix_to_zyx(t[:3, :3])]
    return InlineTable(xyz=_vec(t[:3, 3]), zyx=zyx)


def _scale(kind: str) -> float:
    return DEG if kind == "revolute" else 1.0


def _robot_table(model: RobotModel) -> dict:
    out = {
        "name": model.name,
        "description": model.description,
        "chain": "axes",
        "units": InlineTable(angle="deg", length="m"),
        "gravity": _vec(model.gravity),
    }
    if model.home is not None:
        out["home"] = [h * _scale(j.kind) for h, j in zip(model.home, model.joints, strict=True)]
    if "source" in model.extra:
        out["source"] = model.extra["source"]
    return out


def _assumptions(model: RobotModel) -> dict:
    assumed = dict(model.extra.get("assumed", {}))
    notes = sorted(set(model.extra.get("urdf_notes", [])))
    if notes:
        assumed["urdf_conversion"] = "; ".join(notes)
    return dict(sorted(assumed.items()))


def _joints(model: RobotModel) -> list[dict]:
    out = []
    for j in model.joints:
        s = _scale(j.kind)
        lim = j.limits
        row = {
            "name": j.name,
            "kind": j.kind,
            "axis": _vec(j.axis),
            "origin": _transform(j.origin),
            "position": _vec(np.array(lim.position) * s),
            "speed": _vec(np.array(lim.speed) * s),
            "accel": _vec(np.array(lim.accel) * s),
            "weight": float(j.weight),
        }
        if lim.jerk is not None:
            row["jerk"] = lim.jerk * s
        if j.offset != 0.0:
            row["offset"] = j.offset * s
        out.append(row)
    return out


def _geometry(model: RobotModel) -> list[dict]:
    out = []
    for g in model.geometry:
        row: dict = {"link": g.link}
        if isinstance(g, Capsule):
            row |= {"shape": "capsule", "a": _vec(g.a), "b": _vec(g.b)}
        else:
            row |= {"shape": "sphere", "center": _vec(g.center)}
        out.append(row | {"radius": float(g.radius)})
    return out


def _inertials(model: RobotModel) -> list[dict]:
    out = []
    for m in model.inertials:
        i = m.inertia
        six = [i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2]]
        row = {"link": m.link, "mass": float(m.mass), "com": _vec(m.com), "inertia": _vec(six)}
        if m.assumed:
            row |= {"assumed": True, "reason": "assumed in the source description"}
        out.append(row)
    return out


def model_to_toml(model: RobotModel, header: str = "") -> str:
    """The TOML text of ``model`` (see the module doc); ``header``: leading comment lines.
    A non-finite number is a :class:`ValueError`."""
    left = [k for k in NOT_WRITTEN if k in model.extra] + (["limit_sets"] * bool(model.limit_sets))
    if left:
        raise ValueError(f"robot {model.name}: cannot write {', '.join(left)} (not supported)")
    doc: dict = {"robot": _robot_table(model)}
    if assumptions := _assumptions(model):
        doc["assumptions"] = assumptions
    for label, t in (("base", model.base), ("flange", model.flange), ("tool", model.tool)):
        doc[label] = dict(_transform(t))
    doc |= {"joints": _joints(model), "geometry": _geometry(model)}
    doc["inertials"] = _inertials(model)
    return dumps(doc, header=header, finite=True)


def generated_header(source: Path, target: Path) -> str:
    return (
        f"{target.name}: GENERATED from {source} (do not edit: edit the source and run\n"
        f"`python -m irlc.robots.toml_export {source} {target}` in the repository).\n"
        "The same model in the core format, so it loads without the optional yourdfpy;\n"
        "tests/robots/test_panda_core.py checks it equals the URDF import."
    )


def main(argv: list[str]) -> int:
    from irlc.robots import load_robot

    if len(argv) != 2:
        print("usage: python -m irlc.robots.toml_export SOURCE.toml|.urdf OUT.toml")
        return 3
    source, target = Path(argv[0]), Path(argv[1])
    text = model_to_toml(load_robot(source), generated_header(source, target))
    target.write_text(text, encoding="utf-8")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
