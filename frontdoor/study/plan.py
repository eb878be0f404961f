"""From a read study file to a :class:`Plan` the workers run, checked before anything runs.

The program is compiled once here (:func:`irlc.api.compile_program`); every value of every
varied key is put into its document and checked by that document's owner — run options by
the run's checks, robot values by the robot loader (``build_model``, and the drive data
reader for ``robot.drives.…``), a placement by the run's check of ``AT``, data-list values
by the data-list loader — so a bad value is reported with the study file's line before the
first variant starts. A random key is checked at its smallest and largest sample. The
program's robots — one, or a cell's — are :class:`~irlc.study.robots.PlanRobot` s.
"""

from __future__ import annotations

import copy
import hashlib
import json
import tempfile
import tomllib
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from irlc.lang.file_access import describe
from irlc.lang.irdata import Code
from irlc.runtime import engine_policy
from irlc.study import paths
from irlc.study.expand import axis_values
from irlc.study.robots import (
    PlanRobot,
    VariantSetupError,
    check_placement,
    placement,
    robot_key,
    robot_model,
    robot_named,
)
from irlc.study.spec import Study, StudyError, count_variants

__all__ = ["Plan", "VariantSetupError", "build_plan", "check_value", "datalist_text"]


@dataclass(frozen=True)
class Plan:
    """Everything a worker needs (picklable; sent once per worker)."""

    token: str  # the study file, program, robot file and data lists: caches, resume check
    program: str  # absolute path
    program_text: str
    robot: str | None
    datalist_path: tuple[str, ...]
    run: dict[str, Any]
    code: Code  # the program compiled once
    keys: tuple[str, ...]
    robots: tuple[PlanRobot, ...] = ()  # the program's robots (a cell's: several)
    datalists: dict[str, tuple[str, dict]] = field(default_factory=dict)  # name → (file, doc)
    joints: tuple[tuple[str, str], ...] = ()  # (program name, unit) per joint; a cell's
    # prefixed by their robot's name (holder_a1), as the trace and the report name them
    obstacles: tuple[str, ...] = ()
    drives: bool = False  # some variant simulates the drives
    variants_dir: str | None = None  # where per-variant reports / traces go
    reports: bool = False
    traces: bool = False
    allow_any_path: bool = False  # the program's robot file and data lists may lie anywhere
    engine: str | None = None  # "compiled": every variant on the kernels (engine_policy.py)

    @property
    def program_dir(self) -> Path:
        return Path(self.program).parent

    @property
    def cell(self) -> tuple[str, ...]:
        """A cell's robot names (record order); ``()`` for a program of one robot."""
        return tuple(r.var for r in self.robots) if len(self.robots) > 1 else ()


def build_plan(
    study: Study, variants_dir: Path | None = None, allow_any_path: bool = False
) -> Plan:
    """Compile the program, load the documents the keys change, check every value;
    ``allow_any_path``: ``--allow-any-path`` (``irlc.lang.file_access``)."""
    from irlc.runtime import units
    from irlc.runtime.run import RunSetupError, load_model

    if study.robot is not None:  # a bad robot is the study file's error, up front
        try:
            load_model(study.robot, study.file.parent)
        except RunSetupError as e:
            raise study.error("robot", str(e)) from None
    code = _code(study, allow_any_path)
    for axis in study.axes:
        try:
            paths.target(axis.key)
        except paths.PathError as e:
            raise study.error(axis.key, str(e), axis.section) from None
    robots = _robots(study, code)
    models = [_model(study, r) for r in robots]
    datalists = _datalist_docs(study, code)
    text = study.program.read_text(encoding="utf-8")
    drives = study.run.get("drives", "ideal") != "ideal"
    values = axis_values(study)
    if "run.drives" in values:
        drives = drives or any(v != "ideal" for v in values["run.drives"])
    engine = engine_policy.for_study(count_variants(study))  # the installation's, per study
    docs = [r.doc for r in robots] if len(robots) > 1 else robots[0].doc
    inputs = [study.text, text, json.dumps([docs, datalists], sort_keys=True, default=str)]
    inputs.append(f"engine={engine}")  # --resume with another engine: another study's bytes
    joints = []
    for r, model in zip(code.robots, models, strict=True):
        for name, kind in zip(r.joint_names, model.joint_kinds, strict=True):
            joints.append((f"{r.var}_{name}" if code.is_cell else name, units.joint_unit(kind)))
    plan = Plan(
        token=hashlib.sha256("\0".join(inputs).encode()).hexdigest()[:16],
        program=str(study.program),
        program_text=text,
        robot=study.robot,
        datalist_path=tuple(str(p) for p in study.datalist_path),
        run=dict(study.run),
        code=code,
        keys=tuple(study.keys),
        robots=robots,
        datalists=datalists,
        joints=tuple(joints),
        obstacles=tuple(o.name for o in code.obstacles),
        drives=drives,
        allow_any_path=allow_any_path,
        engine=engine,
        variants_dir=str(variants_dir) if variants_dir is not None else None,
        reports=study.reports,
        traces=study.traces,
    )
    for axis in study.axes:
        problem = key_problem(plan, axis.key)
        if problem:
            raise study.error(axis.key, problem, axis.section)
        for value in values[axis.key]:
            problem = check_value(plan, axis.key, value)
            if problem:
                raise study.error(axis.key, f"value {describe(value)}: {problem}", axis.section)
    if "seed_config" in study.run:
        problem = check_value(plan, "run.seed_config", study.run["seed_config"])
        if problem:
            raise study.error("seed_config", problem, "run")
    if drives:
        _check_drive_data(study, models)
    return plan


