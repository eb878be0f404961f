"""The REPL's file commands — ``:trace FILE``, ``:plot DIR``, ``:teach NAME [FILE]`` — from
the parts of the session they are given (its positions, folder, run so far, names, the
current robot's view): what each writes and its messages (docs/interfaces.md, "REPL")."""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

from irlc.lang.file_access import path_kind
from irlc.repl_positions import Positions
from irlc.repl_views import Entry, RobotView, pose_text


def trace(pos: Positions, cwd: Path, arg: str, run_result: Callable[[], Any]) -> Entry:
    """``:trace FILE``: the session's trace (CSV, program units), as ``irlc run`` writes it."""
    from irlc.report import write_trace

    if not arg:
        return Entry([pos.located("usage: :trace FILE.csv")], 3)
    target = cwd / Path(arg).expanduser()
    if target.is_dir():
        return Entry([pos.located(f"{target} is a folder; :trace takes a file (FILE.csv)")], 3)
    run = run_result()
    path = write_trace(run.trace_columns, run.trace, target)
    return Entry([f"trace: {len(run.trace)} samples → {path}"])


def plot(pos: Positions, cwd: Path, arg: str, run_result: Callable[[], Any]) -> Entry:
    """``:plot DIR``: the session's figures (PNG), as ``irlc run --plot`` draws them."""
    from irlc.plots import write_plots

    if not arg:
        return Entry([pos.located("usage: :plot DIR")], 3)
    target = cwd / Path(arg).expanduser()  # relative to the session's folder
    if target.exists() and not target.is_dir():
        return Entry([pos.located(f"{target} is not a folder; :plot takes a folder (DIR)")], 3)
    paths = write_plots(run_result(), target)
    return Entry([f"{len(paths)} figures → {Path(arg)}"])


def teach(
    pos: Positions, cwd: Path, arg: str, names: set[str], view: RobotView, in_cell: bool
) -> Entry:
    """``:teach NAME [FILE]``: the pose (R_ACT_POSE: R_BASE frame, with R_TOOL) and the
    joints into a data list (:mod:`irlc.teach`); ``FILE`` relative to the session's
    folder, ``.toml`` added when it has no suffix, default ``taught.toml``."""
    from irlc.lang.parser import keywords
    from irlc.lang.settings import SYSTEM_VARIABLES
    from irlc.teach import JOINTS_SUFFIX, TeachError
    from irlc.teach import teach as store

    parts = arg.split()
    if len(parts) not in (1, 2):
        return Entry([pos.located("usage: :teach NAME [FILE.toml]")], 3)
    name, raw = parts[0], parts[1] if len(parts) == 2 else "taught.toml"
    path = teach_path(cwd, raw)
    if path is None or path_kind(path) == "folder":
        where = raw if path is None else str(path)
        message = f"{where} is a folder; :teach takes a file (FILE.toml)"
        return Entry([pos.located(message)], 3)
    taken = {n.lower() for n in (*names, *keywords(), *SYSTEM_VARIABLES)}
    clash = [n for n in (name, name + JOINTS_SUFFIX) if n.lower() in taken]
    if clash:
        return Entry([pos.located(f"'{clash[0]}' is already a name of this session, a "
                                    "keyword or a system variable; choose another name")],
                     3)  # fmt: skip
    xyzabc = view.xyzabc()
    try:
        keys = store(path, name, xyzabc, view.joints())
    except TeachError as e:
        return Entry([pos.located(str(e))], 3)
    robot = "" if not in_cell else f"{view.name} "
    frame = "" if not in_cell else f" of {view.name} ({view.frame})"
    return Entry([
        f"taught {name}: pose{frame} {pose_text(xyzabc)} [mm, deg ZYX] and "
        f"joints → {', '.join(keys)} in {path}",
        f"  use it: IMPORT DATALIST {path.stem};  MOVE {robot}LIN {name};  "
        f"MOVE {robot}PTP {name}{JOINTS_SUFFIX};",
    ])  # fmt: skip


def teach_path(cwd: Path, raw: str) -> Path | None:
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
