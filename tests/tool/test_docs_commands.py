"""Every command shown in README.md and docs/tutorial.md runs as shown on a fresh copy.

The commands are parsed from the markdown, so the documents and this test cannot drift:

* a ```` ```sh ```` block: each line is a command (``\\`` continues it; ``#`` lines are
  comments);
* a ```` ```console ```` block: lines starting with ``$ `` are commands, the rest is output;
  for an ``irlc repl`` command the transcript's input lines (after a ``NAME> `` or
  ``....... `` prompt) are its standard input;
* a ```` ```irl FILE ```` block is written to ``FILE`` (the reader is told to save it);
* a ```` ```python ```` block runs as a script (``python -``, the block on stdin);
* a command expected to fail says so with ``(exit N)`` in its comment; all others must
  exit 0;
* the output a ``console`` block shows for a command is checked line by line (each line
  must appear in the command's output) unless it abbreviates (``…``, ``...``) or is a
  REPL transcript.

Skipped, and reported as skipped: ``pip install …`` and ``pytest`` (the suite this test
belongs to). ``a && b`` runs its parts in order, without the skipped ones.

Installs are simulated in the test environment: a document starts on the core install
(every optional extra's modules hidden, as ``sys.modules[name] = None`` in a
``sitecustomize`` on ``PYTHONPATH``, so ``import matplotlib`` fails as if it were not
installed); a ``pip install '.[EXTRA]'`` the document shows makes that extra's modules
(from pyproject.toml) available from then on. So a command that needs an extra the
document has not installed yet fails here as it would for the reader.

The documents run in order, each on its own fresh copy of the repository's files
(``git ls-files``) in a temporary folder, with the test environment's ``bin`` first on
``PATH``. It runs every simulation of both pages and the numba precompile steps once: a
scenario test (about a minute and a half on a laptop).
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from dataclasses import dataclass, replace
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCS = ("README.md", "docs/tutorial.md")
FENCE = re.compile(r"^```(\S*)[ \t]*(\S*)[ \t]*$")
EXPECTED_EXIT = re.compile(r"#.*\(exit (\d)\)")
PROMPT = re.compile(r"^(?:\w+> |\.{3,} ?)(.*)$")
SKIPPED = {"pip install": "install command", "pytest": "runs the test suite itself"}
EXTRAS = re.compile(r"\[([\w,\s-]+)\]")
HIDE_MODULES = """import os, sys
for _name in filter(None, os.environ.get("IRLC_DOCS_HIDDEN", "").split(",")):
    sys.modules.setdefault(_name, None)  # import fails as if not installed
