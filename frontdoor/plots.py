"""PNG figures of a run, after the monograph's figures 6.4–6.29.

Per joint over time (one subplot per joint, at most six joints per figure, like the
book's figures for joints 1–6 and 7–11): positions, speeds and accelerations in
program units (deg | mm), with the robot's own limits and any program limits the run
reports drawn as dashed lines. Then the TCP path in 3D and the path length ``s(t)``
and path speed ``v(t) = ‖ṗ(t)‖`` (figures 6.4, 6.24); with simulated drives, the
following errors ``q − q_cmd`` and the motor currents. ``cycle_time``: a Gantt chart of
the report's ``statements`` (one bar per statement from its start to its end, one row per
program line, exact stops dark, approximated ones light, WAITs grey).

A cell (several robots, docs/interfaces.md "Cells of several robots"): the figures of each
robot as a program of that robot's, named ``NAME_joint_positions_1-6`` …
(:mod:`irlc.robot_runs`), the robots' TCP paths in the cell frame in one
``tcp_path_3d``, ``clearance`` — the least distance between links over time, with
``R_CLEARANCE`` — and the cell's ``cycle_time``.

``compare`` overlays a second run as crosses (the book's "— without / +++ with the
option" plots). Figures are written with matplotlib's Agg backend (extra ``plot``);
names are fixed (:data:`FIGURE_STEMS`) so scripts can rely on them.
"""

from __future__ import annotations

import io
import math
from pathlib import Path
from typing import Any

import numpy as np
from irlc.errors import UsageError
from irlc.files import atomic_write_bytes
from irlc.run_data import RunData, run_data
from irlc.runtime import units
from irlc.summary import statement_text

JOINTS_PER_FIGURE = 6
MARKERS_PER_CURVE = 60  # crosses of the compared run per subplot
DPI = 80
QUANTITIES = (  # (file stem, title, derivative order)
    ("joint_positions", "joint positions", 0),
    ("joint_speeds", "joint speeds", 1),
    ("joint_accels", "joint accelerations", 2),
)
FIGURE_STEMS = (  # a cell: per robot NAME_joint_positions_<a>-<b> …; clearance
    "joint_positions_<a>-<b>",
    "joint_speeds_<a>-<b>",
    "joint_accels_<a>-<b>",
    "tcp_path_3d",
    "tcp_path_speed",
    "cycle_time",
    "drive_following_errors_<a>-<b>",
    "drive_currents_<a>-<b>",
    "clearance",
)


