"""The table printed after a run (rich): duration, per-joint motion, path error, obstacle
clearances, IK statistics, drives, warnings. Reads only the report dict (program units),
so it shows a loaded report the same way as a fresh run."""

from __future__ import annotations

from irlc.runtime import units
from irlc.runtime.model.naming import joint_label
from rich.console import Console, Group
from rich.panel import Panel
from rich.table import Table
from rich.text import Text


def shown_number(v, fmt: str = ".4g") -> str:
    """``v`` in ``fmt``, snapped (:func:`units.shown`, :func:`units.fixed` for ``.Nf``)."""
    if v is None:
        return "—"
    if fmt.startswith(".") and fmt.endswith("f"):
        return units.fixed(v, int(fmt[1:-1]))
    return format(units.shown(v), fmt)


MAX_WIDTH = 120  # columns of the summary written to a file or pipe
JOINT_COLUMN_MAX = 32  # the joint column's least width at most: longer names fold
_SHORT = {"position": "pos", "speed": "speed", "accel": "acc", "braking": "brake"}


def _limit_cell(joint: dict) -> Text:
    """Total time any limit of the joint was active, and the bound active longest."""
    t = joint.get("limit_active_s") or 0.0
    if not t:
        return Text("—", style="dim")
    labels = joint.get("limit_activity") or {}
    top = max(labels.items(), key=lambda kv: kv[1])[0] if labels else ""
    what, _, side = top.partition(" ")
    short = f" {_SHORT.get(what, what)} {side}".rstrip() if top else ""
    return Text(f"{t:.2f}s{short}", style="yellow")


def joints_table(report: dict, title: str = "joints (deg | mm, /s, /s²)") -> Table:
    """Per joint of the report (or of a cell's robot entry): range, end, peaks, limits."""
    table = Table(title=title, title_justify="left", show_edge=False, pad_edge=False)
    labels = [
        f"{joint_label(j['name'], j.get('robot_name'))} [{j['unit']}]" for j in report["joints"]
    ]
    longest = max((len(w) for label in labels for w in label.split()), default=5)
    # a narrow terminal wraps names, cuts none; a very long name folds instead of pushing
    # the numbers out of the table
    table.add_column("joint", min_width=min(longest, JOINT_COLUMN_MAX), overflow="fold")
    for name in ("min", "max", "end", "|v|max", "|a|max"):
        table.add_column(name, justify="right", no_wrap=True)
    table.add_column("limit active")
    following = any(j.get("max_following_error") is not None for j in report["joints"])
    if following:
        table.add_column("follow err", justify="right", no_wrap=True)
    end = report.get("end_joints") or []
    for i, j in enumerate(report["joints"]):
        cells: list = [
            Text(labels[i]),
            shown_number(j["min"], ".2f"),
            shown_number(j["max"], ".2f"),
            shown_number(end[i] if i < len(end) else None, ".2f"),
            shown_number(j["max_abs_speed"], ".1f"),
            shown_number(j["max_abs_accel"], ".0f"),
            _limit_cell(j),
        ]
        if following:
            cells.append(shown_number(j.get("max_following_error"), ".3g"))
        table.add_row(*cells)
    return table


def motors_table(report: dict) -> Table | None:
    """Per motor (robots with motor maps): start, end, travel, peak speed, limit and the
    travel time ``travel / limit`` (rad, rad/s, s) — Szkodny's motor-side figures."""
    motors = report.get("motors")
    if not motors:
        return None
    table = _table(
        "motors (rad, rad/s, s)", ("motor", "start", "end", "travel", "|v|max", "limit", "time")
    )
    for m in motors["axes"]:
        table.add_row(
            Text(joint_label(m["joint"], m.get("robot_name"))),
            shown_number(m["start_rad"], ".4f"),
            shown_number(m["end_rad"], ".4f"),
            shown_number(m["travel_rad"], ".4f"),
            shown_number(m["max_abs_speed_rad_s"], ".4g"),
            shown_number(m["speed_limit_rad_s"], ".4g"),
            shown_number(m["travel_time_s"], ".4f"),
        )
    return table


