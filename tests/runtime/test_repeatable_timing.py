"""Segment durations do not depend on round-off (plan_start.py): one lap of the koch11
square with and without CYCLIC takes the same number of samples, and every LIN takes the
closed-form trapezoid time of its *programmed* length rounded up to whole IPO cycles.

The square's sides are 2 m at 1000 mm/s and 2000 mm/s²: T = L/v + v/a = 2.5 s exactly,
a whole number of 10 ms cycles — the case where a 1e-9 m IK residual at the start added
a cycle (2.51 s) with CYCLIC and not without."""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import numpy as np
import pytest
from irlc.runtime.model import spatial
from irlc.runtime.run import run_file

PROGRAMS = Path(__file__).resolve().parents[2] / "programs"

_LAP = """PROGRAM lap;
ROBOT r := koch11;
IMPORT DATALIST square_cell;
IMPORT DATALIST koch11_ch6;
BEGIN
  R_SPEED := 1000;
  R_ACC := 2000;
  R_SPEED_ORI := 50;
  MOVE PTP konf_0;
  JOINTLIMIT jmin_base, jmax_base;
  {start}
  MOVE LIN poz_1;
  MOVE LIN poz_2;
  MOVE LIN poz_3;
  MOVE LIN poz_4;
  MOVE LIN poz_0;
  {end}
  JOINTLIMITEND;
ENDPROGRAM
"""

# the taught points of programs/square_cell.toml (mm, deg ZYX), in the program's order
_POINTS = [
    (11500, 1000, 3500, 0, 0, 0),
    (9500, 1000, 3500, 0, 0, 0),
    (9500, -1000, 3500, -85, 0, 0),
    (9500, -1000, 3500, 0, 85, 0),
    (11500, -1000, 3500, 0, 0, 0),
    (11500, 1000, 3500, 0, 0, 0),
]


def _trapezoid_time(length: float, v: float, a: float) -> float:
    """Time-optimal rest-to-rest time over ``length`` (closed form, independent)."""
    if length == 0.0:
        return 0.0
    if length >= v * v / a:
        return length / v + v / a
    return 2.0 * math.sqrt(length / a)


def _expected_durations(dt: float, k: float = 1.0) -> list[float]:
    """Each side: the larger of the position and orientation trapezoid times (orientation
    acceleration R_SPEED_ORI·R_ACC/R_SPEED) at override ``k`` (speeds ×k, accelerations
    ×k²), rounded up to whole cycles."""
    out = []
    for p, q in itertools.pairwise(_POINTS):
        length = math.dist(p[:3], q[:3])
        r0 = spatial.zyx_to_matrix(*np.radians(p[3:]))
        r1 = spatial.zyx_to_matrix(*np.radians(q[3:]))
        angle = math.degrees(np.linalg.norm(spatial.rotation_vector(r0.T @ r1)))
        v, a, w, wa = 1000.0 * k, 2000.0 * k * k, 50.0 * k, 100.0 * k * k
        t = max(_trapezoid_time(length, v, a), _trapezoid_time(angle, w, wa))
        out.append(math.ceil(t / dt - 1e-9) * dt)
    return out


def _run(tmp_path: Path, cyclic: bool, override: float = 100.0):
    name = "lap_cyclic.irl" if cyclic else "lap.irl"
    start, end = ("CYCLICSTART;", "CYCLICEND;") if cyclic else ("", "")
    src = tmp_path / name
    src.write_text(_LAP.format(start=start, end=end))
    run = run_file(src, datalist_path=[PROGRAMS], override=override)
    assert run.status == "ok", run.error
    return run


@pytest.mark.scenario
def test_a_lap_takes_the_same_samples_with_and_without_cyclic(tmp_path):
    with_cyclic, without = _run(tmp_path, True), _run(tmp_path, False)
    assert with_cyclic.report["samples"] == without.report["samples"]
    dt = 0.01
    expected = _expected_durations(dt)
    assert expected[0] == pytest.approx(2.5, abs=1e-12)  # the whole-cycle case
    for run in (with_cyclic, without):
        lins = [s for s in run.report["statements"] if s["kind"] == "MOVE LIN"]
        got = [s["duration_s"] for s in lins]
        assert got == pytest.approx(expected, abs=1e-9)


@pytest.mark.scenario
def test_at_half_override_every_side_takes_its_closed_form_time(tmp_path):
    """R_OVERRIDE 50 %: T/k = 5.0 s for a side, not 5.01 s."""
    run = _run(tmp_path, True, override=50.0)
    lins = [s for s in run.report["statements"] if s["kind"] == "MOVE LIN"]
    expected = _expected_durations(0.01, 0.5)
    assert expected[0] == pytest.approx(5.0, abs=1e-12)
    assert [s["duration_s"] for s in lins] == pytest.approx(expected, abs=1e-9)


def test_only_a_residual_sized_offset_snaps_to_the_programmed_point():
    """1e-9 m (the IK's residual): plan from the programmed point; 5 µm (a real offset, a
    relaxed stop within R_PATH_TOL): from the actual pose, no jump back; a rotation
    offset counts only where the task controls orientation."""
    from irlc.runtime.plan.plan_start import planning_start

    programmed = spatial.transform(spatial.rot_z(0.3), (1.0, 0.5, 0.2))
    near = programmed.copy()
    near[:3, 3] += 1e-9
    far = programmed.copy()
    far[:3, 3] += 5e-6
    turned = programmed @ spatial.transform(spatial.rot_z(1e-3))
    rows6, rows_xy = (0, 1, 2, 3, 4, 5), (0, 1)
    tol = (1e-6, 1e-6)
    assert np.array_equal(planning_start(near, programmed, rows6, *tol), programmed)
    assert np.array_equal(planning_start(far, programmed, rows6, *tol), far)
    assert np.array_equal(planning_start(turned, programmed, rows6, *tol), turned)
    assert np.array_equal(planning_start(turned, programmed, rows_xy, *tol), programmed)
    assert np.array_equal(planning_start(near, None, rows6, *tol), near)
