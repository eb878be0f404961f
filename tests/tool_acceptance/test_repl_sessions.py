"""Scripted `irlc repl` sessions (interfaces.md § REPL), piped in as a user's script would be.

Held-out checks written from the spec and the tutorial only: every meta-command, blocks over
several lines, modal options open across entries, an error in the middle, WRITELN output.
"""

from __future__ import annotations

import itertools
import re

import pytest

from .helpers import (
    KONF_0,
    KONF_0_TEXT,
    angle_diff,
    assert_clean,
    fk_pose,
    joint_lines,
    pose_lines,
    read_trace,
    repl,
)

pytestmark = pytest.mark.scenario
NAMES11 = [f"a{i}" for i in range(1, 12)]
J11_MIN = (-180, -150, -180, 0, -240, -240, -240, -90, -180, -700, 0)
J11_MAX = (180, 90, 60, 240, 0, 60, 240, 90, 180, 700, 60)


def _assert_pose_close(printed, expected, mm=0.5, deg=0.05):
    for got, want in zip(printed[:3], expected[:3], strict=True):
        assert abs(got - want) < mm, (printed, expected)
    for got, want in zip(printed[3:], expected[3:], strict=True):
        assert abs(angle_diff(got, want)) < deg, (printed, expected)


# --- session 1: declarations, assignments, PTP/LIN, :where against `irlc fk` ----------------

SESSION_MOVES = f"""\
POSE: p0, p1;
MAIN_JOINT: konf_0;
INTEGER: i;
konf_0 := ({KONF_0_TEXT});
p0 := (11500, 1000, 3500, 0, 0, 0);
p1 := (11000, 1200, 3400, 0, 0, 0);
MOVE PTP konf_0;
:where
MOVE LIN p1;
:where
i := 21;
WRITELN('twice i = ', 2 * i);
MOVE LIN p0
:where
:quit
WRITELN('never printed');
"""


@pytest.fixture(scope="module")
def moves():
    return repl(SESSION_MOVES)


def test_session_moves_runs_clean(moves):
    assert_clean(moves)
    assert moves.rc == 0, moves.both
    assert "twice i = 42" in moves.out
    assert "never printed" not in moves.out, ":quit must end the session"


def test_where_after_ptp_shows_konf0_and_its_fk_pose(moves):
    joints = joint_lines(moves.out, NAMES11)
    assert joints, f"no joint vector a1=… a11=… printed:\n{moves.out}"
    # the first printed joint vector after MOVE PTP konf_0 is konf_0 itself
    for got, want in zip(joints[0], KONF_0, strict=True):
        assert abs(got - want) < 2e-3, (joints[0], KONF_0)
    poses = pose_lines(moves.out)
    assert poses, f"no 'pose (x, y, z, a, b, c)' printed:\n{moves.out}"
    _assert_pose_close(poses[0], fk_pose("koch11", KONF_0), mm=0.05, deg=0.01)


def test_where_pose_is_fk_of_where_joints(moves):
    """Every printed (pose, joints) pair agrees with the independent `irlc fk` command."""
    poses = pose_lines(moves.out)
    joints = joint_lines(moves.out, NAMES11)
    assert len(poses) >= 3 and len(joints) >= 3, moves.out
    # printed joints are rounded: allow the resulting lever-arm error on an 11 m arm
    for pose, q in zip(poses[-2:], joints[-2:], strict=True):
        _assert_pose_close(pose, fk_pose("koch11", q), mm=2.0, deg=0.1)


def test_move_lin_reaches_its_target(moves):
    poses = pose_lines(moves.out)
    assert any(_close(p, (11000, 1200, 3400, 0, 0, 0)) for p in poses), poses
    assert _close(poses[-1], (11500, 1000, 3500, 0, 0, 0)), poses


def _close(p, q, mm=0.05, deg=0.01):
    return all(abs(a - b) < mm for a, b in zip(p[:3], q[:3], strict=True)) and all(
        abs(angle_diff(a, b)) < deg for a, b in zip(p[3:], q[3:], strict=True)
    )


# --- session 2: blocks over several lines, procedures, loops, errors in the middle ----------

