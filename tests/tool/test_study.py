"""``irlc study``: study files, checks before anything runs, workers, resume, failing rows.

The runs are a short planar3 program (one 0.5 m line, < 1 s simulated) so that a study of a
few variants takes seconds; the expensive ones (process pools, a Dask cluster) are marked
``scenario``.
"""

from __future__ import annotations

import csv
import json
import math
import shutil
from pathlib import Path

import numpy as np
import pytest
from irlc import run_program
from irlc.cli import main
from irlc.study import StudyError, read_study, run_study
from irlc.study.expand import variants
from irlc.study.spec import key_line

PROGRAM = """PROGRAM p3;
ROBOT r := planar3;
IMPORT DATALIST cell3;

BEGIN
  R_SPEED := 800;
  R_ACC := 4000;
  MOVE PTP home;
  MOVE LIN sq_1;
ENDPROGRAM
"""
MOVE_LINE = 9  # the MOVE LIN line of PROGRAM

CELL = """[poses]
sq_1 = [1500, 1000, 0, 0, 0, 0]

[joints]
home = [0, 90, -90]

[obstacles.post]
kind = "sphere"
center = [1700, 1300, 0]
radius = 100
"""


@pytest.fixture
def cell(tmp_path: Path) -> Path:
    (tmp_path / "p3.irl").write_text(PROGRAM)
    (tmp_path / "cell3.toml").write_text(CELL)
    return tmp_path


def write_study(folder: Path, body: str, name: str = "s.toml") -> Path:
    path = folder / name
    path.write_text('program = "p3.irl"\n\n' + body)
    return path


def rows(folder: Path) -> list[dict[str, str]]:
    with (folder / "results.csv").open(newline="") as f:
        return list(csv.DictReader(f))


# --------------------------------------------------------------------------- expansion


def test_grid_is_every_combination_first_key_slowest(cell):
    study = read_study(write_study(cell, '[grid]\n"run.ipo" = [0.01, 0.02]\n'
                                         'robot.joints.2.weight = [1, 2, 3]\n'))  # fmt: skip
    got = list(variants(study))
    assert [i for i, _ in got] == list(range(6))
    assert [v for _, v in got] == [
        (0.01, 1), (0.01, 2), (0.01, 3), (0.02, 1), (0.02, 2), (0.02, 3),
    ]  # fmt: skip


def test_random_is_seeded_deterministic_and_crossed_with_the_grid(cell):
    body = (
        '[grid]\n"run.ipo" = [0.01, 0.02]\n\n[random]\nn = 5\nseed = 42\n'
        '"datalist.cell3.obstacles.post.radius" = { uniform = [50, 150] }\n'
        '"robot.joints.2.weight" = { normal = [2, 0.1] }\n'
    )
    study = read_study(write_study(cell, body))
    first, again = list(variants(study)), list(variants(read_study(study.file)))
    assert first == again and len(first) == 10
    # the documented draw: one PCG64 stream, keys in file order, n values per key
    rng = np.random.Generator(np.random.PCG64(42))
    radius, weight = rng.uniform(50, 150, 5), rng.normal(2, 0.1, 5)
    for g, ipo in enumerate((0.01, 0.02)):
        for i in range(5):
            index, values = first[g * 5 + i]
            assert index == g * 5 + i
            assert values == (ipo, float(radius[i]), float(weight[i]))
    assert all(50 <= r < 150 for r in radius)
    other = read_study(write_study(cell, body.replace("seed = 42", "seed = 43"), "t.toml"))
    assert list(variants(other)) != first


def test_dotted_and_quoted_keys_name_the_same_path(cell):
    a = read_study(write_study(cell, '[grid]\n"robot.joints.2.weight" = [1]\n', "a.toml"))
    b = read_study(write_study(cell, "[grid.robot.joints.2]\nweight = [1]\n", "b.toml"))
    assert a.keys == b.keys == ["robot.joints.2.weight"]


# --------------------------------------------------------------------------- checks

