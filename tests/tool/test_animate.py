"""The HTML animation: self-contained, frame data consistent with FK, loads in Chromium."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import tempfile

import numpy as np
import pytest
from irlc.animate import MAX_FRAMES, STATUS_ID, animation_data, frame_indices, write_animation
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.model.obstacles import BoxObstacle, PlaneObstacle, SphereObstacle

from .tool_fixtures import make_run


def _run_with_obstacles():
    run = make_run()
    run.obstacles = (
        SphereObstacle("ball", np.array([0.6, 0.3, 0.3]), 0.08),
        BoxObstacle("table", np.array([0.7, -0.3, 0.1]), np.array([0.3, 0.3, 0.2])),
        PlaneObstacle("floor", np.zeros(3), np.array([0.0, 0.0, 1.0])),
    )
    return run


def _embedded(html: str) -> dict:
    m = re.search(r'<script id="irlc-data" type="application/json">(.*?)</script>', html, re.S)
    return json.loads(m.group(1))


def test_self_contained(tmp_path):
    html = write_animation(_run_with_obstacles(), tmp_path / "a.html").read_text()
    assert "http://" not in html and "https://" not in html
    assert "<script src" not in html and "<link" not in html
    data = _embedded(html)
    assert [o["type"] for o in data["obstacles"]] == ["sphere", "box", "plane"]
    assert data["obstacles"][0]["c"] == [600, 300, 300] and data["obstacles"][0]["r"] == 80


def test_frames_follow_forward_kinematics(tmp_path):
    run = make_run()
    data = animation_data(run)
    kin = Kinematics(run.model)
    k = 137
    frames = kin.link_frames(run.q[k])
    tcp_mm = kin.tcp(run.q[k])[:3, 3] * 1000.0
    pts = np.array(data["points"][k])
    assert np.max(np.abs(pts[: kin.n + 1] - frames[:, :3, 3] * 1000.0)) <= 0.5
    assert np.max(np.abs(pts[kin.n + 1] - tcp_mm)) <= 0.5
    # capsule of link 2 ends at the link-2 frame origin + R·(0.4, 0, 0)
    end = frames[2, :3, :3] @ np.array([0.4, 0, 0]) + frames[2, :3, 3]
    cap = data["shapes"][1]
    assert np.max(np.abs(pts[cap["i"][1]] - end * 1000.0)) <= 0.5
    assert data["t"][k] == pytest.approx(run.times[k]) and data["line"][k] == 7


def test_decimation_keeps_first_and_last():
    for k in (1, 5, 1999, 2000, 2001, 4001, 12480):
        idx = frame_indices(k)
        assert idx[0] == 0 and idx[-1] == k - 1 and len(idx) <= MAX_FRAMES
        assert np.all(np.diff(idx) > 0)
    long = make_run(duration=30.0)  # 3001 samples → decimated
    data = animation_data(long)
    assert len(data["t"]) <= MAX_FRAMES and data["t"][-1] == 30.0


CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]


@pytest.mark.skipif(CHROMIUM is None, reason="chromium is not installed")
def test_loads_in_headless_chromium(tmp_path):
    page = write_animation(_run_with_obstacles(), tmp_path / "anim.html")
    url = page.resolve().as_uri()
    with tempfile.TemporaryDirectory() as profile:
        dom = subprocess.run(
            [CHROMIUM, *FLAGS, f"--user-data-dir={profile}", "--virtual-time-budget=3000",
             "--dump-dom", url],
            capture_output=True, text=True, timeout=90,
        ).stdout  # fmt: skip
    assert f'<div id="{STATUS_ID}">ok</div>' in dom
    assert "t = 0.00 s" in dom and "line 7" in dom
    shot = tmp_path / "shot.png"
    with tempfile.TemporaryDirectory() as profile:
        subprocess.run(
            [CHROMIUM, *FLAGS, f"--user-data-dir={profile}", f"--screenshot={shot}",
             "--window-size=1000,700", url],
            capture_output=True, timeout=90, cwd=tmp_path,
        )  # fmt: skip
    mpimg = pytest.importorskip("matplotlib.image")
    img = mpimg.imread(shot)[:, :, :3]
    assert img.std() > 0.05  # not blank
    # the robot's links are drawn in saturated colours; the background is grey
    saturation = img.max(axis=2) - img.min(axis=2)
    assert (saturation > 0.3).mean() > 0.002
