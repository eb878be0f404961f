"""The rows of docs/fidelity.md: a published reference, the book's number, irlc's number and
the command that reproduces it — one line of ``bench/fidelity.py`` each, and the table.

A :class:`Row` computes its :class:`Result` on demand. ``book_values`` and ``tolerance``
(absolute, in the row's unit) state what counts as reproduced; a row without them has no
book number to compare (a formula irlc evaluates, a qualitative observation, or a number
the sources at hand do not give) and its ``note`` says which. Numbers are printed to the
digits the book prints; round-off-sized deviations as ``< floor`` (the same text on every
machine).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass

NOT_AT_HAND = "the book's value is not in the sources at hand"
DOC_BEGIN = "<!-- fidelity-table:begin (written by python bench/fidelity.py --write-doc) -->"
DOC_END = "<!-- fidelity-table:end -->"


@dataclass(frozen=True)
class Result:
    """irlc's side of a row: ``text`` (numbers in the book's units and order), ``values``
    (the same numbers, for the tolerance check), ``reproduced`` (``None``: nothing to compare
    with; else within the row's tolerance, or the qualitative statement holds), ``note``
    (how the number was obtained or why it cannot be the book's), ``figure`` (docs/img/…)."""

    text: str
    values: tuple[float, ...] = ()
    reproduced: bool | None = None
    note: str = ""
    figure: str | None = None


@dataclass(frozen=True)
class Row:
    ref: str
    title: str
    unit: str
    book: str
    command: str
    compute: Callable[[], Result]
    book_values: tuple[float, ...] | None = None
    tolerance: float | None = None
    slow: bool = False
    needs: str | None = None  # an optional module the row needs (its absence: skipped)

    @property
    def key(self) -> str:
        return f"{self.ref} {self.title}"

    def judge(self, values: Sequence[float]) -> bool | None:
        """Within ``tolerance`` of ``book_values`` (None when the row has none)."""
        if self.book_values is None or self.tolerance is None:
            return None
        if len(values) != len(self.book_values):
            return False
        return all(
            abs(a - b) <= self.tolerance for a, b in zip(values, self.book_values, strict=True)
        )


def line(row: Row, result: Result) -> str:
    """The bench line: ``REF TITLE [UNIT]: irlc's numbers | book: … | note``."""
    unit = f" [{row.unit}]" if row.unit else ""
    out = f"{row.key}{unit}: {result.text} | book: {row.book}"
    if result.reproduced is not None:
        out += " | reproduced" if result.reproduced else " | NOT reproduced"
    return out + (f" | {result.note}" if result.note else "")


def doc_row(row: Row, result: Result) -> str:
    """One row of the docs/fidelity.md table."""
    unit = f" [{row.unit}]" if row.unit else ""
    irlc = result.text
    if result.reproduced is not None:
        irlc += " (reproduced)" if result.reproduced else " (**not** reproduced)"
    if result.note:
        irlc += f" — {result.note}"
    if result.figure:
        irlc += f" ([figure]({result.figure}))"
    cells = [f"{row.key}{unit}", row.book, irlc, f"`{row.command}`"]
    return "| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |"


def doc_table(rows: Sequence[tuple[Row, Result]]) -> str:
    head = "| reference | book's number | irlc's number | command |\n|---|---|---|---|"
    return "\n".join([head, *(doc_row(r, res) for r, res in rows)])


def replace_table(doc: str, table: str) -> str:
    """``doc`` with the text between the markers replaced by ``table``."""
    start, end = doc.index(DOC_BEGIN) + len(DOC_BEGIN), doc.index(DOC_END)
    return doc[:start] + "\n" + table + "\n" + doc[end:]


def doc_cells(doc: str) -> dict[str, list[str]]:
    """The table of docs/fidelity.md as ``{reference cell: [book, irlc, command]}``."""
    body = doc[doc.index(DOC_BEGIN) + len(DOC_BEGIN) : doc.index(DOC_END)]
    out = {}
    for text in body.strip().splitlines()[2:]:
        cells = [c.strip().replace("\\|", "|") for c in re.split(r"(?<!\\)\|", text)[1:-1]]
        out[cells[0]] = cells[1:]
    return out


def only(ref: str) -> str:
    """The command that prints one row: ``python bench/fidelity.py --only "REF"``."""
    quoted = ref if re.fullmatch(r"[\w.-]+", ref) else f'"{ref}"'
    return f"python bench/fidelity.py --only {quoted}"


def fmt(values: Sequence[float], digits: int = 3) -> str:
    """Numbers to ``digits`` significant digits, space-separated."""
    return " ".join(f"{v:.{digits}g}" for v in values)


def fmt_small(value: float, floor: float) -> str:
    """A deviation: ``< floor`` when below it (round-off), else 3 significant digits."""
    return f"< {floor:g}" if value < floor else f"{value:.3g}"
