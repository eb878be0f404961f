"""Regenerate the figures of docs/tutorial.md into docs/img/ (a few small PNGs).

    python docs/make_figures.py            # needs matplotlib; chromium for the screenshot
    python docs/make_figures.py cooperating    # only docs/img/cooperating.png

Each figure is one file of ``irlc.plots.write_plots`` for a run of a program in
``programs/`` (optionally overlaid with a second run), copied under a descriptive name;
``cooperating.png`` (docs/runtime.md, "Cells of several robots") is the seed's figure 3.5
for ``programs/cooperating.irl``: both robots' joints along the seam, without and with the
JOINTLIMIT sets.
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
    if sys.argv[1:] == ["cooperating"]:
        make_cooperating()
        return
    names = {n for f in FIGURES for n in f[1:3] if n} | {SCREENSHOT[1]}
    runs = {n: _run(n) for n in sorted(names)}
    make_plots(runs)
    make_screenshot(runs)
    make_cooperating()


if __name__ == "__main__":
    main()
