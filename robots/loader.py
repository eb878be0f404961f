"""Load and validate a robot description file (TOML) into a :class:`RobotModel`.

The format is documented in ``docs/robots.md``. Every value is checked; a bad file raises
:class:`RobotFileError` naming the file, the key (``joints[3].axis``) and the expected
shape. File units are ``[robot].units`` (default: ``angle = "deg"``, ``length = "m"``);
joint values follow the joint kind (revolute → angle unit, prismatic → length unit).
Everything is converted to SI here, once.

This module reads the top level (``[robot]``, ``[base]``, ``[flange]``, ``[tool]``,
``[assumptions]``, ``[ik]``, ``[reachability]``, a URDF-backed chain) and hands each
section to its reader: :mod:`~irlc.robots.toml_reader` (typed values, units, errors),
:mod:`~irlc.robots.chain` (``[[joints]]``: DH or axes), :mod:`~irlc.robots.limits`
(joint limits, home, limit sets, coupled limits), :mod:`~irlc.robots.inertia`
(``[[geometry]]``, ``[[inertials]]``), :mod:`~irlc.robots.transmission` and
:mod:`~irlc.robots.platform` (``[platform]``). ``[drives]``
is stored unvalidated for :mod:`irlc.runtime.drives.params`.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
from irlc.lang.file_access import ALLOW_HINT, describe, inside_roots, is_file, refusal, shown
from irlc.lang.textfile import read_user_text
from irlc.lang.toml_keys import TomlError, parse_toml
from irlc.robots.chain import read_chain
from irlc.robots.extends import inherit
from irlc.robots.inertia import read_geometry, read_inertials
from irlc.robots.limits import read_coupled, read_home, read_limit_sets, read_pair, read_rate
from irlc.robots.model import TASK_COMPONENTS, Joint, RobotModel
from irlc.robots.platform import read_platform
from irlc.robots.toml_reader import (
    ANGLE_UNITS,
    LENGTH_UNITS,
    MissingExtraError,
    Reader,
    RobotFileError,
    show,
)
from irlc.robots.transmission import read_transmission

__all__ = ["MissingExtraError", "RobotFileError", "build_model", "load_toml"]

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
    "platform",
}
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

# ----------------------------------------------------------------------------- entry


def load_toml(path: str | Path, roots: tuple[Path, ...] | None = None) -> RobotModel:
    """Parse and validate one TOML robot file (raises :class:`RobotFileError`). ``roots``:
    the folders a URDF or a parent file (``[robot] extends``, :mod:`~irlc.robots.extends`)
    the file names must lie in (a program's robot file, :mod:`irlc.lang.file_access`);
    ``None``: anywhere."""
    path = Path(path)
    file = str(path)
    text = read_user_text(path, lambda f, reason: RobotFileError(f, "", reason))
    try:
        doc = parse_toml(text)
    except TomlError as e:
        raise RobotFileError(file, "", f"not valid TOML: {e.reason}", e.line) from None
    doc, parents = inherit(doc, path, roots)
    model = build_model(doc, file, path.parent, roots)
    if parents:
        model.extra["extends"] = [str(p) for p in parents]
    return model


def _read_ik(rd: Reader, table: Any) -> dict:
    """``[ik] task = ["x", "y"]``: the pose-error components the inverse transformation
    controls (default all six; a planar arm controls only its plane's position).
    ``closed_form = "<family>"``: the robot's closed-form IK family
    (:mod:`irlc.runtime.ik.closed_form`)."""
    from irlc.runtime.ik.closed_form import FAMILY_NAMES

    ik = rd.table(table, "ik", {"task", "closed_form"})
    out = {}
    if "closed_form" in ik:
        out["closed_form"] = rd.string(ik["closed_form"], "ik.closed_form", FAMILY_NAMES)
    if "task" not in ik:
        return out
    task = ik["task"]
    if not isinstance(task, list) or not task:
        raise rd.fail("ik.task", f"expected a non-empty list of {', '.join(TASK_COMPONENTS)}")
    names = [rd.string(c, f"ik.task[{i}]", TASK_COMPONENTS) for i, c in enumerate(task)]
    if len(set(names)) != len(names):
        raise rd.fail("ik.task", "a component is listed twice")
    return {**out, "task": names}


def build_model(
    doc: dict, file: str, folder: Path, roots: tuple[Path, ...] | None = None
) -> RobotModel:
    rd = Reader(file)
    rd.table(doc, "", TOP_KEYS)
    if "robot" not in doc:
        raise rd.fail("robot", "missing table [robot]")
    robot = rd.table(doc["robot"], "robot", ROBOT_KEYS)
    _read_units(rd, robot)
    assumed = _read_assumptions(rd, doc)
    if "urdf" in robot:
        joints, fixed = _from_urdf(rd, robot, folder, doc, roots)
    else:
        joints, fixed = read_chain(rd, robot, doc, assumed)
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
    home = read_home(rd, robot, joints, fixed.get("home"))
    geometry = fixed.get("geometry", ())
    if "geometry" in doc:
        geometry = read_geometry(rd, doc["geometry"], n, assumed)
    inertials = fixed.get("inertials", ())
    if "inertials" in doc:
        inertials = read_inertials(rd, doc["inertials"], n, geometry, assumed)
    extra: dict[str, Any] = {"assumed": assumed, "units": {"angle": rd.angle, "length": rd.length}}
    if "urdf_extra" in fixed:
        assumed.update(fixed["urdf_extra"]["assumed"])
        extra["urdf_notes"] = fixed["urdf_extra"]["urdf_notes"]
        extra["urdf"] = fixed["urdf_extra"]["urdf"]
    if "drives" in doc:  # owned by the drives area: stored unvalidated
        extra["drives"] = doc["drives"]
    if "coupled_limits" in doc:
        extra["coupled_limits"] = read_coupled(rd, doc["coupled_limits"], joints)
    if "transmission" in doc:
        extra["transmission"] = read_transmission(rd, doc["transmission"], joints, assumed)
    if "reachability" in doc:
        extra["reachability"] = _read_reachability(rd, doc["reachability"], n)
    if "ik" in doc:
        extra["ik"] = _read_ik(rd, doc["ik"])
    for k in ("source", "notes"):
        if k in robot:
            extra[k] = rd.string(robot[k], f"robot.{k}")
    limit_sets = read_limit_sets(rd, doc.get("limit_sets", {}), joints)
    model = RobotModel(
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
    if "platform" in doc:  # needs the chain's kinematics: read once the model is built
        rows = len(extra.get("ik", {}).get("task", TASK_COMPONENTS))
        extra["platform"] = read_platform(rd, doc["platform"], model, rows)
    return model


def _read_units(rd: Reader, robot: dict) -> None:
    units = rd.table(robot.get("units", {}), "robot.units", {"angle", "length"})
    angle = rd.string(units.get("angle", "deg"), "robot.units.angle", tuple(ANGLE_UNITS))
    length = rd.string(units.get("length", "m"), "robot.units.length", tuple(LENGTH_UNITS))
    rd.set_units(angle, length)


def _read_assumptions(rd: Reader, doc: dict) -> dict[str, str]:
    """``[assumptions]``: section name → reason; marks every entry of that section."""
    table = rd.table(doc.get("assumptions", {}), "assumptions")
    return {k: rd.string(v, f"assumptions.{k}") for k, v in table.items()}


def _read_reachability(rd: Reader, value: Any, n: int) -> dict:
    t = rd.table(value, "reachability", {"type", "plane_joint", "text"})
    kind = rd.string(t.get("type", "vertical_plane"), "reachability.type", ("vertical_plane",))
    j = t.get("plane_joint", 1)
    if not isinstance(j, int) or isinstance(j, bool) or not 1 <= j <= n:
        raise rd.fail("reachability.plane_joint", f"expected a joint number 1..{n}, got {show(j)}")
    return {
        "type": kind,
        "plane_joint": j - 1,
        "text": rd.string(t.get("text", ""), "reachability.text"),
    }


# ----------------------------------------------------------------------------- URDF-backed


def _from_urdf(
    rd: Reader, robot: dict, folder: Path, doc: dict, roots: tuple[Path, ...] | None
) -> tuple[list[Joint], dict]:
    """``[robot] urdf = "file.urdf"``: chain, limits, inertials, geometry from the URDF; the
    TOML may override name, home, tool, base, weights (``[[joints]]`` with name + weight).
    With ``roots`` (a program's robot file) the URDF must lie inside them, once resolved."""
    from irlc.robots import urdf_import

    rel = rd.string(robot["urdf"], "robot.urdf")
    tip = rd.string(robot["tip"], "robot.tip") if "tip" in robot else None
    path = folder / rel
    if roots is not None and not inside_roots(path, roots):
        raise rd.fail("robot.urdf", f"{shown(path)}: {refusal(roots)}; {ALLOW_HINT}")
    if not is_file(path):
        raise rd.fail("robot.urdf", f"file not found: {shown(path)}")
    path = path.resolve()
    model = urdf_import.load_urdf(path, tip=tip)
    joints = list(model.joints)
    if "joints" in doc:
        rows = rd.array_of_tables(doc["joints"], "joints")
        if len(rows) != len(joints):
            raise rd.fail(
                "joints", f"expected {len(joints)} entries to match the URDF, got {len(rows)}"
            )
        for i, row in enumerate(rows):
            key = f"joints[{i + 1}]"
            rd.table(row, key, {"name", "weight", "accel", "jerk", "assumed", "reason"})
            rd.assumption(row, key)
            if "name" in row and row["name"] != joints[i].name:
                urdf_name = describe(joints[i].name)
                raise rd.fail(f"{key}.name", f"expected the URDF's joint {i + 1}, {urdf_name}")
            if "weight" in row:
                joints[i] = replace(joints[i], weight=rd.positive(row["weight"], f"{key}.weight"))
            if "accel" in row:
                accel = read_pair(rd, row["accel"], f"{key}.accel", rd.scale(joints[i].kind))
                limits = replace(joints[i].limits, accel=accel)
                joints[i] = replace(joints[i], limits=limits)
                model.extra["assumed"].pop(f"joint '{joints[i].name}' acceleration", None)
            if "jerk" in row:
                jerk = read_rate(rd, row["jerk"], f"{key}.jerk", rd.scale(joints[i].kind))
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
