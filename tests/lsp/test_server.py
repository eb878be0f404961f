"""``irlc lsp`` end to end: a real LSP client (pytest-lsp) starts the command and speaks the
protocol with it over stdio, with the capabilities VS Code and Neovim announce. Expected
positions and values are computed here from the test's own texts and files (the robot file
read with tomllib), not from the server's modules."""

from __future__ import annotations

import shutil
import tomllib
from pathlib import Path

import pytest

pytest_lsp = pytest.importorskip("pytest_lsp", reason="the test extra has pytest-lsp")
from lsprotocol import types  # noqa: E402

from tests.lsp.lsp_client import (  # noqa: E402
    ROOT,
    UNITS,
    at,
    change,
    close,
    complete,
    definition,
    diagnostics_of,
    hover,
    open_doc,
    span,
    uri,
)

pytestmark = [
    pytest.mark.asyncio(loop_scope="module"),
    # an answer the client's capabilities do not allow (a snippet, Markdown) fails the test
    pytest.mark.filterwarnings("error::pytest_lsp.LspSpecificationWarning"),
]

PROGRAM = """PROGRAM cell;
ROBOT r := planar3;
IMPORT DATALIST cell;
CONST side = 200.0;
TYPE RECORD POSE: where; INTEGER: count; ENDRECORD = station;
VAR POSE: p1, p2; INTEGER: n; station: st;
PROCEDURE corner(POSE: c; VAR INTEGER: count);
VAR REAL: tmp;
BEGIN
  tmp := side;
  MOVE LIN c;
  count := count + 1;
ENDPROC;
FUNCTION half(REAL: x): REAL;
BEGIN
  RETURN x / 2;
ENDFCT;
BEGIN
  R_SPEED := 250;
  p1 := start;
  p2 := POSE(1000, 1000, 0, 0, 0, 0);
  MOVE LIN p1 WITH SPEED := 100;
  corner(p2, n);
  again: n := n + 1;
  IF n < 3 THEN GOTO again ENDIF;
  OBSTACLE post;
  MOVE LIN p1;
  OBSTACLEEND post;
  st.where := p1;
ENDPROGRAM
"""
DATALIST = """# the cell
[poses]
start = [2000, 1000, 0, 0, 0, 0]

[joints]
home = [0, 90, -90]

[obstacles.post]
kind = "sphere"
center = [1500, 500, 0]
radius = 100
"""


@pytest.fixture
def cell(tmp_path) -> Path:
    (tmp_path / "cell.irl").write_text(PROGRAM, encoding="utf-8")
    (tmp_path / "cell.toml").write_text(DATALIST, encoding="utf-8")
    return tmp_path


# ---------------------------------------------------------------------------- diagnostics


async def test_a_correct_program_has_no_diagnostics(client, cell):
    assert await open_doc(client, cell / "cell.irl") == []
    close(client, cell / "cell.irl")


async def test_diagnostics_on_open_and_on_every_change_with_exact_ranges(client, cell):
    path = cell / "cell.irl"
    text = PROGRAM.replace("tmp := side;", "tmp := sied + 1;")
    (error,) = await open_doc(client, path, text)
    assert error.severity == types.DiagnosticSeverity.Error and error.source == "irlc"
    assert error.range == span(text, "sied")
    assert "unknown name 'sied'" in error.message and "did you mean 'side'" in error.message

    fixed = await change(client, path, PROGRAM, 2)
    assert fixed == []

    # a non-BMP character before the error: 2 UTF-16 code units, 4 UTF-8 ones
    broken = PROGRAM.replace("  R_SPEED := 250;", "  { 🤖 } R_SPEED := -5;")
    (error,) = await change(client, path, broken, 3)
    assert error.range.start == at(broken, "-5")
    extra = {"utf-8": 3, "utf-16": 1, "utf-32": 0}[UNITS["encoding"]]
    assert error.range.start.character == len("  { 🤖 } R_SPEED := ") + extra
    assert "the value must be in (0, 100000] mm/s" in error.message

    syntax = PROGRAM.replace("  MOVE LIN c;", "  MOVE LIN c")
    (error,) = await change(client, path, syntax, 4)
    assert error.range.start == at(syntax, "  MOVE LIN c", offset=12)  # after the c
    assert "expected ';'" in error.message
    close(client, path)


