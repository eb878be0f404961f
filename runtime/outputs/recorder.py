"""The recorder: one sample per IPO cycle, and the derived quantities of a run (SI).

Per sample ``k``: time ``t_k``, program line, joints ``θ_k``, actual TCP pose
``f(θ_k)`` (world, 4×4), the path error against the desired pose ``x_d(t_k)``
(norms of the position and orientation parts of ``f(θ_k) ⊖ x_d``, controlled components
only: a planar arm's task is ``x, y``), Newton iterations, whether the
cycle was relaxed, which joint limits were active, the clearance to every obstacle and
the manipulability of the task Jacobian. Cartesian samples also keep the desired pose
``x_d(t_k)`` and the path tolerance in effect (``R_PATH_TOL``), so that a drive run can
judge its *actual* TCP against the commanded path (:mod:`irlc.runtime.outputs.actual_motion`).

Samples go into preallocated arrays that double their capacity when full (no Python
object per sample: ≈ 430 B per sample on koch11, 11 joints; the unfilled capacity is
never touched, so it costs address space, not memory). :meth:`Recorder.arrays` returns
read-only *views* of the filled rows, not copies: a long run keeps its samples once, not
twice (1 h of koch11, 360,000 samples: ≈ 155 MB saved). A view stays valid: later
samples go to rows after it (or into a new buffer when the capacity doubles), and
:meth:`Recorder.rewind` only drops samples recorded after a :meth:`Recorder.mark`, which
the views taken before it do not reach.

Derivatives are **backward finite differences** on the sample grid, computed once after
the run (vectorised),

    θ̇_k = (θ_k − θ_{k−1}) / (t_k − t_{k−1}),   θ̈_k = (θ̇_k − θ̇_{k−1}) / (t_k − t_{k−1}),

with the robot at rest before the first sample (``θ̇_0 = θ̈_0 = 0``). These are exactly the
quantities the inverse transformation bounds each cycle (its box limits the cycle
displacement ``θ_k − θ_{k−1}`` and its change), so a check of the trace against the
limits is a check of the controller.
"""

from __future__ import annotations

import dataclasses
import tempfile
from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np
from irlc.runtime.ik.limits import SOURCE_NAMES, active_label, encode_active
from irlc.runtime.model import spatial


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