HUGE = "1" + "0" * 400
BAD = [
    # (body, the text of the offending line, words of the message)
    ('[grid]\n"robot.joints.2.weight" = [1.0, -4.0]\n', '"robot.joints.2.weight"', "positive"),
    ('[grid]\n"robot.joints.2.wieght" = [1.0]\n', '"robot.joints.2.wieght"', "unknown key"),
    ('[grid]\n"robot.joints.7.weight" = [1.0]\n', '"robot.joints.7.weight"', "outside 1"),
    ('[grid]\nrobot.joints.2.weight = ["x"]\n', "robot.joints.2.weight", "expected a number"),
    ('[grid]\n"datalist.cell3.obstacles.post.radius" = [2, -5]\n', "post.radius", "positive"),
    ('[grid]\n"datalist.cell3.poses.sq_1" = [[1, 2, 3]]\n', "poses.sq_1", "6 values"),
    ('[grid]\n"datalist.cell4.poses.sq_1" = [1]\n', "cell4", "imports: cell3"),
    ('[grid]\n"run.ipo" = [0.01, -1]\n', '"run.ipo"', "must be in"),
    ('[grid]\n"run.drives" = ["fast"]\n', '"run.drives"', "ideal"),
    ('[grid]\n"run.path_tolrance" = [1]\n', "path_tolrance", "unknown run option"),
    ("[grid]\nfoo.bar = [1]\n", "foo.bar", "unknown key"),
    ('[grid]\n"run.ipo" = []\n', '"run.ipo"', "non-empty list"),
    ('[grid]\n"run.ipo" = [0.01, 0.02, 0.01]\n', '"run.ipo"', "value 0.01 is listed twice"),
    ('[grid]\n"run.override" = [50, 50.0]\n', '"run.override"', "value 50.0 is listed twice"),
    (
        '[random]\nn = 0\nseed = 1\n"run.ipo" = { uniform = [0.01, 0.02] }\n',
        "n = 0",
        "1 to 10,000,000",
    ),
    ('[random]\nn = 3\nseed = 1\n"run.ipo" = { uniform = [0.02, 0.01] }\n', '"run.ipo"', "a < b"),
    ('[random]\nn = 3\nseed = 1\n"run.ipo" = { gauss = [1, 2] }\n', '"run.ipo"', "uniform"),
    # a random key is checked at its extreme samples: weights around 0.1 ± 1 go negative
    (
        '[random]\nn = 50\nseed = 1\n"robot.joints.1.weight" = { normal = [0.1, 1] }\n',
        '"robot.joints.1.weight"',
        "positive",
    ),
    ("[grid.robot.joints.2]\nspeed = [1, 0]\n", "speed = [1, 0]", "positive"),
    (
        '[run]\nipo = "fast"\n\n[grid]\n"run.drives" = ["ideal"]\n',
        'ipo = "fast"',
        'run.ipo: expected a number, got "fast"; the value must be in',
    ),
    # one key twice in [grid] (two spellings): not "varied both in [grid] and in [random]"
    (
        '[grid]\n"run.override" = [50]\nrun.override = [60]\n',
        '"run.override"',
        "grid.run.override: varied twice in [grid] (two spellings of one key)",
    ),
    ('colour = 1\n[grid]\n"run.ipo" = [0.01]\n', "colour", "unknown key"),
    ('robot = "nosuch"\n[grid]\n"run.ipo" = [0.01]\n', "nosuch", "unknown robot"),
    ('[grid]\n"run.drives" = ["ideal", "decoupled"]\n', '"run.drives"', "no drive data"),
    ('[grid]\n"run.override" = [50, 150]\n', '"run.override"', "[1, 100] %"),
    ('[run]\nmax_time = 0\n[grid]\n"run.ipo" = [0.01]\n', "max_time", "positive"),
    ('[grid]\n"run.seed_config" = [[0, 90, -90], [1, 2]]\n', "seed_config", "has 3 joints"),
    # non-finite values are the owner's to refuse, described (never "nan" in a message)
    ('[grid]\n"datalist.cell3.poses.sq_1.x" = [nan]\n', "sq_1.x", "value not-a-number"),
    ('[grid]\n"datalist.cell3.poses.sq_1.x" = [-inf]\n', "sq_1.x", "numbers must be finite"),
    ('[grid]\n"run.seed_config" = [[nan, 0, 0]]\n', "seed_config", "[not-a-number, 0, 0]"),
    # samples a float cannot hold: numpy's OverflowError (uniform) or infinite draws (normal)
    (
        '[random]\nn = 3\nseed = 1\n"run.ipo" = { uniform = [-1e308, 1e308] }\n',
        '"run.ipo"',
        "samples beyond a float's range",
    ),
    (
        '[random]\nn = 3\nseed = 1\n"run.ipo" = { normal = [0, 1e307] }\n',
        '"run.ipo"',
        "samples beyond a float's range",
    ),
    # integers a float cannot hold (TOML's have any size): named, never echoed (exit 4 before)
    (
        f'[random]\nn = 3\nseed = 1\n"run.ipo" = {{ uniform = [0, {HUGE}] }}\n',
        '"run.ipo"',
        "uniform: expected two finite numbers",
    ),
    (
        f'[random]\nn = 3\nseed = 1\n"run.ipo" = {{ normal = [{HUGE}, 1] }}\n',
        '"run.ipo"',
        "normal: expected two finite numbers",
    ),
    (
        f'[random]\nn = {HUGE}\nseed = 1\n"run.ipo" = {{ uniform = [0.01, 0.02] }}\n',
        "n = ",
        "random.n: must be 1 to 10,000,000, got an integer of about 401 digits",
    ),
    (f'[run]\nmax_time = {HUGE}\n[grid]\n"run.ipo" = [0.01]\n', "max_time", "401 digits"),
    (f'[grid]\n"run.seed_config" = [[{HUGE}, 0, 0]]\n', "seed_config", "401 digits, 0, 0]"),
    (f'[grid]\n"run.path_tolerance" = [-{HUGE}]\n', "path_tolerance", "positive number"),
]


@pytest.mark.parametrize(("body", "marker", "words"), BAD)
def test_bad_study_files_name_the_line_before_anything_runs(cell, capsys, body, marker, words):
    path = write_study(cell, body)
    line = next(i for i, t in enumerate(path.read_text().splitlines(), 1) if marker in t)
    assert main(["study", str(path), "--out", str(cell / "out"), "-q"]) == 3
    err = capsys.readouterr().err
    assert f"s.toml:{line}:" in err and words in err, err
    assert "Traceback" not in err and "nan" not in err
    assert not (cell / "out" / "results.csv").exists()  # nothing ran


