"""``irlc repl``: an interactive IRL session on one simulated robot.

Every entry is compiled as a whole program — the accumulated data-list imports and
declarations, then the new statements as the main body (``compile_source(…, repl=True)``)
— and executed with the interpreter's incremental mode on one persistent
:class:`~irlc.runtime.control.executor.SimulatedController` and
:class:`~irlc.runtime.interpreter.MachineState`: variables, system variables, modal
options (JOINTLIMIT … FREEZE), simulated time and the recorded trace carry over.

Entries:

* declarations — ``VAR …``, ``CONST …``, ``TYPE …``, ``PROCEDURE … ENDPROC``,
  ``FUNCTION … ENDFCT``, the short form ``POSE: p1, p2;`` (= ``VAR POSE: p1, p2;``) and
  ``POSE: p := expr;`` (declare, then assign); ``IMPORT DATALIST name;``;
* statements — anything else; after motion the session prints where the robot went;
* meta-commands — ``:where :robot :limits :options :trace FILE :plot DIR :teach NAME [FILE]
  :program :reset :help :quit``. ``:teach`` stores the current pose and joints into a
  data list (:mod:`irlc.teach`), like a teach pendant.

A block (IF … ENDIF, WHILE … ENDWHILE, FOR, REPEAT … UNTIL, CASE, PROCEDURE … ENDPROC,
FUNCTION … ENDFCT, RECORD … ENDRECORD) is read until it closes; a final ``;`` may be left
out. Diagnostics of a script piped in point at the script (``<stdin>:LINE:COL``, LINE =
the entry's first line + the line within the entry); interactively they point into the
entry (``<input>:LINE:COL``). On a terminal the line editor is prompt_toolkit (history,
completion, highlighting); otherwise plain lines.
"""

from __future__ import annotations

import dataclasses
import functools
import os
import re
import sys
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from irlc.lang import types as T
from irlc.lang.diagnostics import Diagnostic, line_span, render
from irlc.lang.file_access import path_kind
from irlc.lang.settings import LIMIT_OPTIONS, SETTINGS
from irlc.runtime import units, values
from irlc.runtime.model.naming import JointNaming

INPUT_NAME = "<input>"  # an entry typed at the terminal
SCRIPT_NAME = "<stdin>"  # a script piped in
DEFAULT_ROBOT = "koch11"
TYPE_WORDS = (*T.SIMPLE, *T.JOINT_TUPLE_TYPES)
DECL_STARTS = ("VAR", "CONST", "TYPE", "PROCEDURE", "FUNCTION")
BLOCKS = {  # opener → closer
    "IF": "ENDIF",
    "WHILE": "ENDWHILE",
    "FOR": "ENDFOR",
    "REPEAT": "UNTIL",
    "CASE": "ENDCASE",
    "PROCEDURE": "ENDPROC",
    "FUNCTION": "ENDFCT",
    "RECORD": "ENDRECORD",
}
META_HELP = """\
:where          pose (mm, deg) and joints of the robot, simulated time
:robot          the robot: joints, kinds, units
:limits         joint limits: the robot's and the active program limits
:options        active modal options (JOINTLIMIT …, CYCLIC, OBSTACLE, FREEZE), the R_… settings
:trace FILE     write the session's trace (CSV, program units)
:plot DIR       write the session's figures (PNG) into DIR
:teach NAME [FILE]  store the pose as NAME and the joints as NAME_joints in a data list
                (default taught.toml here; created or updated, comments kept)
:program        print the session as one IRL program
:reset          forget declarations and variables; robot back home
:help           this text
:quit           end the session (also Ctrl-D)
Declarations: VAR POSE: p;  POSE: p := (x, y, z, a, b, c);  CONST …;  PROCEDURE … ENDPROC
Statements run at once; blocks (IF … ENDIF, WHILE … ENDWHILE, …) are read until they close."""

_TOKEN = re.compile(
    r"\{.*?\}|\(\*.*?\*\)|//[^\n]*|'(?:[^']|'')*'|\"[^\"]*\"|[A-Za-z_][A-Za-z0-9_]*|\S", re.S
)


# --------------------------------------------------------------------------- input shape


def words(text: str) -> list[str]:
    """Upper-cased words of ``text`` outside comments and strings."""
    out = []
    for m in _TOKEN.finditer(text):
        tok = m.group()
        if tok[0].isalpha() or tok[0] == "_":
            out.append(tok.upper())
    return out


def block_depth(text: str) -> int:
    """Open blocks in ``text`` (openers minus closers; ``END…`` words of options excluded)."""
    depth = 0
    closers = set(BLOCKS.values())
    for w in words(text):
        if w in BLOCKS:
            depth += 1
        elif w in closers:
            depth -= 1
    return depth


_CLOSED = re.compile(r"\{.*?\}|\(\*.*?\*\)|//[^\n]*|'(?:[^']|'')*'|\"[^\"]*\"", re.S)


def _unterminated_comment(text: str) -> bool:
    rest = _CLOSED.sub(" ", text)
    return "{" in rest or "(*" in rest


def is_complete(text: str) -> bool:
    """An entry is complete when no block or comment is left open."""
    return block_depth(text) <= 0 and not _unterminated_comment(text)


