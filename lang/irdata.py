"""IRDATA code: the in-memory model, the writer and the reader (assembler).

The format is documented in ``docs/irdata.md``. ``write_code(read_code(text)) == text``
for every text the writer produced (byte-identical round trip).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from irlc.lang.diagnostics import CompileError, Diagnostic, Span
from irlc.lang.settings import ALL_KINDS
from irlc.lang.settings import SYSTEM_VARIABLES as _SYSTEM_VARIABLES

FORMAT_VERSION = 1
MAGIC = f"IRDATA {FORMAT_VERSION}"

JOINT_TUPLE_TYPES = (
    "MAIN_JOINT",
    "MAIN_JOINT_MIN",
    "MAIN_JOINT_MAX",
    "MAIN_JOINT_SPEED_MIN",
    "MAIN_JOINT_SPEED_MAX",
    "MAIN_JOINT_ACCEL_MIN",
    "MAIN_JOINT_ACCEL_MAX",
)
SYSTEM_VARIABLES = tuple(_SYSTEM_VARIABLES)  # names; their rows: lang/settings.py
MOVE_KINDS = ALL_KINDS
MODAL_OPTIONS = ("JOINTLIMIT", "JOINTSPEEDLIMIT", "JOINTACCELLIMIT", "CYCLIC", "OBSTACLE", "FREEZE")
# The OBSTACLE record's keys per kind, in record order: (key, number count, required).
# The data-list loader and the runtime both validate against this one table.
OBSTACLE_KEYS: dict[str, tuple[tuple[str, int, bool], ...]] = {
    "point": (("center", 3, True),),
    "sphere": (("center", 3, True), ("radius", 1, True)),
    "box": (("center", 3, True), ("size", 3, True), ("rotation", 3, False)),
    "capsule": (("a", 3, True), ("b", 3, True), ("radius", 1, True)),
    "plane": (("point", 3, True), ("normal", 3, True)),
}
OBSTACLE_KINDS = tuple(OBSTACLE_KEYS)
# The physical range of obstacle geometry (mm): coordinates within ±1 km of the world origin,
# lengths (radius, box size) from 1 µm to 1 km. Far outside it a distance (a clearance in the
# trace) or a squared length overflows a float.
GEOMETRY_MAX_MM = 1e6
GEOMETRY_MIN_LENGTH_MM = 1e-3
_OBSTACLE_LENGTHS = ("radius", "size")
_OBSTACLE_POINTS = ("center", "a", "b", "point")


def geometry_problem(what: str, values, unit: str = "mm", unit_mm: float = 1.0) -> str | None:
    """Why one of ``values`` (finite numbers in ``unit``, one ``unit`` being ``unit_mm`` mm)
    is outside the physical range of geometry, else ``None``: ``what = "point"`` is a
    coordinate, within ``±GEOMETRY_MAX_MM``; ``what = "length"`` (a radius, a size, a link
    length) lies in ``[GEOMETRY_MIN_LENGTH_MM, GEOMETRY_MAX_MM]``. The one rule for
    obstacles (data lists, the runtime) and robot geometry (robot files, URDF)."""
    top, low = GEOMETRY_MAX_MM / unit_mm, GEOMETRY_MIN_LENGTH_MM / unit_mm
    for v in values:
        if what == "length" and not low <= v <= top:
            return (
                f"{v:g} {unit} is outside the physical range of a length "
                f"({low:g} to {top:g} {unit})"
            )
        if what == "point" and not abs(v) <= top:
            return (
                f"{v:g} {unit} is outside the physical range of a coordinate "
                f"(within ±{top:g} {unit})"
            )
    return None


def obstacle_range_problem(key: str, nums: tuple[float, ...]) -> str | None:
    """Why an obstacle field's numbers (mm; finite, positive where required) are outside
    the physical range (:func:`geometry_problem`), or ``None``."""
    if key in _OBSTACLE_LENGTHS:
        return geometry_problem("length", nums)
    if key in _OBSTACLE_POINTS:
        return geometry_problem("point", nums)
    return None


def obstacle_field_problem(key: str, nums: tuple[float, ...]) -> str | None:
    """Why an obstacle field's finite numbers (mm) are not valid, or ``None``: box sizes
    must be positive, a plane normal must not be zero, and every field lies in the physical
    range (:func:`obstacle_range_problem`). The one rule for the data-list loader and the
    runtime, so a hand-written ``.ird`` cannot pass what a data list would reject (each
    reader checks that a radius is a positive number while reading it)."""
    if key == "size" and min(nums) <= 0:
        return "box sizes must be positive"
    if key == "normal" and not any(nums):
        return "the plane normal must not be zero"
    return obstacle_range_problem(key, nums)


INT_MIN, INT_MAX = -(2**63), 2**63 - 1  # INTEGER is signed 64-bit, as in the runtime
MAX_STRING = 65_535
"""The most characters a STRING holds: a longer literal, .ird constant or concatenation
result is an error (a loop doubling a string would otherwise fill the memory)."""


def string_too_long(n: int) -> str | None:
    """The words for a STRING of ``n`` characters beyond :data:`MAX_STRING`; else ``None``."""
    if n <= MAX_STRING:
        return None
    return f"a STRING of {n} characters is too long (at most {MAX_STRING})"


def integer_overflow(x: int) -> str | None:
    """The runtime's words for an INTEGER outside ``[INT_MIN, INT_MAX]``; ``None`` if inside."""
    if INT_MIN <= x <= INT_MAX:
        return None
    return f"INTEGER overflow ({x} is outside the 64-bit range)"


