"""From a read study file to a :class:`Plan` the workers run, checked before anything runs.

The program is compiled once here (:func:`irlc.api.compile_program`); every value of every
varied key is put into its document and checked by that document's owner — run options by
the run's checks, robot values by the robot loader (``build_model``, and the drive data
reader for ``robot.drives.…``), data-list values by the data-list loader — so a bad value
is reported with the study file's line before the first variant starts. A random key is
checked at its smallest and largest sample.
"""

from __future__ import annotations

import copy
import hashlib
import json
import tempfile
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from irlc.lang.errors import IrlcError
from irlc.lang.file_access import describe
from irlc.lang.irdata import Code
from irlc.lang.joint_kinds import kind_letters
from irlc.runtime import engine_policy
from irlc.study import paths
from irlc.study.expand import axis_values
from irlc.study.spec import Study, StudyError, count_variants


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
    robot_file: str | None = None  # the robot description (TOML) robot.… keys change
    robot_doc: dict | None = None
    datalists: dict[str, tuple[str, dict]] = field(default_factory=dict)  # name → (file, doc)
    joints: tuple[tuple[str, str], ...] = ()  # (program name, unit) per joint
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
    program_dir = study.program.parent
    model = load_model(study.robot or code.robot, program_dir)
    kinds = [axis.key.partition(".")[0] for axis in study.axes]
    for axis in study.axes:
        try:
            paths.target(axis.key)
        except paths.PathError as e:
            raise study.error(axis.key, str(e), axis.section) from None
    robot_file, robot_doc = _robot_doc(study, code, "robot" in kinds)
    datalists = _datalist_docs(study, code)
    text = study.program.read_text(encoding="utf-8")
    drives = study.run.get("drives", "ideal") != "ideal"
    values = axis_values(study)
    if "run.drives" in values:
        drives = drives or any(v != "ideal" for v in values["run.drives"])
    engine = engine_policy.for_study(count_variants(study))  # the installation's, per study
    inputs = [study.text, text, json.dumps([robot_doc, datalists], sort_keys=True, default=str)]
    inputs.append(f"engine={engine}")  # --resume with another engine: another study's bytes
    plan = Plan(
        token=hashlib.sha256("\0".join(inputs).encode()).hexdigest()[:16],
        program=str(study.program),
        program_text=text,
        robot=study.robot,
        datalist_path=tuple(str(p) for p in study.datalist_path),
        run=dict(study.run),
        code=code,
        keys=tuple(study.keys),
        robot_file=robot_file,
        robot_doc=robot_doc,
        datalists=datalists,
        joints=tuple(
            (name, units.joint_unit(kind))
            for name, kind in zip(code.joint_names, model.joint_kinds, strict=True)
        ),
        obstacles=tuple(o.name for o in code.obstacles),
        drives=drives,
        allow_any_path=allow_any_path,
        engine=engine,
        variants_dir=str(variants_dir) if variants_dir is not None else None,
        reports=study.reports,
        traces=study.traces,
    )
    for axis in study.axes:
        for value in values[axis.key]:
            problem = check_value(plan, axis.key, value)
            if problem:
                raise study.error(axis.key, f"value {describe(value)}: {problem}", axis.section)
    if "seed_config" in study.run:
        problem = check_value(plan, "run.seed_config", study.run["seed_config"])
        if problem:
            raise study.error("seed_config", problem, "run")
    if drives:
        _check_drive_data(study, model)
    return plan


def _check_drive_data(study: Study, model) -> None:
    """Some variant simulates the drives: the robot must have drive data."""
    from irlc.runtime.drives import drive_params

    try:
        ok = drive_params(model) is not None
        problem = "" if ok else f"robot {model.name} has no drive data ([drives] in its file)"
    except ValueError as e:
        problem = f"robot {model.name}: bad drive data: {e}"
    if problem:
        key = "run.drives" if "run.drives" in study.keys else "drives"
        section = next((a.section for a in study.axes if a.key == key), "run")
        raise study.error(key, problem, section)


