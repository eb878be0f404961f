"""IPO-cycle time of the inverse transformation on koch11, per option.

    python bench/bench_ik.py [--cycles 400] [--repeat 3]

A straight line of the TCP (−2 m along x from the home pose, smooth profile, Δt = 10 ms,
400 cycles) is solved cycle by cycle with each option; the per-cycle wall time of
``InverseTransformation.step`` (and its thread CPU time, which a loaded machine's
preemptions do not inflate) is collected over ``repeat`` passes (the first pass is a
warm-up and not counted). quadprog (Goldfarb–Idnani) on the numpy path and on the
compiled path (numba, if installed) and daqp (numpy path), passes alternating. Prints a
Markdown table (paste into docs/benchmarks.md).
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import numpy as np
from irlc.robots import load_robot
from irlc.runtime import accel_support, warmup
from irlc.runtime.ik import CycleOptions, IKParams, InverseTransformation
from irlc.runtime.ik.qp import daqp_available
from irlc.runtime.model.distance import robot_parts
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.model.obstacles import PointObstacle


def line_targets(kin, q0, cycles):
    start = kin.tcp(q0)
    out = []
    for i in range(1, cycles + 1):
        s = i / cycles
        t = start.copy()
        t[0, 3] -= 2.0 * s * s * (3.0 - 2.0 * s)
        out.append(t)
    return out


def limits_array(sets, attr):
    return np.array([getattr(lim, attr) for lim in sets])


def options(model, kin, q0):
    sets = model.limit_sets
    base = limits_array(sets["base"], "position") if "base" in sets else None
    speed = limits_array(sets["speed"], "speed") if "speed" in sets else None
    accel = limits_array(sets["accel"], "accel") if "accel" in sets else None
    # a point obstacle 0.35 m beside the middle of link 4 (inside the activation distance)
    _, a, b, r = next(p for p in robot_parts(kin, kin.link_frames(q0)) if p[0] == 4)
    point = 0.5 * (a + b) + np.array([0.0, r + 0.35, 0.0])
    obstacle = PointObstacle("bench_point", point)
    return {
        "default": CycleOptions(),
        "joint limits (set 6.1)": CycleOptions(position=base),
        "speed + accel limits (6.2, 6.3)": CycleOptions(speed=speed, accel=accel),
        "cyclic": CycleOptions(reference=q0.copy()),
        "obstacle (1 point)": CycleOptions(
            obstacles=[obstacle], active_obstacles=frozenset({"bench_point"})
        ),
        "freeze J2, J3": CycleOptions(frozen={1: q0[1], 2: q0[2]}),
    }


def run(model, kin, q0, targets, opts, variants, repeat):
    """Per variant ``(solver, jit)``: the statistics; passes of the variants alternate."""
    acc = {v: ([], [], [], [0]) for v in variants}
    for rep in range(repeat + 1):
        for solver, jit in variants:
            times, cpu, iters, relaxed = acc[(solver, jit)]
            ik = InverseTransformation(model, kin, IKParams(solver=solver, accel=jit))
            q_prev, q = q0.copy(), q0.copy()
            for target in targets:
                c0 = time.thread_time_ns()
                t0 = time.perf_counter()
                r = ik.step(q, q_prev, target, 0.01, opts)
                dt = time.perf_counter() - t0
                dc = time.thread_time_ns() - c0
                q_prev, q = q, r.q
                if rep:
                    times.append(dt)
                    cpu.append(dc)
                    iters.append(r.iterations)
                    relaxed[0] += r.relaxed
    out = {}
    for v, (times, cpu, iters, relaxed) in acc.items():
        t = np.array(times) * 1e6
        c = np.array(cpu) * 1e-3
        out[v] = (
            np.median(t),
            np.percentile(t, 99),
            np.median(c),
            np.percentile(c, 99),
            np.mean(iters),
            relaxed[0] // repeat,
        )
    return out


def koch11_line(description: str):
    """``(args, model, kin, q0, targets, variants)``: the command line (``--cycles``,
    ``--repeat``), koch11's line of ``cycles`` targets from home, and quadprog on the numpy
    and (numba installed) the compiled path."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--cycles", type=int, default=400)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    model = load_robot("koch11")
    kin = Kinematics(model)
    q0 = model.home_q()
    targets = line_targets(kin, q0, args.cycles)
    variants = [("quadprog", False)] + ([("quadprog", True)] if accel_support.AVAILABLE else [])
    return args, model, kin, q0, targets, variants


def main() -> None:
    args, model, kin, q0, targets, variants = koch11_line(__doc__.splitlines()[0])
    seconds = warmup.warm_ik() + warmup.warm_ik_obstacles() if accel_support.AVAILABLE else None
    variants += [("daqp", False)] if daqp_available() else []
    print(f"python {platform.python_version()}, numpy {np.__version__}, {platform.machine()}")
    print(f"koch11 (n = 11, m = 6), {args.cycles} cycles × {args.repeat} passes")
    print(f"load average {' '.join(f'{x:.2f}' for x in os.getloadavg())}\n")
    print(
        "| option | path | median µs | p99 µs | CPU median µs | CPU p99 µs "
        "| iterations/cycle | relaxed cycles |"
    )
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    for name, opts in options(model, kin, q0).items():
        stats = run(model, kin, q0, targets, opts, variants, args.repeat)
        for (solver, jit), (med, p99, cmed, cp99, it, rel) in stats.items():
            path = f"{solver}, {'compiled' if jit else 'numpy'}"
            print(
                f"| {name} | {path} | {med:.0f} | {p99:.0f} | {cmed:.0f} | {cp99:.0f} "
                f"| {it:.2f} | {rel} |"
            )
    if seconds is not None:
        print(f"\ncompiled kernels loaded (or compiled) in {seconds:.2f} s")


if __name__ == "__main__":
    main()
