"""The ``.ird`` text → IRDATA code (the assembler, ``docs/irdata.md``): every malformed
record is a diagnostic with its line and column; table indices, jump targets and words are
checked, so a hand-written file fails here rather than at run time."""

from __future__ import annotations

import re
from dataclasses import replace

from irlc.lang import platform
from irlc.lang.diagnostics import CompileError, Diagnostic, Span
from irlc.lang.irdata_checks import (
    TypeTable,
    const_problem,
    obstacle_problem,
    shown_word,
    timeline_problem,
)
from irlc.lang.irdata_model import (
    FORMAT_VERSION,
    MAGIC,
    MODAL_OPTIONS,
    MOVE_KINDS,
    OPCODES,
    SYSTEM_VARIABLES,
    Code,
    Instruction,
    ObstacleDef,
    Operand,
    RecordType,
    Routine,
    Slot,
    Target,
    Value,
)
from irlc.lang.irdata_robot_records import RobotRecords
from irlc.lang.irdata_robots import (
    cooperate_problem,
    instruction_problems,
    move_parts,
    robot_operand,
)
from irlc.lang.value_ranges import parse_integer, string_too_long

MAX_ERRORS = 20  # errors shown of one file
_DECIMAL = re.compile(r"[+-]?[0-9]+")
# The escaped form E'…' of a string holding a line break (irdata_writer._quote).
_UNESCAPE = re.compile(r"\\(\\|u[0-9a-f]{4})")
_TOKEN = re.compile(r"E?'(?:[^']|'')*'|[^\s']+")


class _Reader:
    def __init__(self, text: str, filename: str):
        self.text = text
        self.file = filename
        self.diags: list[Diagnostic] = []
        self.more = 0  # errors beyond MAX_ERRORS (counted, not shown)
        self.bad_routine = False  # a malformed ROUTINE record: "no MAIN routine" would be noise
        # (what, item, line, column) of header records checked once the header is read
        # (types refer to TYPE records; joint tuples to the ROBOT record's joint count)
        self.later: list[tuple[str, object, int, int]] = []
        self.types = TypeTable({})
        self.robots = RobotRecords(filename, self.error)

    def error(self, line: int, col: int, msg: str, hint: str | None = None) -> None:
        if len(self.diags) >= MAX_ERRORS:
            self.more += 1  # a damaged file repeats its error on every record: shown once
            return
        self.diags.append(Diagnostic("error", msg, self.file, Span(line, col), hint))

    def failure(self) -> CompileError:
        """The errors found, the first :data:`MAX_ERRORS` of them with a count of the rest."""
        if self.more:
            note = f"{self.more} more error(s) in {self.file} not shown"
            self.diags[-1] = replace(self.diags[-1], notes=(*self.diags[-1].notes, note))
        return CompileError(self.diags)

    def index(self, word: str, col: int, lineno: int, op: str) -> int | None:
        """A table index operand (a non-negative integer), or ``None`` after an error."""
        if re.fullmatch(r"[0-9]+", word):
            value = parse_integer(word)
            if isinstance(value, int):
                return value
            self.error(lineno, col, f"{op}: {value}")
            return None
        self.error(lineno, col, f"{op}: expected an index, got {shown_word(word)}")
        return None

    def tokens(self, line_text: str) -> list[tuple[str, int]]:
        out = []
        for m in _TOKEN.finditer(line_text):
            if m.group().startswith(";"):
                break
            out.append((m.group(), m.start() + 1))
        return out


def _parse_number(tok: str) -> float | int | None:
    """An integer inside the 64-bit range, else a finite float, else ``None``."""
    if _DECIMAL.fullmatch(tok) and isinstance(value := parse_integer(tok), int):
        return value
    try:
        v = float(tok)
    except ValueError:
        return None
    return v if v == v and v not in (float("inf"), float("-inf")) else None


def _decimal_after(tok: str, prefix: str) -> int | None:
    """``<prefix><digits>`` (a record or line number): the number, ``None`` if malformed or
    outside the 64-bit range (``@1.5``, ``@-0.0``, ``@4.9e-324``, ``L²`` are malformed)."""
    if not tok.startswith(prefix) or not re.fullmatch(r"[0-9]+", tok[len(prefix) :]):
        return None
    value = parse_integer(tok[len(prefix) :])
    return value if isinstance(value, int) else None


