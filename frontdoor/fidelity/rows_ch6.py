"""The rows of the seed monograph's chapter 6 (the 11-joint test robot, koch11): the
observations O1–O18 of docs/robots.md and the figures' surviving tick ranges."""

from __future__ import annotations

import numpy as np
from irlc.fidelity import chapter6 as c6
from irlc.fidelity import kinematics_rows as kr
from irlc.fidelity.table import Result, Row, only


def koch11_tcp() -> Result:
    tcp = kr.koch11_zero_tcp() / 1e3
    return Result(
        " ".join(f"{v + 0.0:.4f}" for v in tcp), tuple(tcp), note="irlc fk koch11 at q = 0"
    )


def o1() -> Result:
    t = float(c6.run("square").times[-1])
    return Result(f"{t:.2f}", (t,), note="programs/square.irl, kinematic run")


def _active(program: str, lo: str, hi: str, expected: set) -> Result:
    found = c6.active(c6.joints(c6.run(program)), c6.SETS[lo], c6.SETS[hi])
    return Result(c6.describe(found), reproduced=found == expected, note=f"programs/{program}.irl")


def o2() -> Result:
    return _active("square_limits", "jmin_base", "jmax_base", {(11, "max")})


def o3() -> Result:
    return _active("square_j11", "jmin_j11", "jmax_j11", {(11, "min"), (11, "max")})


def o4() -> Result:
    order, change = c6.change_ranking("square_limits", "square_j11")
    top = ", ".join(f"J{j} {change[j - 1]:.1f}°" for j in order[:3])
    return Result(top, reproduced=set(order[:2]) == {7, 8}, note="largest changes, J1–J9")


def o6() -> Result:
    v = c6.speeds(c6.run("square_speed"))
    sides = c6.active(v, c6.SETS["jsmin"], c6.SETS["jsmax"])
    peak = float(np.abs(v[:, 10]).max())
    hit = {s for j, s in sides if j == 11}
    return Result(
        f"|v11| max {peak:.2f} deg/s, J11 speed bounds active: {', '.join(sorted(hit)) or 'none'}",
        (peak,),
        reproduced=bool(hit) and abs(peak - 25.0) <= c6.BOUND_TOL,
        note="programs/square_speed.irl",
    )


def o7() -> Result:
    found = c6.active(c6.joints(c6.run("square_speed")), c6.SETS["jmin_base"], c6.SETS["jmax_base"])
    return Result(c6.describe(found), reproduced=(11, "max") in found)


def o8() -> Result:
    base, limited = c6.peak_accels("square_limits"), c6.peak_accels("square_accel")
    return Result(
        f"{base[6]:.0f} → {limited[6]:.0f}",
        (base[6], limited[6]),
        reproduced=False,
        note=f"no J7 bound reached; set 6.3 binds J11 ({base[10]:.0f} → {limited[10]:.0f} deg/s²)"
        " — why: docs/robots.md, O8/O9",
    )


def o9() -> Result:
    base, limited = c6.peak_accels("square_limits"), c6.peak_accels("square_accel")
    rise = (limited - base) / base
    j = int(np.argmax(rise)) + 1
    unit = "mm/s²" if j == 10 else "deg/s²"
    return Result(
        f"J{j} ({base[j - 1]:.0f} → {limited[j - 1]:.0f} {unit})",
        reproduced=j == 10,
        note="largest relative rise of a peak |acceleration| with set 6.3",
    )


def o8_search() -> Result:
    s = c6.o8_search()
    followed = sum(c.ok for c in s.j7_above)
    return Result(
        f"{len(s.cases)} timings, J7 > 350 deg/s² in {len(s.j7_above)}, book-like in "
        f"{len(s.book_like)}",
        reproduced=bool(s.book_like),
        note="R_ACC 2000–12000 mm/s², R_SPEED_ORI 50–300 deg/s, R_SPEED 500–1000 mm/s from "
        f"konf_0; of the {len(s.j7_above)} timings where J7 exceeds 350 without set 6.3, the "
        f"set-6.3 run follows the path in {followed} (docs/robots.md)",
    )


def o10() -> Result:
    base = c6.peak_accels("square_accel")[9]
    heavy = c6.peak_accels("square_accel", w10_factor=4.0)[9]
    return Result(
        f"{base:.0f} → {heavy:.0f} (× {heavy / base:.2f})",
        (heavy / base,),
        reproduced=heavy < 0.5 * base,
        note="programs/square_accel.irl with w10 × 4",
    )


