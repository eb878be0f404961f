"""``irlc lsp`` on a cell of several robots (docs/language.md §10), end to end over stdio
with a real LSP client (pytest-lsp), as test_server.py: hover, completion and go to
definition on the robots' names wherever a program writes them (the ROBOT clause, MOVE
name, a group move's AND part, FOR name, COOPERATE a IN b, name.R_…, FK(name, …)), joint
values shown against the robot they are used with, and the compiler's cell diagnostics
with their ranges. Expected positions come from the test's own text; joint counts and
ranges from the robot files read with tomllib."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

pytest_lsp = pytest.importorskip("pytest_lsp", reason="the test extra has pytest-lsp")
from lsprotocol import types  # noqa: E402

from tests.lsp.lsp_client import (  # noqa: E402
    ROOT,
    at,
    change,
    close,
    complete,
    definition,
    hover,
    open_doc,
    span,
    uri,
)

pytestmark = [
    pytest.mark.asyncio(loop_scope="module"),
    pytest.mark.filterwarnings("error::pytest_lsp.LspSpecificationWarning"),
]

CELL = """PROGRAM weld_cell;
ROBOT holder := as6;
ROBOT welder := as6 AT (0, -2200, 0, 180, 0, 0);
ROBOT arm := panda AT (1500, 0, 0, 90, 0, 0);
CONST
  MAIN_JOINT: h_start = (90, 45, 0, 45, 90, 0);
  MAIN_JOINT: w_far = (90, 45, 0, 95, 90, 0);
  MAIN_JOINT: a_home = (0, -45, 0, -135, 0, 90, 45);
  MAIN_JOINT_MIN: h_min = (0, -90, -90, -90, 60, -90);
  MAIN_JOINT_MAX: h_max = (330, 90, 90, 90, 100, 90);
VAR
  POSE: p;
BEGIN
  R_CLEARANCE := 50;
  MOVE holder PTP h_start AND welder PTP h_start;
  MOVE arm PTP a_home;
  holder.R_TOOL := (0, 0, 150, 0, 0, 0);
  p := FK(welder, h_start) : welder.R_ACT_POSE;
  JOINTLIMIT h_min, h_max FOR holder;
  COOPERATE welder IN holder WITH VERTICAL;
    MOVE welder LIN p;
  COOPERATEEND;
  JOINTLIMITEND FOR holder;
  MOVE welder PTP w_far;