def _record_number(tok: str) -> int | None:
    """A jump target or routine entry ``@<record>``; ``None`` if malformed."""
    return _decimal_after(tok, "@")


def _parse_bool(tok: str) -> bool | None:
    return {"TRUE": True, "FALSE": False}.get(tok.upper())


def _unquote(tok: str) -> str | None:
    """The text of ``'…'`` or of the escaped form ``E'…'``; ``None`` if ``tok`` is neither."""
    if len(tok) >= 3 and tok[0] == "E" and tok[1] == tok[-1] == "'":
        body = _UNESCAPE.sub(_unescape, tok[2:-1])
        return body.replace("''", "'")
    if len(tok) >= 2 and tok[0] == tok[-1] == "'":
        return tok[1:-1].replace("''", "'")
    return None


def _unescape(m: re.Match) -> str:
    code = m.group(1)
    return "\\" if code == "\\" else chr(int(code[1:], 16))


def read_code(text: str, filename: str = "<irdata>") -> Code:
    """Parse IRDATA text; raise :class:`CompileError` with positioned diagnostics."""
    r = _Reader(text, filename)
    lines = text.splitlines()
    if not lines or lines[0].strip() != MAGIC:
        got = shown_word(lines[0].strip()) if lines else "an empty file"
        r.error(1, 1, f"not IRDATA code of version {FORMAT_VERSION}: expected '{MAGIC}', got {got}")
        raise r.failure()
    code = Code("", "", "", "", "", ())
    records: list[tuple[int, list[tuple[str, int]]]] = []  # (file line, tokens)
    expected = 1
    for lineno, raw in enumerate(lines[1:], start=2):
        if not raw.strip() or raw.lstrip().startswith(";"):
            continue
        toks = r.tokens(raw)
        if not toks:
            continue
        num = _parse_number(toks[0][0])
        if not isinstance(num, int) or num != expected:
            got = shown_word(toks[0][0])
            r.error(lineno, toks[0][1], f"expected record number {expected}, got {got}")
            raise r.failure()
        expected += 1
        records.append((lineno, toks[1:]))
    # header
    k = 0
    pending_entries: list[tuple[Routine, int, int, int]] = []  # routine, recno, line, col
    while k < len(records):
        lineno, toks = records[k]
        k += 1
        if not toks:
            r.error(lineno, 1, "empty record")
            continue
        op, col = toks[0]
        if op == "CODE":
            break
        _read_header_record(r, code, op, toks, lineno, pending_entries)
    else:
        r.error(len(lines), 1, "missing CODE record")
        raise r.failure()
    _check_header(r, code)
    first_code_recno = k + 1
    jump_fixups: list[tuple[int, int, int, int, int]] = []
    for idx, (lineno, toks) in enumerate(records[k:]):
        ins = _read_instruction(r, toks, lineno, idx, jump_fixups)
        code.code.append(ins if ins is not None else _BAD_INSTRUCTION)  # keeps indices = records
    ncode = len(code.code)
    for ins_idx, arg_idx, rec, lineno, col in jump_fixups:
        target = rec - first_code_recno
        if not 0 <= target < ncode:
            r.error(lineno, col, f"jump target @{rec} is not an instruction record")
            continue
        ins = code.code[ins_idx]
        args = list(ins.args)
        args[arg_idx] = Target(target)
        code.code[ins_idx] = Instruction(ins.op, tuple(args), ins.line)
    for routine, rec, lineno, col in pending_entries:
        target = rec - first_code_recno
        if not 0 <= target < ncode:
            r.error(lineno, col, f"routine entry @{rec} is not an instruction record")
        routine.entry = target
    _check_references(r, code, records[k:])
    if r.diags:
        raise r.failure()
    return code


