"""IRb-6 coupled limits against the book's piecewise form; the plane reachability test."""

from __future__ import annotations

import math

import numpy as np
from irlc.robots import load_robot
from irlc.runtime.model import spatial
from irlc.runtime.model.coupled_limits import as_inequalities, coupled_limits, violations
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.model.reachability import check_vertical_plane


def book_ok(t2: float, t3: float, t4: float) -> bool:
    """robots.md, literally (degrees)."""
    if not -40 <= t2 <= 40:
        return False
    if -40 <= t2 <= -15:
        ok3 = -40 - t2 <= t3 <= 40
    elif t2 <= 0:
        ok3 = -40 - t2 <= t3 <= 25 - t2
    else:
        ok3 = -40 <= t3 <= 25 - t2
    return ok3 and -90 <= t2 + t3 + t4 <= 90


def test_irb6_coupled_limits_equal_the_book():
    model = load_robot("irb6")
    lims = coupled_limits(model)
    a, b = as_inequalities(lims, model.n)
    box = model.position_limits
    rng = np.random.default_rng(0)
    for _ in range(5000):
        deg = np.array([10.0, *rng.uniform(-60, 60, 2), rng.uniform(-150, 150), 0.0])
        q = np.radians(deg)
        in_box = bool(
            np.all(box[1:3, 0] - 1e-12 <= q[1:3]) and np.all(q[1:3] <= box[1:3, 1] + 1e-12)
        )
        ours = in_box and not violations(lims, q)
        assert ours == book_ok(*deg[1:4]), deg
        assert (not violations(lims, q)) == bool(np.all(a @ q >= b - 1e-12))


def test_violation_reports_amount():
    model = load_robot("irb6")
    q = np.radians([10, 30, 0, 80, 0])  # θ2+θ3+θ4 = 110 > 90, θ2+θ3 = 30 > 25
    found = {(v.name, v.side): math.degrees(v.amount) for v in violations(coupled_limits(model), q)}
    assert math.isclose(found[("theta2+theta3+theta4", "upper")], 20.0)
    assert math.isclose(found[("theta2+theta3", "upper")], 5.0)


def test_irb6_plane_condition():
    model = load_robot("irb6")
    kin = Kinematics(model)
    rng = np.random.default_rng(1)
    for _ in range(10):
        q = np.radians([rng.uniform(0, 340), *rng.uniform(-20, 20, 3), rng.uniform(-180, 180)])
        t = kin.tcp(q)
        assert check_vertical_plane(model, t).reachable  # every FK pose satisfies it
        flange = kin.flange_from_frames(kin.link_frames(q))
        c, d = flange[:3, 2], flange[:3, 3]
        assert abs(c[0] * d[1] - c[1] * d[0]) < 1e-12  # the book's key equation
        # turn the approach vector out of the plane: 10° about the world z axis at the TCP
        turned = t.copy()
        turned[:3, :3] = spatial.rot_z(math.radians(10)) @ t[:3, :3]
        res = check_vertical_plane(model, turned)
        if np.linalg.norm(c[:2]) > 0.1:
            assert not res.reachable and "vertical plane" in res.message


def test_track_position_solves_the_plane_condition():
    model = load_robot("irb6_track")
    kin = Kinematics(model)
    q = np.array([0.3, *np.radians([120, 10, -10, -30, 20])])
    res = check_vertical_plane(model, kin.tcp(q))
    assert res.reachable and math.isclose(res.track, 0.3, abs_tol=1e-9)
