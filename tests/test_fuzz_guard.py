"""The fuzz tests' hang guard (tests/fuzz_budget.py): a case that hangs fails, it does not
stall the run (issue 11: "zero hangs over 5 s" needs a hang to be seen)."""

from __future__ import annotations

import signal
import time

import pytest
from hypothesis import given
from hypothesis import strategies as st

from .fuzz_budget import FuzzHang, fuzz_settings, hang_guard

pytestmark = pytest.mark.skipif(not hasattr(signal, "setitimer"), reason="needs SIGALRM")


def test_fuzz_guard_interrupts_an_endless_loop() -> None:
    @hang_guard(0.2)
    def spin() -> None:
        while True:
            pass

    start = time.perf_counter()
    with pytest.raises(FuzzHang, match=r"after 0\.2 s"):
        spin()
    assert time.perf_counter() - start < 2.0


def test_fuzz_guard_leaves_fast_cases_and_the_timer_alone() -> None:
    assert hang_guard(0.5)(lambda x: x + 1)(1) == 2
    time.sleep(0.6)  # the timer was cancelled: no late FuzzHang
    assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)


def test_fuzz_guard_fails_a_hanging_hypothesis_case(monkeypatch) -> None:
    monkeypatch.setenv("IRLC_FUZZ_HANG_S", "0.2")

    @fuzz_settings(5)
    @given(st.just(3))
    def hangs_on_three(k: int) -> None:
        while k == 3:
            pass

    with pytest.raises(FuzzHang):
        hangs_on_three()