def _read_header_record(r: _Reader, code: Code, op, toks, lineno, pending) -> None:
    words = [t for t, _ in toks]
    col_of = [c for _, c in toks]

    def need(n: int) -> bool:
        if len(words) < n:
            r.error(lineno, col_of[-1], f"{op}: expected at least {n - 1} operands")
            return False
        return True

    if op == "PROGRAM" and need(2):
        code.program = words[1]
    elif op == "SOURCE" and need(2):
        code.source = _file_name(r, words[1], lineno, col_of[1], op)
    elif op == "ROBOT" and need(5):
        r.robots.robot(words, col_of, lineno, _file_name(r, words[2], lineno, col_of[2], op))
    elif op == "JOINTS":
        r.robots.joints(words, col_of, lineno)
    elif op == "UNITS":
        if words[1:] != ["mm", "deg", "s"]:
            r.error(lineno, col_of[0], "UNITS: only 'mm deg s' is supported")
    elif op == "DATALIST" and need(3):
        code.datalists.append((words[1], _file_name(r, words[2], lineno, col_of[2], op)))
    elif op == "CONST":
        v = _read_const(r, len(code.consts), words, col_of, lineno) if need(3) else None
        code.consts.append(v if v is not None else _BAD_VALUE)  # later indices stay right
        if v is not None:
            r.later.append(("const", v, lineno, col_of[2]))
    elif op == "OBSTACLE" and need(3):
        fields: list[tuple[str, tuple[float, ...]]] = []
        key, vals = None, []
        for t, c in zip(words[3:], col_of[3:], strict=True):
            num = _parse_number(t)
            if num is None:
                if key is not None:
                    fields.append((key, tuple(float(v) for v in vals)))
                key, vals = t, []
            elif key is None:
                r.error(lineno, c, "OBSTACLE: a number before any key")
            else:
                vals.append(num)
        if key is not None:
            fields.append((key, tuple(float(v) for v in vals)))
        obstacle = ObstacleDef(words[1], words[2], tuple(fields))
        if problem := obstacle_problem(obstacle):
            r.error(lineno, col_of[2], f"OBSTACLE {shown_word(words[1])}: {problem}")
        code.obstacles.append(obstacle)
    elif op == "INPUT" and need(2):
        events = []
        rest = words[2:]
        if len(rest) % 2:
            r.error(lineno, col_of[-1], "INPUT: expected pairs of time and TRUE/FALSE")
        for t, v in zip(rest[::2], rest[1::2], strict=False):
            tv, bv = _parse_number(t), _parse_bool(v)
            if tv is None or bv is None:
                r.error(lineno, col_of[0], f"INPUT: bad event {shown_word(t)} {shown_word(v)}")
                continue
            events.append((float(tv), bv))
        if problem := timeline_problem(events):
            r.error(lineno, col_of[0], f"INPUT: {problem}")
        signal = r.index(words[1], col_of[1], lineno, op)
        if signal is not None:
            code.inputs[signal] = events
    elif op == "TYPE" and need(3):
        _read_type(r, code, words, col_of, lineno)
    elif op == "GLOBAL":
        index = r.index(words[1], col_of[1], lineno, op) if need(4) else None
        if index is not None and index != len(code.globals):
            r.error(lineno, col_of[1], f"GLOBAL: expected index {len(code.globals)}, got {index}")
        slot = Slot(index, words[2], words[3]) if index is not None else _BAD_SLOT
        code.globals.append(slot)  # a placeholder keeps later indices right
        if index is not None:
            r.later.append(("slot", words[2], lineno, col_of[2]))
    elif op == "ROUTINE":
        index = r.index(words[1], col_of[1], lineno, op) if need(7) else None
        if index is None:
            r.bad_routine = True
            code.routines.append(Routine(len(code.routines), "?", "?", -1))
            return
        if index != len(code.routines):
            r.error(lineno, col_of[1], f"ROUTINE: expected index {len(code.routines)}, got {index}")
        routine = Routine(index, words[2], words[3], -1)
        code.routines.append(routine)
        if words[3].startswith("FUNC:"):
            r.later.append(("result", words[3][5:], lineno, col_of[3]))
        elif words[3] not in ("MAIN", "PROC"):
            r.error(
                lineno,
                col_of[3],
                f"ROUTINE: expected MAIN, PROC or FUNC:TYPE, got {shown_word(words[3])}",
            )
        counts = [r.index(w, c, lineno, op) for w, c in zip(words[4:6], col_of[4:6], strict=True)]
        r.later.append(("routine", (routine, counts), lineno, col_of[4]))
        rec = words[6]
        entry = _record_number(rec)
        if entry is None:
            r.error(lineno, col_of[6], f"ROUTINE: expected an entry @record, got {shown_word(rec)}")
        else:
            pending.append((routine, entry, lineno, col_of[6]))
    elif op in ("PARAM", "LOCAL") and need(5):
        routine = next((x for x in code.routines if x.index == _parse_number(words[1])), None)
        if routine is None:
            r.error(lineno, col_of[1], f"{op}: unknown routine {shown_word(words[1])}")
            return
        by_ref = words[3] == "VAR"
        rest = words[4:] if by_ref else words[3:]
        index = r.index(words[2], col_of[2], lineno, op)
        if index is None:
            return
        slot = Slot(index, rest[0], rest[1] if len(rest) > 1 else "?", by_ref)
        (routine.params if op == "PARAM" else routine.locals).append(slot)
        r.later.append(("slot", rest[0], lineno, col_of[4] if by_ref else col_of[3]))
    elif op not in ("PROGRAM", "SOURCE", "ROBOT", "DATALIST", "CONST", "OBSTACLE", "INPUT",
                    "TYPE", "GLOBAL", "ROUTINE", "PARAM", "LOCAL"):  # fmt: skip
        r.error(lineno, col_of[0], f"unknown header record {shown_word(op)}")


