"""Targeted checks of decisions the golden files do not show on their own."""

from __future__ import annotations

from pathlib import Path

import pytest
from irlc.lang import SimpleRobot, compile_source
from irlc.lang.parser import keywords, parse

from .conftest import compile_text


def test_repl_mode_skips_pairing_checks() -> None:
    src = "PROGRAM t;\nROBOT r := six;\nBEGIN\n  CYCLICSTART;\n  FREEZEEND;\nENDPROGRAM\n"
    assert not compile_text(src).ok
    result = compile_text(src, repl=True)
    assert result.ok, [d.header() for d in result.diagnostics]
    ops = [(i.op, i.args) for i in result.code.code]
    assert ("OPTON", ("CYCLIC",)) in ops and ("OPTOFF", ("FREEZE",)) in ops


def test_repl_mode_keeps_other_checks() -> None:
    src = "PROGRAM t;\nROBOT r := six;\nBEGIN\n  OBSTACLE ghost;\n  FREEZESTART 9;\nENDPROGRAM\n"
    msgs = [d.message for d in compile_text(src, repl=True).errors]
    assert any("unknown obstacle" in m for m in msgs)
    assert any("joint 9 does not exist" in m for m in msgs)


def test_robot_override_without_clause() -> None:
    result = compile_text("PROGRAM t;\nBEGIN\nENDPROGRAM\n", robot_override="planar3")
    assert result.ok
    assert (result.code.robot, result.code.robot_var, result.code.joint_kinds) == (
        "planar3",
        "r",
        "RRR",
    )


def test_robot_override_wins_with_warning() -> None:
    result = compile_text(
        "PROGRAM t;\nROBOT arm := six;\nBEGIN\nENDPROGRAM\n", robot_override="planar3"
    )
    assert result.ok and result.code.robot == "planar3" and result.code.robot_var == "arm"
    assert [d.severity for d in result.diagnostics] == ["warning"]


def test_resolver_lookup_errors_become_diagnostics_and_bugs_propagate() -> None:
    src = "PROGRAM t;\nROBOT r := x;\nBEGIN\nENDPROGRAM\n"

    def missing(name: str):
        raise LookupError("robot file is corrupt")

    result = compile_source(src, "t.irl", resolve_robot=missing)
    assert not result.ok and "robot file is corrupt" in result.errors[0].message

    def broken(name: str):  # a bug in a resolver must not masquerade as a diagnostic
        raise RuntimeError("bug")

    with pytest.raises(RuntimeError, match="bug"):
        compile_source(src, "t.irl", resolve_robot=broken)


def test_names_are_case_insensitive_and_echo_declared_spelling() -> None:
    src = (
        "PROGRAM t;\nROBOT r := six;\nVAR POSE: Poz_1;\nBEGIN\n  POZ_1 := poz_1 + 1;\nENDPROGRAM\n"
    )
    result = compile_text(src)
    assert "cannot add POSE and INTEGER" in result.errors[0].message
    src = "PROGRAM t;\nROBOT r := six;\nCONST Limit = 3;\nBEGIN\n  LIMIT := 4;\nENDPROGRAM\n"
    assert "'Limit'" in compile_text(src).errors[0].message


def test_main_joint_record_names_the_joints() -> None:
    src = (
        "PROGRAM t;\nROBOT r := planar3;\n"
        "TYPE RECORD REAL: hip, knee, ankle; ENDRECORD = MAIN_JOINT;\n"
        "VAR MAIN_JOINT: k; MAIN_JOINT_MAX: m; REAL: x;\nBEGIN\n  x := k.KNEE + m.ankle;\n"
        "  k.Hip := 1;\nENDPROGRAM\n"
    )
    result = compile_text(src)
    assert result.ok
    assert result.code.joint_names == ("hip", "knee", "ankle")
    fields = [i.args[0] for i in result.code.code if i.op in ("GETF", "SETF")]
    assert fields == ["knee", "ankle", "hip"]  # canonical, declared spelling


def test_default_joint_names() -> None:
    result = compile_text("PROGRAM t;\nROBOT r := koch11;\nBEGIN\nENDPROGRAM\n")
    assert result.code.joint_names == tuple(f"a{i}" for i in range(1, 12))
    assert result.code.joint_kinds == "RRRRRRRRRPR"


