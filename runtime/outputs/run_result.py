"""A run's result (:class:`RunResult`) and the in-memory form of its samples and trace
(:class:`TraceArrays`): what :func:`irlc.runtime.run.run_code` returns and
:func:`irlc.runtime.outputs.results.assemble` builds."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from irlc.lang.irdata import Code
from irlc.robots.model import RobotModel
from irlc.runtime.errors import RunFailure
from irlc.runtime.model.obstacles import Obstacle
from irlc.runtime.outputs.recorder import RecordedRun


@dataclass
class TraceArrays:
    """A run's samples and trace table kept in memory (what :class:`RunResult` reads)."""

    times: np.ndarray  # (k,) s
    q: np.ndarray  # (k, n) SI
    tcp: np.ndarray  # (k, 4, 4) world, m
    trace: np.ndarray  # (k', columns), program units
    recorded: Any = None  # RecordedRun

    def tables(self) -> Iterator[np.ndarray]:
        """The trace table as pieces (here: one)."""
        yield self.trace


@dataclass
class RunResult:
    """A run's result. ``times``, ``q``, ``tcp`` (SI: the actual joints, the commanded ones
    with ideal drives), ``trace`` (program units, one row per sample) and ``recorded`` are
    read from ``source``: arrays kept in memory, or, for a streamed run
    (``run_code(stream=True)``), built on first use; :meth:`trace_tables` gives the trace
    in pieces of rows, which is how the CLI writes it (bounded memory)."""

    status: str  # "ok" | "failed"
    error: RunFailure | None
    report: dict
    trace_columns: list[str]
    model: RobotModel
    obstacles: tuple[Obstacle, ...]  # SI shapes (runtime.obstacles)
    output: list[str]
    drive: Any = None  # the drive simulation result, or None (ideal)
    code: Code | None = None
    joint_names: tuple[str, ...] = ()
    diagnostics: list = field(default_factory=list)  # compiler warnings (run_file)
    source: Any = None  # TraceArrays | results.StreamedTrace

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    @property
    def times(self) -> np.ndarray:
        """(k,) s."""
        return self.source.times

    @property
    def q(self) -> np.ndarray:
        """(k, n) SI."""
        return self.source.q

    @property
    def tcp(self) -> np.ndarray:
        """(k, 4, 4) world, m."""
        return self.source.tcp

    @property
    def trace(self) -> np.ndarray:
        """(k', len(trace_columns)), program units (a streamed run's: built on first use)."""
        return self.source.trace

    @trace.setter
    def trace(self, table: np.ndarray) -> None:
        src = self.source
        self.source = TraceArrays(src.times, src.q, src.tcp, table, src.recorded)

    @property
    def recorded(self) -> RecordedRun | None:
        """The recorder's samples (SI; :class:`~irlc.runtime.outputs.recorder.RecordedRun`)."""
        return self.source.recorded if self.source is not None else None

    def trace_tables(self):
        """The trace table in consecutive pieces of rows (bounded memory when streamed)."""
        return self.source.tables()

    @property
    def lines(self) -> np.ndarray:
        return self.recorded.lines if self.recorded is not None else np.zeros(0, dtype=int)