def _file_name(r: _Reader, word: str, lineno: int, col: int, op: str) -> str:
    """A file or robot name operand (quoted or a bare word); a NUL character or a name no
    file system takes (over 4,096 characters, a part over 255) is an error."""
    name = _unquote(word) or word
    if "\x00" in name:
        r.error(lineno, col, f"{op}: a file name cannot hold a NUL character")
    elif len(name) > 4096 or any(len(part) > 255 for part in re.split(r"[/\\]", name)):
        r.error(
            lineno, col, f"{op}: a file name too long for a file system ({len(name)} characters)"
        )
    return name


def _read_type(r: _Reader, code: Code, words, cols, lineno) -> None:
    """``TYPE k RECORD name:TYPE …``: ``k`` the next index, each field ``name:TYPE``."""
    index = r.index(words[1], cols[1], lineno, "TYPE")
    if index is not None and index != len(code.types):
        r.error(lineno, cols[1], f"TYPE: expected index {len(code.types)}, got {index}")
    if words[2] != "RECORD":
        r.error(lineno, cols[2], f"TYPE: expected RECORD, got {shown_word(words[2])}")
    fields = []
    for w, c in zip(words[3:], cols[3:], strict=True):
        name, _, ty = w.partition(":")
        if not name or not ty:
            r.error(lineno, c, f"TYPE: expected a field 'name:TYPE', got {shown_word(w)}")
            continue
        fields.append((name, ty))
        r.later.append(("field", ty, lineno, c))
    code.types.append(RecordType(len(code.types), tuple(fields)))


def _check_header(r: _Reader, code: Code) -> None:
    """The checks of :mod:`irlc.lang.irdata_checks` on the records kept in ``r.later``;
    the robots (:mod:`irlc.lang.irdata_robot_records`)."""
    r.robots.install(code)
    types = r.types = TypeTable({t.index: t.fields for t in code.types})
    for what, item, lineno, col in r.later:
        problem = None
        if what in ("slot", "field", "result"):
            problem = types.problem(item, signal=what == "slot")  # type: ignore[arg-type]
        elif what == "const":
            problem = const_problem(item, r.robots.joint_counts)  # type: ignore[arg-type]
        elif what == "routine":
            problem = _slot_problem(*item)  # type: ignore[misc]
        if problem:
            r.error(lineno, col, problem)