def _teach_path(cwd: Path, raw: str) -> Path | None:
    """The data-list file of ``:teach NAME FILE``: relative to ``cwd``, ``.toml`` added to
    a name without a suffix (``cell`` is ``cell.toml``, even beside a folder ``cell``);
    ``None`` when ``raw`` can only mean a folder (``dir/``, ``.``, ``..``, ``~``)."""
    if (
        raw.endswith(("/", os.sep))
        or Path(raw).name in ("", ".", "..")
        or (raw.startswith("~") and os.sep not in raw)
    ):
        return None
    path = cwd / Path(raw).expanduser()
    return path if path.suffix else path.with_suffix(".toml")


_ADDED_END = "unexpected ';'"  # a parse error at the ';' that _terminated adds


def _terminated(text: str) -> str:
    body = text.rstrip()
    return body if body.endswith(";") else body + ";"


def classify(text: str) -> str:
    """``meta`` | ``empty`` | ``import`` | ``robot`` | ``decl`` | ``typed`` | ``stmt``."""
    stripped = text.strip()
    if not stripped:
        return "empty"
    if stripped.startswith(":") and not stripped.startswith(":="):
        return "meta"
    ws = words(stripped)
    if not ws:
        return "empty"
    if ws[:2] == ["IMPORT", "DATALIST"]:
        return "import"
    if ws[0] == "ROBOT":
        return "robot"
    if ws[0] in DECL_STARTS:
        return "decl"
    if _typed_short_form(stripped):
        return "typed"
    return "stmt"


_TYPE_ALTERNATIVES = "|".join(sorted(TYPE_WORDS, key=len, reverse=True))
_TYPED = re.compile(
    rf"^\s*(?P<type>(?:{_TYPE_ALTERNATIVES})\b|ARRAY\s*\[.*?\]\s*OF\s+\w+)\s*:\s*"
    r"(?P<names>[^:;]*?)\s*(?::=\s*(?P<init>.*?))?\s*;?\s*$",
    re.I | re.S,
)


def _typed_short_form(text: str) -> re.Match | None:
    return _TYPED.match(text)


# --------------------------------------------------------------------------- session


@dataclass
class Entry:
    """The outcome of one entry: what to print and whether it failed (1 compile, 2 run)."""

    lines: list[str] = field(default_factory=list)
    failure: int = 0


