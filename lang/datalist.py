"""Data lists (``IMPORT DATALIST name;``): taught poses, configurations, obstacles, inputs.

A data list is a TOML file ``name.toml`` found in the program's folder, then in each
``--datalist-path`` directory, then in the robot library's ``datalists`` folder. Sections
(docs/language.md §8, plus ``[limits]``)::

    [poses]               name = [x, y, z, a, b, c]        mm, deg (ZYX)
    [joints]              name = [q1, ..., qN]             deg / mm per joint
    [limits]              name = { type = "MAIN_JOINT_MIN" | ... , values = [N numbers] }
    [obstacles.NAME]      kind = point|sphere|box|capsule|plane and its keys (mm)
    [inputs]              "n" = [[time_s, bool], ...]      times non-decreasing
    [platform]            name = y  |  name = [x, y]       mm: a platform target

Every problem is a :class:`Diagnostic` naming the file and the key (with the key's line
when it can be found in the text).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

from irlc.lang import platform
from irlc.lang.diagnostics import Diagnostic, Span
from irlc.lang.file_access import describe, is_file, is_finite_number, is_finite_real, shown_key
from irlc.lang.irdata import (
    JOINT_TUPLE_TYPES,
    OBSTACLE_KEYS,
    ObstacleDef,
    Value,
    obstacle_field_problem,
)
from irlc.lang.textfile import read_user_text
from irlc.lang.toml_keys import TomlError, key_position, parse_toml

SECTIONS = ("poses", "joints", "limits", "obstacles", "inputs", "platform")
_IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


@dataclass(frozen=True)
class Item:
    """A named value of a data list: a global constant of the program."""

    name: str
    value: Value
    file: str
    key: str  # e.g. "poses.poz_1"
    span: Span | None


@dataclass
class Datalist:
    name: str
    path: str  # as used for reading (for diagnostics)
    shown_path: str  # provenance written to the IRDATA DATALIST record
    items: list[Item] = field(default_factory=list)
    obstacles: list[tuple[ObstacleDef, Item]] = field(default_factory=list)
    inputs: dict[int, list[tuple[float, bool]]] = field(default_factory=dict)
    # names of entries that failed their check (reported here): the checker declares them
    # as errors, so that a program's use is not a second "unknown name" error
    rejected: list[str] = field(default_factory=list)


def library_folder() -> Path | None:
    try:
        return Path(str(resources.files("irlc.robots") / "datalists"))
    except (ModuleNotFoundError, TypeError):
        return None


def find(
    name: str, program_dir: Path, search_path: tuple[str, ...]
) -> tuple[Path | None, list[str]]:
    """Locate ``name.toml``; return the path (or None) and the folders searched."""
    searched = []
    for folder in folders(program_dir, search_path):
        candidate = folder / f"{name}.toml"
        searched.append(str(folder) if str(folder) else ".")
        if is_file(candidate):
            return candidate, searched
    return None, searched


def folders(program_dir: Path, search_path: tuple[str, ...]) -> list[Path]:
    """Where data lists are searched, in order — also the only folders a data list may lie
    in once resolved (``irlc.lang.file_access``): the program's folder, each search-path
    folder, the library's ``datalists`` folder."""
    out = [program_dir, *(Path(p) for p in search_path)]
    lib = library_folder()
    if lib is not None:
        out.append(lib)
    return out


def shown_path(path: Path, program_dir: Path) -> str:
    """A machine-independent provenance string for the IRDATA header."""
    lib = library_folder()
    try:
        if lib is not None and path.resolve().parent == lib.resolve():
            return f"irlc.robots:datalists/{path.name}"
    except OSError:
        pass
    try:
        return path.resolve().relative_to(program_dir.resolve()).as_posix()
    except (ValueError, OSError):
        return str(path)