def overview_table(report: dict) -> Table:
    table = Table.grid(padding=(0, 2))
    table.add_column(style="bold")
    table.add_column()
    status = report["status"]
    style = "green" if status == "ok" else "red"
    table.add_row("status", Text(status, style=style))
    table.add_row("program / robot", f"{report['program']} on {report['robot']}")
    table.add_row(
        "duration",
        f"{shown_number(report['duration_s'], '.3f')} s, {report['samples']} samples at "
        f"IPO {shown_number(report['ipo_s'] * 1e3, '.3g')} ms, drives {report['drives']}",
    )
    table.add_row("path error", _path_error(report, cell=bool(report.get("robots"))))
    ik = report.get("ik") or {}
    table.add_row(
        "inverse transformation",
        f"{ik.get('cycles', 0)} cycles, {shown_number(ik.get('iterations_mean'), '.2f')} "
        f"iterations mean / {ik.get('iterations_max', 0)} max, "
        f"{ik.get('relaxed_cycles', 0)} relaxed",
    )
    for name, o in sorted((report.get("obstacles") or {}).items()):
        table.add_row(
            f"obstacle {name}",
            f"min clearance {shown_number(o.get('min_distance_mm'), '.1f')} mm"
            + (f" ({o['robot']})" if o.get("robot") else "")
            + (f" at t = {o['at_time_s']:.2f} s" if o.get("at_time_s") is not None else ""),
        )
    for label, text in clearance_rows(report):
        table.add_row(label, text)
    for label, text in measure_rows(report):
        table.add_row(label, text)
    collisions = _collisions(report)
    if collisions is not None:
        table.add_row("collisions", collisions)
    approximated = approximations_text(report)
    if approximated:
        table.add_row("approximated points", approximated)
    drives = report.get("drives_summary")
    if drives:
        table.add_row("drives", drives_text(drives))
    if report.get("verdict"):
        table.add_row("verdict criteria", _criteria(report["verdict"]))
    tool = report.get("tool")
    if tool:
        for label, text in zip(("tool (at the end)", ""), tool_text(tool), strict=True):
            table.add_row(label, text)
    error = report.get("error")
    if error:
        where = f"line {error.get('line')}, t = {shown_number(error.get('time_s'), '.3f')} s"
        table.add_row("error", Text(f"{where}: {error['message']}", style="red"))
    return table


def clearance_rows(report: dict) -> list[tuple[str, str]]:
    """A cell's clearance between links, per pair of robots (``clearance.pairs``): the
    least distance, the links, time and line; then R_CLEARANCE when one was kept. A
    program of one robot: its own links' least distance (``self_clearance``)."""
    rows = []
    own = report.get("self_clearance")
    if own and own.get("min_distance_mm") is not None:
        text = _pair_text(own, own=True)
        if own["min_distance_mm"] < 0:  # (R_CLEARANCE > 0 would have failed the run)
            text += " — they overlap: reported, not judged (R_CLEARANCE judges them)"
        rows.append(("own links", text))
    clearance = report.get("clearance") or {}
    ideal = ((report.get("ideal") or {}).get("clearance") or {}).get("pairs")
    for k, pair in enumerate(clearance.get("pairs") or []):
        if pair.get("min_distance_mm") is None:
            continue
        a, b = pair["robot_a"], pair["robot_b"]
        label = f"clearance {a}–{b}" if a != b else f"clearance {a} (own links)"
        text = _pair_text(pair, own=a == b)
        if ideal is not None and k < len(ideal):  # a drive run: the actual motion's
            commanded = shown_number(ideal[k].get("min_distance_mm"), ".1f")
            text += f" (actual motion; set points {commanded} mm)"
        rows.append((label, text))
    required = clearance.get("required_mm")
    if required:
        kept = _closer(clearance) if report.get("status") == "ok" else ""
        rows.append(("R_CLEARANCE", f"{shown_number(required, 'g')} mm kept{kept}"))
    return rows


