"""The recorder: one sample per IPO cycle, and the derived quantities of a run (SI).

Per sample ``k``: time ``t_k``, program line, joints ``θ_k``, actual TCP pose
``f(θ_k)`` (world, 4×4), the path error against the desired pose ``x_d(t_k)``
(norms of the position and orientation parts of ``f(θ_k) ⊖ x_d``, controlled components
only: a planar arm's task is ``x, y``), Newton iterations, whether the
cycle was relaxed, which joint limits were active, the clearance to every obstacle and
the manipulability of the task Jacobian.

Derivatives are **backward finite differences** on the sample grid,

    θ̇_k = (θ_k − θ_{k−1}) / (t_k − t_{k−1}),   θ̈_k = (θ̇_k − θ̇_{k−1}) / (t_k − t_{k−1}),

with the robot at rest before the first sample (``θ̇_0 = θ̈_0 = 0``). These are exactly the
quantities the inverse transformation bounds each cycle (its box limits the cycle
displacement ``θ_k − θ_{k−1}`` and its change), so a check of the trace against the
limits is a check of the controller.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from irlc.runtime import spatial


@dataclass
class RelaxedSpan:
    """Consecutive relaxed cycles of one statement (reported as a warning)."""

    line: int
    t_start: float
    t_end: float
    cycles: int
    max_deviation: float  # m
    max_orientation: float  # rad
    binding: str


@dataclass
class Recorder:
    n: int
    obstacle_names: tuple[str, ...] = ()
    task_rows: tuple[int, ...] = (0, 1, 2, 3, 4, 5)  # controlled pose-error components
    times: list[float] = field(default_factory=list)
    lines: list[int] = field(default_factory=list)
    q: list[np.ndarray] = field(default_factory=list)
    tcp: list[np.ndarray] = field(default_factory=list)
    pos_error: list[float] = field(default_factory=list)
    ori_error: list[float] = field(default_factory=list)
    iterations: list[int] = field(default_factory=list)
    relaxed: list[bool] = field(default_factory=list)
    manipulability: list[float] = field(default_factory=list)
    active: list[np.ndarray] = field(default_factory=list)  # bool (n,) per sample
    clearance: dict[str, list[float]] = field(default_factory=dict)
    active_time: dict[tuple[int, str], float] = field(default_factory=dict)
    relaxed_spans: list[RelaxedSpan] = field(default_factory=list)
    events: list[dict] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    ik_cycles: int = 0

    def __post_init__(self) -> None:
        self.clearance = {name: [] for name in self.obstacle_names}
        self._no_active = np.zeros(self.n, dtype=bool)
        rows = np.array(self.task_rows, dtype=int)
        self._pos_rows = rows[rows < 3]
        self._ori_rows = rows[rows >= 3]

    def __len__(self) -> int:
        return len(self.times)

    def add(
        self,
        t: float,
        line: int,
        q: np.ndarray,
        tcp: np.ndarray,
        desired: np.ndarray | None,
        *,
        iterations: int = 0,
        relaxed: bool = False,
        active: dict[int, str] | None = None,
        clearances: dict[str, tuple[float, int]] | None = None,
        manipulability: float = float("nan"),
        dt: float = 0.0,
    ) -> None:
        """Append one sample; ``desired`` is the desired TCP pose (``None``: the actual
        pose, i.e. no path error, e.g. standing still or PTP)."""
        self.times.append(float(t))
        self.lines.append(int(line))
        self.q.append(np.array(q, dtype=float))
        self.tcp.append(tcp)
        if desired is None:
            self.pos_error.append(0.0)
            self.ori_error.append(0.0)
        else:
            err = spatial.pose_error(tcp, desired)
            self.pos_error.append(float(np.linalg.norm(err[self._pos_rows])))
            self.ori_error.append(float(np.linalg.norm(err[self._ori_rows])))
        self.iterations.append(int(iterations))
        self.relaxed.append(bool(relaxed))
        self.manipulability.append(float(manipulability))
        flags = self._no_active
        if active:
            flags = np.zeros(self.n, dtype=bool)
            for j, label in active.items():
                flags[j] = True
                key = (int(j), label)
                self.active_time[key] = self.active_time.get(key, 0.0) + dt
        self.active.append(flags)
        for name in self.obstacle_names:
            values = self.clearance[name]
            if clearances and name in clearances:
                values.append(float(clearances[name][0]))
            else:  # not measured this cycle (robot standing): repeat the last value
                values.append(values[-1] if values else float("inf"))

    def note_relaxed(
        self, line: int, t: float, dt: float, deviation: float, ori: float, binding: str
    ) -> None:
        """Merge a relaxed cycle into the current span (same line, consecutive)."""
        last = self.relaxed_spans[-1] if self.relaxed_spans else None
        if last is not None and last.line == line and abs(last.t_end + dt - t) < 1e-9:
            last.t_end = t
            last.cycles += 1
            last.max_deviation = max(last.max_deviation, deviation)
            last.max_orientation = max(last.max_orientation, ori)
            last.binding = last.binding or binding
        else:
            self.relaxed_spans.append(RelaxedSpan(line, t, t, 1, deviation, ori, binding))

    # ------------------------------------------------------------------ arrays
    def arrays(self) -> RecordedRun:
        k = len(self.times)
        q = np.array(self.q) if k else np.zeros((0, self.n))
        times = np.array(self.times)
        speed, accel = finite_differences(times, q)
        return RecordedRun(
            times=times,
            lines=np.array(self.lines, dtype=int),
            q=q,
            speed=speed,
            accel=accel,
            tcp=np.array(self.tcp) if k else np.zeros((0, 4, 4)),
            pos_error=np.array(self.pos_error),
            ori_error=np.array(self.ori_error),
            iterations=np.array(self.iterations, dtype=int),
            relaxed=np.array(self.relaxed, dtype=bool),
            manipulability=np.array(self.manipulability),
            active=np.array(self.active) if k else np.zeros((0, self.n), dtype=bool),
            clearance={name: np.array(v) for name, v in self.clearance.items()},
        )


@dataclass
class RecordedRun:
    """The recorded samples as arrays (SI)."""

    times: np.ndarray  # (k,)
    lines: np.ndarray  # (k,)
    q: np.ndarray  # (k, n)
    speed: np.ndarray  # (k, n)
    accel: np.ndarray  # (k, n)
    tcp: np.ndarray  # (k, 4, 4)
    pos_error: np.ndarray  # (k,) m
    ori_error: np.ndarray  # (k,) rad
    iterations: np.ndarray
    relaxed: np.ndarray
    manipulability: np.ndarray
    active: np.ndarray  # (k, n) bool
    clearance: dict[str, np.ndarray]


def finite_differences(times: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Backward differences (module doc); rest before the first sample."""
    speed = np.zeros_like(q)
    accel = np.zeros_like(q)
    if len(times) < 2:
        return speed, accel
    dt = np.diff(times)[:, None]
    dt = np.where(dt > 0.0, dt, np.inf)  # repeated time stamps: no derivative
    speed[1:] = np.diff(q, axis=0) / dt
    accel[1:] = np.diff(speed, axis=0) / dt
    return speed, accel
