"""Cycle time per statement: which statement used which span of simulated time.

The controller logs one :class:`StatementSpan` for every statement that advances
simulated time — a motion (``MOVE …``), ``RECONFIGURATION``, ``WAIT … SEC`` and
``WAIT FOR`` (the latter two stand still) — from the time it started to the time it
ended (its last IPO sample). Statements run one after the other on one clock, so the
spans tile ``[0, duration]``: their durations sum to the run's duration (the start
sample at t = 0 takes no time). A motion that ends in an exact stop is ``"exact"``; one
that is blended into the next (approximate positioning) ``"approximated"``; a span
cut short by a run failure ``"failed"``; WAITs have no stop (``None``).

The report lists them under ``statements`` (docs/interfaces.md), with the statement's
source text where the program's source file is at hand (:class:`StatementTexts`): its
line, or — where several statements that take time share the line
(``MOVE LIN p1;  MOVE LIN p2;``) — its own statement on it; a motion inside a routine
also names the routine and the line of its call.
"""

from __future__ import annotations

import re
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

# How a motion statement is written, for runs without the source text: owned by the
# language's settings table, re-exported here for the executor.
from irlc.lang.file_access import program_source_lines
from irlc.lang.settings import KIND_WORDS as KIND_WORDS


@dataclass(frozen=True)
class StatementSpan:
    """One statement's share of simulated time (s)."""

    line: int
    kind: str  # "MOVE LIN", …, "RECONFIGURATION", "WAIT"
    start: float
    end: float
    stop: str | None  # "exact" | "approximated" | "failed" | None (no motion)
    limit: str = ""  # what set the motion's time ("path speed/acceleration", "WITH TIME", …)
    override: float | None = None  # R_OVERRIDE (%) the motion ran at; None for a WAIT
    call: tuple[str, int] | None = None  # (routine, line of its call) for a motion in one

    @property
    def duration(self) -> float:
        return self.end - self.start


def motion_limit(limits: Sequence[str], fixed_time: bool) -> str:
    """The binding limit of a motion from its segments' ``limiting`` (distinct, in order),
    or ``"WITH TIME"`` when the statement fixed its time."""
    if fixed_time:
        return "WITH TIME"
    return "; ".join(dict.fromkeys(s for s in limits if s))


def source_lines(source: str, base_dir: str | Path | None) -> list[str]:
    """The lines of the program's source file (``code.source``, an ``.irl`` file looked up
    next to the program, else as given), or ``[]`` when it cannot be read
    (:func:`~irlc.lang.file_access.program_source_lines`)."""
    return program_source_lines(source, base_dir) or []


def code_text(line: str) -> str:
    """A source line without its trailing comment (``{ … }``, ``(* … *)``, ``// …``), in
    linear time (a regular expression with ``\\s*`` took quadratic time on a line of
    40,000 blanks: 18 s)."""
    text = line.rstrip()
    start = _comment_start(text)
    return (text if start is None else text[:start]).strip()


def _comment_start(text: str) -> int | None:
    """The leftmost start of a comment that ends ``text`` (no trailing blanks): ``{…}``
    with no ``{``, ``}`` or quote inside, ``(*…*)`` with no ``*)`` inside, or ``//…`` with
    no quote after it; ``None`` when the line ends in code."""
    starts = []
    slash = text.find("//", text.rfind("'") + 1)
    if slash >= 0:
        starts.append(slash)
    if text.endswith("}"):
        brace = text.rfind("{")
        if brace >= 0 and not any(c in text[brace + 1 : -1] for c in "{}'"):
            starts.append(brace)
    end = len(text) - 2  # where a closing *) begins
    if end >= 2 and text.endswith("*)"):
        inner = text.rfind("*)", 0, end + 1)  # the last *) before it (may overlap a "(*)")
        opening = text.find("(*", max(inner - 1, 0) if inner >= 0 else 0, end)
        if opening >= 0:
            starts.append(opening)
    return min(starts) if starts else None


def statement_rows(spans: Sequence[StatementSpan], lines: Sequence[str], rnd) -> list[dict]:
    """The report's ``statements``: one object per span (``rnd`` rounds the numbers; a
    joint in ``limit`` is named by the pre-interpolator's naming, runtime/model/naming.py)."""
    texts = StatementTexts(lines)
    rows = []
    for s in spans:
        limit = s.limit
        rows.append(
            {
                "line": s.line,
                "statement": texts.text(s) or s.kind,
                "kind": s.kind,
                "start_s": rnd(s.start),
                "duration_s": rnd(s.duration),
                "stop": s.stop,
                "limit": limit or None,
                "override_percent": rnd(s.override),
                "routine": s.call[0] if s.call else None,
                "called_at": s.call[1] if s.call else None,
            }
        )
    return rows


