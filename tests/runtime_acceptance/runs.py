"""Run the acceptance programs through the user's CLI and read back report + trace.

Each program runs once per session as `irlc run PROG --report r.json --trace t.csv`
(a subprocess: exactly what a user or a CI script sees). Runs are cached and started
two at a time in the background.
"""

from __future__ import annotations

import csv
import json
import shutil
import subprocess
import sys
import tempfile
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
PROGRAMS = HERE / "programs"
FAILING = HERE / "failing"
OUT = Path(tempfile.mkdtemp(prefix="irlc_acceptance_"))


def irlc_command() -> list[str]:
    """The installed console script next to the running interpreter."""
    local = Path(sys.executable).with_name("irlc")
    return [str(local)] if local.exists() else [shutil.which("irlc") or "irlc"]


@dataclass
class Run:
    """One finished run: exit code, report, trace columns, source lines."""

    name: str
    rc: int
    stdout: str
    stderr: str
    report: dict | None
    header: list[str] = field(default_factory=list)
    cols: dict[str, np.ndarray] = field(default_factory=dict)
    source: list[str] = field(default_factory=list)

    @property
    def n_rows(self) -> int:
        return len(self.cols.get("t_s", ()))

    def line_of(self, text: str, nth: int = 0) -> int:
        """1-based line number of the nth source line containing text."""
        hits = [i + 1 for i, s in enumerate(self.source) if text in s]
        assert len(hits) > nth, f"{text!r} not in {self.name}"
        return hits[nth]

    def runs_of(self, line: int) -> list[np.ndarray]:
        """Index arrays of the contiguous groups of trace rows labelled with `line`."""
        idx = np.flatnonzero(self.cols["line"] == line)
        if idx.size == 0:
            return []
        breaks = np.flatnonzero(np.diff(idx) > 1) + 1
        return np.split(idx, breaks)

    def joints(self, joint_cols: list[str]) -> np.ndarray:
        return np.column_stack([self.cols[c] for c in joint_cols])


def _execute(path: Path) -> Run:
    name = path.stem
    report, trace = OUT / f"{name}.json", OUT / f"{name}.csv"
    cmd = [*irlc_command(), "run", path.name, "--report", str(report), "--trace", str(trace)]
    cmd += ["--quiet", "--datalist-path", str(PROGRAMS)]
    proc = subprocess.run(cmd, cwd=path.parent, capture_output=True, text=True, timeout=300)
    run = Run(name, proc.returncode, proc.stdout, proc.stderr, None)
    run.source = path.read_text().splitlines()
    if report.exists():
        run.report = json.loads(report.read_text())
    if trace.exists():
        with trace.open(newline="") as fh:
            rows = list(csv.reader(fh))
        run.header = rows[0]
        data = np.array(rows[1:], dtype=float).reshape(len(rows) - 1, len(run.header))
        run.cols = {h: data[:, i] for i, h in enumerate(run.header)}
    return run


_POOL = ThreadPoolExecutor(max_workers=2)
_FUTURES: dict[Path, Future] = {}


def start_all() -> None:
    """Queue every program (cheap to call repeatedly)."""
    for path in sorted(PROGRAMS.glob("*.irl")) + sorted(FAILING.glob("*.irl")):
        if path not in _FUTURES:
            _FUTURES[path] = _POOL.submit(_execute, path)


def get(name: str) -> Run:
    """The finished run of programs/NAME.irl or failing/NAME.irl."""
    start_all()
    for path, fut in _FUTURES.items():
        if path.stem == name:
            return fut.result()
    raise KeyError(name)
