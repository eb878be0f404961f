"""The REPL: scripted sessions through a pipe, plus the input-shape helpers."""

from __future__ import annotations

import math
import subprocess
import sys

import pytest
from irlc.repl import (
    block_depth,
    classify,
    is_complete,
    numbered_entries,
    read_entries,
    token_styles,
)

IRLC = [sys.executable, "-c", "from irlc.cli import entry; entry()"]


def _session(script: str, *args: str, cwd=None) -> subprocess.CompletedProcess:
    return subprocess.run(
        [*IRLC, "repl", "--robot", "koch11", *args],
        input=script,
        capture_output=True,
        text=True,
        timeout=120,
        cwd=cwd,
    )


def _compiler_available() -> bool:
    try:
        from irlc.lang.compiler import compile_source  # noqa: F401
        from irlc.runtime.control.executor import SimulatedController  # noqa: F401
    except ImportError:
        return False
    return True


needs_runtime = pytest.mark.skipif(not _compiler_available(), reason="compiler/runtime missing")


def test_entry_shapes():
    assert classify("POSE: p, q;") == "typed"
    assert classify("pose: p := (1, 2, 3, 0, 0, 0)") == "typed"
    assert classify("VAR REAL: x;") == "decl"
    assert classify("x := 1") == "stmt"
    assert classify(":where") == "meta"
    assert classify("IMPORT DATALIST cell;") == "import"
    assert classify("  { only a comment }  ") == "empty"
    assert block_depth("IF a THEN WHILE b DO x := 1; ENDWHILE") == 1
    assert block_depth("JOINTLIMIT a, b; JOINTLIMITEND") == 0  # options are not blocks
    assert not is_complete("PROCEDURE p; BEGIN")
    assert not is_complete("x := 1; { comment")
    assert is_complete("WRITELN('IF');")  # keywords in strings do not count


def test_entries_from_lines():
    text = "IF x > 1 THEN\n  y := 2;\nENDIF\n:where\n(* a\nENDIF *) z := 1\n"
    assert list(read_entries(iter(text.splitlines(keepends=True)))) == [
        "IF x > 1 THEN\n  y := 2;\nENDIF",
        ":where",
        "(* a\nENDIF *) z := 1",
    ]
    assert [n for n, _ in numbered_entries(iter(text.splitlines(keepends=True)))] == [1, 4, 5]
    assert list(numbered_entries(iter(["\n", "  x := 1\n", "\n", "WHILE a DO\n", "ENDWHILE"]))) == [
        (1, ""),
        (2, "  x := 1"),
        (3, ""),
        (4, "WHILE a DO\nENDWHILE"),
    ]


def test_a_meta_command_inside_an_open_block_runs_at_once():
    # it was kept as a line of the block: 'IF TRUE THEN' + ':where' compiled as the label
    # 'THEN:' ("'THEN' is a reserved word and cannot be a label"); inside a comment it is text
    import io

    from irlc.repl import Session, run_plain

    text = "IF TRUE THEN\n:where\n  WRITELN(7);\nENDIF;\n{ open\n:where\n} WRITELN(8);\n"
    assert list(numbered_entries(iter(text.splitlines()))) == [
        (2, ":where"),
        (1, "IF TRUE THEN\n  WRITELN(7);\nENDIF;"),
        (5, "{ open\n:where\n} WRITELN(8);"),
    ]
    printed: list[str] = []
    script = text + "WHILE TRUE DO\n:quit\nENDWHILE;\n"  # :quit ends the session there
    assert run_plain(Session("planar3"), io.StringIO(script), printed.append) == 0
    assert printed[0].startswith("t = 0.000 s  pose (2000, 1000, 0, 0, 0, 0)")
    assert printed[-2:] == ["7", "8"], printed


def test_highlighting_covers_the_line():
    line = "MOVE LIN p WITH SPEED := 200 { fast } 'x'"
    frags = token_styles(line, frozenset({"MOVE", "LIN", "WITH"}))
    assert "".join(t for _, t in frags) == line
    styles = dict((t, s) for s, t in frags)
    assert styles["MOVE"] == styles["WITH"] != styles["p"]
    assert styles["200"] != styles["{ fast }"]


