"""Writers for the run report (JSON) and trace (CSV), and the reader ``load_run``.

Both writers are

* **atomic**: :func:`irlc.files.atomic_write_text` (temporary file, fsync, rename);
* **deterministic**: same run → same bytes. JSON: two-space indent, keys in the order of
  ``docs/interfaces.md`` (the report dict's insertion order), UTF-8, a final newline. CSV:
  numbers with ``%.10g`` (no negative zero), ``line`` as an integer, ``\\n`` line ends;
* **never NaN**: a non-finite number raises :class:`NonFiniteError` (a bug upstream),
  nothing is written.

``load_run(path)`` reads a report (``.json``) or a trace (``.csv``) back, e.g. for
``--compare``: a :class:`LoadedRun` with ``report``, ``trace_columns``, ``trace`` (and
``times`` when a trace is given).
"""

from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from irlc.files import atomic_write_chunks, atomic_write_text, parse_user_json, read_user_text
from irlc.lang.errors import IrlcError

FLOAT_FORMAT = "%.10g"


class NonFiniteError(IrlcError, ValueError):
    """A NaN or infinity reached a report or trace (a bug: never written)."""


class RunFileError(IrlcError, ValueError):
    """A report or trace file cannot be read back."""


# --------------------------------------------------------------------------- writing


def report_json(report: dict) -> str:
    _check_finite(report, "report")
    return json.dumps(report, indent=2, ensure_ascii=False, allow_nan=False) + "\n"


def write_report(report: dict, path: str | Path) -> Path:
    return atomic_write_text(path, report_json(report))


PARTIAL_COLUMN = "partial"  # the last column of a failed run's trace, 1 on every row
TRACE_CHUNK_ROWS = 4096  # rows formatted at a time: the writer's memory is O(chunk)


def trace_csv(columns: list[str], table: np.ndarray, partial: bool = False) -> str:
    """The whole trace as CSV text (:func:`trace_chunks` joined)."""
    return "".join(trace_chunks(columns, table, partial))


def trace_chunks(
    columns: list[str], table: np.ndarray | Iterator[np.ndarray], partial: bool = False
) -> Iterator[str]:
    """The trace's CSV text in pieces of :data:`TRACE_CHUNK_ROWS` rows (header first).
    ``table`` is the whole table, or an iterator of consecutive pieces of its rows (a
    streamed run's, :meth:`~irlc.runtime.outputs.run_result.RunResult.trace_tables`): the
    same text. Each
    piece of the table is checked finite before its first row is formatted (a whole
    table before the header: nothing is produced for a bad one; a bad piece stops the
    text, which :func:`write_trace`'s atomic write then discards); each piece of text
    holds only its own rows, so writing a long trace needs memory for one piece, not for
    the file. ``partial`` (the run failed, the trace ends at the failure) adds the column
    :data:`PARTIAL_COLUMN`, 1 on every row, so the file itself says so."""
    if partial:
        columns = [*columns, PARTIAL_COLUMN]
    whole = not isinstance(table, Iterator)  # an array (or nested lists), not pieces
    pieces = [_checked(columns, table, partial, 0)] if whole else table
    cells = [FLOAT_FORMAT] * len(columns)
    if "line" in columns:
        cells[columns.index("line")] = "%d"  # an integer (the value is a whole number)
    row_format = ",".join(cells) + "\n"
    yield ",".join(columns) + "\n"
    row0 = 0
    for piece in pieces:
        piece = piece if whole else _checked(columns, piece, partial, row0)
        row0 += len(piece)
        for start in range(0, len(piece), TRACE_CHUNK_ROWS):
            rows = (piece[start : start + TRACE_CHUNK_ROWS] + 0.0).tolist()  # no negative zero
            yield "".join([row_format % tuple(row) for row in rows])


def _checked(columns: list[str], table, partial: bool, row0: int) -> np.ndarray:
    """``table`` as floats, with the ``partial`` column (1) when asked for, checked: the
    column count, every value finite (:class:`NonFiniteError` naming the column and the
    row, counted from ``row0``)."""
    table = np.asarray(table, dtype=float)
    if partial:
        table = np.hstack([table.reshape(len(table), -1), np.ones((len(table), 1))])
    if table.ndim != 2 or table.shape[1] != len(columns):
        raise ValueError(f"trace has {table.shape} values for {len(columns)} columns")
    for start in range(0, len(table), TRACE_CHUNK_ROWS):
        bad = ~np.isfinite(table[start : start + TRACE_CHUNK_ROWS])
        if bad.any():
            r, c = np.argwhere(bad)[0]
            raise NonFiniteError(
                f"trace: non-finite value in column {columns[c]!r}, row {row0 + start + r}"
            )
    return table