class Session:
    """One robot, one controller, one machine state; see the module docstring."""

    def __init__(
        self,
        robot: str | None = None,
        datalist_path=(),
        cwd: Path | None = None,
        allow_any_path: bool = False,
    ):
        from irlc.robots import load_robot

        self.robot_name = robot or DEFAULT_ROBOT
        self.model = load_robot(self.robot_name)
        self.cwd = Path(cwd or Path.cwd())
        self.datalist_path = tuple(str(p) for p in datalist_path)
        self.allow_any_path = allow_any_path  # data lists outside cwd / --datalist-path
        self.imports: list[str] = []
        self.decls: list[str] = []
        self.names: set[str] = set()
        self.history: list[str] = []  # statements run, for :program
        self.last_code = None
        self.origin: int | None = None  # script line of the current entry (None: terminal)
        self.q_start = self.model.home_q()
        self._new_machine(self.q_start, {})

    # ------------------------------------------------------------------ machine

    def _new_machine(self, q0: np.ndarray, obstacles: dict, keep_state: bool = False) -> None:
        from irlc.runtime.interpreter import MachineState
        from irlc.runtime.run import SPILL_ROWS

        self.obstacles = obstacles
        self.controller = _controller_class()(self.model, q0, obstacles=obstacles)
        self.controller.recorder.spill(SPILL_ROWS)  # a long session: older samples on disk
        if not keep_state:
            self.state = MachineState()

    def reset(self) -> Entry:
        self.imports, self.decls, self.names, self.history = [], [], set(), []
        self.last_code = None
        self._new_machine(self.model.home_q(), {})
        return Entry([f"reset: {self.model.name} at home, no declarations"])

    # ------------------------------------------------------------------ program text

    def _robot_clause(self) -> str:
        name = self.robot_name
        shown = name if re.fullmatch(r"[A-Za-z_]\w*", name) else "'" + name.replace("'", "''") + "'"
        return f"ROBOT r := {shown};"

    def program_text(self, decls: list[str], imports: list[str], body: str) -> tuple[str, int]:
        """The whole program and the 1-based line where ``body`` starts."""
        head = ["PROGRAM repl;", self._robot_clause(), *imports, *decls, "BEGIN"]
        text = "\n".join(head)
        first = text.count("\n") + 2
        return f"{text}\n{body}\nENDPROGRAM\n", first

    # ------------------------------------------------------------------ compiling

    def compile(self, decls, imports, body: str, chunk: str, chunk_line: int):
        """Compile; return ``(code, messages)`` (code None on errors)."""
        from irlc.lang.compiler import compile_source
        from irlc.robots import load_robot

        text, _ = self.program_text(decls, imports, body)

        def resolve(name: str):
            return self.model if str(name) == self.robot_name else load_robot(name)

        result = compile_source(
            text,
            str(self.cwd / "repl.irl"),
            resolve_robot=resolve,
            datalist_path=(str(self.cwd), *self.datalist_path),
            repl=True,
            allow_any_path=self.allow_any_path,
        )
        diags = list(result.diagnostics)
        errors = [d for d in diags if d.is_error]
        messages = [self._render(d, chunk, chunk_line) for d in diags]
        session = str(self.cwd / "repl.irl")
        if errors and all(d.file != session for d in errors):  # all in a data list's file
            messages.append(self._named_file(errors[0].file, chunk))
        if errors or result.code is None:
            return None, messages or [self._located("the entry does not compile")]
        return result.code, messages

    def _named_file(self, file: str, chunk: str) -> str:
        """The entry's own error when its errors lie in another file (a data list it
        imports, positioned there): at the entry's first mention of the file's name."""
        name = Path(file).stem
        for line, text in enumerate(chunk.split("\n"), 1):
            column = text.lower().find(name.lower()) + 1
            if column:
                return self._located(f"data list '{name}' has errors (above)", line, column)
        return self._located(f"data list '{name}' has errors (above)")

    def _render(self, diag, chunk: str, chunk_line: int) -> str:
        """``diag`` (a position in the session program) as a position in the entry."""
        span = diag.span
        n_lines = chunk.count("\n") + 1
        session = str(self.cwd / "repl.irl")
        if diag.file != session:  # a data list's problem: its own file and line
            return render(diag, "")
        if span is None or not chunk_line <= span.line < chunk_line + n_lines:
            # outside the entry (the session program's end): at the entry's first or last line
            local_line = n_lines if span is not None and span.line >= chunk_line else 1
            _, _, rest = render(dataclasses.replace(diag, span=None), "").partition("\n")
            header = self._located(diag.message, local_line, severity=diag.severity)
            return f"{header}\n{rest}" if rest else header
        local = _shifted(span, 1 - chunk_line)  # line 1 = the entry's first line
        typed = chunk.split("\n")[local.line - 1].rstrip()
        if local.column > len(typed) and diag.message.startswith(_ADDED_END):
            # at the ';' the session adds to a statement: the user's entry ends there
            rest = diag.message[len(_ADDED_END) :]
            diag = dataclasses.replace(diag, message=f"unexpected end of the entry{rest}")
        _, _, shown = render(dataclasses.replace(diag, span=local), chunk).partition("\n")
        file, where = self._entry_file(), local
        if self.origin is not None:
            where = _shifted(local, self.origin - 1)
        header = dataclasses.replace(diag, file=file, span=where).header()
        return f"{header}\n{shown}" if shown else header

    def _entry_file(self) -> str:
        return INPUT_NAME if self.origin is None else SCRIPT_NAME

    def _located(
        self, message: str, local_line: int = 1, column: int = 1, severity: str = "error"
    ) -> str:
        """``FILE:LINE:COL: error: message`` at a line of the entry (1 = its first), as
        every diagnostic of the session is (``docs/interfaces.md``, Diagnostics)."""
        line = self._entry_line(local_line)
        return f"{self._entry_file()}:{line}:{column}: {severity}: {message}"

    def _entry_line(self, local_line: int) -> int:
        """A line of the entry (1 = its first) as the user counts it."""
        return local_line if self.origin is None else self.origin + local_line - 1

    # ------------------------------------------------------------------ entries

    def enter(self, text: str, line: int | None = None) -> Entry:
        """Run one entry; ``line``: where it starts in a script (positions are then
        ``<stdin>:LINE:COL``), None at the terminal (``<input>:LINE:COL`` in the entry).

        The session survives any entry: a failure that escapes the compiler and the
        interpreter (a robot or data file, the environment: 3; anything else, a bug: 4)
        is reported for this entry and the session goes on with its state."""
        self.origin = line
        try:
            return self._enter(text)
        except RecursionError:
            return Entry([self._located("the entry nests too deeply")], 1)
        except Exception as e:
            return Entry([self._escaped_failure(e)], _failure_status(e))

    def _escaped_failure(self, e: Exception) -> str:
        if _failure_status(e) == 2:
            return self._located(f"run-time failure: {getattr(e, 'message', e)}")
        if _failure_status(e) == 3:
            return self._located(str(e))
        return self._located(
            f"internal error: {type(e).__name__}: {e} (a bug in irlc; the session goes on)"
        )

    def _enter(self, text: str) -> Entry:
        kind = classify(text)
        if kind == "empty":
            return Entry()
        if kind == "meta":
            return self.meta(text.strip())
        if kind == "robot":
            return Entry([self._located("the robot is chosen with --robot or :robot NAME")], 1)
        # entries keep their leading blanks, so that columns match what was typed
        if kind == "import":
            return self._declare(imports=[_terminated(text)], decls=[])
        if kind == "decl":
            return self._declare(imports=[], decls=[_terminated(text)])
        if kind == "typed":
            return self._typed(text)
        return self._statement(_terminated(text), shown=text)  # (the ';' is not shown)

    def _typed(self, text: str) -> Entry:
        """``POSE: p, q;`` and ``POSE: p := expr;``: declare (``VAR`` on a line of its own
        above the text as typed), then assign (the text with its ``POSE:`` blanked out), so
        that the compiler's columns are the entry's."""
        m = _typed_short_form(text)
        decl = f"VAR\n{text[: m.end('names')]};"
        kept = f"VAR {m.group('type')}: {m.group('names').strip()};"
        if not m.group("init"):
            return self._declare(imports=[], decls=[decl], shown=text, skip=1, kept=kept)
        names = [n.strip() for n in m.group("names").split(",")]
        if len(names) != 1:
            return Entry([self._located("':=' declares one name at a time")], 1)
        entry = self._declare(imports=[], decls=[decl], shown=text, skip=1, kept=kept)
        if entry.failure:
            return entry
        prefix = re.sub(r"[^\n]", " ", text[: m.start("names")])
        more = self._statement(_terminated(prefix + text[m.start("names") :]), shown=text)
        if more.failure:  # keep the declaration; report the assignment's problem
            return Entry(entry.lines + more.lines, more.failure)
        return Entry(entry.lines + more.lines)

    def _declare(
        self,
        imports: list[str],
        decls: list[str],
        shown: str | None = None,
        skip: int = 0,
        kept: str | None = None,
    ) -> Entry:
        """Add an import or a declaration; ``shown`` is the entry as typed, which starts
        ``skip`` lines into the added text; ``kept`` (default: the text, stripped) is what
        the session keeps of it once it compiles (what ``:program`` shows)."""
        chunk = (imports or decls)[0]
        new_imports, new_decls = self.imports + imports, self.decls + decls
        before = self.imports if imports else [*new_imports, *self.decls]
        chunk_line = 3 + sum(t.count("\n") + 1 for t in before) + skip  # after PROGRAM, ROBOT
        code, messages = self.compile(new_decls, new_imports, "", shown or chunk, chunk_line)
        if code is None:
            return Entry(messages, 1)
        kept = kept or chunk.strip()
        if imports:
            self.imports = [*self.imports, kept]
        else:
            self.decls = [*self.decls, kept]
        self.last_code = code
        self._learn_names(code, chunk)
        notes = self._obstacle_change(code)
        return Entry(messages + notes)

    def _learn_names(self, code, chunk: str) -> None:
        self.names.update(g.name for g in code.globals)
        self.names.update(r.name for r in code.routines if r.kind != "MAIN")
        self.names.update(o.name for o in code.obstacles)
        for m in re.finditer(r"\b([A-Za-z_]\w*)\s*=", chunk):
            self.names.add(m.group(1))

    def _obstacle_change(self, code) -> list[str]:
        from irlc.runtime.run import obstacle_shapes

        shapes = obstacle_shapes(code)
        if set(shapes) == set(self.obstacles):
            return []
        self._new_machine(self.controller.q.copy(), shapes, keep_state=True)
        return [f"obstacles now known: {', '.join(sorted(shapes))} (the trace restarts here)"]

    def _statement(self, body: str, shown: str | None = None) -> Entry:
        """Run ``body``; ``shown`` (the entry as typed, default ``body``) has its columns."""
        from irlc.runtime.interpreter import Interpreter

        _, first = self.program_text(self.decls, self.imports, body)
        code, messages = self.compile(self.decls, self.imports, body, shown or body, first)
        if code is None:
            return Entry(messages, 1)
        out: list[str] = []
        t0, q0, motions = self.controller.time, self.controller.q.copy(), self.controller.motions
        self.controller.restart_cycle_budget()  # each entry has the whole cycle budget
        # an obstacle the arm is inside (a collision failed the last entry) may be left
        self.controller.collisions.tolerate(self.controller.recorder.last_clearances())
        self.controller.naming = JointNaming.for_model(self.model, code.joint_names)
        result = Interpreter(code, self.controller, state=self.state, output=out.append).run(
            check=False
        )
        self.state, self.last_code = result.state, code
        _drop_temporaries(self.state)
        lines = messages + list(out)
        if result.error is not None:
            lines.append(self._run_error(result.error, first, shown or body))
            # left out of :program (it would stop there), but not without a word: what it
            # did before failing (motion, assignments) stays in the session
            t = getattr(result.error, "time_s", None)
            when = f" at t = {t:.3f} s" if t is not None else ""
            self.history.append(
                f"{{ left out: an entry that failed{when}; what it did before failing (motion, "
                "assignments) stays in the session, so this program may not reproduce it }"
            )
            return Entry(lines, 2)
        self.history.append(body.strip())
        if self.controller.time > t0 or not np.array_equal(self.controller.q, q0):
            lines += self.where(short=True)
        elif self.controller.motions > motions:
            lines.append(f"→ already there (t = {self.controller.time:.3f} s)")
        return Entry(lines)

    def _run_error(self, error, first: int, body: str) -> str:
        """``FILE:LINE:COL: error: run-time failure at t = … s: message`` (as ``irlc run``:
        the column of the line's statement text); a failure in a routine declared earlier
        is placed at the entry's first line."""
        line = getattr(error, "line", None)
        local = 1
        if line is not None and first <= line < first + body.count("\n") + 1:
            local = line - first + 1
        t = getattr(error, "time_s", None)
        at = f" at t = {t:.3f} s" if t is not None else ""
        message = f"run-time failure{at}: {getattr(error, 'message', str(error))}"
        span = line_span(body, local)
        header = self._located(message, local, span.column)
        # the line and its underline, as a compile error shows them
        _, _, shown = render(Diagnostic("error", message, "", span), body).partition("\n")
        return f"{header}\n{shown}" if shown else header

    # ------------------------------------------------------------------ meta-commands

    def meta(self, text: str) -> Entry:
        name, _, arg = text[1:].partition(" ")
        arg = arg.strip()
        handlers: dict[str, Callable[[str], Entry]] = {
            "where": lambda a: Entry(self.where()),
            "robot": self._meta_robot,
            "limits": lambda a: Entry(self.limits()),
            "options": lambda a: Entry(self.options()),
            "trace": self._meta_trace,
            "plot": self._meta_plot,
            "teach": self._meta_teach,
            "program": lambda a: Entry(self.program_text(self.decls, self.imports,
                                                        "\n".join(self.history))[0].splitlines()),
            "reset": lambda a: self.reset(),
            "help": lambda a: Entry(META_HELP.splitlines()),
        }  # fmt: skip
        handler = handlers.get(name.lower())
        if handler is None:
            known = " ".join(":" + k for k in [*handlers, "quit"])
            return Entry([self._located(f"unknown command :{name}; known: {known}")], 1)
        try:
            return handler(arg)
        except OSError as e:  # a file it could not write or read: named, without the errno
            what = f"{e.filename}: {e.strerror}" if e.filename and e.strerror else str(e)
            return Entry([self._located(f"cannot use {what}")], 3)
        except Exception as e:  # a meta-command must not end the session
            return Entry([self._located(str(e))], 3)

    def _program_units(self, q_si: np.ndarray) -> list[float]:
        return [float(v) for v in units.joints_from_si(q_si, self.model.joint_kinds)]

    def naming(self) -> JointNaming:
        """Program names (the session's MAIN_JOINT names, default ``a1 … aN``) beside the
        robot file's (:mod:`irlc.runtime.model.naming`)."""
        code = self.last_code
        return JointNaming.for_model(self.model, code.joint_names if code is not None else None)

    def joint_names(self) -> tuple[str, ...]:
        return self.naming().program

    def _names_line(self) -> list[str]:
        """``names a1 (panda_joint1), …`` where the robot file names a joint differently."""
        naming = self.naming()
        if all(naming.label(j) == naming.name(j) for j in range(self.model.n)):
            return []
        return [f"  names  {naming.labels(range(self.model.n))}"]

    def where(self, short: bool = False) -> list[str]:
        pose = self.controller.pose(self.state.settings)
        x, y, z, a, b, c = units.pose_from_si(values.pose_to_matrix(pose))
        q = self._program_units(self.controller.q)
        joints = "  ".join(f"{n}={_fmt(v)}" for n, v in zip(self.joint_names(), q, strict=True))
        pose_text = ", ".join(_fmt(v) for v in (x, y, z, a, b, c))
        prefix = "→ " if short else ""
        return [
            f"{prefix}t = {self.controller.time:.3f} s  pose ({pose_text})  [mm, deg ZYX]",
            f"  joints {joints}",
            *([] if short else self._names_line()),
        ]

    def _meta_robot(self, arg: str) -> Entry:
        if arg:  # the robot is loaded first: one that cannot be keeps the session as it is
            from irlc.robots import load_robot

            load_robot(arg)
            self.__init__(arg, self.datalist_path, self.cwd, self.allow_any_path)
            return Entry([f"robot {self.model.name}: a new session (declarations cleared)"])
        m = self.model
        out = [f"robot {m.name}: {m.n} joints  {m.description}".rstrip()]
        naming = self.naming()
        for i, j in enumerate(m.joints):
            out.append(f"  {naming.label(i):20} {j.kind:9} [{units.joint_unit(j.kind)}]")
        tool = ", ".join(_fmt(v) for v in units.pose_from_si(m.tool))
        out.append(f"  tool ({tool}) [mm, deg]; R_TOOL is composed after it")
        return Entry(out)

    def _tool_line(self) -> str:
        """The active tool: the robot file's, then R_TOOL (mm, deg ZYX)."""

        def pose(t) -> str:
            return "(" + ", ".join(_fmt(v) for v in units.pose_from_si(t)) + ")"

        file_tool = self.model.tool
        r_tool = values.pose_to_matrix(self.state.settings.tool)
        return (
            f"R_TOOL {pose(r_tool)} after the robot file's tool {pose(file_tool)}: "
            f"TCP tool {pose(file_tool @ r_tool)}  [mm, deg]"
        )

    def limits(self) -> list[str]:
        m, opts = self.model, self.state.options
        naming = self.naming()
        width = max(len(naming.label(j)) for j in range(m.n))
        out = [f"{'joint':{width}}  position min..max    speed max    accel max   program position"]
        scale = units.joint_scale(m.joint_kinds)
        prog = opts.joint_limits
        for j, joint in enumerate(m.joints):
            name = f"{naming.label(j):{width}}"
            lo, hi = (v / scale[j] for v in joint.limits.position)
            sp = joint.limits.speed[1] / scale[j]
            ac = joint.limits.accel[1] / scale[j]
            p = f"{_fmt(prog[0].values[j])}..{_fmt(prog[1].values[j])}" if prog else "-"
            unit = units.joint_unit(joint.kind)
            out.append(f"{name:6} {_fmt(lo):>9}..{_fmt(hi):<9} {_fmt(sp):>8} {_fmt(ac):>12}"
                       f"   {p}  [{unit}]")  # fmt: skip
        return out

    def options(self) -> list[str]:
        """The active modal options, then every setting of the table (lang/settings.py) and
        the tool."""
        o = self.state.options
        out = []
        for option in LIMIT_OPTIONS:
            pair = getattr(o, option.field)
            if pair:
                lo = ", ".join(_fmt(v) for v in pair[0].values)
                hi = ", ".join(_fmt(v) for v in pair[1].values)
                out.append(f"{option.word} min ({lo}) max ({hi})")
        if o.cyclic_reference is not None:
            out.append("CYCLIC reference (" + ", ".join(_fmt(v) for v in o.cyclic_reference) + ")")
        for name in o.obstacles:
            out.append(f"OBSTACLE {name}")
        if o.frozen:
            naming = self.naming()
            frozen = ", ".join(f"{naming.name(j)}={_fmt(v)}" for j, v in sorted(o.frozen.items()))
            out.append(f"FREEZE {frozen}")
        active = bool(out)
        out += settings_lines(self.state.settings)
        out.append(self._tool_line())
        return out if active else ["no modal options active", *out]

    # ------------------------------------------------------------------ files

    def run_result(self):
        """The session so far as a RunResult (for traces and plots)."""
        from irlc.runtime.control.executor import ExecutionOptions
        from irlc.runtime.interpreter import ExecutionResult
        from irlc.runtime.outputs.results import RunData, assemble
        from irlc.runtime.outputs.samples import Samples

        if self.last_code is None:
            _, self.last_code = None, self.compile([], [], "", "", 1)[0]
        s = self.state
        execution = ExecutionResult("ok", list(s.output), list(s.events), list(s.warnings),
                                    None, s, 0)  # fmt: skip
        samples = Samples.of(self.controller.recorder.arrays())
        run = assemble(RunData(self.last_code, self.model, self.controller, execution,
                               ExecutionOptions(), samples))  # fmt: skip
        for row in run.report["statements"]:  # entries have no source file (a repl.irl
            row["statement"] = row["kind"]  # in the folder is not the session's)
        return run

    def _meta_trace(self, arg: str) -> Entry:
        from irlc.report import write_trace

        if not arg:
            return Entry([self._located("usage: :trace FILE.csv")], 3)
        target = self.cwd / Path(arg).expanduser()
        if target.is_dir():
            return Entry(
                [self._located(f"{target} is a folder; :trace takes a file (FILE.csv)")], 3
            )
        run = self.run_result()
        path = write_trace(run.trace_columns, run.trace, target)
        return Entry([f"trace: {len(run.trace)} samples → {path}"])

    def _meta_plot(self, arg: str) -> Entry:
        from irlc.plots import write_plots

        if not arg:
            return Entry([self._located("usage: :plot DIR")], 3)
        target = self.cwd / Path(arg).expanduser()  # relative to the session's folder
        if target.exists() and not target.is_dir():
            return Entry(
                [self._located(f"{target} is not a folder; :plot takes a folder (DIR)")], 3
            )
        paths = write_plots(self.run_result(), target)
        return Entry([f"{len(paths)} figures → {Path(arg)}"])

    def _meta_teach(self, arg: str) -> Entry:
        """``:teach NAME [FILE]``: the pose (R_ACT_POSE: R_BASE frame, with R_TOOL) and the
        joints into a data list (:mod:`irlc.teach`); ``FILE`` relative to the session's
        folder, ``.toml`` added when it has no suffix, default ``taught.toml``."""
        from irlc.lang.parser import keywords
        from irlc.lang.settings import SYSTEM_VARIABLES
        from irlc.teach import JOINTS_SUFFIX, TeachError, teach

        parts = arg.split()
        if len(parts) not in (1, 2):
            return Entry([self._located("usage: :teach NAME [FILE.toml]")], 3)
        name, raw = parts[0], parts[1] if len(parts) == 2 else "taught.toml"
        path = _teach_path(self.cwd, raw)
        if path is None or path_kind(path) == "folder":
            where = raw if path is None else str(path)
            message = f"{where} is a folder; :teach takes a file (FILE.toml)"
            return Entry([self._located(message)], 3)
        taken = {n.lower() for n in (*self.names, *keywords(), *SYSTEM_VARIABLES)}
        clash = [n for n in (name, name + JOINTS_SUFFIX) if n.lower() in taken]
        if clash:
            return Entry([self._located(f"'{clash[0]}' is already a name of this session, a "
                                        "keyword or a system variable; choose another name")],
                         3)  # fmt: skip
        pose = self.controller.pose(self.state.settings)
        xyzabc = units.pose_from_si(values.pose_to_matrix(pose))
        joints = self._program_units(self.controller.q)
        try:
            keys = teach(path, name, xyzabc, joints)
        except TeachError as e:
            return Entry([self._located(str(e))], 3)
        return Entry([
            f"taught {name}: pose ({', '.join(_fmt(v) for v in xyzabc)}) [mm, deg ZYX] and "
            f"joints → {', '.join(keys)} in {path}",
            f"  use it: IMPORT DATALIST {path.stem};  MOVE LIN {name};  "
            f"MOVE PTP {name}{JOINTS_SUFFIX};",
        ])  # fmt: skip

    # ------------------------------------------------------------------ completion

    def completions(self) -> list[str]:
        from irlc.lang.parser import keywords

        metas = [":" + k for k in ("where", "robot", "limits", "options", "trace", "plot",
                                   "teach", "program", "reset", "help", "quit")]  # fmt: skip
        return sorted(set(keywords()) | self.names) + metas


