"""Every citation of a document points at a file and a section that exist.

A citation is a ``NAME.md`` (or ``docs/NAME.md``) in a doc (``docs/*.md``, ``README.md``)
or in the source of the four packages and the tests (docstrings, comments, messages),
optionally followed by a section: numbered ``§N`` / ``§N.M`` or named ``§ Name``. The file
must exist (in ``docs/``, at the repository root, or beside the citing doc); a numbered
section must be a numbered heading of it (``## 6. Motion``, ``### 6.1 Approximate
positioning``), a named one the start of a heading (``§ REPL`` for ``## REPL (`irlc
repl`)``). A bare ``§N`` inside a doc with numbered headings cites that doc itself.
Relative Markdown links must resolve, a repository path (``runtime/plan/profiles.py``,
``programs/square.irl``) must exist unless it is a placeholder (``robots/NAME.toml``), and
docs cite nothing outside the repository (the specification lives elsewhere).

A literature citation names an entry of the bibliography, docs/references.md (entries are
headings ``### [Key] …``): a bracketed key with a year (``[Karnopp 1985]``, ``[Goldfarb &
Idnani 1983]``, ``[Arnström et al. 2022]``) or a key without one that the bibliography has
(``[Szkodny]``); the seed monograph's ``seed eq. N`` / ``seed eqs. N–M`` must name formulas
its entry lists (``*Formulas cited:*``), ``seed N.M`` / ``seed chapter N`` / ``seed's
chapter N`` sections it lists (``*Sections cited:*``); every entry says what irlc takes
from the work.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
SOURCE_DIRS = ("lang", "runtime", "robots", "frontdoor", "tests")
SOURCE_SUFFIXES = {".py", ".lark", ".toml", ".md"}

CITATION = re.compile(r"(?<![\w/.-])((?:[\w.-]+/)*[\w-]+\.md)\b")
# after a citation: closing backticks / quotes, spaces, an opening parenthesis, then §N
SECTION_AFTER = re.compile(r"[`'\"]*\s*\(?\s*§\s*(\d+(?:\.\d+)*)")
NAMED_AFTER = re.compile(r"[`'\"]*\s*\(?\s*§\s*([A-Za-z][^,;)\n]*)")
BARE_SECTION = re.compile(r"§\s*(\d+(?:\.\d+)*)")
NUMBERED_HEADING = re.compile(r"^#{1,6}\s+(\d+(?:\.\d+)*)\.?\s", re.MULTILINE)
HEADING = re.compile(r"^#{1,6}\s+(.*)$", re.MULTILINE)
TOP_FOLDERS = "lang|runtime|robots|frontdoor|tests|docs|bench|programs"
REPO_PATH = re.compile(
    rf"(?<![\w/.-])((?:{TOP_FOLDERS})/[\w./-]+\.(?:py|toml|lark|md|json|csv|txt|irl|ird))\b"
)
PLACEHOLDER = re.compile(r"(?:^|/)(?:[A-Z]+|x)(?:\.|/)")  # NAME.toml, x.toml
LINK = re.compile(r"\]\(([^)\s]+)\)")
REFERENCES = DOCS / "references.md"
ENTRY = re.compile(r"^### \[([^\]]+)\]", re.MULTILINE)
NAME = r"[A-Z][\w'’-]+"
KEYED = re.compile(rf"\[((?:{NAME})(?: (?:&|and) {NAME}| et al\.)? \d{{4}}[a-z]?)\]")
BRACKET = re.compile(r"\[([A-Z][\w &.'’-]*)\]")
SEED_FORMULA = re.compile(r"(?<![-\w])seed (?:eqs?\.|formulas?) (\d+)(?:\s*[–-]\s*(\d+))?")
SEED_SECTION = re.compile(
    r"(?<![-\w])seed(?:'s)? (?:(?:chapter|ch\.|§) ?(\d+(?:\.\d+)*)|(\d+(?:\.\d+)+))"
)


def _numbers(label: str, text: str) -> set[str]:
    """The numbers of an entry's ``*label:*`` line (``39, 40``; ``6.1``)."""
    m = re.search(rf"^\*{label}:\* (.*(?:\n(?!\n|\*|#).*)*)", text, re.MULTILINE)
    return set(re.findall(r"\d+(?:\.\d+)*", m.group(1))) if m else set()