class _Loader:
    def __init__(self, path: Path, text: str, joint_count: int | tuple[int, ...] | None):
        self.file = str(path)
        self.text = text
        self.n = joint_count
        self.diags: list[Diagnostic] = []

    def error(self, key: str, message: str, hint: str | None = None) -> None:
        span = self.key_span(key)
        message = f"key '{shown_key(key)}': {message}"
        self.diags.append(Diagnostic("error", message, self.file, span, hint))

    def key_span(self, key: str) -> Span | None:
        """Best-effort position of ``key`` (``table.sub.name``) in the TOML text."""
        position = key_position(self.text, key)
        return Span(*position) if position else None

    def numbers(
        self, value, key: str, size: int | tuple[int, ...] | None, what: str
    ) -> tuple[float, ...] | None:
        """A list of ``size`` finite numbers (a tuple of sizes: one of them), else an error."""
        if not isinstance(value, list):
            self.error(key, f"expected {what}, got {_show(value)}")
            return None
        bad = next((i for i, v in enumerate(value) if not _is_number(v)), None)
        if bad is not None:  # (a list of numbers but one: "got a list of 3 values" read odd)
            self.error(key, f"value {bad + 1} is not a number: {_show(value[bad])} ({what})")
            return None
        sizes = (size,) if isinstance(size, int) else size
        if sizes is not None and len(value) not in sizes:
            shown = " or ".join(str(n) for n in sizes)
            self.error(key, f"expected {shown} numbers ({what}), got {len(value)}")
            return None
        if not all(is_finite_number(v) for v in value):
            self.error(key, "numbers must be finite")
            return None
        return tuple(float(v) for v in value)


def _is_number(v) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool)


def _show(v) -> str:
    return describe(v)


def load(
    name: str,
    path: Path,
    program_dir: Path,
    joint_count: int | tuple[int, ...] | None,
    text: str | None = None,
) -> tuple[Datalist, list[Diagnostic]]:
    """Read and validate one data list; ``joint_count`` None skips joint-arity checks (a
    tuple: the joint counts of a cell's robots, a joint value has one of them); ``text``:
    the data list's text, read instead of the file (an editor's buffer)."""
    dl = Datalist(name, str(path), shown_path(path, program_dir))
    if text is None:
        try:
            text = read_user_text(path, lambda file, reason: ValueError(reason))
        except ValueError as e:  # missing, unreadable, not UTF-8 (the byte's line)
            return dl, [Diagnostic("error", f"cannot read data list: {e}", str(path))]
    ld = _Loader(path, text, joint_count)
    try:
        doc = parse_toml(text)
    except TomlError as e:
        span = Span(e.line, e.column or 1) if e.line else None
        return dl, [Diagnostic("error", f"invalid TOML: {e.reason}", str(path), span)]
    for section, body in doc.items():
        if section not in SECTIONS:
            ld.error(section, "unknown section", f"data list sections: {', '.join(SECTIONS)}")
        elif not isinstance(body, dict):
            ld.error(section, f"expected a table, got {_show(body)}")
        else:
            _SECTION_READERS[section](ld, dl, body)
    return dl, ld.diags


def _item(ld: _Loader, dl: Datalist, key: str, name: str, value: Value) -> None:
    if not _IDENT.fullmatch(name):
        ld.error(key, f"'{shown_key(name)}' is not a valid IRL name (letters, digits, '_')")
        return
    dl.items.append(Item(name, value, ld.file, key, ld.key_span(key)))


def _read_poses(ld: _Loader, dl: Datalist, body: dict) -> None:
    for name, value in body.items():
        key = f"poses.{name}"
        nums = ld.numbers(value, key, 6, "x, y, z in mm and a, b, c in degrees")
        if nums is not None:
            _item(ld, dl, key, name, Value("POSE", nums))
        else:
            dl.rejected.append(name)


def _read_joints(ld: _Loader, dl: Datalist, body: dict) -> None:
    for name, value in body.items():
        key = f"joints.{name}"
        nums = ld.numbers(value, key, ld.n, "one value per joint")
        if nums is not None:
            _item(ld, dl, key, name, Value("MAIN_JOINT", nums))
        else:
            dl.rejected.append(name)


def _read_limits(ld: _Loader, dl: Datalist, body: dict) -> None:
    for name, value in body.items():
        key = f"limits.{name}"
        if not isinstance(value, dict):
            ld.error(
                key, f'expected {{ type = "MAIN_JOINT_MIN", values = [...] }}, got {_show(value)}'
            )
            continue
        extra = sorted(set(value) - {"type", "values"})
        if extra:
            ld.error(f"{key}.{extra[0]}", "unknown key; a limit has 'type' and 'values'")
            continue
        ty = value.get("type")
        limit_types = JOINT_TUPLE_TYPES[1:]
        if ty not in limit_types:
            ld.error(f"{key}.type", f"expected one of {', '.join(limit_types)}, got {_show(ty)}")
            continue
        nums = ld.numbers(value.get("values"), f"{key}.values", ld.n, "one value per joint")
        if nums is not None:
            _item(ld, dl, key, name, Value(ty, nums))