def _slot_problem(routine: Routine, counts: list[int | None]) -> str | None:
    """The PARAM and LOCAL records of ``routine`` number its slots 0, 1, … (parameters
    first) and match the counts of its ROUTINE record."""
    slots = [s.index for s in routine.params + routine.locals]
    if slots != list(range(len(slots))):
        return f"the PARAM and LOCAL records of routine {routine.index} do not number 0..n-1"
    found = [len(routine.params), len(routine.locals)]
    if None not in counts and counts != found:
        return (
            f"routine {routine.index} declares {counts[0]} parameter(s) and {counts[1]} "
            f"local(s); its PARAM and LOCAL records give {found[0]} and {found[1]}"
        )
    return None


_BAD_VALUE = Value("<bad>", ())  # placeholders of malformed records (the read fails anyway)
_BAD_SLOT = Slot(-1, "<bad>", "<bad>")
_BAD_INSTRUCTION = Instruction("<bad>", (), 0)


def _read_const(r: _Reader, expected: int, words, cols, lineno) -> Value | None:
    """``CONST k <value>``: ``k`` must be the next index."""
    index = r.index(words[1], cols[1], lineno, "CONST")
    if index is not None and index != expected:
        r.error(lineno, cols[1], f"CONST: expected index {expected}, got {index}")
    return _read_value(r, words[2:], cols[2:], lineno)


def _read_value(r: _Reader, words, cols, lineno) -> Value | None:
    ty, rest = words[0], words[1:]
    word = re.fullmatch(r"[A-Z_]{1,32}(#[0-9]{1,9})?", ty) or platform.constant_count(ty)
    if not word:  # echoed below: a type word only (or a platform target's ARRAY)
        r.error(lineno, cols[0], f"CONST: expected a type, got {shown_word(ty)}")
        return None
    if ty in ("STRING", "CHAR"):
        s = _unquote(rest[0]) if rest else None
        if s is None:
            r.error(lineno, cols[0], f"{ty}: expected a quoted string")
            return None
        if too_long := string_too_long(len(s)):
            r.error(lineno, cols[1], f"{ty}: {too_long}")
            return None
        return Value(ty, (s,))
    if ty == "BOOLEAN":
        b = _parse_bool(rest[0]) if rest else None
        if b is None:
            r.error(lineno, cols[0], "BOOLEAN: expected TRUE or FALSE")
            return None
        return Value(ty, (b,))
    if ty == "INTEGER" and len(rest) == 1 and _DECIMAL.fullmatch(rest[0]):
        value = parse_integer(rest[0])
        if isinstance(value, str):
            r.error(lineno, cols[1], f"INTEGER: {value}")
            return None
        return Value(ty, (value,))
    nums = [_parse_number(t) for t in rest]
    if any(n is None for n in nums):
        r.error(lineno, cols[0], f"{ty}: expected numbers")
        return None
    if ty == "INTEGER":
        r.error(lineno, cols[0], "INTEGER: expected one integer")
        return None
    if not nums:
        r.error(lineno, cols[0], f"{ty}: expected numbers")
        return None
    return Value(ty, tuple(float(n) for n in nums))  # type: ignore[arg-type]


def _read_instruction(r: _Reader, toks, lineno, idx, fixups) -> Instruction | None:
    line = _decimal_after(toks[0][0], "L") if toks else None
    if len(toks) < 2 or line is None:
        r.error(lineno, toks[0][1] if toks else 1, "expected a source line 'L<n>' and an opcode")
        return None
    op, col = toks[1]
    sig = OPCODES.get(op)
    if sig is None:
        r.error(lineno, col, f"unknown opcode {shown_word(op)}")
        return None
    operands = toks[2:]
    args: list[Operand] = []
    fixed = sig.rstrip("*")
    variadic = sig.endswith("*")
    if len(operands) < len(fixed) or (not variadic and len(operands) > len(fixed)):
        r.error(lineno, col, f"{op}: expected {len(fixed)} operand(s), got {len(operands)}")
        return None
    for k, (tok, c) in enumerate(operands):
        kind = fixed[k] if k < len(fixed) else "*"
        if kind == "t":
            rec = _record_number(tok)
            if rec is None:
                got = shown_word(tok)
                r.error(lineno, c, f"{op}: expected a jump target '@<record>', got {got}")
                return None
            fixups.append((idx, k, rec, lineno, c))
            args.append(Target(-1))
        elif kind == "i" or (kind == "*" and re.fullmatch(r"-?[0-9]+", tok)):
            if not re.fullmatch(r"-?[0-9]+", tok):
                r.error(lineno, c, f"{op}: expected an integer, got {shown_word(tok)}")
                return None
            value = parse_integer(tok)
            if isinstance(value, str):
                r.error(lineno, c, f"{op}: {value}")
                return None
            args.append(value)
        else:
            args.append(tok)
    return Instruction(op, tuple(args), line)


