"""R_OVERRIDE / --override: a time scaling of every motion (speeds ×k, accelerations ×k²),
checked against the closed form of the trapezoid and from the trace alone."""

from __future__ import annotations

import numpy as np
import pytest
from irlc.cli import main
from irlc.runtime.run import RunSetupError, run_file

# planar3 starts at its home (0, 90, -90): the TCP at (2000, 1000) mm
PROGRAM = """PROGRAM ov;
ROBOT r := planar3;
BEGIN
  R_SPEED := 200;
  R_ACC := 500;
  MOVE LIN POSE(1000, 1000, 0, 0, 0, 0);
  {SET}
  MOVE LIN POSE(1000, 0, 0, 0, 0, 0);
  MOVE PTP (0, 90, -90);
  WRITELN(R_OVERRIDE);
ENDPROGRAM
"""
L, V, A = 1000.0, 200.0, 500.0  # mm, mm/s, mm/s²


def _trapezoid(length: float, v: float, a: float) -> float:
    """Minimum time of a rest-to-rest trapezoid: L/v + v/a (when it reaches v)."""
    assert length >= v * v / a
    return length / v + v / a


def _run(tmp_path, set_line: str = "", **options):
    path = tmp_path / "ov.irl"
    path.write_text(PROGRAM.replace("{SET}", set_line), encoding="utf-8")
    run = run_file(path, **options)
    assert run.ok, run.error
    return run


def _segments(run) -> dict[int, float]:
    """Duration per program line, from the recorded samples (IPO cycles)."""
    lines, dt = run.lines, run.report["ipo_s"]
    return {int(n): float(np.count_nonzero(lines[1:] == n) * dt) for n in set(lines[1:].tolist())}


def test_override_start_value_doubles_every_time(tmp_path):
    full = _run(tmp_path)
    half = _run(tmp_path, override=50)
    t_full, t_half = _segments(full), _segments(half)
    assert t_full[6] == pytest.approx(_trapezoid(L, V, A), abs=1e-9)  # 5.4 s
    assert t_half[6] == pytest.approx(_trapezoid(L, 0.5 * V, 0.25 * A), abs=1e-9)  # 10.8 s
    for line in (6, 8, 9):
        assert t_half[line] == pytest.approx(2.0 * t_full[line], abs=0.011)
    assert half.report["duration_s"] == pytest.approx(2 * full.report["duration_s"], abs=0.03)
    assert half.output == ["50.0"] and full.output == ["100.0"]
    rows = half.report["statements"]
    assert [r["override_percent"] for r in rows] == [50.0, 50.0, 50.0]
    assert [r["duration_s"] for r in rows] == pytest.approx([2 * t_full[n] for n in (6, 8, 9)],
                                                            abs=0.011)  # fmt: skip


def test_same_path_twice_as_slow(tmp_path):
    full = _run(tmp_path)
    half = _run(tmp_path, override=50)
    cols = full.trace_columns
    x, y, t = cols.index("x_mm"), cols.index("y_mm"), cols.index("t_s")
    n = round(_trapezoid(L, V, A) / 0.01)  # samples of the first LIN
    a, b = full.trace[: n + 1], half.trace[: 2 * n + 1 : 2]  # b at twice a's times
    assert np.allclose(b[:, t], 2 * a[:, t])
    assert np.allclose(b[:, [x, y]], a[:, [x, y]], atol=1e-6)
    v_full = np.max(np.hypot(*np.diff(a[:, [x, y]], axis=0).T)) / 0.01
    v_half = np.max(np.hypot(*np.diff(half.trace[: 2 * n + 1][:, [x, y]], axis=0).T)) / 0.01
    assert v_full == pytest.approx(V, rel=1e-6) and v_half == pytest.approx(V / 2, rel=1e-6)


def test_assignment_applies_from_the_next_statement(tmp_path):
    run = _run(tmp_path, "R_OVERRIDE := 25;")
    t = _segments(run)
    assert t[6] == pytest.approx(_trapezoid(L, V, A), abs=1e-9)
    assert t[8] == pytest.approx(_trapezoid(L, 0.25 * V, 0.0625 * A), abs=1e-9)  # 4×
    assert run.output == ["25.0"]
    assert [r["override_percent"] for r in run.report["statements"]] == [100.0, 25.0, 25.0]