"""
TIMEOUT_S = 300


@dataclass(frozen=True)
class Step:
    """One thing the document asks the reader to do, in document order."""

    line: int  # 1-based line in the document
    command: str = ""  # shell command ("" for a file to write)
    exit_code: int = 0
    stdin: str = ""
    expect: tuple[str, ...] = ()  # output lines shown in the document (stripped)
    write: tuple[str, str] | None = None  # (file name, text)


def _blocks(text: str):
    """``(info, argument, first line number, lines)`` of each fenced block."""
    lines = text.splitlines()
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if m is None:
            i += 1
            continue
        start = i + 1
        end = next(k for k in range(start, len(lines)) if lines[k].startswith("```"))
        yield m.group(1), m.group(2), start + 1, lines[start:end]
        i = end + 1


def _sh_steps(first: int, lines: list[str]) -> list[Step]:
    steps, pending, at = [], "", first
    for k, line in enumerate(lines):
        if not pending:
            at = first + k
        if line.rstrip().endswith("\\"):
            pending += line.rstrip()[:-1] + " "
            continue
        command = (pending + line).strip()
        pending = ""
        if command and not command.startswith("#"):
            steps.append(_step(at, command))
    return steps


def _console_steps(first: int, lines: list[str]) -> list[Step]:
    steps = []
    for k, line in enumerate(lines):
        if not line.startswith("$ "):
            continue
        command = line[2:].strip()
        shown = []
        for later in lines[k + 1 :]:
            if later.startswith("$ "):
                break
            shown.append(later)
        stdin, expect = "", ()
        if re.match(r"irlc repl\b", command):
            inputs = [m.group(1) for m in map(PROMPT.match, shown) if m]
            stdin = "".join(f"{x}\n" for x in inputs)
        elif not any("…" in x or "..." in x for x in shown):
            expect = tuple(x.strip() for x in shown if x.strip())
        steps.append(replace(_step(first + k, command, stdin), expect=expect))
    return steps


def _step(line: int, command: str, stdin: str = "") -> Step:
    m = EXPECTED_EXIT.search(command)
    return Step(line, command, int(m.group(1)) if m else 0, stdin)


def doc_steps(doc: str) -> list[Step]:
    """The steps of one document of the repository (see the module doc)."""
    return steps_of((ROOT / doc).read_text(encoding="utf-8"))


def steps_of(text: str) -> list[Step]:
    steps: list[Step] = []
    for info, arg, first, lines in _blocks(text):
        if info == "sh":
            steps += _sh_steps(first, lines)
        elif info == "console":
            steps += _console_steps(first, lines)
        elif info == "python":
            steps.append(Step(first, "python -", stdin="\n".join(lines) + "\n"))
        elif info == "irl" and arg:
            steps.append(Step(first - 1, write=(arg, "\n".join(lines) + "\n")))
    return steps


def runnable(command: str) -> tuple[str, list[str]]:
    """``command`` without its skipped parts, and the reasons for what was skipped."""
    kept, skipped = [], []
    for part in (p.strip() for p in command.split("&&")):
        reason = next((r for prefix, r in SKIPPED.items() if part.startswith(prefix)), None)
        if reason:
            skipped.append(f"{part!r}: {reason}")
        else:
            kept.append(part)
    return " && ".join(kept), skipped


def extra_modules() -> dict[str, set[str]]:
    """Optional extra → the top-level modules its packages provide (pyproject.toml;
    ``irlc[a,b]`` entries resolved)."""
    import tomllib

    table = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    extras = table["project"]["optional-dependencies"]

    def modules(extra: str) -> set[str]:
        out: set[str] = set()
        for req in extras[extra]:
            m = re.match(r"irlc\[([^\]]+)\]", req)
            if m:
                out |= set().union(*(modules(e.strip()) for e in m.group(1).split(",")))
            else:
                out.add(re.split(r"[<>=!~\[; ]", req, maxsplit=1)[0].lower().replace("-", "_"))
        return out

    return {extra: modules(extra) for extra in extras}


def installed_extras(command: str) -> set[str]:
    """The extras a skipped ``pip install`` names (``.[plot]``, ``-e '.[test]'``)."""
    found: set[str] = set()
    for part in command.split("&&"):
        if part.strip().startswith("pip install"):
            for m in EXTRAS.finditer(part):
                found |= {e.strip() for e in m.group(1).split(",")}
    return found


def fresh_copy(dest: Path) -> Path:
    """The repository's tracked files (as in the working tree) under ``dest``."""
    try:
        listed = subprocess.run(
            ["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True, timeout=60
        ).stdout.decode()
        files = [f for f in listed.split("\0") if f]
    except (OSError, subprocess.SubprocessError):
        pytest.skip("needs a git checkout to know the repository's files")
    for rel in files:
        src = ROOT / rel
        if src.is_file():
            (dest / rel).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / rel)
    return dest


def _env(site: Path) -> dict[str, str]:
    env = dict(os.environ)
    env["PATH"] = str(Path(sys.executable).parent) + os.pathsep + env.get("PATH", "")
    env["PYTHONPATH"] = str(site) + os.pathsep + env.get("PYTHONPATH", "")
    env.setdefault("OPENBLAS_NUM_THREADS", "1")
    env["COLUMNS"] = "120"
    return env


# ----------------------------------------------------------------------------- parser