def _option_problem(ins: Instruction, code: Code) -> str | None:
    """The operands of ``OPTON``/``OPTOFF OPTION [ROBOT:k] …``: one obstacle name for
    OBSTACLE, joint numbers 1..N of the robot for ``OPTON FREEZE``, the two robots of
    COOPERATE, none otherwise."""
    robot, operands = robot_operand(ins.op, ins.args)
    option, rest = operands[0], operands[1:]
    if option == "COOPERATE":
        return cooperate_problem(ins.op, robot, rest, len(code.robots))
    if option == "OBSTACLE":
        return None if len(rest) == 1 else f"expected one obstacle name, got {len(rest)} operands"
    if option == "FREEZE" and ins.op == "OPTON":
        robots = code.robots
        n = (
            robots[robot].joint_count
            if robot is not None and robot < len(robots)
            else code.joint_count
        )
        if rest and all(isinstance(j, int) and 1 <= j <= n for j in rest):
            return None
        return f"expected joint numbers in 1..{n}"
    return f"expected no operands, got {len(rest)}" if rest else None


def _robot_problems(r: _Reader, ins: Instruction, code: Code, lineno: int, toks) -> bool:
    """The robot operands of ``ins`` (lang/irdata_robots.py), each at its operand's column;
    whether there was none."""
    problems = instruction_problems(ins.op, ins.args, len(code.robots))
    for index, message in problems:
        r.error(lineno, toks[2 + index][1] if index >= 0 else toks[1][1], message)
    return not problems


def _check_references(r: _Reader, code: Code, code_records) -> None:
    """Operands that index tables must be in range (a malformed .ird fails here, not later)."""
    tables = {
        "PUSHC": len(code.consts),
        "PUSHG": len(code.globals),
        "POPG": len(code.globals),
        "REFG": len(code.globals),
        "SIGOUT": len(code.globals),
        "CALL": len(code.routines),
    }
    for ins, (lineno, toks) in zip(code.code, code_records, strict=True):
        limit = tables.get(ins.op)
        if limit is not None and not 0 <= int(ins.args[0]) < limit:
            r.error(
                lineno, toks[2][1], f"{ins.op}: index {ins.args[0]} out of range (0..{limit - 1})"
            )
        if ins.op in ("PUSHSYS", "POPSYS") and ins.args[0] not in SYSTEM_VARIABLES:
            r.error(lineno, toks[2][1], f"unknown system variable {shown_word(ins.args[0])}")
        if ins.op == "MAKE" and (problem := r.types.problem(str(ins.args[0]))):
            r.error(lineno, toks[2][1], f"MAKE: {problem}")
        robots_ok = _robot_problems(r, ins, code, lineno, toks)
        if ins.op == "MOVE":
            for part in move_parts(ins.args)[0]:
                if part.kind not in MOVE_KINDS:
                    col = toks[2 + part.start][1]
                    r.error(lineno, col, f"unknown motion kind {shown_word(part.kind)}")
        if ins.op in ("OPTON", "OPTOFF") and ins.args[0] not in MODAL_OPTIONS:
            r.error(lineno, toks[2][1], f"unknown modal option {shown_word(ins.args[0])}")
        elif (
            ins.op in ("OPTON", "OPTOFF") and robots_ok and (problem := _option_problem(ins, code))
        ):
            r.error(lineno, toks[2][1], f"{ins.op} {ins.args[0]}: {problem}")
    if not r.bad_routine and not any(rt.kind == "MAIN" for rt in code.routines):
        r.error(1, 1, "no MAIN routine")
