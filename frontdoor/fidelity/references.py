"""Every reference of docs/fidelity.md in the books' order: Szkodny's chapters 3 (AS), 4
(L-1) and 5 (IRb-6), the seed monograph's chapter 6 (koch11), then the dynamics checks —
and :func:`compute`, which runs a row and judges it against the book's number."""

from __future__ import annotations

import importlib.util
from collections.abc import Iterable

from irlc.fidelity import rows_ch6, rows_szkodny
from irlc.fidelity.table import Result, Row


def all_rows() -> list[Row]:
    szkodny = rows_szkodny.rows()
    dynamics = [r for r in szkodny if r.needs]
    return [r for r in szkodny if not r.needs] + rows_ch6.rows() + dynamics


def select(rows: Iterable[Row], names: Iterable[str] = (), fast: bool = False) -> list[Row]:
    """The rows whose reference (or ``reference title``) is one of ``names`` (all when
    none are given), only the fast ones with ``fast``."""
    wanted = set(names)
    return [
        r for r in rows
        if (not wanted or r.ref in wanted or r.key in wanted) and not (fast and r.slow)
    ]  # fmt: skip


def available(row: Row) -> bool:
    """The optional module the row needs is installed (or it needs none)."""
    return row.needs is None or importlib.util.find_spec(row.needs) is not None


def compute(row: Row) -> Result:
    """The row's result; rows with book numbers are judged by their tolerance."""
    if not available(row):
        return Result(f"not computed: needs {row.needs}", note=f"pip install {row.needs}")
    result = row.compute()
    verdict = row.judge(result.values)
    if verdict is None:
        return result
    return Result(result.text, result.values, verdict, result.note, result.figure)
