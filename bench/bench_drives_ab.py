"""Drive simulation before / after: an older revision against the current tree, interleaved.

The setpoints (``bench_drives.setpoints``: the irb6_track line and the koch11 square) are
computed once by the current tree and pickled; every round then runs one worker process
per tree, alternating, each timing every case once after an untimed warm-up run (pwm:
on the first three samples only, the full run is long). A compiled case ("numba") that
the "before" tree does not cover runs its numpy loop there. "before" is ``git archive
REV`` unpacked into a temporary directory and laid out as the ``irlc`` package
(``pyproject.toml``'s ``package-dir``), first on ``PYTHONPATH``; "after" is the installed
tree. A change of the machine's load hits both alike. Usage::

    OPENBLAS_NUM_THREADS=1 python bench/bench_drives_ab.py --before REV [--repeat 7]

Prints × real time (simulated s / wall s) median / best per case and tree, and the
median against CPU time of the worker (``time.process_time``), which a busy machine
distorts less.
"""

from __future__ import annotations

import argparse
import json
import os
import pickle
import shutil
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
import tomllib
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CASES = [  # (setpoints, level, step s | None = rule, compiled loop[, dynamics_every])
    ("irb6_track line", "coupled", 1e-3, False),
    ("irb6_track line", "coupled", 1e-3, True),
    ("irb6_track line", "decoupled", 1e-3, False),
    ("irb6_track line", "pwm", None, False),
    ("irb6_track line", "pwm", None, True),
    ("koch11 square", "coupled", 1e-3, False),
    ("koch11 square", "coupled", 1e-3, True),
    ("irb6_track line", "coupled", 1e-3, True, 1),  # M(q), C q̇ + G refreshed every step
    ("koch11 square", "coupled", 1e-3, True, 1),
]


def worker(data_path: str) -> None:
    """Time each case once in this process; print ``{case: [wall, cpu, simulated]}``."""
    from irlc.runtime.drives import simulate_drives

    with open(data_path, "rb") as fh:
        data = pickle.load(fh)
    warnings.simplefilter("ignore")
    out = {}
    for case, level, step, fast, *every in CASES:
        model, times, q = data[case]
        every = every[0] if every else None

        def go(model=model, times=times, q=q, level=level, step=step, fast=fast, every=every):
            return simulate_drives(
                model, times, q, level=level, step=step, hold=0.0, accel=fast,
                dynamics_every=every,
            )  # fmt: skip

        if level != "pwm":
            go()
        else:  # the first samples only (the full run is long): imports, kernels loaded
            go(times=times[:3], q=q[:3])
        w0, c0 = time.perf_counter(), time.process_time()
        run = go()
        wall, cpu = time.perf_counter() - w0, time.process_time() - c0
        out[_label(case, level, step, fast, every)] = [wall, cpu, float(run.t[-1] - run.t[0])]
    print(json.dumps(out))


def _label(case, level, step, fast, every=None) -> str:
    when = "rule" if step is None else f"{step * 1e3:g} ms"
    refresh = "" if every is None else f", M refreshed every {every} step(s)"
    return f"{case}, {level} {when}, {'numba' if fast else 'numpy'}{refresh}"


def overlay(rev: str, into: Path) -> Path:
    """``git archive rev`` laid out as the ``irlc`` package under ``into``; returns the
    directory to put on ``PYTHONPATH``."""
    tree = into / "tree"
    tree.mkdir()
    blob = subprocess.run(
        ["git", "-C", str(ROOT), "archive", rev], check=True, capture_output=True
    ).stdout
    tar_path = into / "rev.tar"
    tar_path.write_bytes(blob)
    with tarfile.open(tar_path) as tar:
        if hasattr(tarfile, "data_filter"):  # Python ≥ 3.11.4
            tar.extractall(tree, filter="data")
        else:
            tar.extractall(tree)
    mapping = tomllib.loads((tree / "pyproject.toml").read_text(encoding="utf-8"))
    dirs = mapping["tool"]["setuptools"]["package-dir"]
    site = into / "site"
    site.mkdir()
    top = site / "irlc"
    shutil.copytree(tree / dirs["irlc"], top)
    for key, rel in dirs.items():  # sub-packages mapped outside the top one
        if key.startswith("irlc.") and "." not in key[5:]:
            os.symlink(tree / rel, top / key[5:])
    return site


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--before", help="git revision of the 'before' tree")
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        worker(args.worker)
        return
    if not args.before:
        ap.error("--before REV is required")
    sys.path.insert(0, str(ROOT / "bench"))
    from bench_drives import setpoints

    with tempfile.TemporaryDirectory() as tmp:
        tmp_path = Path(tmp)
        data_path = tmp_path / "setpoints.pkl"
        data = {case: setpoints(case) for case in ("irb6_track line", "koch11 square")}
        data_path.write_bytes(pickle.dumps(data))
        site = overlay(args.before, tmp_path)
        envs = {
            "before": dict(os.environ, PYTHONPATH=str(site), OPENBLAS_NUM_THREADS="1"),
            "after": dict(os.environ, OPENBLAS_NUM_THREADS="1"),
        }
        load0 = os.getloadavg()
        results = {name: [] for name in envs}
        for _ in range(args.repeat):
            for name, env in envs.items():
                done = subprocess.run(
                    [sys.executable, __file__, "--worker", str(data_path)],
                    env=env,
                    cwd=tmp,
                    check=True,
                    capture_output=True,
                    text=True,
                )
                results[name].append(json.loads(done.stdout.strip().splitlines()[-1]))
        load1 = os.getloadavg()
    print(f"before = {args.before}, after = the working tree; {args.repeat} interleaved rounds")
    print(f"load average (1, 5, 15 min) before {load0}, after {load1}")
    print("| case | before: × real time, wall median / best (CPU) | after: same |")
    print("|---|---|---|")
    for key in results["after"][0]:
        cells = [key]
        for name in ("before", "after"):
            walls = [r[key][0] for r in results[name]]
            cpus = [r[key][1] for r in results[name]]
            sim = results[name][0][key][2]
            cells.append(
                f"{sim / statistics.median(walls):.1f} / {sim / min(walls):.1f} "
                f"({sim / statistics.median(cpus):.1f})"
            )
        print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