class Recorder:
    """Samples of a run in growing arrays (see the module doc)."""

    def __init__(
        self,
        n: int,
        obstacle_names: tuple[str, ...] = (),
        task_rows: tuple[int, ...] = (0, 1, 2, 3, 4, 5),  # controlled pose-error components
        capacity: int = 1024,
    ):
        self.n = n
        self.obstacle_names = tuple(obstacle_names)
        self.task_rows = tuple(task_rows)
        rows = np.array(self.task_rows, dtype=int)
        self._pos_rows = rows[rows < 3]
        self._ori_rows = rows[rows >= 3]
        self.relaxed_spans: list[RelaxedSpan] = []
        self.events: list[dict] = []
        self.warnings: list[str] = []
        self.ik_cycles = 0
        self._k = 0  # samples recorded (spilled ones included)
        self._base = 0  # the index of the buffer's first row (rows before it are spilled)
        self._pins: list[int] = []  # the sample counts of the marks still held
        self._spill: _SpillFile | None = None
        self._alloc(max(1, capacity))
        self._last_clearance = [float("inf")] * len(self.obstacle_names)
        self._last_link = [0] * len(self.obstacle_names)  # the robot link nearest each obstacle
        self.tol_position = 5e-5  # m, the path tolerance in effect (R_PATH_TOL), per sample

    def _alloc(self, cap: int) -> None:
        """(Re)allocate the sample arrays with room for ``cap`` samples, keeping the
        filled rows."""
        k, n, m = self._k - self._base, self.n, len(self.obstacle_names)
        new = {
            "times": np.empty(cap),
            "lines": np.empty(cap, dtype=int),
            "q": np.empty((cap, n)),
            "tcp": np.empty((cap, 4, 4)),
            "pos_error": np.empty(cap),
            "ori_error": np.empty(cap),
            "iterations": np.empty(cap, dtype=int),
            "relaxed": np.empty(cap, dtype=bool),
            "manipulability": np.empty(cap),
            "dt": np.zeros(cap),
            "active": np.zeros((cap, n), dtype=np.int8),  # codes of ik.limits.active_codes
            "clearance": np.empty((cap, m)),
            "clearance_link": np.zeros((cap, m), dtype=np.int16),  # link of the clearance
            "desired": np.empty((cap, 4, 4)),  # x_d(t_k) where on_path
            "on_path": np.zeros(cap, dtype=bool),  # a Cartesian path is commanded
            "tol": np.empty(cap),  # m
        }
        for name, arr in new.items():
            if k:
                arr[:k] = getattr(self, "_" + name)[:k]
            setattr(self, "_" + name, arr)
        self._cap = cap

    def __len__(self) -> int:
        return self._k

    def spill(self, capacity: int = 8192) -> None:
        """From now on keep at most about ``capacity`` samples in memory: full buffers go
        to a temporary file (module doc). The buffer is resized to ``capacity`` rows."""
        self._spill = self._spill or _SpillFile()
        self._alloc(max(capacity, self._k - self._base, 2))

    @property
    def pos_error(self) -> np.ndarray:
        """Path position errors of the samples in memory (m; a view; all of them unless
        spilled)."""
        return self._pos_error[: self._k - self._base]

    @property
    def ori_error(self) -> np.ndarray:
        """Path orientation errors of the samples in memory (rad; a view)."""
        return self._ori_error[: self._k - self._base]

    @property
    def spilled(self) -> int:
        """How many samples are in the temporary file (0: all in memory)."""
        return self._base

    def rows(self, name: str, start: int, stop: int) -> np.ndarray:
        """Rows ``start:stop`` (sample indices of the run) of one sample array, a view;
        only samples still in memory (those after the oldest held mark are)."""
        if start < self._base:
            raise IndexError(f"samples before {self._base} were spilled (Recorder.spill)")
        return getattr(self, "_" + name)[start - self._base : stop - self._base]

    def add(
        self,
        t: float,
        line: int,
        q: np.ndarray,
        tcp: np.ndarray,
        desired: np.ndarray | None,
        *,
        errors: tuple[float, float] | None = None,
        iterations: int = 0,
        relaxed: bool = False,
        active: dict[int, str] | None = None,
        active_codes: np.ndarray | None = None,
        clearances: dict[str, tuple[float, int]] | None = None,
        manipulability: float = float("nan"),
        dt: float = 0.0,
    ) -> None:
        """Append one sample. The path error is ``errors`` (position m, orientation rad)
        when given (the inverse transformation's own, at ``q``), else computed against
        ``desired``, the desired TCP pose (``None``: the actual pose, i.e. no path error,
        e.g. standing still or PTP). Active limits: ``active_codes`` (per joint, coded by
        :func:`~irlc.runtime.ik.limits.active_codes`) or ``active`` (joint → label); they
        count ``dt`` towards :attr:`active_time`."""
        if self._k - self._base == self._cap:
            self._make_room()
        k = self._k - self._base  # the buffer row
        self._times[k] = t
        self._lines[k] = line
        self._q[k] = q
        self._tcp[k] = tcp
        if errors is None:
            errors = (0.0, 0.0) if desired is None else self.path_error(tcp, desired)
        self._pos_error[k], self._ori_error[k] = errors
        on_path = desired is not None and np.shape(desired) == (4, 4)
        self._on_path[k] = on_path
        self._desired[k] = desired if on_path else tcp
        self._tol[k] = self.tol_position
        self._iterations[k] = iterations
        self._relaxed[k] = relaxed
        self._manipulability[k] = manipulability
        self._dt[k] = dt
        if active_codes is not None:
            self._active[k] = active_codes
        elif active:
            for j, label in active.items():
                self._active[k, j] = encode_label(label)
        if self.obstacle_names:
            self._add_clearances(k, clearances)
        self._k += 1

    def _make_room(self) -> None:
        """The buffer is full: spill the rows no mark holds (keeping the one before the
        oldest mark, which a blend reads back) when that frees half of it, else double it."""
        free = self._k if not self._pins else max(min(self._pins) - 1, self._base)
        if self._spill is None or free - self._base < self._cap // 2:
            self._alloc(2 * self._cap)
            return
        n = free - self._base
        names = _FIELDS
        self._spill.write({name: getattr(self, "_" + name)[:n] for name in names})
        kept = self._k - free
        for name in names:
            arr = getattr(self, "_" + name)
            arr[:kept] = arr[n : n + kept]
            if name in ("dt", "active", "on_path"):  # zero-filled by default (add)
                arr[kept:] = 0
        self._base = free

    def restamp_first(
        self, tcp: np.ndarray, clearances: dict[str, tuple[float, int]] | None = None
    ) -> None:
        """Replace the TCP pose (and clearances) of the start sample while it is the only
        one: the program set another tool (``R_TOOL``) before it first moved, and every
        output uses the program's tool from t = 0."""
        if self._k != 1 or self._base:
            raise ValueError("only the start sample can be re-stamped, before the next one")
        self._tcp[0] = tcp
        if not self._on_path[0]:  # off a path the desired pose is the sample's own
            self._desired[0] = tcp
        if self.obstacle_names:
            self._last_clearance = [float("inf")] * len(self.obstacle_names)
            self._last_link = [0] * len(self.obstacle_names)
            self._add_clearances(0, clearances)

    @property
    def active_time(self) -> dict[tuple[int, str], float]:
        """(joint, ``"speed max"``-style label) → seconds the limit was active (the
        ``dt`` of the samples it was active in, summed in time order)."""
        out: dict[tuple[int, str], float] = {}
        for piece in self._pieces(("active", "dt")):
            codes, dts = piece["active"], piece["dt"]
            for k, j in zip(*np.nonzero(codes), strict=True):
                key = (int(j), active_label(codes[k, j]))
                out[key] = out.get(key, 0.0) + float(dts[k])
        return out

    def _add_clearances(self, k: int, clearances: dict[str, tuple[float, int]] | None) -> None:
        last, link = self._last_clearance, self._last_link
        if clearances:
            for i, name in enumerate(self.obstacle_names):
                if name in clearances:
                    last[i] = float(clearances[name][0])
                    link[i] = int(clearances[name][1])
        # not measured this cycle (robot standing): the last value is repeated
        self._clearance[k] = last
        self._clearance_link[k] = link

    def last_clearances(self) -> dict[str, tuple[float, int]]:
        """Obstacle → (clearance m, link) of the last sample (infinite before any)."""
        return {
            name: (self._last_clearance[i], self._last_link[i])
            for i, name in enumerate(self.obstacle_names)
        }

    def path_error(self, tcp: np.ndarray, desired: np.ndarray) -> tuple[float, float]:
        """Norms of the position and orientation parts of ``tcp ⊖ desired`` on the
        controlled task components (m, rad)."""
        err = spatial.pose_error(tcp, desired)
        return float(np.linalg.norm(err[self._pos_rows])), float(
            np.linalg.norm(err[self._ori_rows])
        )

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

    def mark(self) -> tuple:
        """The recorder's state, to :meth:`rewind` to (a blend that is tried and
        shortened: approximate positioning)."""
        spans = [dataclasses.replace(s) for s in self.relaxed_spans]
        self._pins.append(self._k)  # its samples stay in memory until release(mark)
        return (self._k, spans, len(self.warnings), len(self.events), self.ik_cycles,
                list(self._last_clearance), list(self._last_link))  # fmt: skip

    def rewind(self, mark: tuple) -> None:
        """Drop every sample, span, warning and event recorded after :meth:`mark`."""
        if mark[0] < self._base:
            raise RuntimeError("rewind to samples that were spilled (a mark not held)")
        self._k, spans, n_warn, n_events, self.ik_cycles, clearance, link = mark
        self.relaxed_spans = [dataclasses.replace(s) for s in spans]
        del self.warnings[n_warn:], self.events[n_events:]
        self._last_clearance, self._last_link = list(clearance), list(link)

    def truncate(self, k: int) -> None:
        """Drop the samples from ``k`` on (still in memory): a cell's samples of the other
        robots recorded during a blend that was undone (runtime/control/cell.py)."""
        if not self._base <= k <= self._k:
            raise IndexError(f"cannot truncate {self._k} samples to {k}")
        self._k = k
        if self.obstacle_names and k > self._base:
            row = k - 1 - self._base
            self._last_clearance = [float(v) for v in self._clearance[row]]
            self._last_link = [int(v) for v in self._clearance_link[row]]

    def release(self, mark: tuple) -> None:
        """The caller of :meth:`mark` will not :meth:`rewind` to it any more: its samples
        may be spilled (module doc)."""
        if mark[0] in self._pins:
            self._pins.remove(mark[0])

    # ------------------------------------------------------------------ arrays
    def _rows(self, name: str) -> np.ndarray:
        """A read-only view of the filled rows of one sample array (module doc)."""
        view = getattr(self, "_" + name)[: self._k - self._base]
        view.flags.writeable = False
        return view

    def _pieces(self, names: tuple[str, ...] = ()) -> Iterator[dict[str, np.ndarray]]:
        """The samples in order as pieces ``name → rows`` (all fields unless ``names``):
        the spilled ones read back from the file, then the buffer's (views)."""
        names = names or _FIELDS
        if self._spill is not None:
            yield from self._spill.read(names, self._base)
        if self._k > self._base or not self._base:
            yield {name: self._rows(name) for name in names}

    def arrays(self) -> RecordedRun:
        """The samples so far as a :class:`RecordedRun` of read-only views (module doc);
        speeds, accelerations, the active flags and the clearances are new arrays. After
        spilling, the pieces joined: the whole run in memory."""
        if not self._base:
            return self._recorded(self._pieces().__next__(), None)
        pieces = list(self._pieces())
        whole = {name: np.concatenate([p[name] for p in pieces]) for name in _FIELDS}
        return self._recorded(whole, None)

    def chunks(self) -> Iterator[RecordedRun]:
        """The samples so far as consecutive :class:`RecordedRun` pieces (one when nothing
        was spilled); each piece's derivatives carry the previous piece's last row, so they
        equal those of :meth:`arrays` row for row."""
        carry = None
        for piece in self._pieces():
            rec = self._recorded(piece, carry)
            if len(rec.times):
                carry = (rec.times[-1], rec.q[-1], rec.speed[-1])
            yield rec

    def _recorded(self, piece: dict[str, np.ndarray], carry) -> RecordedRun:
        """A :class:`RecordedRun` of one piece (``carry``: :func:`finite_differences`')."""
        times, q = piece["times"], piece["q"]
        args = (times, q) if carry is None else (times, q, carry)
        speed, accel = finite_differences(*args)
        clearance, link = piece["clearance"], piece["clearance_link"]
        return RecordedRun(
            times=times,
            lines=piece["lines"],
            q=q,
            speed=speed,
            accel=accel,
            tcp=piece["tcp"],
            pos_error=piece["pos_error"],
            ori_error=piece["ori_error"],
            iterations=piece["iterations"],
            relaxed=piece["relaxed"],
            manipulability=piece["manipulability"],
            active=piece["active"] != 0,
            clearance={name: clearance[:, i].copy() for i, name in enumerate(self.obstacle_names)},
            desired=piece["desired"],
            on_path=piece["on_path"],
            tol_position=piece["tol"],
            clearance_link={
                name: link[:, i].astype(int) for i, name in enumerate(self.obstacle_names)
            },
        )


