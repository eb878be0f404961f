"""``DIR/results.csv``: rows appended as variants finish, sorted by variant at the end.

* Appending: each row is one ``write`` of its whole line to the file opened with
  ``O_APPEND`` — a row is either entirely in the file or not at all (Ctrl-C or a killed
  study loses nothing written; a machine crash can leave at most a last line without its
  newline, which a resume drops). ``fsync`` runs at most every :data:`SYNC_EVERY_S`
  seconds and at the end, so a million rows do not cost a million disk flushes.
* ``DIR/study.json`` records the study's token and the columns; ``--resume`` refuses a
  folder of another study (or of a changed study file, program, robot file, data list).
* At the end (also after Ctrl-C) the rows are rewritten sorted by ``variant``
  (:func:`irlc.files.atomic_write_text`), so the file is the same bytes whatever the order
  in which variants finished and however often the study was resumed.
* With ``pyarrow`` installed, ``DIR/results.parquet`` is written next to it at the end: the
  same rows, columns typed by pyarrow's CSV reader (numbers, strings; empty cells null).
"""

from __future__ import annotations

import csv
import io
import json
import os
import time
from pathlib import Path

from irlc.files import atomic_write_bytes, atomic_write_text, parse_user_json, read_user_text
from irlc.lang.file_access import path_kind
from irlc.study.spec import StudyError

RESULTS = "results.csv"
SYNC_EVERY_S = 1.0
META = "study.json"


def _line(columns: list[str], row: dict[str, str]) -> str:
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerow([row.get(c, "") for c in columns])
    return buf.getvalue()


class ResultsFile:
    """The results of one study in ``folder`` (see the module doc)."""

    def __init__(self, folder: Path, columns: list[str], token: str, resume: bool):
        self.folder, self.columns, self.token = Path(folder), columns, token
        self.path = self.folder / RESULTS
        self.done: dict[int, str] = {}  # variant → its line
        self._fd: int | None = None
        self._synced = time.monotonic()
        if path_kind(self.folder) in ("file", "other"):
            raise StudyError(str(self.folder), None, "", "not a folder (--out takes a folder)")
        if resume and self.path.exists():
            self._load()
        elif self.path.exists() and not resume:
            raise StudyError(
                str(self.path), None, "",
                "already exists: pass --resume to complete it, or choose another --out",
            )  # fmt: skip
        else:
            self.folder.mkdir(parents=True, exist_ok=True)
            meta = {"format": "irlc-study 1", "token": token, "columns": columns}
            atomic_write_text(self.folder / META, json.dumps(meta, indent=1) + "\n")
            atomic_write_text(self.path, _line(columns, {c: c for c in columns}))

    def _load(self) -> None:
        meta_path = self.folder / META

        def unreadable(file: str, reason: str) -> StudyError:
            return StudyError(str(meta_path), None, "", "missing or unreadable: cannot resume")

        meta = parse_user_json(read_user_text(meta_path, unreadable), meta_path, unreadable)
        if (
            not isinstance(meta, dict)
            or meta.get("token") != self.token
            or meta.get("columns") != self.columns
        ):
            raise StudyError(
                str(self.path), None, "",
                "written by another study (or the study file or program changed): "
                "cannot resume; choose another --out",
            )  # fmt: skip
        text = read_user_text(self.path, lambda f, r: StudyError(f, None, "", r))
        if not text.endswith("\n"):  # a row cut short by a crash: dropped
            text = text[: text.rfind("\n") + 1]
            atomic_write_text(self.path, text)
        for body in text.split("\n")[1:-1]:
            variant = _variant(body)
            if variant is not None:
                self.done[variant] = body + "\n"

    def append(self, row: dict[str, str]) -> None:
        line = _line(self.columns, row)
        if self._fd is None:
            self._fd = os.open(self.path, os.O_WRONLY | os.O_APPEND)
        os.write(self._fd, line.encode("utf-8"))
        if time.monotonic() - self._synced >= SYNC_EVERY_S:
            os.fsync(self._fd)
            self._synced = time.monotonic()
        self.done[int(row["variant"])] = line

    def finish(self) -> None:
        """Rewrite the rows in variant order (atomically)."""
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None
        header = _line(self.columns, {c: c for c in self.columns})
        body = "".join(self.done[i] for i in sorted(self.done))
        atomic_write_text(self.path, header + body)
        write_parquet(self.path)

    def rows(self) -> list[dict[str, str]]:
        """All rows done, in variant order, as dicts of text."""
        reader = csv.reader(self.done[i] for i in sorted(self.done))
        return [dict(zip(self.columns, r, strict=False)) for r in reader]


def _variant(line: str) -> int | None:
    """The variant number a row of results.csv starts with, or None (a header, a line
    that is no row irlc wrote: a stray edit, a NUL byte, a field beyond the csv limit)."""
    try:
        first = next(csv.reader([line]), [""])[0]
    except csv.Error:
        return None
    return int(first) if first.isascii() and first.isdigit() else None


def write_parquet(csv_path: Path) -> Path | None:
    """``results.parquet`` from ``results.csv`` if pyarrow is installed, else nothing."""
    try:
        import pyarrow.csv as pacsv
        import pyarrow.parquet as pq
    except ImportError:
        return None
    options = pacsv.ConvertOptions(strings_can_be_null=True)
    table = pacsv.read_csv(csv_path, convert_options=options)
    buf = io.BytesIO()
    pq.write_table(table, buf)
    return atomic_write_bytes(csv_path.with_suffix(".parquet"), buf.getvalue())
