"""Approximate positioning (WITH APPROX / R_APPROX), checked from the report and the trace
against closed forms (runtime/plan/blending.py, docs/language.md "Approximate positioning").

The LIN corner: two 200 mm sides at R_SPEED 250 mm/s, R_ACC 1000 mm/s² take exactly
1.05 s each (ramps 0.25 s over 31.25 mm), so for APPROX d ≤ 31.25 mm the blend lies in
both ramps: it lasts T = ⌊√(2d/a)/Δt⌋·Δt, starts a·T²/2 before the corner on side A and
rejoins side B a·T²/2 after it; half-way both offsets are a·T²/8 (perpendicular sides:
distance √2·a·T²/8 from the corner) and the speed is a·T/√2 (v_A ⊥ v_B, each a·T/2).
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
from irlc.lang.diagnostics import CompileError
from irlc.runtime.plan.blending import choose_overlap, limit_distance, tail_cycles
from irlc.runtime.run import run_file

PROGRAMS = Path(__file__).resolve().parents[2] / "programs"

CORNER = """PROGRAM corner;
ROBOT r := panda;
BEGIN
  R_SPEED := 250;
  R_ACC := 1000;
  MOVE PTP (0, -30, 0, -120, 0, 90, 45);
  MOVE LIN POSE(400, -100, 500, 0, 0, 180);
  MOVE LIN POSE(400, 100, 500, 0, 0, 180){approx};
  MOVE LIN POSE({x2}, 100, 500, 0, 0, 180);