def test_python_api_start_value(tmp_path):
    from irlc.api import run_program

    path = tmp_path / "ov.irl"
    path.write_text(PROGRAM.replace("{SET}", ""), encoding="utf-8")
    run = run_program(path, override=25)
    assert _segments(run)[6] == pytest.approx(_trapezoid(L, V / 4, A / 16), abs=1e-9)  # 21.6 s


def test_with_time_is_stretched(tmp_path):
    path = tmp_path / "t.irl"
    path.write_text(PROGRAM.replace("MOVE LIN POSE(1000, 0, 0, 0, 0, 0);",
                                    "MOVE LIN POSE(1000, 0, 0, 0, 0, 0) WITH TIME := 8;")
                    .replace("{SET}", ""), encoding="utf-8")  # fmt: skip
    assert _segments(run_file(path, override=80))[8] == pytest.approx(10.0, abs=1e-9)


def test_out_of_range(tmp_path, capsys):
    path = tmp_path / "ov.irl"
    path.write_text(PROGRAM.replace("{SET}", "R_OVERRIDE := 150;"), encoding="utf-8")
    assert main([str(path), "-q"]) == 1
    err = " ".join(capsys.readouterr().err.split())  # the console wraps long lines
    assert "R_OVERRIDE := 150: the value must be in [1, 100] %" in err
    path.write_text(PROGRAM.replace("{SET}", ""), encoding="utf-8")
    assert main([str(path), "-q", "--override", "0"]) == 3
    assert "--override 0.0: the value must be in [1, 100] %" in " ".join(
        capsys.readouterr().err.split()
    )
    with pytest.raises(RunSetupError):
        run_file(path, override=101)


def test_scurve_is_scaled_in_time_too(tmp_path):
    """With R_PROFILE = 'SCURVE' the override also scales the jerk (×k³): each motion
    takes 1/k times as long (to an IPO cycle)."""
    path = tmp_path / "s.irl"
    path.write_text(
        "PROGRAM s;\nROBOT r := planar3;\nBEGIN\n  R_PROFILE := 'SCURVE';\n"
        "  MOVE LIN POSE(1000, 1000, 0, 0, 0, 0);\n  MOVE PTP (20, 80, -60);\n"
        "  MOVE_INC PTP (0.5, 0, 0);\nENDPROGRAM\n",
        encoding="utf-8",
    )
    full = [r["duration_s"] for r in run_file(path).report["statements"]]
    half = [r["duration_s"] for r in run_file(path, override=50).report["statements"]]
    assert all(t > 0.05 for t in full)
    assert half == pytest.approx([2 * t for t in full], abs=0.0201)


def test_ptp_jerks_scale_with_k_cubed():
    """A PTP's joint jerk is ``ptp_jerks(…) · R_ACC_PTP``: with the override's k² in
    R_ACC_PTP, ``ptp_jerks`` carries one more k — for a robot file's own jerks (panda) and
    for the fallback ``θ̈max · R_JERK / R_ACC`` (planar3, none in its file)."""
    from irlc.robots import load_robot
    from irlc.runtime.commands import MotionCommand, Settings
    from irlc.runtime.plan.motion_values import motion_values
    from irlc.runtime.plan.preinterp import PreInterpolator

    cmd = MotionCommand("PTP", (), 1)
    for name in ("panda", "planar3"):
        model = load_robot(name)
        pre = PreInterpolator(model)
        accel = np.full(model.n, 3.0)
        full = pre.ptp_jerks(motion_values(cmd, Settings(profile="SCURVE")), accel)
        half = pre.ptp_jerks(motion_values(cmd, Settings(profile="SCURVE", override=50.0)), accel)
        assert np.all(np.isfinite(full)) and half == pytest.approx(0.5 * full, rel=1e-12)
    assert not np.isnan(load_robot("panda").jerk_limits).any()