def o11() -> Result:
    result = c6.run("square_cyclic")
    q, lines = c6.joints(result), result.lines
    last = int(lines[-1])
    ends = [*np.flatnonzero((lines[:-1] == last) & (lines[1:] != last)).tolist(), len(q) - 1]
    worst = max(float(np.abs(q[k] - q[0]).max()) for k in ends)
    return Result(
        f"{len(ends)} laps, largest |q_end − q_start| {worst:.4f}",
        (worst,),
        reproduced=worst < c6.BOUND_TOL,
        note="deg | mm, programs/square_cyclic.irl",
    )


def o12() -> Result:
    result = c6.run("square_limits")
    q = c6.joints(result)
    cols = [result.trace_columns.index(c) for c in ("x_mm", "y_mm", "z_mm")]
    tcp = float(np.abs(result.trace[-1, cols] - result.trace[0, cols]).max())
    drift = float(np.abs(q[-1, 9] - q[0, 9]))
    return Result(
        f"J10 drifts {drift:.0f} mm, the TCP returns to {tcp:.3f} mm",
        (drift,),
        reproduced=drift > 1.0 and tcp < 0.1,
    )


def o13() -> Result:
    found = c6.active(
        c6.joints(c6.run("square_cyclic")), c6.SETS["jmin_base"], c6.SETS["jmax_base"]
    )
    return Result(
        c6.describe(found),
        reproduced=any(j == 10 for j, _ in found) and any(j == 11 for j, _ in found),
        note="J10 stays inside its ±500 mm with w10 = 5 per m² (docs/robots.md)",
    )


def o14() -> Result:
    fz = c6.run("square_freeze")
    pos = c6.active(c6.joints(fz), c6.SETS["jmin_j11"], c6.SETS["jmax_j11"])
    spd = c6.active(c6.speeds(fz), c6.SETS["jsmin"], c6.SETS["jsmax"])
    book = {(11, "min"), (11, "max"), (10, "min")}
    return Result(
        f"positions: {c6.describe(pos)}; speeds: {c6.describe(spd)}",
        reproduced=book <= pos and (11, "min") in spd,
        note="programs/square_freeze.irl",
    )


def o15() -> Result:
    qf, qs = c6.joints(c6.run("square_freeze")), c6.joints(c6.run("square_speed"))
    span_f, span_s = np.ptp(qf, axis=0), np.ptp(qs, axis=0)
    free = [j for j in range(11) if j not in (1, 2)]
    wider = [j + 1 for j in free if span_f[j] > span_s[j] + c6.BOUND_TOL]
    return Result(
        f"wider ranges on J{', J'.join(map(str, wider))}",
        reproduced=len(wider) == len(free),
        note="FREEZE 2, 3 against the speed run (same limits but J2, J3 free)",
    )


def _obstacle(program: str) -> float:
    """The smallest clearance to the post over the whole motion (collisions allowed, so
    that the run without avoidance goes on through the post, as the book's did)."""
    run = c6.run(program, allow_collisions=True)
    return float(run.report["obstacles"]["slup"]["min_distance_mm"])


def o16() -> Result:
    d = _obstacle("obstacle_line")
    return Result(f"{d:.1f}", (d,), reproduced=d < 0.0, note="smallest clearance (< 0: hit)")


def o17() -> Result:
    d = _obstacle("obstacle_line_avoid")
    return Result(f"{d:.1f}", (d,), reproduced=d > 0.0, note="smallest clearance")


def o18() -> Result:
    q = c6.joints(c6.run("obstacle_line_avoid"))
    top = float(q[:, 9].max())
    return Result(
        f"{top:.1f}",
        (top,),
        reproduced=abs(top - 700.0) <= c6.BOUND_TOL,
        note="J10's largest value with avoidance (set 6.6: ±700 mm)",
    )


def fig_6_20() -> Result:
    ranges = c6.freeze_ranges()
    inside = all(
        c6.FIG_6_20[j + 1][0] <= lo and hi <= c6.FIG_6_20[j + 1][1]
        for j, (lo, hi) in enumerate(ranges)
    )
    text = ", ".join(f"J{j + 1} {round(lo):d}…{round(hi):d}" for j, (lo, hi) in enumerate(ranges))
    return Result(
        text,
        reproduced=inside,
        note="the FREEZE run's joint ranges inside the figure's axes",
        figure="img/fidelity_fig6_20.png",
    )


