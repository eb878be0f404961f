"""Cycle time with approximate positioning against exact stops (kinematic runs).

Each case is a program of programs/ run twice: as written with an ``R_APPROX`` (mm)
and with ``R_APPROX := 0`` (every point an exact stop). Reported: both durations, the
time saved, and per approximated point the distance actually used (the report's
``approximations``). Cases:

* the chapter-6 square on koch11 (programs/square.irl) with ``R_APPROX := 100``
  inserted after ``R_ACC`` (its corner poz_2 → poz_3 → poz_4 has an orientation-only
  side of length 0, so those two points stay exact stops: APPROX is a TCP distance);
* the pick-and-place cycle on the Panda (programs/pick_place.irl, ``R_APPROX := 40``).

Usage::

    python bench/bench_blend.py [--json]
"""

from __future__ import annotations

import argparse
import json
import re
import tempfile
from pathlib import Path

from irlc.runtime.run import run_file

PROGRAMS = Path(__file__).resolve().parents[1] / "programs"
CASES = [
    ("square.irl", "koch11 chapter-6 square", 100.0),
    ("pick_place.irl", "panda pick and place", 40.0),
]
_APPROX = re.compile(r"R_APPROX := [0-9.]+;")


def variant(text: str, approx: float) -> str:
    """The program with ``R_APPROX := approx`` (replacing its own, or after R_ACC)."""
    line = f"R_APPROX := {approx:g};"
    if _APPROX.search(text):
        return _APPROX.sub(line, text, count=1)
    return re.sub(r"(R_ACC := [0-9.]+;)", r"\1\n  " + line, text, count=1)


def run_case(name: str, approx: float, folder: Path) -> dict:
    text = (PROGRAMS / name).read_text(encoding="utf-8")
    out = {}
    for label, value in (("exact", 0.0), ("approx", approx)):
        path = folder / f"{label}_{name}"
        path.write_text(variant(text, value), encoding="utf-8")
        run = run_file(path, datalist_path=[PROGRAMS])
        if run.status != "ok":
            raise SystemExit(f"{name} ({label}): {run.error}")
        out[label] = run.report
    exact, blended = out["exact"]["duration_s"], out["approx"]["duration_s"]
    points = out["approx"]["approximations"]
    return {
        "program": name,
        "approx_mm": approx,
        "exact_stop_s": exact,
        "approximated_s": blended,
        "saved_s": round(exact - blended, 9),
        "saved_percent": round(100.0 * (exact - blended) / exact, 3),
        "points": [
            {
                "line": p["line"],
                "point": p["point"],
                "used_mm": p["used_mm"],
                "min_speed_mm_s": p["min_speed_mm_s"],
                "note": p["note"],
            }
            for p in points
        ],
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", action="store_true", help="print the results as JSON")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        results = [run_case(name, approx, Path(tmp)) for name, _, approx in CASES]
    if args.json:
        print(json.dumps({"units": {"time": "s", "length": "mm"}, "cases": results}, indent=2))
        return
    for (_, title, _), r in zip(CASES, results, strict=True):
        print(f"{title} ({r['program']}), R_APPROX := {r['approx_mm']:g} mm")
        print(f"  exact stops   {r['exact_stop_s']:8.3f} s")
        print(f"  approximated  {r['approximated_s']:8.3f} s  "
              f"(−{r['saved_s']:.3f} s, −{r['saved_percent']:.1f} %)")  # fmt: skip
        for p in r["points"]:
            what = f"used {p['used_mm']:7.2f} mm, min speed {p['min_speed_mm_s']:7.1f} mm/s"
            if p["note"]:
                what += f"  ({p['note']})"
            print(f"    line {p['line']:3d} point {p['point']}: {what}")


if __name__ == "__main__":
    main()
