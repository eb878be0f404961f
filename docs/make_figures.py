"""Regenerate the figures of docs/tutorial.md into docs/img/ (a few small PNGs).

    python docs/make_figures.py            # needs matplotlib; chromium for the screenshot

Each figure is one file of ``irlc.plots.write_plots`` for a run of a program in
``programs/`` (optionally overlaid with a second run), copied under a descriptive name.
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


def main() -> None:
    IMG.mkdir(parents=True, exist_ok=True)
    names = {n for f in FIGURES for n in f[1:3] if n} | {SCREENSHOT[1]}
    runs = {n: _run(n) for n in sorted(names)}
    make_plots(runs)
    make_screenshot(runs)


if __name__ == "__main__":
    main()