_DECIMAL = re.compile(r"[+-]?[0-9]+")
_ECHO_DIGITS = 40  # a longer literal is named by its length in messages, not echoed


def parse_integer(text: str) -> int | str:
    """A decimal integer literal ``[+-]?[0-9]+``: its value, or the overflow message.

    Leading zeros are dropped first and a literal of more than 40 significant digits (far
    outside ``[INT_MIN, INT_MAX]``) is refused before ``int()``, which refuses strings of
    over 4,300 digits; its message names its length instead of echoing it.
    """
    sign = "-" if text.startswith("-") else ""
    digits = text.lstrip("+-").lstrip("0") or "0"
    if len(digits) > _ECHO_DIGITS:
        return f"INTEGER overflow (a {len(digits)}-digit number is outside the 64-bit range)"
    return integer_overflow(value := int(sign + digits)) or value


# Operand signatures: i = integer, w = word, t = jump target, * = any number of int/word.
OPCODES: dict[str, str] = {
    "PUSHC": "i", "PUSHG": "i", "POPG": "i", "PUSHL": "i", "POPL": "i",
    "REFG": "i", "REFL": "i", "PUSHSYS": "w", "POPSYS": "w", "POP": "", "DUP": "",
    "GETF": "w", "SETF": "w", "GETI": "", "SETI": "",
    "ADD": "", "SUB": "", "MUL": "", "DIV": "", "IDIV": "", "MOD": "", "NEG": "", "NOT": "",
    "EQ": "", "NE": "", "LT": "", "GT": "", "LE": "", "GE": "",
    "AND": "", "OR": "", "XOR": "", "COMPOSE": "",
    "MAKE": "wi", "CALLB": "wi", "CALL": "ii", "RET": "", "RETV": "",
    "JMP": "t", "JF": "t", "JT": "t", "HALT": "", "PAUSE": "", "END": "",
    "WAIT": "", "WAITFOR": "t", "PUSHIN": "", "SIGOUT": "i", "WRITE": "i", "WRITELN": "i",
    "OUTSET": "", "PUSHOUT": "", "PULSE": "",
    "MOVE": "wi*", "RECONF": "", "OPTON": "w*", "OPTOFF": "w*",
}  # fmt: skip


@dataclass(frozen=True)
class Target:
    """A jump or entry target: the index of an instruction in ``Code.code``."""

    index: int


Operand = int | str | Target


@dataclass(frozen=True)
class Instruction:
    op: str
    args: tuple[Operand, ...] = ()
    line: int = 0  # source line (0: generated)


@dataclass(frozen=True)
class Value:
    """A constant in program units: ``type`` is an IRDATA type name, ``data`` its fields."""

    type: str
    data: tuple


@dataclass(frozen=True)
class Slot:
    index: int
    type: str
    name: str
    by_ref: bool = False


@dataclass
class Routine:
    index: int
    name: str
    kind: str  # "MAIN" | "PROC" | "FUNC:<TYPE>"
    entry: int  # index into Code.code
    params: list[Slot] = field(default_factory=list)
    locals: list[Slot] = field(default_factory=list)

    @property
    def result_type(self) -> str | None:
        return self.kind[5:] if self.kind.startswith("FUNC:") else None


@dataclass(frozen=True)
class ObstacleDef:
    """An obstacle from a data list: ``fields`` maps key → numbers (mm / deg), in order."""

    name: str
    kind: str
    fields: tuple[tuple[str, tuple[float, ...]], ...]

    def get(self, key: str) -> tuple[float, ...] | None:
        return dict(self.fields).get(key)


