"""Where the variants run: local worker processes (default) or a Dask cluster.

**Local** (:func:`run_local`): a ``ProcessPoolExecutor`` of ``workers`` processes
(``forkserver``: clean workers, the plan sent once to each by the initializer). At most
``2·workers`` variants are in flight, so a study of a million variants holds only that
many futures. Each finished variant is handed to ``on_row`` at once (results.csv is
appended); the order of completion does not matter, the file is sorted at the end.

A worker that *dies* (segfault, ``os._exit``, out of memory) breaks the whole pool. The
variants that were in flight are then the suspects: each is run again alone in a fresh
one-process pool, and one that kills that pool too is a ``crashed`` row; the rest of the
study goes on in a new pool. A variant that merely fails is a row from the worker itself.

**Dask** (:func:`run_dask`): the same :func:`irlc.study.worker.run_variant` in tasks on
an existing ``dask.distributed`` scheduler (``tcp://HOST:8786``); the plan is scattered
once to every worker, each worker keeps its caches across tasks. A task runs a batch of
up to :data:`MAX_BATCH` variants (:func:`batch_size`: small studies one per task), so a
million short variants are not a million scheduler round trips. A task whose worker
keeps dying ends as ``KilledWorker`` (after Dask's own retries): its variants run again
one per task, and the one that kills its worker again is a ``crashed`` row.
"""

from __future__ import annotations

import multiprocessing
from collections import deque
from collections.abc import Callable, Iterable
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool

from irlc.lang.errors import IrlcError
from irlc.study import metrics
from irlc.study.expand import Variant
from irlc.study.plan import Plan
from irlc.study.worker import init_worker, run_indexed

OnRow = Callable[[dict[str, str]], None]
CRASH_MESSAGE = "the worker process died while running this variant"


THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


def _context():
    """The ``forkserver`` context; its workers get one BLAS thread each unless the user
    set one (``workers`` processes × all-core BLAS threads would oversubscribe the cores;
    a run's matrices are small)."""
    import os

    for name in THREAD_VARIABLES:
        os.environ.setdefault(name, "1")
    return multiprocessing.get_context("forkserver")


def _pool(plan: Plan, workers: int) -> ProcessPoolExecutor:
    ctx = _context()
    ctx.set_forkserver_preload(["irlc.study.worker", "irlc.runtime.run"])
    return ProcessPoolExecutor(workers, mp_context=ctx, initializer=init_worker, initargs=(plan,))


def crashed_row(plan: Plan, index: int, values: tuple, message: str = CRASH_MESSAGE) -> dict:
    return {
        **metrics.parameter_cells(plan, index, values),
        **metrics.error_cells("crashed", None, message, None),
    }


class _Lazy:
    """An iterator with ``popleft`` and a truth value: variants are made as they are sent,
    so a million of them are never in memory at once."""

    _END = object()

    def __init__(self, items: Iterable):
        self._it = iter(items)
        self._next = next(self._it, self._END)

    def __bool__(self) -> bool:
        return self._next is not self._END

    def popleft(self):
        value, self._next = self._next, next(self._it, self._END)
        return value


def run_local(
    plan: Plan, todo: Iterable[Variant], workers: int, on_row: OnRow, count: int | None = None
) -> None:
    """Run ``todo`` (``count`` of them, if known) on ``workers`` local processes (see the
    module doc)."""
    queue = _Lazy(todo)
    if count is not None:
        workers = min(workers, count)
    workers = max(1, workers)
    while queue:
        suspects = _run_pool(plan, queue, workers, on_row)
        for index, values in suspects:  # the pool broke: isolate the culprit(s)
            rows = _run_alone(plan, (index, values))
            on_row(rows)


def _run_pool(plan: Plan, queue: _Lazy, workers: int, on_row: OnRow) -> list[Variant]:
    """Run from ``queue`` until it is empty or the pool breaks; then return the variants
    that were in flight (and put nothing of them back on the queue)."""
    window = 2 * workers
    pool = _pool(plan, workers)
    running: dict[Future, Variant] = {}
    try:
        while queue or running:
            while queue and len(running) < window:
                variant = queue.popleft()
                running[pool.submit(run_indexed, *variant)] = variant
            done, _ = wait(running, return_when=FIRST_COMPLETED)
            for future in done:
                variant = running.pop(future)
                try:
                    row = future.result()
                except BrokenProcessPool:
                    suspects = [variant, *running.values()]
                    running.clear()
                    return suspects
                on_row(row)
        return []
    finally:
        for future in running:
            future.cancel()
        pool.shutdown(wait=True, cancel_futures=True)


def _run_alone(plan: Plan, variant: Variant) -> dict[str, str]:
    pool = _pool(plan, 1)
    try:
        return pool.submit(run_indexed, *variant).result()
    except BrokenProcessPool:
        return crashed_row(plan, *variant)
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


# --------------------------------------------------------------------------- dask


class ClusterError(IrlcError):
    """No Dask, or the scheduler cannot be reached (exit 3)."""


def _dask_task(plan: Plan, batch: list[Variant]) -> list[dict[str, str]]:
    """One Dask task: the rows of a batch of variants, run one after the other."""
    from irlc.study.worker import run_variant

    return [run_variant(plan, index, values) for index, values in batch]