def test_key_line_finds_quoted_dotted_and_table_keys():
    text = '[grid]\n"a.b" = [1]\nc . "d" = [2]\n\n[random.e]\nf = 3\n'
    assert key_line(text, "grid.a.b") == 2
    assert key_line(text, "grid.c.d") == 3
    assert key_line(text, "random.e.f") == 6
    assert key_line(text, "random.e.g") == 5  # the table that would hold it


def test_missing_program_and_invalid_toml(cell, capsys):
    path = cell / "s.toml"
    path.write_text('program = "nope.irl"\n[grid]\n"run.ipo" = [0.01]\n')
    assert main(["study", str(path), "-q"]) == 3
    assert "s.toml:1: program: nope.irl: no such file" in capsys.readouterr().err
    path.write_text('program = "p3.irl"\n[grid\n')
    assert main(["study", str(path), "-q"]) == 3
    assert "s.toml:2: invalid TOML" in capsys.readouterr().err


def test_an_out_that_cannot_be_a_folder_is_a_usage_error(cell, capsys):
    # --out /dev/null was an internal error (FileExistsError from mkdir)
    path = write_study(cell, '[grid]\n"run.ipo" = [0.01]\n')
    (cell / "plain").write_text("x")
    for out, words in ((cell / "plain", "not a folder (--out takes a folder)"),
                       (cell / "plain" / "sub", "Not a directory")):  # fmt: skip
        assert main(["study", str(path), "--out", str(out), "-q"]) == 3
        err = capsys.readouterr().err
        flat = "".join(err.split())  # however the console wrapped a long path
        assert "".join(f"{out}: {words}".split()) in flat, err  # (main's OSError: exit 3)
        assert "internal error" not in err
    assert (cell / "plain").read_text() == "x"


# --------------------------------------------------------------------------- running

STUDY = (
    '[grid]\n"robot.joints.2.weight" = [1.0, 4.0]\n\n[random]\nn = 2\nseed = 7\n'
    '"datalist.cell3.obstacles.post.radius" = { uniform = [50, 150] }\n'
)


@pytest.mark.scenario
def test_results_are_the_same_bytes_with_one_and_two_workers(cell):
    path = write_study(cell, STUDY)
    one = run_study(path, out=cell / "one", workers=1)
    two = run_study(path, out=cell / "two", workers=2)
    assert one.ran == two.ran == 4
    a, b = (cell / "one/results.csv").read_bytes(), (cell / "two/results.csv").read_bytes()
    assert a == b
    table = rows(cell / "one")
    assert [r["variant"] for r in table] == ["0", "1", "2", "3"]
    assert all(r["status"] == "ok" and r["exit_code"] == "0" for r in table)
    # clearance to a sphere = distance to its centre − radius: same motion (same weight),
    # other radius → the clearance moves by exactly the radius difference
    for i, j in ((0, 1), (2, 3)):
        dr = float(table[j]["datalist.cell3.obstacles.post.radius"]) - float(
            table[i]["datalist.cell3.obstacles.post.radius"]
        )
        dc = float(table[j]["min_clearance_post_mm"]) - float(table[i]["min_clearance_post_mm"])
        assert math.isclose(dc, -dr, abs_tol=1e-5)
    # the weight changes how the redundancy is resolved: other joint speeds
    assert table[0]["peak_speed_a2_deg_s"] != table[2]["peak_speed_a2_deg_s"]
    pq = pytest.importorskip("pyarrow.parquet")  # results.parquet: the same rows, typed
    parquet = pq.read_table(cell / "one/results.parquet").to_pylist()
    assert [p["variant"] for p in parquet] == [0, 1, 2, 3]
    assert (cell / "one/results.parquet").read_bytes() == (
        cell / "two/results.parquet"
    ).read_bytes()
    assert [p["min_clearance_post_mm"] for p in parquet] == [
        float(r["min_clearance_post_mm"]) for r in table
    ]


@pytest.mark.scenario
def test_resume_after_an_interruption_runs_only_the_missing_variants(cell):
    path = write_study(cell, STUDY)
    full = run_study(path, out=cell / "full", workers=1)
    expected = (cell / "full/results.csv").read_bytes()
    # an interrupted run: two rows written out of order, a third cut off mid-line
    shutil.copytree(cell / "full", cell / "cut")
    lines = expected.decode().split("\n")
    cut = lines[0] + "\n" + lines[3] + "\n" + lines[1] + "\n" + lines[4][:10]
    (cell / "cut/results.csv").write_text(cut)
    done = []
    again = run_study(path, out=cell / "cut", workers=1, resume=True,
                      started=lambda todo, total: done.append((todo, total)))  # fmt: skip
    assert done == [(2, 4)] and again.ran == 2 and full.ran == 4
    assert (cell / "cut/results.csv").read_bytes() == expected
    # resuming a complete study runs nothing; without --resume the folder is refused
    assert run_study(path, out=cell / "cut", resume=True).ran == 0
    with pytest.raises(StudyError, match="--resume"):
        run_study(path, out=cell / "cut")
    # a changed study file cannot resume into the old results
    path.write_text(path.read_text().replace("seed = 7", "seed = 8"))
    with pytest.raises(StudyError, match="another study"):
        run_study(path, out=cell / "cut", resume=True)


