"""Run the benchmarks that write JSON and merge their documents into one file, so that a
later change can be compared figure by figure (``bench/bench_json.py`` has the shape).

    python bench/run_all.py --json all.json [--quick]

``--quick``: whole programs best of 1, lengths 1× and 10× only (≈ 2 min on an idle
2-core machine; the full set, with the 1-hour program, ≈ 10 min). The merged file is
``{"benchmarks": {name: document, …}}``; each script's table is printed as it runs.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent


def plan(quick: bool) -> dict[str, list[str]]:
    """Script name → its arguments (before ``--json``)."""
    repeat = "1" if quick else "3"
    scales = ["1", "10"] if quick else ["1", "10", "100"]
    return {
        "first_run": ["bench_first_run.py"],
        "run": ["bench_run.py", "--repeat", repeat, "--split", "--engine", "numpy", "compiled"],
        "length": ["bench_length.py", "--scales", *scales],
    }


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--json", type=Path, required=True, help="the merged JSON file")
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    merged: dict[str, dict] = {}
    with tempfile.TemporaryDirectory(prefix="irlc-bench-") as tmp:
        for name, cmd in plan(args.quick).items():
            out = Path(tmp) / f"{name}.json"
            print(f"\n## {name}: python bench/{' '.join(cmd)}", flush=True)
            subprocess.run([sys.executable, str(HERE / cmd[0]), *cmd[1:], "--json", str(out)],
                           check=True)  # fmt: skip
            merged[name] = json.loads(out.read_text(encoding="utf-8"))
    text = json.dumps({"benchmarks": merged}, indent=2, ensure_ascii=False) + "\n"
    args.json.write_text(text, encoding="utf-8")


if __name__ == "__main__":
    main()