_FIELDS = ("times", "lines", "q", "tcp", "pos_error", "ori_error", "iterations", "relaxed",
           "manipulability", "dt", "active", "clearance", "clearance_link", "desired", "on_path",
           "tol")  # fmt: skip


class _SpillFile:
    """Spilled samples: an anonymous temporary file (deleted when closed) of raw rows,
    one record ``(rows, {field: (offset, dtype, row shape)})`` per spilled piece."""

    def __init__(self):
        # open as long as the recorder (its samples); deleted when closed or collected
        self._file = tempfile.TemporaryFile(prefix="irlc-samples-")  # noqa: SIM115
        self._pieces: list[tuple[int, dict[str, tuple[int, np.dtype, tuple]]]] = []

    def write(self, arrays: dict[str, np.ndarray]) -> None:
        """Append one piece (equal row counts)."""
        f, layout, rows = self._file, {}, 0
        f.seek(0, 2)
        for name, arr in arrays.items():
            rows = len(arr)
            layout[name] = (f.tell(), arr.dtype, arr.shape[1:])
            f.write(np.ascontiguousarray(arr).tobytes())
        self._pieces.append((rows, layout))

    def read(self, names: tuple[str, ...], upto: int) -> Iterator[dict[str, np.ndarray]]:
        """The pieces in order (``upto``: the samples spilled; a check)."""
        total = 0
        for rows, layout in self._pieces:
            out = {}
            for name in names:
                offset, dtype, shape = layout[name]
                self._file.seek(offset)
                count = rows * int(np.prod(shape, dtype=int))
                arr = np.fromfile(self._file, dtype=dtype, count=count).reshape((rows, *shape))
                arr.flags.writeable = False
                out[name] = arr
            total += rows
            yield out
        if total != upto:
            raise RuntimeError(f"spill file holds {total} samples, expected {upto}")


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
    desired: np.ndarray | None = None  # (k, 4, 4) x_d(t_k); the sample's TCP off the path
    on_path: np.ndarray | None = None  # (k,) bool: a Cartesian path is commanded
    tol_position: np.ndarray | None = None  # (k,) m, the path tolerance in effect
    clearance_link: dict[str, np.ndarray] | None = None  # the link nearest each obstacle


