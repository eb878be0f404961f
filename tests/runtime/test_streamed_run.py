"""A streamed run (``run_code(stream=True)``, what ``irlc run`` does) keeps a bounded number
of samples in memory — the recorder spills the rest to a temporary file — and gives the
same bytes as a run kept in memory: the report JSON and the trace CSV, for programs of
every kind (blends, WAIT, obstacles, motor maps, I/O, failing runs with a partial trace).
The spill buffer is made tiny here (16 samples), so every run is cut into many pieces."""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
import pytest
from irlc.report import report_json, trace_chunks, trace_csv, write_trace
from irlc.runtime import run as run_mod
from irlc.runtime.outputs.recorder import Recorder, backward_jerk, finite_differences
from irlc.runtime.run import run_file

ROOT = Path(__file__).resolve().parents[2]
CASES = [
    ROOT / "programs" / "square.irl",  # koch11, 11 joints
    ROOT / "programs" / "pick_place.irl",  # irb6: motor maps, blends, I/O
    ROOT / "programs" / "combined.irl",  # obstacles, freeze, cyclic
    ROOT / "programs" / "planar4_obstacle.irl",
    ROOT / "programs" / "mobile8_freeze.irl",
    ROOT / "tests/runtime_acceptance/programs/k12_time_wait_ptp.irl",  # WAIT
    ROOT / "tests/runtime_acceptance/programs/k09_reconfiguration.irl",
    ROOT / "tests/drives_acceptance/programs/ptp_multi.irl",  # PTP blends, motors
    ROOT / "tests/runtime_acceptance/failing/f01_unreachable.irl",  # failing: partial trace
    ROOT / "tests/runtime_acceptance/failing/f04_singular.irl",
]


def _bytes(run, streamed: bool) -> tuple[str, str]:
    partial = run.error is not None
    table = run.trace_tables() if streamed else run.trace
    return report_json(run.report), "".join(trace_chunks(run.trace_columns, table, partial))


@pytest.mark.parametrize("program", CASES, ids=lambda p: p.stem)
def test_streamed_run_gives_the_same_bytes(program, monkeypatch):
    memory = run_file(program)
    monkeypatch.setattr(run_mod, "SPILL_ROWS", 16)
    streamed = run_file(program, stream=True)
    recorder = streamed.source.run.controller.recorder
    assert recorder.spilled >= len(memory.times) - 64  # nearly all went to the file
    assert recorder._cap <= 64  # the buffer stayed small
    report, trace = _bytes(memory, False)
    assert (report, trace) == _bytes(streamed, True)
    assert streamed.status == memory.status
    # the Python API's arrays, built on first use, are the in-memory run's
    np.testing.assert_array_equal(streamed.trace, memory.trace)
    np.testing.assert_array_equal(streamed.q, memory.q)
    np.testing.assert_array_equal(streamed.recorded.speed, memory.recorded.speed)
    assert trace == trace_csv(memory.trace_columns, streamed.trace, memory.error is not None)


def test_drive_runs_are_kept_in_memory_with_stream(monkeypatch):
    """Drives read the whole run (not streamed): ``stream`` changes nothing there."""
    program = ROOT / "tests/drives_acceptance/programs/short.irl"
    monkeypatch.setattr(run_mod, "SPILL_ROWS", 16)
    a = run_file(program, drives="decoupled")
    b = run_file(program, drives="decoupled", stream=True)
    assert b.source.__class__.__name__ == "TraceArrays"
    assert _bytes(a, False) == _bytes(b, True)


def test_cli_streams_the_trace_with_the_same_bytes(tmp_path, monkeypatch):
    from click.testing import CliRunner
    from irlc.cli import cli

    program = ROOT / "programs" / "pick_place.irl"
    monkeypatch.setattr(run_mod, "SPILL_ROWS", 16)
    args = ["run", str(program), "-q", "--report", str(tmp_path / "r.json")]
    res = CliRunner().invoke(cli, [*args, "--trace", str(tmp_path / "t.csv")])
    assert res.exit_code == 0, res.output
    memory = run_file(program)
    report, trace = _bytes(memory, False)
    assert (tmp_path / "r.json").read_text(encoding="utf-8") == report
    assert (tmp_path / "t.csv").read_bytes() == trace.encode("utf-8")