def write_trace(
    columns: list[str],
    table: np.ndarray | Iterator[np.ndarray],
    path: str | Path,
    partial: bool = False,
) -> Path:
    """Write the trace atomically, streamed piece by piece (:func:`trace_chunks`; ``table``
    whole or in pieces of rows)."""
    return atomic_write_chunks(
        path, (piece.encode("utf-8") for piece in trace_chunks(columns, table, partial))
    )


def _check_finite(obj: Any, where: str) -> None:
    if isinstance(obj, dict):
        for k, v in obj.items():
            _check_finite(v, f"{where}.{k}")
    elif isinstance(obj, list | tuple):
        for i, v in enumerate(obj):
            _check_finite(v, f"{where}[{i}]")
    elif isinstance(obj, float) and not math.isfinite(obj):
        raise NonFiniteError(f"non-finite number at {where}: {obj}")


# --------------------------------------------------------------------------- reading


@dataclass
class LoadedRun:
    """A run read back from files (the fields the tools read from a RunResult)."""

    path: Path
    report: dict = field(default_factory=dict)
    trace_columns: list[str] | None = None
    trace: np.ndarray | None = None

    @property
    def times(self) -> np.ndarray | None:
        if self.trace is None or not self.trace_columns or "t_s" not in self.trace_columns:
            return None
        return self.trace[:, self.trace_columns.index("t_s")]

    def column(self, name: str) -> np.ndarray:
        if self.trace is None or not self.trace_columns or name not in self.trace_columns:
            raise KeyError(name)
        return self.trace[:, self.trace_columns.index(name)]


def load_run(path: str | Path) -> LoadedRun:
    """Read a report (``.json``) or a trace (``.csv``); raises :class:`RunFileError`."""
    path = Path(path)

    def error(file: str, reason: str) -> RunFileError:
        return RunFileError(f"{file}: {reason}")

    text = read_user_text(path, error)
    if path.suffix.lower() == ".json" or text.lstrip().startswith("{"):
        return LoadedRun(path, _checked_report(parse_user_json(text, path, error), path))
    columns, table = _read_csv(path, text)
    return LoadedRun(path, {}, columns, table)


def _checked_report(report: Any, path: Path) -> dict:
    """``report`` when it has the shape the readers use (``status``; the numbers
    ``--compare`` shows: ``duration_s``, ``max_path_error_mm``, per joint ``name``,
    ``min``, ``max``, ``max_abs_speed``), else :class:`RunFileError` naming the key."""
    if not isinstance(report, dict) or "status" not in report:
        raise RunFileError(f"{path}: not an irlc report (no 'status' key)")
    for key in ("duration_s", "max_path_error_mm"):
        _number_or_null(report, key, path, key)
    joints = report.get("joints", [])
    if not isinstance(joints, list):
        raise RunFileError(f"{path}: key 'joints': expected a list of joints")
    for i, joint in enumerate(joints):
        if not isinstance(joint, dict) or not isinstance(joint.get("name"), str):
            raise RunFileError(f"{path}: key 'joints[{i}]': expected an object with a 'name'")
        for key in ("min", "max", "max_abs_speed"):
            _number_or_null(joint, key, path, f"joints[{i}].{key}")
    return report


# The largest magnitude a value of a report or trace read back (--compare) may have, in
# its unit (mm, deg, s, …): no run produces more, and figures cannot scale beyond it.
COMPARE_LIMIT = 1e12


def _number_or_null(obj: dict, key: str, path: Path, where: str) -> None:
    value = obj.get(key)
    if value is not None and (isinstance(value, bool) or not isinstance(value, int | float)):
        raise RunFileError(f"{path}: key '{where}': expected a number or null")
    if value is not None and not abs(value) <= COMPARE_LIMIT:
        raise RunFileError(f"{path}: key '{where}': a number beyond ±{COMPARE_LIMIT:g}")


def _read_csv(path: Path, text: str) -> tuple[list[str], np.ndarray]:
    rows = list(csv.reader(io.StringIO(text)))
    if not rows or "t_s" not in rows[0]:
        raise RunFileError(f"{path}: not an irlc trace (no 't_s' column in the header)")
    columns = [c.strip() for c in rows[0]]
    data = []
    for i, row in enumerate(rows[1:], start=2):
        if not row:
            continue
        if len(row) != len(columns):
            raise RunFileError(f"{path}:{i}: {len(row)} values for {len(columns)} columns")
        try:
            values = [float(v) for v in row]
        except ValueError:
            values = []
        if not values or not all(math.isfinite(v) for v in values):
            raise RunFileError(f"{path}:{i}: a value that is not a finite number")
        if not all(abs(v) <= COMPARE_LIMIT for v in values):
            raise RunFileError(f"{path}:{i}: a value beyond ±{COMPARE_LIMIT:g}")
        data.append(values)
    table = np.array(data, dtype=float) if data else np.zeros((0, len(columns)))
    return columns, table
