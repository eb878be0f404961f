"""The first run after installing (issue 14): wall and CPU time of
``irlc programs/square.irl`` as a fresh process, per engine and cache state.

Rows: ``numpy`` (the default), ``compiled`` with an empty numba cache (a fresh
``NUMBA_CACHE_DIR``: it compiles, and must say so), ``compiled`` again with the filled
cache (it loads), and ``auto``. Each row records whether the process printed the compile
message and whether its trace has the same bytes as the first run of the same engine.
Usage::

    python bench/bench_first_run.py [--program programs/square.irl] [--json out.json]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from bench_json import Recorder  # (bench/: the script's folder is on sys.path)

ROOT = Path(__file__).resolve().parents[1]
CLI = "import sys; from irlc.cli import main; sys.exit(main(sys.argv[1:]))"
CASES = [  # (label, IRLC_ENGINE, cache)
    ("numpy (default: IRLC_ENGINE unset)", "", "fresh"),
    ("compiled, empty cache", "compiled", "fresh"),
    ("compiled, filled cache", "compiled", "kept"),
    ("auto, filled cache", "auto", "kept"),
]


def run_case(program: Path, engine: str, cache: Path, trace: Path) -> dict:
    env = dict(os.environ, IRLC_ENGINE=engine, NUMBA_CACHE_DIR=str(cache))
    env["OPENBLAS_NUM_THREADS"] = "1"
    cmd = [sys.executable, "-c", CLI, str(program), "--quiet", "--trace", str(trace)]
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, env=env, stderr=subprocess.PIPE, text=True, cwd=ROOT)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    err = proc.stderr.read() if proc.stderr else ""
    code = os.waitstatus_to_exitcode(status)
    if code != 0:
        raise SystemExit(f"{engine}: irlc exited {code}: {err}")
    return {
        "wall_s": round(wall, 2),
        "cpu_s": round(usage.ru_utime + usage.ru_stime, 2),
        "peak_rss_mib": round(usage.ru_maxrss / 1024, 1),
        "said_compiling": "irlc: compiling" in err,
    }


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--program", type=Path, default=ROOT / "programs" / "square.irl")
    ap.add_argument("--json", default=None, help="write the rows as JSON to this file")
    args = ap.parse_args()
    out = Recorder("first_run", "numpy,compiled,auto", program=str(args.program.name))
    print("| case | wall s | CPU s | peak RSS MiB | said 'compiling' | same bytes as first |")
    print("|---|---:|---:|---:|---|---|")
    first: dict[str, bytes] = {}
    with tempfile.TemporaryDirectory(prefix="irlc-first-run-") as tmp:
        cache = Path(tmp) / "numba-cache"
        for label, engine, state in CASES:
            trace = Path(tmp) / "trace.csv"
            row = run_case(args.program, engine, cache, trace)
            data = trace.read_bytes()
            kind = "numpy" if engine in ("", "numpy") else "compiled"
            row["same_bytes_as_first"] = first.setdefault(kind, data) == data
            out.add(case=label, engine=engine, cache=state, **row)
            print(f"| {label} | {row['wall_s']:.2f} | {row['cpu_s']:.2f} | "
                  f"{row['peak_rss_mib']:.0f} | {row['said_compiling']} | "
                  f"{row['same_bytes_as_first']} |", flush=True)  # fmt: skip
    out.write(args.json)


if __name__ == "__main__":
    main()