def _closer(clearance: dict) -> str:
    """`` (floor's own links 5, 7: closer at home, kept apart only)``: a robot's own pairs
    below R_CLEARANCE in a run that kept it (docs/runtime.md: such a pair keeps ≥ 0)."""
    required = clearance["required_mm"]
    close = [
        f"{p['robot_a']}'s own links {p['link_a']}, {p['link_b']}"
        for p in clearance.get("pairs") or []
        if p["robot_a"] == p["robot_b"] and (p.get("min_distance_mm") or required) < required
    ]
    return f" ({'; '.join(close)}: closer at home, kept apart only)" if close else ""


def drives_text(drives: dict) -> str:
    """``decoupled, step 1 ms, could follow`` (rich markup: NOT in red)."""
    return f"{drives['level']}, step {shown_number(drives['step_s'] * 1e3, '.3g')} ms, " + (
        "could follow" if drives["could_follow"] else "[red]could NOT follow[/red]"
    )


def measure_rows(report: dict) -> list[tuple[str, str]]:
    """Issue 27's figures of a robot's report (or a cell's robot entry), a row each where
    present: the links' kinetic energy (largest, its time, the integral), the velocity
    ratio's extremes (SI), where the platform went and its largest distance from a line
    of ``WITH PLATFORM``."""
    rows = []
    energy = report.get("kinetic_energy")
    if energy and energy.get("max_j") is not None:
        rows.append((
            "kinetic energy",
            f"max {shown_number(energy['max_j'], '.4g')} J at t = "
            f"{shown_number(energy.get('max_at_time_s'), '.2f')} s, integral "
            f"{shown_number(energy.get('integral_j_s'), '.4g')} J·s",
        ))  # fmt: skip
    mvr = report.get("mvr")
    if mvr and mvr.get("min") is not None:
        rows.append((
            "velocity ratio (MVR)",
            f"min {shown_number(mvr['min'], '.4g')} at t = "
            f"{shown_number(mvr.get('min_at_time_s'), '.2f')} s, max "
            f"{shown_number(mvr.get('max'), '.4g')} at t = "
            f"{shown_number(mvr.get('max_at_time_s'), '.2f')} s (SI)",
        ))  # fmt: skip
    platform = report.get("platform")
    if platform:
        rows.append(("platform", _platform_text(platform)))
    return rows


def _platform_text(platform: dict) -> str:
    """``x 0 → 0, y 0 → 500 mm; 2 motions WITH PLATFORM, off their lines ≤ 1e-06 mm``."""
    coords = platform.get("coordinates") or []
    start, end = platform.get("start_mm") or [], platform.get("end_mm") or []
    went = ", ".join(
        f"{c} {shown_number(a, '.6g')} → {shown_number(b, '.6g')}"
        for c, a, b in zip(coords, start, end, strict=False)
    )
    motions = len(platform.get("motions") or [])
    if not motions:
        return f"{went} mm (no motion WITH PLATFORM)"
    noun, lines = ("motion", "its line") if motions == 1 else ("motions", "their lines")
    return (
        f"{went} mm; {motions} {noun} WITH PLATFORM, off {lines} ≤ "
        f"{shown_number(platform.get('max_error_mm'), '.3g')} mm"
    )


def _pair_text(pair: dict, own: bool = False) -> str:
    """``min 51.0 mm (ceiling link 5, floor link 4) at t = 5.64 s, line 21``."""
    if own:
        links = f"links {pair['link_a']}, {pair['link_b']}"
    else:
        links = f"{pair['robot_a']} link {pair['link_a']}, {pair['robot_b']} link {pair['link_b']}"
    line = pair.get("line")
    where = f"line {line}" if line else "the start configuration"  # line 0: before any
    return (
        f"min {shown_number(pair['min_distance_mm'], '.1f')} mm ({links}) at t = "
        f"{shown_number(pair.get('at_time_s'), '.2f')} s, {where}"
    )