@needs_runtime
def test_scripted_session():
    script = "\n".join(
        [
            "POSE: p := (11500, 1000, 3500, 0, 0, 0);",
            "MOVE LIN (11000, 1000, 3500, 0, 0, 0)",
            ":where",
            "MOVE LIN p + 1;",  # a compile error: the session goes on
            "REAL: x;",
            "x := 2.5",
            "IF x > 2 THEN",
            "  WRITELN('big', x * 2);",
            "ENDIF",
            ":options",
            ":quit",
            "WRITELN('never');",
        ]
    )
    res = _session(script + "\n")
    out = res.stdout.splitlines()
    assert res.returncode == 1, res.stderr  # the first failure was a compile error
    assert "Traceback" not in res.stdout + res.stderr
    moved = [i for i, line in enumerate(out) if line.startswith("→ t = ")]
    assert len(moved) == 1
    assert "pose (11000, 1000, 3500, 0, 0, 0)" in out[moved[0]]
    where = out[moved[0] + 2]  # :where repeats the pose, without the arrow
    assert where.startswith("t = ") and "pose (11000, 1000, 3500, 0, 0, 0)" in where
    # the straight 500 mm line at R_SPEED 500, R_ACC 1000: t = s/v + v/a = 1.5 s (+ 1 cycle)
    t = float(where.split()[2])
    assert math.isclose(t, 1.5, abs_tol=0.03)
    err = out.index("<stdin>:4:12: error: cannot add POSE and INTEGER")
    assert out[err + 1].strip() == "MOVE LIN p + 1;" and out[err + 2].strip() == "^"
    assert "big5.0" in out
    assert "no modal options active" in out
    assert "never" not in res.stdout


@needs_runtime
def test_modal_options_persist_and_runtime_errors_continue(tmp_path):
    jmin = "(-180, -150, -180, 0, -240, -240, -240, -90, -180, -700, 0)"
    jmax = "(180, 90, 60, 240, 0, 60, 240, 90, 180, 700, {a11})"
    script = "\n".join(
        [
            f"MAIN_JOINT_MIN: jmin := {jmin};",
            f"MAIN_JOINT_MAX: jmax := {jmax.format(a11=60)};",
            f"MAIN_JOINT_MAX: tight := {jmax.format(a11=20)};",
            "JOINTLIMIT jmin, jmax;",
            "JOINTLIMIT jmin, jmax;",  # already on: a run-time error, the session goes on
            ":options",
            "JOINTLIMITEND;",
            "JOINTLIMIT jmin, tight;",  # a11 is at 21.119 deg (home): excluded
            "JOINTLIMIT jmin, jmax;",
            "MOVE LIN (11000, 1000, 3500, 0, 0, 0);",
            f":trace {tmp_path / 'session.csv'}",
            ":quit",
        ]
    )
    res = _session(script + "\n")
    out = res.stdout.splitlines()
    assert "Traceback" not in res.stdout + res.stderr
    errors = [line for line in out if "error: run-time failure" in line]
    assert len(errors) == 2
    assert errors[0].startswith("<stdin>:5:1: ") and errors[1].startswith("<stdin>:8:1: ")
    assert "already on" in errors[0]
    assert "a11" in errors[1] and "20" in errors[1]
    assert res.returncode == 2
    active = next(line for line in out if line.startswith("JOINTLIMIT min"))
    assert active.endswith("max (180, 90, 60, 240, 0, 60, 240, 90, 180, 700, 60)")
    assert any(line.startswith("→ t = ") for line in out)  # the move ran under the limits
    trace = (tmp_path / "session.csv").read_text().splitlines()
    assert trace[0].startswith("t_s,line,a1_deg")
    assert len(trace) > 100  # ≈ 1.5 s of 10 ms samples
    a11 = trace[0].split(",").index("a11_deg")
    assert all(-1e-6 <= float(row.split(",")[a11]) <= 60 + 1e-6 for row in trace[1:])


