"""Memory of long runs: the recorder hands its samples out without copying them, and the
trace writer streams the CSV (no whole-file string in memory) with the same bytes."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest
from irlc import report as report_mod
from irlc.report import NonFiniteError, trace_chunks, trace_csv, write_trace
from irlc.runtime.outputs.recorder import Recorder


def _reference_csv(columns, table) -> str:
    """The trace format written out cell by cell (docs/interfaces.md: ``%.10g``, no
    negative zero, ``line`` an integer, ``\\n`` line ends), independently of the writer."""
    lines = [",".join(columns)]
    for row in np.asarray(table, dtype=float):
        cells = []
        for name, v in zip(columns, row, strict=True):
            v = 0.0 if v == 0.0 else float(v)
            cells.append(str(int(v)) if name == "line" else f"{v:.10g}")
        lines.append(",".join(cells))
    return "\n".join(lines) + "\n"


def _table(rows: int, rng) -> tuple[list[str], np.ndarray]:
    columns = ["t_s", "line", "a1_deg", "x_mm", "path_error_mm"]
    table = np.column_stack(
        [
            np.arange(rows) * 0.01,
            rng.integers(1, 400, rows).astype(float),
            rng.normal(0.0, 90.0, rows),
            rng.normal(0.0, 1e3, rows) * rng.choice([1.0, 1e-12, 1e9], rows),
            np.where(rng.random(rows) < 0.3, -0.0, rng.uniform(0, 1e-3, rows)),
        ]
    )
    return columns, table


def test_streamed_trace_is_the_reference_format(monkeypatch, tmp_path):
    rng = np.random.default_rng(3)
    columns, table = _table(1000, rng)
    monkeypatch.setattr(report_mod, "TRACE_CHUNK_ROWS", 64)  # 16 pieces, the last short
    pieces = list(trace_chunks(columns, table))
    assert len(pieces) == 1 + 16
    expected = _reference_csv(columns, table)
    assert "".join(pieces) == expected == trace_csv(columns, table)
    assert "-0," not in expected and "-0\n" not in expected
    path = write_trace(columns, table, tmp_path / "t.csv")
    assert path.read_bytes() == expected.encode("utf-8")


def test_non_finite_in_a_late_piece_writes_nothing(monkeypatch, tmp_path):
    rng = np.random.default_rng(4)
    columns, table = _table(300, rng)
    table[257, 3] = np.nan
    monkeypatch.setattr(report_mod, "TRACE_CHUNK_ROWS", 64)
    target = tmp_path / "t.csv"
    target.write_text("old\n")
    with pytest.raises(NonFiniteError, match="'x_mm', row 257"):
        write_trace(columns, table, target)
    assert target.read_text() == "old\n"  # untouched
    assert sorted(p.name for p in tmp_path.iterdir()) == ["t.csv"]  # no temporary left


def test_writing_a_long_trace_needs_memory_for_one_piece(tmp_path):
    """200,000 rows (≈ 12 MB of text): the writer's peak Python allocation stays far
    below the file's size (the whole-string writer needed about twice the file)."""
    rng = np.random.default_rng(5)
    columns, table = _table(200_000, rng)
    tracemalloc.start()
    try:
        path = write_trace(columns, table, tmp_path / "long.csv")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    size = path.stat().st_size
    assert size > 8_000_000
    assert peak < size / 4, (peak, size)


def _filled(k: int, capacity: int = 4) -> tuple[Recorder, np.ndarray]:
    rec = Recorder(2, ("box",), capacity=capacity)
    q = np.random.default_rng(7).normal(size=(k, 2))
    for i in range(k):
        rec.add(0.01 * i, 1, q[i], np.eye(4), None, clearances={"box": (1.0 + i, 0)})
    return rec, q


def test_recorder_arrays_are_read_only_views_not_copies():
    rec, q = _filled(50)
    out = rec.arrays()
    assert np.shares_memory(out.q, rec._q) and np.shares_memory(out.tcp, rec._tcp)
    assert np.shares_memory(out.times, rec._times)
    with pytest.raises(ValueError, match="read-only"):
        out.q[0, 0] = 1.0
    # the recorder itself still records, into rows the views do not reach or a new buffer
    for i in range(50, 200):  # grows 64 → 128 → 256
        rec.add(0.01 * i, 2, np.zeros(2), np.eye(4), None)
    np.testing.assert_array_equal(out.q, q)
    assert out.times.shape == (50,) and out.lines.tolist() == [1] * 50
    assert rec.arrays().q.shape == (200, 2)


def test_a_rewind_after_arrays_leaves_the_views_alone():
    rec, q = _filled(10)
    mark = rec.mark()
    out = rec.arrays()
    rec.add(0.1, 3, np.ones(2), np.eye(4), None)
    rec.rewind(mark)
    rec.add(0.1, 4, np.full(2, 5.0), np.eye(4), None)
    np.testing.assert_array_equal(out.q, q)
    assert rec.arrays().lines[-1] == 4


def test_arrays_allocate_only_the_derived_quantities():
    """arrays() of 20,000 samples allocates the speeds and accelerations (2 × k × n
    floats) and the flags, not a second copy of the ≈ 430 B per sample."""
    rec, _ = _filled(20_000, capacity=32_768)
    tracemalloc.start()
    try:
        out = rec.arrays()
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    derived = out.speed.nbytes + out.accel.nbytes + out.active.nbytes
    copies = sum(a.nbytes for a in (out.q, out.tcp, out.desired, out.times))
    assert peak < derived + copies / 4, (peak, derived, copies)
