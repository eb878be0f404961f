"""Study throughput: variants per second with 1, 2, … local workers and a local Dask cluster.

The study: a planar3 program moving 1 s (simulated) along a line past a sphere; a grid over
joint 2's weight (a robot-file value: each variant loads its robot once per worker) and a
data-list value (the sphere's radius: each variant compiles its own data once per worker).
Per worker count the whole study is run (``run_study``, results.csv written): ``wall`` from
the call to its return (pool start-up, compile and checks included) and the **steady**
rate from the first finished variant to the last (start-up excluded). The **overhead per
variant** is ``workers / steady rate`` minus the time of the same run called in-process
(``run_code`` on the compiled code, best of ``--repeat``), relative to the latter: what a
variant costs beyond its run (pickling, queueing, the row, results.csv's fsync).
Usage::

    python bench/bench_study.py [--variants 40] [--workers 1 2] [--dask] [--repeat 3] [--koch11]
"""

from __future__ import annotations

import argparse
import platform
import tempfile
import time
from pathlib import Path

PROGRAM = """PROGRAM bench;
ROBOT r := planar3;
IMPORT DATALIST cellb;

BEGIN
  R_SPEED := 500;
  R_ACC := 2000;
  MOVE PTP home;
  MOVE LIN q1;
ENDPROGRAM
"""
CELL = """[poses]
q1 = [1600, 1000, 0, 0, 0, 0]

[joints]
home = [0, 90, -90]

[obstacles.post]
kind = "sphere"
center = [1700, 1300, 0]
radius = 100
"""


# --koch11: the first side of the chapter-6 square on the 11-joint robot (2 m, ≈ 2.5 s
# simulated: a short run), a grid over joint 10's weight (one robot build per variant).
KOCH11 = """PROGRAM bench;
ROBOT r := koch11;
IMPORT DATALIST square_cell;

BEGIN
  R_SPEED := 1000;
  R_ACC := 2000;
  MOVE PTP konf_0;
  MOVE LIN poz_1;
ENDPROGRAM
"""


def _study(folder: Path, variants: int, koch11: bool) -> Path:
    path = folder / "bench.toml"
    if koch11:
        (folder / "bench.irl").write_text(KOCH11)
        cell = Path(__file__).resolve().parents[1] / "programs" / "square_cell.toml"
        (folder / "square_cell.toml").write_text(cell.read_text())
        weights = ", ".join(repr(5.0 + 0.5 * k) for k in range(variants))
        path.write_text(
            f'program = "bench.irl"\n\n[grid]\n"robot.joints.10.weight" = [{weights}]\n'
        )
        return path
    (folder / "bench.irl").write_text(PROGRAM)
    (folder / "cellb.toml").write_text(CELL)
    weights = ", ".join(repr(1.0 + 0.25 * k) for k in range(max(1, variants // 2)))
    path.write_text(
        'program = "bench.irl"\n\n[grid]\n'
        f'"robot.joints.2.weight" = [{weights}]\n'
        '"datalist.cellb.obstacles.post.radius" = [80, 120]\n'
    )
    return path


def _single(path: Path, repeat: int, robot: str) -> float:
    """Best in-process wall time of one variant's run (compiled once, robot loaded once)."""
    from irlc.api import compile_program
    from irlc.runtime.run import load_model, run_code

    code = compile_program(path.parent / "bench.irl")
    model = load_model(robot, path.parent)
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        run_code(code, robot=model)
        best = min(best, time.perf_counter() - t0)
    return best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--variants", type=int, default=40)
    ap.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--dask", action="store_true", help="also a LocalCluster of each size")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--koch11", action="store_true", help="a 2.5 s koch11 line per variant")
    args = ap.parse_args()
    from irlc.study import default_workers, run_study

    print(f"Python {platform.python_version()}, {platform.machine()}, "
          f"{default_workers()} usable cores")  # fmt: skip
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        path = _study(folder, args.variants, args.koch11)
        single = _single(path, args.repeat, "koch11" if args.koch11 else "planar3")
        print(f"one run in-process: {single * 1e3:.0f} ms")
        print(f"{'executor':<22}{'variants':>9}{'wall s':>8}{'/s wall':>9}{'/s steady':>10}"
              f"{'overhead':>10}{'speed-up':>10}")  # fmt: skip
        base = None
        for w in args.workers:
            rows = [("local", w, False)]
            if args.dask:
                rows.append(("dask LocalCluster", w, True))
            for label, workers, dask in rows:
                out = folder / f"out_{label.split()[0]}_{workers}"
                stamps: list[float] = []
                tick = lambda done, todo, s=stamps: s.append(time.perf_counter())  # noqa: E731
                t0 = time.perf_counter()
                if dask:
                    from distributed import Client, LocalCluster

                    with LocalCluster(
                        n_workers=workers, threads_per_worker=1, processes=True,
                        dashboard_address=None,
                    ) as cluster, Client(cluster) as client:  # fmt: skip
                        outcome = run_study(path, out=out, cluster=client, progress=tick)
                else:
                    outcome = run_study(path, out=out, workers=workers, progress=tick)
                wall = time.perf_counter() - t0
                steady = (len(stamps) - 1) / (stamps[-1] - stamps[0])
                base = base or steady
                overhead = workers / steady / single - 1.0
                print(f"{label + f' x{workers}':<22}{outcome.ran:>9}{wall:>8.2f}"
                      f"{outcome.ran / wall:>9.2f}{steady:>10.2f}{overhead:>10.0%}"
                      f"{steady / base:>9.2f}x")  # fmt: skip


if __name__ == "__main__":
    main()
