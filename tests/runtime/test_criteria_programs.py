"""R_CRITERION end to end: programs/square_energy.irl and programs/reach_mvr.irl against the
same programs under DISTANCE (what docs/ik.md claims, "ENERGY and MVR"), the places where
the local criteria do not help (so that the documentation stays true), and bad input with
its position and exit code."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from irlc import run_program
from irlc.cli import main
from irlc.robots import ROBOTS_DIR

PROGRAMS = Path(__file__).resolve().parents[2] / "programs"


def _variant(tmp_path, name: str, word: str, **options):
    """``name`` from programs/ with ``R_CRITERION := word`` (set, or replaced), run with
    the run ``options``."""
    source = (PROGRAMS / name).read_text(encoding="utf-8")
    if "R_CRITERION" in source:
        source = re.sub(r"R_CRITERION := '\w+'", f"R_CRITERION := '{word}'", source)
    else:
        source = source.replace("BEGIN\n", f"BEGIN\n  R_CRITERION := '{word}';\n", 1)
    path = tmp_path / f"{word.lower()}_{name}"
    path.write_text(source, encoding="utf-8")
    return run_program(path, datalist_path=[str(PROGRAMS)], **options)


def _column(run, name):
    return run.trace[:, run.trace_columns.index(name)]


def test_square_energy_needs_less_kinetic_energy_and_moves_the_heavy_joints_less(tmp_path):
    energy = run_program(PROGRAMS / "square_energy.irl")
    distance = _variant(tmp_path, "square_energy.irl", "DISTANCE")
    assert energy.status == distance.status == "ok"
    assert energy.report["duration_s"] == distance.report["duration_s"]  # the same path
    e_int = energy.report["kinetic_energy"]["integral_j_s"]
    d_int = distance.report["kinetic_energy"]["integral_j_s"]
    assert e_int < 0.6 * d_int  # 2936 against 5274 J·s
    # the integral from the trace agrees (Σ E_k Δt_k)
    t = _column(energy, "t_s")
    assert e_int == pytest.approx(np.sum(_column(energy, "kinetic_energy_j")[1:] * np.diff(t)))

    def travel(run):
        return np.abs(np.diff(run.q, axis=0)).sum(axis=0)

    heavy = [1, 2]  # J2, J3: the largest diagonal entries of M (1.6e5, 7.6e4 kg·m²)
    assert np.all(travel(energy)[heavy] < 0.2 * travel(distance)[heavy])


def test_reach_mvr_keeps_the_higher_velocity_ratio_near_the_singular_configuration(tmp_path):
    mvr = run_program(PROGRAMS / "reach_mvr.irl")
    distance = _variant(tmp_path, "reach_mvr.irl", "DISTANCE")
    assert mvr.status == distance.status == "ok"
    a, b = _column(mvr, "mvr"), _column(distance, "mvr")
    assert np.array_equal(_column(mvr, "t_s"), _column(distance, "t_s"))
    moving = (a > 0) & (b > 0)
    assert moving.sum() > 500
    assert np.all(a[moving] >= b[moving] - 1e-12)  # higher at every sample
    assert mvr.report["mvr"]["min"] > distance.report["mvr"]["min"] * 1.03
    # near the stretched arm: the manipulability (σ product) is small there
    assert mvr.report["ik"]["min_manipulability"] < 0.7


def test_where_the_local_criteria_do_not_help(tmp_path):
    """docs/ik.md, "Where they do not help": each case stays as documented."""
    # ENERGY raises the integral where obstacle avoidance bends the path of the joints
    energy = _variant(tmp_path, "obstacle_line_avoid.irl", "ENERGY")
    distance = _variant(tmp_path, "obstacle_line_avoid.irl", "DISTANCE")
    assert energy.status == distance.status == "ok"
    assert (
        energy.report["kinetic_energy"]["integral_j_s"]
        > 1.1 * distance.report["kinetic_energy"]["integral_j_s"]
    )
    # and its greed for the light wrist runs J11 into its limit on the plain square
    square = _variant(tmp_path, "square.irl", "ENERGY")
    assert square.status == "failed" and square.error.line == 14
    assert "a11 (J11) at its position max 90 deg" in str(square.error)
    # MVR, lap after lap on planar3_drift's square, drifts to a lower velocity ratio
    drift = _variant(tmp_path, "planar3_drift.irl", "MVR")
    weighted = _variant(tmp_path, "planar3_drift.irl", "DISTANCE")
    assert drift.status == weighted.status == "ok"
    assert drift.report["mvr"]["min"] < 0.7 * weighted.report["mvr"]["min"]


def test_freeze_holds_and_the_limits_bind_under_energy_and_mvr(tmp_path):
    """square_freeze.irl (J2, J3 frozen; J11 within 0 … 60°; the speed set 6.2) under each
    criterion: the frozen joints do not move, every joint stays within its bounds, and
    ENERGY takes less energy than DISTANCE (2697 against 4118 J·s)."""
    integral = {}
    for word in ("ENERGY", "MVR", "DISTANCE"):
        run = _variant(tmp_path, "square_freeze.irl", word)
        assert run.status == "ok", (word, run.error)
        on_path = _column(run, "line") >= 16  # the LIN statements (after FREEZESTART)
        q = np.degrees(run.q[on_path])
        assert np.ptp(q[:, 1]) < 1e-9 and np.ptp(q[:, 2]) < 1e-9  # J2, J3 held
        assert q[:, 10].min() > -1e-6 and q[:, 10].max() < 60 + 1e-6  # J11 in 0 … 60
        bounds = [50.0] * 9 + [500.0, 25.0]  # the speed set 6.2: deg/s, J10 mm/s
        for j, bound in enumerate(bounds, start=1):
            unit = "mm_s" if j == 10 else "deg_s"
            speed = np.abs(_column(run, f"a{j}_speed_{unit}")[on_path]).max()
            assert speed <= bound * (1 + 1e-9), (word, j, speed)
        integral[word] = run.report["kinetic_energy"]["integral_j_s"]
    assert integral["ENERGY"] < 0.8 * integral["DISTANCE"]


@pytest.mark.scenario
def test_energy_with_the_drives(tmp_path):
    """--drives coupled follows square_speed.irl under ENERGY (the speed set 6.2 keeps the
    light wrist within what its drives can do), with less energy than under DISTANCE; on
    square_energy.irl (no speed set) J9's drive cannot follow ENERGY's set points."""
    runs = {}
    for word in ("ENERGY", "DISTANCE"):
        run = _variant(tmp_path, "square_speed.irl", word, drives="coupled", **TOLERANT)
        assert run.status == "ok" and run.report["verdict"]["could_follow"], word
        runs[word] = run.report["kinetic_energy"]["integral_j_s"]
    assert runs["ENERGY"] < 0.6 * runs["DISTANCE"]  # 2571 against 5235 J·s
    fast = run_program(PROGRAMS / "square_energy.irl", drives="coupled", **TOLERANT)
    assert fast.status == "failed" and "a9 (J9) could not follow" in str(fast.error)


TOLERANT = {"path_tolerance": 10.0, "orientation_tolerance": 2.0}  # the drives lag (mm, deg)


KONF_0 = [-0.695, -75, -102, 115.205, -98.722, -76.097, -0.168, -21.813, -90.452, 227.313, 21.119]
"""square_cell's konf_0 (deg; J10 in mm), where square_cyclic.irl starts its laps."""


