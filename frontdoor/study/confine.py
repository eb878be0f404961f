"""Which files a study file may make irlc read: its ``program``, ``robot`` and
``datalist_path``.

A study file is input — perhaps someone else's, like a program (lang/file_access.py) — and
irlc reads what it names with the user's rights, then shows parts of it in messages (a
program's compile errors quote its lines: ``program = "/proc/self/environ"`` echoed the
environment). A study is written beside the programs it studies, so the rule is looser
than a program's:

* a path written **relative** to the study file is allowed where it leads
  (``../square_accel.irl``, as the docs write it), unless that is a system file;
* an **absolute** path must lie inside the working folder or the study file's folder;
* a **system file** — under ``/proc``, ``/sys``, ``/dev``, ``/etc``, ``/boot``, ``/run``,
  ``/root`` — is refused however it is written (the path is judged resolved: ``..``
  removed, every link followed).

``--allow-any-path`` on the user's own command line (``allow_any_path=True`` in Python)
lifts the rule, as for ``irlc run``; nothing in the study file can.
"""

from __future__ import annotations

from pathlib import Path

from irlc.lang.file_access import inside_roots, shown

SYSTEM_FOLDERS = ("/proc", "/sys", "/dev", "/etc", "/boot", "/run", "/root")
HINT = "pass --allow-any-path on the command line to read it anyway"


def refusal(written: str, resolved: Path, study_file: Path) -> str | None:
    """Why the study file may not name ``written`` (resolved to ``resolved``), or ``None``."""
    system = next((f for f in SYSTEM_FOLDERS if inside_roots(resolved, [Path(f)])), None)
    if system is not None:
        return f"{shown(resolved)}: a system file (under {system}); {HINT}"
    if not Path(written).is_absolute():
        return None
    roots = [Path.cwd(), study_file.parent]
    if inside_roots(resolved, roots):
        return None
    folders = ", ".join(dict.fromkeys(shown(r) for r in roots))
    return (
        f"{shown(resolved)}: an absolute path outside the working folder and the study's "
        f"folder ({folders}); write it relative to the study file, or {HINT}"
    )
