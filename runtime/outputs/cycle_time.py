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
source line where the program's source file is at hand.
"""

from __future__ import annotations

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
    rows = []
    for s in spans:
        text = code_text(lines[s.line - 1]) if 0 < s.line <= len(lines) else ""
        limit = s.limit
        rows.append(
            {
                "line": s.line,
                "statement": text or s.kind,
                "kind": s.kind,
                "start_s": rnd(s.start),
                "duration_s": rnd(s.duration),
                "stop": s.stop,
                "limit": limit or None,
                "override_percent": rnd(s.override),
            }
        )
    return rows
