"""``WITH PLATFORM := q`` and ``R_PLATFORM`` in the front end (issue 27): checks with their
positions, the IRDATA code (a REAL or an ARRAY operand, ``PLATFORM`` clause word), data
lists' ``[platform]`` entries as constants and their round trip through the reader.

The robots are fakes with a :class:`~irlc.lang.platform.PlatformSignature` (the checker
needs nothing else); one test uses the library's mobile8 (its limits from its file).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import pytest
from irlc.lang import SimpleRobot, compile_source, read_code, write_code
from irlc.lang.platform import PlatformSignature, platform_of

from .conftest import ROBOTS


@dataclass(frozen=True)
class FakePlatform:
    coordinates: tuple[str, ...]
    low: float = -5000.0
    high: float = 5000.0

    @property
    def joints(self) -> tuple[int, ...]:
        return tuple(range(len(self.coordinates)))

    def problem(self, target_mm: Sequence[float], labels=None) -> str | None:
        bad = [v for v in target_mm if not self.low <= v <= self.high]
        if not bad:
            return None
        return f"the platform target {bad[0]:g} mm is outside the platform's limits"


@dataclass(frozen=True)
class PlatformRobot(SimpleRobot):
    platform: FakePlatform | None = field(default=None)


FAKES = {
    **ROBOTS,
    "mobile": PlatformRobot("mobile", ("P", "P") + ("R",) * 6, (), FakePlatform(("x", "y"))),
    "track": PlatformRobot("track", ("P",) + ("R",) * 6, (), FakePlatform(("y",), 0, 2500)),
}


def _resolve(name: str):
    try:
        return FAKES[name.lower()]
    except KeyError:
        raise LookupError(f"unknown robot {name}") from None


def _compile(robot: str, stmts: str, decls: str = "", **kw):
    text = f"PROGRAM p;\nROBOT r := {robot};\n{decls}BEGIN\n{stmts}\nENDPROGRAM\n"
    kw.setdefault("resolve_robot", _resolve)
    return compile_source(text, "p.irl", **kw)


def _errors(result) -> list[tuple[int, int, str]]:
    return [(d.span.line, d.span.column, d.message) for d in result.errors]


P = "(1000, 0, 800, 0, 90, 0)"


def test_the_fake_is_a_platform_signature():
    assert isinstance(FAKES["mobile"].platform, PlatformSignature)
    assert platform_of(FAKES["mobile"]) is FAKES["mobile"].platform
    assert platform_of(FAKES["six"]) is None


def test_platform_targets_compile_to_one_operand_and_the_platform_word():
    decls = "VAR ARRAY [1..2] OF REAL: goal;\n"
    stmts = (
        f"  goal[1] := 10; goal[2] := 20;\n"
        f"  MOVE LIN {P} WITH PLATFORM := (300, 2 * 100);\n"
        f"  MOVE LIN {P} WITH PLATFORM := goal WITH SPEED := 100;\n"
        f"  MOVE CIRCLE {P}, {P} WITH PLATFORM := goal;\n"
        f"  MOVE_INC LIN (0, 0, 10, 0, 0, 0) WITH PLATFORM := goal;\n"
        f"  MOVE PTP {P} WITH PLATFORM := goal;\n"
        f"  MOVE LIN PATH ({P}, {P}) WITH PLATFORM := goal;\n"
        "  R_PLATFORM := 'HOLD';\n  R_PLATFORM := 'free';\n"
    )
    result = _compile("mobile", stmts, decls)
    assert result.ok, [d.header() for d in result.diagnostics]
    text = write_code(result.code)
    assert "MAKE ARRAY[1..2]OFREAL 2\n" in text.replace(" ; ", "\n")
    assert "MOVE LIN 1 PLATFORM\n" in text and "MOVE LIN 1 PLATFORM SPEED" in text
    assert "MOVE CIRCLE 2 PLATFORM" in text and "MOVE LININC 1 PLATFORM" in text
    assert "MOVE PTP 1 PLATFORM" in text and "MOVE LINPATH 2 PLATFORM" in text
    assert "POPSYS R_PLATFORM" in text
    assert write_code(read_code(text)) == text  # the reader takes the clause word
    one = write_code(_compile("track", f"  MOVE LIN {P} WITH PLATFORM := 1500;").code)
    assert "REAL 1500.0" in one and "MOVE LIN 1 PLATFORM" in one  # a number: a REAL


@pytest.mark.parametrize(
    ("robot", "clause", "column", "message"),
    [
        ("six", "WITH PLATFORM := (1, 2)", 42, "WITH PLATFORM: robot six has no platform"),
        ("mobile", "WITH PLATFORM := (1, 2, 3)", 54,
         "WITH PLATFORM: the platform has 2 coordinates (x, y mm), got 3 values"),
        ("mobile", "WITH PLATFORM := 5", 54, "WITH PLATFORM: the platform has 2 coordinates "
         "(x, y mm): expected ARRAY [1..2] OF REAL, got INTEGER"),
        ("track", "WITH PLATFORM := (1, 2)", 54, "WITH PLATFORM: the platform has 1 coordinate "
         "(y mm), got 2 values"),
        ("track", "WITH PLATFORM := 'far'", 54,
         "WITH PLATFORM: the platform has 1 coordinate (y mm): expected REAL, got STRING"),
        ("mobile", "WITH PLATFORM := (6000, 0)", 54,
         "WITH PLATFORM: the platform target 6000 mm is outside the platform's limits"),
        ("track", "WITH PLATFORM := -1", 54,
         "WITH PLATFORM: the platform target -1 mm is outside the platform's limits"),
        ("mobile", "WITH PLATFORM := (1, 2) WITH APPROX := 5", 42,
         "a motion WITH PLATFORM ends with an exact stop: it takes no WITH APPROX"),
    ],
)  # fmt: skip
def test_bad_platform_clauses_are_errors_at_their_place(robot, clause, column, message):
    result = _compile(robot, f"  MOVE LIN {P} {clause};\n  MOVE LIN {P};")
    assert _errors(result) == [(4, column, message)]


def test_a_joint_target_or_increment_fixes_the_platform():
    result = _compile(
        "mobile",
        "  MOVE PTP (0, 0, 0, 0, 0, 0, 0, 0) WITH PLATFORM := (1, 2);\n"
        "  MOVE_INC PTP (0, 0, 0, 0, 0, 0, 0, 1) WITH PLATFORM := (1, 2);",
    )
    assert [(line, m) for line, _, m in _errors(result)] == [
        (4, "WITH PLATFORM needs a POSE target"),
        (5, "WITH PLATFORM needs a POSE target"),
    ]


def test_r_platform_words_and_hold_without_a_platform():
    assert _errors(_compile("mobile", "  R_PLATFORM := 'STAY';")) == [
        (4, 17, "R_PLATFORM := 'STAY': the value must be one of 'FREE', 'HOLD'")
    ]
    hold = _compile("six", "  R_PLATFORM := 'Hold';")
    assert hold.ok and [(d.span.line, d.span.column, d.message) for d in hold.warnings] == [
        (4, 17, "R_PLATFORM := 'HOLD': robot six has no platform to hold")
    ]
    assert _compile("six", "  R_PLATFORM := 'FREE';").ok


def test_data_list_platform_entries_are_constants_of_their_shape(tmp_path):
    (tmp_path / "cell.toml").write_text(
        "[platform]\ngoal = [300, 200]\nend = 1500\nfar = [7000, 0]\nbad = [1, 2, 3, 4]\n"
        "word = 'x'\n"
    )
    program = tmp_path / "p.irl"
    program.write_text(
        "PROGRAM p;\nROBOT r := mobile;\nIMPORT DATALIST cell;\nBEGIN\n"
        f"  MOVE LIN {P} WITH PLATFORM := goal;\n"  # 5: fine
        f"  MOVE LIN {P} WITH PLATFORM := far;\n"  # 6: beyond the limits (a constant)
        f"  MOVE LIN {P} WITH PLATFORM := end;\n"  # 7: one coordinate for two
        "ENDPROGRAM\n"
    )
    result = compile_source(program.read_text(), str(program), resolve_robot=_resolve)
    messages = [(d.span.line if d.span else None, d.message) for d in result.errors]
    far = "WITH PLATFORM: the platform target 7000 mm is outside the platform's limits"
    assert (6, far) in messages
    assert any(line == 7 and "expected ARRAY [1..2] OF REAL, got REAL" in m for line, m in messages)
    bad = [m for line, m in messages if "platform.bad" in m or "platform.word" in m]
    assert len(bad) == 2 and "expected 1 or 2 or 3 numbers" in bad[0]
    # the good entry alone: an ARRAY constant in the code, read back the same
    program.write_text(program.read_text().replace("far;", "goal;").replace("end;", "goal;"))
    (tmp_path / "cell.toml").write_text("[platform]\ngoal = [300, 200]\n")
    result = compile_source(program.read_text(), str(program), resolve_robot=_resolve)
    assert result.ok, [d.header() for d in result.diagnostics]
    text = write_code(result.code)
    assert "CONST 1 ARRAY[1..2]OFREAL 300.0 200.0" in text
    assert write_code(read_code(text)) == text
    wrong = text.replace("ARRAY[1..2]OFREAL 300.0 200.0", "ARRAY[1..2]OFREAL 300.0")
    with pytest.raises(Exception, match=r"ARRAY\[1..2\]OFREAL: expected 2 numbers, got 1"):
        read_code(wrong)


def test_the_library_mobile8_checks_a_constant_against_its_file_limits():
    from irlc.robots import load_robot

    result = _compile("mobile8", f"  MOVE LIN {P} WITH PLATFORM := (100, -5001);",
                      resolve_robot=load_robot)  # fmt: skip
    assert _errors(result) == [
        (4, 54, "WITH PLATFORM: the platform target (x 100, y -5001) mm is outside the "
         "platform's limits: it needs joint a2 (Y) at -5001 mm, beyond its limit (min -5000 mm)")
    ]  # fmt: skip