@needs_runtime
def test_unknown_robot_is_a_usage_error():
    res = subprocess.run(
        [*IRLC, "repl", "--robot", "no_such_robot"],
        input=":quit\n",
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert res.returncode == 3 and "no_such_robot" in res.stderr
    assert "Traceback" not in res.stderr


@needs_runtime
def test_loops_leave_no_temporaries_behind():
    """Regression (acceptance): after a FOR (or CASE) entry the session state kept the
    loop's hidden `$for` global, and every later entry failed with "the code declares 2
    globals but the session state has 3"."""
    from irlc.repl import Session

    s = Session("planar3")
    for text in ("INTEGER: i, n;", "n := 0;", "FOR i := 1 TO 4 DO\n  n := n + i;\nENDFOR",
                 "CASE n OF 10: n := n + 1; ENDCASE", "REAL: v;", "v := 0.5;"):  # fmt: skip
        entry = s.enter(text)
        assert entry.failure == 0, (text, entry.lines)
    out = s.enter("WRITELN(n, ' ', v)")
    assert out.failure == 0 and out.lines == ["11 0.5"], out.lines
    assert not any(slot.name.startswith("$") for slot in s.state.global_slots)


def _diagnostics(printed: list[str]) -> dict[str, tuple[str, int]]:
    """header → (the source line shown under it, the caret's 1-based column)."""
    lines = "\n".join(printed).splitlines()
    out = {}
    for k, line in enumerate(lines):
        if ": error: " in line and k + 2 < len(lines) and lines[k + 2].strip().startswith("^"):
            out[line] = (lines[k + 1][2:], lines[k + 2].index("^") - 1)
    return out


@needs_runtime
def test_script_diagnostics_point_at_script_lines_and_columns():
    """A piped script's diagnostics say <stdin>:LINE:COL with LINE and COL in the script,
    and the caret stands under that column of the script's own text (indentation, the
    short form POSE: q := …, blocks over several lines)."""
    import io

    from irlc.repl import Session, run_plain

    script = [
        "REAL: y;",
        "",
        "  y := 1 + R_ACT_POSE;",
        "IF y > 0 THEN",
        "  y := y + 'a';",
        "ENDIF",
        "   POSE: q := 3;",
        "MAIN_JOINT: k := (1, 2);",
        "JOINTLIMITEND",
        "  VAR REAL: z;",
        "PROCEDURE twice;",
        "BEGIN",
        "  y := 'a';",
        "ENDPROC",
    ]
    printed: list[str] = []
    status = run_plain(Session("planar3"), io.StringIO("\n".join(script) + "\n"), printed.append)
    assert status == 1
    where = {
        "<stdin>:3:10: error: cannot add INTEGER and POSE": "+",
        "<stdin>:5:10: error: cannot add REAL and STRING": "+",
        "<stdin>:7:15: error: cannot assign to 'q': expected POSE, got INTEGER": "3",
        "<stdin>:8:18: error: MAIN_JOINT needs 3 values, got 2": "(",
        "<stdin>:13:8: error: cannot assign to 'y': expected REAL, got STRING": "'",
        # a run-time failure shows its line and caret too (at the statement's text)
        "<stdin>:9:1: error: run-time failure at t = 0.000 s: JOINTLIMIT is switched off "
        "but it is not on": "J",
    }
    shown = _diagnostics(printed)
    assert set(shown) == set(where), printed
    for header, token in where.items():
        line, column = (int(v) for v in header.split(":")[1:3])
        text, caret = shown[header]
        assert text == script[line - 1] and caret == column, (header, text, caret)
        assert text[column - 1] == token
    failed = [p for p in printed if "run-time failure" in p]
    assert len(failed) == 1 and failed[0].startswith("<stdin>:9:1: error: run-time failure"), failed


@needs_runtime
def test_terminal_entries_keep_positions_within_the_entry():
    from irlc.repl import Session

    s = Session("planar3")
    entry = s.enter("  x := 1 + R_ACT_POSE;")
    assert entry.failure == 1
    assert entry.lines[0].splitlines()[0] == "<input>:1:3: error: unknown name 'x'"
    assert s.enter("JOINTLIMITEND").lines[0].startswith("<input>:1:1: error: run-time failure")
    # a run-time failure's column: where its line's text begins (the code records lines)
    entry = s.enter("REAL: w := -1;\nIF TRUE THEN\n    WAIT w SEC;\nENDIF;")
    assert entry.lines[-1].startswith("<input>:3:5: error: run-time failure"), entry.lines


def test_an_unfinished_statement_is_not_shown_with_the_added_semicolon():
    """Regression (new-user walk): `MOVE LIN (1,2` was shown as `MOVE LIN (1,2;` with
    "unexpected ';'" — a ';' the session adds, the user never typed."""
    from irlc.repl import Session

    lines = Session("planar3").enter("MOVE LIN (1,2").lines[0].splitlines()
    assert lines[0] == "<input>:1:14: error: unexpected end of the entry; expected ')'"
    assert lines[1:] == ["  MOVE LIN (1,2", "  " + " " * 13 + "^"]
    typed = Session("planar3").enter("x := ;").lines[0]  # a ';' the user typed is named
    assert typed.startswith("<input>:1:6: error: unexpected ';'")


@needs_runtime
def test_a_move_that_goes_nowhere_says_so():
    from irlc.repl import Session

    s = Session("planar3")
    assert s.enter("MOVE LIN R_ACT_POSE").lines == ["→ already there (t = 0.000 s)"]
    assert s.enter("MOVE_INC PTP (0, 0, 0)").lines == ["→ already there (t = 0.000 s)"]
    assert s.enter("IF FALSE THEN MOVE LIN R_ACT_POSE; ENDIF").lines == []  # no motion ran
    moved = s.enter("MOVE_INC PTP (10, 0, 0)").lines
    assert moved[0].startswith("→ t = ") and "already" not in moved[0]
    t = float(moved[0].split()[3])
    assert t > 0
    assert s.enter("MOVE LIN R_ACT_POSE").lines == [f"→ already there (t = {t:.3f} s)"]


def test_the_input_ending_inside_a_block_names_the_block_and_its_line():
    # It compiled the half block with the session's ENDPROGRAM: "<session>: unexpected
    # 'ENDPROGRAM'", a line the user never typed and no line number.
    script = "VAR REAL: x;\nx := 1;\nIF x > 0 THEN\n  WHILE x < 3 DO\n    x := x + 1;\n"
    script += "  ENDWHILE;\n"
    proc = _session(script)
    assert proc.returncode == 1, proc.stderr
    assert proc.stdout.strip() == (
        "<stdin>:6:1: error: the input ends inside a block: IF on line 3 is not closed "
        "(expected ENDIF)"
    )
    assert "ENDPROGRAM" not in proc.stdout + proc.stderr


def test_unclosed_block_finds_the_innermost_open_block():
    from irlc.repl import unclosed_block

    assert unclosed_block("IF a THEN\n  WHILE b DO\n x := 'ENDWHILE';\n") == ("WHILE", 2)
    assert unclosed_block("IF a THEN\n  WHILE b DO\n  ENDWHILE;\n") == ("IF", 1)
    assert unclosed_block("IF a THEN x := 1; ENDIF;") is None


@pytest.mark.skipif(not _compiler_available(), reason="compiler/runtime not installed")
def test_the_session_survives_an_entry_that_escapes_the_interpreter(monkeypatch):
    # A failure escaping the interpreter ended the whole session with exit 4 (state lost).
    from irlc.repl import Session
    from irlc.robots import RobotFileError
    from irlc.runtime.interpreter import Interpreter

    session = Session("planar3")
    assert session.enter("VAR REAL: x;").failure == 0
    assert session.enter("x := 41;").failure == 0
    real_run = Interpreter.run
    for exc, status in ((ZeroDivisionError("bug"), 4), (RobotFileError("f.toml", "k", "bad"), 3)):

        def broken(self, *a, _exc=exc, **k):
            raise _exc

        monkeypatch.setattr(Interpreter, "run", broken)
        result = session.enter("x := x + 1;", 5)
        assert result.failure == status
        assert result.lines[0].startswith("<stdin>:5:1: error: ")
        monkeypatch.setattr(Interpreter, "run", real_run)
    assert session.enter("WRITELN(x + 1);").lines == ["42.0"]  # the state survived


@pytest.mark.skipif(not _compiler_available(), reason="compiler/runtime not installed")
def test_a_scripted_session_goes_on_after_a_failing_line():
    proc = _session("VAR REAL: x;\nx := 2;\nWAIT 1e308 SEC;\nWRITELN(x * 21);\n")
    assert "internal error" not in proc.stdout + proc.stderr
    assert proc.returncode in (2, 3), proc.stdout
    assert proc.stdout.strip().splitlines()[-1] == "42.0"


@needs_runtime
def test_failing_meta_commands_are_positioned_and_keep_the_session(tmp_path):
    # ':robot nosuch' re-created the session (declarations lost); ':trace DIR' said
    # "[Errno 21] Is a directory: '/.tmp.….tmp' -> '/tmp'"; neither had a position.
    from irlc.repl import Session

    s = Session("planar3", cwd=tmp_path)
    assert s.enter("VAR REAL: x;", 1).failure == 0
    assert s.enter("x := 41;", 2).failure == 0
    robot = s.enter(":robot nosuch", 3)
    assert robot.failure == 3 and robot.lines[0].startswith("<stdin>:3:1: error: unknown robot")
    trace = s.enter(f":trace {tmp_path}", 4)
    assert trace.failure == 3
    assert trace.lines == [
        f"<stdin>:4:1: error: {tmp_path} is a folder; :trace takes a file (FILE.csv)"
    ]
    unknown = s.enter(":nosuch", 5)
    assert unknown.failure == 1 and unknown.lines[0].startswith(
        "<stdin>:5:1: error: unknown command"
    )
    assert s.enter("WRITELN(x + 1);", 6).lines == ["42.0"]
    # ':plot FILE' said "[Errno 17] File exists: '/dev/null'"; a file it cannot write
    # gave the errno too
    (tmp_path / "a_file").write_text("")
    plot = s.enter(":plot a_file", 7)
    assert plot.failure == 3
    assert plot.lines == [
        f"<stdin>:7:1: error: {tmp_path / 'a_file'} is not a folder; :plot takes a folder (DIR)"
    ]
    nowhere = tmp_path / "a_file" / "t.csv"  # a file where a folder should be
    trace = s.enter(f":trace {nowhere}", 8)
    assert trace.failure == 3 and trace.lines[0].startswith(
        f"<stdin>:8:1: error: cannot use {nowhere}: "
    )
    assert "Errno" not in trace.lines[0]


@needs_runtime
def test_an_import_whose_errors_lie_in_the_data_list_is_positioned_in_the_entry(tmp_path):
    # the data list's own diagnostic (its file and line) was the entry's only error line
    from irlc.repl import Session

    (tmp_path / "cell.toml").write_text("[joints]\nhome = [0, 90, -90]\n")
    (tmp_path / "broken.toml").write_text("[poses]\np = [1, 2\n")
    s = Session("koch11", cwd=tmp_path)
    wrong = s.enter("  IMPORT DATALIST cell;", 7)
    assert wrong.failure == 1 and "cell.toml:2:1: error: key 'joints.home'" in wrong.lines[0]
    assert wrong.lines[-1] == "<stdin>:7:19: error: data list 'cell' has errors (above)"
    broken = s.enter("IMPORT DATALIST broken;", 8)
    assert broken.lines[-1] == "<stdin>:8:17: error: data list 'broken' has errors (above)"
    assert s.enter("WRITELN(1);", 9).lines == ["1"]


def test_a_long_session_spills_its_samples_and_traces_the_same(tmp_path, monkeypatch):
    """A session keeps at most ``SPILL_ROWS`` samples in memory (older ones go to a temporary
    file, as a streamed run's do): its ``:trace`` is the same bytes as with every sample in
    memory."""
    from irlc.repl import Session
    from irlc.runtime import run as run_mod

    moves = [f"MOVE PTP ({a}, {a / 2}, {-a / 3});" for a in (10, -20, 30, 0, 45, -45)]

    def trace(rows: int, name: str) -> tuple[bytes, int]:
        monkeypatch.setattr(run_mod, "SPILL_ROWS", rows)
        s = Session("planar3")
        for k, line in enumerate(moves, start=1):
            assert s.enter(line, k).failure == 0
        target = tmp_path / name
        assert s.enter(f":trace {target}", len(moves) + 1).failure == 0
        return target.read_bytes(), s.controller.recorder.spilled

    spilled_bytes, spilled = trace(16, "spilled.csv")
    whole_bytes, none = trace(10**6, "whole.csv")
    assert spilled > 100 and none == 0  # the small buffer did spill, the large one not
    assert spilled_bytes == whole_bytes and spilled_bytes.count(b"\n") > spilled


def test_each_entry_has_the_whole_cycle_budget():
    """The cycle budget bounds what one entry computes, not the session: a session may
    move for longer than the budget in all."""
    from irlc.repl import Session

    s = Session("planar3")
    s.controller.opts.max_cycles = 600
    for k, target in enumerate(("(10, 20, 30)", "(0, 20, 30)", "(10, 20, 30)"), start=1):
        entry = s.enter(f"MOVE PTP {target} WITH TIME := 5;", k)
        assert entry.failure == 0, entry.lines  # 500 cycles each, 1500 in the session
    entry = s.enter("MOVE PTP (0, 20, 30) WITH TIME := 7;", 4)
    assert entry.failure == 2
    assert "would take 700 IPO cycles and the run past its budget of 600" in " ".join(entry.lines)


@needs_runtime
def test_program_names_an_entry_that_failed_part_way():
    """Regression (probe): `:program` dropped a FOR that failed in its second pass without
    a word, though its first pass had moved the robot; the program did not reproduce it."""
    from irlc.repl import Session

    s = Session("planar3")
    assert (
        s.enter("MOVE LIN (1500, 600, 0, 0, 0, 0);\nMOVE LIN (9000, 0, 0, 0, 0, 0);").failure == 2
    )
    assert s.enter("MOVE LIN (1500, 900, 0, 0, 0, 0)").failure == 0
    program = s.meta(":program").lines
    left = [line for line in program if line.startswith("{ left out:")]
    assert len(left) == 1 and "failed at t = " in left[0] and left[0].endswith("}")
    assert program.index(left[0]) < program.index("MOVE LIN (1500, 900, 0, 0, 0, 0);")
    assert not any("9000" in line for line in program)


@needs_runtime
def test_options_lists_every_row_of_the_settings_table():
    """`:options` is generated from lang/settings.py: every system variable of the table
    with the session's value and unit (R_ACC_PTP and R_APPROX included), and every limit
    option of the table while it is on."""
    from irlc.lang.settings import LIMIT_OPTIONS, SETTINGS
    from irlc.repl import Session

    s = Session("planar3")
    for text in ("R_ACC_PTP := 30;", "R_APPROX := 5;", "R_IPO := 0.00002;"):
        assert s.enter(text).failure == 0, text
    text = "\n".join(s.enter(":options").lines)
    assert text.startswith("no modal options active")
    expected = {"acc_ptp": "30", "approx": "5", "ipo": "2e-05"}
    for row in SETTINGS:
        if row.system_variable:
            value = expected.get(row.field, f"{row.default:g}" if row.unit else row.default)
            unit = f" {row.unit}" if row.unit else ""
            assert f"{row.system_variable} {value}{unit}" in text, row.system_variable
    bounds = {0: ("(-90, -90, -90)", "(90, 90, 90)"), 1: ("(-10, -10, -10)", "(10, 10, 10)"),
              2: ("(-50, -50, -50)", "(50, 50, 50)")}  # fmt: skip
    for option in LIMIT_OPTIONS:
        lo, hi = bounds[option.derivative]
        assert s.enter(f"{option.word} {lo}, {hi};").failure == 0, option.word
    lines = s.enter(":options").lines
    for option in LIMIT_OPTIONS:
        lo, hi = bounds[option.derivative]
        assert f"{option.word} min {lo} max {hi}" in lines, option.word
    assert "no modal options active" not in lines
