"""Path geometry of the interpolator against closed forms."""

from __future__ import annotations

import numpy as np
import pytest
from irlc.runtime.model import spatial
from irlc.runtime.plan.interpolator import CartesianArc, CartesianLine, CircleError, ReferencePath


def _pose(p, r=None):
    return spatial.transform(np.eye(3) if r is None else r, p)


def test_line_is_straight_and_slerps_orientation():
    r1 = spatial.rot_z(np.radians(90))
    line = CartesianLine(_pose((0, 0, 0)), _pose((2, 0, 0), r1))
    assert line.length == pytest.approx(2.0)
    assert line.angle == pytest.approx(np.pi / 2)
    mid = line.at(0.5)
    assert np.allclose(mid[:3, 3], (1, 0, 0))
    assert np.allclose(mid[:3, :3], spatial.rot_z(np.radians(45)))


@pytest.mark.parametrize("via_angle", [30.0, 90.0, 200.0])
def test_arc_passes_the_via_point_on_a_circle(via_angle):
    # circle of radius 2 about c in a tilted plane; start at angle 0, via, target at 270°
    c = np.array([0.3, -0.2, 1.0])
    u = np.array([1.0, 0.0, 0.0])
    v = np.array([0.0, np.cos(0.4), np.sin(0.4)])

    def on(deg):
        a = np.radians(deg)
        return c + 2.0 * (np.cos(a) * u + np.sin(a) * v)

    arc = CartesianArc(_pose(on(0)), on(via_angle), _pose(on(270), spatial.rot_x(0.5)))
    assert arc.length == pytest.approx(2.0 * np.radians(270))
    assert arc.via_fraction == pytest.approx(via_angle / 270)
    for s in np.linspace(0, 1, 37):
        assert np.linalg.norm(arc.position(s) - c) == pytest.approx(2.0)
    assert np.allclose(arc.position(arc.via_fraction), on(via_angle))
    assert np.allclose(arc.at(1.0)[:3, 3], on(270))
    assert np.allclose(arc.at(1.0)[:3, :3], spatial.rot_x(0.5))
    # constant speed along the arc: equal s steps → equal chords
    chords = np.linalg.norm(
        np.diff([arc.position(s) for s in np.linspace(0, 1, 11)], axis=0), axis=1
    )
    assert np.allclose(chords, chords[0])


def test_collinear_circle_is_rejected():
    with pytest.raises(CircleError):
        CartesianArc(_pose((0, 0, 0)), np.array([1.0, 0, 0]), _pose((2, 0, 0)))


def test_reference_path_is_piecewise_linear():
    ref = ReferencePath(np.array([0.0, 0.25, 1.0]), np.array([[0.0], [1.0], [4.0]]))
    assert ref.at(0.125)[0] == pytest.approx(0.5)
    assert ref.at(0.25)[0] == pytest.approx(1.0)
    assert ref.at(0.625)[0] == pytest.approx(2.5)
    assert ref.at(1.0)[0] == pytest.approx(4.0)
