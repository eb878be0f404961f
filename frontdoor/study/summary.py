"""After a study: the best and worst variants by a metric (rich table) and a figure of the
metric against one or two parameters (a line per … or a heat map; matplotlib, extra
``plot``). Both read only the rows of results.csv (text), so they show a resumed study the
same way as a fresh one."""

from __future__ import annotations

import io
import math
from pathlib import Path

from irlc.errors import UsageError
from rich.table import Table

DEFAULT_SORT = "max_path_error_mm"


def _number(text: str) -> float | None:
    try:
        x = float(text)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


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
        if r.get("status", "ok") == "ok" and (v := _number(r.get(metric, ""))) is not None
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


def plot(
    rows: list[dict[str, str]],
    keys: list[str],
    metric: str,
    path: Path,
    grid: frozenset[str] | set[str] = frozenset(),
) -> Path:
    """``metric`` against the varied keys: one key — a line over a ``[grid]`` key's values
    (dots for a random key); two ``[grid]`` keys with few values — a heat map; otherwise —
    the first key on x, one line per value of a second grid key, or for a second random
    key the samples as dots coloured by the metric. Text values (``run.drives``) are
    categories, in the order they appear."""
    from irlc.plots import pyplot

    plt = pyplot("--plot figures")
    from irlc.files import atomic_write_bytes

    fig, ax = plt.subplots(figsize=(7, 4.5))
    kx = keys[0]
    ky = keys[1] if len(keys) > 1 else None
    xs, xticks = _axis([r[kx] for r in rows])
    ms = [_number(r.get(metric, "")) for r in rows]
    if ky is not None and kx in grid and ky in grid and _few(rows, kx, 30) and _few(rows, ky, 12):
        _heat(ax, fig, rows, kx, ky, metric)
    elif ky is not None and ky not in grid:
        ys, yticks = _axis([r[ky] for r in rows])
        pts = [(x, y, m) for x, y, m in zip(xs, ys, ms, strict=True) if m is not None]
        sc = ax.scatter([p[0] for p in pts], [p[1] for p in pts], c=[p[2] for p in pts], s=14)
        fig.colorbar(sc, ax=ax, label=metric)
        ax.set_xlabel(kx)
        ax.set_ylabel(ky)
        if yticks:
            ax.set_yticks(range(len(yticks)), yticks)
    else:
        levels = _ordered([r[ky] for r in rows]) if ky else [None]
        for level in levels:
            pts = sorted(
                (x, m)
                for x, m, r in zip(xs, ms, rows, strict=True)
                if m is not None and (ky is None or r[ky] == level)
            )
            single = len({p[0] for p in pts}) == len(pts)  # one point per x: a line
            style = "o-" if kx in grid and single else "o" if kx in grid else "."
            ax.plot([p[0] for p in pts], [p[1] for p in pts], style,
                    label=f"{ky} = {level}" if ky else None)  # fmt: skip
        ax.set_xlabel(kx)
        ax.set_ylabel(metric)
        if ky:
            ax.legend(fontsize=8)
        ax.grid(True, alpha=0.3)
    if xticks and not (ky is not None and kx in grid and ky in grid):
        ax.set_xticks(range(len(xticks)), xticks)
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110, metadata={"Software": None})
    plt.close(fig)
    return atomic_write_bytes(path, buf.getvalue())


def _ordered(values: list[str]) -> list[str]:
    """Distinct values: numbers ascending, then texts in order of appearance."""
    return sorted(dict.fromkeys(values), key=_sort_key)


def _few(rows, key: str, limit: int) -> bool:
    return len({r[key] for r in rows}) <= limit


def _axis(values: list[str]) -> tuple[list[float], list[str]]:
    """Positions on an axis: the numbers themselves, or category indices (and their
    labels) when some value is not a number."""
    nums = [_number(v) for v in values]
    if all(n is not None for n in nums):
        return [float(n) for n in nums], []  # type: ignore[arg-type]
    cats = list(dict.fromkeys(values))
    return [float(cats.index(v)) for v in values], cats


def _sort_key(text: str):
    x = _number(text)
    return (0, x) if x is not None else (1, 0.0)  # texts keep their order (stable sort)


def _heat(ax, fig, rows, kx, ky, metric) -> None:
    import numpy as np

    xs, ys = _ordered([r[kx] for r in rows]), _ordered([r[ky] for r in rows])
    grid = np.full((len(ys), len(xs)), np.nan)
    for r in rows:
        v = _number(r.get(metric, ""))
        if v is not None:
            grid[ys.index(r[ky]), xs.index(r[kx])] = v
    im = ax.imshow(grid, origin="lower", aspect="auto", cmap="viridis")
    ax.set_xticks(range(len(xs)), xs, rotation=45, fontsize=7)
    ax.set_yticks(range(len(ys)), ys, fontsize=7)
    ax.set_xlabel(kx)
    ax.set_ylabel(ky)
    fig.colorbar(im, ax=ax, label=metric)
