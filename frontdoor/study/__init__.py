"""Studies: one program over many variants (``irlc study STUDY.toml``; docs/studies.md).

:func:`run_study` reads the study file (:mod:`.spec`), compiles the program and checks
every value before anything runs (:mod:`.plan`; the program's robots and the ``robot.…``
keys that change them: :mod:`.robots`), expands the variants (:mod:`.expand`),
runs the missing ones on local processes or a Dask cluster (:mod:`.runner`, each variant
one run of the normal pipeline in :mod:`.worker`) and keeps ``DIR/results.csv``
(:mod:`.results`, columns in :mod:`.metrics`).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from irlc.study.spec import Study, StudyError, read_study

__all__ = ["StudyError", "StudyOutcome", "read_study", "run_study"]


@dataclass
class StudyOutcome:
    study: Study
    folder: Path
    columns: list[str]
    rows: list[dict[str, str]]  # every variant done, in variant order
    ran: int  # variants run by this call (the rest were in results.csv already)
    total: int


def default_workers() -> int:
    """All cores this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def run_study(
    path: str | Path,
    *,
    out: str | Path | None = None,
    workers: int | None = None,
    cluster: str | object | None = None,
    resume: bool = False,
    progress: Callable[[int, int], None] | None = None,
    started: Callable[[int, int], None] | None = None,
    check: Callable[[list[str], list[str]], None] | None = None,
    allow_any_path: bool = False,
) -> StudyOutcome:
    """Run (or complete, ``resume``) the study in ``path``; see the module doc.

    ``out``: the results folder (default ``STUDY.results`` next to the study file);
    ``workers``: local processes (default all cores); ``cluster``: a Dask scheduler
    address (or ``Client``) instead. ``started(todo, total)`` is called once the checks
    passed, ``progress(done, todo)`` after every variant; ``check(columns, keys)`` before
    anything is written (the caller's own checks, e.g. of a metric name);
    ``allow_any_path``: ``--allow-any-path`` (``irlc.lang.file_access``)."""
    from irlc.runtime import engine_policy
    from irlc.study.expand import variants
    from irlc.study.metrics import columns
    from irlc.study.plan import build_plan
    from irlc.study.results import ResultsFile
    from irlc.study.runner import connect, run_dask, run_local
    from irlc.study.spec import count_variants

    study = read_study(path, allow_any_path)
    folder = Path(out) if out is not None else study.file.with_suffix(".results")
    plan = build_plan(study, folder / "variants", allow_any_path)
    cols = columns(plan)
    if check is not None:
        check(cols, study.keys)
    client = connect(cluster) if cluster is not None else None  # before any file is written
    try:
        results = ResultsFile(folder, cols, plan.token, resume)
    except BaseException:
        _close(client, cluster)
        raise
    done = set(results.done)
    todo = (v for v in variants(study) if v[0] not in done)  # made as they are sent
    total = count_variants(study)
    todo_count = total - len(done)
    if started is not None:
        started(todo_count, total)
    count = 0

    def on_row(row: dict[str, str]) -> None:
        nonlocal count
        results.append(row)
        count += 1
        if progress is not None:
            progress(count, todo_count)

    try:
        if client is not None:
            run_dask(plan, todo, client, on_row, todo_count)
        else:
            if plan.engine == "compiled" and todo_count:  # its workers load, not compile
                engine_policy.compile_once(bool(plan.obstacles), plan.drives)
            run_local(plan, todo, workers or default_workers(), on_row, todo_count)
    finally:
        results.finish()
        _close(client, cluster)
    return StudyOutcome(study, folder, cols, results.rows(), count, total)


def _close(client, given) -> None:
    """Close a client this call opened (not one the caller gave)."""
    if client is not None and client is not given:
        client.close()
