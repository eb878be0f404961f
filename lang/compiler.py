"""The front end's entry points: IRL source in, diagnostics and IRDATA code out.

``compile_source`` never raises for bad user input: parse errors, unknown robots,
missing or malformed data lists and every static check end up as diagnostics, and
``code`` is ``None`` when any of them is an error.
"""

from __future__ import annotations

import gc
from collections.abc import Iterable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

from irlc.lang import ast
from irlc.lang import datalist as dlmod
from irlc.lang.cell import ProgramRobot, common_joint_count
from irlc.lang.checker import Checked, Checker
from irlc.lang.codegen import generate
from irlc.lang.diagnostics import Diagnostic, Span
from irlc.lang.errors import IrlcError
from irlc.lang.file_access import ALLOW_HINT, inside_roots, refusal
from irlc.lang.irdata import Code
from irlc.lang.nesting import nesting_error
from irlc.lang.parser import parse
from irlc.lang.signature import RobotResolver, RobotSignature, kind_letters
from irlc.lang.textfile import read_user_bytes


@dataclass
class CompileResult:
    code: Code | None
    diagnostics: list[Diagnostic] = field(default_factory=list)
    source: str = ""
    filename: str = ""

    @property
    def ok(self) -> bool:
        return self.code is not None

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.is_error]

    @property
    def warnings(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.severity == "warning"]


def compile_source(
    text: str,
    filename: str,
    *,
    resolve_robot: RobotResolver,
    datalist_path: Iterable[str] = (),
    robot_override: str | None = None,
    repl: bool = False,
    allow_any_path: bool = False,
    cooperating: tuple[tuple[int, int], ...] = (),
) -> CompileResult:
    """Compile IRL ``text`` (``filename`` is used in diagnostics and the SOURCE record).

    Data lists are searched in ``filename``'s folder, then in ``datalist_path``, then in
    the robot library, and must lie inside one of those folders once resolved unless
    ``allow_any_path`` (``irlc.lang.file_access``; the robot file's rule is the resolver's).
    ``robot_override`` is the command line's ``--robot``. ``cooperating`` (with ``repl``):
    the ``COOPERATE`` blocks an earlier entry opened, ``(worker, holder)`` robot indices —
    a ``COOPERATEEND`` of the program's main body may close them.
    """
    with _cycle_collector_paused():
        return _compile(
            text, filename, resolve_robot, tuple(datalist_path), robot_override, repl,
            allow_any_path, cooperating=cooperating,
        ).result  # fmt: skip


@dataclass
class Analysis:
    """A compilation with what the front end knew (:func:`analyze_source`): the result, the
    program's AST (``None`` when it did not parse) and the checked program — the AST
    annotated with types and symbols, the scopes, the data lists — (``None`` when it did
    not parse or names no usable robot)."""

    result: CompileResult
    program: ast.Program | None = None
    checked: Checked | None = None


def analyze_source(
    text: str,
    filename: str,
    *,
    resolve_robot: RobotResolver,
    datalist_path: Iterable[str] = (),
    allow_any_path: bool = False,
    datalist_texts: Mapping[str, str] | None = None,
) -> Analysis:
    """Compile ``text`` as :func:`compile_source` does and keep the checked program, for
    tools that look into it (the language server, ``irlc.lsp``). ``datalist_texts`` maps
    a data list's resolved path to the text to read in place of the file (an editor's
    unsaved buffer)."""
    with _cycle_collector_paused():
        return _compile(
            text, filename, resolve_robot, tuple(datalist_path), None, False, allow_any_path,
            dict(datalist_texts or {}),
        )  # fmt: skip


@contextmanager
def _cycle_collector_paused() -> Iterator[None]:
    """Pause CPython's cycle collector while the front end builds its trees.

    Parsing, checking and code generation allocate some 60 objects per source line, alive
    until the code is built. The collector runs a full collection each time the long-lived
    objects grow by a quarter, and each one traverses every object: ~log(n) passes over a
    heap growing to n objects, which made up half the compile time of a 1 MB program
    (40,000 lines: 3.3 s of 6.2 s in full collections). The front end's objects form
    trees, freed by reference counting without the collector, so the collector is paused
    for the compilation and restarted after (by the caller that paused it only).
    """
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_enabled:
            gc.enable()


