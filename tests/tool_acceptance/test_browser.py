"""The animation opens offline in a real (headless) browser and draws something."""

from __future__ import annotations

import shutil
import subprocess
import tempfile
from pathlib import Path

import pytest

from .heldout import write_heldout
from .helpers import irlc

pytestmark = pytest.mark.scenario
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")


def screenshot(html: Path, png: Path, fragment: str = "") -> subprocess.CompletedProcess:
    with tempfile.TemporaryDirectory() as profile:
        return subprocess.run(
            [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
             "--no-first-run", "--disable-background-networking", "--disable-component-update",
             "--disable-sync", f"--user-data-dir={profile}", f"--screenshot={png}",
             "--window-size=1000,700", "--virtual-time-budget=3000",
             f"file://{html}{fragment}"],
            capture_output=True, text=True, timeout=60,
        )  # fmt: skip


@pytest.mark.skipif(CHROMIUM is None, reason="chromium not installed")
def test_animation_renders_in_headless_chromium(tmp_path):
    import matplotlib.image as mpimg
    import numpy as np

    prog = write_heldout(tmp_path)
    html = tmp_path / "a.html"
    assert irlc("run", prog, "-q", "--animate", html).rc == 0
    png = tmp_path / "shot.png"
    proc = screenshot(html, png, "#t=2.0")
    assert png.exists(), proc.stderr[-2000:]
    img = mpimg.imread(png)[..., :3]
    # not blank: many distinct colours and a real spread of brightness
    colours = np.unique((img * 255).astype(np.uint8).reshape(-1, 3), axis=0)
    assert len(colours) > 50, len(colours)
    assert img.std() > 0.05
    shutil.copy(png, Path(tempfile.gettempdir()) / "irlc_acceptance_animation.png")
