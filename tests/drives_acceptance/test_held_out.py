"""Held-out acceptance of the simulated drives (issue 5) through the command line.

Four irb6_track programs written from the language spec (``programs/``): a track move with
arm motion, Szkodny's line test in miniature (LIN in the work area), a multi-joint PTP and
a very short move for the PWM level. Each runs as
``irlc run PROG --drives LEVEL --report r.json --trace t.csv``; every check below is
computed from those two files, independently of the drive code:

* exit 0; a finite ``max_following_error`` per joint in the report;
* trace columns ``<joint>_cmd_<unit>`` and ``<joint>_current_A``;
* the current clamp ``|i| ≤ 10 A`` at every sample;
* following errors of Szkodny's order: motor side (through the robot file's
  transmission) at most ``1.1·v_max/K_v`` — the steady error of a P position loop
  at the slave's speed limit (1.6 rad on the arm axes, K_v = 30 1/s; 4.8 rad on the
  track, K_v = 10 1/s) — and larger than zero (the drives really lag);
* settling: every program ends with ``WAIT 0.6 SEC`` (setpoints held); at the last
  sample actual and commanded agree within 0.02 rad on the motor side, 1/80 of
  ``v_max/K_v`` (0.011° on A2/A3 behind their 101:1 screws, 0.05 mm on the track): the
  A2/A3 screws' 0.33 N·m static friction leaves a stick–slip hunting of ≈ 0.01 rad under
  PWM (≤ 0.007 rad averaged);
* the verdict is the actual motion's: the programs are run with ``--path-tolerance 20``
  and ``--orientation-tolerance 1`` (mm, deg; the drives lag by ``v/K_v`` along the path,
  millimetres at these speeds — the default 0.05 mm would fail them, see
  tests/drives/test_verdict.py); the report's path error is the actual one and below it,
  the ideal one stays near zero under ``ideal``;
* decoupled vs coupled: the largest joint difference in % of the commanded range
  (Szkodny's measure), bounded by his 5.1 % simulation-vs-measurement agreement on
  joints that move more than 2° or 10 mm.
"""

from __future__ import annotations

import csv
import json
import math
import subprocess
import sys
from functools import cache
from pathlib import Path

import numpy as np
import pytest
from irlc.robots.loader import load_toml
from irlc.runtime.drives import drive_params
from irlc.runtime.drives.transmission import Transmission
from irlc.runtime.units import joint_unit, joints_to_si

HERE = Path(__file__).resolve().parent
ROBOT = HERE.parents[1] / "robots" / "irb6_track.toml"
PROGRAMS = ("track_arm", "line", "ptp_multi", "short")
PATH_TOLERANCE_MM = 20.0  # stated: the lag v/K_v of these drives along the path
ORIENTATION_TOLERANCE_DEG = 1.0
LEVELS = ("ideal", "decoupled", "coupled", "pwm")
CASES = [(p, lv) for p in PROGRAMS for lv in LEVELS if lv != "pwm" or p in ("short", "track_arm")]
SETTLED_MOTOR_RAD = 0.02
I_MAX = 10.0
UNITS = ("mm", "deg", "deg", "deg", "deg", "deg")  # irb6_track: T prismatic, A1–A5 revolute

pytestmark = pytest.mark.scenario


@cache
def robot():
    model = load_toml(ROBOT)
    params = drive_params(model)
    return model, params, Transmission(model, params)


@cache
def run_cli(program: str, level: str, tmp: str):
    out = Path(tmp) / f"{program}.{level}"
    report, trace = out.with_suffix(".json"), out.with_suffix(".csv")
    cmd = [sys.executable, "-c", "from irlc.cli import entry; entry()"]
    args = ["run", str(HERE / "programs" / f"{program}.irl"), "--drives", level]
    args += ["--path-tolerance", str(PATH_TOLERANCE_MM)]
    args += ["--orientation-tolerance", str(ORIENTATION_TOLERANCE_DEG)]
    proc = subprocess.run(
        [*cmd, *args, "--report", str(report), "--trace", str(trace), "-q"],
        capture_output=True,
        text=True,
        timeout=170,
    )
    assert proc.returncode == 0, proc.stderr + proc.stdout
    with trace.open(newline="") as f:
        rows = list(csv.DictReader(f))
    return json.loads(report.read_text()), rows


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    return str(tmp_path_factory.mktemp("drives_acceptance"))


