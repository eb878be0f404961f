"""Every program of programs/ on both IK paths in one run: numpy and compiled (numba).

Each program is compiled once; then its kinematic run (ideal drives, the program's own
R_IPO) is timed with ``IKParams(accel=False)`` (numpy, the reference) and
``IKParams(accel=True)`` (the compiled cycle), the two alternating, ``--repeat`` rounds,
best and median wall time of each. The accelerator's kernels are compiled (or loaded
from numba's cache) before the first timed run. Both columns come from the same run, so
they compare even on a busy machine. Usage::

    python bench/bench_programs.py [--repeat 3] [--json out.json] [PROGRAM.irl …]

Prints a Markdown table (× real time = simulated s / wall s, from the best round); the
ratio column is numpy wall / compiled wall (> 1: the accelerator is faster). The process's
CPU time of each run is measured too (best round; on a loaded machine it is the figure
that compares with a quiet one): the compiled path's CPU s and × real time by CPU close
each row.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import time
from pathlib import Path

from irlc.lang.compiler import compile_file
from irlc.runtime import accel_support, warmup
from irlc.runtime.control.executor import ExecutionOptions
from irlc.runtime.ik.params import IKParams
from irlc.runtime.run import resolve_model, robot_resolver, run_code

PROGRAMS = Path(__file__).resolve().parents[1] / "programs"
PATHS = (("numpy", False), ("compiled", True))


def _time_once(code, model, base: Path, flag: bool) -> tuple[float, float, dict]:
    """Wall and CPU seconds of one run, and its report."""
    opts = ExecutionOptions(ik=IKParams.for_robot(model, accel=flag))
    t0, c0 = time.perf_counter(), time.process_time()
    run = run_code(code, robot=model, base_dir=base, options=opts)
    return time.perf_counter() - t0, time.process_time() - c0, run.report


def measure(path: Path, repeat: int) -> dict:
    """Wall times of one program on both paths (rounds alternate the paths)."""
    result = compile_file(path, resolve_robot=robot_resolver(path.parent, None))
    model = resolve_model(result.code, None, path.parent)
    walls: dict[str, list[float]] = {name: [] for name, _ in PATHS}
    cpus: dict[str, list[float]] = {name: [] for name, _ in PATHS}
    report: dict = {}
    for _ in range(repeat):
        for name, flag in PATHS:
            wall, cpu, report = _time_once(result.code, model, path.parent, flag)
            walls[name].append(wall)
            cpus[name].append(cpu)
    sim = float(report.get("duration_s", 0.0))
    out = {"program": path.name, "status": report.get("status"), "simulated_s": sim,
           "ipo_cycles": max(int(report.get("samples", 1)) - 1, 1)}  # fmt: skip
    for name, _ in PATHS:
        best = min(walls[name])
        out[f"{name}_wall_s_best"] = best
        out[f"{name}_wall_s_median"] = statistics.median(walls[name])
        out[f"{name}_x_real_time"] = sim / best if best > 0 else None
        cpu = min(cpus[name])
        out[f"{name}_cpu_s_best"] = cpu
        out[f"{name}_x_real_time_cpu"] = sim / cpu if cpu > 0 else None
    out["speedup"] = out["numpy_wall_s_best"] / out["compiled_wall_s_best"]
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("programs", nargs="*", help="default: every programs/*.irl")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--json", type=Path, default=None, help="also write the rows as JSON")
    args = ap.parse_args()
    if not accel_support.AVAILABLE:
        raise SystemExit("numba is not installed (pip install 'irlc[fast]')")
    files = [Path(p) for p in args.programs] or sorted(PROGRAMS.glob("*.irl"))
    seconds = warmup.warm_ik() + warmup.warm_ik_obstacles()
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"python {platform.python_version()}, {platform.machine()}, kernels ready in "
          f"{seconds:.2f} s, load average (1 min) {load:.2f}, best of {args.repeat}")  # fmt: skip
    print("| program | simulated s | IPO cycles | numpy wall s | numpy × real time "
          "| compiled wall s | compiled × real time | numpy / compiled "
          "| compiled CPU s | compiled × real time (CPU) |")  # fmt: skip
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    rows = []
    for path in files:
        row = measure(path, args.repeat)
        rows.append(row)
        print(f"| {row['program']} | {row['simulated_s']:.2f} | {row['ipo_cycles']} | "
              f"{row['numpy_wall_s_best']:.3f} | {row['numpy_x_real_time']:.1f} | "
              f"{row['compiled_wall_s_best']:.3f} | {row['compiled_x_real_time']:.1f} | "
              f"{row['speedup']:.2f} | {row['compiled_cpu_s_best']:.3f} | "
              f"{row['compiled_x_real_time_cpu']:.1f} |", flush=True)  # fmt: skip
    if args.json is not None:
        doc = {"units": {"time": "s"}, "load_average_1min": load, "rows": rows}
        args.json.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
