"""A cell with --drives where one robot has no drive data (docs/drives.md): that robot runs
ideal — its actual motion is its set points — beside the other's simulated drives, and the
run says so; a cell without any drive data is refused as a program of one robot is."""

from __future__ import annotations

import numpy as np
import pytest
from irlc import run_program
from irlc.runtime.errors import DriveSetupError

CELL = """PROGRAM mixed;
ROBOT arm := as6;
ROBOT cobot := panda AT (0, -1500, 0, 90, 0, 0);
BEGIN
  MOVE arm PTP (100, 40, 0, 30, 90, 0) AND cobot PTP (10, -45, 0, -135, 0, 90, 45);
ENDPROGRAM
"""


def _run(tmp_path, text: str, **options):
    path = tmp_path / "mixed.irl"
    path.write_text(text, encoding="utf-8")
    return run_program(path, **options)


def test_a_robot_without_drive_data_runs_ideal_beside_driven_ones(tmp_path):
    ideal = _run(tmp_path, CELL)
    run = _run(tmp_path, CELL, drives="decoupled")
    assert run.status == "ok", run.report.get("error")
    arm, cobot = run.report["robots"]
    assert arm["drives_summary"]["level"] == "decoupled" and "verdict" in arm
    assert "drives_summary" not in cobot and "verdict" not in cobot
    note = "robot panda has no drive data ([drives] in its robot file): it runs ideal"
    assert any(note in w for w in cobot["warnings"])
    assert any(w.startswith(f"cobot: {note}") for w in run.report["warnings"])
    # the panda's motion is its set points; the as6 lags them
    assert np.array_equal(run.robots["cobot"].q, ideal.robots["cobot"].q)
    assert not np.allclose(run.robots["arm"].q, ideal.robots["arm"].q, atol=1e-6)


def test_a_cell_without_any_drive_data_is_refused(tmp_path):
    two = CELL.replace("ROBOT arm := as6;", "ROBOT arm := panda AT (0, 1500, 0, 0, 0, 0);")
    two = two.replace(
        "MOVE arm PTP (100, 40, 0, 30, 90, 0)", "MOVE arm PTP (10, -45, 0, -135, 0, 90, 45)"
    )
    with pytest.raises(DriveSetupError, match="robot panda has no drive data"):
        _run(tmp_path, two, drives="decoupled")


def test_a_robots_drive_failure_in_a_cell_names_the_robot(tmp_path):
    text = CELL.replace(
        "ENDPROGRAM", "  MOVE arm LIN arm.R_ACT_POSE : (0, 0, -100, 0, 0, 0);\nENDPROGRAM"
    )
    run = _run(tmp_path, text, drives="decoupled", path_tolerance=0.5)
    error = run.report["error"]
    assert run.status == "failed" and error["line"] == 6
    assert error["message"].startswith("robot arm: the actual TCP (simulated drives) leaves")