def _failure_status(e: Exception) -> int:
    """The exit status a failure escaping an entry stands for (docs/interfaces.md)."""
    from irlc.robots import RobotFileError
    from irlc.runtime.errors import RunFailure
    from irlc.runtime.run import RunSetupError

    if isinstance(e, RunFailure):
        return 2
    if isinstance(e, RunSetupError | RobotFileError | OSError | MemoryError):
        return 3
    return 4


def unclosed_block(text: str) -> tuple[str, int] | None:
    """The innermost block left open in ``text``: its opening word and the line (1 = the
    first line of ``text``) it is on; ``None`` when every block closes."""
    closers = {v: k for k, v in BLOCKS.items()}
    stack: list[tuple[str, int]] = []
    for m in _TOKEN.finditer(text):
        word = m.group().upper()
        if word in BLOCKS:
            stack.append((word, text.count("\n", 0, m.start()) + 1))
        elif word in closers and stack:
            stack.pop()
    return stack[-1] if stack else None


@functools.cache
def _controller_class() -> type:
    """The simulated controller, counting the motion it is asked for (a MOVE to where the
    robot already is takes no time, yet the session should say that it ran)."""
    from irlc.runtime.control.executor import SimulatedController

    class ReplController(SimulatedController):
        motions = 0

        def move(self, cmd, settings, options) -> None:
            self.motions += 1
            super().move(cmd, settings, options)

        def reconfigure(self, target, line, settings, options) -> None:
            self.motions += 1
            super().reconfigure(target, line, settings, options)

    return ReplController


