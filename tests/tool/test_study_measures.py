"""``irlc study`` sorts by the kinetic energy and the velocity ratio: the columns
``max_kinetic_energy_j``, ``kinetic_energy_integral_j_s``, ``min_mvr`` and ``max_mvr`` are
each variant's report values, and ``--sort`` ranks by them."""

from __future__ import annotations

import csv

import pytest
from irlc import run_program
from irlc.cli import main

from .test_study import CELL, PROGRAM  # the short planar3 line and its data list


def test_the_study_ranks_variants_by_their_kinetic_energy(tmp_path, capsys):
    (tmp_path / "p3.irl").write_text(PROGRAM)
    (tmp_path / "cell3.toml").write_text(CELL)
    study = tmp_path / "s.toml"
    study.write_text('program = "p3.irl"\n\n[grid]\n"robot.inertials.2.mass" = [4.0, 0.5, 1.0]\n')
    out = tmp_path / "out"
    args = ["study", str(study), "--out", str(out), "-j", "1"]
    assert main([*args, "--sort", "kinetic_energy_integral_j_s"]) == 0
    with (out / "results.csv").open(newline="") as f:
        rows = list(csv.DictReader(f))
    integral = [float(r["kinetic_energy_integral_j_s"]) for r in rows]
    assert integral[0] > integral[2] > integral[1]  # 4 kg > 1 kg > 0.5 kg on link 2
    # the plain run of the program is the 1 kg variant (the robot file's own mass)
    report = run_program(tmp_path / "p3.irl").report
    row = rows[2]
    assert row["kinetic_energy_integral_j_s"] == repr(report["kinetic_energy"]["integral_j_s"])
    assert row["max_kinetic_energy_j"] == repr(report["kinetic_energy"]["max_j"])
    assert row["min_mvr"] == repr(report["mvr"]["min"])
    assert row["max_mvr"] == repr(report["mvr"]["max"])
    summary = capsys.readouterr().out
    assert "by kinetic_energy_integral_j_s, smallest first" in summary
    best = next(line for line in summary.splitlines() if line.startswith("best"))
    assert best.split("│")[1].strip() == "1"  # variant 1: 0.5 kg
    for metric in ("max_kinetic_energy_j", "-min_mvr", "max_mvr"):
        assert main([*args, "--resume", "--sort", metric]) == 0


@pytest.mark.parametrize("metric", ["max_kinetic_energy_j", "min_mvr"])
def test_the_new_columns_are_metrics(metric):
    from irlc.study.metrics import RUN_COLUMNS, TEXT_COLUMNS

    assert metric in RUN_COLUMNS and metric not in TEXT_COLUMNS