@dataclass(frozen=True)
class RecordType:
    index: int
    fields: tuple[tuple[str, str], ...]  # (name, type)


@dataclass
class Code:
    program: str
    source: str
    robot_var: str
    robot: str
    joint_kinds: str  # one letter per joint: R | P
    joint_names: tuple[str, ...]
    datalists: list[tuple[str, str]] = field(default_factory=list)
    consts: list[Value] = field(default_factory=list)
    obstacles: list[ObstacleDef] = field(default_factory=list)
    inputs: dict[int, list[tuple[float, bool]]] = field(default_factory=dict)
    types: list[RecordType] = field(default_factory=list)
    globals: list[Slot] = field(default_factory=list)
    routines: list[Routine] = field(default_factory=list)
    code: list[Instruction] = field(default_factory=list)

    @property
    def joint_count(self) -> int:
        return len(self.joint_kinds)

    def obstacle(self, name: str) -> ObstacleDef | None:
        key = name.lower()
        return next((o for o in self.obstacles if o.name.lower() == key), None)


# --------------------------------------------------------------------------- writer


def _num(v: float | int) -> str:
    if isinstance(v, bool):
        return "TRUE" if v else "FALSE"
    if isinstance(v, int):
        return str(v)
    return repr(float(v))


# The characters str.splitlines() breaks a line at: a string holding one is written in the
# escaped form E'…', where each of them is \uXXXX and a backslash is \\ (docs/irdata.md).
_LINE_BREAKS = "\n\r\x0b\x0c\x1c\x1d\x1e\x85\u2028\u2029"
_NEEDS_ESCAPE = re.compile(f"[{_LINE_BREAKS}]")
_ESCAPED = re.compile(f"[\\\\{_LINE_BREAKS}]")
_UNESCAPE = re.compile(r"\\(\\|u[0-9a-f]{4})")


def _quote(s: str) -> str:
    """``'text'`` (a quote doubled), or ``E'text'`` with escapes when a line break is in it."""
    body = s.replace("'", "''")
    if not _NEEDS_ESCAPE.search(s):
        return "'" + body + "'"
    return "E'" + _ESCAPED.sub(lambda m: _escape(m.group()), body) + "'"


def _escape(ch: str) -> str:
    return "\\\\" if ch == "\\" else f"\\u{ord(ch):04x}"


def format_value(v: Value) -> str:
    if v.type in ("STRING", "CHAR"):
        return f"{v.type} {_quote(v.data[0])}"
    if v.type == "BOOLEAN":
        return f"BOOLEAN {'TRUE' if v.data[0] else 'FALSE'}"
    return " ".join([v.type, *(_num(x) for x in v.data)])


def _short_value(v: Value) -> str:
    text = format_value(v).split(" ", 1)[1] if v.data else ""
    return text if len(text) <= 48 else text[:45] + "..."


def _slot(s: Slot) -> str:
    return f"{'VAR ' if s.by_ref else ''}{s.type} {s.name}"


def _header_records(code: Code, entry_recno) -> list[str]:
    recs = [
        f"PROGRAM {code.program}",
        f"SOURCE {_quote(code.source)}",
        f"ROBOT {code.robot_var} {code.robot if _is_word(code.robot) else _quote(code.robot)} "
        f"{code.joint_count} {code.joint_kinds}",
        "JOINTS " + " ".join(code.joint_names),
        "UNITS mm deg s",
    ]
    recs += [f"DATALIST {name} {_quote(path)}" for name, path in code.datalists]
    recs += [f"CONST {k} {format_value(v)}" for k, v in enumerate(code.consts)]
    for o in code.obstacles:
        parts = [f"OBSTACLE {o.name} {o.kind}"]
        parts += [f"{key} " + " ".join(_num(x) for x in vals) for key, vals in o.fields]
        recs.append(" ".join(parts))
    for n in sorted(code.inputs):
        events = " ".join(f"{_num(float(t))} {'TRUE' if v else 'FALSE'}" for t, v in code.inputs[n])
        recs.append(f"INPUT {n} {events}".rstrip())
    for t in code.types:
        recs.append(f"TYPE {t.index} RECORD " + " ".join(f"{n}:{ty}" for n, ty in t.fields))
    recs += [f"GLOBAL {g.index} {g.type} {g.name}" for g in code.globals]
    for r in code.routines:
        recs.append(
            f"ROUTINE {r.index} {r.name} {r.kind} {len(r.params)} {len(r.locals)} "
            f"@{entry_recno(r.entry)}"
        )
        recs += [f"PARAM {r.index} {p.index} {_slot(p)}" for p in r.params]
        recs += [f"LOCAL {r.index} {s.index} {s.type} {s.name}" for s in r.locals]
    recs.append("CODE")
    return recs