async def test_warnings_are_warnings(client, cell):
    path = cell / "cell.irl"
    text = PROGRAM.replace("  RETURN x / 2;\n", "  x := x / 2;\n")
    (warning,) = await open_doc(client, path, text)
    assert warning.severity == types.DiagnosticSeverity.Warning
    assert "may end without RETURN" in warning.message
    assert warning.range.start == at(text, "ENDFCT")
    close(client, path)


async def test_a_data_list_problem_is_on_the_import_line_and_in_the_open_toml(client, cell):
    bad = DATALIST.replace("start = [2000, 1000, 0, 0, 0, 0]", "start = [2000, 1000, 0, 0, 0]")
    (cell / "cell.toml").write_text(bad, encoding="utf-8")
    program = cell / "cell.irl"
    found = await open_doc(client, program)
    (on_import,) = [d for d in found if d.range.start.line == 2]
    assert on_import.range == span(PROGRAM, "cell", nth=1)  # IMPORT DATALIST cell;
    assert on_import.message.startswith("cell.toml:3: key 'poses.start'")
    assert "expected 6 numbers" in on_import.message

    toml = cell / "cell.toml"
    (in_toml,) = await open_doc(client, toml)
    assert in_toml.range.start == at(bad, "start")
    assert "expected 6 numbers" in in_toml.message

    # fixing the unsaved buffer clears both (the program reads the buffer, not the file)
    assert await change(client, toml, DATALIST, 2) == []
    assert await diagnostics_of(client, uri(program), 1) == []
    close(client, toml)
    close(client, program)


async def test_a_toml_no_open_program_imports_is_checked_on_its_own(client, tmp_path):
    toml = tmp_path / "alone.toml"
    text = '[poses]\np = [1, 2, 3, 4, 5, 6]\n[obstacles.w]\nkind = "box"\n'
    found = await open_doc(client, toml, text)
    assert {d.message for d in found} == {"key 'obstacles.w': a box needs 'center'",
                                          "key 'obstacles.w': a box needs 'size'"}  # fmt: skip
    assert all(d.range.start == at(text, "[obstacles.w]") for d in found)
    close(client, toml)
    for other in (ROOT / "robots" / "planar3.toml", ROOT / "pyproject.toml"):  # not data lists
        copy = tmp_path / other.name
        shutil.copy(other, copy)
        assert await open_doc(client, copy) == []
        close(client, copy)


# ---------------------------------------------------------------------------- completion


async def test_completion_offers_names_in_scope_with_kinds(client, cell):
    path = cell / "cell.irl"
    await open_doc(client, path)
    K = types.CompletionItemKind
    main = await complete(client, path, PROGRAM, at(PROGRAM, "  corner(p2, n);"))
    expected = {"p1": K.Variable, "st": K.Variable, "side": K.Constant, "start": K.Constant,
                "home": K.Constant, "post": K.Value, "station": K.Struct, "corner": K.Method,
                "half": K.Function}  # fmt: skip
    assert {name: main[name].kind for name in expected} == expected
    assert "tmp" not in main and "count" not in main  # the procedure's own names
    assert "cell.toml" in main["start"].detail
    assert main["R_SPEED"].kind == K.Variable and "mm/s" in main["R_SPEED"].detail
    assert main["ENDIF"].kind == K.Keyword and main["SIN"].kind == K.Function
    assert "MOVE LIN" in main and "SPECIFICATION" not in main  # unsupported clauses

    inside = await complete(client, path, PROGRAM, at(PROGRAM, "  count := count + 1;"))
    assert inside["tmp"].kind == K.Variable and inside["c"].kind == K.Variable
    assert inside["count"].sort_text < inside["p1"].sort_text  # its own names first
    close(client, path)


