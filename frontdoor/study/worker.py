"""Run one variant in a worker process: the normal pipeline, with per-process caches.

:func:`run_variant` puts the variant's values where they belong and calls
:func:`irlc.runtime.run.run_code` — the code compiled once per study (:class:`Plan`), or,
when data-list values vary, compiled once per distinct data (the varied lists written to a
private folder searched before the program's); each robot loaded once per distinct set of
its values and handed to the run, with its placement, as the run's own robot
(:class:`~irlc.runtime.run_setup.RobotOverride`: a cell's robots too). Both caches live in
the worker process for the whole study (LRU, :data:`CACHE_SIZE` entries), so a worker that
runs many variants reloads nothing that did not change. Any error becomes the row's
status; nothing here raises for a bad variant.
"""

from __future__ import annotations

import shutil
import tempfile
from collections import OrderedDict
from pathlib import Path
from typing import Any

from irlc.study import metrics, paths
from irlc.study.plan import Plan, VariantSetupError, datalist_text
from irlc.study.robots import PlanRobot, placement, robot_key, robot_model

CACHE_SIZE = 16
_caches: dict[str, OrderedDict] = {}  # plan token + kind → LRU cache
_plans: dict[str, Plan] = {}  # set by the pool initializer


def init_worker(plan: Plan) -> None:
    """Process-pool initializer: keep the plan for :func:`run_indexed`."""
    _plans["current"] = plan


def run_indexed(index: int, values: tuple) -> dict[str, str]:
    """:func:`run_variant` with the plan the initializer stored (local pool)."""
    return run_variant(_plans["current"], index, values)


MAX_STUDIES = 2  # a long-lived (Dask) worker keeps the caches of the last two studies


def _cached(plan: Plan, kind: str, key: Any, make):
    name = f"{plan.token}:{kind}"
    tokens = list(dict.fromkeys(k.partition(":")[0] for k in _caches))  # oldest first
    if plan.token not in tokens:  # a new study: forget all but the last MAX_STUDIES − 1
        for old in tokens[: max(0, len(tokens) - MAX_STUDIES + 1)]:
            for k in [k for k in _caches if k.startswith(old + ":")]:
                del _caches[k]
    cache = _caches.setdefault(name, OrderedDict())
    if key in cache:
        cache.move_to_end(key)
        return cache[key]
    value = make()
    cache[key] = value
    if len(cache) > CACHE_SIZE:
        cache.popitem(last=False)
    return value


def run_variant(plan: Plan, index: int, values: tuple) -> dict[str, str]:
    """One row of results.csv for variant ``index`` (see :mod:`irlc.study.metrics`)."""
    from irlc.lang.diagnostics import CompileError
    from irlc.robots import RobotFileError
    from irlc.runtime.errors import DriveSetupError
    from irlc.runtime.run import RunSetupError, run_code

    row = metrics.parameter_cells(plan, index, values)
    groups = _group(plan, values)
    try:
        robots = _robots(plan, groups["robot"])
        code = _code(plan, groups["datalist"])
        options = {**plan.run, **groups["run"]}
        result = run_code(
            code, robots=robots, base_dir=plan.program_dir, engine=plan.engine, **options
        )
    except CompileError as e:
        first = next((d for d in e.diagnostics if d.is_error), None)
        line = first.line if first is not None else None
        return {**row, **metrics.error_cells("compile_error", 1, str(e), line)}
    except (RunSetupError, DriveSetupError, RobotFileError, VariantSetupError) as e:
        return {**row, **metrics.error_cells("setup_error", 3, str(e), None)}
    except Exception as e:  # a bug in irlc: the row says so, the study goes on
        message = f"internal error: {type(e).__name__}: {e}"
        return {**row, **metrics.error_cells("internal_error", 4, message, None)}
    _write_outputs(plan, index, result)
    return {**row, **metrics.report_cells(plan, result.report)}


def _group(plan: Plan, values: tuple) -> dict[str, Any]:
    """The values by target: run options, robot changes per robot (:class:`RobotKey`,
    value), data-list changes per list."""
    out: dict[str, Any] = {"run": {}, "robot": {}, "datalist": {}}
    for key, value in zip(plan.keys, values, strict=True):
        head, parts = paths.target(key)
        if head == "run":
            out["run"][parts[0]] = value
        elif head == "robot":
            rk = robot_key(plan.robots, parts)
            out["robot"].setdefault(rk.robot, []).append((rk, value))
        else:
            out["datalist"].setdefault(parts[0], []).append((parts[1:], value))
    return out


def _freeze(changes) -> tuple:
    return tuple((tuple(p), repr(v)) for p, v in changes)


def _robots(plan: Plan, changes: dict[str, list]) -> dict:
    """Each robot of this variant for the run, by its name: its model (its file's, or
    with the varied values) and its placement (the program's ``AT`` when none varies)."""
    from irlc.runtime.run import RobotOverride

    out = {}
    for robot in plan.robots:
        mine = changes.get(robot.var, [])
        values = [(list(rk.parts), v) for rk, v in mine if not rk.at]
        at = [(rk.component, v) for rk, v in mine if rk.at]
        model = _model(plan, robot, values)
        out[robot.var] = RobotOverride(model, placement(robot, at) if at else None)
    return out


def _model(plan: Plan, robot: PlanRobot, changes: list):
    """A robot of this variant (its file's when no value of it varies)."""
    from irlc.runtime.run import load_model

    key = (robot.var, _freeze(changes))
    if robot.doc is None:  # a URDF robot: loaded from its files (no value of it varies)
        return _cached(plan, "robot", key, lambda: load_model(robot.source, plan.program_dir))
    return _cached(plan, "robot", key, lambda: robot_model(robot, changes))


def _code(plan: Plan, changes: dict[str, list]):
    """The code of this variant: the plan's, or compiled with the varied data lists."""
    if not changes:
        return plan.code
    key = tuple(sorted((name, _freeze(c)) for name, c in changes.items()))
    return _cached(plan, "code", key, lambda: _compile(plan, changes))


def _compile(plan: Plan, changes: dict[str, list]):
    from irlc.lang.compiler import compile_source
    from irlc.lang.diagnostics import CompileError
    from irlc.robots import resolver

    folder = Path(tempfile.mkdtemp(prefix="irlc-study-"))
    try:
        for real in plan.datalists:  # every imported list: no file of the study is read
            c = next((c for name, c in changes.items() if name.lower() == real.lower()), [])
            (folder / f"{real}.toml").write_text(datalist_text(plan, real, c), encoding="utf-8")
        result = compile_source(
            plan.program_text,
            str(folder / Path(plan.program).name),
            resolve_robot=resolver(
                plan.program_dir, allow_any_path=plan.allow_any_path, user_robot=plan.robot
            ),
            datalist_path=(str(plan.program_dir), *plan.datalist_path),
            robot_override=plan.robot,
            allow_any_path=plan.allow_any_path,
        )
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    if result.code is None or any(d.is_error for d in result.diagnostics):
        raise CompileError(result.diagnostics)
    return result.code


def _write_outputs(plan: Plan, index: int, result) -> None:
    """``[output]``: the variant's report (JSON) and trace (CSV), the writers of ``irlc run``."""
    from irlc.report import write_report, write_trace

    if plan.variants_dir is None:
        return
    stem = Path(plan.variants_dir) / f"variant_{index:07d}"
    if plan.reports:
        write_report(result.report, stem.with_suffix(".report.json"))
    if plan.traces:
        path = stem.with_suffix(".trace.csv")
        write_trace(result.trace_columns, result.trace, path, result.error is not None)
