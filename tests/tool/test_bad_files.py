"""Bad expectation files in ``irlc test`` and the one atomic writer (mode, content)."""

from __future__ import annotations

import errno
import os
import stat
import time

import pytest
from irlc.cli import main
from irlc.files import atomic_write_bytes, atomic_write_text, read_user_text
from irlc.golden import ExpectationError, load_expectation, run_case

PROGRAM = "PROGRAM p;\nROBOT r := planar3;\nBEGIN\nENDPROGRAM\n"


def _case(tmp_path, expected: bytes):
    prog = tmp_path / "p.irl"
    prog.write_text(PROGRAM, encoding="utf-8")
    (tmp_path / "p.expected.json").write_bytes(expected)
    return prog


def _no_run(program, options):
    raise AssertionError("a bad expectation must be reported before running")


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (b"\x89PNG\r\n\x1a\n\x00", "p.expected.json: not a UTF-8 text file (byte 0x89 on line 1)"),
        (b'"just a string"', "p.expected.json: expected a JSON object, got a string"),
        (b"[1, 2]", "p.expected.json: expected a JSON object, got an array"),
        (b'{"status": "ok",\n "x": }', "p.expected.json:2:7: not valid JSON"),
        (b'{"tolerances": {"x": "abc"}}', "key 'tolerances.x': expected a number ≥ 0, got \"abc\""),
        (b'{"tolerances": {"x": -1}}', "key 'tolerances.x': expected a number ≥ 0, got -1"),
        (b'{"tolerances": [1]}', "key 'tolerances': expected an object, got an array"),
        # a typo in a tolerance's key was ignored, the default quantum applied (probe)
        (b'{"tolerances": {"duraton_s": 0.5}}', "key 'tolerances.duraton_s': no number of the"),
        (b'{"tolerances": {"output": 1}}', "key 'tolerances.output': no number of the"),
        (b'{"tolerances": {"max_path_error_mm_below": 1}}', "a bound (it passes while"),
        (b'{"tolerances": {"samples.x": 1}}', "'samples' is one number: it has no parts"),
        (b'{"tolerances": {"joints.a1.mx": 1}}', "joints.NAME has the fields min, max, end"),
        (
            b'{"joints": {"a1": {}}, "tolerances": {"joints.a9": 1}}',
            "no joint 'a9' in the expectation (joints: a1)",
        ),
        (b'{"options": "fast"}', "key 'options': expected an object, got a string"),
        (b'{"options": {"speed": 2}}', "key 'options.speed': unknown run option"),
        (b"[" * 100_000 + b"]" * 100_000, "p.expected.json: not valid JSON: nested too deeply"),
        (b'{"x": 1' + b"0" * 5000 + b"}", "not valid JSON: an integer of 5001 digits"),
        (b'{"duration_s": NaN}', "not valid JSON: a number that is not finite (not-a-number)"),
        (b'{"tolerances": {"x": 1e400}}', "not valid JSON: the number 1e400 is beyond"),
        (b'{"tolerances": {"x": "' + b"v" * 5000 + b'"}}', "expected a number ≥ 0, got a string"),
        # options of the wrong type ran and failed with a bare "TypeError: 'int' object is
        # not iterable", naming neither the file nor the key
        (b'{"options": {"datalist_path": 5}}', "key 'options.datalist_path': expected a folder"),
        (b'{"options": {"seed_config": "xyz"}}', "key 'options.seed_config': expected a list of"),
        (b'{"options": {"robot": [1]}}', "key 'options.robot': expected a robot name or file"),
        (b'{"options": {"allow_any_path": 1}}', "key 'options.allow_any_path': expected true"),
        (b'{"options": {"ipo": -1}}', "key 'options.ipo': the value must be in [1e-05, 1] s"),
        (b'{"options": {"max_cycles": 2.5}}', "key 'options.max_cycles': must be a positive int"),
        (b'{"options": {"drives": "fast"}}', "key 'options.drives': expected one of ideal,"),
        # an integer a float cannot hold: an OverflowError (exit 4) before
        (b'{"options": {"max_time": 1' + b"0" * 400 + b"}}", "0000… (401 characters) is beyond"),
        (b'{"tolerances": {"x": -1' + b"0" * 400 + b"}}", "not valid JSON: the number -1000"),
        (
            b'{"options": {"seed_config": "' + b"x" * 5000 + b'"}}',
            "key 'options.seed_config': expected a list of finite numbers (deg | mm), got a str",
        ),
    ],
)
def test_bad_expectation_is_an_error_case_naming_file_and_key(tmp_path, content, message):
    result = run_case(_case(tmp_path, content), runner=_no_run)
    assert result.status == "error" and message in result.message


