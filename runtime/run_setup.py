"""The setup of a run, shared by the runs of one robot (:mod:`irlc.runtime.run`) and of a
cell (:mod:`irlc.runtime.cell_run`): the usage errors of a run (:class:`RunSetupError`, exit
3), the robot files and their placement (``AT``), a run's own robots in place of the code's
(:class:`RobotOverride`, :func:`with_overrides`), the code's obstacles, the checked run
options (:func:`run_options`, :func:`check_run_option`), the drives' step for the cycle
budget, and the interpreter's call (:func:`interpret`, :class:`HeldOutput`)."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from irlc.lang.cell import placement_problem
from irlc.lang.errors import IrlcError
from irlc.lang.file_access import describe, is_finite_real
from irlc.lang.irdata import Code
from irlc.robots.model import RobotModel
from irlc.runtime import units
from irlc.runtime.commands import Settings, setting_error
from irlc.runtime.control.executor import ExecutionOptions
from irlc.runtime.drives.levels import LEVELS as DRIVE_LEVELS
from irlc.runtime.errors import DriveSetupError
from irlc.runtime.model.obstacles import Obstacle


class RunSetupError(IrlcError):
    """The run cannot start: unknown robot, mismatching code, bad options (exit 3)."""


# --------------------------------------------------------------------------- setup


def placed(model: RobotModel, at: Sequence[float] | None) -> RobotModel:
    """``model`` with its base placed in the cell by ``AT`` (mm, ZYX deg): base =
    placement · the file's base; unchanged without ``AT``."""
    if at is None or not any(at):
        return model
    return replace(model, base=placement(at) @ model.base)


def placement(at: Sequence[float] | None) -> np.ndarray:
    """The 4×4 placement (SI) of ``AT (x, y, z, a, b, c)`` (mm, ZYX deg); the identity
    without one."""
    if at is None:
        return np.eye(4)
    from irlc.runtime import values

    return values.pose_to_matrix(values.pose_from_zyx(*at))


@dataclass(frozen=True)
class RobotOverride:
    """A run's own choice for one robot of the code, in place of what its ``ROBOT`` record
    gives (a study's variant, :mod:`irlc.study`): ``model``, its robot (e.g. its file with
    a changed value; checked against the code's joints as the record's robot is), ``at``,
    its placement (x, y, z mm, a, b, c ZYX deg; checked as the compiler checks ``AT``).
    ``None``: the record's."""

    model: RobotModel | None = None
    at: tuple[float, ...] | None = None


def with_overrides(
    code: Code, overrides: Mapping[str, RobotOverride] | None
) -> tuple[Code, list[RobotModel | None]]:
    """``code`` with each overridden placement in its robot's record — the run, its report
    (``at``) and its result then place the robot there, as if the program had said so:
    ``AT`` is a record of the code, folded into no instruction — and the overriding models,
    one per robot of the code in the records' order (``None``: the record's robot).
    ``overrides`` is keyed by the program's robot names (any case); another name, or a
    placement that is not one, is a :class:`RunSetupError`."""
    robots = code.robots
    models: list[RobotModel | None] = [None] * len(robots)
    if not overrides:
        return code, models
    index = {r.var.lower(): k for k, r in enumerate(robots)}
    placements = [r.at for r in robots]
    for name, override in overrides.items():
        k = index.get(name.lower())
        if k is None:
            known = ", ".join(r.var for r in robots)
            raise RunSetupError(f"the program has no robot {name} (its robots: {known})")
        models[k] = override.model
        if override.at is not None:
            at = tuple(override.at)
            finite = all(is_finite_real(v) for v in at)
            problem = placement_problem(at) if finite else "its values must be finite numbers"
            if problem:
                raise RunSetupError(f"placement of robot {robots[k].var}: {problem}")
            placements[k] = tuple(float(v) for v in at)
    others = [replace(r, at=at) for r, at in zip(code.other_robots, placements[1:], strict=True)]
    return replace(code, at=placements[0], other_robots=others), models


