"""Run a cell: code with several ``ROBOT`` records (docs/irdata.md, "Cells").

The same pipeline as :func:`irlc.runtime.run.run_code`, one call per stage, with one
robot per ``ROBOT`` record: the setup (each robot's file, its placement ``AT`` and start
configuration), the interpreter with the cell's controller
(:class:`~irlc.runtime.control.cell.CellController`: every robot's set points, on one
clock), each robot's drives (``--drives``), the results
(:mod:`irlc.runtime.outputs.cell_results`: the report with ``robots``, the trace with each
robot's columns prefixed by its name).

**Start configuration** of robot ``k``: ``seed_config`` holds every robot's joints one
robot after the other (program units, in the ``ROBOT`` records' order); else the robot's
``home``; else all joints at zero. A start inside an obstacle, or with two robots' (or one
robot's) links inside each other, fails the program's first statement at t = 0.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np
from irlc.lang.irdata import Code
from irlc.robots.model import RobotModel
from irlc.runtime import engine_policy, units
from irlc.runtime import run_setup as setup
from irlc.runtime.control.cell import CellController, CellMember
from irlc.runtime.model.limit_check import first_outside
from irlc.runtime.model.naming import JointNaming
from irlc.runtime.outputs import actual_clearance
from irlc.runtime.outputs.run_result import RunResult
from irlc.runtime.run_setup import HeldOutput, RunSetupError


def run_cell(code: Code, arguments: dict) -> RunResult:
    """Execute a cell's ``code`` (module doc). ``arguments`` are :func:`run_code`'s keyword
    arguments, which calls this one (its docstring); ``robot`` — another robot for the
    program — is refused: a cell names its robots (``models``: a run's own model per robot,
    :func:`~irlc.runtime.run_setup.with_overrides`)."""
    from irlc.runtime.outputs.cell_results import CellRunData, RobotRun, assemble_cell

    a = arguments
    robot, drives, seed_config, progress = a["robot"], a["drives"], a["seed_config"], a["progress"]
    output, options, phase = a["output"], a["options"], a["phase"]
    if robot is not None:
        raise RunSetupError(
            f"--robot cannot be used with a cell: the code names {len(code.robots)} robots "
            f"({', '.join(r.var for r in code.robots)})"
        )
    if a["trace_every_step"]:
        raise RunSetupError(
            "--trace-every-step cannot be used with a cell: its robots' drives step at their "
            "own rates (the trace has a row per IPO sample)"
        )
    common = setup.run_options(
        drives, a["ipo"], a["override"], a["instruction_budget"], a["base_dir"], a["max_time"],
        a["max_cycles"], options, a["path_tolerance"], a["orientation_tolerance"],
        a["allow_collisions"],
    )  # fmt: skip
    opts = common.options
    members = cell_members(
        code, common.base_dir, seed_config, a["allow_any_path"], a.get("models", ())
    )
    driven = _driven(members, drives)
    if drives != "ideal":
        opts.drive_step_s = min(
            setup.drive_step_for(m.model, drives, m.q0)
            for m, d in zip(members, driven, strict=True)
            if d
        )
    if opts.engine is None and (opts.ik is None or opts.ik.accel is None):
        opts.engine = engine_policy.for_run(a["engine"])
    cell = CellController(
        members, obstacles=setup.obstacle_shapes(code), options=opts, progress=progress
    )
    held = None if drives == "ideal" else HeldOutput(cell)  # judged by the drives first
    execution = setup.interpret(code, cell, common.settings, held or output, common.budget,
                          _start_failure(code, cell, members, seed_config))  # fmt: skip
    robots = [RobotRun.kinematic(unit) for unit in cell.robots]
    actual = None
    if drives != "ideal" and len(robots[0].samples.recorded.times) > 0:
        if phase is not None:
            t_end = robots[0].samples.recorded.times[-1]
            phase(f"simulating the drives ({drives}) of {len(robots)} robots over {t_end:.2f} s")
        until = None if execution.error is None else execution.error.time_s
        for run, d in zip(robots, driven, strict=True):
            if d:
                run.drive(drives, False, cell.obstacles, opts, until)
            else:
                run.undriven = (
                    f"robot {run.unit.model.name} has no drive data ([drives] in its robot "
                    f"file): it runs ideal beside the others' {drives} drives"
                )
        actual = actual_clearance.measure(cell.parts, [r.samples.shown for r in robots],
                                          cell.clearances.required, opts.allow_collisions,
                                          until)  # fmt: skip
        failure = _first_failure(robots, until, actual)
        if failure is not None:
            t_f = float(failure.time_s)
            for run in robots:
                run.cut(t_f, opts)
            actual.cut(t_f)
            execution = _stopped(execution, held, failure)
        _judge_actual_clearance(robots, actual)
    if held is not None:
        held.release(output, execution.output)
    data = CellRunData(code, cell, execution, opts, robots, drives, common.base_dir, actual)
    return assemble_cell(data)


def cell_members(
    code: Code,
    base_dir: Path | None,
    seed_config,
    allow_any_path: bool,
    models: Sequence[RobotModel | None] = (),
) -> list[CellMember]:
    """Each robot of the code: its file (the ``ROBOT`` record's, positioned errors) or its
    model in ``models`` (the run's own, ``None``: the record's), placed by ``AT``, its start
    configuration (module doc) and its joint naming."""
    from irlc.lang.joint_kinds import kind_letters

    robots = code.robots
    seeds = _seeds(seed_config, robots)
    out = []
    for k, r in enumerate(robots):
        where = "{}:{}:{}: ".format(*r.position) if r.position else ""
        model = models[k] if k < len(models) else None
        try:
            if model is None:
                model = setup.load_model(r.robot, base_dir, restricted=not allow_any_path)
        except RunSetupError as exc:
            raise RunSetupError(f"{where}cannot use robot {r.robot} of {r.var}: {exc}") from None
        kinds = kind_letters(model.joint_kinds)
        if kinds != r.joint_kinds:
            raise RunSetupError(
                f"{where}the code was compiled for robot {r.var} with {r.joint_count} joints "
                f"({r.joint_kinds}) but robot {model.name} has {model.n} ({kinds})"
            )
        model = setup.placed(model, r.at)
        naming = JointNaming.for_model(model, r.joint_names)
        q0 = _start(model, seeds[k], naming, r.var)
        out.append(CellMember(r.var, model, q0, naming, setup.placement(r.at)))
    return out


def _seeds(seed_config, robots) -> list[list[float] | None]:
    """``seed_config`` cut into each robot's joints (``None``s without one)."""
    if seed_config is None:
        return [None] * len(robots)
    vals = [float(v) for v in seed_config]
    total = sum(r.joint_count for r in robots)
    if len(vals) != total:
        counts = ", ".join(f"{r.var}: {r.joint_count}" for r in robots)
        raise RunSetupError(
            f"--seed-config has {len(vals)} values but the cell's robots have {total} joints "
            f"({counts}), given one robot after the other"
        )
    if not all(math.isfinite(v) for v in vals):
        raise RunSetupError("--seed-config values must be finite numbers")
    out, i = [], 0
    for r in robots:
        out.append(vals[i : i + r.joint_count])
        i += r.joint_count
    return out


def _start(model, seed: list[float] | None, naming: JointNaming, name: str) -> np.ndarray:
    """A robot's start joints (SI): the seed (inside its limits), its home, or zeros."""
    if seed is None:
        return model.home_q()
    q = units.joints_to_si(seed, model.joint_kinds)
    limits = model.position_limits
    out = first_outside(q, limits[:, 0], limits[:, 1])
    if out is not None:
        unit = units.joint_unit(model.joint_kinds[out.joint])
        bound = units.joints_from_si([out.bound], [model.joint_kinds[out.joint]])[0]
        raise RunSetupError(
            f"--seed-config: robot {name}'s joint {naming.label(out.joint)} = "
            f"{seed[out.joint]:g} {unit} is {out.where} bound {bound:g} {unit} of its position "
            "limits"
        )
    return q


def _start_failure(code: Code, cell: CellController, members, seed_config):
    """The failure of a start inside an obstacle or with links inside each other."""
    line = setup.first_line(code)
    origin = "--seed-config" if seed_config is not None else "the robots' homes"
    for unit in cell.robots:
        clear = unit.channel.last_clearances()
        failure = unit.controller.collisions.start_failure(clear, line, f"{unit.name}: {origin}")
        if failure is not None:
            return failure
    return cell.start_failure(line)


def _driven(members, drives: str) -> list[bool]:
    """Which robots' drives are simulated: with ``--drives`` every robot with drive data
    (one without runs ideal, and its report says so); none has any: the one-robot error
    (:class:`~irlc.runtime.errors.DriveSetupError`, exit 3)."""
    if drives == "ideal":
        return [False] * len(members)
    from irlc.runtime.drives.stage import drive_data, has_drive_data

    driven = [has_drive_data(m.model) for m in members]
    if not any(driven):
        drive_data(members[0].model)  # raises, naming the robot
    return driven


def _first_failure(robots, until, actual):
    """The earliest failure of the drive run (before ``until``): of a robot's verdict or
    of the actual clearance (a tie: the robot's), or ``None``."""
    failures = [
        r.verdict.failure.of_robot(f"robot {r.unit.name}")
        for r in robots
        if r.verdict is not None and r.verdict.failure is not None
    ] + [actual.failure]
    failures = [f for f in failures if f is not None and (until is None or f.time_s < until)]
    return min(failures, key=lambda f: f.time_s) if failures else None


def _judge_actual_clearance(robots, actual) -> None:
    """The actual clearance in the robots' verdicts: its criteria in each, its failure (if
    the run stopped at it) a violation of both robots it names."""
    row = actual.violation()
    for run in robots:
        verdict = run.verdict
        if verdict is None:
            continue
        verdict.criteria.update(actual.criteria)
        if row is not None and run.unit.name in (row["robot_a"], row["robot_b"]):
            verdict.violations = sorted([*verdict.violations, row], key=lambda v: v["time_s"])
            verdict.failure = verdict.failure or actual.failure


def _stopped(execution, held: HeldOutput | None, failure):
    """The interpreter's result cut at a drive failure (:mod:`irlc.runtime.outputs.stop`)."""
    from irlc.runtime.outputs import stop

    t_f = float(failure.time_s)
    output = stop.before(held.lines if held is not None else [], t_f)
    events = stop.before(((e["time_s"], e) for e in execution.events), t_f)
    return replace(execution, status="failed", output=output, events=events, error=failure)