def _bibliography(text: str) -> tuple[set[str], set[str], set[str]]:
    """The entry keys of docs/references.md, and the seed's formulas and sections."""
    keys = set(ENTRY.findall(text))
    seed = text.split("### [seed]", 1)[1].split("\n### ", 1)[0] if "### [seed]" in text else ""
    return keys, _numbers("Formulas cited", seed), _numbers("Sections cited", seed)


BIBLIOGRAPHY = _bibliography(REFERENCES.read_text(encoding="utf-8"))


def _literature_problems(text: str, where, bibliography=BIBLIOGRAPHY) -> list[str]:
    """Citations of the literature that name no entry (or no listed seed formula or
    section) of docs/references.md."""
    keys, formulas, sections = bibliography
    firsts = {k.split()[0] for k in keys}
    problems = []

    def problem(m: re.Match, what: str) -> None:
        problems.append(f"{where}:{_line(text, m.start())}: {what} in references.md")

    for m in KEYED.finditer(text):
        if m.group(1) not in keys:
            problem(m, f"[{m.group(1)}] is not an entry")
    for m in BRACKET.finditer(text):  # a key without a year: one the bibliography has
        name = m.group(1)
        if name not in keys and not KEYED.fullmatch(m.group()) and name.split()[0] in firsts:
            problem(m, f"[{name}] is not an entry")
    for m in SEED_FORMULA.finditer(text):
        first, last = int(m.group(1)), int(m.group(2) or m.group(1))
        missing = [n for n in range(first, last + 1) if str(n) not in formulas]
        if missing or last < first:
            problem(m, f"seed formula {missing or first} is not listed")
    for m in SEED_SECTION.finditer(text):
        if (section := m.group(1) or m.group(2)) not in sections:
            problem(m, f"seed section {section} is not listed")
    return problems


def _citing_files() -> list[Path]:
    files = [*sorted(DOCS.glob("*.md")), ROOT / "README.md"]
    for folder in SOURCE_DIRS:
        files += sorted(
            p
            for p in (ROOT / folder).rglob("*")
            if p.is_file() and p.suffix in SOURCE_SUFFIXES and p != Path(__file__).resolve()
        )
    return files


def _resolve(name: str, citing: Path) -> Path | None:
    for base in (citing.parent, DOCS, ROOT):
        candidate = base / name
        if candidate.is_file():
            return candidate.resolve()
    return None


def _sections(doc: Path) -> set[str]:
    return set(NUMBERED_HEADING.findall(doc.read_text(encoding="utf-8")))


def _named(doc: Path, name: str) -> bool:
    """Whether a heading of ``doc`` starts with ``name`` (case-insensitive)."""
    headings = HEADING.findall(doc.read_text(encoding="utf-8"))
    return any(h.strip().lower().startswith(name.strip().lower()) for h in headings)


def _line(text: str, pos: int) -> int:
    return text.count("\n", 0, pos) + 1


def _problems(path: Path) -> list[str]:
    text = path.read_text(encoding="utf-8")
    where = path.relative_to(ROOT) if path.is_relative_to(ROOT) else path.name
    problems, cited_spans = [], []
    for m in CITATION.finditer(text):
        name = m.group(1)
        target = _resolve(name, path)
        if target is None:
            problems.append(f"{where}:{_line(text, m.start())}: {name} does not exist")
            continue
        named = NAMED_AFTER.match(text, m.end())
        if named and not _named(target, named.group(1)):
            problems.append(
                f"{where}:{_line(text, m.start())}: {name} has no section § {named.group(1)}"
            )
        sec = SECTION_AFTER.match(text, m.end())
        if sec:
            cited_spans.append(sec.start(1))
            if sec.group(1) not in _sections(target):
                problems.append(
                    f"{where}:{_line(text, m.start())}: {name} has no section §{sec.group(1)}"
                )
    if path.suffix == ".md" and (own := _sections(path)):
        for m in BARE_SECTION.finditer(text):
            if m.start(1) not in cited_spans and m.group(1) not in own:
                problems.append(f"{where}:{_line(text, m.start())}: no section §{m.group(1)}")
    for m in REPO_PATH.finditer(text):
        cited = m.group(1)
        if not PLACEHOLDER.search(cited) and not (ROOT / cited).exists():
            problems.append(f"{where}:{_line(text, m.start())}: {cited} does not exist")
    problems += _literature_problems(text, where)
    if path.suffix == ".md":
        for m in LINK.finditer(text):
            link = m.group(1).split("#")[0]
            if link and "://" not in link and not (path.parent / link).exists():
                problems.append(f"{where}:{_line(text, m.start())}: link {link} does not exist")
    # by line (stable: within a line, citations, then bare sections, then links)
    return sorted(problems, key=lambda s: int(s.split(":")[1]))


