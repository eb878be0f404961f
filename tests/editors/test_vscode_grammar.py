"""The VS Code TextMate grammar (``editors/vscode/syntaxes/irl.tmLanguage.json``) against
the compiler's own lexer.

The grammar is run by the tokenizer VS Code itself uses — vscode-textmate with the
Oniguruma regular expressions of vscode-oniguruma, through node
(``editors/vscode/test/tokenize.js``) — over every program of ``programs/``, the language
tests' valid programs and a generated text holding every keyword, system variable,
built-in function and lexical form. The lark lexer of ``lang/irl.lark`` is the independent
reference: per character, both must agree whether it is a comment, a string, a number, a
keyword (control, motion, declaration, operator word: ``keyword.*``; a type:
``storage.type.*``; TRUE/FALSE: ``constant.language.*``), a system variable, a built-in
function, a name or an operator — every character of every token the lexer finds has its
class's scope, and nothing the grammar scopes as a comment, string, number or keyword is
anything else to the lexer. Two words are keywords only where they stand (docs/language.md
§10): ``AT`` in a ROBOT clause and the option after ``COOPERATE a IN b WITH`` (``VERTICAL``);
the parsed program says where (:func:`contextual_keywords`).

Cells are shown as such: a robot's name where a cell names it (``MOVE name``, a group
move's ``AND name``, ``FOR name``, ``COOPERATE a IN b``) is scoped a robot, and the AND of a
group move differs from the logical AND (:func:`test_cell_words_are_scoped_as_cells_read`).

Needs node (skipped, saying so, without it) and the node packages of editors/vscode
(``npm ci`` there, which ``.ci/run`` does; the test runs it when they are missing).
"""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import pytest
from irlc.lang import ast
from irlc.lang.builtins import BUILTINS
from irlc.lang.grammar import keywords, lark_parser
from irlc.lang.parser import parse
from irlc.lang.settings import SYSTEM_VARIABLES

ROOT = Path(__file__).resolve().parents[2]
VSCODE = ROOT / "editors" / "vscode"
NODE = shutil.which("node")
pytestmark = pytest.mark.skipif(NODE is None, reason="node is not installed (the grammar's "
                                "tokenizer, vscode-textmate, runs on node)")  # fmt: skip

TYPES = {"INTEGER", "REAL", "BOOLEAN", "CHAR", "STRING", "POSITION", "ORIENTATION", "POSE",
         "SIGNAL", "MAIN_JOINT", "MAIN_JOINT_MIN", "MAIN_JOINT_MAX", "MAIN_JOINT_SPEED_MIN",
         "MAIN_JOINT_SPEED_MAX", "MAIN_JOINT_ACCEL_MIN", "MAIN_JOINT_ACCEL_MAX"}  # fmt: skip
CALLABLE = set(BUILTINS) | {"PULSE"}  # PULSE(OUT[n], t): the pulse statement
PREFIXES = {  # class → the scope prefixes that show it
    "comment": ("comment.",),
    "string": ("string.",),
    "number": ("constant.numeric.",),
    "keyword": ("keyword.",),
    "type": ("storage.type.",),
    "boolean": ("constant.language.",),
    "system variable": ("variable.language.",),
    "built-in": ("support.function.",),
    "name": ("variable.other.", "entity.name."),
    "operator": ("keyword.operator.", "punctuation."),
}
STRONG = ("comment", "string", "number", "keyword", "type", "boolean")  # checked both ways


def _lexer_class(tok, text_after: str) -> str:
    kind, word = tok.type, tok.value.upper()
    if kind in ("COMMENT", "STRING", "NUMBER"):
        return {"COMMENT": "comment", "STRING": "string", "NUMBER": "number"}[kind]
    if kind == "NAME":
        if word in SYSTEM_VARIABLES:
            return "system variable"
        if word in CALLABLE and text_after.lstrip().startswith("("):
            return "built-in"
        return "name"
    if word in keywords():
        return "type" if word in TYPES else "boolean" if word in ("TRUE", "FALSE") else "keyword"
    return "operator"


