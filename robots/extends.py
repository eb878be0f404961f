"""``[robot] extends``: a robot file that is another robot file with a few changes.

A variant of a library robot (another reading of a published limit, other drive gains, a
heavier payload) need not repeat the whole file::

    [robot]
    name = "irb6_sym5"
    extends = "irb6"                  # a library name, or a file relative to this one
    description = "…"

    [[coupled_limits]]                # the row of the same name in irb6.toml, changed
    name = "theta5-theta234/k5"
    min = -180.0
    max = 180.0

The parent document is read first (it may extend another; a cycle or a chain deeper than
:data:`MAX_DEPTH` is an error), then the child is laid over it:

* ``[robot]`` and ``[assumptions]``: key by key, the child's value wins; ``name`` (default:
  the child's file name) and ``extends`` are not inherited; the child may not set
  ``units`` (the parent's values are written in the parent's units, which stay the file's);
* ``[[joints]]`` and ``[[coupled_limits]]``: a child row merges key by key into the
  parent's row of the same ``name``; a joint row must name a joint of the parent (the chain
  is the parent's), a coupled-limit row with a new name is appended;
* every other top-level table (``[tool]``, ``[drives]``, ``[[inertials]]``, …) replaces the
  parent's whole.

A parent's ``[robot] urdf`` is resolved relative to the parent's folder. A file a
*program* names (``roots`` given, :mod:`irlc.lang.file_access`) may extend only files inside
the same roots. The merged document is then validated as any robot file; its
``extra["extends"]`` lists the parent files (resolved), so caches can see them change.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from irlc.lang.file_access import ALLOW_HINT, inside_roots, is_file, refusal, shown
from irlc.lang.textfile import read_user_text
from irlc.lang.toml_keys import TomlError, parse_toml
from irlc.robots.toml_reader import Reader, RobotFileError

MAX_DEPTH = 8
"""The longest chain of ``extends`` (a deeper one is refused as a likely cycle)."""

LIBRARY = Path(__file__).resolve().parent
MERGED_BY_KEY = ("robot", "assumptions")
MERGED_BY_NAME = ("joints", "coupled_limits")
NOT_INHERITED = ("extends", "name")


def inherit(
    doc: dict, path: Path, roots: tuple[Path, ...] | None, _chain: tuple[Path, ...] = ()
) -> tuple[dict, list[Path]]:
    """``doc`` (the parsed file ``path``) with its ``extends`` resolved: the merged
    document and the parent files, nearest first. A document without ``extends`` is
    returned as it is."""
    robot = doc.get("robot")
    if not isinstance(robot, dict) or "extends" not in robot:
        return doc, []
    rd = Reader(str(path))
    if "units" in robot:
        raise rd.fail("robot.units", "a file that extends another keeps the parent's units")
    parent_path = _parent_file(rd, robot["extends"], path, roots)
    chain = (*_chain, path.resolve())
    if parent_path in chain:
        raise rd.fail("robot.extends", f"{shown(parent_path)} extends this file again (a cycle)")
    if len(chain) > MAX_DEPTH:
        raise rd.fail("robot.extends", f"more than {MAX_DEPTH} files extend one another")
    parent_doc = _parse(parent_path)
    parent_doc, grand = inherit(parent_doc, parent_path, roots, chain)
    _pin_urdf(parent_doc, parent_path)
    return merge(rd, parent_doc, doc), [parent_path, *grand]


def merge(rd: Reader, parent: dict, child: dict) -> dict:
    """``child`` laid over ``parent`` by the rules of the module doc (new dicts; the inputs
    are not changed)."""
    out = dict(parent)
    for key, value in child.items():
        if key in MERGED_BY_KEY and isinstance(value, dict):
            base = {k: v for k, v in out.get(key, {}).items() if k not in NOT_INHERITED}
            out[key] = {**base, **value}
        elif key in MERGED_BY_NAME and isinstance(value, list):
            out[key] = _merge_rows(rd, key, out.get(key, []), value)
        else:
            out[key] = value
    robot = out.get("robot", {})
    out["robot"] = {k: v for k, v in robot.items() if k != "extends"}
    return out


def _merge_rows(rd: Reader, key: str, parent_rows: Any, rows: list) -> list:
    merged = [dict(r) if isinstance(r, dict) else r for r in parent_rows]
    names = {r.get("name"): i for i, r in enumerate(merged) if isinstance(r, dict)}
    for i, row in enumerate(rows):
        where = f"{key}[{i + 1}]"
        if not isinstance(row, dict) or not isinstance(row.get("name"), str):
            raise rd.fail(f"{where}.name", "a row of a file that extends another needs a name")
        if row["name"] in names:
            merged[names[row["name"]]] = {**merged[names[row["name"]]], **row}
        elif key == "joints":
            raise rd.fail(f"{where}.name", f"no joint '{row['name']}' in the parent robot")
        else:
            names[row["name"]] = len(merged)
            merged.append(dict(row))
    return merged


def _parent_file(rd: Reader, value: Any, path: Path, roots: tuple[Path, ...] | None) -> Path:
    """The file ``extends`` names: a library robot name, or a ``.toml`` file relative to
    the extending file's folder (inside ``roots`` when given)."""
    text = rd.string(value, "robot.extends")
    named_file = text.lower().endswith(".toml") or "/" in text or "\\" in text
    candidate = path.parent / text if named_file else LIBRARY / f"{text.lower()}.toml"
    if named_file and roots is not None and not inside_roots(candidate, roots):
        raise rd.fail("robot.extends", f"{shown(candidate)}: {refusal(roots)}; {ALLOW_HINT}")
    if not text or not is_file(candidate):
        what = "file not found" if named_file else "no library robot of that name"
        raise rd.fail("robot.extends", f"{what}: {text}")
    return candidate.resolve()


def _parse(path: Path) -> dict:
    text = read_user_text(path, lambda f, reason: RobotFileError(f, "", reason))
    try:
        return parse_toml(text)
    except TomlError as e:
        raise RobotFileError(str(path), "", f"not valid TOML: {e.reason}", e.line) from None


def _pin_urdf(doc: dict, path: Path) -> None:
    """A parent's relative ``[robot] urdf`` made absolute (it is relative to the parent)."""
    robot = doc.get("robot")
    if isinstance(robot, dict) and isinstance(robot.get("urdf"), str):
        robot["urdf"] = str(path.parent / robot["urdf"])
