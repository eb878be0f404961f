"""Regenerate the figures of docs/tutorial.md, docs/language.md and docs/ik.md into docs/img/.

    python docs/make_figures.py [plots] [screenshot] [platform] [criteria] [cooperating]
    # default: all
    # needs matplotlib; chromium for the screenshot

Each tutorial figure is one file of ``irlc.plots.write_plots`` for a run of a program in
``programs/`` (optionally overlaid with a second run), copied under a descriptive name.
The platform figures (``platform``) are drawn here from the traces of
``programs/track_platform.irl`` and ``programs/mobile_platform.irl``: where the TCP and the
platform are over time, and the fraction of its way each has gone in the motions WITH
PLATFORM (the two curves coincide: the platform moves in step with the TCP).
``criteria.png`` (docs/ik.md, "ENERGY and MVR", group ``criteria``) runs
programs/square_energy.irl and programs/reach_mvr.irl as written and with
``R_CRITERION := 'DISTANCE'``.
``cooperating.png`` (docs/runtime.md, "Cells of several robots", group ``cooperating``) is
the seed's figure 3.5 for ``programs/cooperating.irl``: both robots' joints along the seam,
without and with the JOINTLIMIT sets.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PROGRAMS = ROOT / "programs"
IMG = ROOT / "docs" / "img"

# (output name, program, compared program or None, figure of write_plots)
FIGURES = [
    ("square_path_speed.png", "square", None, "tcp_path_speed.png"),
    ("square_j11_positions_7-11.png", "square_limits", "square_j11",
     "joint_positions_7-11.png"),
    ("square_speed_speeds_7-11.png", "square_limits", "square_speed", "joint_speeds_7-11.png"),
    ("obstacle_positions_7-11.png", "obstacle_line", "obstacle_line_avoid",
     "joint_positions_7-11.png"),
]  # fmt: skip
SCREENSHOT = ("animation_obstacle.png", "obstacle_line_avoid")
CRITERIA = ("criteria.png", ("square_energy", "ENERGY"), ("reach_mvr", "MVR"))


def _run(name: str):
    from irlc.runtime.run import run_file

    # obstacle_line shows the arm passing through the post: collisions allowed for it
    run = run_file(PROGRAMS / f"{name}.irl", allow_collisions=name == "obstacle_line")
    if run.status != "ok":
        print(f"{name}.irl failed ({run.error}): its figures are skipped", file=sys.stderr)
        return None
    return run


def make_plots(runs: dict) -> None:
    from irlc.plots import write_plots

    for out_name, name, other, figure in FIGURES:
        if runs[name] is None or (other and runs[other] is None):
            continue
        with tempfile.TemporaryDirectory() as tmp:
            compare = runs[other] if other else None
            write_plots(runs[name], tmp, compare=compare)
            shutil.copyfile(Path(tmp) / figure, IMG / out_name)
        print(f"docs/img/{out_name}")


def _with_criterion(name: str, word: str):
    """``programs/NAME.irl`` run with its ``R_CRITERION`` word replaced by ``word``."""
    import re

    from irlc.runtime.run import run_file

    source = (PROGRAMS / f"{name}.irl").read_text(encoding="utf-8")
    source = re.sub(r"R_CRITERION := '\w+'", f"R_CRITERION := '{word}'", source)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f"{name}.irl"
        path.write_text(source, encoding="utf-8")
        return run_file(path, datalist_path=[str(PROGRAMS)])


def make_criteria_figure() -> None:
    """The links' kinetic energy along square_energy.irl and the velocity ratio along
    reach_mvr.irl, each under its criterion and under DISTANCE; the joints' travel."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from irlc.runtime import units

    out_name, (square, energy), (reach, ratio) = CRITERIA
    fig, axes = plt.subplots(1, 3, figsize=(13.5, 3.8))
    runs = {word: _with_criterion(square, word) for word in (energy, "DISTANCE")}
    for word, run in runs.items():
        t = run.trace[:, run.trace_columns.index("t_s")]
        e = run.trace[:, run.trace_columns.index("kinetic_energy_j")]
        total = run.report["kinetic_energy"]["integral_j_s"]
        axes[0].plot(t, e, label=f"{word}: ∫E dt = {total:.0f} J·s")
        scale = units.joint_scale(run.model.joint_kinds)  # rad | m per deg | mm
        travel = np.abs(np.diff(run.q, axis=0)).sum(axis=0) / scale
        shift = -0.2 if word == energy else 0.2
        axes[1].bar(np.arange(1, run.model.n + 1) + shift, travel, width=0.4, label=word)
    axes[0].set(title=f"{square}.irl (koch11): links' kinetic energy", xlabel="t (s)",
                ylabel="kinetic_energy_j (J)")  # fmt: skip
    axes[1].set(title="joint travel Σ|Δθ| (J10: mm)", xlabel="joint", ylabel="deg | mm",
                xticks=range(1, 12), yscale="log")  # fmt: skip
    ratios = {}
    for word in (ratio, "DISTANCE"):
        run = _with_criterion(reach, word)
        t = run.trace[:, run.trace_columns.index("t_s")]
        ratios[word] = m = run.trace[:, run.trace_columns.index("mvr")]
        moving = m > 0
        label = f"{word}: min {run.report['mvr']['min']:.3f}"
        axes[2].plot(t[moving], m[moving], label=label)
    axes[2].set(title=f"{reach}.irl (planar3): velocity ratio", xlabel="t (s)",
                ylabel="mvr (m/rad)")  # fmt: skip
    gain = axes[2].twinx()  # how much higher MVR keeps it, sample by sample
    moving = (ratios[ratio] > 0) & (ratios["DISTANCE"] > 0)
    rel = 100.0 * (ratios[ratio][moving] / ratios["DISTANCE"][moving] - 1.0)
    gain.plot(t[moving], rel, color="0.5", linestyle="--", linewidth=1)
    gain.set_ylabel(f"{ratio} over DISTANCE (%, dashed)", color="0.4")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(IMG / out_name, dpi=90)
    plt.close(fig)
    print(f"docs/img/{out_name}")


