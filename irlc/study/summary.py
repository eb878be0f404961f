"""After a study: the best and worst variants by a metric (rich table) and a figure of the
metric against one or two parameters (a line per … or a heat map; matplotlib, extra
``plot``). Both read only the rows of results.csv (text), so they show a resumed study the
same way as a fresh one."""

from __future__ import annotations

import math
from pathlib import Path

from rich.table import Table

from irlc.errors import UsageError

DEFAULT_SORT = "max_path_error_mm"


def _number(text: str) -> float | None:
    try:
        x = float(text)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


def check_metric(metric: str, columns: list[str], keys: list[str]) -> None:
    if metric not in columns or metric in keys or metric == "variant":
        numeric = [c for c in columns if c not in keys and c not in ("variant", "status", "error")]
        raise UsageError(f"--sort {metric}: not a metric column (columns: {', '.join(numeric)})")


def ranked(rows: list[dict[str, str]], metric: str) -> list[dict[str, str]]:
    """Rows with a number in ``metric``, smallest first (ties: variant order)."""
    scored = [
        (v, int(r["variant"]), r) for r in rows if (v := _number(r.get(metric, ""))) is not None
    ]
    return [r for _, _, r in sorted(scored, key=lambda t: (t[0], t[1]))]


def summary_table(rows: list[dict[str, str]], keys: list[str], metric: str, k: int = 5) -> Table:
    """The ``k`` best (smallest ``metric``) and ``k`` worst variants, and the status count."""
    order = ranked(rows, metric)
    counts: dict[str, int] = {}
    for r in rows:
        counts[r["status"]] = counts.get(r["status"], 0) + 1
    status = ", ".join(f"{n} {s}" for s, n in sorted(counts.items()))
    table = Table(
        title=f"{len(rows)} variants ({status}); by {metric}, smallest first",
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


def _pyplot():
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as e:
        raise UsageError(
            "--plot needs matplotlib: pip install 'irlc[plot]' (or pip install matplotlib)"
        ) from e
    return plt


def plot(rows: list[dict[str, str]], keys: list[str], metric: str, path: Path) -> Path:
    """``metric`` against the first varied key (a line per value of the second key, if
    any), or a heat map over the first two keys when both have few values (a grid)."""
    plt = _pyplot()
    from irlc.files import atomic_write_bytes

    fig, ax = plt.subplots(figsize=(7, 4.5))
    xs = [_number(r[keys[0]]) for r in rows]
    ys = [_number(r.get(metric, "")) for r in rows]
    second = keys[1] if len(keys) > 1 else None
    levels = sorted({r[second] for r in rows}, key=_sort_key) if second else [None]
    firsts = sorted({r[keys[0]] for r in rows}, key=_sort_key)
    if second and len(levels) <= 12 and len(firsts) <= 30:
        _heat(ax, fig, rows, keys[0], second, firsts, levels, metric)
    else:
        for level in levels:
            pts = sorted(
                (x, y)
                for x, y, r in zip(xs, ys, rows, strict=True)
                if x is not None and y is not None and (second is None or r[second] == level)
            )
            style = "o-" if len(pts) < 200 else "."
            ax.plot([p[0] for p in pts], [p[1] for p in pts], style,
                    label=f"{second} = {level}" if second else None)  # fmt: skip
        ax.set_xlabel(keys[0])
        ax.set_ylabel(metric)
        if second:
            ax.legend(fontsize=8)
        ax.grid(True, alpha=0.3)
    fig.tight_layout()
    import io

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110, metadata={"Software": None})
    plt.close(fig)
    return atomic_write_bytes(path, buf.getvalue())


def _sort_key(text: str):
    x = _number(text)
    return (0, x, "") if x is not None else (1, 0.0, text)


def _heat(ax, fig, rows, kx, ky, xs, ys, metric) -> None:
    import numpy as np

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
