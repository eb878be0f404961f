"""A failed run's trace says it is partial (issue 11): the column ``partial`` (1 on every
row) ends the header of a failed run's trace and is absent from a finished run's."""

from __future__ import annotations

import csv

from irlc.cli import main

PROGRAM = "PROGRAM p;\nROBOT r := planar3;\nBEGIN\n  MOVE PTP (0, 90, 0);\n{last}\nENDPROGRAM\n"


def _rows(path) -> list[list[str]]:
    with path.open(newline="") as fh:
        return list(csv.reader(fh))


def test_a_failed_runs_trace_is_marked_partial(tmp_path) -> None:
    prog = tmp_path / "fail.irl"
    prog.write_text(PROGRAM.format(last="  MOVE LIN POSE(9500, 500, 0, 0, 0, 0);"))
    assert main(["run", str(prog), "-q", "--trace", str(tmp_path / "t.csv")]) == 2
    rows = _rows(tmp_path / "t.csv")
    assert rows[0][-1] == "partial" and rows[0][:2] == ["t_s", "line"]
    assert len(rows) > 2 and all(r[-1] == "1" and len(r) == len(rows[0]) for r in rows[1:])


def test_a_finished_runs_trace_has_no_partial_column(tmp_path) -> None:
    prog = tmp_path / "ok.irl"
    prog.write_text(PROGRAM.format(last="  MOVE PTP (0, 80, 0);"))
    assert main(["run", str(prog), "-q", "--trace", str(tmp_path / "t.csv")]) == 0
    assert "partial" not in _rows(tmp_path / "t.csv")[0]
