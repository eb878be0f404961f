"""What a drive simulation returns, its per-axis summary, and the report/trace views in
program units (deg | mm) through :mod:`irlc.runtime.units`."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime import units

REVOLUTE_TOLERANCE = 5.0 * units.DEG  # default "could not follow" bound (rad)
PRISMATIC_TOLERANCE = 10.0 * units.MM  # (m)


@dataclass(frozen=True)
class AxisSummary:
    """One joint's result; SI (rad | m, s, A, N·m | N)."""

    joint: int  # 0-based
    name: str
    kind: str
    drive: str  # "dc" | "stepper" | "ideal"
    max_following_error: float
    final_error: float
    settling_time: float | None  # s after the last setpoint change; None: never settled
    saturation_time: float  # s with any saturation (P, PI, voltage, current) active
    peak_current: float
    peak_torque: float
    could_follow: bool
    lost_steps: int | None = None
    setpoint_violations: int = 0  # drive steps where the slave's v_max / a_max is exceeded


@dataclass
class DriveRun:
    """Per drive step (or per IPO sample, ``record="ipo"``), shape ``(k, n)`` unless noted.

    ``current`` is motor side (A; the on phase for steppers), ``torque`` the drive torque on
    the joint side (``i·τ_m``; for an ideal joint the torque its motion needs, or zero
    without inertial data), ``friction`` joint side, ``voltage`` the armature voltage.
    """

    level: str
    step: float
    t: np.ndarray  # (k,)
    q_actual: np.ndarray
    q_cmd_interp: np.ndarray
    qd_actual: np.ndarray
    current: np.ndarray
    torque: np.ndarray
    voltage: np.ndarray
    friction: np.ndarray
    driven: np.ndarray  # (n,) bool: True where the joint has drive data
    axes: list[AxisSummary]
    notes: list[str] = field(default_factory=list)
    electrical_energy: np.ndarray | None = None  # (n,) J delivered by the power stages
    copper_energy: np.ndarray | None = None  # (n,) J lost in the windings (∫ R i² dt)
    # (k, n) s: the saturation time up to each row (a run cut at a failure: its share)
    saturation_cum: np.ndarray | None = None

    @property
    def could_follow(self) -> bool:
        return all(a.could_follow for a in self.axes)

    @property
    def following_error(self) -> np.ndarray:
        return self.q_cmd_interp - self.q_actual


def default_tolerance(model: RobotModel) -> np.ndarray:
    return np.array(
        [REVOLUTE_TOLERANCE if j.kind == "revolute" else PRISMATIC_TOLERANCE for j in model.joints]
    )


def summarise(
    run: DriveRun,
    model: RobotModel,
    times: np.ndarray,
    q_cmd: np.ndarray,
    saturated: np.ndarray,
    tolerance: np.ndarray,
    drives: list[str],
    lost: dict[int, int],
    violations: np.ndarray,
) -> list[AxisSummary]:
    """Per-axis summary; ``saturated`` is ``(k, n)`` bool per recorded step."""
    err = np.abs(run.following_error)
    span = np.ptp(q_cmd, axis=0)
    moving = np.flatnonzero(np.any(np.abs(np.diff(q_cmd, axis=0)) > 0.0, axis=1))
    t_last = times[moving[-1] + 1] if moving.size else times[0]
    dt = np.diff(run.t, prepend=run.t[0])
    out = []
    for j, joint in enumerate(model.joints):
        band = max(0.02 * span[j], 1e-3 * tolerance[j])
        outside = np.flatnonzero((err[:, j] > band) & (run.t >= t_last))
        if outside.size == 0:
            settle = 0.0
        elif outside[-1] == len(run.t) - 1:
            settle = None
        else:
            settle = float(run.t[outside[-1] + 1] - t_last)
        follow = bool(err[:, j].max() <= tolerance[j]) and lost.get(j, 0) == 0
        out.append(
            AxisSummary(
                joint=j,
                name=joint.name,
                kind=joint.kind,
                drive=drives[j],
                max_following_error=float(err[:, j].max()),
                final_error=float(err[-1, j]),
                settling_time=settle,
                saturation_time=float(np.sum(dt[saturated[:, j]])),
                peak_current=float(np.abs(run.current[:, j]).max()),
                peak_torque=float(np.abs(run.torque[:, j]).max()),
                could_follow=follow,
                lost_steps=lost.get(j),
                setpoint_violations=int(violations[j]),
            )
        )
    return out


def deviation_percent(reference: DriveRun, other: DriveRun) -> np.ndarray:
    """Szkodny's simplification measure, per joint: the largest difference between two
    runs of the same setpoints, in % of the commanded range ``max q_cmd − min q_cmd``."""
    if reference.t.shape != other.t.shape or not np.allclose(reference.t, other.t):
        raise ValueError("deviation_percent needs two runs on the same time grid")
    span = np.ptp(reference.q_cmd_interp, axis=0)
    diff = np.max(np.abs(reference.q_actual - other.q_actual), axis=0)
    return 100.0 * diff / np.where(span > 0.0, span, np.inf)


def report_axes(run: DriveRun, model: RobotModel) -> list[dict]:
    """The per-axis summary as plain dicts in program units (deg | mm, s, A, N·m | N)."""
    rows = []
    for a in run.axes:
        unit = units.joint_unit(a.kind)
        scale = units.joint_scale([a.kind])[0]
        force = "torque_Nm" if a.kind == "revolute" else "force_N"
        rows.append(
            {
                "joint": a.name,
                "drive": a.drive,
                f"max_following_error_{unit}": a.max_following_error / scale,
                f"final_error_{unit}": a.final_error / scale,
                "settling_time_s": a.settling_time,
                "saturation_time_s": a.saturation_time,
                "peak_current_A": a.peak_current,
                f"peak_{force}": a.peak_torque,
                "could_follow": a.could_follow,
                "lost_steps": a.lost_steps,
                "setpoint_violations": a.setpoint_violations,
            }
        )
    return rows


def trace_columns(
    run: DriveRun, model: RobotModel, times: np.ndarray | None = None
) -> dict[str, np.ndarray]:
    """``<joint>_cmd_<unit>`` (setpoint seen by the drive) and ``<joint>_current_A``,
    sampled at ``times`` (default: the run's own), program units."""
    t = run.t if times is None else np.asarray(times, dtype=float)
    kinds = model.joint_kinds
    scale = units.joint_scale(kinds)
    out: dict[str, np.ndarray] = {}
    for j, joint in enumerate(model.joints):
        cmd = np.interp(t, run.t, run.q_cmd_interp[:, j]) / scale[j]
        out[f"{joint.name}_cmd_{units.joint_unit(kinds[j])}"] = cmd
        out[f"{joint.name}_current_A"] = np.interp(t, run.t, run.current[:, j])
    return out
