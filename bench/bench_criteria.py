"""IPO-cycle time of R_CRITERION := 'DISTANCE' | 'ENERGY' | 'MVR' on koch11, and what the
trace's kinetic_energy_j and mvr columns cost per sample.

    python bench/bench_criteria.py [--cycles 400] [--repeat 3]

The line of bench/bench_ik.py (−2 m along x from koch11's home pose, smooth profile,
Δt = 10 ms, 400 cycles) with each criterion alone, within the joint limits of set 6.1,
with CYCLIC and with one avoided point obstacle; numpy and compiled paths, passes
alternating, the first pass a warm-up (bench_ik.run). Then
``MotionMeasures.table`` (the links' velocities of every sample: kinetic energy and
velocity ratio) on 10,000 samples of koch11, the M(θ) refresh alone on both paths, and
what the two trace columns add to whole runs (programs/*.irl in-process with the report
and the trace, best of 5, with the measures and with them replaced by zeros, alternating).
Prints Markdown tables (docs/benchmarks.md, "Criteria").
"""

from __future__ import annotations

import os
import platform
import time

import bench_ik
import numpy as np
from irlc.runtime import accel_support, warmup
from irlc.runtime.ik import CycleOptions
from irlc.runtime.ik.energy import InertiaMetric
from irlc.runtime.model.kinematics import Kinematics


def criteria_options(model, kin, q0) -> dict[str, CycleOptions]:
    base = bench_ik.options(model, kin, q0)
    picked = ("default", "joint limits (set 6.1)", "cyclic", "obstacle (1 point)")
    out = {}
    for name in picked:
        for word in ("DISTANCE", "ENERGY", "MVR"):
            opts = base[name]
            out[(name, word)] = CycleOptions(
                position=opts.position,
                reference=opts.reference,
                obstacles=opts.obstacles,
                active_obstacles=opts.active_obstacles,
                criterion=word,
            )
    return out


def measures_cost(model, samples: int = 10_000) -> float:
    """µs per sample of the trace's two columns (``MotionMeasures.table``)."""
    from irlc.runtime.outputs.measures import MotionMeasures
    from irlc.runtime.outputs.samples import Motion

    rng = np.random.default_rng(0)
    kin = Kinematics(model)
    q = model.home_q() + rng.normal(size=(samples, model.n)) * 0.1
    qd = rng.normal(size=(samples, model.n)) * 0.2
    tcp = np.repeat(kin.tcp(model.home_q())[None], samples, axis=0)
    zeros = np.zeros(samples)
    motion = Motion(np.arange(samples) * 0.01, zeros.astype(int), q, qd, qd, tcp, zeros,
                    zeros, zeros.astype(bool), {})  # fmt: skip
    best = np.inf
    for _ in range(3):
        measures = MotionMeasures(model)  # (a new one: it keeps the last motion's values)
        t0 = time.perf_counter()
        measures.table(motion)
        best = min(best, time.perf_counter() - t0)
    return best / samples * 1e6


def metric_cost(model, compiled: bool, repeat: int = 2000) -> float:
    """µs per M(θ) refresh (ENERGY's metric at θ_s): numpy or the compiled kernel."""
    q = model.home_q()
    if not compiled:
        metric = InertiaMetric(model, model.weights)
        call = lambda: metric(q)  # noqa: E731
    else:  # the kernel on the packed chain and inertials, as the compiled driver calls it
        from irlc.runtime.ik.compiled.inertia import inertia_metric

        n, c = model.n, Kinematics(model).chain_data
        d = InertiaMetric(model, model.weights).dynamics.data
        dyn = (d.axes, d.revolute, d.rotor, d.mass, d.com, d.inertia, d.gravity)
        buf = (np.empty((n + 1, 4, 4)), np.empty((4, 4)), np.zeros(n), np.empty(n))
        out, total = np.empty((n, n)), float(model.weights.sum())
        chain = (c.basis, c.joints, c.ends[0])
        call = lambda: inertia_metric(chain, dyn, q, total, 1.0, buf, out)  # noqa: E731
    call()
    t0 = time.perf_counter()
    for _ in range(repeat):
        call()
    return (time.perf_counter() - t0) / repeat * 1e6


def run_overhead(names=("square", "square_cyclic", "combined"), repeat: int = 5):
    """``{program: (samples, s with the measures, s without)}``: best of ``repeat``."""
    from pathlib import Path

    from irlc import run_program
    from irlc.runtime.outputs import measures

    programs = Path(__file__).resolve().parents[1] / "programs"
    real = measures.MotionMeasures._of

    def zeros(self, motion):
        k = len(motion.times)
        return np.zeros(k), np.zeros(k)

    out = {}
    for name in names:
        best = {True: np.inf, False: np.inf}
        for _ in range(repeat):
            for on in (True, False):
                measures.MotionMeasures._of = real if on else zeros
                t0 = time.perf_counter()
                run = run_program(programs / f"{name}.irl")
                run.trace  # noqa: B018 (built on first use)
                best[on] = min(best[on], time.perf_counter() - t0)
        measures.MotionMeasures._of = real
        out[name] = (run.report["samples"], best[True], best[False])
    return out


def main() -> None:
    args, model, kin, q0, targets, variants = bench_ik.koch11_line(__doc__.splitlines()[0])
    if accel_support.AVAILABLE:
        warmup.warm_ik(), warmup.warm_ik_obstacles(), warmup.warm_ik_energy()
    print(f"python {platform.python_version()}, numpy {np.__version__}, {platform.machine()}")
    print(f"koch11 (n = 11, m = 6), {args.cycles} cycles × {args.repeat} passes")
    print(f"load average {' '.join(f'{x:.2f}' for x in os.getloadavg())}\n")
    print("| option | R_CRITERION | path | median µs | p99 µs | CPU median µs | iterations/cycle |")
    print("|---|---|---|---:|---:|---:|---:|")
    for (name, word), opts in criteria_options(model, kin, q0).items():
        stats = bench_ik.run(model, kin, q0, targets, opts, variants, args.repeat)
        for (_, jit), (med, p99, cmed, _, it, _) in stats.items():
            path = "compiled" if jit else "numpy"
            print(f"| {name} | {word} | {path} | {med:.0f} | {p99:.0f} | {cmed:.0f} | {it:.2f} |")
    print("\n| what | µs |")
    print("|---|---:|")
    print(f"| M(θ) refresh, numpy (Jacobian form) | {metric_cost(model, False):.1f} |")
    if accel_support.AVAILABLE:
        print(f"| M(θ) refresh, compiled kernel | {metric_cost(model, True):.1f} |")
    print(f"| trace columns kinetic_energy_j + mvr, per sample | {measures_cost(model):.2f} |")
    print("\n| program | samples | run + report + trace, s | without the two columns, s | share |")
    print("|---|---:|---:|---:|---:|")
    for name, (samples, on, off) in run_overhead().items():
        print(f"| {name}.irl | {samples} | {on:.3f} | {off:.3f} | {100 * (on - off) / on:.1f} % |")


if __name__ == "__main__":
    main()