def pyplot(what: str = "plots"):
    """matplotlib.pyplot on the file-only Agg backend, or a UsageError naming ``what``
    needs it and how to install it (the one place the optional dependency is imported)."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as e:
        raise UsageError(
            f"{what} need matplotlib: pip install 'irlc[plot]' (or pip install matplotlib)"
        ) from e
    return plt


def write_plots(run: Any, out_dir: str | Path, compare: Any = None) -> list[Path]:
    """Write the figures of ``run`` (optionally overlaid with ``compare``) into ``out_dir``;
    a cell's (several robots): each robot's figures of a program of that robot, named
    ``NAME_…``, the robots' TCP paths in one ``tcp_path_3d.png``, the clearance between
    links over time (``clearance.png``) and the cycle time."""
    plt = pyplot()
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    if getattr(run, "is_cell", False):
        return _cell_figures(plt, out, run, compare)
    d = run_data(run)
    c = None if compare is None else run_data(compare)
    paths: list[Path] = []
    for stem, title, order in QUANTITIES:
        paths += _joint_figures(plt, out, stem, d, c, order, title)
    if d.tcp is not None:
        paths.append(_save(plt, _tcp_path_3d(plt, [d], c), out / "tcp_path_3d.png"))
        paths.append(_save(plt, _tcp_path_speed(plt, d, c), out / "tcp_path_speed.png"))
    paths += _cycle_time_figure(plt, out, getattr(run, "report", None) or {})
    return paths + _drive_figures(plt, out, d, c, "")


def _cycle_time_figure(plt, out: Path, report: dict) -> list[Path]:
    statements = report.get("statements") or []
    if not statements:
        return []
    name = report.get("program") or "run"
    return [_save(plt, _cycle_time(plt, name, statements), out / "cycle_time.png")]


def _drive_figures(plt, out: Path, d: RunData, c: RunData | None, prefix: str) -> list[Path]:
    """With simulated drives: following errors and motor currents per joint."""
    paths: list[Path] = []
    if d.q_cmd is not None:
        paths += _joint_figures(
            plt, out, prefix + "drive_following_errors", d, c, "error", "following error q − q_cmd"
        )
    if d.current is not None:
        paths += _joint_figures(plt, out, prefix + "drive_currents", d, c, "current",
                                "motor current")  # fmt: skip
    return paths


def _cell_figures(plt, out: Path, run: Any, compare: Any) -> list[Path]:
    """Per robot its figures (``NAME_…``; a ``--compare`` trace of a cell overlays each
    robot's columns), every robot's TCP path in the cell frame, the clearance, the cycle
    time."""
    from irlc.robot_runs import compared_robot, robot_runs

    robots = robot_runs(run)
    names = [r.name for r in robots]
    paths: list[Path] = []
    for r in robots:
        d, prefix = r.data, f"{r.name}_"
        view = None if compare is None else compared_robot(compare, r.name, names)
        c = None if view is None else run_data(view, label=f"{r.name} (compare)")
        for stem, title, order in QUANTITIES:
            paths += _joint_figures(plt, out, prefix + stem, d, c, order, title)
        if d.tcp is not None:
            paths.append(
                _save(plt, _tcp_path_speed(plt, d, c), out / f"{prefix}tcp_path_speed.png")
            )
        paths += _drive_figures(plt, out, d, c, prefix)
    shown = [r.data for r in robots if r.data.tcp is not None]
    if shown:
        paths.append(_save(plt, _tcp_path_3d(plt, shown, None), out / "tcp_path_3d.png"))
    if "clearance_mm" in run.trace_columns:
        paths.append(_save(plt, _clearance(plt, run, compare), out / "clearance.png"))
    return paths + _cycle_time_figure(plt, out, run.report)


def _save(plt, fig, path: Path) -> Path:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=DPI, metadata={"Software": None})
    plt.close(fig)
    atomic_write_bytes(path, buf.getvalue())
    return path


# --------------------------------------------------------------------------- per joint


def _title(d: RunData) -> str:
    """The program's name, and a cell's robot's (``pair.irl, robot left``)."""
    program = d.report.get("program") or d.label or "run"
    robot = d.report.get("name")
    return f"{program}, robot {robot}" if robot else program


def _series(d: RunData, what) -> np.ndarray | None:
    """(k, n) values in program units for ``what`` = 0 | 1 | 2 | "error" | "current"."""
    if what == "current":
        return d.current
    if what == "error":
        return None if d.q_cmd is None else d.program_units(d.q - d.q_cmd)
    return d.program_units((d.q, d.qd, d.qdd)[what])


def axis_label(d: RunData, j: int, what) -> str:
    unit = "A" if what == "current" else d.unit(j, 0 if what == "error" else what)
    return f"{d.joint_label(j)} [{unit}]"


def _joint_figures(plt, out: Path, stem, d: RunData, c, what, title) -> list[Path]:
    values = _series(d, what)
    other = None if c is None else _series(c, what)
    paths = []
    for first in range(0, d.n, JOINTS_PER_FIGURE):
        joints = range(first, min(first + JOINTS_PER_FIGURE, d.n))
        fig = _joint_page(plt, d, c, values, other, joints, what, title)
        name = f"{stem}_{joints[0] + 1}-{joints[-1] + 1}.png"
        paths.append(_save(plt, fig, out / name))
    return paths


def _joint_page(plt, d, c, values, other, joints, what, title):
    rows = math.ceil(len(joints) / 2)
    fig, axes = plt.subplots(rows, 2, figsize=(10, 2.1 * rows + 0.6), squeeze=False)
    for ax in axes.flat[len(joints) :]:
        ax.set_visible(False)
    for ax, j in zip(axes.flat, joints, strict=False):
        ax.plot(d.times, values[:, j], "-", color="C0", lw=1.2, label=d.label or "run")
        shown = values[:, j]
        jc = None if other is None else _matching_joint(d, c, j)
        if jc is not None:
            shown = np.concatenate([shown, other[:, jc]])
            every = max(1, c.k // MARKERS_PER_CURVE)
            ax.plot(c.times[::every], other[::every, jc], "+", color="C3", ms=5,
                    label=c.label or "compare")  # fmt: skip
        _draw_limits(ax, d, j, what, shown)
        ax.set_ylabel(axis_label(d, j, what))
        ax.grid(True, lw=0.3)
    for ax in axes[-1]:
        ax.set_xlabel("t [s]")
    fig.suptitle(f"{_title(d)}: {title}", fontsize=11)
    if c is not None:
        axes.flat[0].legend(fontsize=7, loc="best")
    fig.tight_layout()
    return fig


def _matching_joint(d: RunData, c: RunData, j: int) -> int | None:
    if d.joint_names[j] in c.joint_names:
        return c.joint_names.index(d.joint_names[j])
    return j if j < c.n else None


def limit_values(d: RunData, j: int, order: int) -> list[tuple[float, str]]:
    """Limits of joint ``j`` in program units: ``[(value, "robot" | "program"), ...]``.

    The robot's own limits come from the model; program limits (JOINTLIMIT …) from
    the report's ``joints[j].program_limits`` = ``{"position"|"speed"|"accel": [lo, hi]}``
    when the run reports them.
    """
    out: list[tuple[float, str]] = []
    kind = ("position", "speed", "accel")[order]
    if d.model is not None and j < d.model.n:
        pair = getattr(d.model.joints[j].limits, kind)
        scale = units.joint_scale([d.joint_kinds[j]])[0]
        out += [(float(v) / scale, "robot") for v in pair if math.isfinite(v)]
    rows = d.report.get("joints") or []
    prog = (rows[j].get("program_limits") or {}) if j < len(rows) else {}
    for v in prog.get(kind) or ():
        if v is not None and math.isfinite(v):
            out.append((float(v), "program"))
    return out


def _draw_limits(ax, d: RunData, j: int, what, data: np.ndarray) -> None:
    """Dashed limit lines; the view shows the data plus the limits that come near it."""
    lo, hi = float(np.min(data)), float(np.max(data))
    span = max(hi - lo, 1e-9, 0.05 * max(abs(lo), abs(hi)))
    view = [lo - 0.08 * span, hi + 0.08 * span]
    if what in (0, 1, 2):
        for value, source in limit_values(d, j, what):
            style = {"robot": ("k", "--"), "program": ("C2", "-.")}[source]
            ax.axhline(value, color=style[0], ls=style[1], lw=0.9)
            if lo - span <= value <= hi + span:  # near enough to matter: keep in view
                view = [min(view[0], value - 0.05 * span), max(view[1], value + 0.05 * span)]
    ax.set_ylim(*view)


# --------------------------------------------------------------------------- TCP


def _tcp_path_3d(plt, runs: list[RunData], c):
    """The TCP path in 3D; several robots (a cell): each robot's path in the cell frame."""
    fig = plt.figure(figsize=(6.5, 5.5))
    ax = fig.add_subplot(projection="3d")
    cell = len(runs) > 1
    for k, d in enumerate(runs):
        p = d.tcp / units.MM
        label = d.label or "run"
        ax.plot(p[:, 0], p[:, 1], p[:, 2], "-", color=f"C{k}", lw=1.5, label=label)
        ax.scatter(*p[0], color="g", s=25, label=None if cell and k else "start")
        ax.scatter(*p[-1], color="r", s=25, label=None if cell and k else "end")
    if c is not None and c.tcp is not None:
        pc = c.tcp / units.MM
        every = max(1, c.k // (2 * MARKERS_PER_CURVE))
        ax.plot(pc[::every, 0], pc[::every, 1], pc[::every, 2], "+", color="C3",
                label=c.label or "compare")  # fmt: skip
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_zlabel("z [mm]")
    _equal_3d(ax, np.concatenate([d.tcp / units.MM for d in runs]))
    ax.legend(fontsize=7, loc="upper left")
    what = "TCP paths in the cell frame" if cell else "TCP path"
    ax.set_title(f"{runs[0].report.get('program') or runs[0].label or 'run'}: {what}", fontsize=11)
    fig.tight_layout()
    return fig


def _equal_3d(ax, p: np.ndarray) -> None:
    centre = (p.min(axis=0) + p.max(axis=0)) / 2
    half = max(float(np.max(p.max(axis=0) - p.min(axis=0))) / 2, 1.0)
    for setter, m in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre, strict=True):
        setter(m - half, m + half)


def path_length_and_speed(d: RunData) -> tuple[np.ndarray, np.ndarray]:
    """Path length ``s(t)`` [mm] (cumulative chord length) and speed ``ds/dt`` [mm/s]."""
    p = d.tcp / units.MM
    steps = np.linalg.norm(np.diff(p, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(steps)])
    v = np.gradient(s, d.times) if d.k > 1 else np.zeros(1)
    return s, v


def _tcp_path_speed(plt, d: RunData, c):
    fig, (ax_s, ax_v) = plt.subplots(2, 1, figsize=(8, 5), sharex=True)
    for run, fmt, colour in ((d, "-", "C0"), (c, "+", "C3")):
        if run is None or run.tcp is None:
            continue
        s, v = path_length_and_speed(run)
        every = 1 if run is d else max(1, run.k // MARKERS_PER_CURVE)
        label = run.label or ("run" if run is d else "compare")
        ax_s.plot(run.times[::every], s[::every], fmt, color=colour, label=label)
        ax_v.plot(run.times[::every], v[::every], fmt, color=colour, label=label)
    ax_s.set_ylabel("path s [mm]")
    ax_v.set_ylabel("speed v [mm/s]")
    ax_v.set_xlabel("t [s]")
    for ax in (ax_s, ax_v):
        ax.grid(True, lw=0.3)
    if c is not None:
        ax_s.legend(fontsize=7)
    ax_s.set_title(f"{_title(d)}: TCP path and speed")
    fig.tight_layout()
    return fig


# --------------------------------------------------------------------------- cycle time

_STOP_COLOURS = {"exact": "C0", "approximated": "C9", "failed": "C3", None: "0.6"}


def _cycle_time(plt, name: str, statements: list[dict]):
    """Gantt chart: per statement (rows, in order of first execution: its line and text,
    so statements sharing a line and a routine's calls are rows of their own) a bar per
    execution, from ``start_s`` for ``duration_s``."""
    keys = [(r["line"], statement_text(r)) for r in statements]
    order = list(dict.fromkeys(keys))
    row = {key: i for i, key in enumerate(order)}
    height = min(12.0, 1.5 + 0.3 * len(order))
    fig, ax = plt.subplots(figsize=(9, height))
    for r, key in zip(statements, keys, strict=True):
        colour = _STOP_COLOURS.get(r["stop"], "C0")
        ax.broken_barh([(r["start_s"], r["duration_s"])], (row[key] - 0.4, 0.8),
                       facecolors=colour, edgecolor="k", linewidth=0.3)  # fmt: skip
    labels = [f"{line}: {text}" for line, text in order]
    ax.set_yticks(range(len(order)), labels, fontsize=7)
    ax.invert_yaxis()
    ax.set_xlabel("t [s]")
    ax.grid(True, axis="x", lw=0.3)
    total = sum(r["duration_s"] for r in statements)
    ax.set_title(f"{name}: cycle time per statement, {total:.3f} s")
    fig.tight_layout()
    return fig


# --------------------------------------------------------------------------- clearance


def _clearance(plt, run: Any, compare: Any):
    """A cell's clearance between links over time (the trace's ``clearance_mm``: the least
    over every watched pair, between robots and within one), ``R_CLEARANCE`` dashed where
    one was kept, the least marked with its pair; a compared trace's as crosses."""
    columns = list(run.trace_columns)
    trace = np.asarray(run.trace, dtype=float)
    t, d = trace[:, columns.index("t_s")], trace[:, columns.index("clearance_mm")]
    fig, ax = plt.subplots(figsize=(8, 3.6))
    ax.plot(t, d, "-", color="C0", lw=1.2, label="this run")
    other_cols = getattr(compare, "trace_columns", None) or []
    if "clearance_mm" in other_cols and "t_s" in other_cols:
        other = np.asarray(compare.trace, dtype=float)
        every = max(1, len(other) // MARKERS_PER_CURVE)
        ax.plot(other[::every, other_cols.index("t_s")],
                other[::every, other_cols.index("clearance_mm")], "+", color="C3",
                label="compare")  # fmt: skip
    info = run.report.get("clearance") or {}
    if info.get("required_mm"):
        ax.axhline(info["required_mm"], color="k", ls="--", lw=0.9, label="R_CLEARANCE")
    if info.get("min_distance_mm") is not None and info.get("at_time_s") is not None:
        pair = (f"{info['robot_a']} link {info['link_a']} – {info['robot_b']} link "
                f"{info['link_b']}")  # fmt: skip
        ax.plot([info["at_time_s"]], [info["min_distance_mm"]], "o", color="C3", ms=5,
                label=f"min {info['min_distance_mm']:.1f} mm: {pair}")  # fmt: skip
    ax.set_xlabel("t [s]")
    ax.set_ylabel("clearance [mm]")
    ax.grid(True, lw=0.3)
    ax.legend(fontsize=7, loc="best")
    name = run.report.get("program") or "run"
    ax.set_title(f"{name}: clearance between links (least over all pairs)", fontsize=11)
    fig.tight_layout()
    return fig