def _shifted(span, lines: int):
    """``span`` moved down by ``lines`` lines (up when negative)."""
    from irlc.lang.diagnostics import Span

    end = max(span.end_line + lines, 0) if span.end_line else 0
    return Span(span.line + lines, span.column, end, span.end_column)


def _drop_temporaries(state) -> None:
    """Forget the entry's compiler temporaries (``$for12``, ``$case3`` globals).

    The main body's temporaries are globals numbered after the declared ones; the next
    entry's code does not have them, so they must not stay in the session state."""
    keep = len(state.global_slots)
    while keep and state.global_slots[keep - 1].name.startswith("$"):
        keep -= 1
    del state.global_slots[keep:]
    del state.globals[keep:]


def settings_lines(settings, width: int = 88) -> list[str]:
    """The system variables of the settings table (lang/settings.py), one ``NAME value
    unit`` each, in the table's order, as lines of at most ``width`` characters."""
    items = []
    for row in SETTINGS:
        if row.system_variable:
            value = getattr(settings, row.field)
            shown = value if isinstance(value, str) else f"{value:g}"
            items.append(f"{row.system_variable} {shown}{' ' + row.unit if row.unit else ''}")
    lines = [items[0]]
    for item in items[1:]:
        if len(lines[-1]) + 2 + len(item) <= width:
            lines[-1] += "  " + item
        else:
            lines.append(item)
    return lines