def robot_tables(report: dict) -> list:
    """A cell's robots (``robots``): per robot its name, robot, placement and path error,
    its figures of issue 27 (:func:`measure_rows`), its joints and its motors."""
    parts: list = []
    for entry in report.get("robots") or []:
        at = ", ".join(shown_number(v, ".6g") for v in entry.get("at") or [])
        head = Text(f"{entry['name']} ({entry['robot']}) at ({at})", style="bold")
        parts += [Text(""), head]
        rows = [("path error", _path_error(entry)), *measure_rows(entry)]
        if entry.get("drives_summary"):
            rows.append(("drives", drives_text(entry["drives_summary"])))
        elif report.get("drives", "ideal") != "ideal":
            rows.append(("drives", "ideal: its robot file has no drive data"))
        if entry.get("verdict"):
            rows.append(("verdict criteria", _criteria(entry["verdict"])))
        if rows:
            grid = Table.grid(padding=(0, 2))
            grid.add_column()
            grid.add_column()
            for label, text in rows:
                grid.add_row(label, text)
            parts.append(grid)
        parts.append(joints_table(entry, f"{entry['name']}: joints (deg | mm, /s, /s²)"))
        motors = motors_table(entry)
        if motors is not None:
            motors.title = f"{entry['name']}: {motors.title}"
            parts.append(motors)
    return parts


def _collisions(report: dict) -> Text | None:
    """``allowed (--allow-collisions): slup 119.9 mm deep (link 6) at t = 2.31 s, line 13``;
    ``None`` when collisions fail the run (the default) and none happened."""
    c = report.get("collisions") or {}
    hits = [
        f"{p['obstacle']} {shown_number(p['depth_mm'], '.4g')} mm deep (link {p['link']}) at "
        f"t = {shown_number(p['time_s'], '.2f')} s, line {p['line']}"
        for p in c.get("penetrations") or []
    ]
    if c.get("allowed"):
        text = "; ".join(hits) if hits else "none"
        return Text(f"allowed (--allow-collisions): {text}", style="yellow" if hits else "")
    if hits:
        return Text(f"fail the run: {'; '.join(hits)}", style="red")
    return None


def approximations_text(report: dict) -> str:
    """``5 blended (used 38.1–40 mm, saved 1.0 s), 1 exact stop (line 17: the program
    ends)``; empty without approximate positioning."""
    entries = report.get("approximations") or []
    if not entries:
        return ""
    blended = [e for e in entries if e["blended"]]
    parts = []
    if blended:
        used = [e["used_mm"] for e in blended]
        saved = sum(e["saved_s"] for e in blended)
        span = f"{min(used):.3g}–{max(used):.3g}" if min(used) != max(used) else f"{used[0]:.3g}"
        parts.append(f"{len(blended)} blended (used {span} mm, saved {saved:.3g} s)")
    stops = [e for e in entries if not e["blended"]]
    if stops:
        first = stops[0]
        more = f" and {len(stops) - 1} more" if len(stops) > 1 else ""
        parts.append(
            f"{len(stops)} exact stop{'s' if len(stops) > 1 else ''} "
            f"(line {first['line']}: {first['note']}{more})"
        )
    return ", ".join(parts)


def _path_error(report: dict, cell: bool = False) -> str:
    """``max … mm, … deg``; with drives ``(actual motion; ideal …)`` and the tolerance that
    judged the path (the verdict's), if one did; a ``cell``'s: judged per robot."""
    text = (
        f"max {shown_number(report['max_path_error_mm'], '.3g')} mm, "
        f"{shown_number(report['max_orientation_error_deg'], '.3g')} deg"
    )
    ideal = report.get("ideal")
    if not ideal:
        return text
    text += (
        f" (actual motion; ideal {shown_number(ideal.get('max_path_error_mm'), '.3g')} mm, "
        f"{shown_number(ideal.get('max_orientation_error_deg'), '.3g')} deg"
    )
    if cell:
        return text + "; judged per robot below)"
    text += ")"
    criteria = (report.get("verdict") or {}).get("criteria") or {}
    path = criteria.get("path_tolerance_mm")
    if path is None:
        return text + ", not judged (no path tolerance stated)"
    return (
        text + f", tolerance {shown_number(path, 'g')} mm ({criteria.get('path_tolerance_from')})"
    )