@pytest.mark.scenario
def test_resume_from_a_damaged_folder_is_refused_or_skips_the_damage(cell):
    # a study.json nested too deeply (RecursionError) or not an object (AttributeError)
    # ended --resume in exit 4; so did rows of results.csv that csv or int() refuse
    path = write_study(cell, '[grid]\n"run.ipo" = [0.01, 0.02]\n')
    run_study(path, out=cell / "out", workers=1)
    expected = (cell / "out/results.csv").read_bytes()
    meta = cell / "out/study.json"
    good = meta.read_text()
    for damage in ("[" * 100_000, "[1, 2]"):
        meta.write_text(damage)
        with pytest.raises(StudyError, match=r"missing or unreadable|another study"):
            run_study(path, out=cell / "out", resume=True)
    meta.write_text(good)
    with (cell / "out/results.csv").open("a") as f:
        f.write("²,x\n1\x00,a\n7," + "x" * 200_000 + "\n")
    assert run_study(path, out=cell / "out", resume=True).ran == 0
    assert (cell / "out/results.csv").read_bytes() == expected


@pytest.mark.scenario
def test_a_failing_variant_is_a_row_with_its_error(cell, capsys):
    body = '[grid]\n"datalist.cell3.poses.sq_1.1" = [1500, 9000]\n"run.ipo" = [0.01]\n'
    path = write_study(cell, "[output]\nreports = true\ntraces = true\n\n" + body)
    assert main(["study", str(path), "--out", str(cell / "out"), "-j", "1"]) == 0
    ok, bad = rows(cell / "out")
    assert ok["status"] == "ok" and ok["error"] == ""
    # the ok variant (the data list's own value) is the plain run of the program
    report = run_program(cell / "p3.irl").report
    assert ok["max_path_error_mm"] == repr(report["max_path_error_mm"])
    assert ok["duration_s"] == repr(report["duration_s"])
    assert ok["min_clearance_post_mm"] == repr(report["obstacles"]["post"]["min_distance_mm"])
    for j in report["joints"]:
        assert ok[f"peak_speed_{j['name']}_deg_s"] == repr(j["max_abs_speed"])
        assert ok[f"peak_accel_{j['name']}_deg_s2"] == repr(j["max_abs_accel"])
    # [output]: each variant's report and trace, as irlc run writes them
    saved = json.loads((cell / "out/variants/variant_0000000.report.json").read_text())
    assert saved["max_path_error_mm"] == report["max_path_error_mm"]
    failed = json.loads((cell / "out/variants/variant_0000001.report.json").read_text())
    assert failed["status"] == "failed" and failed["error"]["line"] == MOVE_LINE
    trace = (cell / "out/variants/variant_0000000.trace.csv").read_text().splitlines()
    assert trace[0].startswith("t_s,line,") and len(trace) == 1 + report["samples"]
    assert bad["status"] == "failed" and bad["exit_code"] == "2"
    assert bad["error_line"] == str(MOVE_LINE) and bad["error"]
    out = capsys.readouterr().out
    assert "1 failed, 1 ok" in out


def test_sort_must_name_a_metric(cell, capsys):
    path = write_study(cell, '[grid]\n"run.ipo" = [0.01]\n')
    assert main(["study", str(path), "--out", str(cell / "o"), "-j", "1", "--sort", "x"]) == 3
    assert "--sort x: not a metric column" in capsys.readouterr().err
    assert not (cell / "o").exists()  # checked before anything ran
    for text in ("active_bounds", "status", "error"):  # text columns: no ranking (probe)
        assert main(["study", str(path), "--out", str(cell / "o"), "--sort", text]) == 3
        err = " ".join(capsys.readouterr().err.split())
        assert (
            f"--sort {text}: not a metric column" in err
            and "active_bounds" not in err.split("(columns:")[1]
        )


@pytest.mark.scenario
def test_the_cluster_gives_the_local_results(cell):
    """A grid and a random sample (32 variants: Dask tasks of 2) run on a LocalCluster of
    two worker processes through --cluster tcp://…: the same bytes as the local run. Then
    a batch with a variant that kills its worker: split, only that variant is a crashed
    row."""
    distributed = pytest.importorskip("distributed")
    import dask
    from irlc.study.plan import build_plan
    from irlc.study.runner import batch_size, run_dask

    path = write_study(cell, STUDY.replace("n = 2", "n = 16"))
    run_study(path, out=cell / "local", workers=2)
    assert batch_size(32, 2) == 2
    no_retries = dask.config.set({"distributed.scheduler.allowed-failures": 0})
    with (
        no_retries,
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster,
    ):
        address = cluster.scheduler_address  # tcp://127.0.0.1:PORT, as --cluster takes it
        args = ["study", str(path), "--out", str(cell / "dask"), "--cluster", address, "-q"]
        assert main(args) == 0
        plan = build_plan(read_study(write_study(cell, '[grid]\n"run.ipo" = [0.01]\n')))
        todo = [(0, (0.01,)), (1, (_KillsWhenRun(0.01),)), (2, (0.02,))] + [
            (i, (0.01,)) for i in range(3, 48)
        ]
        got: list[dict] = []
        with distributed.Client(address) as client:
            run_dask(plan, todo, client, got.append, len(todo))
    local = (cell / "local/results.csv").read_bytes()
    assert (cell / "dask/results.csv").read_bytes() == local
    assert local.count(b"\n") == 33
    by_index = {int(r["variant"]): r["status"] for r in got}
    assert sorted(by_index) == list(range(48)) and len(got) == 48
    assert by_index.pop(1) == "crashed" and set(by_index.values()) == {"ok"}