@pytest.mark.parametrize("kind", ["fifo", "folder"])
@pytest.mark.parametrize("suffix", ["json", "txt"])
def test_an_expectation_that_is_not_a_file_is_an_error_case(tmp_path, kind, suffix):
    # a FIFO or a folder named NAME.expected.json was reported as MISSING ("no
    # p.expected.json; run with --update"), and the .txt one was ignored
    prog = _case(tmp_path, b"{}")
    target = tmp_path / f"p.expected.{suffix}"
    target.unlink(missing_ok=True)
    os.mkfifo(target) if kind == "fifo" else target.mkdir()
    result = run_case(prog, runner=lambda program, options: {"output": []})
    assert result.status == "error" and result.message == f"{target}: not a regular file"


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes")
def test_a_program_name_that_is_no_file_is_an_error_case_not_skipped(tmp_path, capsys):
    """Regression: ``irlc test`` passed over a NAME.irl that was a broken link, a folder or
    a FIFO without a word (and "0 passed" for a folder of only such names)."""
    (tmp_path / "broken.irl").symlink_to(tmp_path / "nowhere.irl")
    (tmp_path / "dir.irl").mkdir()
    os.mkfifo(tmp_path / "pipe.irl")  # never opened: a read would block
    assert main(["test", str(tmp_path)]) == 1
    out = " ".join(capsys.readouterr().out.split())
    assert "broken.irl: a broken link" in out and "dir.irl: a folder, not a program" in out
    assert "pipe.irl: not a regular file" in out and "0 passed, 3 failed" in out


def test_valid_user_keys_load(tmp_path):
    path = tmp_path / "e.json"
    path.write_text('{"options": {"ipo": 0.01}, "tolerances": {"duration_s": 0.5}}')
    assert load_expectation(path)["tolerances"] == {"duration_s": 0.5}


def test_cli_reports_a_bad_expectation_without_traceback(tmp_path, capsys):
    _case(tmp_path, b'{"tolerances": {"x": "abc"}}')
    assert main(["test", str(tmp_path)]) == 1
    out = capsys.readouterr()
    text = " ".join((out.out + out.err).split())
    assert "ERROR p.irl" in text and "tolerances.x" in text and "Traceback" not in text


def test_read_user_text_raises_the_callers_error(tmp_path):
    bad = tmp_path / "b.txt"
    bad.write_bytes(b"ok\nok\n\xc3(")
    with pytest.raises(
        ExpectationError, match=r"b\.txt: not a UTF-8 text file \(byte 0xc3 on line 3\)"
    ):
        read_user_text(bad, lambda f, r: ExpectationError(f"{f}: {r}"))
    with pytest.raises(ExpectationError, match=r"missing\.txt: cannot read the file"):
        read_user_text(tmp_path / "missing.txt", lambda f, r: ExpectationError(f"{f}: {r}"))


@pytest.fixture
def umask_022():
    old = os.umask(0o022)
    yield
    os.umask(old)


def _mode(path) -> int:
    return stat.S_IMODE(path.stat().st_mode)


def test_atomic_writer_mode_follows_umask_and_leaves_no_temp(tmp_path, umask_022):
    target = tmp_path / "sub" / "out.json"
    atomic_write_text(target, "é\n")
    assert target.read_bytes() == "é\n".encode() and _mode(target) == 0o644
    os.umask(0o077)
    atomic_write_text(target, "second\n")  # a replaced file keeps its permissions
    assert target.read_text() == "second\n" and _mode(target) == 0o644
    other = atomic_write_text(target.parent / "new.json", "{}\n")  # a new one: the umask's
    assert _mode(other) == 0o600
    assert sorted(p.name for p in target.parent.iterdir()) == ["new.json", "out.json"]