SESSION_BLOCKS = """\
INTEGER: i, s;
s := 0;
FOR i := 1 TO 4 DO
  s := s + i;
ENDFOR;
WRITELN('sum ', s);
IF s > 5 THEN
  WRITELN('big');
ELSE
  WRITELN('small');
ENDIF;
undeclared_x := 3;
PROCEDURE greet(INTEGER: n);
BEGIN
  WRITELN('hello ', n);
ENDPROC;
greet(7);
MOVE LIN (99000, 0, 3500, 0, 0, 0);
WHILE s < 13 DO
  s := s + 1;
ENDWHILE;
WRITELN('still alive ', s);
:quit
"""


@pytest.fixture(scope="module")
def blocks():
    return repl(SESSION_BLOCKS)


def test_multiline_blocks_run(blocks):
    assert_clean(blocks)
    out = blocks.out
    assert "sum 10" in out
    assert "big" in out and "small" not in out
    assert "hello 7" in out, "a PROCEDURE declared over several lines, then called"
    assert "still alive 13" in out, "the session continues after errors"


def test_compile_error_in_the_middle_has_a_position(blocks):
    text = blocks.both
    # the script's own line and column (undeclared_x := 3 is line 12 of SESSION_BLOCKS)
    assert re.search(r"<stdin>:12:1:\s*error", text), f"diagnostic without line:col:\n{text}"
    assert "undeclared_x" in text.lower()
    assert blocks.rc == 1, "tutorial: exit status of the first failing entry (1 = compile)"


def test_runtime_error_in_the_middle_is_reported(blocks):
    # the unreachable MOVE fails at run time; the message is shown, the session goes on
    text = blocks.both.lower()
    assert text.count("error") >= 2, blocks.both
    assert "still alive 13" in blocks.out


# --- session 3: modal options across entries and all the meta-commands ---------------------


def session_options(trace, plots) -> str:
    return f"""\
MAIN_JOINT: konf_0;
MAIN_JOINT_MIN: jmin;
MAIN_JOINT_MAX: jmax;
konf_0 := ({KONF_0_TEXT});
jmin := ({", ".join(map(str, J11_MIN))});
jmax := ({", ".join(map(str, J11_MAX))});
MOVE PTP konf_0;
:options
JOINTLIMIT jmin, jmax;
:options
MOVE LIN (11000, 1000, 3500, 0, 0, 0);
MOVE LIN (11000, 1500, 3500, 0, 0, 0);
JOINTLIMITEND;
:options
CYCLICSTART;
:options
MOVE LIN (11200, 1500, 3300, 0, 0, 0);
MOVE LIN (11000, 1500, 3500, 0, 0, 0);
CYCLICEND;
:where
:trace {trace}
:plot {plots}
:limits
:robot
:help
:reset
:where
:quit
"""


