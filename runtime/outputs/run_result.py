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
from irlc.runtime import values
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
class RobotResult:
    """One robot of a run (:attr:`RunResult.robots`): its name in the program, its model
    (placed in the cell: base = ``at`` · the file's base), its placement ``at`` (4×4, SI),
    its joints' program names, its samples (SI: ``times`` (k,), ``q`` (k, n), ``tcp``
    (k, 4, 4) in the cell frame; with drives the actual motion), its part of the report
    (a cell's ``report["robots"]`` entry; one robot: the whole report), its trace columns
    (a cell's: prefixed ``NAME_``), the recorder's samples and the drive run."""

    name: str
    model: RobotModel
    at: np.ndarray
    joint_names: tuple[str, ...]
    times: np.ndarray
    q: np.ndarray
    tcp: np.ndarray
    report: dict
    trace_columns: list[str]
    recorded: Any = None
    drive: Any = None


@dataclass
class RunResult:
    """A run's result. ``times``, ``q``, ``tcp`` (SI: the actual joints, the commanded ones
    with ideal drives), ``trace`` (program units, one row per sample) and ``recorded`` are
    read from ``source``: arrays kept in memory, or, for a streamed run
    (``run_code(stream=True)``), built on first use; :meth:`trace_tables` gives the trace
    in pieces of rows, which is how the CLI writes it (bounded memory).

    A cell (several robots): :attr:`robots` has each robot's :class:`RobotResult`, in the
    ``ROBOT`` clauses' order; ``q`` is every robot's joints side by side (the order of
    ``joint_names``, ``holder_a1 …``), ``tcp`` is ``None`` (each robot's is
    ``robots[name].tcp``), ``model`` robot 0's, ``recorded`` robot 0's samples (times and
    lines are the cell's)."""

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
    cell: dict[str, RobotResult] | None = None  # a cell's robots (None: one robot)

    @property
    def is_cell(self) -> bool:
        return self.cell is not None

    @property
    def robots(self) -> dict[str, RobotResult]:
        """Each robot's result by its name in the program (one robot: one entry, its
        name that of the ``ROBOT`` clause)."""
        if self.cell is not None:
            return self.cell
        name = self.code.robot_var if self.code is not None else self.model.name
        at = np.eye(4)
        if self.code is not None and self.code.at is not None:
            at = values.pose_to_matrix(values.pose_from_zyx(*self.code.at))
        return {
            name: RobotResult(
                name, self.model, at, tuple(self.joint_names), self.times, self.q, self.tcp,
                self.report, list(self.trace_columns), self.recorded, self.drive,
            )
        }  # fmt: skip

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
