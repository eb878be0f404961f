"""How hard the hypothesis fuzz tests try, and the hang guard on each case (issue 11).

In CI each fuzz target runs its ``ci_examples`` (a few seconds per target). The long fuzz
run (documented in docs/interfaces.md, "Fuzzing"; not in CI)::

    IRLC_FUZZ_EXAMPLES=100000 pytest tests -k fuzz -p no:cacheprovider \
        --hypothesis-show-statistics

runs up to ``IRLC_FUZZ_EXAMPLES`` cases per target (hypothesis stops earlier when a target's
finite input space is exhausted). Every case runs under a hang guard: a case still running
after ``IRLC_FUZZ_HANG_S`` seconds (5 in the long run, 60 in CI) is interrupted by a timer
signal and fails as :class:`FuzzHang` — a real hang fails the case instead of stalling the
run. ``IRLC_FUZZ_DEADLINE_MS`` (default: 5,000 ms in the long run, none in CI) is hypothesis'
own deadline, which also fails a case that finished but took longer.
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
    """The hang guard: ``IRLC_FUZZ_HANG_S``, default 5 s in the long run and 60 s in CI."""
    return float(os.environ.get("IRLC_FUZZ_HANG_S", "5" if long_run() else "60"))


def hang_guard(seconds: float) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """Wrap a test body so a call still running after ``seconds`` raises :class:`FuzzHang`.

    A real-time interval timer (``SIGALRM``) interrupts the case between Python bytecodes,
    so pure-Python loops and any numpy call that returns are caught. Where the platform has
    no ``SIGALRM`` (Windows) the body runs unguarded."""

    def wrap(body: Callable[..., Any]) -> Callable[..., Any]:
        if not hasattr(signal, "setitimer") or seconds <= 0:
            return body

        @functools.wraps(body)
        def guarded(*args: Any, **kwargs: Any) -> Any:
            def expire(signum, frame):
                raise FuzzHang(f"fuzz case still running after {seconds:g} s (a hang)")

            previous = signal.signal(signal.SIGALRM, expire)
            signal.setitimer(signal.ITIMER_REAL, seconds)
            try:
                return body(*args, **kwargs)
            finally:
                signal.setitimer(signal.ITIMER_REAL, 0)
                signal.signal(signal.SIGALRM, previous)

        return guarded

    return wrap


def fuzz_settings(ci_examples: int) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """Decorate a ``@given`` test: ``ci_examples`` cases in CI, ``IRLC_FUZZ_EXAMPLES`` in the
    long run, each case under :func:`hang_guard` (applied to hypothesis' inner test, so it
    times the case itself, not data generation or shrinking)."""
    examples = int(os.environ.get("IRLC_FUZZ_EXAMPLES") or ci_examples)
    deadline = os.environ.get("IRLC_FUZZ_DEADLINE_MS", "5000" if long_run() else "")
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
    from irlc.runtime.drives import accel as drive_accel
    from irlc.runtime.ik import accel as ik_accel

    ik_accel.warm_up()
    drive_accel.warm_up()
