"""Length scaling: wall time, × real time and peak memory of one koch11 program at 1×, 10×
and 100× its length (100× ≈ 1 h of robot time, ≈ 360,000 IPO cycles of 10 ms).

The program is generated: the chapter-6 square (``programs/square.irl``) driven around
``3 × scale`` laps by a ``FOR`` loop (``square_cell``'s points). Each length runs as a
fresh ``irlc run PROGRAM --quiet --trace FILE.csv`` process, so the figures are those a
user sees (start-up and the written trace included); peak RSS is the child's
``ru_maxrss`` (``os.wait4``). ``irlc run`` streams (the recorder spills its samples to a
temporary file, the trace is written piece by piece): memory is bounded when the peak
does not grow with the length; time is linear when CPU / cycle stays constant.

"Marginal" figures are the differences to the previous (shorter) length per extra cycle:
start-up and fixed costs cancel. Usage::

    python bench/bench_length.py [--scales 1 10 100] [--engine numpy] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from bench_json import Recorder  # (bench/: the script's folder is on sys.path)

PROGRAMS = Path(__file__).resolve().parents[1] / "programs"
LAPS_PER_SCALE = 3  # 1×: three laps of the square ≈ 37 s of robot time


def program_text(laps: int) -> str:
    """The generated program: the square, ``laps`` times."""
    return f"""PROGRAM square_laps;
ROBOT r := koch11;
IMPORT DATALIST square_cell;
VAR
  INTEGER: lap;
BEGIN
  R_SPEED := 1000;
  R_ACC := 2000;
  R_SPEED_ORI := 50;
  MOVE PTP konf_0;
  FOR lap := 1 TO {laps} DO
    MOVE LIN poz_1;
    MOVE LIN poz_2;
    MOVE LIN poz_3;
    MOVE LIN poz_4;
    MOVE LIN poz_0;
  ENDFOR;
ENDPROGRAM
"""


def irlc_command() -> list[str]:
    """``irlc`` of this interpreter's environment."""
    return [
        sys.executable,
        "-c",
        "import sys; from irlc.cli import entry; sys.argv[0] = 'irlc'; entry()",
    ]


def run_one(scale: int, folder: Path, engine: str) -> dict:
    """Run the program at ``scale``; wall s, peak RSS MiB, samples, robot time."""
    program = folder / f"square_x{scale}.irl"
    program.write_text(program_text(LAPS_PER_SCALE * scale), encoding="utf-8")
    report, trace = folder / f"x{scale}.json", folder / f"x{scale}.csv"
    # 100× is ≈ 360,000 IPO cycles, more than the default cycle budget (--max-cycles)
    cmd = [*irlc_command(), "run", str(program), "--datalist-path", str(PROGRAMS), "--quiet",
           "--report", str(report), "--trace", str(trace),
           "--max-cycles", str(10**9)]  # fmt: skip
    env = dict(os.environ, IRLC_ENGINE=engine, OPENBLAS_NUM_THREADS="1")
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, env=env, stderr=subprocess.PIPE, text=True)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    proc.returncode = os.waitstatus_to_exitcode(status)
    err = proc.stderr.read() if proc.stderr else ""
    if proc.returncode != 0:
        raise SystemExit(f"scale {scale}: irlc exited {proc.returncode}: {err}")
    rep = json.loads(report.read_text(encoding="utf-8"))
    robot_s = float(rep["duration_s"])
    cycles = int(rep["samples"]) - 1
    trace_mib = trace.stat().st_size / 2**20
    trace.unlink()
    return {
        "scale": scale,
        "laps": LAPS_PER_SCALE * scale,
        "robot_time_s": robot_s,
        "ipo_cycles": cycles,
        "wall_s": round(wall, 3),
        "cpu_s": round(usage.ru_utime + usage.ru_stime, 3),  # the child's user + system
        "x_real_time": round(robot_s / wall, 2),
        "us_per_cycle": round(1e6 * wall / max(cycles, 1), 1),
        "peak_rss_mib": round(usage.ru_maxrss / 1024, 1),  # Linux: KiB
        "trace_mib": round(trace_mib, 1),
    }


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scales", type=int, nargs="+", default=[1, 10, 100])
    ap.add_argument("--engine", default="numpy", choices=("numpy", "compiled", "auto"))
    ap.add_argument("--json", type=Path, default=None, help="write the results as JSON")
    args = ap.parse_args(argv)
    out = Recorder("length", args.engine, scales=args.scales, laps_per_scale=LAPS_PER_SCALE)
    print(f"python {platform.python_version()}, {platform.machine()}, IRLC_ENGINE={args.engine}")
    print("| length | laps | robot s | IPO cycles | wall s | CPU s | × real time "
          "| µs / cycle | marginal µs / cycle (CPU) | peak RSS MiB | marginal B / cycle "
          "| trace MiB |")  # fmt: skip
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory(prefix="irlc-bench-length-") as tmp:
        for scale in args.scales:
            r = run_one(scale, Path(tmp), args.engine)
            _marginal(r, out.rows[-1] if out.rows else None)
            out.add(**r)
            print(f"| {scale}× | {r['laps']} | {r['robot_time_s']:.1f} | {r['ipo_cycles']} | "
                  f"{r['wall_s']:.1f} | {r['cpu_s']:.1f} | {r['x_real_time']:.1f} | "
                  f"{r['us_per_cycle']:.0f} | {_cell(r['marginal_us_per_cycle'])} "
                  f"({_cell(r['marginal_cpu_us_per_cycle'])}) | {r['peak_rss_mib']:.0f} | "
                  f"{_cell(r['marginal_bytes_per_cycle'])} | {r['trace_mib']:.1f} |",
                  flush=True)  # fmt: skip
    out.write(args.json)
    return out.document()


def _marginal(row: dict, previous: dict | None) -> None:
    """Wall time and peak memory per extra IPO cycle against the previous (shorter) run:
    constant when time is linear in the length; the memory one a run keeps per cycle."""
    row["marginal_us_per_cycle"] = row["marginal_bytes_per_cycle"] = None
    row["marginal_cpu_us_per_cycle"] = None
    if previous is None or row["ipo_cycles"] <= previous["ipo_cycles"]:
        return
    extra = row["ipo_cycles"] - previous["ipo_cycles"]
    row["marginal_us_per_cycle"] = round(1e6 * (row["wall_s"] - previous["wall_s"]) / extra, 1)
    row["marginal_cpu_us_per_cycle"] = round(1e6 * (row["cpu_s"] - previous["cpu_s"]) / extra, 1)
    mib = row["peak_rss_mib"] - previous["peak_rss_mib"]
    row["marginal_bytes_per_cycle"] = round(mib * 2**20 / extra)


def _cell(value) -> str:
    return "–" if value is None else f"{value:.0f}"


if __name__ == "__main__":
    main()
