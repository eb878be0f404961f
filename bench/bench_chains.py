"""IPO-cycle time of the inverse transformation per kind of chain (docs/architecture.md,
"Chains and tasks"): one robot, two cooperating robots as one chain, extra task rows.

    python bench/bench_chains.py [--cycles 300] [--repeat 3]

Each chain follows a short line (rest to rest, Δt = 10 ms) from its home: the TCP's, in
the chain's base frame (for the cooperating pair: the welder's tool in the holder's tool
frame, on the workpiece); a platform task's platform follows its own line in step. The
per-cycle thread CPU time of ``InverseTransformation.step`` is collected over ``repeat``
passes after a warm-up pass; the median and 99th percentile are printed as a Markdown
table (docs/benchmarks.md), with the path (numpy or compiled) each chain runs on.
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import time

import numpy as np
from irlc.robots import load_robot
from irlc.runtime.control.platform import platform_chain
from irlc.runtime.ik import CycleOptions, IKParams, InverseTransformation
from irlc.runtime.ik.tasks import AxisTask, PlatformTask
from irlc.runtime.model import spatial
from irlc.runtime.model.chain import SerialChain
from irlc.runtime.model.cooperating import CellRobot, CooperatingChain


def _pair() -> CooperatingChain:
    """Two as6, the welder 1.4 m away facing the holder (the monograph's fig. 3.4)."""
    face = spatial.transform(spatial.rot_z(math.pi), (1.4, 0.0, 0.0))
    holder = CellRobot("holder", load_robot("as6"))
    return CooperatingChain(holder, CellRobot("welder", load_robot("as6"), face))


def _chains() -> list[tuple[str, object, np.ndarray]]:
    """(name, chain, start θ)."""
    out = []
    for robot in ("koch11", "panda", "mobile8"):
        model = load_robot(robot)
        out.append((f"{robot} (one robot)", SerialChain(model), model.home_q()))
    pair = _pair()
    start = pair.join(pair.holder.model.home_q(), pair.worker.model.home_q())
    out.append(("as6 + as6 cooperating (12 joints)", pair, start))
    vertical = pair.with_tasks((AxisTask.vertical(pair),))
    out.append(("as6 + as6 cooperating, welder's tool vertical (6 + 2 rows)", vertical,
                _settled(vertical, start)))  # fmt: skip
    mobile = load_robot("mobile8")
    platform_task = PlatformTask(link=2)
    chain = SerialChain(mobile, tasks=(platform_task,))
    out.append(("mobile8 + platform task (6 + 2 rows)", chain, mobile.home_q()))
    track = load_robot("as6_track")  # the file's platform, as the controller builds it
    chain, _ = platform_chain(SerialChain(track), track.platform)
    ready = np.radians([0.0, 126.0, -66.0, 66.0, -39.0, 211.0, 17.0])  # track_cell's
    out.append(("as6_track (one robot)", SerialChain(track), ready))
    out.append(("as6_track + platform task (6 + 1 rows)", chain, ready))
    return out


def _settled(chain, start: np.ndarray) -> np.ndarray:
    """A start that meets the extra rows: one cycle with room for iterations and joint
    rates (the home pose's tool is not vertical)."""
    wide = np.tile([-1e6, 1e6], (chain.n, 1))
    ik = InverseTransformation(chain, params=IKParams(max_iter=50))
    return ik.step(start, start, chain.tcp(start), 0.01, CycleOptions(speed=wide, accel=wide)).q


def _run(chain, start, cycles: int, repeat: int) -> tuple[float, float, bool]:
    ik = InverseTransformation(chain, params=IKParams())
    tcp0 = chain.tcp(start)
    platform0 = None
    for task in chain.tasks:
        if isinstance(task, PlatformTask):
            platform0 = task.position(chain.point(start))[task.coords].copy()
    times = []
    for rep in range(repeat + 1):
        q_prev = q = start.copy()
        for k in range(1, cycles + 1):
            s = 0.5 - 0.5 * math.cos(math.pi * k / cycles)
            target = tcp0.copy()
            target[:3, 3] += tcp0[:3, :3] @ np.array([0.03 * s, 0.02 * s, 0.0])
            for task in chain.tasks:
                if isinstance(task, PlatformTask):
                    task.target = platform0 + s * np.array([0.02, 0.01])[: task.size]
            c0 = time.thread_time_ns()
            r = ik.step(q, q_prev, target, 0.01)
            if rep:
                times.append(time.thread_time_ns() - c0)
            if not r.converged:
                raise RuntimeError(f"cycle {k} did not converge: {r}")
            q_prev, q = q, r.q
    t = np.array(times) * 1e-3
    return float(np.median(t)), float(np.percentile(t, 99)), ik.accelerated


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cycles", type=int, default=300)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    print(f"python {platform.python_version()}, numpy {np.__version__}, {platform.machine()}")
    print(f"{args.cycles} cycles × {args.repeat} passes, IRLC_ENGINE="
          f"{os.environ.get('IRLC_ENGINE', 'numpy')}")  # fmt: skip
    print(f"load average {' '.join(f'{x:.2f}' for x in os.getloadavg())}\n")
    print("| chain | n | rows | path | CPU median µs | CPU p99 µs |")
    print("|---|---:|---:|---|---:|---:|")
    for name, chain, start in _chains():
        med, p99, compiled = _run(chain, start, args.cycles, args.repeat)
        path = "compiled" if compiled else "numpy"
        print(f"| {name} | {chain.n} | {chain.rows} | {path} | {med:.0f} | {p99:.0f} |")


if __name__ == "__main__":
    main()