class _KillsWhenRun(float):
    """An IPO value that ends the process comparing it with its range — the run's check,
    in the worker. Unpickling it is harmless (Dask's scheduler, in the test's process,
    unpickles task arguments)."""

    def _die(self, other):
        import os

        os._exit(70)

    __ge__ = __gt__ = __le__ = __lt__ = _die


class _KillsTheWorker:
    """A value whose unpickling ends the worker process at once (like a segfault would)."""

    def __reduce__(self):
        import os

        return (os._exit, (70,))

    def __str__(self) -> str:
        return "killer"


@pytest.mark.scenario
def test_a_variant_that_kills_its_worker_is_a_crashed_row_and_the_rest_run(cell):
    from irlc.study.plan import build_plan
    from irlc.study.runner import run_local

    study = read_study(write_study(cell, '[grid]\n"run.ipo" = [0.01, 0.02]\n'))
    plan = build_plan(study)
    todo = [(0, (0.01,)), (1, (_KillsTheWorker(),)), (2, (0.02,))]
    got: list[dict] = []
    run_local(plan, todo, 2, got.append)
    by_index = {int(r["variant"]): r for r in got}
    assert sorted(by_index) == [0, 1, 2] and len(got) == 3
    assert by_index[1]["status"] == "crashed" and "died" in by_index[1]["error"]
    assert by_index[0]["status"] == by_index[2]["status"] == "ok"


@pytest.mark.scenario
def test_golden_tests_in_parallel_give_the_serial_results(cell, capsys):
    for k, x in enumerate((1500, 1600, 1700)):
        (cell / f"p{k}.irl").write_text(PROGRAM.replace("sq_1", f"q{k}"))
        (cell / "cell3.toml").write_text(
            (cell / "cell3.toml")
            .read_text()
            .replace("[joints]", f"q{k} = [{x}, 1000, 0, 0, 0, 0]\n\n[joints]")
        )
    (cell / "p3.irl").unlink()
    assert main(["test", str(cell), "--update"]) == 0
    capsys.readouterr()
    assert main(["test", str(cell), "-j", "1"]) == 0
    serial = capsys.readouterr().out
    assert main(["test", str(cell), "-j", "2"]) == 0
    assert capsys.readouterr().out == serial and serial.count("PASS") == 3
    # a broken expectation fails in parallel as it does serially, at its own program
    path = cell / "p1.expected.json"
    path.write_text(path.read_text().replace('"status": "ok"', '"status": "failed"'))
    assert main(["test", str(cell), "-j", "2"]) == 1
    out = capsys.readouterr().out
    assert main(["test", str(cell), "-j", "1"]) == 1
    assert capsys.readouterr().out == out and "FAIL" in out and "p1" in out


@pytest.mark.scenario
def test_ctrl_c_keeps_the_finished_rows_and_resume_completes_them(cell):
    import os
    import signal
    import subprocess
    import sys
    import time

    body = '[random]\nn = 24\nseed = 5\n"robot.joints.2.weight" = { uniform = [0.5, 4] }\n'
    path = write_study(cell, body)
    run_study(path, out=cell / "full", workers=1)
    irlc = [sys.executable, "-c", "from irlc.cli import entry; entry()"]
    cmd = [*irlc, "study", str(path), "--out", str(cell / "cut"), "-j", "1"]
    proc = subprocess.Popen(
        cmd, start_new_session=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )  # fmt: skip
    results = cell / "cut" / "results.csv"
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline and proc.poll() is None:
        if results.exists() and results.read_text().count("\n") > 3:
            break
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGINT)  # what Ctrl-C does: the whole process group
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err.decode()
    assert "--resume" in err.decode()
    kept = rows(cell / "cut")
    assert 3 <= len(kept) < 24
    assert [int(r["variant"]) for r in kept] == sorted(int(r["variant"]) for r in kept)
    again = run_study(path, out=cell / "cut", workers=1, resume=True)
    assert again.ran == 24 - len(kept)
    assert results.read_bytes() == (cell / "full" / "results.csv").read_bytes()