def _is_word(s: str) -> bool:
    return re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", s) is not None


def _comment(code: Code, ins: Instruction, routine: Routine | None) -> str:
    op, a = ins.op, ins.args
    if op in ("PUSHC",) and 0 <= a[0] < len(code.consts):
        return _short_value(code.consts[a[0]])
    if op in ("PUSHG", "POPG", "REFG", "SIGOUT") and 0 <= a[0] < len(code.globals):
        return code.globals[a[0]].name
    if op in ("PUSHL", "POPL", "REFL") and routine is not None:
        slots = routine.params + routine.locals
        if 0 <= a[0] < len(slots):
            return slots[a[0]].name
    if op == "CALL" and 0 <= a[0] < len(code.routines):
        return code.routines[a[0]].name
    return ""


def write_code(code: Code) -> str:
    """Serialise ``code`` to the IRDATA text format (deterministic)."""
    header_len = len(_header_records(code, lambda i: 0))
    first_code_recno = header_len + 1

    def recno(index: int) -> int:
        return first_code_recno + index

    lines = [MAGIC, f"; irlc IRDATA code of program {code.program}"]
    n = 0
    for rec in _header_records(code, recno):
        n += 1
        lines.append(f"{n} {rec}")
    owner = _routine_of_instruction(code)
    for i, ins in enumerate(code.code):
        n += 1
        ops = [_operand(a, recno) for a in ins.args]
        text = " ".join([str(n), f"L{ins.line}", ins.op, *ops])
        comment = _comment(code, ins, owner[i])
        lines.append(f"{text} ; {comment}" if comment else text)
    return "\n".join(lines) + "\n"


def _operand(a: Operand, recno) -> str:
    if isinstance(a, Target):
        return f"@{recno(a.index)}"
    return str(a)


def _routine_of_instruction(code: Code) -> list[Routine | None]:
    """The routine each instruction belongs to (routines are laid out contiguously)."""
    owner: list[Routine | None] = [None] * len(code.code)
    starts = sorted(code.routines, key=lambda r: r.entry)
    for k, r in enumerate(starts):
        end = starts[k + 1].entry if k + 1 < len(starts) else len(code.code)
        for i in range(r.entry, end):
            owner[i] = r
    return owner


# --------------------------------------------------------------------------- reader

_TOKEN = re.compile(r"E?'(?:[^']|'')*'|[^\s']+")


