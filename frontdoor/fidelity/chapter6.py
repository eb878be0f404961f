"""Chapter 6 of the seed monograph on koch11: the observations O1–O18 (docs/robots.md), the
tick ranges that survive in the scan's figures, and the search for O8/O9.

Every number is read from the trace of a run of a ``programs/`` chapter-6 program: joint
columns, speed and acceleration columns (program units: deg, mm). A bound is *active*
when the trace sits on it to :data:`BOUND_TOL` (the QP holds an active bound exactly).
"""

from __future__ import annotations

import dataclasses
import functools
import itertools
import tempfile
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from irlc.robots import DATALISTS_DIR, load_robot
from irlc.runtime import units
from irlc.runtime.run import run_file

PROGRAMS = Path(__file__).resolve().parents[2] / "programs"
BOUND_TOL = 0.01  # deg | mm | deg/s: the golden files' quantum

# The limit sets of the chapter (program units), from the robot library's data list.
SETS = {
    k: np.array(v["values"], dtype=float)
    for k, v in tomllib.loads((DATALISTS_DIR / "koch11_ch6.toml").read_text("utf-8"))[
        "limits"
    ].items()
}

# Tick ranges that survive in the scan (deg). Fig. 6.20 (the FREEZE run, joints 1–6): the
# OCR keeps the left column's axes (J1, J3, J5: the issue's reading) and the right column's
# (J2, J4, J6, in the column's order, read here). Fig. 6.24: the 5 m line, time 0…6 s,
# path 0…6 m, speed 0…1.5 m/s.
FIG_6_20 = {
    1: (-50.0, 50.0),
    2: (-100.0, -10.0),
    3: (-120.0, -20.0),
    4: (60.0, 160.0),
    5: (-100.0, 0.0),
    6: (-100.0, -10.0),
}
FIG_6_20_ISSUE = (1, 3, 5)  # the ranges the issue quotes; the others are read from the OCR
FIG_6_24 = {"time_s": (0.0, 6.0), "path_m": (0.0, 6.0), "speed_m_s": (0.0, 1.5)}


@functools.cache
def run(
    program: str,
    robot: str = "koch11",
    w10_factor: float = 1.0,
    edits: tuple = (),
    allow_collisions: bool = False,
):
    """A chapter-6 program's run (cached): ``w10_factor`` scales joint 10's weight (the
    book's 4× of 6.3), ``edits`` are ``(old, new)`` text replacements of the program;
    ``allow_collisions``: the whole motion through an obstacle (by default the run fails
    at the first penetration)."""
    model = load_robot(robot)
    if w10_factor != 1.0:
        joints = list(model.joints)
        joints[9] = dataclasses.replace(joints[9], weight=joints[9].weight * w10_factor)
        model = dataclasses.replace(model, joints=tuple(joints))
    path = PROGRAMS / f"{program}.irl"
    if not edits:
        return run_file(path, robot=model, allow_collisions=allow_collisions)
    text = path.read_text("utf-8")
    for old, new in edits:
        text = text.replace(old, new)
    with tempfile.TemporaryDirectory() as folder:
        edited = Path(folder) / path.name
        edited.write_text(text, "utf-8")
        return run_file(
            edited, robot=model, datalist_path=[PROGRAMS], allow_collisions=allow_collisions
        )


def block(result, pattern: str) -> np.ndarray:
    """Trace columns ``pattern.format(name, unit)`` of every joint (program units)."""
    cols = [
        pattern.format(n, units.joint_unit(k))
        for n, k in zip(result.joint_names, result.model.joint_kinds, strict=True)
    ]
    return result.trace[:, [result.trace_columns.index(c) for c in cols]]


def joints(result) -> np.ndarray:
    return block(result, "{}_{}")


def speeds(result) -> np.ndarray:
    return block(result, "{}_speed_{}_s")


def accels(result) -> np.ndarray:
    return block(result, "{}_accel_{}_s2")


