"""The machine-readable output of the benchmarks (``--json FILE``): one JSON object per
run of a benchmark, so that later changes can be compared figure by figure.

Shape (keys in this order; units in the key names)::

    {"benchmark": "run", "command": "python bench/bench_run.py --repeat 3 …",
     "git_commit": "0661ffb…", "python": "3.11.7", "machine": "x86_64", "cpus": 2,
     "load_average_1min": [1.2, 1.4],   # before and after the measurement
     "engine": "numpy", "settings": {…}, "rows": [{…}, …]}

``rows`` holds one object per table row, with the same figures as the printed table.
"""

from __future__ import annotations

import json
import os
import platform
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def git_commit() -> str | None:
    """The repository's HEAD commit (``None`` outside a git checkout)."""
    try:
        out = subprocess.run(
            ["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True, text=True, check=True
        )
    except (OSError, subprocess.CalledProcessError):
        return None
    return out.stdout.strip() or None


def load_average() -> float | None:
    """The 1-minute load average (``None`` where the OS has none)."""
    try:
        return round(os.getloadavg()[0], 2)
    except (AttributeError, OSError):
        return None


class Recorder:
    """Collects a benchmark's rows; :meth:`write` saves them with the run's context."""

    def __init__(self, benchmark: str, engine: str | None = None, **settings):
        self.benchmark, self.engine, self.settings = benchmark, engine, settings
        self.rows: list[dict] = []
        self._load_before = load_average()

    def add(self, **row) -> dict:
        self.rows.append(row)
        return row

    def document(self) -> dict:
        return {
            "benchmark": self.benchmark,
            "command": " ".join(["python", *sys.argv]),
            "git_commit": git_commit(),
            "python": platform.python_version(),
            "machine": platform.machine(),
            "cpus": os.cpu_count(),
            "load_average_1min": [self._load_before, load_average()],
            "engine": self.engine,
            "settings": self.settings,
            "rows": self.rows,
        }

    def write(self, path: str | Path | None) -> None:
        """Write the JSON document to ``path`` (nothing when ``None``)."""
        if path is not None:
            text = json.dumps(self.document(), indent=2, ensure_ascii=False) + "\n"
            Path(path).write_text(text, encoding="utf-8")