class _Reader:
    def __init__(self, text: str, filename: str):
        self.text = text
        self.file = filename
        self.diags: list[Diagnostic] = []
        self.bad_routine = False  # a malformed ROUTINE record: "no MAIN routine" would be noise

    def error(self, line: int, col: int, msg: str, hint: str | None = None) -> None:
        self.diags.append(Diagnostic("error", msg, self.file, Span(line, col), hint))

    def index(self, word: str, col: int, lineno: int, op: str) -> int | None:
        """A table index operand (a non-negative integer), or ``None`` after an error."""
        if re.fullmatch(r"[0-9]+", word):
            value = parse_integer(word)
            if isinstance(value, int):
                return value
            self.error(lineno, col, f"{op}: {value}")
            return None
        self.error(lineno, col, f"{op}: expected an index, got {word!r}")
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
        got = lines[0].strip() if lines else "an empty file"
        r.error(
            1, 1, f"not IRDATA code of version {FORMAT_VERSION}: expected '{MAGIC}', got {got!r}"
        )
        raise CompileError(r.diags)
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
            r.error(lineno, toks[0][1], f"expected record number {expected}, got {toks[0][0]!r}")
            raise CompileError(r.diags)
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
        raise CompileError(r.diags)
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
        raise CompileError(r.diags)
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
        code.source = _unquote(words[1]) or words[1]
    elif op == "ROBOT" and need(5):
        code.robot_var = words[1]
        code.robot = _unquote(words[2]) or words[2]
        kinds = words[4]
        if not re.fullmatch(r"[RP]+", kinds) or str(len(kinds)) != words[3]:
            r.error(
                lineno, col_of[4], f"ROBOT: joint kinds {kinds!r} do not match count {words[3]}"
            )
        code.joint_kinds = kinds
    elif op == "JOINTS":
        code.joint_names = tuple(words[1:])
    elif op == "UNITS":
        if words[1:] != ["mm", "deg", "s"]:
            r.error(lineno, col_of[0], "UNITS: only 'mm deg s' is supported")
    elif op == "DATALIST" and need(3):
        code.datalists.append((words[1], _unquote(words[2]) or words[2]))
    elif op == "CONST":
        v = _read_const(r, len(code.consts), words, col_of, lineno) if need(3) else None
        code.consts.append(v if v is not None else _BAD_VALUE)  # later indices stay right
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
        if words[2] not in OBSTACLE_KINDS:
            r.error(lineno, col_of[2], f"OBSTACLE: unknown kind {words[2]!r}")
        code.obstacles.append(ObstacleDef(words[1], words[2], tuple(fields)))
    elif op == "INPUT" and need(2):
        events = []
        rest = words[2:]
        if len(rest) % 2:
            r.error(lineno, col_of[-1], "INPUT: expected pairs of time and TRUE/FALSE")
        for t, v in zip(rest[::2], rest[1::2], strict=False):
            tv, bv = _parse_number(t), _parse_bool(v)
            if tv is None or bv is None:
                r.error(lineno, col_of[0], f"INPUT: bad event {t} {v}")
                continue
            events.append((float(tv), bv))
        signal = r.index(words[1], col_of[1], lineno, op)
        if signal is not None:
            code.inputs[signal] = events
    elif op == "TYPE" and need(3):
        fields_t = tuple(tuple(w.split(":", 1)) for w in words[3:])
        index = r.index(words[1], col_of[1], lineno, op)
        index = len(code.types) if index is None else index
        code.types.append(RecordType(index, fields_t))  # type: ignore[arg-type]
    elif op == "GLOBAL":
        index = r.index(words[1], col_of[1], lineno, op) if need(4) else None
        slot = Slot(index, words[2], words[3]) if index is not None else _BAD_SLOT
        code.globals.append(slot)  # a placeholder keeps later indices right
    elif op == "ROUTINE":
        index = r.index(words[1], col_of[1], lineno, op) if need(7) else None
        if index is None:
            r.bad_routine = True
            code.routines.append(Routine(len(code.routines), "?", "?", -1))
            return
        routine = Routine(index, words[2], words[3], -1)
        code.routines.append(routine)
        rec = words[6]
        entry = _record_number(rec)
        if entry is None:
            r.error(lineno, col_of[6], f"ROUTINE: expected an entry @record, got {rec!r}")
        else:
            pending.append((routine, entry, lineno, col_of[6]))
    elif op in ("PARAM", "LOCAL") and need(5):
        routine = next((x for x in code.routines if x.index == _parse_number(words[1])), None)
        if routine is None:
            r.error(lineno, col_of[1], f"{op}: unknown routine {words[1]}")
            return
        by_ref = words[3] == "VAR"
        rest = words[4:] if by_ref else words[3:]
        index = r.index(words[2], col_of[2], lineno, op)
        if index is None:
            return
        slot = Slot(index, rest[0], rest[1] if len(rest) > 1 else "?", by_ref)
        (routine.params if op == "PARAM" else routine.locals).append(slot)
    elif op not in ("PROGRAM", "SOURCE", "ROBOT", "DATALIST", "CONST", "OBSTACLE", "INPUT",
                    "TYPE", "GLOBAL", "ROUTINE", "PARAM", "LOCAL"):  # fmt: skip
        r.error(lineno, col_of[0], f"unknown header record {op!r}")


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
        r.error(lineno, col, f"unknown opcode {op!r}")
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
                r.error(lineno, c, f"{op}: expected a jump target '@<record>', got {tok!r}")
                return None
            fixups.append((idx, k, rec, lineno, c))
            args.append(Target(-1))
        elif kind == "i" or (kind == "*" and re.fullmatch(r"-?[0-9]+", tok)):
            if not re.fullmatch(r"-?[0-9]+", tok):
                r.error(lineno, c, f"{op}: expected an integer, got {tok!r}")
                return None
            value = parse_integer(tok)
            if isinstance(value, str):
                r.error(lineno, c, f"{op}: {value}")
                return None
            args.append(value)
        else:
            args.append(tok)
    return Instruction(op, tuple(args), line)


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
            r.error(lineno, toks[2][1], f"unknown system variable {ins.args[0]!r}")
        if ins.op == "MOVE" and ins.args[0] not in MOVE_KINDS:
            r.error(lineno, toks[2][1], f"unknown motion kind {ins.args[0]!r}")
        if ins.op in ("OPTON", "OPTOFF") and ins.args[0] not in MODAL_OPTIONS:
            r.error(lineno, toks[2][1], f"unknown modal option {ins.args[0]!r}")
    if not r.bad_routine and not any(rt.kind == "MAIN" for rt in code.routines):
        r.error(1, 1, "no MAIN routine")