def _fmt(v: float) -> str:
    """Up to 3 decimals, trailing zeros dropped; snapped (:func:`units.fixed`)."""
    text = units.fixed(v, 3).rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


# --------------------------------------------------------------------------- front ends


def numbered_entries(lines: Iterator[str]) -> Iterator[tuple[int, str]]:
    """Group raw lines into entries (blocks and comments are read until they close);
    yield ``(line of the entry's first line, entry)``, lines counted from 1."""
    buf: list[str] = []
    first = 1
    for number, line in enumerate(lines, start=1):
        if buf and _is_meta_line(line) and not _unterminated_comment("\n".join(buf)):
            yield number, line.rstrip("\n")  # a meta-command inside an open block runs now
            continue
        if not buf:
            first = number
        buf.append(line.rstrip("\n"))
        text = "\n".join(buf)
        if text.strip().startswith(":") or is_complete(text):
            yield first, text
            buf = []
    if buf and "\n".join(buf).strip():
        yield first, "\n".join(buf)


def _is_meta_line(line: str) -> bool:
    """A line that is a meta-command (``:where``): IRL has no statement that starts with a
    colon, so inside an open block it cannot be the block's text."""
    stripped = line.strip()
    return stripped.startswith(":") and not stripped.startswith(":=")


def read_entries(lines: Iterator[str]) -> Iterator[str]:
    """The entries of :func:`numbered_entries` without their line numbers."""
    return (text for _, text in numbered_entries(lines))


