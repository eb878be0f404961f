"""Robot files vs data lists, seed tables and the drives contract."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest
from irlc.robots import DATALISTS_DIR, list_robots, load_robot
from irlc.runtime import units

REQUIRED = {"koch11", "irb6", "irb6_track", "as6", "l1", "planar3", "planar4", "mobile8", "panda"}


def test_library_has_every_required_robot():
    assert set(list_robots()) >= REQUIRED


@pytest.mark.parametrize("name", sorted(REQUIRED))
def test_every_robot_has_geometry_inertials_and_valid_home(name):
    m = load_robot(name)
    assert m.geometry, "collision geometry is needed by the IK's obstacle avoidance"
    assert m.inertials, "inertials are needed by the drives (M, C, G)"
    lim = m.position_limits
    assert np.all(lim[:, 0] <= m.home_q()) and np.all(m.home_q() <= lim[:, 1])
    for g in m.geometry:
        assert 0 <= g.link <= m.n and g.radius > 0
    for i in m.inertials:
        ev = np.linalg.eigvalsh(i.inertia)
        assert i.mass > 0 and ev[0] >= -1e-12 and ev[0] + ev[1] >= ev[2] - 1e-9


def test_koch11_datalist_agrees_with_limit_sets():
    model = load_robot("koch11")
    doc = tomllib.loads((DATALISTS_DIR / "koch11_ch6.toml").read_text())["limits"]
    kinds = model.joint_kinds
    pairs = {
        ("jmin_base", "jmax_base"): ("base", "position"),
        ("jmin_j11", "jmax_j11"): ("j11", "position"),
        ("jmin_obst", "jmax_obst"): ("obstacle", "position"),
        ("jsmin", "jsmax"): ("speed", "speed"),
        ("jamin", "jamax"): ("accel", "accel"),
    }
    types = {"position": "MAIN_JOINT", "speed": "MAIN_JOINT_SPEED", "accel": "MAIN_JOINT_ACCEL"}
    for (lo_name, hi_name), (set_name, field) in pairs.items():
        values = np.array([getattr(lim, field) for lim in model.limit_sets[set_name]])
        assert doc[lo_name]["type"] == types[field] + "_MIN"
        assert doc[hi_name]["type"] == types[field] + "_MAX"
        assert np.allclose(units.joints_to_si(doc[lo_name]["values"], kinds), values[:, 0])
        assert np.allclose(units.joints_to_si(doc[hi_name]["values"], kinds), values[:, 1])


def test_koch11_sets_against_the_book_table():
    """Spot checks straight from robots.md (program units)."""
    doc = tomllib.loads((DATALISTS_DIR / "koch11_ch6.toml").read_text())["limits"]
    assert doc["jmax_base"]["values"][10] == 60 and doc["jmin_base"]["values"][10] == -20
    assert doc["jmin_j11"]["values"][10] == 0
    assert doc["jsmax"]["values"][9] == 500 and doc["jsmax"]["values"][10] == 25
    assert doc["jamin"]["values"][6] == -350
    assert doc["jmax_obst"]["values"][3] == 240 and doc["jmin_obst"]["values"][9] == -700


def test_koch11_own_limits_are_the_widest():
    model = load_robot("koch11")
    for lims in model.limit_sets.values():
        for own, s in zip(model.joints, lims, strict=True):
            assert (
                own.limits.position[0] <= s.position[0] and s.position[1] <= own.limits.position[1]
            )
            assert own.limits.speed[1] >= s.speed[1] and own.limits.accel[1] >= s.accel[1]


def test_koch11_weights():
    w = load_robot("koch11").weights
    assert list(w[:9]) == [11, 10, 9, 8, 7, 6, 5, 4, 3] and w[10] == 1 and w[9] > 0


def test_l1_transmission_constants():
    rows = load_robot("l1").extra["transmission"]
    assert np.isclose(rows[0]["ratio"], 360 * np.pi) and rows[3]["ratio"] == -3.6
    assert rows[4]["couple"] == [(3, 0.5)] and rows[5]["couple"] == [(4, 2.0)]
