"""Where the compiled engine pays (issue 24 §6): fresh ``irlc`` processes per engine.

The compiled kernels cost a fixed price per process — importing numba and loading the
cached machine code (compiling it, once per installation, is ``irlc warmup``'s ≈ 40 s) —
and save per IK cycle and per drive step. This bench runs the same commands with
``IRLC_ENGINE=numpy`` and ``IRLC_ENGINE=compiled`` (warm numba cache) and with the
engine left unset (the policy of :mod:`irlc.runtime.engine_policy`), as fresh processes,
and prints CPU seconds (the process and its children, ``RUSAGE_CHILDREN``: on a shared
machine wall time is noise) and wall seconds. Rows:

* kinematic runs of 1, 3 and 10 laps of the koch11 square (1,280 … 12,800 IPO cycles),
  ``combined.irl`` (obstacles: a costlier numpy cycle);
* the square with ``--drives decoupled`` (the drive loop);
* a study of N short koch11 variants run as one worker runs them (``run_variant`` one
  after the other in one process, the plan built as ``irlc study`` builds it: the fixed
  price is paid once per worker, the saving per variant).

Usage::

    python bench/bench_engine.py [--repeat 2] [--laps 3 10] [--variants 30 100 300] [--only TEXT]
                                 [--json out.json]
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from bench_json import Recorder  # (bench/: the script's folder is on sys.path)
from bench_length import program_text

ROOT = Path(__file__).resolve().parents[1]
PROGRAMS = ROOT / "programs"
CLI = "import sys; from irlc.cli import main; sys.exit(main(sys.argv[1:]))"
WORKER = (  # one worker's loop over a study's variants (frontdoor/study/worker.py)
    "import sys; from irlc.study import read_study; from irlc.study.plan import build_plan;"
    "from irlc.study.expand import variants; from irlc.study.worker import run_variant;"
    "s = read_study(sys.argv[1]); p = build_plan(s);"
    "rows = [run_variant(p, i, v) for i, v in variants(s)];"
    "sys.exit(any(r['status'] != 'ok' for r in rows))"
)
ENGINES = ("numpy", "compiled", "")  # "": unset, the policy decides
STUDY_PROGRAM = """PROGRAM line;
ROBOT r := koch11;
IMPORT DATALIST square_cell;
BEGIN
  R_SPEED := 1000;  R_ACC := 2000;
  MOVE PTP konf_0;
  MOVE LIN poz_1;
ENDPROGRAM
"""


def timed(args: list[str], engine: str, cwd: Path) -> tuple[float, float]:
    """(CPU s of the process and its children, wall s) of ``irlc ARGS``."""
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    env.pop("IRLC_ENGINE", None)
    if engine:
        env["IRLC_ENGINE"] = engine
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    script = WORKER if args[0] == "worker" else CLI
    argv = args[1:] if args[0] == "worker" else args
    proc = subprocess.run([sys.executable, "-c", script, *argv], env=env, cwd=cwd,
                          capture_output=True, text=True)  # fmt: skip
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        raise SystemExit(f"irlc {' '.join(args)} ({engine or 'unset'}): {proc.stderr}")
    if "compiling" in proc.stderr:
        raise SystemExit("the numba cache is cold: run `irlc warmup` first")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return cpu, wall


def cases(folder: Path, variants: list[int], laps_list: list[int]) -> list[tuple[str, list[str]]]:
    out = [("square.irl (1 lap, 1,280 cycles)", ["run", str(PROGRAMS / "square.irl"), "-q"])]
    for laps in sorted({3, *laps_list}):
        path = folder / f"laps{laps}.irl"
        path.write_text(program_text(laps))
        run = ["run", str(path), "-q", "--datalist-path", str(PROGRAMS), "--max-cycles", "10000000"]
        out.append((f"square, {laps} laps ({laps * 1280:,} cycles)", run))
    out.append(("combined.irl (obstacles, 1,453 cycles)", ["run", str(PROGRAMS / "combined.irl"),
                                                          "-q"]))  # fmt: skip
    out.append(("square.irl --drives decoupled", ["run", str(PROGRAMS / "square.irl"), "-q",
                                                  "--drives", "decoupled",
                                                  "--path-tolerance", "150",
                                                  "--orientation-tolerance", "6"]))  # fmt: skip
    drives = ["--path-tolerance", "150", "--orientation-tolerance", "6"]
    laps3 = ["run", str(folder / "laps3.irl"), "-q", "--datalist-path", str(PROGRAMS)]
    out.append(("square, 3 laps --drives decoupled", [*laps3, "--drives", "decoupled", *drives]))
    square = ["run", str(PROGRAMS / "square.irl"), "-q"]
    out.append(("square.irl --drives pwm", [*square, "--drives", "pwm", *drives]))
    (folder / "line.irl").write_text(STUDY_PROGRAM)
    for name in ("square_cell.toml",):
        (folder / name).write_text((PROGRAMS / name).read_text())
    for n in variants:
        study = folder / f"s{n}.toml"
        weights = ", ".join(f"{5.0 + 0.01 * i:.2f}" for i in range(n))
        study.write_text(f'program = "line.irl"\n[grid]\n"robot.joints.10.weight" = [{weights}]\n')
        out.append((f"study, {n} variants, one worker", ["worker", str(study)]))
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=2, help="rounds; the best CPU is kept")
    ap.add_argument("--variants", type=int, nargs="*", default=[30, 100, 300])
    ap.add_argument("--laps", type=int, nargs="*", default=[3, 10], help="square laps")
    ap.add_argument("--only", default="", help="run the cases whose label contains this")
    ap.add_argument("--json", default=None)
    args = ap.parse_args()
    out = Recorder("engine", "numpy,compiled,policy", repeat=args.repeat)
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        rows = [c for c in cases(folder, args.variants, args.laps) if args.only in c[0]]
        print(f"{'case':44s} {'numpy CPU/wall s':>18s} {'compiled':>14s} {'policy':>14s}")
        for label, argv in rows:
            best: dict[str, tuple[float, float]] = {}
            for _ in range(args.repeat):
                for engine in ENGINES:  # interleaved: load changes hit all alike
                    cpu, wall = timed(argv, engine, folder)
                    if engine not in best or cpu < best[engine][0]:
                        best[engine] = (cpu, wall)
            cells = [f"{best[e][0]:6.2f} / {best[e][1]:5.1f}" for e in ENGINES]
            print(f"{label:44s} {cells[0]:>18s} {cells[1]:>14s} {cells[2]:>14s}")
            figures = {}
            for e in ENGINES:
                figures[f"{e or 'policy'}_cpu_s"] = round(best[e][0], 3)
                figures[f"{e or 'policy'}_wall_s"] = round(best[e][1], 2)
            out.add(case=label, **figures)
    if args.json:
        out.write(args.json)


if __name__ == "__main__":
    main()