def _compile(
    text: str,
    filename: str,
    resolve_robot: RobotResolver,
    datalist_path: tuple[str, ...],
    robot_override: str | None,
    repl: bool,
    allow_any_path: bool,
    datalist_texts: dict[str, str] | None = None,
    cooperating: tuple[tuple[int, int], ...] = (),
) -> Analysis:
    result = CompileResult(None, [], text, filename)
    analysis = Analysis(result)
    program, diags = parse(text, filename)
    result.diagnostics += diags
    if program is None:
        return analysis
    analysis.program = program
    if too_deep := nesting_error(program, filename):
        result.diagnostics.append(too_deep)
        return analysis
    robots = _robots(program, filename, resolve_robot, robot_override, result)
    if robots is None:  # every joint check depends on the robots: report only theirs
        return analysis
    counts = common_joint_count(robots) or tuple(sorted({r.n for r in robots}))
    datalists = _datalists(
        program, filename, datalist_path, counts, result, allow_any_path, datalist_texts or {}
    )
    checker = Checker(program, filename, robots, datalists, repl=repl, cooperating=cooperating)
    analysis.checked = checker.check()
    result.diagnostics += checker.diags
    if any(d.is_error for d in result.diagnostics):
        return analysis
    result.code = generate(analysis.checked, filename)
    return analysis


class _Unreadable(IrlcError):
    """Why the program file cannot be read (:func:`compile_file`)."""


def compile_file(path: str | Path, **options) -> CompileResult:
    """Read ``path`` (UTF-8; a leading byte-order mark is dropped) and compile it; a read
    failure is a diagnostic, a byte that is not UTF-8 one at its line and column."""
    name = str(path)
    try:
        data = read_user_bytes(path, lambda file, reason: _Unreadable(reason))
    except _Unreadable as e:  # "not a regular file", "cannot read the file (…)"
        return CompileResult(None, [Diagnostic("error", str(e), name)], "", name)
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as e:
        return CompileResult(None, [_not_utf8(data, e, name)], "", name)
    return compile_source(text, name, **options)


def _not_utf8(data: bytes, e: UnicodeDecodeError, name: str) -> Diagnostic:
    """The undecodable byte at its line and column (columns count characters before it)."""
    start = data.rfind(b"\n", 0, e.start) + 1
    line = data.count(b"\n", 0, e.start) + 1
    column = len(data[start : e.start].decode("utf-8", errors="replace")) + 1
    return Diagnostic(
        "error",
        f"the program is not UTF-8 text (byte 0x{data[e.start]:02x})",
        name,
        Span(line, column, line, column + 1),
        "save the file as UTF-8",
    )


def _robots(
    program: ast.Program,
    filename: str,
    resolve: RobotResolver,
    override: str | None,
    result: CompileResult,
) -> list[ProgramRobot] | None:
    """The program's robots (one per ROBOT clause, or the ``--robot`` one); ``None`` after
    a diagnostic: no robot, ``--robot`` with a cell, a robot that cannot be used."""
    clauses = program.robot
    if not clauses and override is None:
        result.diagnostics.append(
            Diagnostic(
                "error",
                "the program names no robot",
                filename,
                program.span,
                "add 'ROBOT r := koch11;' after the PROGRAM line, or pass --robot NAME",
            )
        )
        return None
    if len(clauses) > 1 and override is not None:
        result.diagnostics.append(
            Diagnostic(
                "error",
                f"--robot {override} cannot be used with a cell: the program names "
                f"{len(clauses)} robots ({', '.join(c.var for c in clauses)})",
                filename,
                clauses[1].span,
                "leave out --robot; each ROBOT clause names its robot",
            )
        )
        return None
    if len(clauses) > 1:
        robots = [_robot(k, c, filename, resolve, None, result) for k, c in enumerate(clauses)]
        return None if None in robots else robots  # type: ignore[return-value]
    robot = _robot(0, clauses[0] if clauses else None, filename, resolve, override, result)
    return None if robot is None else [robot]