def _check_drive_data(study: Study, models) -> None:
    """Some variant simulates the drives: a robot's drive data must be valid, and one
    robot at least must have them (a cell's robot without runs ideal beside the others,
    docs/drives.md)."""
    from irlc.runtime.drives import drive_params

    driven = []
    for model in models:
        try:
            driven.append(drive_params(model) is not None)
        except ValueError as e:
            _drive_data_error(study, f"robot {model.name}: bad drive data: {e}")
    if not any(driven):
        name = models[0].name
        _drive_data_error(study, f"robot {name} has no drive data ([drives] in its file)")


def _drive_data_error(study: Study, problem: str) -> None:
    key = "run.drives" if "run.drives" in study.keys else "drives"
    section = next((a.section for a in study.axes if a.key == key), "run")
    raise study.error(key, problem, section)


def _code(study: Study, allow_any_path: bool = False) -> Code:
    """The program compiled (``.irl``) or read (``.ird``: IRDATA code, whose data lists are
    compiled in, so no ``datalist.…`` key can change them)."""
    from irlc.api import compile_program
    from irlc.lang.diagnostics import CompileError

    if study.program.suffix.lower() != ".ird":
        try:
            return compile_program(
                study.program,
                robot=study.robot,
                datalist_path=study.datalist_path,
                allow_any_path=allow_any_path,
            )
        except CompileError:
            if study.robot is not None:  # a cell refuses robot = …: the study file's error
                _no_robot_for_a_cell(study, _code(replace(study, robot=None), allow_any_path))
            raise
    from irlc.files import read_user_text
    from irlc.lang.irdata import read_code

    text = read_user_text(study.program, lambda f, r: StudyError(f, None, "", r))
    key = next((k for k in study.keys if k.startswith("datalist.")), None)
    if key is not None:
        section = next(a.section for a in study.axes if a.key == key)
        raise study.error(key, "the program is IRDATA code: its data lists are compiled in; "
                          "vary them with the .irl program", section)  # fmt: skip
    return read_code(text, str(study.program))


def _robots(study: Study, code: Code) -> tuple[PlanRobot, ...]:
    """The program's robots with their files' parsed texts (so workers need no file of
    them; ``None`` for a URDF robot, whose values a study cannot vary)."""
    from irlc.robots import RobotFileError, robot_file

    _no_robot_for_a_cell(study, code)
    out = []
    for r in code.robots:
        source = study.robot or r.robot
        try:
            path = robot_file(source, study.program.parent)
        except RobotFileError as e:
            where = "robot" if study.robot else ""
            raise StudyError(str(study.file), study.line("robot"), where, str(e)) from None
        robot = PlanRobot(r.var, source, r.joint_kinds, r.at)
        if path.suffix.lower() == ".toml":
            doc = tomllib.loads(path.read_text(encoding="utf-8"))
            robot = PlanRobot(r.var, source, r.joint_kinds, r.at, str(path), doc)
        out.append(robot)
    return tuple(out)


def _no_robot_for_a_cell(study: Study, code: Code) -> None:
    """``robot = …`` is refused for a cell, as ``--robot`` is: a cell names its robots."""
    if study.robot is not None and code.is_cell:
        names = ", ".join(r.var for r in code.robots)
        raise study.error("robot", f"the program is a cell of {len(code.robots)} robots "
                          f"({names}), each named by its ROBOT clause: robot = … cannot "
                          "replace them; vary a robot's values with robot.NAME.… keys")  # fmt: skip


def _model(study: Study, robot: PlanRobot):
    """The robot as its file says (the loader's errors are the study file's)."""
    from irlc.runtime.run import RunSetupError, load_model

    try:
        if robot.doc is None:
            return load_model(robot.source, study.program.parent)
        return robot_model(robot, [])
    except (RunSetupError, VariantSetupError) as e:
        raise StudyError(str(study.file), study.line("robot"), "", str(e)) from None