def load_model(
    name_or_path: str | Path, base_dir: Path | None, restricted: bool = False
) -> RobotModel:
    """:func:`irlc.robots.resolve_robot`; its errors become :class:`RunSetupError` (exit 3)."""
    from irlc.robots import RobotFileError, resolve_robot

    try:
        return resolve_robot(name_or_path, base_dir, restricted=restricted)
    except RobotFileError as exc:
        raise RunSetupError(str(exc)) from None


def obstacle_shapes(code: Code) -> dict[str, Obstacle]:
    """The code's obstacles (OBSTACLE records, mm) as SI shapes, by name."""
    from irlc.runtime.model.obstacles import from_definition

    out = {}
    for o in code.obstacles:
        try:
            out[o.name] = from_definition(o)
        except ValueError as exc:
            raise RunSetupError(str(exc)) from None
    return out


def first_line(code: Code) -> int:
    """The source line of the main routine's first instruction that records one (0: none)."""
    main = next((r for r in code.routines if r.kind == "MAIN"), None)
    start = main.entry if main is not None else 0
    return next((ins.line for ins in code.code[start:] if ins.line > 0), 0)


class HeldOutput:
    """The program's output lines with the simulated time each was written at, held until
    the drive stage has judged the run (:func:`run_code`)."""

    def __init__(self, controller):  # SimulatedController | CellController: its time
        self.controller = controller
        self.lines: list[tuple[float, str]] = []

    def __call__(self, text: str) -> None:
        self.lines.append((float(self.controller.time), text))

    def release(self, output: Callable[[str], None] | None, kept: list[str]) -> None:
        """Hand the ``kept`` lines (the first ones, those before a failure) to ``output``."""
        if output is not None:
            for text in kept:
                output(text)


@dataclass
class RunOptions:
    """The options of a run that do not depend on its robots: the controller's options,
    the interpreter's start settings and instruction budget, the program's folder."""

    options: ExecutionOptions
    settings: Settings
    budget: int
    base_dir: Path | None


def run_options(drives, ipo, override, instruction_budget, base_dir, max_time, max_cycles,
                options, path_tolerance, orientation_tolerance,
                allow_collisions) -> RunOptions:  # fmt: skip
    """The robot-independent arguments of :func:`run_code` checked (a bad one is a
    :class:`RunSetupError`), as :class:`RunOptions`."""
    if drives not in DRIVE_LEVELS:
        raise RunSetupError(f"unknown drive level {drives!r} (known: {', '.join(DRIVE_LEVELS)})")
    if ipo is not None and setting_error("ipo", ipo):
        raise RunSetupError(f"--ipo {describe(ipo)}: {setting_error('ipo', ipo)}")
    if override is not None and setting_error("override", override):
        raise RunSetupError(
            f"--override {describe(override)}: {setting_error('override', override)}"
        )
    budget = instruction_budget_of(instruction_budget)
    base = Path(base_dir) if base_dir is not None else None
    if max_time is not None:
        positive("--max-time", max_time, "seconds")
    if max_cycles is not None:
        whole("--max-cycles", max_cycles)
    opts = options or ExecutionOptions()
    if ipo is not None:
        opts.ipo = float(ipo)
    if max_time is not None:
        opts.max_time_s = float(max_time)
    if max_cycles is not None:
        opts.max_cycles = max_cycles
    tol_mm = opts.tol_position / units.MM
    if path_tolerance is not None:
        tol_mm = path_tolerance_of("--path-tolerance", path_tolerance)
        opts.tol_position = tol_mm * units.MM
        opts.path_tolerance_stated = True  # it judges a drive run's path (verdict.py)
    if orientation_tolerance is not None:
        deg = positive("--orientation-tolerance", orientation_tolerance, "deg")
        opts.tol_orientation = deg * units.DEG
        opts.orientation_tolerance_stated = True
    if allow_collisions:
        opts.allow_collisions = True
    settings = Settings(path_tol=tol_mm)  # R_PATH_TOL's start value, as given
    if opts.ipo is not None:
        settings.ipo = opts.ipo
    if override is not None:
        settings.override = float(override)  # R_OVERRIDE's start value
    return RunOptions(opts, settings, budget, base)