def make_screenshot(runs: dict) -> None:
    from irlc.animate import write_animation

    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    if chromium is None:
        print("chromium not found: screenshot skipped", file=sys.stderr)
        return
    out_name, name = SCREENSHOT
    if runs[name] is None:
        return
    with tempfile.TemporaryDirectory() as tmp:
        page = write_animation(runs[name], Path(tmp) / "a.html")
        subprocess.run(
            [chromium, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
             "--disable-background-networking", "--disable-component-update", "--disable-sync",
             f"--user-data-dir={tmp}/profile", f"--screenshot={IMG / out_name}",
             "--window-size=900,560", page.as_uri() + "#t=4.5"],
            check=True, capture_output=True, timeout=120,
        )  # fmt: skip
    print(f"docs/img/{out_name}")


def _fractions(trace, columns, lines, platform_axes: list[str]):
    """Time, the TCP's and the platform's fraction of the way (0 … 1) over the rows of the
    statements ``lines`` (and the row before them): the TCP's by its path length, the
    platform's along its line from the first to the last row."""
    import numpy as np

    at = trace[:, columns.index("line")]
    idx = np.flatnonzero(np.isin(at, lines))
    idx = np.concatenate(([idx[0] - 1], idx))
    t = trace[idx, columns.index("t_s")]
    tcp = trace[np.ix_(idx, [columns.index(c) for c in ("x_mm", "y_mm", "z_mm")])]
    travelled = np.concatenate(([0.0], np.cumsum(np.linalg.norm(np.diff(tcp, axis=0), axis=1))))
    pl = trace[np.ix_(idx, [columns.index(c) for c in platform_axes])]
    d = pl[-1] - pl[0]
    return t, travelled / travelled[-1], (pl - pl[0]) @ d / (d @ d)


def _in_step(ax, fractions, labels: tuple[str, str], title: str) -> None:
    """The TCP's and the platform's fraction of the way over time, on ``ax``."""
    ts, f_tcp, f_platform = fractions
    ax.plot(ts, f_tcp, lw=3, alpha=0.5, label=labels[0])
    ax.plot(ts, f_platform, "k--", lw=1, label=labels[1])
    ax.set(xlabel="t [s]", ylabel="fraction of the way", title=title)
    ax.legend(loc="upper left", fontsize=8)


def _save(fig, name: str) -> None:
    fig.tight_layout()
    fig.savefig(IMG / name, dpi=90)
    print(f"docs/img/{name}")