def _criteria(verdict: dict) -> str:
    """What judged the drive run, in one line: the following-error bounds and where they
    come from, the path and orientation tolerances (and theirs), collisions, ratings."""
    c = verdict.get("criteria") or {}
    bounds: dict[str, set[str]] = {}
    for b in c.get("following_error_bound") or []:
        bounds.setdefault(b.get("from") or "", set()).add(
            f"{shown_number(b['bound'], '.3g')} {b['unit']}"
        )
    parts = [
        f"following error ≤ {' | '.join(sorted(v))}" + (f" ({src})" if src else "")
        for src, v in sorted(bounds.items())
    ]
    for key, what, unit in (("path", "path", "mm"), ("orientation", "orientation", "deg")):
        value = c.get(f"{key}_tolerance_{unit}")
        if value is None:
            parts.append(f"{what} not judged (no tolerance stated)")
        else:
            source = c.get(f"{key}_tolerance_from")
            parts.append(
                f"{what} ≤ {shown_number(value, 'g')} {unit}" + (f" ({source})" if source else "")
            )
    if c.get("collisions") == "allowed":
        parts.append("collisions allowed")
    required = c.get("clearance_required_mm")
    if required:  # a cell's actual clearance (docs/drives.md)
        tolerance = shown_number(c.get("clearance_tolerance_mm"), "g")
        parts.append(f"links ≥ R_CLEARANCE {shown_number(required, 'g')} mm − {tolerance} mm")
    for key, what in (("current_peak_A", "peak current"), ("torque_rating", "gear torque")):
        rated = [r for r in c.get(key) or [] if r.get("value") is not None]
        parts.append(f"{what} {'rated' if rated else 'not rated'}")
    return "; ".join(parts)


def _pose_text(pose) -> str:
    return "(" + ", ".join(shown_number(v, ".6g") for v in pose) + ")"


def tool_text(tool: dict) -> tuple[str, str]:
    """The active tool, and how it is composed: the robot file's tool, then ``R_TOOL``."""
    active = f"{_pose_text(tool['active'])} mm, deg"
    if not any(tool.get("r_tool") or []):
        return active, "= the robot file's tool (R_TOOL not set)"
    return active, (
        f"= robot file's {_pose_text(tool['robot_file'])} · R_TOOL {_pose_text(tool['r_tool'])}"
    )


MAX_STATEMENT_ROWS = 20  # rows of the cycle-time table in the summary (all in the report)


def _short(text: str, width: int = 40) -> str:
    return text if len(text) <= width else text[: width - 1] + "…"


def statement_text(row: dict, width: int = 40) -> str:
    """A row's statement as the table shows it: its text, cut to ``width``, and for a
    motion in a routine the routine and its call site, ``MOVE LIN p; (corner, called at
    line 12)``."""
    call = f" ({row['routine']}, called at line {row['called_at']})" if row.get("routine") else ""
    return _short(row["statement"], max(width - len(call), 12)) + call