_TIMED = re.compile(r"\b(MOVE_INC|MOVE|RECONFIGURATION|WAIT)\b", re.IGNORECASE)
_CONTROL = re.compile(
    r"\b(IF|ELSIF|ELSE|CASE|FOR|WHILE|REPEAT|UNTIL|GOTO|RETURN|HALT)\b", re.IGNORECASE
)


class StatementTexts:
    """The text a span shows: its source line; where several statements that take time
    share the line, the one of the span's kind — the k-th execution of that kind on the
    line is its (k mod count)-th statement, as straight-line code runs them. A line with
    control flow (IF, a loop, GOTO …) and several statements of one kind is shown whole:
    which one ran is not known from the line alone."""

    def __init__(self, lines: Sequence[str]):
        self.lines = lines
        self._pieces: dict[int, tuple[str, list[tuple[str, str]]]] = {}
        self._runs: Counter = Counter()

    def text(self, span: StatementSpan) -> str:
        if not 0 < span.line <= len(self.lines):
            return ""
        code, pieces = self._line(span.line)
        same = [text for kind, text in pieces if kind == span.kind]
        if len(pieces) > 1 and len(same) == 1:
            return same[0]
        if len(pieces) > 1 and same and not _CONTROL.search(code):
            key = (span.line, span.kind)
            shown = same[self._runs[key] % len(same)]
            self._runs[key] += 1
            return shown
        return code

    def _line(self, line: int) -> tuple[str, list[tuple[str, str]]]:
        found = self._pieces.get(line)
        if found is None:
            code = code_text(self.lines[line - 1])
            found = self._pieces[line] = (code, timed_statements(code))
        return found


def timed_statements(code: str) -> list[tuple[str, str]]:
    """``(kind, text)`` of each statement of a source line that takes time (a motion,
    RECONFIGURATION, WAIT), in order: ``"MOVE LIN p1;  MOVE LIN p2;"`` →
    ``[("MOVE LIN", "MOVE LIN p1;"), ("MOVE LIN", "MOVE LIN p2;")]``."""
    out = []
    for piece, blanked in _statements(code):
        match = _TIMED.search(blanked)  # not a word in a string or comment
        if match is not None:
            text = piece[match.start() :].strip()
            out.append((_kind(text), text + ";"))
    return out


def _statements(code: str) -> list[tuple[str, str]]:
    """``code`` split at the ``;`` outside strings and comments (linear): each piece and
    the piece with its strings and comments blanked."""
    blanked = list(code)
    cuts, i, n = [], 0, len(code)
    closers = {"'": "'", '"': '"', "{": "}", "(*": "*)"}
    while i < n:
        opener = "(*" if code.startswith("(*", i) else code[i]
        if opener in closers:
            end = code.find(closers[opener], i + len(opener))
            stop = n if end < 0 else end + len(closers[opener])
            blanked[i:stop] = " " * (stop - i)
            i = stop
            continue
        if code[i] == ";":
            cuts.append(i)
        i += 1
    flat = "".join(blanked)
    bounds = zip([-1, *cuts], [*cuts, n], strict=True)
    return [(code[a + 1 : b], flat[a + 1 : b]) for a, b in bounds if flat[a + 1 : b].strip()]


def _kind(text: str) -> str:
    """A statement's kind as the spans name it (KIND_WORDS, ``RECONFIGURATION``,
    ``WAIT``): ``MOVE CIRC …`` is ``MOVE CIRCLE``, ``MOVE LIN PATH(…)`` ``MOVE LIN PATH``."""
    words = re.findall(r"[A-Za-z_]+", text.upper())[:3]
    if words[0] in ("RECONFIGURATION", "WAIT") or len(words) < 2:
        return words[0]
    if words[1] == "CIRC":
        words[1] = "CIRCLE"
    if words[:2] == ["MOVE", "LIN"] and words[2:3] == ["PATH"]:
        return "MOVE LIN PATH"
    return f"{words[0]} {words[1]}"
