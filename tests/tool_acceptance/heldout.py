"""The held-out program of the acceptance checks (planar3, own data list, limit + obstacle)."""

from __future__ import annotations

from pathlib import Path

CELL = """\
# held-out cell for the tool acceptance checks (mm, deg)
[poses]
p_home = [2000, 1000, 0, 0, 0, 0]
p_a = [1500, 1400, 0, 0, 0, 0]
p_b = [1100, 700, 0, 0, 0, 0]
p_c = [1800, 300, 0, 0, 0, 0]

[joints]
start = [0, 90, -90]

[obstacles.post]
kind = "sphere"
center = [250, 1000, 0]
radius = 120
"""

PROGRAM = """\
PROGRAM acc_tri;
{ held-out: a triangle with joint limits and an obstacle on planar3 }
ROBOT r := planar3;
IMPORT DATALIST acc_cell;
VAR
  MAIN_JOINT_MIN: jmin;
  MAIN_JOINT_MAX: jmax;
BEGIN
  jmin := (-40, 0, -175);
  jmax := (70, 170, 10);
  R_SPEED := 600;
  R_ACC := 1500;
  MOVE PTP start;
  JOINTLIMIT jmin, jmax;
  OBSTACLE post;
  MOVE LIN p_a;
  MOVE LIN p_b;
  MOVE LIN p_c;
  MOVE LIN p_home;
  OBSTACLEEND post;
  JOINTLIMITEND;
  WRITELN('triangle done');
ENDPROGRAM
"""

JMIN = (-40, 0, -175)
JMAX = (70, 170, 10)
OBSTACLE_CENTER = (250, 1000, 0)
OBSTACLE_RADIUS = 120


def write_heldout(folder: Path, name: str = "acc_tri", free: bool = False) -> Path:
    """Write the program (free=True: without JOINTLIMIT/OBSTACLE, the twin) and its cell."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "acc_cell.toml").write_text(CELL)
    text = PROGRAM.replace("PROGRAM acc_tri;", f"PROGRAM {name};")
    if free:
        drop = ("JOINTLIMIT", "OBSTACLE")
        text = "\n".join(ln for ln in text.splitlines() if not ln.strip().startswith(drop)) + "\n"
    path = folder / f"{name}.irl"
    path.write_text(text)
    return path