def encode_label(label: str) -> int:
    """The active-limit code of a ``"speed max"``-style label."""
    source, side = label.split()
    return encode_active(SOURCE_NAMES.index(source), side == "max")


def finite_differences(
    times: np.ndarray, q: np.ndarray, carry: tuple | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Backward differences (module doc); rest before the first sample. ``carry``: the
    time, joints and speed of the sample before ``times[0]`` (a later piece of a run: the
    same values row for row as the whole run's)."""
    if carry is not None and len(times):
        t0, q0, v0 = carry
        speed, accel = _differences(np.r_[t0, times], np.vstack([q0, q]))
        accel[1] = (speed[1] - v0) / _positive_step(times[0] - t0)
        return speed[1:], accel[1:]
    return _differences(times, q)


def _differences(times: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`finite_differences` of a whole run (rest before the first sample)."""
    speed = np.zeros_like(q)
    accel = np.zeros_like(q)
    if len(times) < 2:
        return speed, accel
    dt = _positive_step(np.diff(times)[:, None])  # repeated time stamps: no derivative
    speed[1:] = np.diff(q, axis=0) / dt
    accel[1:] = np.diff(speed, axis=0) / dt
    return speed, accel


def _positive_step(dt):
    """``Δt`` where positive, else ∞ (a repeated time stamp: no derivative)."""
    return np.where(dt > 0.0, dt, np.inf)


def backward_jerk(times: np.ndarray, accel: np.ndarray, carry: tuple | None = None) -> np.ndarray:
    """The jerk as the backward difference of :func:`finite_differences`' accelerations
    (third differences of the positions over ``Δt³`` on a uniform grid); 0 at the first
    sample. ``carry``: the time and acceleration of the sample before ``times[0]``."""
    if carry is not None and len(times):
        t0, a0 = carry
        return backward_jerk(np.r_[t0, times], np.vstack([a0, accel]))[1:]
    jerk = np.zeros_like(accel)
    if len(times) < 2:
        return jerk
    dt = np.diff(times)[:, None]
    jerk[1:] = np.diff(accel, axis=0) / _positive_step(dt)
    return jerk