def statements_table(report: dict) -> Table | None:
    """Cycle time per statement (``statements`` of the report): line, statement, start,
    duration, stop, binding limit, and the sum (the run's duration). More executions
    than fit (a loop) are summed per program line instead: runs, total, share."""
    rows = report.get("statements") or []
    if not rows:
        return None
    total = sum(r["duration_s"] or 0.0 for r in rows)
    if len(rows) > MAX_STATEMENT_ROWS:
        return _statement_lines_table(rows, total)
    overrides = {r.get("override_percent") for r in rows} - {None}
    shown = overrides != {100.0} and bool(overrides)  # the column only when it matters
    group = any(len(r.get("robots") or {}) > 1 for r in rows)  # a cell's group moves
    columns = ("line", "statement", "start", "duration", "stop", "limit")
    columns += ("override %",) if shown else ()
    table = _table("cycle time per statement (s)", columns + (("robots",) if group else ()))
    for r in rows:
        cells = [
            str(r["line"]), statement_text(r), shown_number(r["start_s"], ".3f"),
            shown_number(r["duration_s"], ".3f"), r["stop"] or "—", r["limit"] or "—",
        ]  # fmt: skip
        cells += [shown_number(r.get("override_percent"), "g")] if shown else []
        table.add_row(*cells, *([robots_text(r.get("robots") or {})] if group else []))
    blank = [""] * (2 + shown + group)
    table.add_row(
        "", Text("sum", style="dim"), "", Text(shown_number(total, ".3f"), style="bold"), *blank
    )
    return table


def robots_text(robots: dict) -> str:
    """A group move's parts: ``floor 3.100* ceiling 0.610`` — each robot's own time (s),
    ``*`` the one that set the group's."""
    parts = []
    for name, info in robots.items():
        own = info.get("duration_s")
        time = "follows" if own is None else shown_number(own, ".3f")
        parts.append(f"{name} {time}{'*' if info.get('set_the_time') else ''}")
    return " ".join(parts) if len(robots) > 1 else ""


def _statement_lines_table(rows: list[dict], total: float) -> Table:
    """Per statement (its line and text: the statements sharing a line apart, a routine's
    motion per call site): how often it ran, its total time and share."""
    per_statement: dict[tuple[int, str], list] = {}
    for r in rows:
        entry = per_statement.setdefault((r["line"], statement_text(r)), [0, 0.0])
        entry[0] += 1
        entry[1] += r["duration_s"] or 0.0
    title = f"cycle time per statement, summed (s), {len(rows)} runs"
    table = _table(title, ("line", "statement", "runs", "total", "share"))
    shown = list(per_statement.items())[:MAX_STATEMENT_ROWS]
    for (line, text), (runs, t) in shown:
        share = f"{100.0 * t / total:.1f} %" if total > 0 else "—"
        table.add_row(str(line), text, str(runs), shown_number(t, ".3f"), share)
    more = len(per_statement) - len(shown)
    label = f"… {more} more statements (report: statements)" if more > 0 else "sum"
    table.add_row(
        "", Text(label, style="dim"), "", Text(shown_number(total, ".3f"), style="bold"), ""
    )
    return table


def _table(title: str, columns: tuple[str, ...]) -> Table:
    table = Table(title=title, title_justify="left", show_edge=False, pad_edge=False)
    for name in columns:
        left = name in ("statement", "stop", "limit", "motor")
        table.add_column(name, justify="left" if left else "right", overflow="fold")
    return table


def render_summary(report: dict, console: Console) -> None:
    parts: list = [overview_table(report)]
    if report.get("robots"):  # a cell: a table per robot
        parts += robot_tables(report)
    elif report.get("joints"):
        parts += [Text(""), joints_table(report)]
    motors = motors_table(report)
    if motors is not None:
        parts += [Text(""), motors]
    statements = statements_table(report)
    if statements is not None:
        parts += [Text(""), statements]
    warnings = report.get("warnings") or []
    if warnings:
        shown = warnings[:10]
        more = len(warnings) - len(shown)
        body = "\n".join(f"• {w}" for w in shown) + (f"\n… and {more} more" if more else "")
        parts += [Text(""), Text("warnings", style="bold yellow"), Text(body, style="yellow")]
    panel = Panel(Group(*parts), title="irlc run", expand=False)
    if not console.is_terminal:  # a file or pipe: the natural width, nothing squeezed
        wide = console.options.update_width(1000)
        width = min(console.measure(panel, options=wide).maximum, MAX_WIDTH)
        if width > console.width:
            console = Console(
                file=console.file, width=width, highlight=False, soft_wrap=False, no_color=True
            )
    console.print(panel)


