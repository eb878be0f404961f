"""``resolve_robot`` (the one naming rule + cache), unreadable robot files, the IK command's
input checks and JSON, and coupled limits of prismatic joints in program units (mm)."""

from __future__ import annotations

import json
import math
import os

import numpy as np
import pytest
from irlc.cli import main
from irlc.robots import RobotFileError, UnknownRobotError, list_robots, loader, resolve_robot
from irlc.runtime import units
from irlc.runtime.ik.coupled import CoupledRows
from irlc.runtime.ik.pose import solve_pose
from irlc.runtime.model.coupled_limits import coupled_limits, describe, row_label, violations
from irlc.runtime.model.kinematics import Kinematics

SLIDE = """\
[robot]
name = "slide"
description = "two slides along x, one along y"
chain = "axes"
units = { angle = "deg", length = "mm" }
home = [100.0, 100.0, 0.0]
"""
for _name, _axis, _lo in (("d1", "x", 0.0), ("d2", "x", 0.0), ("d3", "y", -400.0)):
    SLIDE += f"""
[[joints]]
name = "{_name}"
kind = "prismatic"
axis = "{_axis}"
link = [0.0, 0.0, 0.0]
position = [{_lo}, 400.0]
speed = 100.0
accel = 1000.0
"""
SLIDE += '\n[[coupled_limits]]\nname = "d1+d2"\ncoeffs = [1, 1, 0]\nmax = 500.0\n'


def run(capsys, *args: str) -> tuple[int, str, str]:
    code = main(list(args))
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.fixture
def slide(tmp_path):
    path = tmp_path / "slide.toml"
    path.write_text(SLIDE, encoding="utf-8")
    return path


@pytest.fixture
def garbage(tmp_path):
    path = tmp_path / "garbage.toml"
    path.write_bytes(b'[robot]\nname = "x"\n\xff\xfe\x00binary')
    return path


# ----------------------------------------------------------------------------- resolve_robot


def test_library_names_are_case_insensitive():
    assert resolve_robot("PLANAR3").name == resolve_robot("planar3").name == "planar3"


def test_unknown_name_lists_the_library():
    with pytest.raises(UnknownRobotError) as info:
        resolve_robot("nosuch")
    assert str(info.value) == f"unknown robot 'nosuch' (known: {', '.join(list_robots())})"
    assert isinstance(info.value, LookupError)  # what the compiler's resolvers raise


def test_path_relative_to_base_dir_first_then_as_given(tmp_path, monkeypatch, slide):
    other = tmp_path / "cwd"
    other.mkdir()
    (other / "slide.toml").write_text(SLIDE.replace('"slide"', '"cwd_slide"', 1), "utf-8")
    monkeypatch.chdir(other)
    assert resolve_robot("slide.toml", tmp_path).name == "slide"  # base_dir wins
    assert resolve_robot("slide.toml", tmp_path / "nowhere").name == "cwd_slide"  # as given
    with pytest.raises(RobotFileError, match="file not found"):
        resolve_robot("missing.toml", tmp_path)


def test_cache_reads_a_file_once_and_again_after_an_edit(slide, monkeypatch):
    calls = []
    real = loader.build_model
    monkeypatch.setattr(loader, "build_model", lambda *a: calls.append(1) or real(*a))
    first = resolve_robot(str(slide))
    assert resolve_robot(slide.name, slide.parent) is first and len(calls) == 1
    slide.write_text(SLIDE.replace('"slide"', '"slide2"', 1), encoding="utf-8")
    os.utime(slide, ns=(1, 10**18))  # a different mtime even on coarse clocks
    assert resolve_robot(str(slide)).name == "slide2" and len(calls) == 2


def test_non_utf8_robot_file_names_the_file(garbage):
    with pytest.raises(RobotFileError, match=r"garbage\.toml: not a UTF-8 text file"):
        resolve_robot(str(garbage))


@pytest.mark.parametrize("cmd", [["robot"], ["fk"], ["ik"]])
def test_cli_non_utf8_robot_file_is_a_usage_error(capsys, garbage, cmd):
    extra = {"robot": [], "fk": ["0", "0", "0"], "ik": ["0"] * 6}[cmd[0]]
    code, _, err = run(capsys, *cmd, str(garbage), *extra)
    assert code == 3
    assert "garbage.toml: not a UTF-8 text file (byte 0xff on line 3)" in err
    assert "internal error" not in err and "Traceback" not in err