def test_cyclic_still_closes_the_square_under_energy_and_mvr(tmp_path):
    """square_cyclic.irl: three laps with CYCLIC from konf_0; the reference term is
    measured in the criterion's metric at θ⁰ (constant), so the laps end where they
    started — to 0.02 (deg, mm) under ENERGY, whose light wrist joints lag behind their
    weak pull when the arm stops (DISTANCE and MVR: 0.001)."""
    for word, tol in (("ENERGY", 0.02), ("MVR", 0.002), ("DISTANCE", 0.002)):
        run = _variant(tmp_path, "square_cyclic.irl", word)
        assert run.status == "ok" and len(run.report["output"]) == 3
        end = np.array(run.report["end_joints"])
        assert np.abs(end - KONF_0).max() < tol, (word, end - KONF_0)


COOPERATING = """PROGRAM pair;
ROBOT holder := as6;
ROBOT welder := as6 AT (0, -2200, 0, 180, 0, 0);
CONST
  MAIN_JOINT: start = (90, 45, 0, 45, 90, 0);
VAR
  POSE: grip, seam_end;
BEGIN
  R_CRITERION := 'WORD';
  MOVE holder PTP start AND welder PTP start;
  grip := INV(FK(holder, start)) : FK(welder, start);
  seam_end := grip : (200, 0, 0, 0, 0, 30);
  COOPERATE welder IN holder;
    MOVE welder LIN seam_end WITH SPEED := 100;
  COOPERATEEND;
ENDPROGRAM
"""