ENDPROGRAM
"""
A = 1000.0  # mm/s²
DT = 0.01


def _run(tmp_path: Path, text: str, name: str = "p", **kw):
    path = tmp_path / f"{name}.irl"
    path.write_text(text, encoding="utf-8")
    run = run_file(path, **kw)
    assert run.status == "ok", run.error
    return run


def _corner(tmp_path, approx: float | None, x2: float = 600.0):
    clause = "" if approx is None else f" WITH APPROX := {approx:g}"
    return _run(tmp_path, CORNER.format(approx=clause, x2=f"{x2:g}"), "corner")


def _positions_mm(run) -> np.ndarray:
    return run.recorded.tcp[:, :3, 3] * 1000.0


@pytest.fixture(scope="module")
def exact_and_blended(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("blend")
    return _corner(tmp, None), _corner(tmp, 20.0)


def test_corner_blend_closed_form(exact_and_blended):
    exact, blended = exact_and_blended
    (entry,) = [e for e in blended.report["approximations"] if e["line"] == 8]
    cycles = math.floor(math.sqrt(2 * 20.0 / A) / DT + 1e-9)
    t_blend = cycles * DT
    assert entry["blended"] and entry["cycles"] == cycles == 20
    assert entry["approx_mm"] == 20.0 and entry["limit_mm"] == 20.0
    assert entry["used_mm"] == pytest.approx(A * t_blend**2 / 2, abs=1e-6)
    # the blend saves its overlap: cycle time shorter by T
    assert exact.report["duration_s"] - blended.report["duration_s"] == pytest.approx(t_blend)
    assert entry["saved_s"] == pytest.approx(t_blend)
    # closest point to the corner half-way: offsets a·T²/8 along −y and +x
    p = _positions_mm(blended)
    corner = np.array([400.0, 100.0, 500.0])
    dist = np.linalg.norm(p - corner, axis=1)
    k = int(np.argmin(dist))
    half = A * t_blend**2 / 8
    assert dist[k] == pytest.approx(math.sqrt(2) * half, abs=1e-3)
    np.testing.assert_allclose(p[k], corner + np.array([half, -half, 0.0]), atol=1e-3)
    # speed there a·T/√2 (not zero)
    t = blended.recorded.times
    speed = np.linalg.norm(np.diff(p, axis=0), axis=1) / np.diff(t)
    around = speed[k - 3 : k + 3]
    assert around.min() > 0.9 * A * t_blend / math.sqrt(2)
    assert entry["min_speed_mm_s"] == pytest.approx(A * t_blend / math.sqrt(2), rel=0.02)
    # the exact run stops at the corner: its speed there drops to zero
    pe = _positions_mm(exact)
    ke = int(np.argmin(np.linalg.norm(pe - corner, axis=1)))
    assert np.linalg.norm(pe[ke] - corner) < 1e-6
    # the whole run stays within APPROX of the programmed polyline's corner region
    near = dist < 25.0
    assert dist[near].min() < 20.0  # the blend passes inside the corner...
    off_path = (p[:, 0] > 400.0 + 1e-6) & (p[:, 1] < 100.0 - 1e-6)
    assert off_path.any() and dist[off_path].max() <= 20.0 + 1e-6  # ...within APPROX


def test_blend_is_commanded_path_and_final_point_exact(exact_and_blended):
    _, blended = exact_and_blended
    rec = blended.recorded
    # the blended corner is the commanded path: the path error stays at the IK's level
    assert blended.report["max_path_error_mm"] < 1e-3
    assert rec.on_path[-30:].all()
    # the last point of the run of approximated moves is reached exactly
    np.testing.assert_allclose(_positions_mm(blended)[-1], [600.0, 100.0, 500.0], atol=1e-6)
    last = blended.report["approximations"]
    assert [e["line"] for e in last] == [8]


def test_blend_shrinks_on_a_short_segment(tmp_path):
    run = _corner(tmp_path, 50.0, x2=430.0)  # side B is 30 mm: at most 15 mm
    (entry,) = run.report["approximations"]
    assert entry["limit_mm"] == pytest.approx(15.0)
    assert entry["blended"] and 0.0 < entry["used_mm"] <= 15.0 + 1e-9
    assert entry["note"] == "shortened to half of a neighbouring segment"
    p = _positions_mm(run)
    dist = np.linalg.norm(p - [400.0, 100.0, 500.0], axis=1)
    inside = (p[:, 0] > 400.0 + 1e-6) & (p[:, 1] < 100.0 - 1e-6)
    assert dist[inside].max() <= 15.0 + 1e-6
    np.testing.assert_allclose(p[-1], [430.0, 100.0, 500.0], atol=1e-6)


def test_modal_r_approx_and_path_points(tmp_path):
    text = CORNER.replace(
        "  MOVE LIN POSE(400, -100", "  R_APPROX := 10;\n  MOVE LIN POSE(400, -100"
    )
    text = text.replace(
        "  MOVE LIN POSE({x2}, 100, 500, 0, 0, 180);",
        "  MOVE LIN PATH (POSE(600, 100, 500, 0, 0, 180), POSE(600, 0, 500, 0, 0, 180),"
        " POSE(500, 0, 500, 0, 0, 180)) WITH APPROX := 25;\n"
        "  MOVE LIN POSE(500, 0, 400, 0, 0, 180) WITH APPROX := 0;",
    )
    run = _run(tmp_path, text.format(approx="", x2=600))
    entries = run.report["approximations"]
    used = {(e["line"], e["point"]): e for e in entries}
    assert used[(9, 1)]["approx_mm"] == 10.0 and used[(9, 1)]["blended"]  # R_APPROX
    for point in (1, 2, 3):  # every point of the PATH, the last into the next LIN
        e = used[(10, point)]
        assert e["blended"] and e["used_mm"] <= 25.0 + 1e-9 and e["min_speed_mm_s"] > 0
    assert (11, 1) not in used  # APPROX := 0: exact stop, nothing to report
    np.testing.assert_allclose(_positions_mm(run)[-1], [500.0, 0.0, 400.0], atol=1e-6)


def test_circle_blends_with_lines(tmp_path):
    text = CORNER.format(approx=" WITH APPROX := 20", x2=600).replace(
        "  MOVE LIN POSE(600, 100, 500, 0, 0, 180);",
        "  MOVE CIRCLE POSE(450, 150, 500, 0, 0, 180), POSE(500, 100, 500, 0, 0, 180)"
        " WITH APPROX := 20;\n  MOVE LIN POSE(500, -50, 500, 0, 0, 180);",
    )
    run = _run(tmp_path, text)
    entries = {e["line"]: e for e in run.report["approximations"]}
    assert entries[8]["blended"] and entries[9]["blended"] and entries[9]["kind"] == "circle"
    for e in entries.values():
        assert e["max_distance_mm"] <= 20.0 + 1e-9 and e["min_speed_mm_s"] > 0.0


PTP = """PROGRAM ptps;
ROBOT r := panda;
BEGIN
  MOVE PTP (0, -30, 0, -120, 0, 90, 45);
  R_APPROX := {approx};
  MOVE PTP (30, -20, 0, -110, 0, 90, 45);
  MOVE PTP (30, 0, 0, -90, 0, 90, 45);
  MOVE PTP (0, -30, 0, -120, 0, 90, 45) WITH APPROX := 0;