def make_platform_figures() -> None:
    """docs/img/track_platform.png and mobile_platform.png (module docstring)."""
    import matplotlib
    import numpy as np

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    track = _run("track_platform")
    if track is not None:
        tr, cols = track.trace, track.trace_columns
        t = tr[:, cols.index("t_s")]
        fig, (a, b) = plt.subplots(1, 2, figsize=(9.6, 3.6))
        a.plot(t, tr[:, cols.index("y_mm")], label="TCP y (the line on the wall)")
        a.plot(t, tr[:, cols.index("platform_y_mm")], label="carriage y (platform_y_mm)")
        a.set(xlabel="t [s]", ylabel="world y [mm]", title="as6_track: tool and carriage")
        a.legend(loc="upper left", fontsize=8)
        labels = ("TCP: fraction of its 600 mm line", "carriage: fraction of 0 → 1500 mm")
        _in_step(b, _fractions(tr, cols, [17], ["platform_y_mm"]), labels,
                 "line 17, WITH PLATFORM := 1500: in step")  # fmt: skip
        _save(fig, "track_platform.png")
        plt.close(fig)
    mobile = _run("mobile_platform")
    if mobile is not None:
        tr, cols = mobile.trace, mobile.trace_columns
        fig, (a, b) = plt.subplots(1, 2, figsize=(9.6, 3.8))
        at = tr[:, cols.index("line")]
        sel = (at >= 16) & (at <= 17)
        y, z = tr[sel, cols.index("y_mm")], tr[sel, cols.index("z_mm")]
        py = tr[sel, cols.index("platform_y_mm")]
        a.plot(y, z, label="TCP on the wall (y, z)")
        for k in range(0, len(y), max(1, len(y) // 12)):  # where the platform is meanwhile
            a.plot([y[k], py[k]], [z[k], 560], color="0.75", lw=0.8)
        a.plot(py, np.full(len(py), 560.0), "k", lw=3,
               label="platform y (drawn at z = 560; grey: at the same time)")  # fmt: skip
        a.set(xlabel="world y [mm]", ylabel="world z [mm]", aspect="equal",
              title="mobile8: circle and platform line")  # fmt: skip
        a.legend(loc="upper right", fontsize=8)
        labels = ("TCP: fraction of the circle", "platform: fraction of (0, 0) → (0, 500) mm")
        fractions = _fractions(tr, cols, [16, 17], ["platform_x_mm", "platform_y_mm"])
        _in_step(b, fractions, labels, "lines 16-17, two CIRCLE halves: in step")
        _save(fig, "mobile_platform.png")
        plt.close(fig)


COOPERATING_LIMITS = {"holder": (4, 60.0, 100.0), "welder": (3, 20.0, 60.0)}  # J5, J4 (deg)


def make_cooperating() -> None:
    """Fig. 3.5 for programs/cooperating.irl: joints 1–6 of the holder and the welder along
    the seam (inside COOPERATE), (a, b) without the JOINTLIMIT statements, (c, d) with them;
    the two narrowed ranges dashed."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from irlc.lang import compile_source
    from irlc.robots import load_robot
    from irlc.runtime.run import run_code, run_file

    path = PROGRAMS / "cooperating.irl"
    text = path.read_text(encoding="utf-8")
    lines = text.splitlines()
    first = next(i + 1 for i, line in enumerate(lines) if "COOPERATE welder IN holder" in line)
    free_text = "\n".join("" if line.lstrip().startswith("JOINTLIMIT") else line for line in lines)
    free = run_code(compile_source(free_text, str(path), resolve_robot=load_robot).code)
    runs = (("without JOINTLIMIT", free), ("with JOINTLIMIT", run_file(path)))
    fig, axes = plt.subplots(2, 2, figsize=(10, 6.4), sharex=True, sharey=True)
    for row, (label, run) in enumerate(runs):
        for col, name in enumerate(("holder", "welder")):
            ax, robot = axes[row][col], run.robots[name]
            at = robot.recorded.lines >= first
            t = robot.times[at] - robot.times[at][0]
            q = np.degrees(robot.q[at])
            for j in range(q.shape[1]):
                ax.plot(
                    t,
                    q[:, j],
                    label=f"J{j + 1}",
                    lw=1.4 if j == COOPERATING_LIMITS[name][0] else 0.9,
                )
            joint, lo, hi = COOPERATING_LIMITS[name]
            for bound in (lo, hi):
                ax.axhline(bound, ls="--", lw=0.8, color=f"C{joint}")
            panel = "abcd"[2 * row + col]
            ax.set_title(f"({panel}) {name}, {label}: J{joint + 1} in [{lo:g}, {hi:g}]", fontsize=9)
            ax.grid(alpha=0.3)
            if row == 1:
                ax.set_xlabel("t in COOPERATE [s]")
            if col == 0:
                ax.set_ylabel("joint [deg]")
    axes[0][1].legend(loc="upper right", fontsize=7, ncol=2)
    fig.suptitle("programs/cooperating.irl: the seam as one chain of 12 joints (seed fig. 3.5)")
    fig.tight_layout()
    fig.savefig(IMG / "cooperating.png", dpi=90)
    print("docs/img/cooperating.png")


def main() -> None:
    IMG.mkdir(parents=True, exist_ok=True)
    groups = set(sys.argv[1:]) or {"plots", "screenshot", "platform", "criteria", "cooperating"}
    names = {n for f in FIGURES for n in f[1:3] if n} | {SCREENSHOT[1]}
    runs = {n: _run(n) for n in sorted(names)} if groups & {"plots", "screenshot"} else {}
    if "plots" in groups:
        make_plots(runs)
    if "screenshot" in groups:
        make_screenshot(runs)
    if "platform" in groups:
        make_platform_figures()
    if "criteria" in groups:
        make_criteria_figure()
    if "cooperating" in groups:
        make_cooperating()


if __name__ == "__main__":
    main()
