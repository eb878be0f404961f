"""Dotted parameter paths of a study and how a value is put where it belongs.

A path starts with its target:

* ``run.KEY`` — an option of the run (``ipo``, ``drives``, ``path_tolerance`` …), the
  same checks as ``irlc run`` (:mod:`irlc.runtime.run`, the settings table for ``ipo``);
* ``robot.…`` — a value of the robot description file (its own units, e.g. deg and m for
  koch11): ``robot.joints.10.weight``, ``robot.joints.J10.speed``,
  ``robot.inertials.3.mass``, ``robot.base.xyz``, ``robot.drives.dc.r``…; ``robot.at`` the
  robot's placement; in a cell ``robot.NAME.…`` (which robot's: :mod:`irlc.study.robots`);
* ``datalist.NAME.…`` — a value of a data list the program imports (mm, deg):
  ``datalist.cell.obstacles.post.center``, ``datalist.square_cell.poses.poz_1.1``.

Inside a document, a whole number indexes a list **from 1** (joint 1 … N, like
``a1 … aN``; the x of a pose is ``.1``); an array of tables (``[[joints]]``) may also be
indexed by a row's ``name``. Two spellings read better and mean the same:
``robot.joints.a10.weight`` (the program's joint name ``aN`` = joint N) and
``datalist.cell.poses.poz_1.x`` (a pose's ``x y z a b c`` = ``1 … 6``).

The meaning of the new value (type, range) is checked by the owner of the document — the
robot loader, the data-list loader — never here.
"""

from __future__ import annotations

import re
from typing import Any

from irlc.lang.errors import IrlcError
from irlc.lang.file_access import describe

TARGETS = ("run", "robot", "datalist")
POSE = ("x", "y", "z", "a", "b", "c")  # a pose's components, in order
_A_N = re.compile(r"[aA][1-9][0-9]*")  # a program joint name aN


class PathError(IrlcError, ValueError):
    """The path does not name a value of its document (the message says why)."""


RUN_KEYS = (
    "ipo",
    "drives",
    "path_tolerance",
    "orientation_tolerance",
    "instruction_budget",
    "seed_config",
    "max_time",
    "max_cycles",
    "override",
    "allow_collisions",
)


def target(key: str) -> tuple[str, list[str]]:
    """``"robot.joints.10.weight"`` → ``("robot", ["joints", "10", "weight"])``."""
    head, _, rest = key.partition(".")
    if head not in TARGETS or not rest:
        raise PathError("unknown key; a varied key starts with run.KEY, robot.… or datalist.NAME.…")
    parts = rest.split(".")
    if head == "robot" and len(parts) > 1 and parts[0] == "joints":
        parts[1] = joint_index(parts[1])
    if head == "datalist" and len(parts) == 4 and parts[1] == "poses" and parts[3] in POSE:
        parts[3] = str(POSE.index(parts[3]) + 1)  # poz_1.x → poz_1.1
    return head, parts


def joint_index(part: str) -> str:
    """A program joint name ``aN`` → ``N`` (joint N of a robot file's ``[[joints]]``)."""
    return part[1:] if _A_N.fullmatch(part) else part


def check_run_value(key: str, value: Any) -> str | None:
    """``None`` if ``value`` is admissible for the run option ``key``, else why not (the
    run's own checks: :func:`irlc.runtime.run.check_run_option`)."""
    from irlc.runtime.run import check_run_option

    if key not in RUN_KEYS:
        return f"unknown run option; run.KEY is one of {', '.join(RUN_KEYS)}"
    return check_run_option(key, value)


def set_value(doc: Any, parts: list[str], value: Any, create: bool) -> None:
    """Put ``value`` at ``parts`` inside the parsed TOML ``doc`` (changed in place).

    ``create``: a missing last key of a table is added (the document's loader decides
    whether it is allowed); otherwise it is a :class:`PathError`."""
    node = doc
    for i, part in enumerate(parts):
        last = i == len(parts) - 1
        where = ".".join(parts[: i + 1])
        if isinstance(node, list):
            idx = _index(node, part, where)
            if last:
                _same_kind(node[idx], value, where)
                node[idx] = value
                return
            node = node[idx]
        elif isinstance(node, dict):
            if part not in node:
                if last and create:
                    node[part] = value
                    return
                if create and not last:
                    node[part] = {}
                else:
                    known = ", ".join(sorted(str(k) for k in node)) or "nothing"
                    raise PathError(f"'{where}' is not in the file (there: {known})")
            if last:
                _same_kind(node[part], value, where)
                node[part] = value
                return
            node = node[part]
        else:
            raise PathError(f"'{'.'.join(parts[:i])}' is a value, it has no '{part}'")


def get_value(doc: Any, parts: list[str]) -> Any:
    """The value at ``parts`` (``PathError`` if there is none)."""
    node = doc
    for i, part in enumerate(parts):
        where = ".".join(parts[: i + 1])
        if isinstance(node, list):
            node = node[_index(node, part, where)]
        elif isinstance(node, dict) and part in node:
            node = node[part]
        else:
            raise PathError(f"'{where}' is not in the file")
    return node


def _index(node: list, part: str, where: str) -> int:
    """A 1-based list index, or the position of the table whose ``name`` is ``part``."""
    if part.isdigit():
        i = int(part)
        if not 1 <= i <= len(node):
            raise PathError(f"'{where}': index {i} outside 1 … {len(node)} (indices count from 1)")
        return i - 1
    for k, row in enumerate(node):
        if isinstance(row, dict) and str(row.get("name", "")).lower() == part.lower():
            return k
    raise PathError(f"'{where}': expected an index 1 … {len(node)} or a row's name")


def _same_kind(old: Any, new: Any, where: str) -> None:
    """A number stays a number, a list a list of the same length, a string a string."""

    def kind(v: Any) -> str:
        if isinstance(v, bool):
            return "true/false"
        if isinstance(v, int | float):
            return "a number"
        if isinstance(v, str):
            return "a string"
        if isinstance(v, list):
            return "a list"
        return "a table"

    if kind(old) != kind(new):
        raise PathError(f"'{where}' is {kind(old)} in the file, got {describe(new)}")
    if isinstance(old, list) and len(old) != len(new):
        raise PathError(f"'{where}' has {len(old)} values in the file, got {len(new)}")