def test_energy_on_two_cooperating_robots_lowers_their_kinetic_energy(tmp_path):
    """ENERGY on a cooperating chain sums both robots' links (docs/ik.md): the seam costs
    the pair less kinetic energy than under DISTANCE, on the same path; each robot's
    ``kinetic_energy_j`` column is its own links' (the chain's M is block-diagonal)."""
    runs = {}
    for word in ("DISTANCE", "ENERGY"):
        path = tmp_path / f"{word.lower()}.irl"
        path.write_text(COOPERATING.replace("WORD", word), encoding="utf-8")
        runs[word] = run_program(path)
        assert runs[word].status == "ok", runs[word].report.get("error")

    def seam_energy(run):
        t, line = _column(run, "t_s"), _column(run, "line")
        total = _column(run, "holder_kinetic_energy_j") + _column(run, "welder_kinetic_energy_j")
        seam = line == 14
        return float(np.sum((total[1:] * np.diff(t))[seam[1:]]))

    energy, distance = seam_energy(runs["ENERGY"]), seam_energy(runs["DISTANCE"])
    assert runs["ENERGY"].report["duration_s"] == runs["DISTANCE"].report["duration_s"]
    assert 0.0 < energy < distance


def _write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


def _bare_arm(folder: Path) -> None:
    """planar3 without its [[inertials]]."""
    text = (ROBOTS_DIR / "planar3.toml").read_text(encoding="utf-8")
    start, end = text.index("[[inertials]]"), text.index("# The arm moves in the xy plane")
    _write(folder, "arm.toml", text[:start] + text[end:])


def _cli_run(tmp_path: Path, capsys, name: str, text: str):
    """``irlc run`` of the program ``text`` written to ``name``: ``(path, exit, stderr)``."""
    prog = _write(tmp_path, name, text)
    code = main(["run", str(prog)])
    out = capsys.readouterr()
    assert "Traceback" not in out.err and "internal error" not in out.err
    return prog, code, out.err


ON_THE_BARE_ARM = "PROGRAM p;\nROBOT r := 'arm.toml';\n{}ENDPROGRAM\n"
CONSTANT = "BEGIN\n  R_CRITERION := 'energy';\n  MOVE LIN POSE(2100, 900, 0, 0, 0, 0);\n"
COMPUTED = (
    "VAR STRING: c;\nBEGIN\n  c := 'ENE';\n  R_CRITERION := c + 'RGY';\n"
    "  MOVE PTP (0, 90, -90);\n  MOVE LIN POSE(2100, 900, 0, 0, 0, 0);\n"
)


def test_energy_on_a_robot_without_inertials_is_a_compile_error_at_the_value(tmp_path, capsys):
    _bare_arm(tmp_path)
    prog, code, err = _cli_run(tmp_path, capsys, "p.irl", ON_THE_BARE_ARM.format(CONSTANT))
    assert code == 1
    assert (
        f"{prog}:4:18: error: R_CRITERION := 'ENERGY' needs the links' inertia matrix: robot "
        f"planar3 has no [[inertials]] ({tmp_path / 'arm.toml'})"
    ) in err


def test_energy_computed_at_run_time_fails_at_the_motion_that_uses_it(tmp_path, capsys):
    _bare_arm(tmp_path)
    prog, code, err = _cli_run(tmp_path, capsys, "p.irl", ON_THE_BARE_ARM.format(COMPUTED))
    assert code == 2
    assert f"{prog}:8:3: error: run-time failure at t = " in err
    assert "R_CRITERION := 'ENERGY' needs the links' inertia matrix: robot planar3 has no" in err


def test_an_unknown_criterion_is_an_error_in_the_tables_words(tmp_path, capsys):
    prog, code, err = _cli_run(
        tmp_path,
        capsys,
        "p.irl",
        "PROGRAM p;\nROBOT r := planar3;\nBEGIN\n  R_CRITERION := 'POWER';\nENDPROGRAM\n",
    )
    assert code == 1
    assert (
        f"{prog}:4:18: error: R_CRITERION := 'POWER': the value must be one of 'DISTANCE', "
        "'ENERGY', 'MVR'"
    ) in err
    prog, code, err = _cli_run(
        tmp_path,
        capsys,
        "q.irl",
        "PROGRAM q;\nROBOT r := planar3;\nVAR STRING: c;\nBEGIN\n  c := 'MV';\n"
        "  R_CRITERION := c + 'P';\nENDPROGRAM\n",
    )
    assert code == 2
    assert f"{prog}:6:3: error: run-time failure" in err
    assert "R_CRITERION := 'MVP': the value must be one of 'DISTANCE', 'ENERGY', 'MVR'" in err