def test_plot_draws_a_line_or_a_heat_map(tmp_path):
    pytest.importorskip("matplotlib")
    from irlc.study.figure import plot

    rows = [
        {"variant": str(i), "a": repr(a), "b": repr(b), "m": repr(a * b), "status": "ok"}
        for i, (a, b) in enumerate((a, b) for a in (1.0, 2.0, 3.0) for b in (10.0, 20.0))
    ]
    line = plot(rows, ["a"], "m", tmp_path / "line.png", {"a"})
    heat = plot(rows, ["a", "b"], "m", tmp_path / "heat.png", {"a", "b"})
    dots = plot(rows, ["a", "b"], "m", tmp_path / "dots.png", {"a"})
    for row in rows:
        row["a"] = "ideal" if row["a"] == "1.0" else "decoupled"
    cats = plot(rows, ["a", "b"], "m", tmp_path / "cats.png", {"a", "b"})
    for png in (line, heat, dots, cats):
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert len({p.read_bytes() for p in (line, heat, dots, cats)}) == 4


def test_a_plot_target_that_cannot_be_written_is_a_usage_error(cell, capsys):
    # --plot DIR was an internal error (IsADirectoryError) after the whole study had run
    pytest.importorskip("matplotlib")
    path = write_study(cell, '[grid]\n"run.ipo" = [0.01]\n')
    (cell / "figs").mkdir()
    assert (
        main(["study", str(path), "--out", str(cell / "o1"), "-q", "--plot", str(cell / "figs")])
        == 3
    )
    assert "is a directory" in capsys.readouterr().err
    assert not (cell / "o1").exists()  # refused before anything ran
    bad = cell / "s.toml" / "x.png"
    assert main(["study", str(path), "--out", str(cell / "o2"), "-q", "--plot", str(bad)]) == 3
    err = capsys.readouterr().err
    assert "".join(f"--plot: cannot write {bad}: Not a directory".split()) in "".join(err.split())
    assert (cell / "o2" / "results.csv").exists()  # the rows are kept


def test_a_long_lived_worker_keeps_the_caches_of_the_last_two_studies(monkeypatch):
    from types import SimpleNamespace

    from irlc.study import worker

    monkeypatch.setattr(worker, "_caches", {})
    made = []
    for token in "abcab":
        plan = SimpleNamespace(token=token)
        for kind in ("robot", "code"):
            worker._cached(plan, kind, 1, lambda t=token, k=kind: made.append((t, k)) or t)
    assert sorted(worker._caches) == ["a:code", "a:robot", "b:code", "b:robot"]
    # a and b were made again after c pushed them out; nothing is made twice in a row
    assert len(made) == 10
    assert worker._cached(SimpleNamespace(token="b"), "code", 1, lambda: "new") == "b"


def test_ranking_smallest_or_largest_first_ties_in_variant_order():
    from irlc.study.summary import ranked

    table = [
        {"variant": "0", "m": "2.0"},
        {"variant": "1", "m": ""},  # no value (a failed run): not ranked
        {"variant": "2", "m": "1.0"},
        {"variant": "3", "m": "2.0"},
    ]
    assert [r["variant"] for r in ranked(table, "m")] == ["2", "0", "3"]
    assert [r["variant"] for r in ranked(table, "-m")] == ["0", "3", "2"]
    # a failed run's numbers stop where it stopped: never ranked, even with a number
    # (regression: failed variants with a path error of 0 at t = 0 headed the table, "best")
    failed = [{**r, "status": "failed"} if r["variant"] == "2" else r for r in table]
    assert [r["variant"] for r in ranked(failed, "m")] == ["0", "3"]


def test_the_example_study_in_programs_is_valid():
    """programs/studies/w10.toml (docs/studies.md) reads, compiles and passes the checks;
    running it (2 koch11 squares) is left to the docs' command."""
    from irlc.study.metrics import columns
    from irlc.study.plan import build_plan

    root = Path(__file__).resolve().parents[2]
    study = read_study(root / "programs" / "studies" / "w10.toml")
    plan = build_plan(study)
    assert [v for _, v in variants(study)] == [(5.0,), (20.0,)]
    assert "peak_accel_a10_mm_s2" in columns(plan)


def test_program_joint_names_and_pose_components_name_the_same_values(cell):
    from irlc.study.paths import target

    assert target("robot.joints.a2.weight") == target("robot.joints.2.weight")
    assert target("datalist.cell3.poses.sq_1.y")[1] == ["cell3", "poses", "sq_1", "2"]
    path = write_study(cell, '[grid]\n"robot.joints.a2.weight" = [-1]\n')
    with pytest.raises(StudyError, match="positive"):
        run_study(path, out=cell / "o")


def test_the_study_file_shown_in_docs_studies_md_is_valid(tmp_path):
    """docs/studies.md's example of every table passes the checks (not run: 400 variants)."""
    from irlc.study.plan import build_plan

    root = Path(__file__).resolve().parents[2]
    text = (root / "docs" / "studies.md").read_text(encoding="utf-8")
    block = text.split("```toml\n", 1)[1].split("```", 1)[0]
    assert 'program = "../square_accel.irl"' in block  # as if in programs/studies/
    for name in ("square_accel.irl", "square_cell.toml"):  # a copy: programs/ beside it
        shutil.copy(root / "programs" / name, tmp_path / name)
    (tmp_path / "studies" / "cells").mkdir(parents=True)  # its datalist_path folder
    path = tmp_path / "studies" / "every_table.toml"
    path.write_text(block)
    example = read_study(path)
    plan = build_plan(example)
    assert len(list(variants(example))) == 400 and plan.drives and not example.reports