def contextual_keywords(text: str) -> set[tuple[int, int]]:
    """The (line, column) of the words that are keywords where they stand: ``AT`` between a
    ROBOT clause's robot and its placement, ``COOPERATE … WITH``'s option (a text that does
    not parse has none)."""
    program, _ = parse(text, "grammar_test.irl")
    if program is None:
        return set()
    found = set()
    for clause in program.robot:
        if clause.at is not None:
            end, start = clause.robot_span, clause.at.span
            found.add(((end.end_line, end.end_column), (start.line, start.column)))
    spots = set()
    for s in ast.statements_in_order(program.body):
        if isinstance(s, ast.ModalOn) and s.word_span is not None:
            spots.add((s.word_span.line, s.word_span.column))
    for tok in lark_parser().lex(text, dont_ignore=True):
        here = (tok.line, tok.column)
        if tok.type == "NAME" and tok.value.upper() == "AT":
            spots |= {here for after, before in found if after <= here < before}
    return spots


def lexer_classes(text: str) -> list[list[str | None]]:
    """Per line, per character: the class of the lark token covering it (None: none)."""
    lines = text.split("\n")
    classes: list[list[str | None]] = [[None] * len(line) for line in lines]
    contextual = contextual_keywords(text)
    for tok in lark_parser().lex(text, dont_ignore=True):
        if tok.type.startswith("__IGNORE"):
            continue
        end = tok.end_pos
        cls = _lexer_class(tok, text[end : end + 40])
        if (tok.line, tok.column) in contextual:
            cls = "keyword"
        line, column = tok.line - 1, tok.column - 1
        for char in tok.value:
            if char == "\n":
                line, column = line + 1, 0
                continue
            if char != "\r":
                classes[line][column] = cls
            column += 1
    return classes


@pytest.fixture(scope="module")
def tokenizer() -> Path:
    if not (VSCODE / "node_modules" / "vscode-textmate").is_dir():
        npm = shutil.which("npm")
        if npm is None:
            pytest.fail("npm is needed to install editors/vscode's test packages (npm ci)")
        done = subprocess.run([npm, "ci", "--no-audit", "--no-fund"], cwd=VSCODE,
                              capture_output=True, text=True, timeout=600)  # fmt: skip
        assert done.returncode == 0, f"npm ci in editors/vscode failed:\n{done.stderr}"
    return VSCODE / "test" / "tokenize.js"


def grammar_classes(tokenizer: Path, files: list[Path]) -> dict[str, list[list[list[str]]]]:
    """Per file, per line, per character (code point): the TextMate scopes."""
    done = subprocess.run([NODE, str(tokenizer), *map(str, files)], capture_output=True,
                          text=True, timeout=300, check=False)  # fmt: skip
    assert done.returncode == 0, done.stderr
    out = {}
    for name, lines in json.loads(done.stdout).items():
        text_lines = Path(name).read_text(encoding="utf-8").split("\n")
        per_file = []
        for tokens, line in zip(lines, text_lines, strict=True):
            utf16 = _utf16_to_index(line.removesuffix("\r"))
            scopes: list[list[str]] = [[] for _ in line.removesuffix("\r")]
            for start, end, names in tokens:
                for i in range(utf16[start], utf16[end]):
                    scopes[i] = names
            per_file.append(scopes)
        out[name] = per_file
    return out


def _utf16_to_index(line: str) -> dict[int, int]:
    """UTF-16 offset → code-point index (JavaScript counts a non-BMP character twice)."""
    mapping, units = {}, 0
    for i, char in enumerate(line):
        mapping[units] = i
        units += 2 if ord(char) > 0xFFFF else 1
    mapping[units] = len(line)
    return mapping


def _shows(scopes: list[str], cls: str) -> bool:
    return any(s.startswith(PREFIXES[cls]) for s in scopes)


def disagreements(text: str, scopes: list[list[list[str]]]) -> list[str]:
    out = []
    lines = zip(lexer_classes(text), scopes, strict=True)
    for n, (classes, line_scopes) in enumerate(lines, start=1):
        for col, (cls, names) in enumerate(zip(classes, line_scopes, strict=True), start=1):
            if cls is not None and not _shows(names, cls):
                out.append(f"{n}:{col}: the lexer's {cls} is scoped {names[1:] or 'nothing'}")
            for strong in STRONG:
                if (
                    cls != strong
                    and _shows(names, strong)
                    and not (
                        strong == "keyword" and cls == "operator"  # keyword.operator.*
                    )
                ):
                    out.append(f"{n}:{col}: scoped {strong} ({names[-1]}), the lexer says {cls}")
    return out