def drive_step_for(model: RobotModel, level: str, q0: np.ndarray) -> float:
    """The drive simulation's step for the run's cycle budget (ExecutionOptions.drive_step_s):
    the drive data is checked here, before the run (:class:`DriveSetupError`, exit 3)."""
    import warnings

    from irlc.runtime.drives.simulate import drive_step
    from irlc.runtime.drives.stage import drive_data
    from irlc.runtime.drives.stepsize import StepSizeWarning

    params = drive_data(model)
    try:
        with warnings.catch_warnings():  # the drive stage warns, once
            warnings.simplefilter("ignore", StepSizeWarning)
            return drive_step(model, params, level, q0)
    except ValueError as exc:
        raise DriveSetupError(f"drive simulation: {exc}") from None


def path_tolerance_of(option: str, value) -> float:
    """A path tolerance in mm: a positive number in R_PATH_TOL's range (lang/settings.py),
    else :class:`RunSetupError`."""
    tol_mm = positive(option, value, "mm")
    if error := setting_error("path_tol", tol_mm):
        raise RunSetupError(f"{option} {describe(value)}: {error}")
    return tol_mm


def positive(option: str, value, unit: str) -> float:
    """``value`` as a float if it is a finite number > 0, else :class:`RunSetupError` (an
    integer beyond a float's range too)."""
    if not (is_finite_real(value) and value > 0):
        raise RunSetupError(f"{option} must be a positive number of {unit}, got {describe(value)}")
    return float(value)


def check_run_option(key: str, value) -> str | None:
    """``None`` if ``value`` is admissible for :func:`run_code`'s option ``key``, else why
    not, naming ``key`` (a study's ``[run]`` values: :mod:`irlc.study.paths`). The checks
    are run_code's: the drive levels, the settings table's ranges for ``ipo`` and
    ``override`` (R_IPO, R_OVERRIDE), :func:`_budget`, :func:`_whole`, :func:`_positive`;
    ``seed_config`` is a list of finite numbers (deg | mm; its length is the robot's);
    ``allow_collisions`` true or false."""
    if key == "drives":
        ok = isinstance(value, str) and value in DRIVE_LEVELS
        return None if ok else f"expected one of {', '.join(DRIVE_LEVELS)}, got {describe(value)}"
    if key in ("ipo", "override"):
        return setting_error(key, value)
    if key == "allow_collisions":
        return None if isinstance(value, bool) else f"expected true or false, got {describe(value)}"
    if key == "seed_config":
        if not (isinstance(value, list) and all(is_finite_real(v) for v in value)):
            return f"expected a list of finite numbers (deg | mm), got {describe(value)}"
        return None
    units = {"path_tolerance": "mm", "orientation_tolerance": "deg", "max_time": "seconds"}
    try:
        if key == "instruction_budget":
            instruction_budget_of(value)
        elif key == "max_cycles":
            whole(key, value)
        elif key == "path_tolerance":
            path_tolerance_of(key, value)
        elif key in units:
            positive(key, value, units[key])
        else:
            return f"unknown run option {key!r}"
    except RunSetupError as e:
        return str(e).replace("--instruction-budget", key)
    return None


def instruction_budget_of(budget: int | None) -> int:
    """The endless-loop budget: ``None`` → the default; else a positive whole number."""
    from irlc.runtime.interpreter import DEFAULT_INSTRUCTION_BUDGET

    if budget is None:
        return DEFAULT_INSTRUCTION_BUDGET
    return whole("--instruction-budget", budget)


def whole(option: str, value) -> int:
    """``value`` if it is a whole number ≥ 1, else :class:`RunSetupError`."""
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise RunSetupError(f"{option} must be a positive integer, got {describe(value)}")
    return value


def interpret(
    code, controller, settings, output: Callable[[str], None] | None, budget: int, start=None
):
    """Run the interpreter; its result carries output, events, warnings and the error.
    ``start``: the failure of the start configuration (a collision): the program does not
    run."""
    from irlc.runtime.interpreter import ExecutionResult, Interpreter

    interp = Interpreter(
        code, controller, settings=settings, output=output, instruction_budget=budget
    )
    if start is not None:
        return ExecutionResult("failed", [], [], [], start, interp.state, 0)
    result = interp.run(check=False)
    if result.error is not None and result.error.time_s is None:
        result.error.time_s = controller.time
    return result
