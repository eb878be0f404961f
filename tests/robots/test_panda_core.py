"""panda on a core install: the shipped robots/panda.toml is the URDF import written in the
core format (robots/toml_export.py), so it loads without the optional yourdfpy; a robot that
does need an extra says so in ``irlc robots`` and in its load error."""

from __future__ import annotations

import math
import re
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from irlc.cli import cli
from irlc.robots import ROBOTS_DIR, RobotFileError, clear_cache, load_robot
from irlc.robots.loader import MissingExtraError, load_toml
from irlc.robots.toml_export import generated_header, model_to_toml

CORE = ROBOTS_DIR / "panda.toml"
URDF_BACKED = ROBOTS_DIR / "urdf" / "panda.toml"


@pytest.fixture
def no_yourdfpy(monkeypatch):
    """A core install: ``import yourdfpy`` fails (``sys.modules[name] = None``)."""
    monkeypatch.setitem(sys.modules, "yourdfpy", None)
    clear_cache()
    yield
    clear_cache()


def _same_transform(a: np.ndarray, b: np.ndarray) -> bool:
    return np.allclose(a, b, rtol=0.0, atol=1e-12)


def test_core_panda_equals_the_urdf_import():
    pytest.importorskip("yourdfpy")
    urdf = load_toml(URDF_BACKED)
    core = load_toml(CORE)
    assert (core.name, core.description) == (urdf.name, urdf.description)
    assert core.joint_names == urdf.joint_names and core.joint_kinds == urdf.joint_kinds
    for a, b in zip(core.joints, urdf.joints, strict=True):
        assert _same_transform(a.origin, b.origin) and np.allclose(a.axis, b.axis, atol=1e-15)
        for k in ("position", "speed", "accel"):
            assert np.allclose(getattr(a.limits, k), getattr(b.limits, k), rtol=1e-15, atol=0)
        assert (a.weight, a.offset) == (b.weight, b.offset)
    for k in ("base", "flange", "tool"):
        assert _same_transform(getattr(core, k), getattr(urdf, k)), k
    assert np.allclose(core.home, urdf.home, atol=1e-15)
    assert np.array_equal(core.gravity, urdf.gravity)
    assert len(core.geometry) == len(urdf.geometry) == 12
    for a, b in zip(core.geometry, urdf.geometry, strict=True):
        assert type(a) is type(b) and a.link == b.link and a.radius == b.radius
        fields = ("a", "b") if hasattr(a, "a") else ("center",)
        assert all(np.array_equal(getattr(a, f), getattr(b, f)) for f in fields)
    assert len(core.inertials) == len(urdf.inertials) == 8
    for a, b in zip(core.inertials, urdf.inertials, strict=True):
        assert (a.link, a.mass, a.assumed) == (b.link, b.mass, b.assumed)
        assert np.array_equal(a.com, b.com)
        assert np.allclose(a.inertia, b.inertia, rtol=0.0, atol=1e-15)  # written symmetric
    assert set(urdf.extra["assumed"]) <= set(core.extra["assumed"])


NUMBER = re.compile(r"-?\d+\.\d*(?:e[-+]?\d+)?|-?\d+e[-+]?\d+")


def _same_text_and_numbers(a: str, b: str) -> bool:
    """The same text with the same numbers to 1e-12 (relative; 1e-15 absolute): the
    URDF's chain products round differently in the last bit on another CPU's numpy
    kernels (seen: AVX2 against AVX-512), which is no staleness."""
    words_a, words_b = NUMBER.split(a), NUMBER.split(b)
    nums_a, nums_b = NUMBER.findall(a), NUMBER.findall(b)
    return (
        words_a == words_b
        and len(nums_a) == len(nums_b)
        and all(
            math.isclose(float(x), float(y), rel_tol=1e-12, abs_tol=1e-15)
            for x, y in zip(nums_a, nums_b, strict=True)
        )
    )