async def test_completion_of_with_options_settings_robots_and_fields(client, cell):
    path = cell / "cell.irl"
    await open_doc(client, path)
    line = at(PROGRAM, "SPEED := 100")
    options = await complete(client, path, PROGRAM, line)
    assert {"SPEED", "ACC", "SPEED_ORI", "SPEED_PTP", "ACC_PTP", "TIME", "APPROX",
            "JOINTLIMIT", "RECONFIGURATION"} <= set(options)  # fmt: skip
    assert "p1" not in options and "MOVE LIN" not in options
    assert "mm/s" in options["SPEED"].detail and "(0, 100000]" in options["SPEED"].detail

    robots = await complete(client, path, PROGRAM, at(PROGRAM, "planar3"))
    library = {p.stem for p in (ROOT / "robots").glob("*.toml")}
    assert set(robots) == library and robots["koch11"].kind == types.CompletionItemKind.Module

    obstacles = await complete(client, path, PROGRAM, at(PROGRAM, "post;"))
    assert set(obstacles) == {"post"} and obstacles["post"].kind == types.CompletionItemKind.Value
    datalists = await complete(client, path, PROGRAM, at(PROGRAM, "DATALIST cell", offset=9))
    assert {"cell", "koch11_ch6"} <= set(datalists)  # the program's folder, the library

    fields = await complete(client, path, PROGRAM, at(PROGRAM, "where := p1"))
    assert set(fields) == {"where", "count"}  # st. → the record's fields
    typed = PROGRAM.replace("  st.where := p1;", "  p1.")
    await change(client, path, typed, 2)
    pose = await complete(client, path, typed, at(typed, "  p1.", offset=5))
    assert set(pose) == {"x", "y", "z", "pos", "ori"}
    close(client, path)


async def test_completion_while_a_statement_is_half_typed(client, cell):
    path = cell / "cell.irl"
    typing = PROGRAM.replace("  corner(p2, n);", "  MOVE LIN p")
    (error,) = await open_doc(client, path, typing)  # the program does not parse
    assert error.severity == types.DiagnosticSeverity.Error
    items = await complete(client, path, typing, at(typing, "  MOVE LIN p", offset=12))
    assert {"p1", "p2", "start", "corner"} <= set(items)
    close(client, path)


# ---------------------------------------------------------------------------- hover


async def test_hover_shows_settings_types_values_and_the_robot(client, cell):
    path = cell / "cell.irl"
    await open_doc(client, path)
    speed = await hover(client, path, at(PROGRAM, "R_SPEED"))
    assert "path speed" in speed and "mm/s" in speed and "(0, 100000]" in speed
    assert "start value: 500" in speed
    with_speed = await hover(client, path, at(PROGRAM, "SPEED := 100"))
    assert "WITH SPEED" in with_speed and "mm/s" in with_speed
    assert "POSE" in await hover(client, path, at(PROGRAM, "p1 := start"))
    assert "station" in await hover(client, path, at(PROGRAM, "st.where"))
    entry = await hover(client, path, at(PROGRAM, "start;"))
    assert "(2000, 1000, 0, 0, 0, 0)" in entry and "poses.start" in entry
    assert "cell.toml" in entry
    assert "FUNCTION half(REAL: x): REAL" in await hover(client, path, at(PROGRAM, "half("))
    assert "sphere" in await hover(client, path, at(PROGRAM, "post;"))
    typed = PROGRAM.replace("  MOVE LIN p1;", "  MOVE PTP home;")
    await change(client, path, typed, 2)
    joints = await hover(client, path, at(typed, "home;"))
    assert "MAIN_JOINT" in joints and "a1 0, a2 90, a3 -90" in joints  # joint by joint
    await change(client, path, PROGRAM, 3)

    robot = await hover(client, path, at(PROGRAM, "planar3"))
    spec = tomllib.loads((ROOT / "robots" / "planar3.toml").read_text(encoding="utf-8"))
    for j, joint in enumerate(spec["joints"], start=1):
        lo, hi = joint["position"]
        row = next(r for r in robot.splitlines() if r.startswith(f"| a{j} |"))
        assert joint["name"] in row and "deg" in row
        assert f"{lo:g} … {hi:g}" in row or f"±{hi:g}" in row
        assert f"±{joint['speed']:g}" in row and f"±{joint['accel']:g}" in row
    close(client, path)


