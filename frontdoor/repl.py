"""``irlc repl``: an interactive IRL session on one simulated robot, or a cell of several.

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
  data list (:mod:`irlc.teach`), like a teach pendant;
* robots — ``ROBOT name := robot [AT pose];``: the first replaces the default robot (none
  given with ``--robot``), the next make the session a cell (:mod:`irlc.repl_cell`); there
  ``:robot NAME`` selects the robot ``:limits``, ``:options`` and ``:teach`` show, ``:where``
  shows every robot. What the meta-commands show of a robot: :mod:`irlc.repl_views`.

A block (IF … ENDIF, WHILE … ENDWHILE, FOR, REPEAT … UNTIL, CASE, PROCEDURE … ENDPROC,
FUNCTION … ENDFCT, RECORD … ENDRECORD) is read until it closes; a final ``;`` may be left
out. Diagnostics of a script piped in point at the script (``<stdin>:LINE:COL``, LINE =
the entry's first line + the line within the entry); interactively they point into the
entry (``<input>:LINE:COL``). On a terminal the line editor is prompt_toolkit (history,
completion, highlighting); otherwise plain lines.
"""

from __future__ import annotations

import functools
import os
import re
import sys
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path

import numpy as np
from irlc import repl_files
from irlc.errors import UsageError
from irlc.lang import types as T
from irlc.repl_cell import CellMachine, check_distinct_names, robot_clause, robot_spec
from irlc.repl_positions import SCRIPT_NAME, Positions
from irlc.repl_views import (
    Entry,
    RobotView,
    cell_where_lines,
    limits_lines,
    names_line,
    options_lines,
    pose_text,
    robot_lines,
    where_lines,
)
from irlc.runtime import units
from irlc.runtime.model.naming import JointNaming

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
:where [NAME]   pose (mm, deg) and joints of the robot (a cell: of every robot), time
:robot [NAME]   the robot: joints, kinds, units (a cell: its robots; NAME selects one)
:limits [NAME]  joint limits: the robot's and the active program limits
:options [NAME] active modal options (JOINTLIMIT …, CYCLIC, OBSTACLE, FREEZE), the R_… settings
:trace FILE     write the session's trace (CSV, program units)
:plot DIR       write the session's figures (PNG) into DIR
:teach NAME [FILE]  store the pose as NAME and the joints as NAME_joints in a data list
                (default taught.toml here; created or updated, comments kept)
:program        print the session as one IRL program
:reset          forget declarations and variables; the robots back home
:help           this text
:quit           end the session (also Ctrl-D)
Declarations: VAR POSE: p;  POSE: p := (x, y, z, a, b, c);  CONST …;  PROCEDURE … ENDPROC
Robots: ROBOT b := as6 AT (0, -1550, 0, 180, 0, 0);  (a second robot makes a cell: MOVE b …)
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


def block_words(text: str) -> list[tuple[str, int]]:
    """The words of ``text`` that open or close a block, with their offsets: not in
    comments or strings, not ``END…`` words of options, and ``FOR`` only as a loop
    (``FOR i :=``), not as the robot suffix of a cell (``JOINTLIMIT lo, hi FOR holder;``)."""
    tokens = [(m.group(), m.start()) for m in _TOKEN.finditer(text)]
    closers = set(BLOCKS.values())
    out = []
    for k, (tok, start) in enumerate(tokens):
        word = tok.upper()
        if word == "FOR" and [t for t, _ in tokens[k + 2 : k + 4]] != [":", "="]:
            continue  # FOR robot
        if word in BLOCKS or word in closers:
            out.append((word, start))
    return out


def block_depth(text: str) -> int:
    """Open blocks in ``text`` (openers minus closers, :func:`block_words`)."""
    return sum(1 if w in BLOCKS else -1 for w, _ in block_words(text))


_CLOSED = re.compile(r"\{.*?\}|\(\*.*?\*\)|//[^\n]*|'(?:[^']|'')*'|\"[^\"]*\"", re.S)


def _unterminated_comment(text: str) -> bool:
    rest = _CLOSED.sub(" ", text)
    return "{" in rest or "(*" in rest


def is_complete(text: str) -> bool:
    """An entry is complete when no block or comment is left open."""
    return block_depth(text) <= 0 and not _unterminated_comment(text)