def fig_6_24() -> Result:
    result = c6.run("obstacle_line", allow_collisions=True)  # the whole 5 m line
    path, speed = c6.tcp_path_speed(result)
    t, top = float(result.times[-1]), float(speed.max())
    return Result(
        f"{t:.2f} s, {path[-1]:.2f} m, peak speed {top:.2f} m/s",
        (t,),
        reproduced=abs(t - 5.5) <= 0.5 and top <= 1.5,
        note="programs/obstacle_line.irl (5 m down)",
        figure="img/fidelity_fig6_24.png",
    )


FIG_6_20_BOOK = (
    "axes "
    + ", ".join(f"J{j} {lo:g}…{hi:g}" for j, (lo, hi) in c6.FIG_6_20.items())
    + " (J1, J3, J5 as the issue reads the scan; J2, J4, J6 read here)"
)


def rows() -> list[Row]:
    """Seed 001, chapter 6, in the book's order."""
    return [
        Row("fig. 6.2", "koch11 TCP at the zero configuration (arm table)", "m",
            "1.2 1.0 -0.1", "irlc fk koch11 0 0 0 0 0 0 0 0 0 0 0", koch11_tcp,
            book_values=(1.2, 1.0, -0.1), tolerance=1e-9),
        Row("O1", "ch. 6 square, duration", "s", "≈ 12.5 (figs. 6.4–6.23)", only("O1"), o1,
            book_values=(12.5,), tolerance=0.5),
        Row("O2", "6.1 base set, active position bounds", "", "J11 max (60°) only",
            only("O2"), o2),
        Row("O3", "6.1 J11 at 0…60, active position bounds", "", "J11 min and max",
            only("O3"), o3),
        Row("O4", "6.1 joints changed most by narrowing J11", "deg", "J7 and J8", only("O4"),
            o4),
        Row("O5/O6", "6.2 speed set, J11's speed bound", "", "±25 deg/s active, J11's path "
            "changes", only("O5/O6"), o6),
        Row("O7", "6.2 speed run, active position bounds", "", "J11 max (60°) again",
            only("O7"), o7),
        Row("O8", "6.3 J7 peak |acceleration| without → with set 6.3", "deg/s²", "425 → 350",
            only("O8"), o8, book_values=(425.0, 350.0), tolerance=25.0),
        Row("O8/O9 search", "6.3 path timings where set 6.3 acts as in the book", "", "J7 cut "
            "to 350, J10 rises most, the path followed", only("O8/O9 search"), o8_search,
            slow=True),
        Row("O9", "6.3 largest rise of a peak |acceleration|", "", "J10", only("O9"), o9),
        Row("O10", "6.3 J10 peak |acceleration|, w10 → 4·w10", "mm/s²", "more than halved",
            only("O10"), o10),
        Row("O11", "6.4 CYCLIC: every lap ends in the start configuration", "", "yes",
            only("O11"), o11),
        Row("O12", "6.4 without CYCLIC", "", "another end configuration, same TCP pose",
            only("O12"), o12),
        Row("O13", "6.4 CYCLIC run, active position bounds", "", "J10 and J11", only("O13"),
            o13),
        Row("O14", "6.5 FREEZE 2, 3: active bounds", "", "positions: J11 min and max, J10 "
            "min; speeds: J11 min", only("O14"), o14),
        Row("O15", "6.5 freezing widens the other joints' motion", "", "yes", only("O15"),
            o15),
        Row("O16", "6.6 without avoidance an arm hits the point obstacle", "mm", "collision",
            only("O16"), o16),
        Row("O17", "6.6 with avoidance it clears", "mm", "no collision", only("O17"), o17),
        Row("O18", "6.6 with avoidance J10's upper bound is active", "mm", "700",
            only("O18"), o18, book_values=(700.0,), tolerance=0.01),
        Row("fig. 6.20", "FREEZE run, joints 1–6", "deg", FIG_6_20_BOOK,
            only("fig. 6.20"), fig_6_20),
        Row("fig. 6.24", "5 m line, duration and TCP speed", "", "5.5 s (caption); speed axis "
            "0…1.5 m/s", only("fig. 6.24"), fig_6_24, book_values=(5.5,), tolerance=0.5),
    ]  # fmt: skip