def run_plain(session: Session, stream, echo: Callable[[str], None]) -> int:
    """Scripted session: read entries from ``stream``; status of the first failure."""
    status = 0
    for line, entry in numbered_entries(iter(stream.readline, "")):
        if entry.strip().lower() in (":quit", ":q", ":exit"):
            break
        if not entry.strip().startswith(":") and not is_complete(entry):
            result = _unfinished(entry, line)  # the input ended inside a block or comment
        else:
            result = session.enter(entry, line)
        for line in result.lines:
            echo(line)
        if result.failure and not status:
            status = result.failure
    return status


def _unfinished(entry: str, first: int) -> Entry:
    """The entry the input ended in: name the block (or comment) left open and its line."""
    block = unclosed_block(entry)
    if block is not None:
        word, local = block
        what = f"{word} on line {first + local - 1} is not closed (expected {BLOCKS[word]})"
    else:
        what = "a comment is not closed"
    end = first + entry.count("\n")
    return Entry([f"{SCRIPT_NAME}:{end}:1: error: the input ends inside a block: {what}"], 1)


def history_file() -> Path:
    state = os.environ.get("XDG_STATE_HOME")
    if state:
        return Path(state) / "irlc" / "history"
    return Path.home() / ".irlc_history"


_STYLE_OF = {"keyword": "ansiblue bold", "comment": "ansigreen", "string": "ansimagenta",
             "number": "ansicyan", "meta": "ansiyellow"}  # fmt: skip