def test_an_irdata_program_varies_robot_values_but_not_its_compiled_data(cell):
    assert main(["compile", str(cell / "p3.irl"), "-o", str(cell / "p3.ird")]) == 0
    path = cell / "ird.toml"
    path.write_text('program = "p3.ird"\n[grid]\n"datalist.cell3.poses.sq_1.x" = [1.0]\n')
    with pytest.raises(StudyError, match="IRDATA code"):
        run_study(path, out=cell / "o")


KOCH11_LINE = """PROGRAM k;
ROBOT r := koch11;
IMPORT DATALIST square_cell;
BEGIN
  R_SPEED := 1000;
  R_ACC := 2000;
  MOVE PTP konf_0;
  MOVE LIN poz_1;
ENDPROGRAM
"""


@pytest.mark.scenario
def test_drive_columns_are_the_drive_runs_report(tmp_path):
    """With drives the row carries the verdict, peak currents and following errors: those
    of the plain run (the drive value given is the robot file's own)."""
    root = Path(__file__).resolve().parents[2]
    (tmp_path / "k.irl").write_text(KOCH11_LINE)
    shutil.copy(root / "programs" / "square_cell.toml", tmp_path)
    options = {"drives": "decoupled", "path_tolerance": 50, "orientation_tolerance": 5}
    path = tmp_path / "d.toml"
    path.write_text(
        'program = "k.irl"\n[run]\ndrives = "decoupled"\npath_tolerance = 50\n'
        'orientation_tolerance = 5\n[grid]\n"robot.drives.dc.kz.value" = [0.25]\n'
    )
    outcome = run_study(path, out=tmp_path / "out", workers=1)
    [row] = outcome.rows
    report = run_program(tmp_path / "k.irl", **options).report
    assert row["status"] == report["status"] == "ok"
    assert row["drives_could_follow"] == "true"
    assert row["max_path_error_mm"] == repr(report["max_path_error_mm"])
    axes = report["drives_summary"]["axes"]
    for j, axis in zip(report["joints"], axes, strict=True):
        assert row[f"peak_current_{j['name']}_A"] == repr(axis["peak_current_A"])
        unit = j["unit"]
        assert row[f"max_following_error_{j['name']}_{unit}"] == repr(j["max_following_error"])
    assert float(row["peak_current_a2_A"]) > 0


@pytest.mark.scenario
def test_the_speed_override_scales_the_motion_time(cell):
    """R_OVERRIDE at 50 % halves every speed and quarters every acceleration: the motion
    takes twice as long (time scaling, lang/settings.py's R_OVERRIDE)."""
    path = write_study(cell, '[grid]\n"run.override" = [100, 50]\n')
    full, half = run_study(path, out=cell / "o", workers=1).rows
    assert full["status"] == half["status"] == "ok"
    report = run_program(cell / "p3.irl", override=50).report
    assert half["duration_s"] == repr(report["duration_s"])
    assert float(half["duration_s"]) == pytest.approx(2 * float(full["duration_s"]), abs=0.02)


# --------------------------------------------------------------------------- confinement


def _study_in(folder: Path, head: str) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "s.toml"
    path.write_text(head + '\n[grid]\n"run.ipo" = [0.01]\n')
    return path


def test_a_study_file_reads_only_what_the_user_allows(cell, capsys, monkeypatch):
    """A study file is input: ``program = "/proc/self/environ"`` echoed the environment,
    an absolute path to a program elsewhere ran it. Relative paths (as the docs write
    them) stay; absolute paths outside the working folder and the study's folder, and
    system files however written, are refused — unless the command line allows any path."""
    studies = cell / "studies"
    elsewhere = cell.parent / f"{cell.name}_elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    robot = cell / "arm.toml"
    robot.write_text((Path(__file__).resolve().parents[2] / "robots" / "planar3.toml").read_text())
    assert read_study(_study_in(studies, 'program = "../p3.irl"')).program == cell / "p3.irl"
    refused = [
        (f'program = "{cell / "p3.irl"}"', "an absolute path outside the working folder"),
        ('program = "/proc/self/environ"', "a system file (under /proc)"),
        ('program = "' + "../" * 30 + 'proc/self/environ"', "a system file (under /proc)"),
        (f'program = "../p3.irl"\nrobot = "{robot}"', "robot: "),
        ('program = "../p3.irl"\ndatalist_path = ["/etc"]', "a system file (under /etc)"),
    ]
    for head, words in refused:
        path = _study_in(studies, head)
        assert main(["study", str(path), "-q", "--out", str(cell / "out")]) == 3
        err = capsys.readouterr().err
        assert words in err and "--allow-any-path" in err, err
        assert "SHELL" not in err and "PATH=" not in err
        if "system file" not in words:
            assert read_study(path, allow_any_path=True).file == path  # the user's word
    monkeypatch.chdir(cell)  # the absolute path is inside the working folder now
    assert read_study(_study_in(studies, f'program = "{cell / "p3.irl"}"')).program.is_file()