ENDPROGRAM
"""


def test_ptp_blend_in_joint_space(tmp_path):
    exact = _run(tmp_path, PTP.format(approx=0), "e")
    blended = _run(tmp_path, PTP.format(approx=40), "b")
    entries = blended.report["approximations"]
    assert [e["line"] for e in entries] == [6, 7] and all(e["blended"] for e in entries)
    saved = sum(e["saved_s"] for e in entries)
    assert saved > 0.1
    assert exact.report["duration_s"] - blended.report["duration_s"] == pytest.approx(saved)
    # the joint limits (robot file) still hold: speeds and accelerations of the trace
    model = blended.model
    for j, row in enumerate(blended.report["joints"]):
        v_max = model.speed_limits[j, 1] * 180 / math.pi
        a_max = model.accel_limits[j, 1] * 180 / math.pi
        assert row["max_abs_speed"] <= v_max * (1 + 1e-6)
        assert row["max_abs_accel"] <= a_max * (1 + 1e-6)
    # within APPROX of each point (TCP, by forward kinematics of the trace)
    from irlc.runtime.model.kinematics import Kinematics

    kin = Kinematics(model)
    p = _positions_mm(blended)
    t = blended.recorded.times
    points = ([30, -20, 0, -110, 0, 90, 45], [30, 0, 0, -90, 0, 90, 45])
    for e, q in zip(entries, points, strict=True):
        corner = kin.tcp(np.radians(q))[:3, 3] * 1000.0
        d = np.linalg.norm(p - corner, axis=1)
        # the blend: from its start sample (on A, used_mm before the point) to B
        window = (t > e["start_s"] - 1e-9) & (t <= e["start_s"] + e["cycles"] * 0.01 + 1e-9)
        assert window.sum() == e["cycles"] + 1
        assert d[window].max() <= 40.0 + 1e-9 and d[window].max() == pytest.approx(
            e["max_distance_mm"], abs=1e-6
        )
        assert d.min() > 1.0  # the point itself is not visited: the corner is cut
    np.testing.assert_allclose(blended.report["end_joints"], [0, -30, 0, -120, 0, 90, 45],
                               atol=1e-9)  # fmt: skip


def test_advance_run_stops_end_the_approximation(tmp_path):
    text = CORNER.format(approx=" WITH APPROX := 20", x2=600).replace(
        "  MOVE LIN POSE(600", "  WAIT 0.1 SEC;\n  MOVE LIN POSE(600"
    )
    run = _run(tmp_path, text)
    (entry,) = run.report["approximations"]
    assert not entry["blended"] and entry["note"] == "WAIT at line 9"
    assert any("WAIT stops the advance run" in d.message for d in run.diagnostics)
    p = _positions_mm(run)
    assert np.linalg.norm(p - [400.0, 100.0, 500.0], axis=1).min() < 1e-6  # exact stop


MIXED = """PROGRAM mx;
ROBOT r := panda;
BEGIN
  R_SPEED := 250;
  MOVE PTP (0, -30, 0, -120, 0, 90, 45);
  R_APPROX := {approx};
  MOVE PTP (20, -20, 0, -110, 0, 90, 45);
  MOVE LIN POSE(450, 100, 500, 0, 0, 180);
  MOVE LIN POSE(450, -100, 500, 0, 0, 180);
  MOVE PTP (-10, -30, 0, -120, 0, 90, 45);
  MOVE CIRCLE POSE(400, 50, 450, 0, 0, 180), POSE(350, 0, 500, 0, 0, 180);
  MOVE PTP (0, -30, 0, -120, 0, 90, 45) WITH APPROX := 0;
