"""Helpers of the user-tool acceptance checks: run `irlc` as a user would (a subprocess)."""

from __future__ import annotations

import csv
import json
import re
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

# koch11's home (its start configuration; robots/koch11.toml)
KONF_0 = (-0.695, -75, -102, 115.205, -98.722, -76.097, -0.168, -21.813, -90.452, 227.313, 21.119)
KONF_0_TEXT = ", ".join(str(v) for v in KONF_0)
ANSI = re.compile(r"\x1b\[")
NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"


@dataclass
class Result:
    rc: int
    out: str
    err: str

    @property
    def both(self) -> str:
        return self.out + self.err


def irlc_command() -> list[str]:
    script = Path(sys.executable).with_name("irlc")
    if script.exists():
        return [str(script)]
    found = shutil.which("irlc")
    return [found] if found else [sys.executable, "-c", "from irlc.cli import entry; entry()"]


def irlc(*args: str | Path, stdin: str | None = None, cwd: Path | None = None) -> Result:
    """Run `irlc ARGS` with stdin from a pipe (never a terminal), capture both streams."""
    proc = subprocess.run(
        [*irlc_command(), *map(str, args)],
        input=stdin if stdin is not None else "",
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=120,
        env=_env(),
    )
    return Result(proc.returncode, proc.stdout, proc.stderr)


def _env() -> dict[str, str]:
    import os

    env = dict(os.environ)
    env.pop("FORCE_COLOR", None)
    env["COLUMNS"] = "160"  # wide tables: no wrapped numbers
    return env


def repl(script: str, robot: str = "koch11", cwd: Path | None = None) -> Result:
    return irlc("repl", "--robot", robot, stdin=script, cwd=cwd)


def assert_clean(result: Result) -> None:
    """No traceback and no terminal escapes in plain (piped) mode."""
    assert "Traceback" not in result.both, result.both
    assert not ANSI.search(result.out), repr(result.out[:400])


def fk_pose(robot: str, joints) -> list[float]:
    """Pose (mm, deg ZYX) of `joints` from `irlc fk --json` (the independent FK path)."""
    res = irlc("fk", robot, *[repr(float(v)) for v in joints], "--json")
    assert res.rc == 0, res.both
    return json.loads(res.out)["pose"]


def pose_lines(text: str) -> list[list[float]]:
    """Every `pose (x, y, z, a, b, c)` printed in `text`."""
    found = []
    for m in re.finditer(r"pose\s*[:=]?\s*\(([^)]*)\)", text):
        nums = [float(v) for v in re.findall(NUMBER, m.group(1))]
        if len(nums) == 6:
            found.append(nums)
    return found


def joint_lines(text: str, names: list[str]) -> list[list[float]]:
    """Every printed joint vector `a1=… a2=… …` (all of `names` on one line)."""
    found = []
    for line in text.splitlines():
        values = {}
        for m in re.finditer(rf"\b(\w+)\s*=\s*({NUMBER})", line):
            values[m.group(1).lower()] = float(m.group(2))
        if all(n.lower() in values for n in names):
            found.append([values[n.lower()] for n in names])
    return found


def read_trace(path: Path) -> tuple[list[str], list[list[float]]]:
    with path.open(newline="") as fh:
        rows = list(csv.reader(fh))
    header = [h.strip() for h in rows[0]]
    return header, [[float(v) for v in r] for r in rows[1:] if r]


def angle_diff(a: float, b: float) -> float:
    return (a - b + 180.0) % 360.0 - 180.0
