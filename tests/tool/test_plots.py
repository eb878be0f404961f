"""PNG figures: the expected files, non-empty images, the compare overlay, limits."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from irlc.plots import limit_values, path_length_and_speed, write_plots
from irlc.run_data import run_data

from .tool_fixtures import make_run

PNG = b"\x89PNG\r\n\x1a\n"


def _image(path):
    import matplotlib.image as mpimg

    return mpimg.imread(path)


def test_figures_of_an_ideal_run(tmp_path, demo_run):
    paths = write_plots(demo_run, tmp_path)
    names = [p.name for p in paths]
    assert names == [
        "joint_positions_1-4.png",
        "joint_speeds_1-4.png",
        "joint_accels_1-4.png",
        "tcp_path_3d.png",
        "tcp_path_speed.png",
    ]
    for p in paths:
        data = p.read_bytes()
        assert data.startswith(PNG) and len(data) > 5000
        assert _image(p).std() > 0.01  # not a blank canvas
    assert sorted(x.name for x in tmp_path.iterdir()) == sorted(names)  # no temp files left


def test_drive_figures_and_compare_overlay(tmp_path):
    run = make_run(drives=True)
    alone = write_plots(run, tmp_path / "a")
    both = write_plots(run, tmp_path / "b", compare=make_run(phase=0.4, label="other"))
    assert [p.name for p in alone][-2:] == [
        "drive_following_errors_1-4.png",
        "drive_currents_1-4.png",
    ]
    assert [p.name for p in alone] == [p.name for p in both]
    for a, b in zip(alone, both, strict=True):  # the overlay changes every figure
        assert a.read_bytes() != b.read_bytes()


def test_figures_are_deterministic(tmp_path, demo_run):
    a = write_plots(demo_run, tmp_path / "a")
    b = write_plots(make_run(), tmp_path / "b")
    assert [p.read_bytes() for p in a] == [p.read_bytes() for p in b]


def test_eleven_joints_split_like_the_book(tmp_path):
    """Figures hold at most six joints: 1-6 and 7-11 as in figures 6.5 / 6.6."""
    run = make_run()
    q = np.tile(run.q, (1, 3))[:, :11]
    names = [f"a{i + 1}" for i in range(11)]
    fake = type("R", (), {})()
    fake.times, fake.q, fake.report = run.times, q, {"joints": [{"name": n} for n in names]}
    paths = write_plots(fake, tmp_path)
    assert [p.name for p in paths] == [
        f"joint_{w}_{r}.png" for w in ("positions", "speeds", "accels") for r in ("1-6", "7-11")
    ]


def test_limits_in_program_units(demo_run):
    d = run_data(demo_run)
    pos = limit_values(d, 1, 0)
    assert [s for _, s in pos] == ["robot", "robot"]
    assert [v for v, _ in pos] == pytest.approx([-25.0, 90.0])
    assert [v for v, _ in limit_values(d, 2, 1)] == pytest.approx([-500.0, 500.0])
    d.report["joints"][0]["program_limits"] = {"position": [-10.0, 20.0]}
    assert (20.0, "program") in limit_values(d, 0, 0)


def test_path_length_of_a_straight_line():
    run = make_run()
    d = run_data(run)
    d.tcp = np.column_stack([np.linspace(0, 1.0, d.k), np.zeros(d.k), np.zeros(d.k)])
    s, v = path_length_and_speed(d)
    assert s[-1] == pytest.approx(1000.0)
    assert v[d.k // 2] == pytest.approx(1000.0 / 3.0)
