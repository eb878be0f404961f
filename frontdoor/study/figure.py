"""The study's figure (``irlc study --plot FILE.png``): the metric against the varied keys.

Two rules, whatever the keys (:func:`layout` decides, :func:`plot` draws):

* **no key that changes the metric is hidden** — every key with more than one value in
  the rows is on an axis, a series (one line per value) or a panel of its own; no two
  variants are drawn into one heat-map cell or averaged into one point;
* **a failed variant shows as failed** — a red ``×`` at its parameters (at the foot of a
  panel whose y axis is the metric: a failed run's numbers stop where it stopped), never
  coloured or placed by its metric, and the title counts them.

Views: one varying key — the metric over it (a line over a ``[grid]`` key, dots over a
random one); two — a heat map for two grid keys with one variant per cell, else the
metric over one key with a series per value of a grid key of few values, else (two random
keys) the samples at their two values coloured by the metric; three or more — one panel
per key, the metric over that key for every variant (each variant is a point in every
panel). Text values (``run.drives``) are categories, in order of appearance. The figure
reads only the rows of results.csv (text), so a resumed study looks the same as a fresh one.
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass, field
from pathlib import Path

MAX_HEAT_X, MAX_HEAT_Y = 30, 12  # values of a heat map's keys
MAX_SERIES = 8  # values of a key drawn as one line each
FAILED_STYLE = {"marker": "x", "color": "tab:red", "linestyle": "none"}


@dataclass(frozen=True)
class Panel:
    """One axes of the figure: ``x`` on the x axis; ``y`` a key on the y axis (heat map,
    scatter) or ``None`` (the metric); ``series`` a key drawn as one line per value."""

    kind: str  # "line" | "dots" | "heat" | "scatter"
    x: str
    y: str | None = None
    series: str | None = None
    keys: tuple[str, ...] = field(default=())  # the keys this panel shows

    def __post_init__(self) -> None:
        shown = tuple(k for k in (self.x, self.y, self.series) if k is not None)
        object.__setattr__(self, "keys", shown)


def number(text: str | None) -> float | None:
    try:
        x = float(text)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


def failed(row: dict[str, str]) -> bool:
    """A variant whose run did not go well (its numbers are not comparable)."""
    return row.get("status", "ok") != "ok"


def varying(rows: list[dict[str, str]], keys: list[str]) -> list[str]:
    """The keys with more than one value among the rows (the others are constant)."""
    return [k for k in keys if len({r.get(k) for r in rows}) > 1]


def layout(rows: list[dict[str, str]], keys: list[str], grid) -> list[Panel]:
    """The panels that show every varying key (module doc)."""
    moving = varying(rows, keys) or keys[:1]
    if len(moving) == 1:
        k = moving[0]
        return [Panel("line" if k in grid else "dots", k)]
    if len(moving) == 2:
        a, b = moving
        cells = {(r[a], r[b]) for r in rows}
        heat = (
            a in grid and b in grid and len(cells) == len(rows)
            and _count(rows, a) <= MAX_HEAT_X and _count(rows, b) <= MAX_HEAT_Y
        )  # fmt: skip
        if heat:
            return [Panel("heat", a, b)]
        series = next((k for k in (b, a) if k in grid and _count(rows, k) <= MAX_SERIES), None)
        if series is not None:
            x = a if series == b else b
            return [Panel("line" if x in grid else "dots", x, series=series)]
        return [Panel("scatter", a, b)]
    return [Panel("dots", k) for k in moving]


def plot(
    rows: list[dict[str, str]],
    keys: list[str],
    metric: str,
    path: Path,
    grid: frozenset[str] | set[str] = frozenset(),
) -> Path:
    """Draw ``metric`` against the varied ``keys`` (``grid``: those of ``[grid]``) into
    the PNG ``path`` (module doc)."""
    from irlc.files import atomic_write_bytes
    from irlc.plots import pyplot

    plt = pyplot("--plot figures")
    panels = layout(rows, keys, grid)
    cols = min(len(panels), 3)
    lines = math.ceil(len(panels) / cols)
    fig, axes = plt.subplots(lines, cols, figsize=(7 if cols == 1 else 4.2 * cols, 4.5 * lines),
                             squeeze=False)  # fmt: skip
    for ax, panel in zip(axes.flat, panels, strict=False):
        _draw(fig, ax, panel, rows, metric, grid)
    for ax in list(axes.flat)[len(panels) :]:
        ax.set_visible(False)
    bad = sum(failed(r) for r in rows)
    fixed = [k for k in keys if k not in varying(rows, keys)]
    title = f"{metric}: {len(rows) - bad} ok" + (f", {bad} failed (×)" if bad else "")
    if fixed and len(keys) > 1:
        title += "; fixed: " + ", ".join(f"{k} = {rows[0][k]}" for k in fixed if rows)
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110, metadata={"Software": None})
    plt.close(fig)
    return atomic_write_bytes(path, buf.getvalue())


def _draw(fig, ax, panel: Panel, rows, metric: str, grid) -> None:
    good = [r for r in rows if not failed(r) and number(r.get(metric)) is not None]
    bad = [r for r in rows if failed(r)]
    heat = panel.kind == "heat"  # cells: every value an index
    xs = _Axis([r[panel.x] for r in rows], heat)
    if panel.kind in ("heat", "scatter"):
        ys = _Axis([r[panel.y] for r in rows], heat)  # type: ignore[index]
        if panel.kind == "heat":
            _heat(fig, ax, panel, good, metric, xs, ys)
        else:
            sc = ax.scatter([xs.at(r[panel.x]) for r in good], [ys.at(r[panel.y]) for r in good],
                            c=[number(r[metric]) for r in good], s=14, cmap="viridis")  # fmt: skip
            fig.colorbar(sc, ax=ax, label=metric)
        if bad:
            ax.plot([xs.at(r[panel.x]) for r in bad], [ys.at(r[panel.y]) for r in bad],
                    label=f"failed ({len(bad)})", **FAILED_STYLE)  # fmt: skip
            ax.legend(fontsize=7)
        ys.label(ax, "y")
        ax.set_ylabel(panel.y)
    else:
        levels = _ordered([r[panel.series] for r in rows]) if panel.series else [None]
        for level in levels:
            pts = sorted(
                (xs.at(r[panel.x]), number(r[metric]))
                for r in good
                if panel.series is None or r[panel.series] == level
            )
            single = len({p[0] for p in pts}) == len(pts)  # one point per x: a line
            style = "o-" if panel.kind == "line" and single else "o" if panel.x in grid else "."
            ax.plot([p[0] for p in pts], [p[1] for p in pts], style,
                    label=f"{panel.series} = {level}" if panel.series else None)  # fmt: skip
        if bad:  # below the metric's values: a failed run's metric is no value of it
            values = [number(r[metric]) for r in good] or [0.0]
            low, high = min(values), max(values)
            foot = low - 0.05 * ((high - low) or abs(low) or 1.0)
            ax.plot([xs.at(r[panel.x]) for r in bad], [foot] * len(bad),
                    label=f"failed ({len(bad)})", **FAILED_STYLE)  # fmt: skip
        if panel.series or bad:
            ax.legend(fontsize=7)
        ax.set_ylabel(metric)
        ax.grid(True, alpha=0.3)
    xs.label(ax, "x")
    ax.set_xlabel(panel.x)


def _heat(fig, ax, panel: Panel, good, metric: str, xs: _Axis, ys: _Axis) -> None:
    import numpy as np

    cells = np.full((len(ys.ticks), len(xs.ticks)), np.nan)  # failed cells stay empty
    for r in good:
        cells[ys.ticks.index(r[panel.y]), xs.ticks.index(r[panel.x])] = number(r[metric])
    im = ax.imshow(cells, origin="lower", aspect="auto", cmap="viridis")
    fig.colorbar(im, ax=ax, label=metric)


class _Axis:
    """Positions on an axis: the numbers themselves, or for a heat map and for text
    values the index of each distinct value (then :meth:`label` names the ticks)."""

    def __init__(self, values: list[str], categories: bool = False):
        self.numeric = all(number(v) is not None for v in values)
        self.ticks = _ordered(values) if self.numeric else list(dict.fromkeys(values))
        self._index = {v: i for i, v in enumerate(self.ticks)}
        self.categorical = categories or not self.numeric

    def at(self, value: str) -> float:
        if self.categorical:
            return float(self._index[value])
        return float(number(value))  # type: ignore[arg-type]

    def label(self, ax, which: str) -> None:
        if self.categorical:
            setter = ax.set_xticks if which == "x" else ax.set_yticks
            setter(range(len(self.ticks)), self.ticks, fontsize=7)


def _count(rows, key: str) -> int:
    return len({r[key] for r in rows})


def _ordered(values: list[str]) -> list[str]:
    """Distinct values: numbers ascending, then texts in order of appearance."""
    return sorted(dict.fromkeys(values), key=_sort_key)


def _sort_key(text: str):
    x = number(text)
    return (0, x) if x is not None else (1, 0.0)  # texts keep their order (stable sort)