def _datalist_docs(study: Study, code: Code) -> dict[str, tuple[str, dict]]:
    from irlc.lang import datalist as dlmod

    if study.program.suffix.lower() == ".ird":  # compiled in; no key may vary them
        return {}
    imported = {name.lower(): name for name, _ in code.datalists}
    out: dict[str, tuple[str, dict]] = {}
    search = tuple(str(p) for p in study.datalist_path)
    for name in imported.values():  # all of them: a worker then needs none of the files
        path, _ = dlmod.find(name, study.program.parent, search)
        if path is None:  # the program compiled with it: removed since?
            raise StudyError(str(study.file), None, "", f"data list {name}.toml not found")
        out[name] = (str(path), tomllib.loads(path.read_text(encoding="utf-8")))
    for axis in study.axes:
        head, parts = axis.key.partition(".")[0], axis.key.split(".")[1:]
        if head != "datalist":
            continue
        if len(parts) < 2 or parts[0].lower() not in imported:
            known = ", ".join(imported.values()) or "none"
            raise study.error(
                axis.key, f"the program imports no such data list (it imports: {known})",
                axis.section,
            )  # fmt: skip
    return out


# --------------------------------------------------------------------------- one value


def key_problem(plan: Plan, key: str) -> str | None:
    """Why ``key`` names nothing the study can vary in this program, else ``None``."""
    head, parts = paths.target(key)
    if head != "robot":
        return None
    try:
        rk = robot_key(plan.robots, parts)
    except paths.PathError as e:
        return str(e)
    robot = robot_named(plan.robots, rk.robot)
    if not rk.at and robot.doc is None:
        name = Path(robot.source).name
        return f"robot.… keys change a TOML robot file; {name} is not one"
    return None


def check_value(plan: Plan, key: str, value: Any) -> str | None:
    """``None`` if ``value`` may be put at ``key``, else why not (the owner's message)."""
    head, parts = paths.target(key)
    try:
        if head == "run":
            problem = paths.check_run_value(".".join(parts), value)
            n = sum(r.joint_count for r in plan.code.robots)
            if problem is None and parts == ["seed_config"] and n and len(value) != n:
                if plan.cell:
                    counts = ", ".join(f"{r.var}: {r.joint_count}" for r in plan.code.robots)
                    return (f"{len(value)} values, the cell's robots have {n} joints "
                            f"({counts}), one robot after the other")  # fmt: skip
                problem = f"{len(value)} values, the robot has {n} joints"
            return problem
        if head == "robot":
            rk = robot_key(plan.robots, parts)
            robot = robot_named(plan.robots, rk.robot)
            if rk.at:
                check_placement(plan.code, robot, placement(robot, [(rk.component, value)]))
            else:
                robot_model(robot, [(list(rk.parts), value)])
            return None
        return _check_datalist(plan, parts[0], [(parts[1:], value)])
    except paths.PathError as e:
        return str(e)
    except VariantSetupError as e:
        return str(e)


def datalist_text(plan: Plan, name: str, changes: list[tuple[list[str], Any]]) -> str:
    """The TOML text of data list ``name`` with ``changes`` applied."""
    from irlc.lang.toml_text import dumps

    _, base = plan.datalists[_dl_name(plan, name)]
    doc = copy.deepcopy(base)
    for parts, value in changes:
        paths.set_value(doc, parts, value, create=False)
    return dumps(doc)


def _joint_counts(code: Code) -> int | tuple[int, ...] | None:
    """The joint count a data list's joint values have (a cell's robots': any of theirs),
    as the compiler checks them."""
    counts = sorted({r.joint_count for r in code.robots if r.joint_count})
    if not counts:
        return None
    return counts[0] if len(counts) == 1 else tuple(counts)


def _dl_name(plan: Plan, name: str) -> str:
    return next(n for n in plan.datalists if n.lower() == name.lower())


def _check_datalist(plan: Plan, name: str, changes) -> str | None:
    """The data-list loader's first error for the changed list, or ``None``."""
    from irlc.lang import datalist as dlmod

    real = _dl_name(plan, name)
    text = datalist_text(plan, name, changes)
    with tempfile.TemporaryDirectory(prefix="irlc-study-") as tmp:
        path = Path(tmp) / f"{real}.toml"
        path.write_text(text, encoding="utf-8")
        _, diags = dlmod.load(real, path, plan.program_dir, _joint_counts(plan.code))
    errors = [d for d in diags if d.is_error]
    return errors[0].message if errors else None
