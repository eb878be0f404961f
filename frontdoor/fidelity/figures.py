"""The figures of docs/fidelity.md (``python bench/fidelity.py --figures``; needs the
``plot`` extra, matplotlib). Each is irlc's counterpart of a figure of the books, drawn on
the book's axes where the scan keeps them (the chapter-6 tick ranges)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from irlc.fidelity import chapter6 as c6
from irlc.fidelity import dc_drives, steppers
from irlc.runtime.outputs.motor_coords import motor_angles

MOTORS = ("θs1", "θs2", "θs3", "θs4", "θs5", "θs6")


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig, path: Path) -> Path:
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    fig.clf()
    return path


def l1_line(path: Path) -> Path:
    """figs. 4.9/4.10, (4.23): the control errors of the six motors on the line P'→K'."""
    plt = _pyplot()
    model, _, drive = steppers.line_drive()
    errors = steppers.motor_errors(model, drive)
    fig, axes = plt.subplots(2, 1, figsize=(7, 5), sharex=True)
    for k in range(6):
        axes[k // 3].plot(drive.t, errors[:, k], lw=0.8, label=MOTORS[k])
    axes[0].set_title("L-1 line P'→K', stepper drives, position limits not enforced")
    axes[0].set_ylabel("e_qs motors 1–3 [rad]")
    axes[1].set_ylabel("e_qs motors 4–6 [rad]")
    axes[1].set_xlabel("t [s]")
    for ax in axes:
        ax.axhline(np.pi / 100, color="grey", lw=0.5, ls=":")
        ax.axhline(-np.pi / 100, color="grey", lw=0.5, ls=":")
        ax.legend(loc="upper right", fontsize=8)
    return _save(fig, path)


def l1_step(path: Path) -> Path:
    """figs. 4.7/4.8: the wrist motors after a step command, with the robot file's wrist
    inertias and with them ×100 (motors 4 and 5 fall out of step)."""
    plt = _pyplot()
    scales = (steppers.WRIST_SCALES[0], steppers.WRIST_SCALES[-1])
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.6), sharey=True)
    for ax, scale in zip(axes, scales, strict=True):
        model, drive = steppers.step_drive(scale)
        theta = motor_angles(model, drive.q_actual)
        cmd = motor_angles(model, drive.q_cmd_interp)
        for k in range(3, 6):
            line = ax.plot(drive.t, theta[:, k] - theta[0, k], lw=0.9, label=MOTORS[k])[0]
            ax.plot(drive.t, cmd[:, k] - cmd[0, k], lw=0.6, ls="--", color=line.get_color())
        ax.set_title(f"wrist inertia ×{scale:g}")
        ax.set_xlabel("t [s]")
    axes[0].set_ylabel("from the start [rad]")
    fig.suptitle("L-1 step command on W4–W6 (dashed: the command)", fontsize=10)
    axes[0].legend(fontsize=8)
    return _save(fig, path)


def irb6_line(path: Path) -> Path:
    """figs. 5.11–5.21: motor-side following errors of the IRb-6 on the track, line test."""
    plt = _pyplot()
    model, _, _ = dc_drives.command("irb6_track")
    drive = dc_drives.drive_run("irb6_track", "coupled")
    errors = steppers.motor_errors(model, drive)
    fig, ax = plt.subplots(figsize=(7, 3.6))
    for k, joint in enumerate(model.joints):
        if np.ptp(errors[:, k]) > 1e-6:
            ax.plot(drive.t, errors[:, k], lw=0.8, label=f"motor {joint.name}")
    ax.set_title("irb6_track line test, coupled drives: following error, motor side")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("[rad]")
    ax.legend(fontsize=8)
    return _save(fig, path)


def fig_6_20(path: Path) -> Path:
    """fig. 6.20: joints 1–6 of the FREEZE run on the book's axes (tick ranges)."""
    plt = _pyplot()
    result = c6.run("square_freeze")
    q = c6.joints(result)
    fig, axes = plt.subplots(3, 2, figsize=(8, 7), sharex=True)
    for j in range(6):
        ax = axes[j // 2, j % 2]
        lo, hi = c6.FIG_6_20[j + 1]
        ax.plot(result.times, q[:, j], lw=1.0)
        ax.set_ylim(lo, hi)
        where = "issue" if j + 1 in c6.FIG_6_20_ISSUE else "OCR"
        ax.set_title(f"joint {j + 1} [deg] — book's axis {lo:g}…{hi:g} ({where})", fontsize=9)
    for ax in axes[-1]:
        ax.set_xlabel("t [s]")
    fig.suptitle("koch11, FREEZE 2, 3 (fig. 6.20), irlc on the book's axes", fontsize=10)
    return _save(fig, path)


def fig_6_24(path: Path) -> Path:
    """fig. 6.24: the TCP's path and speed on the 5 m line, on the book's axes."""
    plt = _pyplot()
    result = c6.run("obstacle_line", allow_collisions=True)  # the whole 5 m line
    s, v = c6.tcp_path_speed(result)
    fig, axes = plt.subplots(1, 2, figsize=(8, 3.2))
    axes[0].plot(result.times, s)
    axes[0].set_ylim(*c6.FIG_6_24["path_m"])
    axes[0].set_ylabel("path [m]")
    axes[1].plot(result.times, v)
    axes[1].set_ylim(*c6.FIG_6_24["speed_m_s"])
    axes[1].set_ylabel("speed [m/s]")
    for ax in axes:
        ax.set_xlim(*c6.FIG_6_24["time_s"])
        ax.set_xlabel("t [s]")
    fig.suptitle("koch11, 5 m line (fig. 6.24), irlc on the book's axes", fontsize=10)
    return _save(fig, path)


FIGURES = {
    "fidelity_l1_line.png": l1_line,
    "fidelity_l1_step.png": l1_step,
    "fidelity_irb6_line.png": irb6_line,
    "fidelity_fig6_20.png": fig_6_20,
    "fidelity_fig6_24.png": fig_6_24,
}


def write_figures(folder: Path) -> list[Path]:
    folder.mkdir(parents=True, exist_ok=True)
    return [make(folder / name) for name, make in FIGURES.items()]
