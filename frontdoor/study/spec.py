"""The study file (``STUDY.toml``): what to run and what to vary. Read and checked here.

Format (docs/studies.md)::

    program = "../square.irl"        # relative to the study file (required)
    robot = "koch11"                 # optional: overrides the program's ROBOT clause
                                     # (refused for a cell: robot.NAME.… keys instead)
    datalist_path = ["cells"]        # optional: folders IMPORT DATALIST searches
    name = "w10"                     # optional: shown in the summary

    [run]                            # optional: options of every variant (as `irlc run`)
    ipo = 0.01                       # s
    drives = "ideal"                 # ideal | decoupled | coupled | pwm
    path_tolerance = 0.05            # mm
    orientation_tolerance = 0.01     # deg
    instruction_budget = 500000
    seed_config = [0, 90, -90]       # deg | mm
    max_time = 60                    # s: the simulated-time budget
    max_cycles = 50000               # IPO cycles of motion: the cycle budget
    override = 100                   # %: R_OVERRIDE's start value

    [grid]                           # every combination of the listed values
    "robot.joints.10.weight" = [5.0, 20.0]

    [random]                         # n samples drawn with seed (numpy PCG64)
    n = 100
    seed = 1
    "datalist.cell.obstacles.post.center.1" = { uniform = [900, 1100] }
    "robot.inertials.3.mass" = { normal = [700, 35] }

Keys of ``[grid]`` and ``[random]`` may be written quoted (one key with dots) or as TOML
dotted keys; both name the same path (:mod:`irlc.study.paths`). With both tables the
variants are every grid point crossed with every random sample, grid-major.

Every problem raises :class:`StudyError` naming the study file and the line of the key
(``tomllib`` gives no positions, so the line is searched in the text: :func:`key_line`).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from irlc.errors import UsageError
from irlc.files import read_user_text
from irlc.lang.file_access import describe, is_finite_real
from irlc.lang.toml_keys import TomlError, parse_toml
from irlc.study import confine
from irlc.study.paths import RUN_KEYS, check_run_value

TOP_KEYS = ("program", "robot", "datalist_path", "name", "run", "grid", "random", "output")
OUTPUT_KEYS = ("reports", "traces")
DISTRIBUTIONS = ("uniform", "normal")
NORMAL_REACH = 40  # sigmas: farther than any sample numpy's normal() draws in float64
MAX_VARIANTS = 10_000_000  # a guard against a typo such as n = 1e9


class StudyError(UsageError):
    """A bad study file (exit 3): ``FILE:LINE: key: message``."""

    def __init__(self, file: str, line: int | None, key: str, message: str):
        self.file, self.line, self.key, self.message = file, line, key, message
        where = f"{file}:{line}" if line else file
        super().__init__(f"{where}: {key}: {message}" if key else f"{where}: {message}")


@dataclass(frozen=True)
class Axis:
    """One varied parameter: its dotted path and how its values come about."""

    key: str  # e.g. "robot.joints.10.weight"
    section: str  # "grid" | "random"
    values: tuple = ()  # grid: the listed values
    distribution: str = ""  # random: "uniform" | "normal"
    params: tuple[float, float] = (0.0, 0.0)  # (a, b) or (mu, sigma)


@dataclass
class Study:
    file: Path
    text: str
    program: Path
    robot: str | None = None
    datalist_path: tuple[Path, ...] = ()
    name: str = ""
    run: dict[str, Any] = field(default_factory=dict)
    grid: list[Axis] = field(default_factory=list)
    random: list[Axis] = field(default_factory=list)
    n: int = 0
    seed: int = 0
    reports: bool = False  # [output] reports: DIR/variants/variant_NNNNNNN.report.json
    traces: bool = False  # [output] traces: DIR/variants/variant_NNNNNNN.trace.csv

    @property
    def axes(self) -> list[Axis]:
        return [*self.grid, *self.random]

    @property
    def keys(self) -> list[str]:
        return [a.key for a in self.axes]

    def line(self, key: str) -> int | None:
        return key_line(self.text, key)

    def error(self, key: str, message: str, section: str | None = None) -> StudyError:
        full = ".".join(p for p in (section, key) if p)
        return StudyError(str(self.file), self.line(full), full, message)


# --------------------------------------------------------------------------- line search

_HEADER = re.compile(r"^\s*\[\s*([^\[\]]+?)\s*\]\s*(#.*)?$")
_ASSIGN = re.compile(
    r"^\s*((?:\"[^\"]*\"|'[^']*'|[A-Za-z0-9_\-]+)(?:\s*\.\s*(?:\"[^\"]*\"|'[^']*'|[A-Za-z0-9_\-]+))*)\s*="
)


def _norm(key_text: str) -> str:
    """A TOML key as written (``a . "b.c"``) → the dotted path ``a.b.c``."""
    parts = re.findall(r"\"([^\"]*)\"|'([^']*)'|([A-Za-z0-9_\-]+)", key_text)
    return ".".join(next(p for p in groups if p) if any(groups) else "" for groups in parts)


def key_line(text: str, key: str) -> int | None:
    """The 1-based line of ``key`` (a dotted path such as ``grid.robot.joints.10.weight``)
    in the TOML ``text``: the line whose table header plus assigned key equals it, else the
    line of the longest such prefix (a table that holds it), else ``None``."""
    best: tuple[int, int] | None = None  # (matched length, line)
    table = ""
    for no, raw in enumerate(text.splitlines(), start=1):
        m = _HEADER.match(raw)
        if m:
            table = _norm(m.group(1))
            path = table
        else:
            m = _ASSIGN.match(raw)
            if not m:
                continue
            path = f"{table}.{_norm(m.group(1))}" if table else _norm(m.group(1))
        if path == key:
            return no
        if key.startswith(path + ".") and (best is None or len(path) > best[0]):
            best = (len(path), no)
    return best[1] if best else None


# --------------------------------------------------------------------------- reading


def read_study(path: str | Path, allow_any_path: bool = False) -> Study:
    """Parse and check the study file's own structure (not yet the values' meaning: that
    needs the program and the robot, :func:`irlc.study.plan.build_plan`); the files it
    names are confined (:mod:`irlc.study.confine`) unless ``allow_any_path``."""
    path = Path(path)
    text = read_user_text(path, lambda f, reason: StudyError(f, None, "", reason))
    try:
        doc = parse_toml(text)  # every way tomllib fails, with a line (lang/toml_keys.py)
    except TomlError as e:
        raise StudyError(str(path), e.line, "", f"invalid TOML: {e.reason}") from None
    study = Study(file=path, text=text, program=Path())
    for key in doc:
        if key not in TOP_KEYS:
            raise study.error(key, f"unknown key; a study file has {', '.join(TOP_KEYS)}")
    _read_top(study, doc, allow_any_path)
    study.run = _read_run(study, doc.get("run", {}))
    if "grid" in doc:
        study.grid = _read_grid(study, _table(study, doc["grid"], "grid"))
    if "random" in doc:
        _read_random(study, _table(study, doc["random"], "random"))
    if not study.axes:
        raise study.error("", "nothing varies: add a [grid] or a [random] table")
    dup = _duplicate([a.key for a in study.axes])
    if dup:
        sections = [a.section for a in study.axes if a.key == dup]
        if len(set(sections)) > 1:
            where = "both in [grid] and in [random]"
        else:  # one table: two spellings of one key ("run.override" and run.override)
            where = f"twice in [{sections[0]}] (two spellings of one key)"
        raise study.error(dup, f"varied {where}", sections[-1])
    count = count_variants(study)
    if count > MAX_VARIANTS:
        raise study.error("", f"{describe(count)} variants; at most {MAX_VARIANTS:,}")
    return study


def count_variants(study: Study) -> int:
    grid = math.prod(len(a.values) for a in study.grid) if study.grid else 1
    return grid * (study.n if study.random else 1)


def _duplicate(keys: list[str]) -> str | None:
    seen: set[str] = set()
    for k in keys:
        if k in seen:
            return k
        seen.add(k)
    return None


def _table(study: Study, value: Any, key: str) -> dict:
    if not isinstance(value, dict):
        raise study.error(key, f"expected a table [{key}], got {_show(value)}")
    return value


def _show(v: Any) -> str:
    text = repr(v)
    return text if len(text) <= 60 else text[:57] + "..."


def _read_top(study: Study, doc: dict, allow_any_path: bool) -> None:
    def named(key: str, written: str) -> Path:
        """``written`` relative to the study file, resolved, and allowed (confine.py)."""
        resolved = (study.file.parent / written).resolve()
        problem = None if allow_any_path else confine.refusal(written, resolved, study.file)
        if problem:
            raise study.error(key, problem)
        return resolved

    program = doc.get("program")
    if not isinstance(program, str) or not program:
        raise study.error("program", "required: the program's path, relative to the study file")
    study.program = named("program", program)
    if not study.program.is_file():
        raise study.error("program", f"{program}: no such file (relative to the study file)")
    robot = doc.get("robot")
    if robot is not None and (not isinstance(robot, str) or not robot):
        raise study.error("robot", f"expected a robot name or file, got {_show(robot)}")
    from irlc.robots import is_robot_path

    if robot is not None and is_robot_path(robot):  # a file: relative to the study file
        robot = str(named("robot", robot))
    study.robot = robot
    dl = doc.get("datalist_path", [])
    if not isinstance(dl, list) or not all(isinstance(p, str) for p in dl):
        raise study.error("datalist_path", f"expected a list of folders, got {_show(dl)}")
    study.datalist_path = tuple(named("datalist_path", p) for p in dl)
    for written, folder in zip(dl, study.datalist_path, strict=True):
        if not folder.is_dir():  # as irlc run --datalist-path: a misspelt folder is an error
            raise study.error(
                "datalist_path", f"{written}: no such folder (relative to the study file)"
            )
    name = doc.get("name", study.file.stem)
    if not isinstance(name, str):
        raise study.error("name", f"expected a string, got {_show(name)}")
    study.name = name
    out = _table(study, doc.get("output", {}), "output")
    for k in out:
        if k not in OUTPUT_KEYS:
            raise study.error(k, f"unknown key; [output] has {', '.join(OUTPUT_KEYS)}", "output")
    for k in OUTPUT_KEYS:
        if not isinstance(out.get(k, False), bool):
            raise study.error(k, "expected true or false", "output")
    study.reports = bool(out.get("reports", False))
    study.traces = bool(out.get("traces", False))


def _read_run(study: Study, value: Any) -> dict:
    run = _table(study, value, "run")
    for k, v in run.items():
        if k not in RUN_KEYS:
            raise study.error(k, f"unknown key; [run] has {', '.join(RUN_KEYS)}", "run")
        problem = check_run_value(k, v)
        if problem:
            raise study.error(k, problem, "run")
    return dict(run)


def flatten(table: dict, prefix: str = "") -> list[tuple[str, Any]]:
    """``{"robot": {"joints": {"10": {"weight": [...]}}}}`` → ``[("robot.joints.10.weight",
    [...])]``; a table that names a distribution (``{uniform = [a, b]}``) is a leaf."""
    out: list[tuple[str, Any]] = []
    for k, v in table.items():
        key = f"{prefix}.{k}" if prefix else k
        if isinstance(v, dict) and not (set(v) & set(DISTRIBUTIONS)):
            out += flatten(v, key)
        else:
            out.append((key, v))
    return out


def _read_grid(study: Study, table: dict) -> list[Axis]:
    axes = []
    for key, values in flatten(table):
        if not isinstance(values, list) or not values:
            raise study.error(
                key, f"expected a non-empty list of values, got {_show(values)}", "grid"
            )
        twice = _repeated(values)
        if twice is not None:
            raise study.error(
                key, f"value {_show(twice)} is listed twice: each grid value is one variant", "grid"
            )
        axes.append(Axis(key, "grid", values=tuple(values)))
    return axes


def _repeated(values: list):
    """The first value listed again (``1`` and ``1.0`` are one value), else ``None``."""
    seen: list = []
    for v in values:
        if any(type(v) is type(u) or (_number(v) and _number(u)) for u in seen if u == v):
            return v
        seen.append(v)
    return None


def _number(v) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool)


def _read_random(study: Study, table: dict) -> None:
    for k, what in (("n", "the number of samples"), ("seed", "the random generator's seed")):
        if k not in table:
            raise study.error(k, f"required: {what}, a whole number ([random] {k} = …)", "random")
        v = table[k]
        if isinstance(v, bool) or not isinstance(v, int):
            raise study.error(k, f"{what}: expected a whole number, got {_show(v)}", "random")
    if not 1 <= table["n"] <= MAX_VARIANTS:
        raise study.error(
            "n", f"must be 1 to {MAX_VARIANTS:,}, got {describe(table['n'])}", "random"
        )
    if table["seed"] < 0:
        raise study.error("seed", f"must be 0 or more, got {describe(table['seed'])}", "random")
    study.n, study.seed = table["n"], table["seed"]
    rest = {k: v for k, v in table.items() if k not in ("n", "seed")}
    for key, spec in flatten(rest):
        study.random.append(_distribution(study, key, spec))
    if not study.random:
        raise study.error("", "[random] names no key to vary", "random")


def _distribution(study: Study, key: str, spec: Any) -> Axis:
    expected = "{ uniform = [a, b] } or { normal = [mu, sigma] }"
    if not isinstance(spec, dict) or len(spec) != 1 or next(iter(spec)) not in DISTRIBUTIONS:
        raise study.error(key, f"expected {expected}, got {_show(spec)}", "random")
    dist, params = next(iter(spec.items()))
    ok = isinstance(params, list) and len(params) == 2 and all(is_finite_real(p) for p in params)
    if not ok:
        raise study.error(
            key, f"{dist}: expected two finite numbers, got {_show(params)}", "random"
        )
    a, b = float(params[0]), float(params[1])
    if dist == "uniform" and not a < b:
        raise study.error(key, f"uniform = [a, b] needs a < b, got [{a:g}, {b:g}]", "random")
    if dist == "normal" and not b > 0:
        raise study.error(key, f"normal = [mu, sigma] needs sigma > 0, got {b:g}", "random")
    if not math.isfinite(b - a if dist == "uniform" else abs(a) + NORMAL_REACH * b):
        raise study.error(key, f"{dist} = [{a:g}, {b:g}]: samples beyond a float's range",
                          "random")  # fmt: skip
    return Axis(key, "random", distribution=dist, params=(a, b))