def test_every_writer_gives_0644(tmp_path, umask_022, capsys):
    from irlc.report import write_report, write_trace

    write_report({"status": "ok"}, tmp_path / "r.json")
    write_trace(["t_s", "line"], [[0.0, 1.0]], tmp_path / "t.csv")
    prog = tmp_path / "p.irl"
    prog.write_text(PROGRAM, encoding="utf-8")
    assert main(["compile", str(prog), "-o", str(tmp_path / "p.ird")]) == 0
    assert main(["run", str(prog), "-q", "--export-trajectory", str(tmp_path / "traj.json"),
                 "--animate", str(tmp_path / "a.html")]) == 0  # fmt: skip
    (tmp_path / "p.expected.json").unlink(missing_ok=True)
    assert main(["test", str(tmp_path), "--update"]) == 0
    capsys.readouterr()
    for name in ("r.json", "t.csv", "p.ird", "traj.json", "a.html", "p.expected.json"):
        assert _mode(tmp_path / name) == 0o644, name


# Writing onto what is not a regular file: as root, `irlc run P --report /dev/null` used to
# rename its temporary file over /dev/null (and /dev/full, /dev/stdout), replacing the
# device with a regular file. The tests go through links in tmp_path, so that a regression
# replaces the link, never a device.
@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes")
def test_a_named_pipe_is_written_in_place_and_one_nobody_reads_fails_at_once(tmp_path):
    import threading

    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    got: list[bytes] = []
    reader = threading.Thread(target=lambda: got.append(fifo.read_bytes()), daemon=True)
    reader.start()
    for _ in range(200):  # wait until the reader has the pipe open
        try:
            atomic_write_text(fifo, "through the pipe\n")
            break
        except OSError as exc:
            assert exc.errno == errno.ENXIO and exc.filename == str(fifo)
            time.sleep(0.01)
    reader.join(5)
    assert got == [b"through the pipe\n"] and stat.S_ISFIFO(fifo.lstat().st_mode)
    with pytest.raises(OSError) as info:  # no reader now: an error, not a hang
        atomic_write_text(fifo, "nobody reads\n")
    assert info.value.errno == errno.ENXIO and info.value.filename == str(fifo)


@pytest.mark.skipif(not os.path.exists("/dev/null"), reason="no /dev/null")
def test_a_link_to_a_device_is_written_through_and_stays(tmp_path):
    link = tmp_path / "null"
    link.symlink_to("/dev/null")
    atomic_write_text(link, "discarded\n")
    assert link.is_symlink() and stat.S_ISCHR(os.stat("/dev/null").st_mode)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["null"]  # no temporary file left


def test_a_link_to_a_file_replaces_the_file_and_keeps_the_link(tmp_path):
    real = tmp_path / "data" / "report.json"
    real.parent.mkdir()
    real.write_text("old\n")
    link = tmp_path / "latest.json"
    link.symlink_to(real)
    atomic_write_text(link, "new\n")
    assert link.is_symlink() and real.read_text() == "new\n"
    dangling = tmp_path / "next.json"
    dangling.symlink_to(tmp_path / "data" / "next_real.json")
    atomic_write_text(dangling, "created\n")
    assert dangling.is_symlink() and (tmp_path / "data" / "next_real.json").read_text() == (
        "created\n"
    )


def test_a_folder_or_an_unwritable_place_is_an_error_naming_the_target(tmp_path, capsys):
    with pytest.raises(IsADirectoryError) as info:
        atomic_write_text(tmp_path, "x")
    assert info.value.filename == str(tmp_path)
    prog = tmp_path / "p.irl"
    prog.write_text(PROGRAM, encoding="utf-8")
    blocker = tmp_path / "file"
    blocker.write_text("")
    target = blocker / "r.json"  # a file where a folder should be
    assert main(["run", str(prog), "-q", "--report", str(target)]) == 3
    err = capsys.readouterr().err
    assert f"cannot write {target}:" in " ".join(err.split()) and ".tmp" not in err


def _compare(tmp_path, capsys, name: str, content: bytes | None) -> str:
    prog = tmp_path / "p.irl"
    prog.write_text(PROGRAM, encoding="utf-8")
    other = tmp_path / name
    if content is None:
        os.mkfifo(other)  # read without end if it were read
    else:
        other.write_bytes(content)
    assert main(["run", str(prog), "-q", "--compare", str(other)]) == 3
    err = capsys.readouterr().err
    assert "internal error" not in err and "nan" not in err.lower()
    return " ".join(err.split())


