"""How hard the hypothesis fuzz tests try, and the hang guard on each case (issue 11).

In CI each fuzz target runs its ``ci_examples`` (a few seconds per target). The long fuzz
run (documented in docs/interfaces.md, "Fuzzing"; not in CI)::

    IRLC_FUZZ_EXAMPLES=100000 pytest tests -k fuzz -p no:cacheprovider \
        --hypothesis-show-statistics

runs up to ``IRLC_FUZZ_EXAMPLES`` cases per target (hypothesis stops earlier when a target's
finite input space is exhausted). Every case runs under a hang guard: a case still running
after ``IRLC_FUZZ_HANG_S`` seconds of CPU time (5 in the long run, 60 in CI), or blocked for
twelve times that on the wall clock, is interrupted by a timer signal and fails as
:class:`FuzzHang` — a real hang fails the case instead of stalling the run.
``IRLC_FUZZ_DEADLINE_MS`` (default: none) sets hypothesis' own deadline, on the wall clock,
which also fails a case that finished but took longer.
"""

from __future__ import annotations

import functools
import os
import signal
from collections.abc import Callable
from typing import Any

from hypothesis import HealthCheck, settings


class FuzzHang(AssertionError):
    """A fuzz case ran longer than the hang guard allows."""


def long_run() -> bool:
    """True in the long fuzz run (``IRLC_FUZZ_EXAMPLES`` set)."""
    return bool(os.environ.get("IRLC_FUZZ_EXAMPLES"))


def hang_seconds() -> float:
    """The hang guard, in CPU seconds: ``IRLC_FUZZ_HANG_S``, default 5 in the long run and 60
    in CI."""
    return float(os.environ.get("IRLC_FUZZ_HANG_S", "5" if long_run() else "60"))


def wall_seconds(cpu_seconds: float) -> float:
    """The wall-clock backstop for a case blocked without computing: ``IRLC_FUZZ_HANG_WALL_S``,
    default twelve times the CPU limit (a 2-core machine at load 12 still passes a case that
    computes less than the CPU limit)."""
    return float(os.environ.get("IRLC_FUZZ_HANG_WALL_S", str(12.0 * cpu_seconds)))


def hang_guard(seconds: float) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """Wrap a test body so a call that has used ``seconds`` of CPU time, or has run
    :func:`wall_seconds` of wall-clock time, raises :class:`FuzzHang`.

    A hang is a case that keeps computing: the process's CPU time (``ITIMER_PROF``, user +
    system) is what counts, so the guard flags the same cases on an idle machine and on one
    shared by many jobs (there the wall clock runs several times faster than the case's CPU
    time: a 0.4 s case once took 5 s of wall time under hypothesis' tracing at load 12). On
    an idle machine a single-threaded case's CPU and wall times agree. A case blocked
    without computing is caught by the wall-clock backstop (``ITIMER_REAL``). The timer
    signals interrupt the case between Python bytecodes, so pure-Python loops and any numpy
    call that returns are caught. Where the platform has no ``setitimer`` (Windows) the
    body runs unguarded."""

    def wrap(body: Callable[..., Any]) -> Callable[..., Any]:
        if not hasattr(signal, "setitimer") or seconds <= 0:
            return body
        wall = wall_seconds(seconds)

        @functools.wraps(body)
        def guarded(*args: Any, **kwargs: Any) -> Any:
            def cpu_spent(signum, frame):
                raise FuzzHang(f"fuzz case still running after {seconds:g} s of CPU (a hang)")

            def wall_spent(signum, frame):
                raise FuzzHang(f"fuzz case still running after {wall:g} s (a hang)")

            previous = (
                signal.signal(signal.SIGPROF, cpu_spent),
                signal.signal(signal.SIGALRM, wall_spent),
            )
            signal.setitimer(signal.ITIMER_PROF, seconds)
            signal.setitimer(signal.ITIMER_REAL, wall)
            try:
                return body(*args, **kwargs)
            finally:
                signal.setitimer(signal.ITIMER_PROF, 0)
                signal.setitimer(signal.ITIMER_REAL, 0)
                signal.signal(signal.SIGPROF, previous[0])
                signal.signal(signal.SIGALRM, previous[1])

        return guarded

    return wrap


def fuzz_settings(ci_examples: int) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """Decorate a ``@given`` test: ``ci_examples`` cases in CI, ``IRLC_FUZZ_EXAMPLES`` in the
    long run, each case under :func:`hang_guard` (applied to hypothesis' inner test, so it
    times the case itself, not data generation or shrinking)."""
    examples = int(os.environ.get("IRLC_FUZZ_EXAMPLES") or ci_examples)
    deadline = os.environ.get("IRLC_FUZZ_DEADLINE_MS", "")  # wall clock: off unless asked
    chosen = settings(
        max_examples=examples,
        deadline=int(deadline) if deadline else None,
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
        database=None,
    )

    def apply(test: Callable[..., Any]) -> Callable[..., Any]:
        test = chosen(test)
        test.hypothesis.inner_test = hang_guard(hang_seconds())(test.hypothesis.inner_test)
        return test

    return apply


def warm_up_kernels() -> None:
    """Compile (or load from numba's cache) the optional compiled kernels before the cases
    run: their one-time compile (≈ 15–30 s) is not a hang of the first case that moves."""
    from irlc.runtime.accel_support import AVAILABLE, decide

    if not (AVAILABLE and decide(None)):
        return
    from irlc.runtime.warmup import warm_drives, warm_ik, warm_ik_obstacles

    warm_ik()
    warm_ik_obstacles()
    warm_drives()