def sample_text() -> str:
    """Every keyword (three spellings), system variable, built-in call and lexical form."""
    words = sorted(keywords())
    lines = [" ".join(words), " ".join(w.lower() for w in words),
             " ".join(w.capitalize() for w in words)]  # fmt: skip
    lines.append(" ".join(f"{v} := {v.lower()};" for v in SYSTEM_VARIABLES))
    lines.append(" ".join(f"{f}(x) {f.lower()} (y)" for f in sorted(CALLABLE)))
    lines += [
        "x := 12 + 180. + .5 + 0.25 + 1e-3 + 2.5E+2 - -3; a[1..3] := b.c[2];",
        "s := 'it''s'; t := \"say \"\"hi\"\"\"; c := 'q'; u := '{ not a comment }';",
        "x := 1 { a brace comment } + 2 (* a Pascal comment *) ; // a line comment",
        "{ a brace comment",
        "  over lines, with 'quotes' and // slashes and (* stars *) }",
        "(* a Pascal comment",
        "   over lines { braces } *) y := p : q <> r <= s >= t < u > v = w;",
        "lin_speed := move_x + endif1 + _r_speed + r_speedy + sin + sinx(1);  { near-keywords }",
    ]
    return "\n".join(lines) + "\n"


def _programs() -> list[Path]:
    found = sorted((ROOT / "programs").glob("*.irl"))
    found += sorted((ROOT / "tests" / "lang" / "golden").glob("*.irl"))
    found += sorted((ROOT / "tests" / "lang_acceptance" / "valid").rglob("*.irl"))
    return found


def test_every_program_is_scoped_as_the_lexer_reads_it(tokenizer):
    programs = _programs()
    assert len(programs) >= 20
    scoped = grammar_classes(tokenizer, programs)
    problems = []
    for path in programs:
        text = path.read_text(encoding="utf-8")
        problems += [f"{path.relative_to(ROOT)}:{p}" for p in
                     disagreements(text, scoped[str(path)])]  # fmt: skip
    assert problems == [], "\n".join(problems[:40])


def test_every_keyword_setting_builtin_and_lexical_form(tokenizer, tmp_path):
    sample = tmp_path / "sample.irl"
    sample.write_text(sample_text(), encoding="utf-8")
    scoped = grammar_classes(tokenizer, [sample])[str(sample)]
    problems = disagreements(sample.read_text(encoding="utf-8"), scoped)
    assert problems == [], "\n".join(problems[:40])


def test_a_wrong_grammar_is_caught(tokenizer, tmp_path):
    """The comparison can fail: a grammar that forgets a keyword disagrees with the lexer."""
    grammar = json.loads((VSCODE / "syntaxes" / "irl.tmLanguage.json").read_text("utf-8"))
    motion = grammar["repository"]["keywords"]["patterns"][1]
    motion["match"] = motion["match"].replace("|PATH", "")
    broken = tmp_path / "vscode"
    shutil.copytree(VSCODE, broken, ignore=shutil.ignore_patterns("node_modules"))
    (broken / "node_modules").symlink_to(VSCODE / "node_modules")
    (broken / "syntaxes" / "irl.tmLanguage.json").write_text(json.dumps(grammar), "utf-8")
    program = ROOT / "programs" / "combined.irl"
    text = program.read_text(encoding="utf-8")
    scoped = grammar_classes(broken / "test" / "tokenize.js", [program])[str(program)]
    if "PATH" in text.upper():
        assert any("the lexer's keyword" in p for p in disagreements(text, scoped))
    sample = tmp_path / "sample.irl"
    sample.write_text(sample_text(), encoding="utf-8")
    scoped = grammar_classes(broken / "test" / "tokenize.js", [sample])[str(sample)]
    assert any("the lexer's keyword" in p for p in disagreements(sample_text(), scoped))