def _code(study: Study, allow_any_path: bool = False) -> Code:
    """The program compiled (``.irl``) or read (``.ird``: IRDATA code, whose data lists are
    compiled in, so no ``datalist.…`` key can change them)."""
    from irlc.api import compile_program

    if study.program.suffix.lower() != ".ird":
        return compile_program(
            study.program,
            robot=study.robot,
            datalist_path=study.datalist_path,
            allow_any_path=allow_any_path,
        )
    from irlc.files import read_user_text
    from irlc.lang.irdata import read_code

    text = read_user_text(study.program, lambda f, r: StudyError(f, None, "", r))
    key = next((k for k in study.keys if k.startswith("datalist.")), None)
    if key is not None:
        section = next(a.section for a in study.axes if a.key == key)
        raise study.error(key, "the program is IRDATA code: its data lists are compiled in; "
                          "vary them with the .irl program", section)  # fmt: skip
    return read_code(text, str(study.program))


def _robot_doc(study: Study, code: Code, varied: bool) -> tuple[str | None, dict | None]:
    """The robot file and its parsed text (so workers need no file of it), or ``None``s
    for a URDF robot, whose values a study cannot vary."""
    from irlc.robots import RobotFileError, robot_file

    name = study.robot or code.robot
    try:
        path = robot_file(name, study.program.parent)
    except RobotFileError as e:
        where = "robot" if study.robot else ""
        raise StudyError(str(study.file), study.line("robot"), where, str(e)) from None
    if path.suffix.lower() != ".toml" and not varied:
        return None, None
    if path.suffix.lower() != ".toml":
        key = next(k for k in study.keys if k.startswith("robot."))
        raise study.error(key, f"robot.… keys change a TOML robot file; {path.name} is not one")
    return str(path), tomllib.loads(path.read_text(encoding="utf-8"))


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


def check_value(plan: Plan, key: str, value: Any) -> str | None:
    """``None`` if ``value`` may be put at ``key``, else why not (the owner's message)."""
    head, parts = paths.target(key)
    try:
        if head == "run":
            problem = paths.check_run_value(".".join(parts), value)
            n = plan.code.joint_count
            if problem is None and parts == ["seed_config"] and n and len(value) != n:
                problem = f"{len(value)} values, the robot has {n} joints"
            return problem
        if head == "robot":
            robot_model(plan, [(parts, value)])
            return None
        return _check_datalist(plan, parts[0], [(parts[1:], value)])
    except paths.PathError as e:
        return str(e)
    except VariantSetupError as e:
        return str(e)


class VariantSetupError(IrlcError):
    """A value does not fit its document (a robot-file or data-list message)."""


def robot_model(plan: Plan, changes: list[tuple[list[str], Any]]):
    """The robot with ``changes`` applied to its file, loaded by the robot loader (and,
    for a ``drives`` change, its drive data read by the drives' reader)."""
    from irlc.robots import RobotFileError
    from irlc.robots.loader import build_model

    doc = copy.deepcopy(plan.robot_doc)
    for parts, value in changes:
        paths.set_value(doc, parts, value, create=True)
    assert plan.robot_file is not None
    try:
        model = build_model(doc, plan.robot_file, Path(plan.robot_file).parent)
    except RobotFileError as e:
        raise VariantSetupError(
            e.message if e.key == "" else f"key '{e.key}': {e.message}"
        ) from None
    kinds = kind_letters(model.joint_kinds)
    if plan.code.joint_kinds and kinds != plan.code.joint_kinds:
        raise VariantSetupError(f"the robot's joints become {kinds}, the program's are "
                                f"{plan.code.joint_kinds}")  # fmt: skip
    if any(parts[0] == "drives" for parts, _ in changes):
        from irlc.runtime.drives import drive_params

        try:
            drive_params(model)
        except ValueError as e:
            raise VariantSetupError(str(e)) from None
    return model


def datalist_text(plan: Plan, name: str, changes: list[tuple[list[str], Any]]) -> str:
    """The TOML text of data list ``name`` with ``changes`` applied."""
    from irlc.lang.toml_text import dumps

    _, base = plan.datalists[_dl_name(plan, name)]
    doc = copy.deepcopy(base)
    for parts, value in changes:
        paths.set_value(doc, parts, value, create=False)
    return dumps(doc)


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
        _, diags = dlmod.load(real, path, plan.program_dir, plan.code.joint_count or None)
    errors = [d for d in diags if d.is_error]
    return errors[0].message if errors else None
