"""Drive simulation speed: simulated time / wall (and CPU) time per fidelity level.

Setpoints come from the real pipeline run kinematically (``--drives ideal``): the koch11
square of chapter 6 (``programs/square.irl``) and a straight line of the irb6_track (a
small program written here: PTP to home, LIN 300 mm along the track's direction and
back). The drive simulation alone is timed. The cases run interleaved (round-robin over
the whole plan, ``--repeat`` rounds) so that a change in the machine's load hits every case
alike; the table gives the median and the best round, and the load average before and
after. ``--plan core`` times only the 1 ms coupled/decoupled and the pwm runs. Every case
runs the numpy loop (``accel=False``, the reference); with numba installed the cases the
compiled loops cover (``runtime/drives/compiled/loop.py``; pwm: ``pwm_loop.py``) run a second
time with ``accel=True`` (the kernels are compiled or loaded from numba's cache before
timing; ``--no-accel`` skips them). Usage::

    python bench/bench_drives.py [--repeat 3] [--plan full|core] [--pwm-koch11] [--no-accel]

``M refresh``: ``adaptive`` is the default (``runtime/drives/refresh.py``), ``every step``
forces ``dynamics_every=1``, ``k steps`` a fixed interval.
"""

from __future__ import annotations

import argparse
import os
import platform
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
from irlc.runtime import accel_support, warmup
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


def timed(model, times, q, level, step, every, fast):
    w0, c0 = time.perf_counter(), time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run = simulate_drives(
            model, times, q, level=level, step=step, hold=0.0, dynamics_every=every, accel=fast
        )
    return time.perf_counter() - w0, time.process_time() - c0, run


FULL = [
    ("decoupled", None, None),
    ("decoupled", 1e-3, None),
    ("coupled", None, None),
    ("coupled", 1e-3, 1),
    ("coupled", 1e-3, None),
    ("pwm", None, None),
]
CORE = [("decoupled", 1e-3, None), ("coupled", 1e-3, None), ("pwm", None, None)]


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--plan", choices=("full", "core"), default="full")
    ap.add_argument("--pwm-koch11", action="store_true", help="also time pwm on koch11 (slow)")
    ap.add_argument("--no-accel", action="store_true", help="numpy loop only")
    args = ap.parse_args()
    print(f"python {platform.python_version()}, numpy {np.__version__}, {platform.machine()}")
    use_fast = accel_support.AVAILABLE and not args.no_accel
    if use_fast:
        import numba
        from irlc.runtime.drives.compiled import loop, pwm_loop

        warm = loop.KERNELS.cache_warm() and pwm_loop.KERNELS.cache_warm()
        seconds = warmup.warm_drives() + warmup.warm_pwm()
        state = "loaded from cache" if warm else "compiled"
        print(f"numba {numba.__version__}: drive kernel {state} in {seconds:.2f} s")
    load0 = os.getloadavg()
    plan = []
    data = {}
    for case in ("irb6_track line", "koch11 square"):
        data[case] = setpoints(case)
        for level, step, every in FULL if args.plan == "full" else CORE:
            if level != "pwm" or case == "irb6_track line" or args.pwm_koch11:
                plan.append((case, level, step, every, False))
                if use_fast:
                    plan.append((case, level, step, every, True))
    times_of = {item: [] for item in plan}
    runs = {}
    for _ in range(args.repeat):  # interleaved rounds
        for item in plan:
            case, level, step, every, fast = item
            wall, cpu, run = timed(*data[case], level, step, every, fast)
            times_of[item].append((wall, cpu))
            runs[item] = run
    load1 = os.getloadavg()
    print(f"load average (1, 5, 15 min) before {load0}, after {load1}")
    print(
        "| case | level | step | M refresh | loop | steps | simulated s | wall s (median) "
        "| × real time, wall (median / best) | × real time, CPU (median) "
        "| max dev. vs rule step, % range | could follow |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for item in plan:
        case, level, step, every, fast = item
        run = runs[item]
        sim = run.t[-1] - run.t[0]
        wall = np.median([w for w, _ in times_of[item]])
        best = min(w for w, _ in times_of[item])
        cpu = np.median([c for _, c in times_of[item]])
        rule = (case, level, None, None, False)
        dev = _deviation(runs.get(rule), run)
        follow = (
            "yes"
            if run.could_follow
            else "no: " + ", ".join(a.name for a in run.axes if not a.could_follow)
        )
        refresh = "adaptive" if every is None else ("every step" if every == 1 else f"{every}")
        label = "rule" if step is None else "forced"
        print(
            f"| {case} | {level} | {run.step * 1e3:.4g} ms ({label}) | {refresh} "
            f"| {'numba' if fast else 'numpy'} "
            f"| {len(run.t)} | {sim:.2f} | {wall:.2f} | {sim / wall:.2f} / {sim / best:.2f} "
            f"| {sim / cpu:.2f} | {dev} | {follow} |"
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