ENDPROGRAM
"""


def test_joint_and_cartesian_motion_blend_into_each_other(tmp_path):
    """PTP → LIN, LIN → LIN, LIN → PTP, PTP → CIRCLE, CIRCLE → PTP: every point blended,
    within APPROX, not stopping, the Cartesian parts still on their path, shorter."""
    exact = _run(tmp_path, MIXED.format(approx=0), "e")
    run = _run(tmp_path, MIXED.format(approx=30), "b")
    entries = run.report["approximations"]
    assert [(e["line"], e["kind"]) for e in entries] == [
        (7, "ptp"), (8, "lin"), (9, "lin"), (10, "ptp"), (11, "circle")
    ]  # fmt: skip
    for e in entries:
        assert e["blended"] and e["max_distance_mm"] <= 30.0 + 1e-9
        assert e["min_speed_mm_s"] > 5.0
    # shorter (not by exactly the overlaps: the redundant arm reaches the LIN's end in
    # another configuration after a blend, so the next PTP's time differs)
    assert run.report["duration_s"] < exact.report["duration_s"] - 0.5
    assert run.report["max_path_error_mm"] < 1e-3
    np.testing.assert_allclose(run.report["end_joints"], [0, -30, 0, -120, 0, 90, 45],
                               atol=1e-9)  # fmt: skip
    assert not run.diagnostics  # nothing stops the advance run here
    model = run.model
    for j, row in enumerate(run.report["joints"]):  # the robot's limits hold
        assert row["max_abs_speed"] <= math.degrees(model.speed_limits[j, 1]) * (1 + 1e-6)
        assert row["max_abs_accel"] <= math.degrees(model.accel_limits[j, 1]) * (1 + 1e-6)
    # the trace has no jump: TCP steps stay below the largest programmed speed's step
    p = _positions_mm(run)
    assert np.linalg.norm(np.diff(p, axis=0), axis=1).max() < 0.01 * 1000.0


def test_a_blend_the_limits_forbid_is_shortened(tmp_path):
    """A 3R arm whose J3 is held near 0 and J2 kept in [30, 150] deg cannot bring the TCP
    nearer than √(5 + 4·cos 150°) ≈ 1.24 m to its base. The corner (1.25, 1.25) m of two
    3 m sides (triangular profiles: 1.5 m ramps) with APPROX 1500 mm would pass
    √2·(1.25 − 1.5/4) ≈ 1.237 m from the base (half-way offsets d/4): inside that circle.
    The blend is shortened (bisected) until the inverse transformation can follow it."""
    text = """PROGRAM sh;
ROBOT r := planar3;
BEGIN
  R_SPEED := 300;
  R_ACC := 30;
  MOVE PTP (-122.26, 95.38, 0);
  JOINTLIMIT (-180, 30, -0.5), (180, 150, 0.5);
  MOVE LIN POSE(1250, 1250, 0, 0, 0, 0) WITH APPROX := 1500;
  MOVE LIN POSE(-1750, 1250, 0, 0, 0, 0);
  JOINTLIMITEND;
ENDPROGRAM
"""
    run = _run(tmp_path, text)
    (entry,) = run.report["approximations"]
    assert entry["limit_mm"] < 1500.0 - 10.0 and entry["used_mm"] <= entry["limit_mm"]
    assert entry["blended"] and entry["used_mm"] > 1000.0  # bisected, not halved
    assert entry["note"].startswith("shortened: the longer blend failed")
    q = np.degrees(run.recorded.q)
    assert q[:, 1].min() >= 30.0 - 1e-6 and q[:, 1].max() <= 150.0 + 1e-6
    r = np.linalg.norm(run.recorded.tcp[:, :2, 3], axis=1)
    r_min = math.sqrt(5 + 4 * math.cos(math.radians(150)))
    assert r.min() >= r_min * (1 - 1e-3)
    assert run.report["max_path_error_mm"] < 0.05


def test_a_blend_bisected_to_an_exact_stop_keeps_its_reason(tmp_path, monkeypatch):
    """When every shortened blend fails too, the bisection ends in an exact stop; the note
    says why (the longer blend failed), not that a segment has no TCP path length."""
    from irlc.runtime.control.approximation import ApproximatePositioning
    from irlc.runtime.errors import RunFailure

    real = ApproximatePositioning._try_blend

    def every_blend_fails(self, pending, run, overlap, *, keep):
        if overlap.cycles:
            return RunFailure("joint 2 position max 150 deg", 8, 0.0)
        return real(self, pending, run, overlap, keep=keep)

    monkeypatch.setattr(ApproximatePositioning, "_try_blend", every_blend_fails)
    text = """PROGRAM st;
