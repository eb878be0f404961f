"""Whole-program speed: simulated time / wall time of the kinematic run (ideal drives).

Each program is compiled once; the run (interpreter → pre-interpolator → interpolator →
inverse transformation every IPO cycle → recorder → report and trace) is timed, best of
``--repeat`` runs. Usage::

    python bench/bench_run.py [--repeat 3] [--ipo 0.01]
"""

from __future__ import annotations

import argparse
import dataclasses
import platform
import time
from pathlib import Path

from irlc.lang.compiler import compile_file
from irlc.robots import load_robot
from irlc.runtime.run import _robot_resolver, run_code

PROGRAMS = Path(__file__).resolve().parents[1] / "programs"
CASES = [
    ("square.irl", "koch11 square (default criterion)"),
    ("square_speed.irl", "koch11 square, speed limits 6.2"),
    ("square_freeze.irl", "koch11 square, FREEZE 2,3 + limits"),
    ("square_cyclic.irl", "koch11 square x3, CYCLIC"),
    ("obstacle_line_avoid.irl", "koch11 vertical line, OBSTACLE"),
    ("combined.irl", "koch11 chapter 5.2, all options"),
    ("planar3_cyclic.irl", "planar3 square x4, CYCLIC"),
    ("mobile8_freeze.irl", "mobile8, FREEZE 1,2"),
]


def _robot_for(name: str):
    model = load_robot(name)
    if name.startswith("planar") and "ik" not in model.extra:
        model = dataclasses.replace(model, extra={**model.extra, "ik": {"task": ["x", "y"]}})
    return model


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--ipo", type=float, default=None)
    args = ap.parse_args()
    print(f"python {platform.python_version()}, {platform.machine()}, ipo {args.ipo or 'R_IPO'}")
    print(
        f"| program | what | simulated s | IPO cycles | wall s (best of {args.repeat}) "
        "| ms / cycle | × real time |"
    )
    print("|---|---|---:|---:|---:|---:|---:|")
    for file, what in CASES:
        path = PROGRAMS / file
        result = compile_file(path, resolve_robot=_robot_resolver(path.parent, None))
        robot = _robot_for(result.code.robot)
        best = float("inf")
        for _ in range(args.repeat):
            t0 = time.perf_counter()
            run = run_code(result.code, robot=robot, ipo=args.ipo, base_dir=path.parent)
            best = min(best, time.perf_counter() - t0)
        sim = run.report["duration_s"]
        cycles = run.report["samples"] - 1
        print(
            f"| {file} | {what} | {sim:.2f} | {cycles} | {best:.3f} | "
            f"{1e3 * best / max(cycles, 1):.3f} | {sim / best:.1f} |"
        )


if __name__ == "__main__":
    main()