def _metrics(report: dict | None, loaded) -> dict:
    """Comparable numbers of a report, or of a loaded trace when there is no report."""
    if report:
        return {
            "duration_s": report.get("duration_s"),
            "max_path_error_mm": report.get("max_path_error_mm"),
            "joints": {
                j["name"]: (j.get("min"), j.get("max"), j.get("max_abs_speed"))
                for j in report.get("joints", [])
            },
        }
    cols = loaded.trace_columns or []
    data = loaded.trace
    out: dict = {"duration_s": None, "max_path_error_mm": None, "joints": {}}
    if data is None or not len(data):
        return out
    out["duration_s"] = float(data[-1, cols.index("t_s")])
    if "path_error_mm" in cols:
        out["max_path_error_mm"] = float(data[:, cols.index("path_error_mm")].max())
    for i, c in enumerate(cols):
        stem, _, unit = c.rpartition("_")
        if unit in ("deg", "mm") and stem and "_" not in stem and stem not in "xyzabc":
            sc = f"{stem}_speed_{unit}_s"
            speed = float(abs(data[:, cols.index(sc)]).max()) if sc in cols else None
            out["joints"][stem] = (float(data[:, i].min()), float(data[:, i].max()), speed)
    return out


def render_comparison(report: dict, other, console: Console) -> None:
    """This run against a loaded report / trace (``--compare``): the file's name on a line
    of its own (never folded into a narrow table), notes on what does not match, the table."""
    theirs = getattr(other, "report", None)
    a = _metrics(report, None)
    b = _metrics(theirs, other)
    lines = [f"compared with {getattr(other, 'path', 'previous run')}"]
    lines += [f"note: {note}" for note in comparison_notes(report, theirs or {}, a, b)]
    for line in lines:  # (a file name is text, never rich markup)
        console.print(line, soft_wrap=True, markup=False)
    table = Table(show_edge=False)
    for name in ("quantity", "this run", "other", "difference"):
        table.add_column(name, justify="left" if name == "quantity" else "right")

    def row(label: str, x, y) -> None:
        diff = None if x is None or y is None else x - y
        table.add_row(
            label, shown_number(x, ".4g"), shown_number(y, ".4g"), shown_number(diff, "+.3g")
        )

    row("duration s", a["duration_s"], b["duration_s"])
    row("max path error mm", a["max_path_error_mm"], b["max_path_error_mm"])
    for name, (lo, hi, sp) in a["joints"].items():
        olo, ohi, osp = b["joints"].get(name, (None, None, None))
        row(f"{name} min", lo, olo)
        row(f"{name} max", hi, ohi)
        row(f"{name} |speed| max", sp, osp)
    console.print(table)


def comparison_notes(report: dict, theirs: dict, mine: dict, other: dict) -> list[str]:
    """What makes a ``--compare`` row not like for like: another robot, a run that did not
    finish, joints on one side only (matched by name; ``mine``/``other`` from
    :func:`_metrics`)."""
    notes = []
    robot, their_robot = report.get("robot"), theirs.get("robot")
    if isinstance(their_robot, str) and robot and their_robot != robot:
        notes.append(
            f"that run is of robot {their_robot!r}, this one of {robot!r}: "
            "joints are matched by name"
        )
    status = theirs.get("status")
    if status is not None and status != "ok":
        notes.append(f"that run's status is {status!r}: its numbers stop where it stopped")
    if other["joints"]:
        missing = [j for j in mine["joints"] if j not in other["joints"]]
        extra = [j for j in other["joints"] if j not in mine["joints"]]
        if not theirs and (missing or extra):  # a trace: its columns are all there is
            notes.append(
                "a trace names no robot, and this one's joints differ from this run's: it "
                "may be another robot's; joints are matched by name"
            )
        if missing:
            notes.append(f"not in that run (shown as —): {', '.join(missing)}")
        if extra:
            notes.append(f"only in that run (not shown): {', '.join(extra)}")
    return notes
