"""A failed drive run stops where it failed.

The drives are simulated after the kinematic run, on all its set points (they do not feed
back into it), and the verdict (:mod:`irlc.runtime.outputs.verdict`) finds the first
violation at ``t_f``. A robot whose drive cannot follow is stopped there, so everything
the run reports ends at ``t_f``, as it does for a kinematic failure:

* the samples (set points, actual motion, the drive's rows: :func:`samples_until`,
  :func:`drive_until`) — so the trace, the duration, the joints' extrema, the IK figures
  and the drive summary (its peaks, following errors and saturation time up to ``t_f``,
  no settling) — and the verdict judged on them again;
* the cycle-time table (:func:`statements_until`: the statement running at ``t_f`` is
  marked ``failed`` and ends there; later ones did not run);
* the program's output and events (:func:`before`: what the program did before ``t_f``;
  output written at ``t_f`` itself comes after the failing sample), the relaxed-cycle
  spans and the approximated points.

Cutting after the simulation gives what a simulation stopped at ``t_f`` would: the drives
and the set-point interpolation are causal, only the settling tail after the last sample
is not simulated any more.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import fields, replace
from typing import TYPE_CHECKING, TypeVar

import numpy as np
from irlc.runtime.outputs.cycle_time import StatementSpan
from irlc.runtime.outputs.samples import Motion, Samples, commanded

if TYPE_CHECKING:
    from irlc.runtime.drives import DriveRun
    from irlc.runtime.outputs.actual_motion import ActualMotion
    from irlc.runtime.outputs.recorder import RecordedRun

T = TypeVar("T")
SLACK = 1e-9  # s: a sample at the failure time (rounded to 1 ns) is the failing one


def rows_until(times: np.ndarray, t_end: float) -> int:
    """The number of rows with ``time ≤ t_end``."""
    return int(np.searchsorted(times, t_end + SLACK, side="right"))


def _sliced(obj: T, k: int, length: int, keep: tuple[str, ...] = ()) -> T:
    """A copy of the dataclass ``obj`` with every array of ``length`` rows (and every
    dict of them) cut to its first ``k`` rows, except the fields ``keep``."""
    changes = {}
    for f in fields(obj):  # type: ignore[arg-type]
        if f.name in keep:
            continue
        value = getattr(obj, f.name)
        if isinstance(value, np.ndarray) and value.ndim and len(value) == length:
            changes[f.name] = value[:k]
        elif isinstance(value, dict) and all(
            isinstance(v, np.ndarray) and len(v) == length for v in value.values()
        ):
            changes[f.name] = {name: v[:k] for name, v in value.items()}
    return replace(obj, **changes)  # type: ignore[type-var]


def recorded_until(rec: RecordedRun, t_end: float) -> RecordedRun:
    """The recorded samples up to ``t_end``."""
    return _sliced(rec, rows_until(rec.times, t_end), len(rec.times))


def actual_until(actual: ActualMotion, t_end: float) -> ActualMotion:
    """The measured actual motion up to ``t_end``."""
    return _sliced(actual, rows_until(actual.times, t_end), len(actual.times))


def motion_until(motion: Motion | None, t_end: float) -> Motion | None:
    return None if motion is None else _sliced(motion, rows_until(motion.times, t_end),
                                               len(motion.times))  # fmt: skip


def drive_until(drive: DriveRun, t_end: float, bound: np.ndarray) -> DriveRun:
    """The drive run up to ``t_end``, its per-axis summary over that part: the largest
    and the last following error, the peaks, the saturation time; ``settling_time`` is
    ``None`` (it was stopped, not settled); ``could_follow`` against ``bound`` (SI)."""
    k = max(rows_until(drive.t, t_end), 1)
    per_joint = ("driven", "electrical_energy", "copper_energy")  # (n,), not rows
    cut = _sliced(drive, k, len(drive.t), per_joint)
    err = np.abs(cut.following_error)
    axes = []
    for a in cut.axes:
        j = a.joint
        saturation = a.saturation_time
        if cut.saturation_cum is not None:
            saturation = float(cut.saturation_cum[-1, j])
        axes.append(
            replace(
                a,
                max_following_error=float(err[:, j].max()),
                final_error=float(err[-1, j]),
                settling_time=None,
                saturation_time=saturation,
                peak_current=float(np.abs(cut.current[:, j]).max()),
                peak_torque=float(np.abs(cut.torque[:, j]).max()),
                could_follow=bool(err[:, j].max() <= bound[j]) and not a.lost_steps,
            )
        )
    cut.axes = axes
    return cut


def samples_until(samples: Samples, t_end: float) -> Samples:
    """The set points up to ``t_end`` (the actual motion and the drive rows are cut by
    :func:`actual_until`, :func:`drive_until` where the drive stage measures them)."""
    rec = recorded_until(samples.recorded, t_end)
    return Samples(rec, commanded(rec), motion_until(samples.actual, t_end),
                   motion_until(samples.steps, t_end), samples.drive)  # fmt: skip


def statements_until(spans: Iterable[StatementSpan], t_end: float) -> list[StatementSpan]:
    """The cycle-time table up to ``t_end``: the statement running then ends there,
    ``failed``; the ones after it did not run."""
    out = []
    for span in spans:
        if span.start >= t_end - SLACK and out:  # (a failure at t = 0: its first span)
            break
        if span.end > t_end - SLACK:
            out.append(replace(span, end=min(span.end, t_end), stop="failed"))
            break
        out.append(span)
    return out


def before(items: Iterable[tuple[float, T]], t_end: float) -> list[T]:
    """The items of ``(time, item)`` pairs that happened before ``t_end``."""
    return [item for t, item in items if t < t_end - SLACK]