def _robot(
    index: int,
    clause: ast.RobotClause | None,
    filename: str,
    resolve: RobotResolver,
    override: str | None,
    result: CompileResult,
) -> ProgramRobot | None:
    """The robot of one ROBOT clause (``--robot`` wins over it, with a warning)."""
    span: Span | None = clause.robot_span if clause else None
    wanted = override if override is not None else clause.robot  # type: ignore[union-attr]
    if clause is not None and override is not None and override.lower() != clause.robot.lower():
        result.diagnostics.append(
            Diagnostic(
                "warning",
                f"--robot {override} overrides the program's robot {clause.robot}",
                filename,
                clause.robot_span,
            )
        )
    robot_var = clause.var if clause else "r"
    where = "" if span is not None else " (given with --robot)"
    try:
        robot = _resolve_any_case(resolve, wanted)
    except LookupError as e:
        msg = str(e.args[0]) if isinstance(e, KeyError) and e.args else str(e)
        msg = f"cannot use robot '{wanted}'{where}: {msg}"
        result.diagnostics.append(Diagnostic("error", msg, filename, span))
        return None
    try:
        letters = kind_letters(robot)
    except ValueError as e:
        letters, problem = "", str(e)
    else:
        problem = "" if robot.joint_count == len(letters) >= 1 else "inconsistent joint count"
    if problem:
        result.diagnostics.append(
            Diagnostic("error", f"cannot use robot '{wanted}'{where}: {problem}", filename, span)
        )
        return None
    return ProgramRobot(index, robot_var, wanted, robot, clause)


def _resolve_any_case(resolve: RobotResolver, wanted: str) -> RobotSignature:
    """Robot names are identifiers, so case-insensitive: retry a library name in lower case.

    Only ``LookupError`` (the resolver protocol's "no such robot") is a diagnostic; any
    other exception is a bug of the resolver and propagates."""
    try:
        return resolve(wanted)
    except LookupError:
        if wanted.lower() == wanted or "/" in wanted or "." in wanted:
            raise
        return resolve(wanted.lower())


def _datalists(
    program: ast.Program,
    filename: str,
    search: tuple[str, ...],
    joint_count: int | tuple[int, ...],
    result: CompileResult,
    allow_any_path: bool = False,
    texts: Mapping[str, str] | None = None,
) -> list[dlmod.Datalist]:
    """The imported data lists; ``joint_count`` checks the arity of their joint values (a
    tuple: a cell's robots differ in joint count, a value has one of them; each use checks
    its robot's)."""
    out = []
    program_dir = Path(filename).parent
    seen: dict[str, int] = {}
    for clause in program.datalists:
        key = clause.name.lower()
        if key in seen:
            result.diagnostics.append(
                Diagnostic(
                    "error",
                    f"data list {clause.name} is imported twice (first on line {seen[key]})",
                    filename,
                    clause.span,
                )
            )
            continue
        seen[key] = clause.span.line
        path, searched = dlmod.find(clause.name, program_dir, search)
        if path is None:
            result.diagnostics.append(
                Diagnostic(
                    "error",
                    f"data list '{clause.name}.toml' not found",
                    filename,
                    clause.span,
                    "searched: " + ", ".join(searched) + " (add folders with --datalist-path DIR)",
                )
            )
            continue
        roots = dlmod.folders(program_dir, search)
        if not allow_any_path and not inside_roots(path, roots):
            msg = f"data list '{clause.name}.toml' is {refusal(roots)}"
            result.diagnostics.append(Diagnostic("error", msg, filename, clause.span, ALLOW_HINT))
            continue
        text = (texts or {}).get(str(path.resolve())) if texts else None
        dl, diags = dlmod.load(clause.name, path, program_dir, joint_count, text)
        result.diagnostics += diags
        out.append(dl)
    return out