def test_the_extension_manifest_and_language_configuration(tmp_path):
    """The manifest names files that exist; the comment markers VS Code inserts (toggle
    comment) are comments to the lexer; the client script is valid JavaScript."""
    manifest = json.loads((VSCODE / "package.json").read_text(encoding="utf-8"))
    (language,) = manifest["contributes"]["languages"]
    (grammar,) = manifest["contributes"]["grammars"]
    assert language["extensions"] == [".irl"] and grammar["language"] == language["id"]
    for rel in (language["configuration"], grammar["path"], manifest["main"]):
        assert (VSCODE / rel).is_file(), rel
    config = json.loads((VSCODE / language["configuration"]).read_text(encoding="utf-8"))
    line, (open_, close) = config["comments"]["lineComment"], config["comments"]["blockComment"]
    for text in (f"{line} MOVE LIN p;\n", f"{open_} MOVE LIN p; {close}"):
        assert [t.type for t in lark_parser().lex(text, dont_ignore=True)
                if not t.type.startswith("__IGNORE")] == ["COMMENT"]  # fmt: skip
    pairs = {(p["open"], p["close"].strip()) for p in config["autoClosingPairs"]}
    assert {("(*", "*)"), ("{", "}")} <= pairs  # the other comment form, and braces
    done = subprocess.run([NODE, "--check", str(VSCODE / manifest["main"])],
                          capture_output=True, text=True, timeout=60)  # fmt: skip
    assert done.returncode == 0, done.stderr


CELL = """PROGRAM cell;
ROBOT holder := as6;
ROBOT welder := as6 AT (0, -2200, 0, 180, 0, 0);
VAR BOOLEAN: ok; INTEGER: i;
BEGIN
  R_CLEARANCE := 50;
  MOVE holder PTP h AND welder LIN w;
  ok := ok AND ok;
  JOINTLIMIT lo, hi FOR holder;
  COOPERATE welder IN holder WITH VERTICAL;
  COOPERATEEND;
  FOR i := 1 TO 2 DO WAIT FOR ok; ENDFOR;
ENDPROGRAM
"""


def test_cell_words_are_scoped_as_cells_read(tokenizer, tmp_path):
    """The words of a cell (docs/language.md §10) by their role: AT and VERTICAL as keywords
    where they stand, a group move's AND apart from the logical one, a FOR suffix apart
    from a loop, the robots' names where a robot is named."""
    path = tmp_path / "cell.irl"
    path.write_text(CELL, encoding="utf-8")
    scoped = grammar_classes(tokenizer, [path])[str(path)]
    lines = CELL.split("\n")

    def scope(line_start: str, word: str, nth: int = 0) -> str:
        row = next(i for i, line in enumerate(lines) if line.startswith(line_start))
        column = -1
        for _ in range(nth + 1):
            column = lines[row].index(word, column + 1)
        names = {tuple(scoped[row][c]) for c in range(column, column + len(word))}
        assert len(names) == 1, (line_start, word, names)  # one token
        return names.pop()[-1]

    assert scope("ROBOT welder", "ROBOT") == "keyword.other.declaration.irl"
    assert scope("ROBOT welder", "welder") == "entity.name.robot.irl"
    assert scope("ROBOT welder", "AT") == "keyword.other.placement.irl"
    assert scope("  R_CLEARANCE", "R_CLEARANCE") == "variable.language.irl"
    assert scope("  MOVE", "holder") == "variable.other.robot.irl"
    assert scope("  MOVE", "AND") == "keyword.other.motion.group.irl"
    assert scope("  MOVE", "welder") == "variable.other.robot.irl"
    assert scope("  ok := ok AND", "AND") == "keyword.operator.word.irl"  # the logical AND
    assert scope("  JOINTLIMIT", "FOR") == "keyword.other.redundancy.for.irl"
    assert scope("  JOINTLIMIT", "holder") == "variable.other.robot.irl"
    assert scope("  COOPERATE ", "COOPERATE") == "keyword.other.redundancy.irl"
    assert scope("  COOPERATE ", "welder") == "variable.other.robot.irl"
    assert scope("  COOPERATE ", "holder") == "variable.other.robot.irl"
    assert scope("  COOPERATE ", "VERTICAL") == "keyword.other.redundancy.option.irl"
    assert scope("  COOPERATEEND", "COOPERATEEND") == "keyword.other.redundancy.irl"
    assert scope("  FOR i", "FOR") == "keyword.control.irl"  # a loop
    assert scope("  FOR i", "FOR", 1) == "keyword.control.irl"  # WAIT FOR
    assert scope("  FOR i", "ok") == "variable.other.irl"
    assert disagreements(CELL, scoped) == []
    assert contextual_keywords(CELL) == {(3, 21), (10, 35)}  # AT, VERTICAL (1-based)
