"""Synthetic runs for the tool tests: a small 4-joint robot (R, R, P, R) moving smoothly.

The run has the fields of ``irlc.runtime.outputs.run_result.RunResult`` that the tools
read, and a trace with the ``interfaces.md`` columns in program units, computed here in closed form.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
from irlc.robots.model import Capsule, Joint, Limits, RobotModel
from irlc.runtime.model.kinematics import Kinematics

DT = 0.01
NAMES = ("a1", "a2", "a3", "a4")
KINDS = ("revolute", "revolute", "prismatic", "revolute")
AMPL = np.array([30.0, 20.0, 150.0, 45.0])  # deg | mm
FREQ = np.array([0.5, 0.8, 0.4, 1.1])  # rad/s


def _trans(x, y, z) -> np.ndarray:
    t = np.eye(4)
    t[:3, 3] = (x, y, z)
    return t


def small_robot() -> RobotModel:
    lim = [
        Limits((-math.radians(170), math.radians(170)), (-2.0, 2.0), (-10.0, 10.0)),
        Limits((-math.radians(25), math.radians(90)), (-1.5, 1.5), (-8.0, 8.0)),
        Limits((-0.2, 0.3), (-0.5, 0.5), (-2.0, 2.0)),
        Limits((-math.radians(120), math.radians(120)), (-3.0, 3.0), (-20.0, 20.0)),
    ]
    joints = (
        Joint("J1", "revolute", np.eye(4), np.array([0, 0, 1.0]), lim[0]),
        Joint("J2", "revolute", _trans(0, 0, 0.5), np.array([0, 1.0, 0]), lim[1]),
        Joint("J3", "prismatic", _trans(0.4, 0, 0), np.array([1.0, 0, 0]), lim[2]),
        Joint("J4", "revolute", _trans(0.3, 0, 0), np.array([0, 1.0, 0]), lim[3]),
    )
    geometry = (
        Capsule(1, np.zeros(3), np.array([0, 0, 0.5]), 0.06),
        Capsule(2, np.zeros(3), np.array([0.4, 0, 0]), 0.05),
        Capsule(3, np.zeros(3), np.array([0.3, 0, 0]), 0.04),
        Capsule(4, np.zeros(3), np.array([0.2, 0, 0]), 0.03),
    )
    return RobotModel("small4", joints, flange=_trans(0.2, 0, 0), geometry=geometry)


def make_run(duration: float = 3.0, phase: float = 0.0, drives: bool = False, label="demo"):
    """A RunResult-like object: q(t) = A·sin(ωt + φ) per joint (program units)."""
    model = small_robot()
    t = np.round(np.arange(0.0, duration + DT / 2, DT), 10)
    arg = np.outer(t, FREQ) + phase
    q_prog = AMPL * np.sin(arg)
    qd_prog = AMPL * FREQ * np.cos(arg)
    qdd_prog = -AMPL * FREQ**2 * np.sin(arg)
    scale = np.array([math.pi / 180, math.pi / 180, 1e-3, math.pi / 180])
    q = q_prog * scale
    kin = Kinematics(model)
    tcp = np.array([kin.tcp(qi) for qi in q])
    cols = ["t_s", "line"]
    cols += [
        f"{n}_{'mm' if k == 'prismatic' else 'deg'}" for n, k in zip(NAMES, KINDS, strict=True)
    ]
    cols += [
        f"{n}_speed_{'mm' if k == 'prismatic' else 'deg'}_s"
        for n, k in zip(NAMES, KINDS, strict=True)
    ]
    cols += [
        f"{n}_accel_{'mm' if k == 'prismatic' else 'deg'}_s2"
        for n, k in zip(NAMES, KINDS, strict=True)
    ]
    cols += ["x_mm", "y_mm", "z_mm", "a_deg", "b_deg", "c_deg", "path_error_mm"]
    lines = np.where(t < duration / 2, 7, 9)
    abc = np.zeros((len(t), 3))
    parts = [t[:, None], lines[:, None], q_prog, qd_prog, qdd_prog, tcp[:, :3, 3] * 1e3, abc,
             np.full((len(t), 1), 1e-4)]  # fmt: skip
    if drives:
        lag = 0.02
        cmd_prog = AMPL * np.sin(np.outer(t + lag, FREQ) + phase)
        cols += [
            f"{n}_cmd_{'mm' if k == 'prismatic' else 'deg'}"
            for n, k in zip(NAMES, KINDS, strict=True)
        ]
        cols += [f"{n}_current_A" for n in NAMES]
        parts += [cmd_prog, 2.0 * np.cos(arg)]
    data = np.hstack(parts)
    report = {
        "status": "ok",
        "error": None,
        "program": f"{label}.irl",
        "robot": "small4",
        "units": {"length": "mm", "angle": "deg", "time": "s"},
        "ipo_s": DT,
        "drives": "decoupled" if drives else "ideal",
        "duration_s": float(t[-1]),
        "samples": len(t),
        "joints": [
            {
                "name": n,
                "unit": "mm" if k == "prismatic" else "deg",
                "min": float(q_prog[:, i].min()),
                "max": float(q_prog[:, i].max()),
                "max_abs_speed": float(abs(qd_prog[:, i]).max()),
                "max_abs_accel": float(abs(qdd_prog[:, i]).max()),
                "limit_active_s": 0.0,
                "max_following_error": None,
            }
            for i, (n, k) in enumerate(zip(NAMES, KINDS, strict=True))
        ],
        "start_joints": [float(v) for v in q_prog[0]],
        "end_joints": [float(v) for v in q_prog[-1]],
        "max_path_error_mm": 1e-4,
        "max_orientation_error_deg": 1e-6,
        "obstacles": {},
        "ik": {"cycles": len(t), "iterations_mean": 1.5, "iterations_max": 3, "relaxed_cycles": 0},
        "output": ["hello"],
        "warnings": [],
    }
    return SimpleNamespace(
        status="ok", error=None, report=report, times=t, q=q, tcp=tcp,
        trace_columns=cols, trace=data, model=model, obstacles=(), output=["hello"],
        drive=None,
    )  # fmt: skip