# ----------------------------------------------------------------------------- irlc ik


def _strict_json(text: str) -> dict:
    def reject(name):
        raise AssertionError(f"non-finite JSON constant {name}")

    return json.loads(text, parse_constant=reject)


def test_ik_seed_outside_limits_is_a_usage_error(capsys):
    code, out, err = run(
        capsys, "ik", "planar3", "2000", "1000", "0", "0", "0", "0", "--seed", "0", "90", "500",
        "--json",
    )  # fmt: skip
    assert code == 3 and out == ""
    assert "seed joint a3 (J3) = 500 deg is outside its position max 180 deg" in err


@pytest.mark.parametrize("x", ["1e300", "-2e9"])
def test_ik_absurd_target_is_a_usage_error(capsys, x):
    code, out, err = run(capsys, "ik", "planar3", x, "0", "0", "0", "0", "0", "--json")
    assert code == 3 and out == "" and "out of range" in err


def _tcp_mm(joints: list[float]) -> tuple[float, ...]:
    q = units.joints_to_si(joints, ["revolute"] * 3)
    return units.pose_from_si(Kinematics(resolve_robot("planar3")).tcp(q))


def test_ik_json_errors_are_finite_and_rounded(capsys):
    # 500 mm beyond the 3 m reach: not converged; the error is the distance FK(joints)–target
    code, out, _ = run(capsys, "ik", "planar3", "3500", "0", "0", "0", "0", "0", "--json")
    data = _strict_json(out)
    assert code == 2 and data["converged"] is False
    x, y, *_ = _tcp_mm(data["joints"])
    assert data["position_error_mm"] == pytest.approx(math.hypot(x - 3500, y), abs=1e-5)
    assert data["position_error_mm"] >= 500.0 - 1e-6  # nothing is closer than the reach
    for key in ("position_error_mm", "orientation_error_deg"):
        assert data[key] == round(data[key], 9)


def test_ik_json_converged_errors_are_rounded(capsys):
    code, out, _ = run(capsys, "ik", "planar3", "1500", "500", "0", "0", "0", "0", "--json")
    data = _strict_json(out)
    assert code == 0 and data["converged"]
    x, y, *_ = _tcp_mm(data["joints"])
    assert data["position_error_mm"] == pytest.approx(math.hypot(x - 1500, y - 500), abs=1e-6)
    for key in ("position_error_mm", "orientation_error_deg"):
        assert data[key] == round(data[key], 9) and data[key] < 1e-3


# ----------------------------------------------------------------------------- coupled, mm


def test_prismatic_coupled_limit_is_labelled_in_mm(slide):
    model = resolve_robot(str(slide))
    (c,) = coupled_limits(model)
    assert c.kind == "prismatic" and c.upper == pytest.approx(0.5)
    assert row_label(c, "max") == "d1+d2 max 500 mm"
    (v,) = violations((c,), np.array([0.3, 0.3, 0.0]))
    assert describe(v).endswith("value 600.000 beyond upper bound 500.000 by 100.000 mm")
    assert CoupledRows(model).describe_row(0) == "coupled limit d1+d2 max 500 mm"


def test_revolute_coupled_limit_stays_in_degrees():
    c = next(c for c in coupled_limits(resolve_robot("irb6")) if c.name == "theta2+theta3")
    assert (row_label(c, "min"), row_label(c, "max")) == (
        "theta2+theta3 min -40 deg",
        "theta2+theta3 max 25 deg",
    )


def test_pose_solver_reports_the_prismatic_coupled_limit_in_mm(slide):
    model = resolve_robot(str(slide))
    sol = solve_pose(model, units.pose_to_si(700, 0, 0, 0, 0, 0), model.home_q())
    assert not sol.converged
    assert sol.position_error == pytest.approx(0.2, abs=1e-6)  # d1 + d2 ≤ 500 mm
    assert "(coupled limits reached: d1+d2 max 500 mm)" in sol.message
    seed = np.array([0.3, 0.3, 0.0])
    bad = solve_pose(model, units.pose_to_si(300, 0, 0, 0, 0, 0), seed)
    assert "by 100.000 mm" in bad.message
    assert math.isfinite(bad.position_error) and bad.position_error == pytest.approx(0.3)