ROBOT r := planar3;
BEGIN
  MOVE PTP (0, 90, -90);
  MOVE LIN POSE(1000, 1200, 0, 0, 0, 0) WITH APPROX := 100;
  MOVE LIN POSE(1200, 1200, 0, 0, 0, 0);
ENDPROGRAM
"""
    (entry,) = _run(tmp_path, text).report["approximations"]
    assert not entry["blended"] and entry["used_mm"] == 0.0
    assert entry["note"] == "shortened: the longer blend failed (joint 2 position max 150 deg)"


@pytest.mark.parametrize("program", ["square_limits", "square_cyclic"])
def test_koch11_square_blended_keeps_the_limits(tmp_path, program):
    text = (PROGRAMS / f"{program}.irl").read_text(encoding="utf-8")
    text = text.replace("R_ACC := 2000;", "R_ACC := 2000;\n  R_APPROX := 100;")
    if program == "square_cyclic":
        text = text.replace("FOR lap := 1 TO 3 DO", "FOR lap := 1 TO 1 DO")
    exact = run_file(PROGRAMS / f"{program}.irl")
    run = _run(tmp_path, text, program, datalist_path=[PROGRAMS])
    blended = [e for e in run.report["approximations"] if e["blended"]]
    assert blended and all(e["used_mm"] <= 100.0 + 1e-9 for e in blended)
    if program == "square_limits":
        assert run.report["duration_s"] < exact.report["duration_s"]
    data = tomllib.loads((PROGRAMS.parent / "robots/datalists/koch11_ch6.toml").read_text())
    lo, hi = data["limits"]["jmin_base"]["values"], data["limits"]["jmax_base"]["values"]
    for j, row in enumerate(run.report["joints"]):
        assert lo[j] - 1e-6 <= row["min"] and row["max"] <= hi[j] + 1e-6, row["name"]
    assert run.report["max_path_error_mm"] <= 0.05


def test_overlap_choice_closed_form():
    """Two perpendicular unit-acceleration ramps: a_i = i²/2 along −y, b_j = j²/2 along +x
    (cycles of 1 s); the largest m with m²/2 ≤ d and the half-way distance ≤ d."""
    i = np.arange(0, 11, dtype=float)
    a = np.column_stack((0 * i, -(i**2) / 2, 0 * i))
    b = np.column_stack((i**2 / 2, 0 * i, 0 * i))
    o = choose_overlap(a, b, 20.0)
    assert o.cycles == 6 and o.used == 18.0  # 6²/2 = 18 ≤ 20 < 7²/2
    assert o.max_distance == 18.0
    assert choose_overlap(a, b, 0.0).cycles == 0
    assert limit_distance(0.05, 0.03, 1.0) == 0.015
    assert tail_cycles([0.0, 1.0, 2.0, 5.0, 1.0], 2.5) == 2


def test_foreign_approximation_words_get_the_hint(tmp_path):
    for statement in ("MOVE LIN p C_DIS;", "MOVE LIN p WITH ZONE := 5;", "MOVE LIN p, z50;",
                      "MOVE PTP p C_PTP;", "MOVE LIN p WITH C_VEL := 5;"):  # fmt: skip
        path = tmp_path / "h.irl"
        path.write_text(
            "PROGRAM h;\nROBOT r := panda;\nVAR POSE: p;\nBEGIN\n"
            f"  p := POSE(400, 0, 500, 0, 0, 180);\n  {statement}\nENDPROGRAM\n",
            encoding="utf-8",
        )
        with pytest.raises(CompileError) as info:
            run_file(path)
        (diag,) = info.value.diagnostics
        assert diag.span.line == 6, statement
        assert "approximate positioning is written WITH APPROX := mm" in (diag.hint or "")


DRIVES = """PROGRAM dc;
ROBOT r := irb6_track;
VAR
  POSE: goal, third;
BEGIN
  goal := (-653.063, 934.597, 400, 135, 0, -90);
  third := (-700, 1100, 400, 135, 0, -90);
  MOVE PTP (400, 90, 0, 0, -45, 0);
  MOVE LIN goal WITH SPEED := 60 WITH ACC := 250{approx};
  MOVE LIN third WITH SPEED := 60 WITH ACC := 250;
  WAIT 0.6 SEC;