MAX_BATCH = 32  # variants per Dask task at most (amortises the scheduler's per-task cost)
MAX_RESCATTERS = 10  # times the plan is sent again after dying workers took every copy


def batch_size(count: int, threads: int) -> int:
    """Variants per task: enough tasks for ≥ 8 per thread (load balance), at most
    :data:`MAX_BATCH`; 1 for small studies."""
    return max(1, min(MAX_BATCH, count // (8 * max(1, threads))))


def connect(address: str | object):
    """A ``distributed.Client`` for the scheduler at ``address`` (a given client as is);
    :class:`ClusterError` without Dask or when the scheduler does not answer in 20 s."""
    if hasattr(address, "submit"):
        return address
    try:
        from distributed import Client
    except ImportError:
        raise ClusterError(
            "--cluster needs dask.distributed: pip install 'irlc[cluster]'"
        ) from None
    try:
        return Client(address, timeout="20s")
    except (OSError, TimeoutError, ValueError) as e:
        raise ClusterError(f"cannot reach the Dask scheduler at {address}: {e}") from None


def run_dask(
    plan: Plan, todo: Iterable[Variant], client, on_row: OnRow, count: int | None = None
) -> None:
    """Run ``todo`` (``count`` of them, if known) on the Dask cluster of ``client``
    (:func:`connect`)."""
    from distributed import as_completed

    _dask_loop(client, plan, _Lazy(todo), on_row, as_completed, count)


def _dask_loop(
    client, plan: Plan, queue: _Lazy, on_row: OnRow, as_completed, count: int | None
) -> None:
    """Batches of variants as tasks, at most 2 × threads tasks in flight. A task that ends
    in ``KilledWorker`` makes its variants suspects: each runs again as a task of its own
    with nothing else in flight, and only one that still kills its worker alone is a
    ``crashed`` row (the others were bystanders of the crash)."""
    from distributed import KilledWorker

    def scatter():
        return client.scatter([plan], broadcast=True, hash=False)[0]

    plan_future = scatter()
    rescatters = 0  # workers that died can take every copy of the plan with them
    retry: deque[list[Variant]] = deque()  # batches that lost the plan: run again
    threads = sum(client.nthreads().values())
    window = max(2 * threads, 2)
    size = batch_size(count or 0, threads)
    pending: dict = {}  # task key → (its variants, ran alone)
    suspects: deque[Variant] = deque()
    stream = as_completed()

    def submit() -> None:
        while len(pending) < window:
            if suspects:
                if pending:  # a suspect runs alone
                    return
                batch, alone = [suspects.popleft()], True
            elif retry:
                batch, alone = retry.popleft(), False
            elif queue:
                batch, alone = [queue.popleft()], False
                while queue and len(batch) < size:
                    batch.append(queue.popleft())
            else:
                return
            key = f"irlc-study-{plan.token}-{batch[0][0]}-{len(batch)}-{int(alone)}"
            future = client.submit(_dask_task, plan_future, batch, key=key, pure=False)
            pending[future.key] = (batch, alone)
            stream.add(future)

    submit()
    for future in stream:
        batch, alone = pending.pop(future.key)
        lost = future.status != "finished" and plan_future.status != "finished"
        if lost and rescatters < MAX_RESCATTERS:  # the plan was lost, not the task's fault
            rescatters += 1
            plan_future = scatter()
            if alone:
                suspects.appendleft(batch[0])
            else:
                retry.append(batch)
            future.release()
            submit()
            continue
        try:
            rows = future.result()
        except KilledWorker:
            rows = [crashed_row(plan, *batch[0])] if alone else []
            if not alone:
                suspects.extend(batch)
        except Exception as e:  # the task itself never raises; this is the cluster's
            rows = [crashed_row(plan, i, v, f"the cluster lost the task: {e}") for i, v in batch]
        for row in rows:
            on_row(row)
        future.release()
        submit()


# --------------------------------------------------------------------------- generic


def ordered_map(
    fn: Callable, items: list, workers: int, crashed: Callable[[object], object]
) -> list:
    """``[fn(x) for x in items]`` on ``workers`` local processes, in the order of ``items``
    whatever the order of completion; an item whose process dies gives ``crashed(item)``
    (the same isolation as :func:`run_local`). ``fn`` must be a module-level function."""
    results: dict[int, object] = {}
    queue = deque(enumerate(items))
    workers = max(1, min(workers, len(items)))
    ctx = _context()
    while queue:
        suspects: list[tuple[int, object]] = []
        with ProcessPoolExecutor(workers, mp_context=ctx) as pool:
            running: dict[Future, tuple[int, object]] = {}
            while (queue or running) and not suspects:
                while queue and len(running) < 2 * workers:
                    i, item = queue.popleft()
                    running[pool.submit(fn, item)] = (i, item)
                done, _ = wait(running, return_when=FIRST_COMPLETED)
                for future in done:
                    i, item = running.pop(future)
                    try:
                        results[i] = future.result()
                    except BrokenProcessPool:
                        suspects = [(i, item), *running.values()]
                        running.clear()
                        break
        for i, item in suspects:
            with ProcessPoolExecutor(1, mp_context=ctx) as alone:
                try:
                    results[i] = alone.submit(fn, item).result()
                except BrokenProcessPool:
                    results[i] = crashed(item)
    return [results[i] for i in range(len(items))]