def _read_platform(ld: _Loader, dl: Datalist, body: dict) -> None:
    """``[platform]``: targets of a robot's platform (``WITH PLATFORM := name``), mm: a
    number (one coordinate: a REAL) or a list of 1 … 3 (an ARRAY [1..k] OF REAL); the
    checker counts them against the robot's platform where they are used."""
    sizes = tuple(range(1, platform.MAX_COORDINATES + 1))
    for name, value in body.items():
        key = f"platform.{name}"
        raw = [value] if _is_number(value) else value
        nums = ld.numbers(raw, key, sizes, "a platform target: its coordinates in mm")
        if nums is not None:
            _item(ld, dl, key, name, platform.constant(nums))
        else:
            dl.rejected.append(name)


def _read_obstacles(ld: _Loader, dl: Datalist, body: dict) -> None:
    for name, table in body.items():
        key = f"obstacles.{name}"
        if not isinstance(table, dict):
            ld.error(key, f"expected a table [obstacles.{name}], got {_show(table)}")
            continue
        kind = table.get("kind")
        if not isinstance(kind, str) or kind not in OBSTACLE_KEYS:
            ld.error(
                f"{key}.kind", f"expected one of {', '.join(OBSTACLE_KEYS)}, got {_show(kind)}"
            )
            continue
        spec = OBSTACLE_KEYS[kind]
        allowed = {"kind", *(k for k, _, _ in spec)}
        unknown = sorted(set(table) - allowed)
        if unknown:
            ld.error(
                f"{key}.{unknown[0]}",
                f"unknown key for a {kind}; keys: {', '.join(sorted(allowed))}",
            )
            continue
        fields = _obstacle_fields(ld, key, kind, table, spec)
        if fields is None or not _IDENT.fullmatch(name):
            if fields is not None:
                ld.error(key, f"'{shown_key(name)}' is not a valid IRL name (letters, digits, '_')")
            continue
        o = ObstacleDef(name, kind, tuple(fields))
        dl.obstacles.append((o, Item(name, Value("OBSTACLE", ()), ld.file, key, ld.key_span(key))))


def _obstacle_fields(ld: _Loader, key: str, kind: str, table: dict, spec) -> list | None:
    fields = []
    ok = True
    for k, size, required in spec:
        if k not in table:
            if required:
                ld.error(key, f"a {kind} needs '{k}'")
                ok = False
            continue
        raw = table[k]
        if size == 1:
            if not is_finite_real(raw) or raw <= 0:
                ld.error(f"{key}.{k}", f"expected a positive number (mm), got {_show(raw)}")
                ok = False
                continue
            if problem := obstacle_field_problem(k, (float(raw),)):
                ld.error(f"{key}.{k}", problem)
                ok = False
                continue
            fields.append((k, (float(raw),)))
            continue
        nums = ld.numbers(raw, f"{key}.{k}", size, f"{size} numbers")
        if nums is None:
            ok = False
        elif problem := obstacle_field_problem(k, nums):
            ld.error(f"{key}.{k}", problem)
            ok = False
        else:
            fields.append((k, nums))
    return fields if ok else None


def _read_inputs(ld: _Loader, dl: Datalist, body: dict) -> None:
    for name, events in body.items():
        key = f"inputs.{name}"
        if not re.fullmatch(r"[0-9]{1,18}", name):  # ASCII digits, inside the 64-bit range
            ld.error(key, "input keys are input numbers (0, 1, 2, ...)")
            continue
        timeline = _timeline(ld, key, events)
        if timeline is not None:
            dl.inputs[int(name)] = timeline


def _timeline(ld: _Loader, key: str, events) -> list[tuple[float, bool]] | None:
    shape = "a list of [time_s, true|false] pairs"
    if not isinstance(events, list):
        ld.error(key, f"expected {shape}, got {_show(events)}")
        return None
    out: list[tuple[float, bool]] = []
    for ev in events:
        if not (
            isinstance(ev, list) and len(ev) == 2 and _is_number(ev[0]) and isinstance(ev[1], bool)
        ):
            ld.error(key, f"expected {shape}, got the event {_show(ev)}")
            return None
        if not is_finite_number(ev[0]) or ev[0] < 0:
            ld.error(key, f"event times must be finite and >= 0, got {_show(ev[0])}")
            return None
        t = float(ev[0])
        if out and t < out[-1][0]:
            ld.error(key, f"event times must not decrease ({out[-1][0]} then {t})")
            return None
        out.append((t, ev[1]))
    return out


_SECTION_READERS = {
    "poses": _read_poses,
    "joints": _read_joints,
    "limits": _read_limits,
    "obstacles": _read_obstacles,
    "inputs": _read_inputs,
    "platform": _read_platform,
}