ENDPROGRAM
"""


def test_drives_judge_the_blended_path_as_commanded(tmp_path):
    """With simulated drives the contour error is measured against the blended corner:
    cutting the corner by ~10 mm is no path error (the error stays that of the drives)."""
    runs = [
        run_file(
            _write(tmp_path, DRIVES.format(approx=a), f"d{i}"),
            drives="decoupled",
            path_tolerance=100.0,
        )
        for i, a in enumerate(("", " WITH APPROX := 10"))
    ]
    exact, blended = (r.report for r in runs)
    (entry,) = blended["approximations"]
    assert entry["blended"] and entry["used_mm"] > 5.0
    # the programmed corner is ~used/√2 mm away from the blended path at its middle
    assert blended["max_path_error_mm"] < exact["max_path_error_mm"] + 0.2
    assert blended["max_path_error_mm"] < 0.5 * entry["used_mm"]
    assert blended["duration_s"] < exact["duration_s"]


def _write(tmp_path: Path, text: str, name: str) -> Path:
    path = tmp_path / f"{name}.irl"
    path.write_text(text, encoding="utf-8")
    return path


def test_summary_lists_the_approximated_points(exact_and_blended):
    from irlc.summary import approximations_text

    exact, blended = exact_and_blended
    assert approximations_text(exact.report) == ""
    assert approximations_text(blended.report) == "1 blended (used 20 mm, saved 0.2 s)"


@pytest.mark.parametrize(
    "program", ["planar4_obstacle", "combined", "mobile8_freeze", "planar3_cyclic"]
)
def test_every_option_program_runs_blended_and_shorter(tmp_path, program):
    """R_APPROX := 50 at the start of the chapter programs with OBSTACLE, FREEZE, CYCLIC,
    RECONFIGURATION and the limit sets: still ok (every option and limit held by the
    inverse transformation), shorter, and switching an option ends the approximation."""
    text = (PROGRAMS / f"{program}.irl").read_text(encoding="utf-8")
    i = text.rindex("BEGIN") + len("BEGIN")
    run = _run(tmp_path, text[:i] + "\n  R_APPROX := 50;" + text[i:], program,
               datalist_path=[PROGRAMS])  # fmt: skip
    exact = run_file(PROGRAMS / f"{program}.irl")
    entries = run.report["approximations"]
    assert any(e["blended"] for e in entries)
    assert run.report["duration_s"] < exact.report["duration_s"]
    assert run.report["max_path_error_mm"] <= 0.05
    for e in entries:
        assert e["blended"] or e["note"], e  # an exact stop always says why
    for name, o in run.report["obstacles"].items():
        assert o["min_distance_mm"] >= min(0.0, exact.report["obstacles"][name]["min_distance_mm"])


def test_collinear_points_keep_the_programmed_speed(tmp_path):
    """Three points on one straight line at R_SPEED 100 mm/s (ramps 5 mm at 1000 mm/s²):
    superposing two cruising segments would double the speed, so the blend stays within
    the ramps — the path speed never exceeds R_SPEED and never drops to zero."""
    text = """PROGRAM col;
ROBOT r := panda;
BEGIN
  R_SPEED := 100;
  R_ACC := 1000;
  MOVE PTP (0, -30, 0, -120, 0, 90, 45);
  MOVE LIN POSE(400, -100, 500, 0, 0, 180);
  MOVE LIN PATH (POSE(400, 0, 500, 0, 0, 180), POSE(400, 100, 500, 0, 0, 180))
    WITH APPROX := 30;
  MOVE LIN POSE(400, 200, 500, 0, 0, 180);
