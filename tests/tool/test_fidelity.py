"""docs/fidelity.md against bench/fidelity.py: every reference is in the table once with the
book's number as the registry states it; the fast rows, recomputed here, give the very
cells of the table, and every row the table calls reproduced is within its tolerance of the
book's number. The slow rows (drive studies, the O8/O9 search) are recomputed as scenario
tests, compared number by number (a simulation's last digits may differ by platform)."""

from __future__ import annotations

import importlib.util
import re
from pathlib import Path

import pytest
from irlc.fidelity.references import all_rows, available, compute, select
from irlc.fidelity.table import NOT_AT_HAND, doc_cells, doc_row, line

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "fidelity.md"
ROWS = all_rows()
FAST = select(ROWS, fast=True)
SLOW = [r for r in ROWS if r.slow]
NUMBER = re.compile(r"-?\d[\d,]*\.?\d*(?:e[-+]?\d+)?")


def cells() -> dict[str, list[str]]:
    return doc_cells(DOC.read_text("utf-8"))


def doc_key(row) -> str:
    return f"{row.key} [{row.unit}]" if row.unit else row.key


def fresh_cells(row) -> tuple[list[str], object]:
    result = compute(row)
    text = doc_row(row, result)
    return doc_cells(f"<!-- fidelity-table:begin (written by python bench/fidelity.py "
                     f"--write-doc) -->\n|h|\n|-|\n{text}\n<!-- fidelity-table:end -->")[
        doc_key(row)
    ], result  # fmt: skip


def test_every_reference_is_in_the_table_once_with_the_books_number():
    table = cells()
    keys = [doc_key(r) for r in ROWS]
    assert len(set(keys)) == len(keys)
    assert sorted(table) == sorted(keys)
    for row in ROWS:
        assert table[doc_key(row)][0] == row.book, row.key
        assert table[doc_key(row)][2] == f"`{row.command}`"


def test_rows_without_a_book_number_say_so_and_are_not_judged():
    for row in ROWS:
        if NOT_AT_HAND in row.book and "values at P, K" not in row.book:
            assert row.book_values is None, row.key


@pytest.mark.parametrize("row", [r for r in FAST if available(r)], ids=lambda r: r.ref)
def test_fast_row_gives_the_tables_cell(row):
    fresh, result = fresh_cells(row)
    assert fresh[1] == cells()[doc_key(row)][1]
    if result.reproduced is not None and "(reproduced)" in fresh[1]:
        assert row.judge(result.values) in (True, None)


@pytest.mark.parametrize("row", [r for r in ROWS if r.book_values], ids=lambda r: r.ref)
def test_rows_called_reproduced_are_within_their_tolerance(row):
    """The doc's verdict is the judgement of the numbers it shows: a 'reproduced' row's
    numbers lie within the tolerance of the book's."""
    irlc = cells()[doc_key(row)][1]
    if "(reproduced)" not in irlc:
        assert "(**not** reproduced)" in irlc, row.key
        return
    shown = irlc.split(" (reproduced)")[0]
    if shown.startswith("<"):  # a round-off-sized deviation, below its floor
        floor = float(shown.split(",")[0].strip("< "))
        assert floor <= row.tolerance, row.key
        return
    values = [float(v.replace(",", "")) for v in NUMBER.findall(shown)]
    if row.ref == "(5.1b)":  # "0 of N grid points disagree"
        values = values[:1]
    assert row.judge(values[: len(row.book_values)]), (row.key, values)


def _numbers_close(a: str, b: str) -> bool:
    na, nb = NUMBER.findall(a), NUMBER.findall(b)
    if NUMBER.sub("#", a) != NUMBER.sub("#", b) or len(na) != len(nb):
        return False
    for x, y in zip(na, nb, strict=True):
        u, v = float(x.replace(",", "")), float(y.replace(",", ""))
        if abs(u - v) > max(0.05 * max(abs(u), abs(v)), 0.002):
            return False
    return True


@pytest.mark.scenario
@pytest.mark.parametrize("row", SLOW, ids=lambda r: r.ref)
def test_slow_row_gives_the_tables_numbers(row):
    fresh, _ = fresh_cells(row)
    assert _numbers_close(fresh[1], cells()[doc_key(row)][1]), (fresh[1], row.key)


@pytest.mark.scenario
def test_l1_wrist_motors_are_within_the_books_4_23():
    """(4.23)'s motors 4–6 (the part the line P'→K' can compare): within 0.005 rad."""
    row = select(ROWS, ["(4.23)"])[0]
    result = compute(row)
    for ours, book in zip(result.values[3:], row.book_values[3:], strict=True):
        assert abs(ours - book) <= row.tolerance


def test_bench_script_prints_a_line_per_reference_starting_with_it(capsys):
    spec = importlib.util.spec_from_file_location("bench_fidelity", ROOT / "bench" / "fidelity.py")
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    assert bench.main(["--only", "(5.3)", "O2", "fig. 6.2"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert [o.split(" ", 1)[0] for o in out] == ["(5.3)", "fig.", "O2"]
    rows = select(ROWS, ["(5.3)", "fig. 6.2", "O2"])
    assert out == [line(r, compute(r)) for r in rows]
    assert out[1].startswith("fig. 6.2 koch11 TCP at the zero configuration (arm table) [m]: "
                             "1.2000 1.0000 -0.1000 | book: 1.2 1.0 -0.1 | reproduced")  # fmt: skip
    with pytest.raises(SystemExit):
        bench.main(["--only", "(9.99)"])


def test_the_book_procedure_runs_what_the_limits_refuse_and_says_so():
    """The L-1 line P'→K' starts on W6's 0° bound: with the limits it fails on that bound;
    on without_position_limits(l1) it runs, and its report names the robot as such."""
    from irlc.fidelity import without_position_limits
    from irlc.fidelity.steppers import LINE_PROGRAM, LINE_START
    from irlc.robots import load_robot
    from irlc.runtime.run import run_file

    limited = run_file(LINE_PROGRAM, seed_config=list(LINE_START))
    assert not limited.ok and "a6 (W6) position min" in limited.error.message
    book = without_position_limits(load_robot("l1"))
    run = run_file(LINE_PROGRAM, robot=book, seed_config=list(LINE_START))
    assert run.ok and run.report["robot"] == "l1 (position limits not enforced)"
    assert run.q[:, 5].min() < -0.17  # W6 went 10° below the bound it started on
    assert book.joints[5].limits.speed == load_robot("l1").joints[5].limits.speed
