"""Whole-program speed: simulated time / wall time of the kinematic run (ideal drives).

Each program is compiled once; the run (interpreter → pre-interpolator → interpolator →
inverse transformation every IPO cycle → recorder → report and trace) is timed, best of
``--repeat`` runs. ``--split`` also times the inverse transformation's ``step`` inside
the best run (a wrapper adds ≈ 0.3 µs per call) and reports the rest of the pipeline per
cycle. ``--engine`` sets ``IRLC_ENGINE`` (numpy, the default, or compiled; both: one
after the other); ``--json FILE`` writes the rows (``bench/bench_json.py``). Usage::

    python bench/bench_run.py [--repeat 3] [--ipo 0.01] [--split] [--engine numpy compiled]
                              [--json out.json]
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import platform
import time
from pathlib import Path

from bench_json import Recorder  # (bench/: the script's folder is on sys.path)
from irlc.lang.compiler import compile_file
from irlc.robots import load_robot
from irlc.runtime.ik.newton import InverseTransformation
from irlc.runtime.run import robot_resolver, run_code

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


_IK_TIME = [0.0]


def _timed_step(step):
    def timed(self, *args, **kwargs):
        t0 = time.perf_counter()
        try:
            return step(self, *args, **kwargs)
        finally:
            _IK_TIME[0] += time.perf_counter() - t0

    return timed


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--ipo", type=float, default=None)
    ap.add_argument("--split", action="store_true", help="time the IK step separately")
    ap.add_argument("--engine", nargs="+", default=["numpy"], choices=("numpy", "compiled"))
    ap.add_argument("--json", default=None, help="write the rows as JSON to this file")
    args = ap.parse_args()
    if args.split:
        InverseTransformation.step = _timed_step(InverseTransformation.step)
    out = Recorder("run", ",".join(args.engine), repeat=args.repeat, ipo_s=args.ipo,
                   split=args.split)  # fmt: skip
    print(f"python {platform.python_version()}, {platform.machine()}, ipo {args.ipo or 'R_IPO'}")
    extra = " IK µs / cycle | rest µs / cycle |" if args.split else ""
    print(
        f"| program | what | engine | simulated s | IPO cycles | wall s (best of {args.repeat}) "
        f"| ms / cycle | × real time |{extra}"
    )
    print("|---|---|---|---:|---:|---:|---:|---:|" + ("---:|---:|" if args.split else ""))
    for engine in args.engine:
        os.environ["IRLC_ENGINE"] = engine  # read when each run builds its solver
        for file, what in CASES:
            _one(file, what, engine, args, out)
    out.write(args.json)


def _one(file: str, what: str, engine: str, args, out: Recorder) -> None:
    path = PROGRAMS / file
    result = compile_file(path, resolve_robot=robot_resolver(path.parent, None))
    robot = _robot_for(result.code.robot)
    best, best_ik = float("inf"), 0.0
    for _ in range(args.repeat):
        _IK_TIME[0] = 0.0
        t0 = time.perf_counter()
        run = run_code(result.code, robot=robot, ipo=args.ipo, base_dir=path.parent)
        wall = time.perf_counter() - t0
        if wall < best:
            best, best_ik = wall, _IK_TIME[0]
    sim = run.report["duration_s"]
    cycles = max(run.report["samples"] - 1, 1)
    row = out.add(program=file, what=what, engine=engine, simulated_s=sim, ipo_cycles=cycles,
                  wall_s=round(best, 4), ms_per_cycle=round(1e3 * best / cycles, 4),
                  x_real_time=round(sim / best, 1))  # fmt: skip
    split = ""
    if args.split:
        row["ik_us_per_cycle"] = round(1e6 * best_ik / cycles, 1)
        row["rest_us_per_cycle"] = round(1e6 * (best - best_ik) / cycles, 1)
        split = f" {row['ik_us_per_cycle']:.0f} | {row['rest_us_per_cycle']:.0f} |"
    print(
        f"| {file} | {what} | {engine} | {sim:.2f} | {cycles} | {best:.3f} | "
        f"{1e3 * best / cycles:.3f} | {sim / best:.1f} |{split}",
        flush=True,
    )


if __name__ == "__main__":
    main()