_POSITION = re.compile(r"^\S+:\d+:\d+: error: ")  # a rendered diagnostic's position


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


class Session:
    """One robot, or a cell of several, with its controller and one machine state; see the
    module docstring."""

    def __init__(
        self,
        robot: str | Sequence[str] | None = None,
        datalist_path=(),
        cwd: Path | None = None,
        allow_any_path: bool = False,
    ):
        from irlc.runtime.interpreter import MachineState

        specs = [robot] if isinstance(robot, str) else list(robot or ())
        check_distinct_names(specs)
        self.cwd = Path(cwd or Path.cwd())
        self.datalist_path = tuple(str(p) for p in datalist_path)
        self.allow_any_path = allow_any_path  # data lists outside cwd / --datalist-path
        self.imports: list[str] = []
        self.decls: list[str] = []
        self.names: set[str] = set()
        self.history: list[str] = []  # statements run, for :program
        self.last_code = None
        self.pos = Positions(str(self.cwd / "repl.irl"))  # where the entry is
        self.implicit = not specs  # the default robot, until a ROBOT entry names one
        self.clauses = [robot_clause(s) for s in specs] or [robot_clause(DEFAULT_ROBOT)]
        self.current = 0  # the robot :where NAME, :limits, :options, :teach show (a cell's)
        self.cell: CellMachine | None = None
        self.obstacles: dict = {}
        self.state = MachineState()
        self._models: dict[str, object] = {}
        for spec in specs:  # a robot that cannot be loaded: RobotFileError
            self._load(robot_spec(spec)[1])
        code, messages = self.compile([], [], "", "", 1)
        if code is None:
            shown = dict.fromkeys(_POSITION.sub("", m.splitlines()[0]) for m in messages)
            raise UsageError(f"--robot: {'; '.join(shown)}")
        self._use_robots(code, {})

    def _load(self, name: str):
        """The robot file ``name`` (loaded once per session)."""
        from irlc.robots import load_robot

        key = str(name)
        if key not in self._models:
            self._models[key] = load_robot(key)
        return self._models[key]

    # ------------------------------------------------------------------ machine

    def _new_machine(self, q0: np.ndarray, obstacles: dict, keep_state: bool = False) -> None:
        from irlc.runtime.interpreter import MachineState
        from irlc.runtime.run import SPILL_ROWS

        self.obstacles = obstacles
        self.controller = _controller_class()(self.model, q0, obstacles=obstacles)
        self.controller.recorder.spill(SPILL_ROWS)  # a long session: older samples on disk
        if not keep_state:
            self.state = MachineState()

    def _use_robots(self, code, joints: dict[str, np.ndarray]) -> None:
        """Run on the robots of ``code``: one robot (placed by its AT) on its controller,
        or a cell (:class:`~irlc.repl_cell.CellMachine`; ``joints``: the robots that keep
        theirs); the machine state's robots grow with the cell."""
        from irlc.runtime.interpreter.state import RobotContext
        from irlc.runtime.run_setup import placed

        if not code.is_cell:
            record = code.robots[0]
            self.robot_var, self.robot_name = record.var, record.robot
            self.model = placed(self._load(record.robot), record.at)
            self.cell = None
            self._new_machine(self.model.home_q(), self.obstacles, keep_state=True)
            return
        st = self.state
        if self.cell is None and not st.robots:  # one robot so far: its own variables
            st.robots = [RobotContext(st.settings.tool, st.settings.base, st.options)]
        st.robots += [RobotContext() for _ in range(len(code.robots) - len(st.robots))]
        self.cell = CellMachine(code, self.cwd, self.allow_any_path, self.obstacles, joints)
        self.model = self.cell.members[0].model

    def _joints_by_name(self) -> dict[str, np.ndarray]:
        if self.cell is not None:
            return self.cell.joints()
        return {self.robot_var: self.controller.q.copy()}

    @property
    def time(self) -> float:
        return self.controller.time if self.cell is None else self.cell.time

    def reset(self) -> Entry:
        from irlc.runtime.interpreter import MachineState

        self.imports, self.decls, self.names, self.history = [], [], set(), []
        self.last_code = None
        if self.cell is not None:  # the robots stay, each at its home
            self.state, self.obstacles, self.cell = MachineState(), {}, None
            code, _ = self.compile([], [], "", "", 1)
            self._use_robots(code, {})
            return Entry([f"reset: {', '.join(self.cell.names)} at home, no declarations"])
        self._new_machine(self.model.home_q(), {})
        return Entry([f"reset: {self.model.name} at home, no declarations"])

    # ------------------------------------------------------------------ program text

    def program_text(
        self, decls: list[str], imports: list[str], body: str, clauses: list[str] | None = None
    ) -> tuple[str, int]:
        """The whole program and the 1-based line where ``body`` starts."""
        head = ["PROGRAM repl;", *(clauses or self.clauses), *imports, *decls, "BEGIN"]
        text = "\n".join(head)
        first = text.count("\n") + 2
        return f"{text}\n{body}\nENDPROGRAM\n", first

    # ------------------------------------------------------------------ compiling

    def compile(self, decls, imports, body: str, chunk: str, chunk_line: int, clauses=None):
        """Compile (with the robots of ``clauses``, default the session's); return
        ``(code, messages)`` (code None on errors)."""
        from irlc.lang.compiler import compile_source

        text, _ = self.program_text(decls, imports, body, clauses)
        result = compile_source(
            text,
            str(self.cwd / "repl.irl"),
            resolve_robot=self._load,
            datalist_path=(str(self.cwd), *self.datalist_path),
            repl=True,
            allow_any_path=self.allow_any_path,
            cooperating=() if self.cell is None else self.cell.cooperating(),
        )
        diags = list(result.diagnostics)
        errors = [d for d in diags if d.is_error]
        messages = [self.pos.render(d, chunk, chunk_line) for d in diags]
        session = str(self.cwd / "repl.irl")
        if errors and all(d.file != session for d in errors):  # all in a data list's file
            messages.append(self.pos.named_file(errors[0].file, chunk))
        if errors or result.code is None:
            return None, messages or [self.pos.located("the entry does not compile")]
        return result.code, messages

    # ------------------------------------------------------------------ entries

    def enter(self, text: str, line: int | None = None) -> Entry:
        """Run one entry; ``line``: where it starts in a script (positions are then
        ``<stdin>:LINE:COL``), None at the terminal (``<input>:LINE:COL`` in the entry).

        The session survives any entry: a failure that escapes the compiler and the
        interpreter (a robot or data file, the environment: 3; anything else, a bug: 4)
        is reported for this entry and the session goes on with its state."""
        self.pos.origin = line
        try:
            return self._enter(text)
        except RecursionError:
            return Entry([self.pos.located("the entry nests too deeply")], 1)
        except Exception as e:
            return Entry([self._escaped_failure(e)], _failure_status(e))

    def _escaped_failure(self, e: Exception) -> str:
        if _failure_status(e) == 2:
            return self.pos.located(f"run-time failure: {getattr(e, 'message', e)}")
        if _failure_status(e) == 3:
            return self.pos.located(str(e))
        return self.pos.located(
            f"internal error: {type(e).__name__}: {e} (a bug in irlc; the session goes on)"
        )

    def _enter(self, text: str) -> Entry:
        kind = classify(text)
        if kind == "empty":
            return Entry()
        if kind == "meta":
            return self.meta(text.strip())
        if kind == "robot":
            return self._robot(text)
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
            return Entry([self.pos.located("':=' declares one name at a time")], 1)
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
        chunk_line = 2 + _line_count([*self.clauses, *before]) + skip  # after PROGRAM
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
        self.names.update(r.var for r in code.robots)
        for m in re.finditer(r"\b([A-Za-z_]\w*)\s*=", chunk):
            self.names.add(m.group(1))

    def _obstacle_change(self, code) -> list[str]:
        from irlc.runtime.run import obstacle_shapes

        shapes = obstacle_shapes(code)
        if set(shapes) == set(self.obstacles):
            return []
        if self.cell is None:
            self._new_machine(self.controller.q.copy(), shapes, keep_state=True)
        else:
            self.obstacles = shapes
            self.cell = self.cell.rebuilt(code, shapes, self.state)
        return [f"obstacles now known: {', '.join(sorted(shapes))} (the trace restarts here)"]

    def _robot(self, text: str) -> Entry:
        """``ROBOT name := robot [AT pose];``: a robot of the session (the first one
        replaces the default robot; a second makes the session a cell). The program with
        it must compile — the declarations, and in a cell the statements so far (what
        :program shows); the robots keep their joints, a new one starts at its home."""
        clauses = [*([] if self.implicit else self.clauses), _terminated(text)]
        refused = self._robot_refused()
        if refused:
            return Entry([self.pos.located(refused)], 1)
        chunk_line = 2 + _line_count(clauses[:-1])
        code, messages = self.compile(self.decls, self.imports, "", text, chunk_line, clauses)
        if code is None:
            return Entry(messages, 1)
        if self.history and code.is_cell:
            problem = self._history_problem(clauses)
            if problem:
                return Entry([self.pos.located(problem)], 1)
        moved, replaced = self.time > 0, self.implicit and self.model.name
        joints = {} if self.implicit else self._joints_by_name()
        self.clauses, self.implicit = [*clauses[:-1], clauses[-1].strip()], False
        self._use_robots(code, joints)
        self.last_code = code
        self._learn_names(code, "")
        record = code.robots[-1]
        at = f" at {pose_text(record.at)}" if record.at is not None else ""
        lines = [f"robot {record.var}: {record.robot}{at}"]
        if self.cell is None:
            lines[0] += f", the session's robot (in place of the default {replaced})"
        else:
            self.current = len(code.robots) - 1
            lines += self.cell.lines(self.current)
        if moved:
            lines.append("  (the robots keep their joints, the new one is at its home; the "
                         "trace restarts here)")  # fmt: skip
        return Entry(messages + lines)

    def _robot_refused(self) -> str | None:
        """Why a robot cannot be added now, else ``None``."""
        if self.implicit and self.history:
            return (
                f"the statements so far ran on the default robot {self.model.name}: :reset "
                "forgets them, then declare the robots (or start with --robot)"
            )
        if self.cell is not None and self.cell.cooperations():
            worker, holder = self.cell.cooperations()[0]
            return f"COOPERATE {worker} IN {holder} is open: end it (COOPERATEEND;) first"
        return None

    def _history_problem(self, clauses: list[str]) -> str | None:
        """Why the statements so far do not compile with the robots of ``clauses`` (a
        cell: each MOVE names its robot), else ``None``."""
        from irlc.lang.compiler import compile_source

        body = "\n".join(self.history)
        text, _ = self.program_text(self.decls, self.imports, body, clauses)
        result = compile_source(text, str(self.cwd / "repl.irl"), resolve_robot=self._load,
                                datalist_path=(str(self.cwd), *self.datalist_path),
                                repl=True, allow_any_path=self.allow_any_path)  # fmt: skip
        errors = [d for d in result.diagnostics if d.is_error]
        if not errors:
            return None
        where = ""
        if errors[0].span is not None:
            where = f" (in `{text.splitlines()[errors[0].span.line - 1].strip()}`)"
        return (
            f"with this robot the statements entered so far do not compile: "
            f"{errors[0].message}{where}; in a cell every MOVE names its robot — :reset forgets "
            "the statements (the robots stay)"
        )

    def _statement(self, body: str, shown: str | None = None) -> Entry:
        """Run ``body``; ``shown`` (the entry as typed, default ``body``) has its columns."""
        from irlc.runtime.interpreter import Interpreter

        _, first = self.program_text(self.decls, self.imports, body)
        code, messages = self.compile(self.decls, self.imports, body, shown or body, first)
        if code is None:
            return Entry(messages, 1)
        out: list[str] = []
        controller = self.controller if self.cell is None else self.cell.controller
        t0, q0, motions = self.time, self._joints_by_name(), controller.motions
        if self.cell is not None:
            self.cell.prepare(code)
        else:
            self.controller.restart_cycle_budget()  # each entry has the whole cycle budget
            # an obstacle the arm is inside (a collision failed the last entry) may be left
            self.controller.collisions.tolerate(self.controller.recorder.last_clearances())
            self.controller.naming = JointNaming.for_model(self.model, code.joint_names)
        result = Interpreter(code, controller, state=self.state, output=out.append).run(check=False)
        self.state, self.last_code = result.state, code
        _drop_temporaries(self.state)
        lines = messages + list(out)
        if result.error is not None:
            lines.append(self.pos.run_error(result.error, first, shown or body))
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
        now = self._joints_by_name()
        moved = [k for k, (n, q) in enumerate(now.items()) if not np.array_equal(q, q0.get(n))]
        if self.cell is not None and (self.time > t0 or moved):
            lines.append(f"→ t = {self.time:.3f} s")
            for k in moved:
                lines += cell_where_lines(self._view(k))
        elif self.time > t0 or moved:
            lines += self.where(short=True)
        elif controller.motions > motions:
            lines.append(f"→ already there (t = {self.time:.3f} s)")
        return Entry(lines)

    # ------------------------------------------------------------------ meta-commands

    def meta(self, text: str) -> Entry:
        name, _, arg = text[1:].partition(" ")
        arg = arg.strip()
        handlers: dict[str, Callable[[str], Entry]] = {
            "where": self._meta_where,
            "robot": self._meta_robot,
            "limits": lambda a: self._per_robot(a, limits_lines),
            "options": lambda a: self._per_robot(a, options_lines),
            "trace": lambda a: repl_files.trace(self.pos, self.cwd, a, self.run_result),
            "plot": lambda a: repl_files.plot(self.pos, self.cwd, a, self.run_result),
            "teach": lambda a: repl_files.teach(self.pos, self.cwd, a, self.names, self._view(),
                                                self.cell is not None),
            "program": lambda a: Entry(self.program_text(self.decls, self.imports,
                                                        "\n".join(self.history))[0].splitlines()),
            "reset": lambda a: self.reset(),
            "help": lambda a: Entry(META_HELP.splitlines()),
        }  # fmt: skip
        handler = handlers.get(name.lower())
        if handler is None:
            known = " ".join(":" + k for k in [*handlers, "quit"])
            return Entry([self.pos.located(f"unknown command :{name}; known: {known}")], 1)
        try:
            return handler(arg)
        except OSError as e:  # a file it could not write or read: named, without the errno
            what = f"{e.filename}: {e.strerror}" if e.filename and e.strerror else str(e)
            return Entry([self.pos.located(f"cannot use {what}")], 3)
        except Exception as e:  # a meta-command must not end the session
            return Entry([self.pos.located(str(e))], 3)

    def _program_units(self, q_si: np.ndarray) -> list[float]:
        return [float(v) for v in units.joints_from_si(q_si, self.model.joint_kinds)]

    def naming(self) -> JointNaming:
        """Program names (the session's MAIN_JOINT names, default ``a1 … aN``) beside the
        robot file's (:mod:`irlc.runtime.model.naming`)."""
        code = self.last_code
        return JointNaming.for_model(self.model, code.joint_names if code is not None else None)

    def joint_names(self) -> tuple[str, ...]:
        return self.naming().program

    # ------------------------------------------------------------------ the robots

    def robot_names(self) -> list[str]:
        return [self.robot_var] if self.cell is None else self.cell.names

    def _robot_index(self, name: str) -> int | None:
        """The session's robot called ``name`` (any case), else ``None``."""
        found = [k for k, n in enumerate(self.robot_names()) if n.lower() == name.lower()]
        return found[0] if found else None

    def _unknown_robot(self, name: str) -> Entry:
        robots = ", ".join(self.robot_names())
        message = f"unknown robot '{name}'; the session's robots: {robots}"
        return Entry([self.pos.located(message)], 1)

    def _view(self, k: int | None = None) -> RobotView:
        """Robot ``k`` (default: the current one) as the meta-commands show it."""
        k = self.current if k is None else k
        if self.cell is not None:
            return self.cell.view(k, self.state)
        pose = self.controller.pose(self.state.settings)
        return RobotView(self.robot_var, self.model, self.controller.q.copy(), self.naming(),
                         self.state.options, self.state.settings, pose)  # fmt: skip

    def _per_robot(self, arg: str, lines: Callable[[RobotView], list[str]]) -> Entry:
        """``:limits [NAME]``, ``:options [NAME]``: of the named robot or the current one;
        in a cell under a line naming it."""
        k = self.current if not arg else self._robot_index(arg)
        if k is None:
            return self._unknown_robot(arg)
        view = self._view(k)
        head = [] if self.cell is None else [f"robot {view.name} ({view.model.name}):"]
        return Entry(head + lines(view))

    def where(self, short: bool = False) -> list[str]:
        return where_lines(self._view(0), self.controller.time, short)

    def limits(self) -> list[str]:
        return limits_lines(self._view())

    def options(self) -> list[str]:
        return options_lines(self._view())

    def _meta_where(self, arg: str) -> Entry:
        """``:where`` (a cell: every robot), ``:where NAME`` (that robot)."""
        k = None if not arg else self._robot_index(arg)
        if arg and k is None:
            return self._unknown_robot(arg)
        if self.cell is None:
            return Entry(self.where())
        if k is not None:
            view = self._view(k)
            head, joints = cell_where_lines(view, indent="")
            return Entry([f"t = {self.time:.3f} s  {head}", joints, *names_line(view)])
        lines = [f"t = {self.time:.3f} s"]
        for j in range(len(self.cell.names)):
            lines += cell_where_lines(self._view(j))
        return Entry(lines)

    def _meta_robot(self, arg: str) -> Entry:
        if arg:
            k = self._robot_index(arg)
            if k is not None:
                self.current = k
                return Entry([f"current robot: {self.robot_names()[k]}", *self._robot_lines()])
            if self.cell is not None:
                return self._unknown_robot(arg)
            # the robot is loaded first: one that cannot be keeps the session as it is
            from irlc.robots import load_robot

            load_robot(arg)
            self.__init__(arg, self.datalist_path, self.cwd, self.allow_any_path)
            return Entry([f"robot {self.model.name}: a new session (declarations cleared)"])
        return Entry(self._robot_lines())

    def prompt(self) -> str:
        """The terminal's prompt: the robot's name (a cell: the current robot's)."""
        return self.model.name if self.cell is None else self.cell.names[self.current]

    def banner(self) -> list[str]:
        """What an interactive session starts with."""
        if self.cell is None:
            head = f"irlc repl on {self.model.name} ({self.model.n} joints). :help for help."
            return [head, *(line.strip() for line in names_line(self._view()))]
        return [f"irlc repl on a cell of {len(self.cell.names)} robots. :help for help.",
                *self.cell.lines(self.current)]  # fmt: skip

    def _robot_lines(self) -> list[str]:
        lines = robot_lines(self._view())
        return lines if self.cell is None else lines + self.cell.lines(self.current)

    # ------------------------------------------------------------------ files

    def run_result(self):
        """The session so far as a RunResult (for traces and plots)."""
        from irlc.runtime.control.executor import ExecutionOptions
        from irlc.runtime.interpreter import ExecutionResult
        from irlc.runtime.outputs.results import RunData, assemble
        from irlc.runtime.outputs.samples import Samples

        if self.last_code is None:
            _, self.last_code = None, self.compile([], [], "", "", 1)[0]
        if self.cell is not None:
            return self.cell.run_result(self.last_code, self.state)
        s = self.state
        execution = ExecutionResult("ok", list(s.output), list(s.events), list(s.warnings),
                                    None, s, 0)  # fmt: skip
        samples = Samples.of(self.controller.recorder.arrays())
        run = assemble(RunData(self.last_code, self.model, self.controller, execution,
                               ExecutionOptions(), samples))  # fmt: skip
        for row in run.report["statements"]:  # entries have no source file (a repl.irl
            row["statement"] = row["kind"]  # in the folder is not the session's)
        return run

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
    for word, start in block_words(text):
        if word in BLOCKS:
            stack.append((word, text.count("\n", 0, start) + 1))
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


def _drop_temporaries(state) -> None:
    """Forget the entry's compiler temporaries (``$for12``, ``$case3`` globals).

    The main body's temporaries are globals numbered after the declared ones; the next
    entry's code does not have them, so they must not stay in the session state."""
    keep = len(state.global_slots)
    while keep and state.global_slots[keep - 1].name.startswith("$"):
        keep -= 1
    del state.global_slots[keep:]
    del state.globals[keep:]


def _line_count(texts: list[str]) -> int:
    """The lines ``texts`` take, one or more each."""
    return sum(t.count("\n") + 1 for t in texts)


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
            text = prompt.prompt(f"{session.prompt()}> ")
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
    robot: str | Sequence[str] | None = None,
    datalist_path=(),
    plain: bool = False,
    allow_any_path: bool = False,
) -> int:
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
        for line in session.banner():
            echo(line)
        return run_terminal(session, echo)
    for line in session.banner()[1:]:  # piped: only a warning of the start, if any
        if line.lstrip().startswith("warning:"):
            echo(line.strip())
    return run_plain(session, sys.stdin, echo)
