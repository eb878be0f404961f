"""Drive simulation speed: simulated time / wall (and CPU) time per fidelity level.

Setpoints come from the real pipeline run kinematically (``--drives ideal``): the koch11
square of chapter 6 (``programs/square.irl``) and a straight line of the irb6_track (a
small program written here: PTP to home, LIN 300 mm along the track's direction and
back). The drive simulation alone is timed, best of ``--repeat``. Usage::

    python bench/bench_drives.py [--repeat 2] [--pwm-koch11]
"""

from __future__ import annotations

import argparse
import platform
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
from irlc.runtime.drives import simulate_drives
from irlc.runtime.run import run_file

ROOT = Path(__file__).resolve().parents[1]
LINE = """PROGRAM drive_line;
ROBOT r := irb6_track;
BEGIN
  R_SPEED := 150;
  R_ACC := 500;
  MOVE PTP (400, 90, 0, 0, -45, 0);
  MOVE_INC LIN (0, 0, 150, 0, 0, 0);
  MOVE_INC LIN (0, 0, -150, 0, 0, 0);
ENDPROGRAM
"""


def setpoints(name: str):
    """``(model, times, q)`` of a kinematic run."""
    if name == "irb6_track line":
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "drive_line.irl"
            path.write_text(LINE, encoding="utf-8")
            run = run_file(path, drives="ideal")
    else:
        run = run_file(ROOT / "programs" / "square.irl", drives="ideal")
    if not run.ok:
        raise SystemExit(f"{name}: the kinematic run failed: {run.error.message}")
    return run.model, run.times, run.q


def timed(model, times, q, level, step, repeat, every=None):
    best = None
    for _ in range(repeat):
        w0, c0 = time.perf_counter(), time.process_time()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            run = simulate_drives(
                model, times, q, level=level, step=step, hold=0.0, dynamics_every=every
            )
        wall, cpu = time.perf_counter() - w0, time.process_time() - c0
        if best is None or wall < best[0]:
            best = (wall, cpu, run)
    return best


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--pwm-koch11", action="store_true", help="also time pwm on koch11 (slow)")
    args = ap.parse_args()
    print(f"python {platform.python_version()}, numpy {np.__version__}, {platform.machine()}")
    print(
        "| case | level | step | M refresh | steps | simulated s | wall s "
        "| × real time (wall) | × real time (CPU) | max dev. vs rule step, % range "
        "| could follow |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for case in ("irb6_track line", "koch11 square"):
        model, times, q = setpoints(case)
        plan = [
            ("decoupled", None, None),
            ("decoupled", 1e-3, None),
            ("coupled", None, None),
            ("coupled", 1e-3, None),
            ("coupled", 1e-3, 2),
            ("coupled", 1e-3, 4),
        ]
        if case == "irb6_track line" or args.pwm_koch11:
            plan.append(("pwm", None, None))
        reference = {}
        for level, step, every in plan:
            wall, cpu, run = timed(model, times, q, level, step, args.repeat, every)
            sim = run.t[-1] - run.t[0]
            label = "rule" if step is None else "forced"
            if step is None:
                reference[level] = run
            dev = _deviation(reference.get(level), run)
            follow = (
                "yes"
                if run.could_follow
                else "no: " + ", ".join(a.name for a in run.axes if not a.could_follow)
            )
            refresh = (
                "every step"
                if level != "pwm" and every is None
                else ("1 ms" if every is None else f"{every} steps")
            )
            print(
                f"| {case} | {level} | {run.step * 1e3:.4g} ms ({label}) | {refresh} "
                f"| {len(run.t)} | {sim:.2f} | {wall:.2f} | {sim / wall:.2f} | {sim / cpu:.2f} "
                f"| {dev} | {follow} |"
            )


def _deviation(reference, run) -> str:
    """Largest joint deviation from the rule-step run, in % of each joint's range."""
    if reference is None or reference is run:
        return "—"
    span = np.ptp(reference.q_cmd_interp, axis=0)
    ref = np.array(
        [
            np.interp(run.t, reference.t, reference.q_actual[:, j])
            for j in range(run.q_actual.shape[1])
        ]
    ).T
    dev = np.max(np.abs(ref - run.q_actual), axis=0) / np.where(span > 0, span, np.inf)
    return f"{100 * dev.max():.3g}"


if __name__ == "__main__":
    main()