ENDPROGRAM
"""
    run = _run(tmp_path, text, "col")
    entries = run.report["approximations"]
    assert len(entries) == 2 and all(e["blended"] for e in entries)
    t = run.recorded.times
    p = _positions_mm(run)
    line = t > t[np.flatnonzero(np.abs(p[:, 1] + 100.0) < 1e-6)[-1]]  # after (400, -100)
    speed = np.linalg.norm(np.diff(p, axis=0), axis=1) / np.diff(t)
    moving = speed[line[1:]]
    assert moving.max() <= 100.0 * (1 + 1e-6)
    inner = line[1:] & (p[1:, 1] > -90.0) & (p[1:, 1] < 190.0)  # between the end ramps
    assert speed[inner].min() > 99.0  # the points are passed at full speed


def test_signal_between_approximated_motions_switches_on_entering_the_region(tmp_path):
    """gripper := TRUE between two approximated LINs (no advance-run stop): the event is
    stamped when the TCP enters the 20 mm region of the corner — 20 mm before it on the
    deceleration ramp of side A, t = t_corner − √(2·20/1000) s = t_corner − 0.2 s, where
    t_corner is side A's own end (1.05 s after it starts)."""
    text = (
        CORNER.format(approx=" WITH APPROX := 20", x2=600)
        .replace(
            "PROGRAM corner;\nROBOT r := panda;\n",
            "PROGRAM corner;\nROBOT r := panda;\nVAR\n  SIGNAL: gripper;\n",
        )
        .replace("  MOVE LIN POSE(600", "  gripper := TRUE;\n  MOVE LIN POSE(600")
    )
    run = _run(tmp_path, text, "sig")
    (event,) = [e for e in run.report["events"] if e["kind"] == "signal"]
    (entry,) = run.report["approximations"]
    assert entry["blended"] and not run.diagnostics
    lines = run.recorded.lines
    t = run.recorded.times
    side_a_start = t[np.flatnonzero(lines == 10)[0] - 1]  # the sample before side A
    t_corner = side_a_start + 1.05
    assert event["time_s"] == pytest.approx(t_corner - 0.2, abs=1e-9)
    p = _positions_mm(run)
    k = int(np.flatnonzero(np.abs(t - event["time_s"]) < 1e-9)[0])
    assert np.linalg.norm(p[k] - [400.0, 100.0, 500.0]) == pytest.approx(20.0, abs=1e-3)


def test_cycle_time_spans_tile_the_run_with_blends_and_exact_stops(tmp_path):
    """The per-statement table still sums to the duration: a blended point's tail counts
    in the next statement's span; a point whose approximation a WAIT or the program's end
    cancels extends its own span, which then ends in an exact stop."""
    text = (
        CORNER.format(approx="", x2=600)
        .replace("  MOVE LIN POSE(400, -100", "  R_APPROX := 20;\n  MOVE LIN POSE(400, -100")
        .replace("  MOVE LIN POSE(600", "  WAIT 0.1 SEC;\n  MOVE LIN POSE(600")
    )
    run = _run(tmp_path, text, "tile")
    rows = run.report["statements"]
    assert sum(r["duration_s"] for r in rows) == pytest.approx(run.report["duration_s"])
    ends = [r["start_s"] + r["duration_s"] for r in rows]
    assert [r["start_s"] for r in rows[1:]] == pytest.approx(ends[:-1])
    stops = {r["line"]: r["stop"] for r in rows if r["kind"].startswith("MOVE")}
    assert stops == {6: "exact", 8: "approximated", 9: "exact", 11: "exact"}
    assert ends[-1] == pytest.approx(run.report["duration_s"])
    notes = {e["line"]: e["note"] for e in run.report["approximations"]}
    assert notes[9] == "WAIT at line 10" and notes[11] == "the program ends"


def test_scurve_profiles_blend_too(tmp_path):
    """R_PROFILE := 'SCURVE': the superposition does not depend on the profile's shape —
    blended within APPROX, not stopping, shorter, the path speed within R_SPEED."""
    scurve = CORNER.replace("  R_ACC := 1000;", "  R_ACC := 1000;\n  R_PROFILE := 'SCURVE';")
    exact = _run(tmp_path, scurve.format(approx="", x2=600), "se")
    run = _run(tmp_path, scurve.format(approx=" WITH APPROX := 20", x2=600), "sb")
    (entry,) = run.report["approximations"]
    assert entry["blended"] and entry["max_distance_mm"] <= 20.0 + 1e-9
    assert entry["min_speed_mm_s"] > 50.0
    # shorter by the overlap, ± one IPO cycle: side B is planned from the programmed
    # corner, the exact run's from where the IK arrived (1e-9 m away), and this S-curve's
    # time lies on a cycle boundary (115 vs 116 cycles)
    saved = exact.report["duration_s"] - run.report["duration_s"]
    assert saved == pytest.approx(entry["saved_s"], abs=0.01 + 1e-9)
    p, t = _positions_mm(run), run.recorded.times
    speed = np.linalg.norm(np.diff(p, axis=0), axis=1) / np.diff(t)
    assert speed[t[1:] > 1.0].max() <= 250.0 * (1 + 1e-6)  # after the start PTP