@pytest.mark.parametrize(
    ("name", "content", "message"),
    [
        ("r.json", b'{"status": "ok", "duration_s": -Infinity}', "not finite (-infinity)"),
        ("r.json", b'{"status": "ok", "duration_s": 1e999}', "the number 1e999 is beyond"),
        ("r.json", b'{"status": "ok", "duration_s": "x"}', "key 'duration_s': expected a number"),
        ("r.json", b'{"status": "ok", "joints": "abc"}', "key 'joints': expected a list"),
        ("r.json", b'{"status": "ok", "joints": [{"name": [1]}]}', "key 'joints[0]': expected"),
        ("r.json", b'{"status": "ok", "joints": [{"name": "a1", "min": {}}]}', "'joints[0].min'"),
        ("r.json", b"[" * 100_000, "not valid JSON: nested too deeply"),
        ("t.csv", b"t_s,a1_deg\n0,nan\n", "t.csv:2: a value that is not a finite number"),
        ("t.csv", b"t_s,a1_deg\n0,1e400\n", "t.csv:2: a value that is not a finite number"),
        # finite but beyond any run: `--plot` failed on them (LinAlgError, exit 4)
        ("t.csv", b"t_s,a1_deg\n0,0\n0.01,1.7e308\n", "t.csv:3: a value beyond ±1e+12"),
        ("r.json", b'{"status": "ok", "duration_s": 1e300}', "'duration_s': a number beyond"),
        ("fifo.csv", None, "fifo.csv: not a regular file"),
    ],
)
def test_compare_with_a_bad_report_or_trace_is_a_usage_error(tmp_path, capsys, name, content,
                                                              message):  # fmt: skip
    assert message in _compare(tmp_path, capsys, name, content)


def test_update_over_a_folder_of_the_expectation_name_is_an_error_case(tmp_path, capsys):
    # os.replace onto the folder: IsADirectoryError escaped as exit 4, naming the temp file
    prog = tmp_path / "p.irl"
    prog.write_text(PROGRAM, encoding="utf-8")
    (tmp_path / "p.expected.json").mkdir()
    assert main(["test", str(tmp_path), "--update"]) == 1
    text = "".join(capsys.readouterr().out.split())  # however the console wrapped the path
    assert "".join(f"ERROR p.irl {tmp_path}/p.expected.json: not a regular file".split()) in text
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.expected.json", "p.irl"]


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes")
def test_a_pipe_whose_reader_stops_drops_the_rest_of_the_file(tmp_path):
    # `irlc run P --trace /dev/stdout | head`: BrokenPipeError was 'cannot write', exit 3
    import threading

    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    fd = os.open(fifo, os.O_RDWR)  # the reader, open before the writer comes
    got: list[bytes] = []

    def read_ten_and_stop() -> None:
        data = b""
        while len(data) < 10:
            data += os.read(fd, 10 - len(data))
        got.append(data)
        os.close(fd)

    reader = threading.Thread(target=read_ten_and_stop, daemon=True)
    reader.start()
    atomic_write_bytes(fifo, b"x" * (64 * 65536))
    reader.join(10)
    assert got == [b"x" * 10] and stat.S_ISFIFO(fifo.lstat().st_mode)


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes")
@pytest.mark.parametrize("command", [["check"], ["compile"], ["run", "-q"], ["disasm"]])
def test_a_program_that_is_a_pipe_or_a_folder_is_refused_not_read(tmp_path, capsys, command):
    # the commands checked is_file() and called a FIFO "no such file"; read, it blocks
    # without a writer (compile_file read it with read_bytes)
    fifo, folder = tmp_path / "p.irl", tmp_path / "d.irl"
    os.mkfifo(fifo)
    folder.mkdir()
    code = main([command[0], str(fifo), *command[1:]])
    err = "".join(capsys.readouterr().err.split())  # however the console wrapped the path
    assert code == 3 and "".join(f"{fifo}: not a regular file".split()) in err, err
    code = main([command[0], str(folder), *command[1:]])
    out = capsys.readouterr()
    assert code == 3 and "Traceback" not in out.err
    assert "a folder, not a file" in out.err or "is a directory" in out.err, out


def test_a_replaced_file_keeps_its_permissions(tmp_path):
    # a report kept private (chmod 600) came back 644; an expectation 400 became 644
    private = tmp_path / "r.json"
    private.write_text("{}")
    private.chmod(0o600)
    atomic_write_text(private, '{"new": 1}\n')
    assert stat.S_IMODE(private.stat().st_mode) == 0o600
    assert private.read_text() == '{"new": 1}\n'
    fresh = atomic_write_text(tmp_path / "n.json", "{}\n")
    umask = os.umask(0)
    os.umask(umask)
    assert stat.S_IMODE(fresh.stat().st_mode) == 0o666 & ~umask
