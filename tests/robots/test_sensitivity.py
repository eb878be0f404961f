"""Kinematic-parameter sensitivities (runtime/model/sensitivity.py) against finite differences of
robot files whose values were changed (the loader builds the perturbed robot: no code of
the module is used for the reference), and against closed forms the books give."""

from __future__ import annotations

import copy
import math
import re

import numpy as np
import pytest
from irlc.lang.toml_keys import parse_toml
from irlc.robots import ROBOTS_DIR, load_robot
from irlc.robots.loader import build_model
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.model.sensitivity import derivatives, dh_row, parameters, sensitivities

STEP = 1e-6  # file units (m, deg → scaled below)


def file_key(name: str, param) -> tuple[list, float]:
    """Where the parameter lives in the robot file's TOML tree, and the size of one file
    unit in SI (deg → rad)."""
    doc = parse_toml((ROBOTS_DIR / f"{name}.toml").read_text(encoding="utf-8"))
    joint_names = [j["name"] for j in doc["joints"]]
    deg = math.pi / 180.0
    if param.name.startswith("tool "):
        return ["tool", "xyz", "xyz".index(param.symbol)], 1.0
    if m := re.fullmatch(r"(.+) (θ|d)0", param.name):
        unit = deg if param.kind == "angle" else 1.0
        return ["joints", joint_names.index(m[1]), "offset"], unit
    if m := re.fullmatch(r"(.+) origin ([xyz])", param.name):
        k = "xyz".index(m[2])
        if m[1] == "flange":
            return ["joints", len(joint_names) - 1, "link", k], 1.0
        i = joint_names.index(m[1])
        if i == 0:
            return ["joints", 0, "origin", "xyz", k], 1.0
        return ["joints", i - 1, "link", k], 1.0  # origin of joint i = link of joint i−1
    joint, symbol = param.name.rsplit(" ", 1)
    key = {"a": "a", "d": "d", "α": "alpha", "θ": "theta"}[symbol]
    return ["joints", joint_names.index(joint), "dh", key], deg if param.kind == "angle" else 1.0


def perturbed_tcp(name: str, param, delta: float, q: np.ndarray) -> np.ndarray:
    doc = parse_toml((ROBOTS_DIR / f"{name}.toml").read_text(encoding="utf-8"))
    path, unit = file_key(name, param)
    doc = copy.deepcopy(doc)
    node = doc
    for k in path[:-1]:
        node = node[k]
    last = path[-1]
    if isinstance(node, dict) and last not in node:
        node[last] = 0.0
    node[last] = float(node[last]) + delta / unit
    model = build_model(doc, f"{name}.toml", ROBOTS_DIR)
    return Kinematics(model).tcp(q)


@pytest.mark.parametrize("name", ["irb6", "l1", "as6", "koch11", "irb6_track"])
def test_derivatives_match_finite_differences_of_edited_robot_files(name):
    model = load_robot(name)
    params = parameters(model)
    rng = np.random.default_rng(3)
    lim = model.position_limits
    for q in [model.home_q(), rng.uniform(lim[:, 0], lim[:, 1])]:
        dp, dw = derivatives(model, params, q)
        for k, p in enumerate(params):
            plus, minus = (perturbed_tcp(name, p, s * STEP, q) for s in (1, -1))
            fd_p = (plus[:3, 3] - minus[:3, 3]) / (2 * STEP)
            r_dot = (plus[:3, :3] - minus[:3, :3]) / (2 * STEP)
            w_hat = r_dot @ Kinematics(model).tcp(q)[:3, :3].T
            fd_w = np.array([w_hat[2, 1], w_hat[0, 2], w_hat[1, 0]])
            assert np.allclose(dp[k], fd_p, atol=1e-6), (p.name, dp[k], fd_p)
            assert np.allclose(dw[k], fd_w, atol=1e-6), (p.name, dw[k], fd_w)


def test_dh_rows_are_recovered_from_the_irb6_file():
    """Szkodny's Table 5.1 (λ1 = 0.70, l2 = 0.45, l3 = 0.67, λ5 = 0.095 m; α 90, 0, 0, 90, 0)."""
    by_name = {p.name: p.value for p in parameters(load_robot("irb6"))}
    expected = {"A1 d": 0.70, "A2 a": 0.45, "A3 a": 0.67, "A5 d": 0.095, "tool z": 0.15}
    for key, value in expected.items():
        assert by_name[key] == pytest.approx(value, abs=1e-12)
    alphas = [math.degrees(by_name[f"A{i} α"]) for i in range(1, 6)]
    assert alphas == pytest.approx([90, 0, 0, 90, 0], abs=1e-9)
    assert dh_row(np.diag([1.0, -1.0, -1.0, 1.0])) is not None  # α = 180°
    assert dh_row(np.array([[0, 0, 1.0, 0], [0, 1, 0, 0], [-1, 0, 0, 0], [0, 0, 0, 1]])) is None


def test_lengths_shift_the_end_point_by_their_own_size_and_angles_by_the_lever():
    """A length parameter translates the rest of the chain: |S p| = |p| at every
    configuration (e.g. the IRb-6's l2 = 450 mm, the closed form (5.3)'s ∂d/∂l2 has norm 1);
    an angle turns it: |S p| = |p| · (distance of the TCP from the axis)."""
    model = load_robot("irb6")
    rows = {s.parameter.name: s for s in sensitivities(model, samples=50)}
    assert rows["A2 a"].position_m == pytest.approx(0.45) == rows["A2 a"].position_max_m
    assert rows["A2 a"].orientation_max_rad == 0.0
    kin = Kinematics(model)
    frames = kin.link_frames(model.home_q())
    axes, origins = kin.joint_axes_world(frames)
    tcp = kin.tcp_from_frames(frames)[:3, 3]
    lever = np.linalg.norm(np.cross(axes[1], tcp - origins[1]))
    assert rows["A2 θ0"].position_m == pytest.approx(lever * math.pi / 2)
    assert rows["A2 θ0"].orientation_rad == pytest.approx(math.pi / 2)


def test_cli_prints_the_sensitivity_table(capsys):
    from irlc.cli import main

    assert main(["robot", "irb6", "--sensitivity", "--samples", "20"]) == 0
    out = capsys.readouterr().out
    assert "|S_k p_k| of the kinematic parameters" in out and "max over 20" in out
    row = next(line for line in out.splitlines() if line.strip().startswith("A2 a "))
    assert row.split()[2:6] == ["450", "mm", "450", "450"]
    assert main(["robot", "irb6", "--sensitivity", "--samples", "0"]) != 0