@pytest.fixture(scope="module")
def options_session(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("repl_options")
    trace, plots = tmp / "session.csv", tmp / "figs"
    return repl(session_options(trace, plots)), trace, plots


def test_options_session_runs_clean(options_session):
    res, _, _ = options_session
    assert_clean(res)
    assert res.rc == 0, res.both


def test_options_meta_command_tracks_modal_options(options_session):
    res, _, _ = options_session
    out = res.out.lower()
    # JOINTLIMIT shows up while active, CYCLIC while active
    assert "jointlimit" in out, res.out
    assert "cyclic" in out, res.out
    # the first :options (before JOINTLIMIT) names no active limit; check the order of
    # appearance: jointlimit mentioned before cyclic, and "no modal options" at the start
    first_opt = out.find("jointlimit")
    assert out.find("cyclic") > first_opt


def test_trace_meta_command_writes_the_interface_columns(options_session):
    _, trace, _ = options_session
    assert trace.exists(), ":trace FILE wrote nothing"
    header, rows = read_trace(trace)
    expected = (
        ["t_s", "line"]
        + [f"a{i}_deg" for i in range(1, 10)]
        + ["a10_mm", "a11_deg"]
        + [f"a{i}_speed_deg_s" for i in range(1, 10)]
        + ["a10_speed_mm_s", "a11_speed_deg_s"]
        + [f"a{i}_accel_deg_s2" for i in range(1, 10)]
        + ["a10_accel_mm_s2", "a11_accel_deg_s2"]
        + ["x_mm", "y_mm", "z_mm", "a_deg", "b_deg", "c_deg", "path_error_mm"]
    )
    assert header[: len(expected)] == expected, header
    assert len(rows) > 50
    col = {h: i for i, h in enumerate(header)}
    times = [r[col["t_s"]] for r in rows]
    assert all(b > a for a, b in itertools.pairwise(times)), "time not increasing"
    # the last row is where the robot stood before :reset: the cyclic block ended on the
    # configuration it started with, and the pose is FK of the joints
    last = rows[-1]
    q = [last[col[h]] for h in expected[2:13]]
    pose = [last[col[h]] for h in ("x_mm", "y_mm", "z_mm", "a_deg", "b_deg", "c_deg")]
    _assert_pose_close(pose, fk_pose("koch11", q), mm=0.01, deg=0.001)
    _assert_pose_close(pose, (11000, 1500, 3500, 0, 0, 0), mm=0.05, deg=0.01)


def test_jointlimit_across_entries_held_a11(options_session):
    """a11 stayed inside the program's 0…60 deg while JOINTLIMIT was open."""
    _, trace, _ = options_session
    header, rows = read_trace(trace)
    col = {h: i for i, h in enumerate(header)}
    a11 = [r[col["a11_deg"]] for r in rows]
    assert min(a11) >= -1e-6 and max(a11) <= 60 + 1e-6, (min(a11), max(a11))


def test_cyclic_across_entries_returns_to_reference(options_session):
    _, trace, _ = options_session
    header, rows = read_trace(trace)
    col = {h: i for i, h in enumerate(header)}
    names = [f"a{i}_deg" for i in range(1, 10)] + ["a10_mm", "a11_deg"]
    # reference = configuration at CYCLICSTART = the first sample at (11000, 1500, 3500)
    # after the JOINTLIMIT moves; the end configuration must equal it
    at_ref = [
        r
        for r in rows
        if abs(r[col["x_mm"]] - 11000) < 1e-3
        and abs(r[col["y_mm"]] - 1500) < 1e-3
        and abs(r[col["z_mm"]] - 3500) < 1e-3
    ]
    assert len(at_ref) >= 2
    first, last = at_ref[0], rows[-1]
    for n in names:
        assert abs(first[col[n]] - last[col[n]]) < 0.05, (n, first[col[n]], last[col[n]])


def test_plot_meta_command_writes_pngs(options_session):
    _, _, plots = options_session
    pngs = sorted(plots.glob("*.png"))
    assert pngs, ":plot DIR wrote no PNG"
    for p in pngs:
        assert p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and p.stat().st_size > 5000


def test_limits_robot_help_reset(options_session):
    res, _, _ = options_session
    out = res.out
    assert "koch11" in out, ":robot names the robot"
    assert "-700" in out and "700" in out, ":limits shows a10's ±700 mm"
    for meta in (":where", ":robot", ":limits", ":options", ":trace", ":plot", ":reset", ":quit"):
        assert meta in out, f":help does not mention {meta}"
    # after :reset the robot stands at its home again (koch11 home = konf_0)
    joints = joint_lines(out, NAMES11)
    for got, want in zip(joints[-1], KONF_0, strict=True):
        assert abs(got - want) < 2e-3, joints[-1]


# --- session 4: planar3 ---------------------------------------------------------------------

SESSION_PLANAR = """\
POSE: a;
a := (1500, 1200, 0, 0, 0, 0);
MOVE LIN a;
:where
WRITELN('x is ', ROUND(R_ACT_POSE.x));
:robot
:quit
"""


def test_planar3_session():
    res = repl(SESSION_PLANAR, robot="planar3")
    assert_clean(res)
    assert res.rc == 0, res.both
    assert "x is 1500" in res.out
    assert "planar3" in res.out
    joints = joint_lines(res.out, ["a1", "a2", "a3"])
    poses = pose_lines(res.out)
    assert joints and poses, res.out
    # planar 3R with unit links: x = Σ cos(cumulative angles), y = Σ sin(...)
    import math

    q = [math.radians(v) for v in joints[-1]]
    x = 1000 * (math.cos(q[0]) + math.cos(q[0] + q[1]) + math.cos(sum(q)))
    y = 1000 * (math.sin(q[0]) + math.sin(q[0] + q[1]) + math.sin(sum(q)))
    assert abs(x - 1500) < 1.0 and abs(y - 1200) < 1.0, (x, y, joints[-1])
    assert abs(poses[-1][0] - 1500) < 0.05 and abs(poses[-1][1] - 1200) < 0.05