def test_datalist_values_are_embedded(tmp_path: Path) -> None:
    (tmp_path / "cell.toml").write_text(
        '[poses]\np = [1, 2, 3, 4, 5, 6]\n[obstacles.b]\nkind = "sphere"\ncenter = [1, 2, 3]\n'
        "radius = 4\n[inputs]\n7 = [[0.5, true]]\n"
    )
    src = "PROGRAM t;\nROBOT r := six;\nIMPORT DATALIST cell;\nBEGIN\n  MOVE LIN p;\nENDPROGRAM\n"
    code = compile_text(src, str(tmp_path / "t.irl")).code
    assert code.datalists == [("cell", "cell.toml")]
    assert code.consts[0].type == "POSE" and code.consts[0].data == (1.0, 2.0, 3.0, 4.0, 5.0, 6.0)
    assert code.obstacle("B").get("radius") == (4.0,)
    assert code.inputs == {7: [(0.5, True)]}


def test_library_datalist_is_found() -> None:
    robot = SimpleRobot("koch11", ("revolute",) * 9 + ("prismatic", "revolute"))
    src = (
        "PROGRAM t;\nROBOT r := koch11;\nIMPORT DATALIST koch11_ch6;\nBEGIN\n"
        "  JOINTLIMIT jmin_base, jmax_base;\n  JOINTLIMITEND;\nENDPROGRAM\n"
    )
    result = compile_source(src, "/nonexistent/t.irl", resolve_robot=lambda n: robot)
    assert result.ok, [d.header() for d in result.diagnostics]
    assert result.code.datalists == [("koch11_ch6", "irlc.robots:datalists/koch11_ch6.toml")]


def test_semicolon_before_end_keywords_is_optional() -> None:
    src = (
        "PROGRAM t;\nROBOT r := six;\nVAR INTEGER: i;\nBEGIN\n"
        "  IF TRUE THEN i := 1 ELSE i := 2 ENDIF;\n"
        "  WHILE i < 3 DO i := i + 1 ENDWHILE\nENDPROGRAM\n"
    )
    assert compile_text(src).ok


def test_number_forms() -> None:
    src = (
        "PROGRAM t;\nROBOT r := six;\nVAR REAL: x;\nBEGIN\n"
        "  x := 12 + 180. + .5 + 0.25 + 1e-3 + 2.5E+2;\nENDPROGRAM\n"
    )
    result = compile_text(src)
    value = result.code.consts[0]
    assert (
        value.type == "REAL" and abs(value.data[0] - (12 + 180 + 0.5 + 0.25 + 0.001 + 250)) < 1e-12
    )


def test_keywords_are_reserved_everywhere() -> None:
    for word in ("CYCLICSTART", "endif", "Move", "sec"):
        src = f"PROGRAM t;\nROBOT r := six;\nVAR REAL: {word};\nBEGIN\nENDPROGRAM\n"
        result = compile_text(src)
        assert f"'{word}' is a reserved word" in result.errors[0].message
    assert {"JOINTLIMIT", "CYCLICEND", "FREEZESTART", "OBSTACLEEND", "MOVE_INC"} <= keywords()
    assert (
        "SPEED" not in keywords() and "TIME" not in keywords()
    )  # WITH option names are not reserved


def test_ast_spans() -> None:
    program, diags = parse("PROGRAM t;\nBEGIN\n  x := 1 + y\nENDPROGRAM\n", "t.irl")
    assert not diags
    assign = program.body[0]
    assert (assign.span.line, assign.span.column) == (3, 3)
    assert (assign.value.span.line, assign.value.span.column) == (3, 10)  # the operator


def test_unknown_obstacle_hint_names_a_bounded_list(tmp_path: Path) -> None:
    """The hint lists at most ten known obstacles, each name cut to a bounded length: a data
    list with many obstacles or a 3,000-character name is never echoed whole."""
    long_name = "a" * 3000  # sorted first: shown, cut short
    names = [long_name, *(f"box{i:02d}" for i in range(11))]
    sphere = 'kind = "sphere"\ncenter = [1, 2, 3]\nradius = 4\n'
    (tmp_path / "cell.toml").write_text("".join(f"[obstacles.{n}]\n{sphere}" for n in names))
    src = "PROGRAM t;\nROBOT r := six;\nIMPORT DATALIST cell;\nBEGIN\n  OBSTACLE wal;\nENDPROGRAM\n"
    (error,) = compile_text(src, str(tmp_path / "t.irl")).errors
    assert error.message == "unknown obstacle 'wal'"
    hint = error.hint or ""
    shown_long = f"{'a' * 32}… (3000 characters)"
    assert hint.startswith(f"known obstacles: {shown_long}, box00, box01, ")
    assert hint.endswith(", box08, and 2 more") and len(hint) < 250