def columns(report, rows):
    """(names, units, actual (k, n), commanded (k, n), currents (k, n)) in program units."""
    model, _, _ = robot()
    names = [j["name"] for j in report["joints"]]
    units = [joint_unit(j.kind) for j in model.joints]
    pairs = list(zip(names, units, strict=True))
    actual = np.array([[float(r[f"{n}_{u}"]) for n, u in pairs] for r in rows])
    cmd = np.array([[float(r[f"{n}_cmd_{u}"]) for n, u in pairs] for r in rows])
    cur = np.array([[float(r[f"{n}_current_A"]) for n in names] for r in rows])
    return names, units, actual, cmd, cur


def motor_error(actual, cmd):
    """Motor-side |actual − commanded| (rad) per sample and axis, through the transmission."""
    model, _, trans = robot()
    kinds = [j.kind for j in model.joints]
    q = np.array([joints_to_si(r, kinds) for r in actual])
    qc = np.array([joints_to_si(r, kinds) for r in cmd])
    return np.abs(trans.to_motor(q) - trans.to_motor(qc))


@pytest.mark.parametrize("program,level", CASES)
def test_program_at_level(program, level, workdir):
    report, rows = run_cli(program, level, workdir)
    assert report["status"] == "ok" and report["drives"] == level
    if level == "ideal":
        # actual = setpoint: the trace's joint columns are the setpoints themselves
        joints = zip(report["joints"], UNITS, strict=True)
        assert all(f"{j['name']}_{u}" in rows[0] for j, u in joints)
        # interfaces.md: the *_cmd_* / *_current_A columns come "with drives", and an ideal
        # run reports "max_following_error": null (its report example is an ideal run)
        assert not any(k.endswith("_current_A") or "_cmd_" in k for k in rows[0])
        assert all(j["max_following_error"] is None for j in report["joints"])
        return
    names, units, actual, cmd, cur = columns(report, rows)
    assert report["verdict"]["could_follow"] and report["drives_summary"]["could_follow"]
    assert report["verdict"]["criteria"]["path_tolerance_mm"] == PATH_TOLERANCE_MM
    assert report["max_path_error_mm"] <= PATH_TOLERANCE_MM
    assert report["ideal"]["max_path_error_mm"] < 1e-3
    if program == "line":  # a LIN (the others are PTP): the drives' lag is a path error
        assert report["max_path_error_mm"] > 100 * report["ideal"]["max_path_error_mm"]
    for n, u in zip(names, units, strict=True):
        assert f"{n}_cmd_{u}" in rows[0] and f"{n}_current_A" in rows[0]
    for j in report["joints"]:
        assert math.isfinite(j["max_following_error"])
    err = motor_error(actual, cmd)
    _, params, _ = robot()
    c = params.chain
    bound = 1.1 * params.slave.v_max / (c.kz / c.ke)
    assert np.all(np.abs(cur) <= I_MAX + 1e-9), "current clamp"
    assert np.all(err.max(axis=0) <= bound), (err.max(axis=0), bound)
    moved = np.ptp(cmd, axis=0) > 1e-3  # deg | mm
    assert np.all(err.max(axis=0)[moved] > 1e-3)  # the drives really lag
    # the report's error (every drive step) is at least the trace's (IPO samples)
    following = np.array([j["max_following_error"] for j in report["joints"]])
    assert np.all(following >= np.abs(actual - cmd).max(axis=0) - 1e-6)
    assert np.all(err[-1] <= SETTLED_MOTOR_RAD), err[-1]
    assert np.allclose(cmd[-1], cmd[-2])  # the last setpoints are held (the WAIT)


@pytest.mark.parametrize("program", ("track_arm", "line", "ptp_multi", "short"))
def test_decoupled_vs_coupled(program, workdir):
    rep_d, rows_d = run_cli(program, "decoupled", workdir)
    rep_c, rows_c = run_cli(program, "coupled", workdir)
    names, units, q_d, _, _ = columns(rep_d, rows_d)
    _, _, q_c, cmd, _ = columns(rep_c, rows_c)
    span = np.ptp(cmd, axis=0)
    dev = 100.0 * np.abs(q_d - q_c).max(axis=0) / np.where(span > 0.0, span, np.inf)
    print(f"\n{program}: decoupled vs coupled, % of the commanded range")
    for n, u, s, d in zip(names, units, span, dev, strict=True):
        print(f"  {n:3s} range {s:8.3f} {u:3s}  deviation {d:6.3f} %")
    big = span > np.where(np.array(units) == "mm", 10.0, 2.0)
    assert big.any()
    assert np.all(dev[big] <= 5.1), dev
