"""FK + 6×n Jacobian of koch11: the precomputed batched kinematics vs a plain baseline.

Run: ``python bench/bench_kinematics.py [ROBOT] [--runs N]``. Prints the median time per
call (µs) of ``Kinematics.tcp_and_jacobian`` and of the straightforward implementation
(per-joint Rodrigues 4×4, product, column loop with ``np.cross``), and the largest
difference between the two results.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
from irlc.robots import load_robot
from irlc.robots.model import RobotModel
from irlc.runtime.model import spatial
from irlc.runtime.model.kinematics import Kinematics


def baseline_tcp_and_jacobian(model: RobotModel, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The plain version: one 4×4 per joint from Rodrigues, products, a column loop."""
    n = model.n
    t = model.base.copy()
    frames = [t]
    for i, j in enumerate(model.joints):
        t = t @ j.origin
        v = q[i] + j.offset
        if j.kind == "revolute":
            m = spatial.transform(spatial.axis_angle(j.axis, v))
        else:
            m = spatial.transform(None, np.asarray(j.axis) * v)
        t = t @ m
        frames.append(t)
    tcp = frames[-1] @ model.flange @ model.tool
    p = tcp[:3, 3]
    jac = np.zeros((6, n))
    for i, j in enumerate(model.joints):
        z = frames[i + 1][:3, :3] @ j.axis
        if j.kind == "revolute":
            jac[:3, i] = np.cross(z, p - frames[i + 1][:3, 3])
            jac[3:, i] = z
        else:
            jac[:3, i] = z
    return tcp, jac


def median_us(fns: dict, qs: list[np.ndarray], repeat: int = 9) -> dict[str, float]:
    """Median µs per call of each function; rounds interleaved so load changes hit all."""
    times: dict[str, list[float]] = {k: [] for k in fns}
    for _ in range(repeat):
        for name, fn in fns.items():
            t0 = time.perf_counter()
            for q in qs:
                fn(q)
            times[name].append((time.perf_counter() - t0) / len(qs) * 1e6)
    return {k: statistics.median(v) for k, v in times.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("robot", nargs="?", default="koch11")
    ap.add_argument("--runs", type=int, default=5000, help="calls per timing round")
    args = ap.parse_args()
    model = load_robot(args.robot)
    kin = Kinematics(model)
    rng = np.random.default_rng(0)
    lim = model.position_limits
    qs = [rng.uniform(lim[:, 0], lim[:, 1]) for _ in range(args.runs)]
    err = 0.0
    for q in qs[:200]:
        t1, j1 = kin.tcp_and_jacobian(q)
        t0, j0 = baseline_tcp_and_jacobian(model, q)
        err = max(err, float(np.abs(t1 - t0).max()), float(np.abs(j1 - j0).max()))
    t = median_us(
        {
            "fast": kin.tcp_and_jacobian,
            "fk": kin.tcp,
            "base": lambda q: baseline_tcp_and_jacobian(model, q),
        },
        qs,
    )
    fast, fk_only, base = t["fast"], t["fk"], t["base"]
    print(f"robot {model.name} (n = {model.n}), {args.runs} random configurations, median of 9")
    print(f"{'':28s}{'irlc':>10s}{'baseline':>12s}")
    print(f"{'FK + Jacobian [µs/call]':28s}{fast:10.1f}{base:12.1f}   speed-up {base / fast:.1f}×")
    print(f"{'FK only [µs/call]':28s}{fk_only:10.1f}")
    print(f"max |difference| irlc vs baseline: {err:.2e}")


if __name__ == "__main__":
    main()
