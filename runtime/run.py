"""Run a program: IRDATA code → interpreter → simulated controller → :class:`RunResult`.

``run_file(path, …)`` compiles an ``.irl`` file (or reads an ``.ird`` file with
:func:`irlc.lang.irdata.read_code`) and calls ``run_code(code, …)``, which is the pipeline,
one call per stage: the setup (:func:`_setup`), the interpreter with the simulated
controller (the set points: :class:`~irlc.runtime.outputs.samples.Samples`), the drives
(:func:`~irlc.runtime.drives.stage.run_drives`: actual motion and verdict), and the
results (:func:`~irlc.runtime.outputs.results.assemble`: report and trace, presentation only).

**Start configuration**, in this order: ``seed_config`` (program units, ``--seed-config``);
the robot's ``home``; the target of the program's first motion statement if that is a
``MOVE PTP`` to a constant MAIN_JOINT (the robot starts there, the PTP takes no time);
else the zero configuration.

The result carries the samples (SI), the report (``docs/interfaces.md`` keys, program units)
and the trace table (program units, column names per ``docs/interfaces.md``). A run failure
(:class:`~irlc.runtime.errors.RunFailure`) does not raise: the result has
``status = "failed"``, the error, and everything recorded up to the failure.
Bad setup (unknown robot, joint count mismatch, bad ``seed_config``) raises
:class:`RunSetupError` (a usage error, exit 3).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from irlc.lang.file_access import path_kind
from irlc.lang.irdata import Code
from irlc.lang.joint_kinds import kind_letters
from irlc.lang.textfile import read_user_text
from irlc.robots.model import RobotModel
from irlc.runtime import engine_policy, units
from irlc.runtime.commands import Settings
from irlc.runtime.control.executor import ExecutionOptions, SimulatedController
from irlc.runtime.model.limit_check import first_outside
from irlc.runtime.model.naming import JointNaming
from irlc.runtime.model.obstacles import Obstacle
from irlc.runtime.outputs.run_result import RunResult
from irlc.runtime.outputs.samples import Samples
from irlc.runtime.run_setup import (
    HeldOutput,
    RobotOverride,
    RunOptions,
    RunSetupError,
    check_run_option,
    drive_step_for,
    first_line,
    interpret,
    load_model,
    obstacle_shapes,
    placed,
    placement,
    run_options,
    with_overrides,
)

__all__ = [  # the setup's names, imported from here by the front door and the tests
    "RobotOverride",
    "RunOptions",
    "RunSetupError",
    "check_run_option",
    "first_line",
    "load_model",
    "obstacle_shapes",
    "placed",
    "placement",
    "run_code",
    "run_file",
]


def resolve_model(
    code: Code,
    robot: str | Path | RobotModel | None,
    base_dir: Path | None,
    allow_any_path: bool = False,
):
    """The robot to run on: ``robot`` (override, the user's) or the code's robot, by
    :func:`irlc.robots.resolve_robot` (a library name or a path relative to the program;
    the code's own path inside the program's allowed roots unless ``allow_any_path``)."""
    if isinstance(robot, RobotModel):
        model = robot
    elif robot:
        model = load_model(robot, base_dir)
    else:
        try:
            model = load_model(code.robot, base_dir, restricted=not allow_any_path)
        except RunSetupError as exc:  # positioned at the code's ROBOT record (h7, issue 11)
            raise RunSetupError(code.robot_problem(str(exc))) from None
    kinds = kind_letters(model.joint_kinds)
    if code.joint_kinds and kinds != code.joint_kinds:
        message = (
            f"the code was compiled for {code.joint_count} joints ({code.joint_kinds}) but robot "
            f"{model.name} has {model.n} ({kinds})"
        )
        raise RunSetupError(message if robot else code.robot_problem(message))
    return placed(model, code.at)


def start_configuration(code: Code, model: RobotModel, seed_config) -> np.ndarray:
    """See the module doc (seed, home, first PTP target, zero)."""
    if seed_config is not None:
        vals = [float(v) for v in seed_config]
        if len(vals) != model.n:
            raise RunSetupError(
                f"--seed-config has {len(vals)} values but robot {model.name} has {model.n} joints"
            )
        if not all(math.isfinite(v) for v in vals):
            raise RunSetupError("--seed-config values must be finite numbers")
        q = units.joints_to_si(vals, model.joint_kinds)
        limits = model.position_limits
        out = first_outside(q, limits[:, 0], limits[:, 1])
        if out is not None:  # (it failed the program's first statement, exit 2)
            unit = units.joint_unit(model.joint_kinds[out.joint])
            bound = units.joints_from_si([out.bound], [model.joint_kinds[out.joint]])[0]
            name = JointNaming.for_model(model, code.joint_names).label(out.joint)
            raise RunSetupError(
                f"--seed-config: joint {name} = {vals[out.joint]:g} {unit} is {out.where} bound "
                f"{bound:g} {unit} of the robot's position limits"
            )
        return q
    if model.home is not None:
        return np.array(model.home, dtype=float)
    first = _first_ptp_target(code)
    if first is not None and len(first) == model.n:
        return units.joints_to_si(first, model.joint_kinds)
    return np.zeros(model.n)


def start_origin(code: Code, model: RobotModel, seed_config) -> str:
    """Where :func:`start_configuration` takes the start from, in words (messages)."""
    if seed_config is not None:
        return "--seed-config"
    if model.home is not None:
        return "the robot's home"
    first = _first_ptp_target(code)
    if first is not None and len(first) == model.n:
        return "the target of the program's first MOVE PTP"
    return "all joints at zero"


def _first_ptp_target(code: Code) -> tuple[float, ...] | None:
    """The constant MAIN_JOINT target of the main routine's first motion, if it is a
    one-point ``MOVE PTP`` without clauses."""
    main = next((r for r in code.routines if r.kind == "MAIN"), None)
    if main is None:
        return None
    for i in range(main.entry, len(code.code)):
        ins = code.code[i]
        if ins.op in ("JMP", "JF", "JT", "CALL", "RET", "END", "HALT"):
            return None
        if ins.op != "MOVE":
            continue
        if ins.args[:2] != ("PTP", 1) or len(ins.args) > 2 or i == 0:
            return None
        prev = code.code[i - 1]
        if prev.op == "PUSHC":
            value = code.consts[int(prev.args[0])]
            if value.type == "MAIN_JOINT":
                return tuple(float(v) for v in value.data)
        return None
    return None


# --------------------------------------------------------------------------- running


def run_code(
    code: Code,
    *,
    robot: str | Path | RobotModel | None = None,
    ipo: float | None = None,
    drives: str = "ideal",
    seed_config: Sequence[float] | None = None,
    base_dir: str | Path | None = None,
    progress: Callable[[float, int], None] | None = None,
    output: Callable[[str], None] | None = None,
    options: ExecutionOptions | None = None,
    trace_every_step: bool = False,
    path_tolerance: float | None = None,
    orientation_tolerance: float | None = None,
    instruction_budget: int | None = None,
    max_time: float | None = None,
    max_cycles: int | None = None,
    override: float | None = None,
    allow_any_path: bool = False,
    stream: bool = False,
    allow_collisions: bool = False,
    phase: Callable[[str], None] | None = None,
    engine: str | None = None,
    robots: Mapping[str, RobotOverride] | None = None,
) -> RunResult:
    """Execute compiled ``code`` (see the module doc). ``path_tolerance`` (mm, the start
    value of ``R_PATH_TOL``) and ``orientation_tolerance`` (deg) override ``options``'
    ``tol_position`` / ``tol_orientation``; a path deviation beyond them fails the run —
    with drives, of the actual motion (:mod:`irlc.runtime.outputs.verdict`). ``instruction_budget``:
    the endless-loop guard (instructions without motion; default
    :data:`~irlc.runtime.interpreter.DEFAULT_INSTRUCTION_BUDGET`). ``max_time``: the
    simulated-time budget in s (default ``ExecutionOptions.max_time_s``, 24 h);
    ``max_cycles``: the cycle budget, the IPO cycles the run may simulate (default
    ``ExecutionOptions.max_cycles``, 50,000: the bound on what a run computes; with drives
    their steps count, :meth:`SimulatedController._grant_cycles`).
    ``override`` (%): the start value of ``R_OVERRIDE`` (``--override``; lang/settings.py's
    range, 1–100). ``allow_any_path``: the code's robot file may lie outside the program's
    folder and the robot library (``irlc.lang.file_access``). ``stream``: bounded memory
    for a long kinematic run (``drives = ideal``; ignored with drives, which read the whole
    run): the recorder spills its samples to a temporary file
    (:meth:`~irlc.runtime.outputs.recorder.Recorder.spill`), the report is summed up piece by piece
    and the trace is built piece by piece when written (:meth:`RunResult.trace_tables`);
    the same bytes as without it. ``allow_collisions``: a penetration of an obstacle does
    not fail the run (:mod:`irlc.runtime.control.collision`; the report lists them).
    ``phase``: called with a line of text when a stage of the run that does not report
    progress by cycle starts (the drive simulation).

    With drives the program's output is handed to ``output`` after the drive stage, up to
    the failure when the drives fail (:mod:`irlc.runtime.outputs.stop`: a failed drive run
    stops where it failed — trace, output, statements, report).
    ``engine``: ``"compiled"`` runs the compiled kernels from the start (a study's
    choice); ``None`` — the engine policy (:mod:`irlc.runtime.engine_policy`: with numba
    installed and ``IRLC_ENGINE`` unset, a long run goes on on the kernels, a long drive
    run's loop is compiled).
    ``robots``: the run's own robots, by the program's robot names — another model or
    placement (``AT``) than the code's :class:`RobotOverride` (a study's variant; a cell's
    robots too, where ``robot`` is refused).

    The pipeline, one call per stage: the setup (robot, start, options), the interpreter
    with the simulated controller (the set points, :mod:`recorder`), the drives
    (:mod:`drive_stage`: actual motion and verdict), the results (:mod:`results`: report
    and trace, presentation only)."""
    from irlc.runtime.drives.stage import run_drives
    from irlc.runtime.outputs.results import RunData, assemble

    code, models = with_overrides(code, robots)
    if code.is_cell:
        from irlc.runtime.cell_run import run_cell

        arguments = dict(robot=robot, ipo=ipo, drives=drives, seed_config=seed_config,
                         base_dir=base_dir, progress=progress, output=output, options=options,
                         trace_every_step=trace_every_step, path_tolerance=path_tolerance,
                         orientation_tolerance=orientation_tolerance,
                         instruction_budget=instruction_budget, max_time=max_time,
                         max_cycles=max_cycles, override=override, allow_any_path=allow_any_path,
                         allow_collisions=allow_collisions, phase=phase, engine=engine,
                         models=models)  # fmt: skip
        return run_cell(code, arguments)
    if models[0] is not None:
        if robot is not None:
            raise RunSetupError("a run takes its robot from robot= or from robots=, not both")
        robot = models[0]
    setup = _setup(code, robot, ipo, drives, seed_config, base_dir, options, path_tolerance,
                   orientation_tolerance, instruction_budget, max_time, max_cycles,
                   override, allow_any_path, allow_collisions)  # fmt: skip
    ik = setup.options.ik
    if setup.options.engine is None and (ik is None or ik.accel is None):  # not the caller's
        setup.options.engine = engine_policy.for_run(engine)
    controller = SimulatedController(setup.model, setup.q0, obstacles=setup.obstacles,
                                     options=setup.options, progress=progress,
                                     naming=setup.naming)  # fmt: skip
    streamed = stream and drives == "ideal"
    if streamed:
        controller.recorder.spill(SPILL_ROWS)
    held = None if drives == "ideal" else HeldOutput(controller)  # judged by the drives first
    start = controller.collisions.start_failure(
        controller.recorder.last_clearances(), first_line(code),
        start_origin(code, setup.model, seed_config),
    )  # fmt: skip
    execution = interpret(code, controller, setup.settings, held or output, setup.budget, start)
    samples, verdict = None, None
    if not streamed:
        samples = Samples.of(controller.recorder.arrays())
    if drives != "ideal" and len(samples.recorded.times) > 0:
        if phase is not None:
            phase(f"simulating the drives ({drives}) over {samples.recorded.times[-1]:.2f} s")
        until = None if execution.error is None else execution.error.time_s
        samples, verdict = run_drives(samples, setup.model, drives, trace_every_step,
                                      controller.obstacles, controller.recorder.task_rows,
                                      setup.naming.program, setup.options, until)  # fmt: skip
        if verdict.failure is not None and (until is None or verdict.failure.time_s < until):
            execution = _stopped(execution, controller, held, verdict.failure)
    if held is not None:
        held.release(output, execution.output)
    run = RunData(code, setup.model, controller, execution, setup.options, samples, drives,
                  verdict, setup.base_dir, streamed)  # fmt: skip
    return assemble(run)


def _stopped(execution, controller: SimulatedController, held: HeldOutput | None, failure):
    """The interpreter's result and the controller's tables cut at a drive failure
    (:mod:`irlc.runtime.outputs.stop`): the run's error is the failure."""
    from dataclasses import replace

    from irlc.runtime.outputs import stop

    t_f = float(failure.time_s)
    controller.log.spans = stop.statements_until(controller.statements, t_f)
    blender = controller.blender
    blender.blends = [b for b in blender.blends if (b.get("start_s") or 0.0) < t_f]
    rec = controller.recorder
    rec.relaxed_spans = [s for s in rec.relaxed_spans if s.t_start <= t_f + stop.SLACK]
    output = stop.before(held.lines if held is not None else [], t_f)
    events = stop.before(((e["time_s"], e) for e in execution.events), t_f)
    return replace(execution, status="failed", output=output, events=events, error=failure)


SPILL_ROWS = 8192  # samples a streamed run keeps in memory (≈ 3.5 MB on koch11)


@dataclass
class RunSetup:
    """A run's checked inputs (SI): the robot, its obstacles and start configuration, the
    controller's options, the interpreter's start settings and instruction budget."""

    model: RobotModel
    obstacles: dict[str, Obstacle]
    q0: np.ndarray
    options: ExecutionOptions
    settings: Settings
    naming: JointNaming  # joints in failure messages
    budget: int
    base_dir: Path | None


def _setup(code, robot, ipo, drives, seed_config, base_dir, options, path_tolerance,
           orientation_tolerance, instruction_budget, max_time, max_cycles, override,
           allow_any_path=False, allow_collisions=False) -> RunSetup:  # fmt: skip
    """:func:`run_code`'s arguments checked (:class:`RunSetup`); a bad one is a
    :class:`RunSetupError`."""
    common = run_options(drives, ipo, override, instruction_budget, base_dir, max_time,
                         max_cycles, options, path_tolerance, orientation_tolerance,
                         allow_collisions)  # fmt: skip
    model = resolve_model(code, robot, common.base_dir, allow_any_path)
    obstacles = obstacle_shapes(code)
    q0 = start_configuration(code, model, seed_config)
    opts = common.options
    if drives != "ideal":
        opts.drive_step_s = drive_step_for(model, drives, q0)
    naming = JointNaming.for_model(model, code.joint_names)
    return RunSetup(model, obstacles, q0, opts, common.settings, naming, common.budget,
                    common.base_dir)  # fmt: skip


def run_file(
    path: str | Path,
    *,
    robot: str | Path | RobotModel | None = None,
    datalist_path: Sequence[str | Path] = (),
    allow_any_path: bool = False,
    **kwargs,
) -> RunResult:
    """Compile (``.irl``) or read (``.ird``) ``path`` and run it. Raises
    :class:`~irlc.lang.diagnostics.CompileError` when it does not compile and
    :class:`RunSetupError` for a missing file or robot."""
    from irlc.lang.diagnostics import CompileError

    path = Path(path)
    if path_kind(path) == "missing":  # anything else is read and refused (a folder, a FIFO)
        raise RunSetupError(f"{path}: no such file")
    override = None if robot is None or isinstance(robot, RobotModel) else str(robot)
    if override is not None:
        robot = load_model(override, path.parent)  # a bad --robot is a usage error, up front
    diagnostics: list = []
    if path.suffix.lower() == ".ird":
        from irlc.lang.irdata import read_code

        text = read_user_text(path, lambda file, reason: RunSetupError(f"{file}: {reason}"))
        code = read_code(text, str(path))
    else:
        from irlc.lang.compiler import compile_file

        result = compile_file(
            path,
            resolve_robot=robot_resolver(path.parent, robot, allow_any_path),
            datalist_path=tuple(str(d) for d in datalist_path),
            robot_override=override,
            allow_any_path=allow_any_path,
        )
        diagnostics = list(result.diagnostics)
        if result.code is None or any(d.is_error for d in diagnostics):
            raise CompileError(diagnostics)
        code = result.code
    run = run_code(code, robot=robot, base_dir=path.parent, allow_any_path=allow_any_path, **kwargs)
    run.diagnostics = [d for d in diagnostics if not d.is_error]
    return run


def robot_resolver(
    base_dir: Path, override: RobotModel | None = None, allow_any_path: bool = False
):
    """``name → RobotModel`` for the compiler: the override model, or
    :func:`irlc.robots.resolver` relative to the program's folder."""
    from irlc.robots import resolver

    if isinstance(override, RobotModel):
        return lambda name: override
    return resolver(base_dir, allow_any_path=allow_any_path)
