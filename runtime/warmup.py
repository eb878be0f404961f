"""Compile the compiled engine's kernels ahead of the first run (``irlc warmup``, or
``python -m irlc.runtime.warmup [ik|drives|pwm …]``): each group runs a tiny problem
through the engine, which compiles its kernels (or loads them from numba's cache) on the
first call.

Nothing calls this on its own: a run that needs a kernel numba has not cached compiles it
at its first call and says so once on stderr (:class:`irlc.runtime.accel_support.Kernels`).
Each group is warmed once per process; :data:`GROUPS` lists them with the cache test
``irlc warmup`` reports ("loaded" or "compiled").
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np
from irlc.runtime import accel_support

_seconds: dict[str, float] = {}  # group → seconds of its warm-up in this process


def _once(name: str, work: Callable[[], None]) -> float:
    """Run ``work`` the first time group ``name`` is warmed; the seconds it took."""
    if name not in _seconds:
        t0 = time.perf_counter()
        work()
        _seconds[name] = time.perf_counter() - t0
    return _seconds[name]


def _tiny_solver():
    """A 3-joint planar arm's solver on the compiled cycle, a configuration and a target."""
    from irlc.robots.model import Joint, Limits, RobotModel
    from irlc.runtime.ik.newton import InverseTransformation
    from irlc.runtime.ik.params import IKParams
    from irlc.runtime.model.kinematics import Kinematics

    link = np.eye(4)
    link[0, 3] = 1.0
    limits = Limits((-3.0, 3.0), (-3.0, 3.0), (-20.0, 20.0))
    axis = np.array([0.0, 0.0, 1.0])
    joints = tuple(
        Joint(f"J{i}", "revolute", link if i else np.eye(4), axis, limits) for i in range(3)
    )
    model = RobotModel(name="warmup", joints=joints, flange=link)
    ik = InverseTransformation(model, Kinematics(model), IKParams(task_rows=(0, 1), accel=True))
    q = np.array([0.1, 0.2, 0.3])
    target = ik.kin.tcp(q)
    target[0, 3] += 1e-3
    return ik, q, target


def warm_ik() -> float:
    """The IK cycle kernel: one tiny cycle (seconds)."""

    def work() -> None:
        ik, q, target = _tiny_solver()
        ik.step(q, q, target, 0.01)

    return _once("ik", work)


def warm_ik_obstacles() -> float:
    """The IK obstacle queries (≈ 8 s of CPU to compile): one tiny cycle avoiding a point."""

    def work() -> None:
        from irlc.runtime.ik.params import CycleOptions
        from irlc.runtime.model.obstacles import PointObstacle

        ik, q, target = _tiny_solver()
        near = PointObstacle("near", target[:3, 3] + (0.0, 0.0, 0.3))
        avoid = CycleOptions(obstacles=(near,), active_obstacles=frozenset({"near"}))
        ik.step(q, q, target, 0.01, avoid)

    return _once("ik_obstacles", work)


def warm_ik_energy() -> float:
    """ENERGY's inertia kernel: one cycle of the planar3 arm (it has inertials)."""

    def work() -> None:
        from irlc.robots import load_robot
        from irlc.runtime.ik.newton import InverseTransformation
        from irlc.runtime.ik.params import CycleOptions, IKParams

        model = load_robot("planar3")
        ik = InverseTransformation(model, None, IKParams.for_robot(model, accel=True))
        q = np.array([0.1, 0.5, -0.5])
        target = ik.kin.tcp(q)
        target[0, 3] += 1e-3
        ik.step(q, q, target, 0.01, CycleOptions(criterion="ENERGY"))

    return _once("ik_energy", work)


def _tiny_drive_run(levels: tuple[str, ...], seconds: float) -> None:
    """The irb6_track (screw levers, friction: every branch's types) standing still."""
    from irlc.robots import load_robot
    from irlc.runtime.drives.simulate import simulate_drives

    model = load_robot("irb6_track")
    q0 = np.asarray(model.home_q(), dtype=float)
    times = np.array([0.0, seconds])
    for level in levels:  # (coupled and decoupled share one kernel; decoupled: no compile)
        simulate_drives(model, times, np.stack([q0, q0]), level=level, hold=0.0, accel=True)


def warm_drives() -> float:
    """The averaged drive kernel (coupled and decoupled levels)."""
    return _once("drives", lambda: _tiny_drive_run(("coupled", "decoupled"), 0.01))


def warm_pwm() -> float:
    """The ``pwm`` drive kernel."""
    return _once("pwm", lambda: _tiny_drive_run(("pwm",), 0.005))


def _ik_cached() -> bool:
    from irlc.runtime.ik.compiled import driver

    return driver.cache_warm()


def _drives_cached() -> bool:
    from irlc.runtime.drives.compiled import loop

    return loop.KERNELS.cache_warm()


def _pwm_cached() -> bool:
    from irlc.runtime.drives.compiled import pwm_loop

    return pwm_loop.KERNELS.cache_warm()


GROUPS: dict[str, tuple[str, Callable[[], bool], tuple[Callable[[], float], ...]]] = {
    "ik": ("IK kernels", _ik_cached, (warm_ik, warm_ik_obstacles, warm_ik_energy)),
    "drives": ("drive kernels", _drives_cached, (warm_drives,)),
    "pwm": ("PWM drive kernels", _pwm_cached, (warm_pwm,)),
}
"""``key: (name, cached, warm-ups)`` of each kernel group, in the order ``irlc warmup``
runs them."""


def warm_all(report: Callable[[str], None] = print, keys: tuple[str, ...] = ()) -> None:
    """Compile (or load) the groups ``keys`` (default: all); ``report`` gets one line per
    group ("IK kernels: loaded from numba's cache in 0.3 s")."""
    for key in keys or tuple(GROUPS):
        name, cached, steps = GROUPS[key]
        warm = cached()
        seconds = sum(step() for step in steps)
        done = "loaded from numba's cache" if warm else "compiled and cached"
        report(f"{name}: {done} in {seconds:.1f} s")


if __name__ == "__main__":  # python -m irlc.runtime.warmup [ik|drives|pwm …]
    import sys

    if not accel_support.kernels_allowed():
        raise SystemExit("numba is not installed (pip install 'irlc[fast]') or IRLC_ENGINE=numpy")
    unknown = [key for key in sys.argv[1:] if key not in GROUPS]
    if unknown:
        raise SystemExit(f"unknown kernel group {unknown[0]!r}; known: {', '.join(GROUPS)}")
    accel_support.WARMING_UP = True
    warm_all(keys=tuple(sys.argv[1:]))
