"""The IPO cycle of a cell of several robots next to one robot's (issue 26).

    python bench/bench_cells.py [--repeat 3]

Each case is a whole kinematic run (``run_code``, the compile excluded) of a program whose
time is nearly all one long Cartesian motion, timed by process CPU; the figure is CPU per
recorded IPO cycle (the run's CPU over its samples), the best of ``repeat`` runs after a
warm-up run. The cases:

* one AS arm's 600 mm LIN (a program of one robot: the single-robot path);
* the same LIN in a cell while a second AS arm holds (the cell's per-cycle work: the other
  robot's hold sample and the clearance between every watched pair of links);
* the welder's 600 mm seam inside ``COOPERATE`` (one 12-joint problem per cycle, both
  robots' samples from the pair's), and the same ``WITH VERTICAL`` (two extra rows);
* the Panda's line of ``programs/two_robots.irl`` with ``R_CLEARANCE := 50`` (QP rows of the
  pairs within reach, the AS arm's links as obstacles) and with ``R_CLEARANCE := 0``;
* a group move: both AS arms' LINs in lock-step.

Prints a Markdown table (docs/benchmarks.md, "Cells").
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import numpy as np
from irlc.lang import compile_source
from irlc.robots import load_robot
from irlc.runtime.run import run_code

HEAD = """PROGRAM b;
ROBOT holder := as6;
{second}
CONST
  MAIN_JOINT: h = (90, 40, -30, 50, 60, 20);
  MAIN_JOINT: w = (90, 45, 0, 45, 90, 0);
VAR
  POSE: p, grip;
BEGIN
"""
ONE = (
    HEAD.format(second="")
    + """  MOVE PTP h;
  p := R_ACT_POSE;
  MOVE LIN p : (0, 0, -150, 0, 0, 0) WITH SPEED := 20;
ENDPROGRAM
"""
)
HOLDS = (
    HEAD.format(second="ROBOT welder := as6 AT (0, -2200, 0, 180, 0, 0);")
    + """  MOVE holder PTP h;
  p := holder.R_ACT_POSE;
  MOVE holder LIN p : (0, 0, -150, 0, 0, 0) WITH SPEED := 20;
ENDPROGRAM
"""
)
GROUP = (
    HEAD.format(second="ROBOT welder := as6 AT (0, -2200, 0, 180, 0, 0);")
    + """  MOVE holder PTP h AND welder PTP h;
  p := holder.R_ACT_POSE;
  grip := welder.R_ACT_POSE;
  MOVE holder LIN p : (0, 0, -150, 0, 0, 0) WITH SPEED := 20
   AND welder LIN grip : (0, 0, -150, 0, 0, 0) WITH SPEED := 20;
ENDPROGRAM
"""
)
COOPERATE = (
    HEAD.format(second="ROBOT welder := as6 AT (0, -2200, 0, 180, 0, 0);")
    + """  MOVE holder PTP w AND welder PTP w;
  grip := INV(holder.R_ACT_POSE) : welder.R_ACT_POSE;
  COOPERATE welder IN holder;
    MOVE welder LIN grip : (600, 0, 0, 0, 0, 0) WITH SPEED := 50;
  COOPERATEEND;
ENDPROGRAM
"""
)
VERTICAL = """PROGRAM b;
ROBOT holder := as6;
ROBOT welder := as6 AT (0, -2200, 0, 180, 0, 0);
CONST
  MAIN_JOINT: h = (90, 40, -30, 50, 60, 20);
  MAIN_JOINT: v = (110.369, 50.074, -8.502, 66.869, 7.274, 63.554);
VAR
  POSE: grip;
BEGIN
  MOVE holder PTP h AND welder PTP v;
  grip := INV(holder.R_ACT_POSE) : welder.R_ACT_POSE;
  COOPERATE welder IN holder WITH VERTICAL;
    MOVE welder LIN grip : (-200, 100, 0, 0, 0, 0) WITH SPEED := 50;
  COOPERATEEND;
ENDPROGRAM
"""


def _two_robots(clearance: int) -> str:
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "programs" / "two_robots.irl").read_text()
    text = text.replace("R_CLEARANCE := 50;", f"R_CLEARANCE := {clearance};")
    cut = text.index("  MOVE floor LIN f_a WITH SPEED := 100;")
    return text[:cut] + "ENDPROGRAM\n"


CASES = [
    ("one AS arm, 150 mm LIN (one robot)", ONE),
    ("the same LIN in a cell, a second AS arm holds", HOLDS),
    ("a group move: two AS arms' LINs in lock-step", GROUP),
    ("COOPERATE: the welder's 600 mm seam, 12 joints", COOPERATE),
    ("COOPERATE WITH VERTICAL (6 + 2 rows)", VERTICAL),
    ("two_robots.irl's Panda line, R_CLEARANCE := 0", _two_robots(0)),
    ("two_robots.irl's Panda line, R_CLEARANCE := 50 (rows bind)", _two_robots(50)),
]


def _measure(text: str, repeat: int) -> tuple[float, int, float]:
    """``(best CPU µs per recorded IPO cycle, samples, simulated s)`` of the run."""
    code = compile_source(text, "b.irl", resolve_robot=load_robot).code
    best, samples, duration = np.inf, 0, 0.0
    for rep in range(repeat + 1):
        c0 = time.process_time()
        run = run_code(code)
        cpu = time.process_time() - c0
        if not run.ok:
            raise RuntimeError(f"{run.error}")
        samples, duration = run.report["samples"], run.report["duration_s"]
        if rep:
            best = min(best, cpu / samples * 1e6)
    return best, samples, duration


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    print(f"python {platform.python_version()}, numpy {np.__version__}, {platform.machine()}, "
          f"IRLC_ENGINE={os.environ.get('IRLC_ENGINE', '(unset)')}")  # fmt: skip
    print(f"load average {' '.join(f'{x:.2f}' for x in os.getloadavg())}\n")
    print("| case | samples | simulated s | CPU per IPO cycle µs | real time / CPU |")
    print("|---|---:|---:|---:|---:|")
    for name, text in CASES:
        us, samples, duration = _measure(text, args.repeat)
        factor = duration / (us * samples * 1e-6)
        print(f"| {name} | {samples} | {duration:.2f} | {us:.0f} | {factor:.0f}× |")


if __name__ == "__main__":
    main()
