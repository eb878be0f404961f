"""Each quantity of a run is derived once (issue 10 §3): the backward differences of the
set points and, with drives, of the actual joints at the sample times; the report and the
trace read the same samples, so their figures agree exactly."""

from __future__ import annotations

import contextlib
import importlib
import sys
from pathlib import Path

import numpy as np
import pytest
from irlc.runtime.outputs import recorder
from irlc.runtime.run import run_file

PROGRAMS = Path(__file__).resolve().parents[2] / "programs"
PIPELINE = (
    "irlc.runtime.outputs.results",
    "irlc.runtime.outputs.samples",
    "irlc.runtime.drives.stage",
)


def _count_differences(monkeypatch) -> list[int]:
    """Counts calls of :func:`recorder.finite_differences` wherever a module bound it."""
    original, calls = recorder.finite_differences, []

    def counted(times, q):
        calls.append(len(times))
        return original(times, q)

    for name, module in list(sys.modules.items()):
        if name.startswith("irlc") and getattr(module, "finite_differences", None) is original:
            monkeypatch.setattr(module, "finite_differences", counted)
    return calls


def _speed_columns(run) -> np.ndarray:
    cols = [i for i, c in enumerate(run.trace_columns) if "_speed_" in c]
    return run.trace[:, cols]


@pytest.mark.parametrize("drives, derived", [("ideal", 1), ("decoupled", 2)])
def test_derivatives_are_computed_once_and_shared(drives, derived, monkeypatch):
    for name in PIPELINE:  # loaded before their bound names are counted
        with contextlib.suppress(ImportError):
            importlib.import_module(name)
    calls = _count_differences(monkeypatch)
    run = run_file(PROGRAMS / "square.irl", drives=drives, path_tolerance=20.0,
                   orientation_tolerance=5.0)  # fmt: skip
    assert len(calls) == derived  # set points (recorder), + the actual joints (drives)
    speed = np.abs(_speed_columns(run)).max(axis=0)
    reported = [j["max_abs_speed"] for j in run.report["joints"]]
    np.testing.assert_allclose(speed, reported, rtol=1e-8)