async def test_hover_gives_a_prismatic_joint_in_mm(client, tmp_path):
    path, text = tmp_path / "track.irl", "PROGRAM t;\nROBOT r := irb6_track;\nBEGIN\nENDPROGRAM\n"
    assert await open_doc(client, path, text) == []
    robot = await hover(client, path, at(text, "irb6_track"))
    spec = tomllib.loads((ROOT / "robots" / "irb6_track.toml").read_text(encoding="utf-8"))
    track = spec["joints"][0]
    assert track["kind"] == "prismatic" and spec["robot"]["units"]["length"] == "m"
    row = next(r for r in robot.splitlines() if r.startswith("| a1 |"))
    lo, hi = (1000 * v for v in track["position"])
    assert f"| {track['name']} | mm | {lo:g} … {hi:g} |" in row
    assert f"±{1000 * track['speed']:g}" in row and f"±{1000 * track['accel']:g}" in row
    close(client, path)


# ---------------------------------------------------------------------------- definition


async def test_go_to_definition(client, cell):
    path = cell / "cell.irl"
    await open_doc(client, path)
    here = uri(path)
    cases = {  # use → declaration
        ("p1 := start", 0): ("p1", 0),
        ("corner(p2", 0): ("corner", 0),
        ("side;", 0): ("side", 0),
        ("count + 1", 0): ("count", 1),  # the parameter, not the record's field
        ("again ENDIF", 0): ("again", 0),
        ("station: st", 0): ("station", 0),
    }
    for (use, nth), (name, decl_nth) in cases.items():
        got = await definition(client, path, at(PROGRAM, use, nth))
        assert got is not None, use
        assert got.uri == here and got.range == span(PROGRAM, name, decl_nth), use

    entry = await definition(client, path, at(PROGRAM, "start;"))
    assert entry.uri == uri(cell / "cell.toml")
    assert entry.range.start == at(DATALIST, "start =")
    obstacle = await definition(client, path, at(PROGRAM, "post;"))
    assert obstacle.uri == uri(cell / "cell.toml")
    assert obstacle.range.start == at(DATALIST, "[obstacles.post]")
    datalist = await definition(client, path, at(PROGRAM, "DATALIST cell", offset=9))
    assert datalist.uri == uri(cell / "cell.toml")
    robot = await definition(client, path, at(PROGRAM, "planar3"))
    assert Path(robot.uri).name == "planar3.toml"
    close(client, path)


# ---------------------------------------------------------------------------- symbols


async def test_document_symbols_and_no_formatting(client, cell):
    path = cell / "cell.irl"
    await open_doc(client, path)
    result = await client.text_document_document_symbol_async(
        types.DocumentSymbolParams(types.TextDocumentIdentifier(uri(path)))
    )
    S = types.SymbolKind
    top = {(s.name, s.kind) for s in result}
    assert top == {("r", S.Object), ("side", S.Constant), ("station", S.Struct),
                   ("p1", S.Variable), ("p2", S.Variable), ("n", S.Variable), ("st", S.Variable),
                   ("corner", S.Method), ("half", S.Function)}  # fmt: skip
    corner = next(s for s in result if s.name == "corner")
    assert [c.name for c in corner.children] == ["c", "count", "tmp"]
    assert corner.selection_range == span(PROGRAM, "corner")
    assert corner.range.end.line == at(PROGRAM, "ENDPROC").line
    capabilities = client.server_capabilities  # nothing rewrites the user's text
    assert not capabilities.document_formatting_provider
    assert not capabilities.document_range_formatting_provider
    close(client, path)
