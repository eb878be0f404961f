"""Regenerate the figures of docs/tutorial.md and docs/ik.md into docs/img/ (small PNGs).

    python docs/make_figures.py            # needs matplotlib; chromium for the screenshot

Each tutorial figure is one file of ``irlc.plots.write_plots`` for a run of a program in
``programs/`` (optionally overlaid with a second run), copied under a descriptive name;
``criteria.png`` (docs/ik.md, "ENERGY and MVR") runs programs/square_energy.irl and
programs/reach_mvr.irl as written and with ``R_CRITERION := 'DISTANCE'``.
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


def main() -> None:
    IMG.mkdir(parents=True, exist_ok=True)
    names = {n for f in FIGURES for n in f[1:3] if n} | {SCREENSHOT[1]}
    runs = {n: _run(n) for n in sorted(names)}
    make_plots(runs)
    make_criteria_figure()
    make_screenshot(runs)


if __name__ == "__main__":
    main()