def test_spilled_recorder_pieces_join_to_the_whole():
    """Pieces read back from the spill file, derivatives with the carried row, the limit
    activity and a rewind to a held mark: the same as a recorder that kept everything."""

    def filled(spill: bool) -> Recorder:
        rec = Recorder(3, ("box",), capacity=8)
        if spill:
            rec.spill(8)
        rng = np.random.default_rng(3)
        q = rng.normal(size=(120, 3))
        t = np.cumsum(rng.choice([0.0, 0.01, 0.02], 120))  # repeated stamps too
        for i in range(120):
            clear = {"box": (1.0 + i % 11, 0)} if i % 3 else None
            active = {1: "speed max"} if i % 7 == 0 else None
            rec.add(t[i], i % 5, q[i], np.eye(4) * i, None, clearances=clear, active=active,
                    dt=0.01, iterations=i % 4)  # fmt: skip
            if i == 40:
                mark = rec.mark()
            if i == 70:  # 30 samples after the mark: held in memory, then dropped
                rec.rewind(mark)
                rec.release(mark)
        return rec

    whole, spilled = filled(False), filled(True)
    assert spilled.spilled > 0 and whole.spilled == 0
    a, b = whole.arrays(), spilled.arrays()
    for name in ("times", "lines", "q", "speed", "accel", "tcp", "active", "iterations"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    np.testing.assert_array_equal(a.clearance["box"], b.clearance["box"])
    pieces = list(spilled.chunks())
    assert len(pieces) > 3
    np.testing.assert_array_equal(np.vstack([p.speed for p in pieces]), a.speed)
    np.testing.assert_array_equal(np.vstack([p.accel for p in pieces]), a.accel)
    assert spilled.active_time == whole.active_time


def test_rewind_past_a_released_mark_is_refused():
    rec = Recorder(1, capacity=4)
    rec.spill(4)
    mark = rec.mark()
    rec.release(mark)
    for i in range(20):
        rec.add(0.01 * (i + 1), 1, np.array([float(i)]), np.eye(4), None)
    assert rec.spilled > 0
    with pytest.raises(RuntimeError, match="spilled"):
        rec.rewind(mark)


def test_carried_differences_equal_the_whole_runs():
    """:func:`finite_differences` and :func:`backward_jerk` with the previous piece's last
    row carried give the whole run's values bit for bit."""
    rng = np.random.default_rng(5)
    t = np.cumsum(rng.choice([0.0, 0.004, 0.01], 500))
    q = np.cumsum(rng.normal(size=(500, 4)), axis=0)
    speed, accel = finite_differences(t, q)
    jerk = backward_jerk(t, accel)
    cuts = [0, 1, 2, 97, 250, 251, 500]
    parts_v, parts_a, parts_j = [], [], []
    carry = jcarry = None
    for lo, hi in itertools.pairwise(cuts):
        v, a = finite_differences(t[lo:hi], q[lo:hi], carry)
        parts_j.append(backward_jerk(t[lo:hi], a, jcarry))
        carry, jcarry = (t[hi - 1], q[hi - 1], v[-1]), (t[hi - 1], a[-1])
        parts_v.append(v)
        parts_a.append(a)
    np.testing.assert_array_equal(np.vstack(parts_v), speed)
    np.testing.assert_array_equal(np.vstack(parts_a), accel)
    np.testing.assert_array_equal(np.vstack(parts_j), jerk)


def test_a_bad_piece_leaves_no_trace_file(tmp_path):
    """A non-finite value in a later piece stops the streamed write: nothing is written."""
    from irlc.report import NonFiniteError

    good = np.ones((5, 2))
    bad = np.ones((5, 2))
    bad[3, 1] = np.inf
    target = tmp_path / "t.csv"
    with pytest.raises(NonFiniteError, match="row 8"):
        write_trace(["t_s", "x_mm"], iter([good, bad]), target)
    assert not target.exists() and not list(tmp_path.iterdir())
