"""[drives] tables: the shipped robot files validate; bad tables fail with file and key."""

from __future__ import annotations

import copy
import re
from pathlib import Path

import numpy as np
import pytest
from irlc.robots.loader import load_toml
from irlc.runtime.drives import DriveParamError, drive_params

from .drive_models import dc_drives, planar, stepper_drives

ROBOTS = Path(__file__).resolve().parents[2] / "robots"


def test_shipped_robot_files_validate():
    p = drive_params(load_toml(ROBOTS / "irb6_track.toml"))
    assert p.type == "dc" and p.axes == tuple(range(6))
    assert np.allclose(p.chain.ki, [36.25, 267.01, 256.80, 264.40, 237.82, 247.96])
    assert np.allclose(p.chain.L, 2.3e-3) and np.allclose(p.chain.i_max, 10.0)
    assert p.chain.pwm_frequency == 8000.0
    assert p.slave.T_pr == 0.04 and np.allclose(p.slave.a_max, 137.1486)
    assert "drives.dc.kz" in p.assumed and "drives.dc.J_m" in p.assumed
    assert "drives.dc.ki" not in p.assumed  # published values are not marked
    l1 = drive_params(load_toml(ROBOTS / "l1.toml"))
    assert l1.type == "stepper" and np.allclose(np.degrees(l1.chain.step_angle), 1.8)
    for name in ("irb6", "as6", "koch11"):
        assert drive_params(load_toml(ROBOTS / f"{name}.toml")).type == "dc"


def test_robot_without_drives_is_none():
    assert drive_params(planar(2)) is None


def bad(table: dict, key: str, match: str):
    model = planar(2, drives=table)
    with pytest.raises(DriveParamError, match=match) as err:
        drive_params(model)
    assert err.value.key == key
    assert err.value.file == "<test model>"


def test_errors_name_file_and_key():
    base = dc_drives(2)
    t = copy.deepcopy(base)
    t["dc"]["R"] = [1.0, 2.0, 3.0]
    bad(t, "drives.dc.R", "expected a number or 2 numbers")
    t = copy.deepcopy(base)
    t["dc"]["R"] = [1.0, -2.0]
    bad(t, "drives.dc.R[2]", "expected a positive number, got -2$")
    t = copy.deepcopy(base)
    t["dc"]["Rr"] = 1.0
    bad(t, "drives.dc.Rr", "unknown key")
    t = copy.deepcopy(base)
    del t["dc"]["kiwzm"]
    bad(t, "drives.dc.kiwzm", "missing")
    t = copy.deepcopy(base)
    t["dc"]["kz"] = {"value": 3.0, "assumed": True}
    bad(t, "drives.dc.kz.reason", "needs a reason")
    t = copy.deepcopy(base)
    t["dc"]["ke"] = "fast"
    bad(t, "drives.dc.ke", "expected a number, got 'fast'$")
    t = copy.deepcopy(base)
    t["friction"] = {"static": 0.1, "running": 0.2}
    bad(t, "drives.friction.running", "exceeds static")
    t = copy.deepcopy(base)
    t["axes"] = [3]
    bad(t, "drives.axes", "joint numbers 1..2")
    t = copy.deepcopy(base)
    t["type"] = "hydraulic"
    bad(t, "drives.type", "dc, stepper")
    bad({"type": "stepper"}, "drives.stepper", "missing")
    s = stepper_drives()
    s["stepper"]["L12"] = 5e-3
    bad(s, "drives.stepper.L12", "mutual inductance")


def test_subset_of_axes_and_values_per_driven_axis():
    t = dc_drives(1)
    t["axes"] = [2]
    p = drive_params(planar(2, drives=t))
    assert p.axes == (1,) and p.count == 1 and p.chain.R.shape == (1,)


def test_messages_are_the_robot_readers():
    """[drives] is read by the robot file reader (robots/toml_reader.py): a bad value reads
    the same as anywhere else in a robot file (file, key, expected, got type and value)."""
    from irlc.robots.toml_reader import Reader

    robot = Reader("<test model>")
    for value, read in (("fast", robot.number), (float("inf"), robot.number), (-2, robot.positive)):
        with pytest.raises(Exception) as same:
            read(value, "drives.dc.ke")
        t = dc_drives(2)
        t["dc"]["ke"] = value
        bad(t, "drives.dc.ke", f"^{re.escape(str(same.value))}$")
    base = dc_drives(2)
    t = copy.deepcopy(base)
    t["dc"]["ke"] = float("inf")
    bad(t, "drives.dc.ke", "expected a finite number, got infinity$")
    t = copy.deepcopy(base)
    t["friction"] = {"static": [0.1, -0.1]}
    bad(t, "drives.friction.static[2]", "expected a non-negative number, got -0.1$")
    t = copy.deepcopy(base)
    t["dc"] = 3
    bad(t, "drives.dc", "expected a table, got 3$")
    t = copy.deepcopy(base)
    t["dc"]["kz"] = {"value": 3.0, "assumed": "yes", "reason": "r"}
    bad(t, "drives.dc.kz.assumed", "expected true or false, got 'yes'$")
    bad([1], "drives", r"expected a table, got \[1\]$")