def test_parser_reads_sh_console_and_files():
    text = "\n".join(
        [
            "```irl a.irl",
            "PROGRAM a;",
            "```",
            "```sh",
            "pip install . && irlc a.irl   # run it",
            "# a comment",
            "irlc check bad.irl \\",
            "  --robot koch11   # (exit 1)",
            "```",
            "```console",
            "$ irlc repl --robot koch11",
            "koch11> MOVE LIN p",
            "→ t = 1 s",
            "....... ENDIF",
            "$ irlc robots",
            "```",
            "```console",
            "$ irlc check a.irl   # (exit 1)",
            "a.irl:1:1: error: x",
            "  hint: y",
            "$ irlc a.irl",
            "│ status ok",
            "│ ...",
            "```",
            "```python",
            "print(1)",
            "```",
            "```text",
            "$ not a command",
            "```",
        ]
    )
    steps = steps_of(text)
    assert steps[0].write == ("a.irl", "PROGRAM a;\n")
    assert runnable(steps[1].command)[0] == "irlc a.irl   # run it"
    assert "install command" in runnable(steps[1].command)[1][0]
    assert (steps[2].command, steps[2].exit_code, steps[2].line) == (
        "irlc check bad.irl    --robot koch11   # (exit 1)",
        1,
        7,
    )
    assert steps[3].stdin == "MOVE LIN p\nENDIF\n" and steps[4].command == "irlc robots"
    assert steps[3].expect == () and steps[4].expect == ()
    assert (steps[5].exit_code, steps[5].expect) == (1, ("a.irl:1:1: error: x", "hint: y"))
    assert steps[6].expect == ()  # abbreviated output is not checked
    assert (steps[7].command, steps[7].stdin) == ("python -", "print(1)\n")
    assert len(steps) == 8


def test_extras_from_pyproject_and_install_commands():
    modules = extra_modules()
    assert modules["plot"] == {"matplotlib"} and modules["urdf"] == {"yourdfpy"}
    assert {"matplotlib", "yourdfpy", "prompt_toolkit"} <= modules["full"] <= modules["test"]
    assert installed_extras("pip install . && irlc x.irl") == set()
    assert installed_extras("pip install -e '.[test]' && pytest") == {"test"}
    assert installed_extras("pip install '.[plot, repl]'") == {"plot", "repl"}


def test_hidden_module_fails_to_import(tmp_path):
    """The simulated core install: a hidden module cannot be imported in a subprocess."""
    (tmp_path / "sitecustomize.py").write_text(HIDE_MODULES, encoding="utf-8")
    env = _env(tmp_path) | {"IRLC_DOCS_HIDDEN": "json"}
    probe = "import importlib.util, sys; print(importlib.util.find_spec('json')); import json"
    done = subprocess.run(
        [sys.executable, "-c", probe], env=env, capture_output=True, text=True, timeout=60
    )
    assert done.returncode == 1 and done.stdout.strip() == "None"
    assert "ModuleNotFoundError" in done.stderr


def test_docs_show_commands():
    """Guard against a silently empty parse (a renamed fence would skip everything)."""
    for doc in DOCS:
        assert sum(bool(s.command) for s in doc_steps(doc)) >= 5, doc


# ----------------------------------------------------------------------------- the run


@pytest.mark.scenario
@pytest.mark.parametrize("doc", DOCS)
def test_every_documented_command_runs(doc, tmp_path, capsys):
    work = fresh_copy(tmp_path / "repo")
    site = tmp_path / "site"
    site.mkdir()
    (site / "sitecustomize.py").write_text(HIDE_MODULES, encoding="utf-8")
    env = _env(site)
    modules = extra_modules()
    hidden = set().union(*modules.values())  # the core install
    skipped: list[str] = []
    for step in doc_steps(doc):
        if step.write is not None:
            (work / step.write[0]).write_text(step.write[1], encoding="utf-8")
            continue
        for extra in installed_extras(step.command):
            hidden -= modules[extra]
        env["IRLC_DOCS_HIDDEN"] = ",".join(sorted(hidden))
        command, why = runnable(step.command)
        skipped += [f"{doc}:{step.line}: {w}" for w in why]
        if not command:
            continue
        done = subprocess.run(
            ["bash", "-c", command],
            cwd=work,
            env=env,
            input=step.stdin,
            capture_output=True,
            text=True,
            timeout=TIMEOUT_S,
        )
        assert done.returncode == step.exit_code, (
            f"{doc}:{step.line}: `{command}` exited {done.returncode}, "
            f"documented {step.exit_code}\n--- stdout\n{done.stdout[-3000:]}"
            f"\n--- stderr\n{done.stderr[-3000:]}"
        )
        assert "Traceback" not in done.stderr, f"{doc}:{step.line}: {done.stderr[-3000:]}"
        printed = {x.strip() for x in (done.stdout + done.stderr).splitlines()}
        missing = [x for x in step.expect if x not in printed]
        assert not missing, (
            f"{doc}:{step.line}: `{command}` did not print the documented lines {missing}\n"
            f"--- stdout\n{done.stdout[-3000:]}\n--- stderr\n{done.stderr[-3000:]}"
        )
    with capsys.disabled():
        for s in skipped:
            print(f"\nskipped {s}", end="")