def test_core_panda_file_is_current():
    """Regenerating from the URDF-backed source gives the shipped file: the same text and
    the same numbers to round-off (:func:`_same_text_and_numbers`)."""
    pytest.importorskip("yourdfpy")
    src, out = Path("robots/urdf/panda.toml"), Path("robots/panda.toml")
    text = model_to_toml(load_toml(URDF_BACKED), generated_header(src, out))
    assert _same_text_and_numbers(text, CORE.read_text(encoding="utf-8")), (
        "robots/panda.toml is stale: python -m irlc.robots.toml_export "
        "robots/urdf/panda.toml robots/panda.toml"
    )


def test_the_staleness_check_sees_a_changed_number_but_not_round_off():
    text = CORE.read_text(encoding="utf-8")
    first = NUMBER.search(text)
    assert first is not None
    value = float(first.group())
    head, tail = text[: first.start()], text[first.end() :]
    assert _same_text_and_numbers(head + repr(value * (1 + 1e-15)) + tail, text)
    assert not _same_text_and_numbers(head + repr(value * 1.001 + 1e-9) + tail, text)
    assert not _same_text_and_numbers(text.replace("panda_joint4", "panda_jointX", 1), text)


def test_panda_loads_and_lists_without_yourdfpy(no_yourdfpy):
    model = load_robot("panda")
    assert model.n == 7 and model.joint_names[3] == "panda_joint4"
    assert np.allclose(model.accel_limits[:, 1], [15, 7.5, 10, 12.5, 15, 20, 20])
    result = CliRunner().invoke(cli, ["robots"], env={"COLUMNS": "240"})
    assert result.exit_code == 0, result.output
    panda = next(line for line in result.output.splitlines() if "│ panda " in line)
    assert "RRRRRRR" in panda


def test_urdf_file_without_yourdfpy_names_the_extra(no_yourdfpy):
    with pytest.raises(MissingExtraError) as err:
        load_robot(URDF_BACKED)
    assert err.value.extra == "urdf"
    assert "pip install 'irlc[urdf]'" in str(err.value) and "panda.urdf" in str(err.value)
    assert isinstance(err.value, RobotFileError)


def test_robots_lists_every_robot_even_one_that_needs_an_extra(no_yourdfpy, tmp_path, monkeypatch):
    """A library robot backed by a URDF: its row says which extra it needs; the listing
    still exits 0 and shows the others; so does a malformed file."""
    import irlc.robots as robots

    shutil.copy(ROBOTS_DIR / "planar3.toml", tmp_path / "planar3.toml")
    (tmp_path / "urdf").mkdir()
    shutil.copy(ROBOTS_DIR / "urdf" / "panda.urdf", tmp_path / "urdf" / "panda.urdf")
    text = URDF_BACKED.read_text(encoding="utf-8").replace('"panda.urdf"', '"urdf/panda.urdf"')
    (tmp_path / "pandaurdf.toml").write_text(text, encoding="utf-8")
    (tmp_path / "broken.toml").write_text("[robot\n", encoding="utf-8")
    monkeypatch.setattr(robots, "ROBOTS_DIR", tmp_path)
    result = CliRunner().invoke(cli, ["robots"], env={"COLUMNS": "240"})
    assert result.exit_code == 0, result.output
    rows = {line.split("│")[1].strip(): line for line in result.output.splitlines() if "│" in line}
    assert "RRR" in rows["planar3"]
    assert "pip install 'irlc[urdf]'" in rows["pandaurdf"]
    assert "cannot load" in rows["broken"]


def test_program_on_panda_compiles_and_runs_without_yourdfpy(no_yourdfpy, tmp_path):
    """The issue's case: ``ROBOT r := panda;`` after ``pip install .`` alone."""
    from irlc import run_program

    program = tmp_path / "p.irl"
    program.write_text(
        "PROGRAM p;\nROBOT r := panda;\nBEGIN\n  MOVE PTP (0, -30, 0, -120, 0, 90, 45);\n"
        "ENDPROGRAM\n",
        encoding="utf-8",
    )
    run = run_program(program)
    assert run.status == "ok", run.error
    assert np.allclose(run.report["end_joints"], [0, -30, 0, -120, 0, 90, 45], atol=1e-6)