@pytest.mark.parametrize("path", _citing_files(), ids=lambda p: str(p.relative_to(ROOT)))
def test_citations_point_at_existing_files_and_sections(path):
    assert _problems(path) == []


def test_docs_cite_nothing_outside_the_repository():
    offenders = [
        str(p.relative_to(ROOT))
        for p in [*DOCS.glob("*.md"), ROOT / "README.md"]
        if re.search(r"\.\./shared|shared/spec|/work/", p.read_text(encoding="utf-8"))
    ]
    assert offenders == []


def test_the_checker_sees_a_stale_section_and_a_missing_file(tmp_path):
    doc = tmp_path / "cites.md"
    doc.write_text(
        "# Cites\n\n## 1. One\n\nSee language.md §6.1, language.md §5.2,\n"
        "nowhere.md, §1, §2, [a link](img/none.png), interfaces.md § REPL,\n"
        "interfaces.md § Nothing, golden.md § 1, runtime/none.py, robots/NAME.toml.\n"
    )
    assert _problems(doc) == [
        "cites.md:5: language.md has no section §5.2",
        "cites.md:6: nowhere.md does not exist",
        "cites.md:6: no section §2",
        "cites.md:6: link img/none.png does not exist",
        "cites.md:7: interfaces.md has no section § Nothing",
        "cites.md:7: golden.md has no section §1",
        "cites.md:7: runtime/none.py does not exist",
    ]


def test_the_bibliography_has_the_sources_and_says_what_irlc_takes():
    text = REFERENCES.read_text(encoding="utf-8")
    keys, formulas, sections = BIBLIOGRAPHY
    assert {"seed", "Szkodny", "Yurevich", "Dubey & Luh 1988", "Pritschow & Koch 1991"} <= keys
    assert {str(n) for n in range(39, 50)} <= formulas and {"4.2", "4.2.4", "6"} <= sections
    entries = re.split(r"^### ", text, flags=re.MULTILINE)[1:]
    assert len(entries) == len(keys)
    for entry in entries:
        assert re.search(r"^\*irlc takes:\* \S", entry, re.MULTILINE), entry.splitlines()[0]


def test_the_checker_sees_a_citation_outside_the_bibliography():
    bibliography = ({"seed", "Karnopp 1985", "Szkodny"}, {"40", "41"}, {"4.2", "6"})
    text = (
        "friction [Karnopp 1985], [Karnopp 1986], [Nobody & Else 1999], [Szkodny], [Karnopp]\n"
        "[deg], [x], seed eq. 40–41, seed eq. 42, seed 4.2, seed 4.3,\n"
        "seed chapter 6, the seed's chapter 7, --seed 2.158, [mm, deg]\n"
    )
    assert _literature_problems(text, "t.md", bibliography) == [
        "t.md:1: [Karnopp 1986] is not an entry in references.md",
        "t.md:1: [Nobody & Else 1999] is not an entry in references.md",
        "t.md:1: [Karnopp] is not an entry in references.md",
        "t.md:2: seed formula [42] is not listed in references.md",
        "t.md:2: seed section 4.3 is not listed in references.md",
        "t.md:3: seed section 7 is not listed in references.md",
    ]