def test_a_missing_datalist_folder_and_random_n_are_named(cell, capsys):
    path = write_study(cell, 'datalist_path = ["nope"]\n[grid]\n"run.ipo" = [0.01]\n')
    assert main(["study", str(path), "-q"]) == 3
    assert "s.toml:3: datalist_path: nope: no such folder" in capsys.readouterr().err
    body = '[random]\nseed = 1\n"run.ipo" = { uniform = [0.01, 0.02] }\n'
    assert main(["study", str(write_study(cell, body)), "-q"]) == 3
    err = capsys.readouterr().err
    assert "random.n: required: the number of samples" in err and "None" not in err


def test_a_large_study_is_planned_in_bounded_memory(cell):
    """The variants are made as they are sent: a 10-million-sample study held ≈ 1.1 GB of
    sample tuples before its first row. With 2 million samples of two keys (≈ 220 MB of
    tuples at once), planning and the first variant now stay below 50 MB, and the values
    are the documented draws (one PCG64 stream, keys in file order, n values per key)."""
    import tracemalloc

    from irlc.study.plan import build_plan

    n = 2_000_000
    body = (
        f'[random]\nn = {n}\nseed = 7\n"run.path_tolerance" = {{ uniform = [0.05, 0.1] }}\n'
        '"robot.joints.2.weight" = { normal = [2, 0.1] }\n'
    )
    tracemalloc.start()
    try:
        study = read_study(write_study(cell, body))
        build_plan(study)
        stream = variants(study)
        first = next(stream)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 50e6, f"{peak / 1e6:.0f} MB before the first variant"
    rng = np.random.Generator(np.random.PCG64(7))
    tol = rng.uniform(0.05, 0.1, n)
    weight = rng.normal(2, 0.1, n)
    assert first == (0, (float(tol[0]), float(weight[0])))
    for index, values in stream:  # a piece boundary (65,536 samples) further on
        if index == 70_000:
            assert values == (float(tol[index]), float(weight[index]))
            break


def _grid_random_rows(failed_at=()):
    """Two grid keys (g, h) × a random key (r); the metric depends on all three."""
    rows, i = [], 0
    for g in (1.0, 2.0, 3.0):
        for h in (10.0, 20.0):
            for k in range(6):
                r = 0.37 * k
                status = "failed" if i in failed_at else "ok"
                rows.append({"variant": str(i), "g": repr(g), "h": repr(h), "r": repr(r),
                             "m": repr(g * h + r * r), "status": status})  # fmt: skip
                i += 1
    return rows


@pytest.mark.parametrize(
    ("keys", "grid"),
    [
        (["g", "r"], {"g"}), (["r", "g"], {"g"}), (["g", "h"], {"g", "h"}),
        (["g", "h", "r"], {"g", "h"}), (["r"], set()), (["g", "r", "h"], {"g", "h"}),
    ],
)  # fmt: skip
def test_the_plot_hides_no_key_that_changes_the_metric(keys, grid):
    """Every key with more than one value is on an axis, a series or a panel, and a heat
    map cell holds one variant: over grid × random keys the heat map of the two grid keys
    overwrote (hid) the random key, and a constant key is no axis."""
    from irlc.study.figure import layout

    rows = _grid_random_rows()
    if keys == ["g", "h"]:  # one variant per (g, h): a heat map is exact there
        rows = [r for r in rows if r["r"] == "0.0"]
    panels = layout(rows, keys, grid)
    shown = {k for p in panels for k in p.keys}
    assert shown == set(keys), panels
    for p in panels:
        if p.kind == "heat":
            assert len({(r[p.x], r[p.y]) for r in rows}) == len(rows)
    constant = [dict(r, c="5") for r in rows]
    assert "c" not in {k for p in layout(constant, [*keys, "c"], grid) for k in p.keys}


def test_a_failed_variant_is_drawn_as_failed_not_by_its_metric(tmp_path):
    """Marking a variant failed changes the figure; its metric (a failed run's numbers
    stop where it stopped) then changes nothing: it is drawn at its parameters, not by
    its value — not coloured, not placed on the metric axis."""
    pytest.importorskip("matplotlib")
    from irlc.study.figure import plot

    for keys, grid in ((["g", "r"], {"g"}), (["r", "g", "h"], {"g", "h"})):
        ok = _grid_random_rows()
        bad = _grid_random_rows(failed_at={3, 17})
        worse = [dict(r, m="1e6") if r["status"] == "failed" else r for r in bad]
        images = [plot(rows, keys, "m", tmp_path / f"{n}.png", grid).read_bytes()
                  for n, rows in (("ok", ok), ("bad", bad), ("worse", worse))]  # fmt: skip
        assert images[0] != images[1] and images[1] == images[2]
    two_random = [dict(r, s=repr(float(r["variant"]) * 0.1)) for r in _grid_random_rows({5})]
    scatter = plot(two_random, ["r", "s"], "m", tmp_path / "a.png", set()).read_bytes()
    moved = [dict(r, m="-3") if r["variant"] == "5" else r for r in two_random]
    assert plot(moved, ["r", "s"], "m", tmp_path / "b.png", set()).read_bytes() == scatter
