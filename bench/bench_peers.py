"""One differential-IK step on the 7-DOF Panda: irlc vs pink vs mink, same URDF, same targets.

Each solver gets the same sequence of configurations and, for each, a target pose of the
``panda_link7`` frame a few millimetres / milliradians away (what one IPO cycle asks
for), with joint position and velocity limits active. A *step* is what each library does
per control cycle: forward kinematics + Jacobian at the current configuration, build the
QP, solve it (quadprog for all three), and return the joint displacement.

* irlc: ``InverseTransformation.step`` with ``max_iter = 1`` (one Newton–Raphson
  iteration = one compact QP), and also a full cycle (iterated to 1e-9 m).
* pink: ``Configuration.update(q)`` + ``solve_ik(..., limits=[configuration, velocity])``.
* mink: ``Configuration.update(q)`` + ``solve_ik(..., limits=[configuration, velocity])``.

``panda_link7`` is used because MuJoCo fuses the fixed links (link8, hand) into link7.
Run: ``pip install -e '.[bench]' && python bench/bench_peers.py`` (needs pin-pink, mink).
"""

from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

import numpy as np
from irlc.robots import load_robot
from irlc.runtime import spatial
from irlc.runtime.ik import CycleOptions, IKParams, InverseTransformation
from irlc.runtime.kinematics import Kinematics

ROOT = Path(__file__).resolve().parents[1]
URDF = ROOT / "robots" / "urdf" / "panda.urdf"
FRAME = "panda_link7"
DT = 0.01
SAMPLES = 2000
REPEATS = 3


def _cases(model, kin, count: int, seed: int = 1):
    """Configurations inside the limits and target poses ~5 mm / ~5 mrad away."""
    rng = np.random.default_rng(seed)
    lo, hi = model.position_limits.T
    cases = []
    for _ in range(count):
        q = lo + (hi - lo) * rng.uniform(0.2, 0.8, size=model.n)
        t = kin.tcp(q)
        w = rng.normal(size=3)
        w *= 5e-3 / np.linalg.norm(w)
        target = t.copy()
        target[:3, 3] += rng.normal(size=3) * 3e-3
        target[:3, :3] = spatial.axis_angle(w / np.linalg.norm(w), 5e-3) @ t[:3, :3]
        cases.append((q, target))
    return cases


def _time_loop(fn, cases) -> list[float]:
    out = []
    for q, target in cases:
        t0 = time.perf_counter()
        fn(q, target)
        out.append(time.perf_counter() - t0)
    return out


def bench_irlc(model, cases, max_iter: int):
    kin = Kinematics(model, tool=spatial.inverse(model.flange))
    ik = InverseTransformation(model, kin, IKParams(max_iter=max_iter))
    opts = CycleOptions()
    return lambda q, target: ik.step(q, q, target, DT, opts)


def bench_pink(cases):
    import pink
    import pinocchio as pin
    from pink.limits import ConfigurationLimit, VelocityLimit
    from pink.tasks import FrameTask

    model = pin.buildModelFromUrdf(str(URDF))
    data = model.createData()
    configuration = pink.Configuration(model, data, cases[0][0])
    task = FrameTask(FRAME, position_cost=1.0, orientation_cost=1.0)
    limits = [ConfigurationLimit(model), VelocityLimit(model)]

    def step(q, target):
        configuration.update(q)
        task.set_target(pin.SE3(target[:3, :3], target[:3, 3]))
        return pink.solve_ik(configuration, [task], DT, solver="quadprog", limits=limits)

    return step


def bench_mink(cases):
    import mink
    import mujoco

    model = mujoco.MjModel.from_xml_path(str(URDF))
    configuration = mink.Configuration(model)
    task = mink.FrameTask(FRAME, "body", position_cost=1.0, orientation_cost=1.0)
    vmax = {model.joint(i).name: 2.0 for i in range(model.njnt)}
    limits = [mink.ConfigurationLimit(model), mink.VelocityLimit(model, vmax)]

    def step(q, target):
        configuration.update(q)
        task.set_target(mink.SE3.from_matrix(target))
        return mink.solve_ik(configuration, [task], DT, solver="quadprog", limits=limits)

    return step


def _summary(samples: list[float]) -> tuple[float, float]:
    s = sorted(samples)
    return statistics.median(s) * 1e6, s[int(0.99 * (len(s) - 1))] * 1e6


def main() -> int:
    model = load_robot("panda")
    kin = Kinematics(model, tool=spatial.inverse(model.flange))
    cases = _cases(model, kin, SAMPLES)
    runners = {
        "irlc (1 Newton iteration)": bench_irlc(model, cases, 1),
        "irlc (full cycle, to 1e-9 m)": bench_irlc(model, cases, 10),
    }
    for name, factory in (("pink", bench_pink), ("mink", bench_mink)):
        try:
            runners[name] = factory(cases)
        except ImportError as e:
            print(f"{name}: not installed ({e}); pip install -e '.[bench]'", file=sys.stderr)
    results: dict[str, list[float]] = {name: [] for name in runners}
    for _ in range(REPEATS):  # interleaved, so machine noise hits all alike
        for name, fn in runners.items():
            _time_loop(fn, cases[:50])  # warm-up
            results[name] += _time_loop(fn, cases)
    base = _summary(results["irlc (1 Newton iteration)"])[0]
    print(f"Panda, {SAMPLES}×{REPEATS} steps, position + velocity limits, quadprog")
    print(f"{'solver':32} {'median µs':>10} {'p99 µs':>10} {'× irlc step':>12}")
    for name, samples in results.items():
        med, p99 = _summary(samples)
        print(f"{name:32} {med:10.1f} {p99:10.1f} {med / base:12.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