def active(values: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> set[tuple[int, str]]:
    """(joint number, ``"min"`` | ``"max"``) of every bound the trace touches."""
    out = set()
    for j in range(values.shape[1]):
        if values[:, j].min() <= lo[j] + BOUND_TOL:
            out.add((j + 1, "min"))
        if values[:, j].max() >= hi[j] - BOUND_TOL:
            out.add((j + 1, "max"))
    return out


def describe(bounds: set[tuple[int, str]]) -> str:
    """``J11 max, J10 min`` (joint order) or ``none``."""
    return ", ".join(f"J{j} {side}" for j, side in sorted(bounds)) or "none"


def change_ranking(a: str, b: str) -> tuple[list[int], np.ndarray]:
    """Joints 1–9 ordered by the largest change of their trajectory between two runs."""
    qa, qb = joints(run(a)), joints(run(b))
    n = min(len(qa), len(qb))
    change = np.abs(qa[:n] - qb[:n]).max(axis=0)
    return [int(j) + 1 for j in np.argsort(-change[:9], kind="stable")], change


def peak_accels(program: str, **kw) -> np.ndarray:
    return np.abs(accels(run(program, **kw))).max(axis=0)


def tcp_path_speed(result) -> tuple[np.ndarray, np.ndarray]:
    """The TCP's path length (m, from the start) and speed (m/s) at the trace's samples."""
    cols = [result.trace_columns.index(c) for c in ("x_mm", "y_mm", "z_mm")]
    p = result.trace[:, cols] / 1e3
    step = np.linalg.norm(np.diff(p, axis=0), axis=1)
    t = result.times
    speed = np.concatenate([[0.0], step / np.diff(t)])
    return np.concatenate([[0.0], np.cumsum(step)]), speed


def freeze_ranges() -> np.ndarray:
    """(6, 2): min and max of joints 1–6 in the FREEZE run (fig. 6.20's run), deg."""
    q = joints(run("square_freeze"))[:, :6]
    return np.stack([q.min(axis=0), q.max(axis=0)], axis=1)


# ----------------------------------------------------------------------------- O8 / O9


@dataclass(frozen=True)
class TimingCase:
    """One path timing of the square: without set 6.3 (``base`` peaks, deg/s² | mm/s²) and
    with it (``ok``: the run follows the path; ``limited`` peaks)."""

    acc: float
    speed_ori: float
    speed: float
    duration: float
    base: np.ndarray
    ok: bool
    limited: np.ndarray


ACC_GRID = (2000.0, 3000.0, 4000.0, 6000.0, 8000.0, 12000.0)
SPEED_ORI_GRID = (50.0, 100.0, 150.0, 200.0, 300.0)
SPEED_GRID = (500.0, 700.0, 1000.0)


def timing_case(acc: float, speed_ori: float, speed: float) -> TimingCase:
    edits = (
        ("R_SPEED := 1000;", f"R_SPEED := {speed:g};"),
        ("R_ACC := 2000;", f"R_ACC := {acc:g};"),
        ("R_SPEED_ORI := 50;", f"R_SPEED_ORI := {speed_ori:g};"),
    )
    base = run("square_limits", edits=edits)
    limited = run("square_accel", edits=edits)
    return TimingCase(
        acc, speed_ori, speed, float(base.times[-1]),
        np.abs(accels(base)).max(axis=0), limited.ok, np.abs(accels(limited)).max(axis=0),
    )  # fmt: skip


@dataclass(frozen=True)
class O8Search:
    """The timings tried; ``j7_above``: those where J7 peaks above its 6.3 bound without
    the set; ``book_like``: of those, the ones where the set-6.3 run follows the path with
    J7 cut to 350 and J10 gaining most (the book's O8 and O9); ``j11_over_j7``: the
    smallest ratio of J11's to J7's peak among ``j7_above``."""

    cases: list[TimingCase]
    j7_above: list[TimingCase]
    book_like: list[TimingCase]
    j11_over_j7: float


def _book_like(c: TimingCase) -> bool:
    rise = (c.limited - c.base) / np.maximum(c.base, 1e-9)
    return c.ok and c.limited[6] <= 350.0 + BOUND_TOL and int(np.argmax(rise)) == 9


@functools.cache
def o8_search() -> O8Search:
    """The square's path timing over :data:`ACC_GRID` × :data:`SPEED_ORI_GRID` ×
    :data:`SPEED_GRID` (R_ACC, R_SPEED_ORI, R_SPEED) from konf_0."""
    cases = [timing_case(*g) for g in itertools.product(ACC_GRID, SPEED_ORI_GRID, SPEED_GRID)]
    above = [c for c in cases if c.base[6] > 350.0]
    ratio = min((c.base[10] / c.base[6] for c in above), default=float("nan"))
    return O8Search(cases, above, [c for c in above if _book_like(c)], ratio)