def token_styles(line: str, keywords: frozenset[str]) -> list[tuple[str, str]]:
    """``(style, text)`` fragments of one input line (for the terminal's highlighting)."""
    out, pos = [], 0
    for m in re.finditer(r"\{[^}]*\}?|\(\*.*?(?:\*\)|$)|//.*|'(?:[^']|'')*'?|\"[^\"]*\"?"
                         r"|\d+\.?\d*(?:[eE][+-]?\d+)?|[A-Za-z_]\w*|^:\w*", line):  # fmt: skip
        if m.start() > pos:
            out.append(("", line[pos : m.start()]))
        tok = m.group()
        if tok.startswith(("{", "(*", "//")):
            kind = "comment"
        elif tok.startswith(("'", '"')):
            kind = "string"
        elif tok[0].isdigit():
            kind = "number"
        elif tok.startswith(":"):
            kind = "meta"
        else:
            kind = "keyword" if tok.upper() in keywords else ""
        out.append((_STYLE_OF.get(kind, ""), tok))
        pos = m.end()
    if pos < len(line):
        out.append(("", line[pos:]))
    return out


def run_terminal(session: Session, echo: Callable[[str], None]) -> int:  # pragma: no cover
    """Interactive session with prompt_toolkit (history, completion, highlighting)."""
    from irlc.lang.parser import keywords
    from prompt_toolkit import PromptSession
    from prompt_toolkit.completion import WordCompleter
    from prompt_toolkit.history import FileHistory
    from prompt_toolkit.key_binding import KeyBindings
    from prompt_toolkit.lexers import Lexer

    kw = frozenset(keywords())

    class IrlLexer(Lexer):
        def lex_document(self, document):
            lines = document.lines
            return lambda i: token_styles(lines[i], kw) if i < len(lines) else []

    bindings = KeyBindings()

    @bindings.add("enter")
    def _(event):
        buf = event.current_buffer
        text = buf.text
        if text.strip().startswith(":") or is_complete(text):
            buf.validate_and_handle()
        else:
            buf.insert_text("\n")

    path = history_file()
    path.parent.mkdir(parents=True, exist_ok=True)
    prompt = PromptSession(
        history=FileHistory(str(path)),
        completer=WordCompleter(
            session.completions, ignore_case=True, pattern=re.compile(r"^[\w:]*")
        ),
        lexer=IrlLexer(),
        multiline=True,
        complete_while_typing=False,  # Tab completes
        key_bindings=bindings,
        prompt_continuation=lambda width, line, wrap: "." * (width - 1) + " ",
    )
    while True:
        try:
            text = prompt.prompt(f"{session.model.name}> ")
        except KeyboardInterrupt:
            continue
        except EOFError:
            return 0
        # a meta-command typed inside a block runs first (numbered_entries), then the block
        for _, entry in numbered_entries(iter(text.split("\n"))):
            if entry.strip().lower() in (":quit", ":q", ":exit"):
                return 0
            for line in session.enter(entry).lines:
                echo(line)


def main(
    robot: str | None = None, datalist_path=(), plain: bool = False, allow_any_path: bool = False
) -> int:
    from irlc.errors import UsageError
    from irlc.robots import RobotFileError

    try:
        session = Session(robot, datalist_path, allow_any_path=allow_any_path)
    except RobotFileError as e:
        raise UsageError(str(e)) from None

    def echo(line: str) -> None:
        print(line, flush=True)

    interactive = not plain and sys.stdin.isatty() and sys.stdout.isatty()
    if interactive:
        try:
            import prompt_toolkit  # noqa: F401
        except ImportError:
            echo("(prompt_toolkit is not installed: plain line input; pip install 'irlc[repl]')")
            interactive = False
    if interactive:
        echo(f"irlc repl on {session.model.name} ({session.model.n} joints). :help for help.")
        for line in session._names_line():
            echo(line.strip())
        return run_terminal(session, echo)
    return run_plain(session, sys.stdin, echo)