ENDPROGRAM
"""
# (needle, nth occurrence, offset to the robot's name) → the robot named there
USES = {
    ("holder := as6", 0, 0): "holder",  # the ROBOT clause
    ("welder := as6", 0, 0): "welder",
    ("MOVE holder", 0, 5): "holder",
    ("AND welder", 0, 4): "welder",  # a group move's part
    ("MOVE arm", 0, 5): "arm",
    ("holder.R_TOOL", 0, 0): "holder",
    ("FK(welder", 0, 3): "welder",
    ("welder.R_ACT_POSE", 0, 0): "welder",
    ("FOR holder", 0, 4): "holder",  # JOINTLIMIT … FOR
    ("COOPERATE welder", 0, 10): "welder",
    ("IN holder", 0, 3): "holder",
    ("MOVE welder LIN", 0, 5): "welder",
    ("FOR holder", 1, 4): "holder",  # JOINTLIMITEND FOR
}
CLAUSE = {"holder": "holder := as6", "welder": "welder := as6", "arm": "arm := panda"}


def robot_file(name: str) -> dict:
    return tomllib.loads((ROOT / "robots" / f"{name}.toml").read_text(encoding="utf-8"))


@pytest.fixture
def cell(tmp_path) -> Path:
    path = tmp_path / "weld_cell.irl"
    path.write_text(CELL, encoding="utf-8")
    return path


def name_at(needle: str, nth: int, offset: int, name: str) -> types.Range:
    start = at(CELL, needle, nth, offset)
    return types.Range(start, types.Position(start.line, start.character + len(name)))


def after_last(text: str, typed: str) -> types.Position:
    """The cursor right after the last ``typed`` in ``text`` (the line being typed)."""
    return at(text, typed, text.count(typed) - 1, offset=len(typed))


async def hover_result(client, path: Path, position: types.Position) -> types.Hover:
    result = await client.text_document_hover_async(
        types.HoverParams(types.TextDocumentIdentifier(uri(path)), position)
    )
    assert result is not None
    return result


async def test_hover_on_a_robot_name_shows_the_robot_wherever_it_is_written(client, cell):
    assert await open_doc(client, cell) == []
    as6 = robot_file("as6")
    for (needle, nth, offset), name in USES.items():
        result = await hover_result(client, cell, at(CELL, needle, nth, offset + 1))
        text = result.contents.value
        assert result.range == name_at(needle, nth, offset, name), needle
        assert text.startswith(f"**{name}** — robot "), needle
        line = at(CELL, CLAUSE[name]).line + 1
        assert f"(ROBOT clause on line {line})" in text, needle
        if name != "arm":
            assert f"- robot: `as6`, {len(as6['joints'])} joints" in text, needle
            rows = [r for r in text.splitlines() if r.startswith("| a")]
            assert [r.split(" | ")[1] for r in rows] == [j["name"] for j in as6["joints"]]
    welder = await hover(client, cell, at(CELL, "MOVE welder LIN", offset=6))
    assert "placement: AT (0, -2200, 0 mm; 180, 0, 0 deg ZYX) in the cell frame" in welder
    assert "robot 2 of 3 of the cell" in welder
    holder = await hover(client, cell, at(CELL, "IN holder", offset=4))
    assert "placement: at the cell frame (no AT)" in holder
    arm = await hover(client, cell, at(CELL, "MOVE arm", offset=6))
    assert "- robot: `panda`, 7 joints" in arm and "AT (1500, 0, 0 mm; 90, 0, 0 deg ZYX)" in arm
    close(client, cell)


async def test_hover_on_joint_values_names_the_robot_they_are_used_with(client, cell):
    await open_doc(client, cell)
    j4 = robot_file("as6")["joints"][3]
    lo, hi = j4["position"]
    far = await hover(client, cell, at(CELL, "w_far;", offset=1))
    assert "used with robot welder (as6, 6 joints): a1 90 deg, a2 45 deg, a3 0 deg, " in far
    assert f"a4 95 deg is outside its range ±{hi:g} (as6 joint {j4['name']})" in far
    assert lo == -hi and not lo <= 95 <= hi  # the test's value is outside, by the file
    # one constant in a group move: each part's robot
    first = await hover(client, cell, at(CELL, "h_start AND", offset=1))
    second = await hover(client, cell, at(CELL, "h_start;", offset=1))
    assert "used with robot holder" in first and "used with robot welder" in second
    assert "within as6's joint ranges" in first
    fk = await hover(client, cell, at(CELL, "h_start) :", offset=1))
    assert "used with robot welder" in fk
    limits = await hover(client, cell, at(CELL, "h_min, h_max FOR", offset=1))
    assert "MAIN_JOINT_MIN" in limits and "used with robot holder" in limits
    panda = await hover(client, cell, at(CELL, "a_home;", offset=1))
    assert "used with robot arm (panda, 7 joints): a1 0 deg, a2 -45 deg" in panda
    # where it is declared, no robot is in sight: the robots it fits (6 of 6, 6, 7 joints)
    declared = await hover(client, cell, at(CELL, "h_start =", offset=1))
    assert "6 values: fits robot holder (as6), welder (as6)" in declared
    assert "used with" not in declared
    close(client, cell)


async def test_hover_on_robot_variables_vertical_and_clearance(client, cell):
    await open_doc(client, cell)
    actual = await hover_result(client, cell, at(CELL, "R_ACT_POSE", offset=2))
    assert actual.range == span(CELL, "R_ACT_POSE")
    assert actual.contents.value.startswith("**welder.R_ACT_POSE**: POSE — robot welder's own")
    assert "read-only" in actual.contents.value
    tool = await hover(client, cell, at(CELL, "R_TOOL", offset=2))
    assert tool.startswith("**holder.R_TOOL**: POSE") and "read and written" in tool
    vertical = await hover_result(client, cell, at(CELL, "VERTICAL", offset=3))
    assert vertical.range == span(CELL, "VERTICAL")
    assert "tool z axis stays vertical" in vertical.contents.value
    clearance = await hover(client, cell, at(CELL, "R_CLEARANCE"))
    assert "robots' links" in clearance and "mm" in clearance and "[0, 100000]" in clearance
    close(client, cell)


async def test_go_to_definition_of_a_robot_name_is_its_robot_clause(client, cell):
    await open_doc(client, cell)
    for (needle, nth, offset), name in USES.items():
        got = await definition(client, cell, at(CELL, needle, nth, offset + 1))
        assert got is not None, needle
        assert got.uri == uri(cell) and got.range == span(CELL, CLAUSE[name].split()[0]), needle
    library = await definition(client, cell, at(CELL, "panda", offset=1))
    assert Path(library.uri).name == "panda.toml"  # the library name: the robot file
    close(client, cell)


async def test_completion_offers_the_cells_robots_where_a_robot_is_named(client, cell):
    await open_doc(client, cell)
    K = types.CompletionItemKind
    everyone = {"holder", "welder", "arm"}
    cases = {  # text before the cursor, on a line of its own → the robots offered
        "  MOVE ": everyone,
        "  MOVE_INC ": everyone,
        "  MOVE holder PTP h_start AND ": {"welder", "arm"},  # each robot once in a group
        "  MOVE holder PTP h_start AND welder PTP h_start AND ": {"arm"},
        "  JOINTLIMIT h_min, h_max FOR ": everyone,
        "  CYCLICEND FOR ": everyone,
        "  COOPERATE ": everyone,
        "  COOPERATE welder IN ": {"holder", "arm"},
    }
    version = 2
    for typed, robots in cases.items():
        text = CELL.replace("  MOVE welder PTP w_far;", typed)
        await change(client, cell, text, version)
        version += 1
        items = await complete(client, cell, text, after_last(text, typed))
        assert set(items) == robots, typed
        assert all(items[r].kind == K.Module for r in robots), typed
        details = {
            "holder": "robot as6 (6 joints) at the cell frame (no AT)",
            "welder": "robot as6 (6 joints) AT (0, -2200, 0 mm; 180, 0, 0 deg ZYX)",
            "arm": "robot panda (7 joints) AT (1500, 0, 0 mm; 90, 0, 0 deg ZYX)",
        }
        assert all(items[r].detail.startswith(details[r]) for r in robots), typed
    text = CELL.replace("  MOVE welder PTP w_far;", "  COOPERATE welder IN holder WITH ")
    await change(client, cell, text, version)
    items = await complete(client, cell, text, after_last(text, "holder WITH "))
    assert set(items) == {"VERTICAL"}
    text = CELL.replace("  MOVE welder PTP w_far;", "  p := holder.")
    await change(client, cell, text, version + 1)
    items = await complete(client, cell, text, after_last(text, "holder."))
    assert set(items) == {"R_TOOL", "R_BASE", "R_ACT_POSE", "R_ACT_JOINT"}
    text = CELL.replace("  MOVE welder PTP w_far;", "  FOR ")  # a loop, not a suffix
    await change(client, cell, text, version + 2)
    items = await complete(client, cell, text, after_last(text, "  FOR "))
    assert {"p", "MOVE LIN", "R_SPEED"} <= set(items)
    close(client, cell)


async def test_completion_after_move_with_one_robot(client, tmp_path):
    path = tmp_path / "one.irl"
    text = "PROGRAM one;\nROBOT r := planar3;\nBEGIN\n  MOVE \nENDPROGRAM\n"
    await open_doc(client, path, text)
    items = await complete(client, path, text, at(text, "  MOVE ", offset=7))
    assert set(items) == {"PTP", "LIN", "LIN PATH", "CIRCLE", "r"}
    assert items["PTP"].sort_text < items["r"].sort_text  # one robot: the name is optional
    close(client, path)


async def test_cell_diagnostics_come_positioned_from_the_compiler(client, cell):
    no_robot = CELL.replace("  MOVE arm PTP a_home;", "  MOVE PTP a_home;")
    (error,) = await open_doc(client, cell, no_robot)
    assert error.severity == types.DiagnosticSeverity.Error
    assert error.range == span(no_robot, "MOVE", 1)
    assert error.message == (
        "MOVE PTP in a cell names its robot (holder, welder, arm)\nhint: write MOVE holder PTP …"
    )
    unknown = CELL.replace("  MOVE arm PTP a_home;", "  MOVE ram PTP a_home;")
    (error,) = await change(client, cell, unknown, 2)
    assert error.range == span(unknown, "ram")
    assert error.message.startswith("unknown robot 'ram'")
    assert "robots of this program: holder, welder, arm" in error.message
    twice = CELL.replace("ROBOT arm := panda", "ROBOT Welder := panda")
    errors = await change(client, cell, twice, 3)
    clash = [e for e in errors if "already defined" in e.message]
    assert clash and all(e.range == span(twice, "Welder") for e in clash)
    assert clash[0].message.startswith("'Welder' is already defined as 'welder' (line 3)")
    count = CELL.replace("  MOVE arm PTP a_home;", "  MOVE arm PTP h_start;")
    (error,) = await change(client, cell, count, 4)
    start = at(count, "arm PTP h_start", offset=8)
    assert error.range == types.Range(start, types.Position(start.line, start.character + 7))
    assert "MAIN_JOINT for robot arm needs 7 values, got 6" in error.message
    assert await change(client, cell, CELL, 5) == []
    close(client, cell)


async def test_the_outline_lists_the_robots(client, cell):
    await open_doc(client, cell)
    result = await client.text_document_document_symbol_async(
        types.DocumentSymbolParams(types.TextDocumentIdentifier(uri(cell)))
    )
    robots = [(s.name, s.detail, s.selection_range) for s in result
              if s.kind == types.SymbolKind.Object]  # fmt: skip
    assert robots == [
        ("holder", "ROBOT as6", span(CELL, "holder")),
        ("welder", "ROBOT as6 AT (0, -2200, 0, 180, 0, 0)", span(CELL, "welder")),
        ("arm", "ROBOT panda AT (1500, 0, 0, 90, 0, 0)", span(CELL, "arm")),
    ]
    close(client, cell)


@pytest.mark.parametrize("name", ["two_robots", "cooperating"])
async def test_the_example_cells_have_no_diagnostics_and_answer_on_every_robot_name(client, name):
    path = ROOT / "programs" / f"{name}.irl"
    text = path.read_text(encoding="utf-8")
    assert await open_doc(client, path) == []
    clauses = [line for line in text.splitlines() if line.startswith("ROBOT ")]
    for line in clauses:
        robot = line.split()[1]
        start = at(text, f"ROBOT {robot}", offset=6)
        target = types.Range(start, types.Position(start.line, start.character + len(robot)))
        for nth in range(text.count(f"MOVE {robot} ")):
            use = at(text, f"MOVE {robot} ", nth, offset=5)
            got = await definition(client, path, use)
            assert got.uri == uri(path) and got.range == target, (robot, nth)
            assert (await hover(client, path, use)).startswith(f"**{robot}** — robot ")
    close(client, path)
