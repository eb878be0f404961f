"""After a study: the best and worst variants by a metric (rich table; the figure is
:mod:`irlc.study.figure`). It reads only the rows of results.csv (text), so it shows a
resumed study the same way as a fresh one."""

from __future__ import annotations

from irlc.errors import UsageError
from irlc.study.figure import number
from rich.table import Table

DEFAULT_SORT = "max_path_error_mm"


def split_sort(sort: str) -> tuple[str, bool]:
    """``"-min_clearance_post_mm"`` → ``("min_clearance_post_mm", True)``: a leading ``-``
    ranks the largest value best."""
    return (sort[1:], True) if sort.startswith("-") else (sort, False)


def check_metric(sort: str, columns: list[str], keys: list[str]) -> None:
    """A :class:`UsageError` unless ``sort`` names a numeric metric column."""
    from irlc.study.metrics import TEXT_COLUMNS

    metric, _ = split_sort(sort)
    numeric = [c for c in columns if c not in keys and c != "variant" and c not in TEXT_COLUMNS]
    if metric not in numeric:
        raise UsageError(f"--sort {metric}: not a metric column (columns: {', '.join(numeric)})")


def ranked(rows: list[dict[str, str]], sort: str) -> list[dict[str, str]]:
    """The rows of runs that went well (``status`` ok) with a number in the metric, best
    first: smallest, or largest for ``-METRIC`` (ties: variant order). A failed run's
    numbers stop where it stopped (a path error of 0 at t = 0 is no best)."""
    metric, descending = split_sort(sort)
    sign = -1.0 if descending else 1.0
    scored = [
        (sign * v, int(r["variant"]), r)
        for r in rows
        if r.get("status", "ok") == "ok" and (v := number(r.get(metric, ""))) is not None
    ]
    return [r for _, _, r in sorted(scored, key=lambda t: (t[0], t[1]))]


def summary_table(
    rows: list[dict[str, str]], keys: list[str], sort: str, k: int = 5, name: str = ""
) -> Table:
    """The ``k`` best and ``k`` worst variants by ``sort`` (:func:`ranked`), and the status
    count."""
    order = ranked(rows, sort)
    metric, descending = split_sort(sort)
    counts: dict[str, int] = {}
    for r in rows:
        counts[r["status"]] = counts.get(r["status"], 0) + 1
    status = ", ".join(f"{n} {s}" for s, n in sorted(counts.items()))
    table = Table(
        title=(f"{name}: " if name else "")
        + f"{len(rows)} variants ({status}); by {metric}, "
        + ("largest" if descending else "smallest")
        + " first"
        + ("" if counts.get("ok", 0) == len(rows) else " (of the runs that went well)"),
        title_justify="left",
        show_edge=False,
        pad_edge=False,
    )
    table.add_column("", style="bold")
    table.add_column("variant", justify="right")
    for key in keys:
        table.add_column(key, justify="right")
    table.add_column("status")
    table.add_column(metric, justify="right")
    best = order[:k]
    worst = [r for r in order[-k:][::-1] if r not in best]
    for label, group in (("best", best), ("worst", worst)):
        for i, r in enumerate(group):
            table.add_row(
                label if i == 0 else "",
                r["variant"], *(r[key] for key in keys), r["status"], r[metric],
            )  # fmt: skip
    return table
