"""Golden-output tests of IRL programs: ``NAME.irl`` + ``NAME.expected.json`` (+ ``.txt``).

A run's report is *reduced* to what matters and rounded (:func:`reduce_report`, the
rules are in ``docs/golden.md``); the expectation is compared key by key with a
tolerance of one rounding quantum, so last-digit float noise across machines passes
and real changes fail with a readable list of what changed. ``--update`` rewrites the
expectations (atomically), keeping the user's ``options`` and ``tolerances``.
"""

from __future__ import annotations

import difflib
import json
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from irlc.files import atomic_write_text, parse_user_json, read_user_text
from irlc.lang.errors import IrlcError
from irlc.lang.file_access import path_kind, shown_key

GOLDEN_FORMAT = "irlc-golden 1"
USER_KEYS = ("options", "tolerances")  # kept as written by the user on --update
UNITS = {"length": "mm", "angle": "deg", "time": "s"}  # of the reduced report's numbers
NEWER_KEYS = ("units",)  # added later: an expectation written before may lack them
# Rounding quantum per key (the key's last path component, or its first for joints).
QUANTA = {
    "duration_s": 0.001,
    "min": 0.01,
    "max": 0.01,
    "end": 0.01,
    "max_following_error": 0.001,
    "min_distance_mm": 0.1,
}
BOUND_SUFFIX = "_below"  # "x_below": passes when actual x ≤ expected bound
BOUND_FLOOR = 1e-3  # mm | deg: path errors below this are solver noise, not behaviour

Runner = Callable[[Path, dict], dict]  # (program, options) → report dict


# --------------------------------------------------------------------------- reduction


def _q(value: float | None, quantum: float) -> float | None:
    """``value`` rounded to a multiple of ``quantum`` (a float with no noise digits)."""
    if value is None or not math.isfinite(value):
        return None
    decimals = max(0, -math.floor(math.log10(quantum)))
    return round(round(value / quantum) * quantum, decimals) + 0.0


def nice_bound(value: float | None) -> float | None:
    """The smallest ``{1, 2, 5}·10^k`` ≥ 2·value (≥ :data:`BOUND_FLOOR`): a bound with headroom."""
    if value is None or not math.isfinite(value):
        return None
    target = max(2.0 * abs(value), BOUND_FLOOR)
    exp = math.floor(math.log10(target))
    for mantissa in (1.0, 2.0, 5.0, 10.0):
        bound = float(f"{mantissa}e{exp}")
        if bound >= target * (1 - 1e-12):
            return bound
    return float(f"1e{exp + 1}")  # pragma: no cover - the loop always returns


def reduce_report(report: dict) -> dict:
    """The reduced, rounded report (``docs/golden.md``)."""
    if report.get("status") == "compile_error":
        return {
            "format": GOLDEN_FORMAT,
            "status": "compile_error",
            "diagnostics": list(report.get("diagnostics", [])),
        }
    error = report.get("error") or {}
    out: dict[str, Any] = {
        "format": GOLDEN_FORMAT,
        "units": dict(UNITS),
        "status": report.get("status"),
        "error_line": error.get("line"),
        "duration_s": _q(report.get("duration_s"), QUANTA["duration_s"]),
        "samples": report.get("samples"),
        "joints": {},
    }
    ends = report.get("end_joints") or []
    for i, row in enumerate(report.get("joints") or []):
        j = {"min": _q(row.get("min"), 0.01), "max": _q(row.get("max"), 0.01)}
        if i < len(ends):
            j["end"] = _q(ends[i], 0.01)
        if row.get("max_following_error") is not None:
            j["max_following_error"] = _q(row["max_following_error"], 0.001)
        out["joints"][row.get("name", f"a{i + 1}")] = j
    for key in ("max_path_error_mm", "max_orientation_error_deg"):
        if report.get(key) is not None:
            out[key + BOUND_SUFFIX] = nice_bound(report[key])
    obstacles = report.get("obstacles") or {}
    out["obstacles"] = {
        name: {"min_distance_mm": _q((v or {}).get("min_distance_mm"), 0.1)}
        for name, v in sorted(obstacles.items())
    }
    clearance = report.get("clearance")
    if clearance:  # a cell: the least distance between links, and per pair of robots
        out["clearance"] = {"min_distance_mm": _q(clearance.get("min_distance_mm"), 0.1)}
        for pair in clearance.get("pairs") or []:
            name = f"{pair.get('robot_a')}-{pair.get('robot_b')}"
            out["clearance"][name] = {"min_distance_mm": _q(pair.get("min_distance_mm"), 0.1)}
    out["ik_relaxed_cycles"] = (report.get("ik") or {}).get("relaxed_cycles")
    out["output"] = list(report.get("output") or [])
    return out


# --------------------------------------------------------------------------- comparison


@dataclass(frozen=True)
class Mismatch:
    path: str  # dotted key, e.g. "joints.a3.max"
    expected: Any
    actual: Any
    note: str = ""


def _tolerance(path: str, tolerances: dict) -> float:
    best, best_len = None, -1
    for prefix, tol in tolerances.items():
        if _covers(prefix, path) and len(prefix) > best_len:
            best, best_len = float(tol), len(prefix)
    if best is not None:
        return best
    leaf = path.rsplit(".", 1)[-1]
    return QUANTA.get(leaf, 0.0)


def _covers(prefix: str, path: str) -> bool:
    """Whether the tolerance key ``prefix`` applies to ``path``: the key itself, a key
    below it, and in a cell ``joints.ROBOT`` every joint of that robot (``joints.ROBOT_a1``)."""
    if path == prefix or path.startswith(prefix + "."):
        return True
    return prefix.startswith("joints.") and prefix.count(".") == 1 and path.startswith(prefix + "_")


def compare(expected: dict, actual: dict, tolerances: dict | None = None) -> list[Mismatch]:
    """Differences between a reduced expectation and a reduced actual report."""
    out: list[Mismatch] = []
    tolerances = tolerances or {}
    _compare(expected, actual, "", tolerances, out)
    return out


def _compare(exp: Any, act: Any, path: str, tolerances: dict, out: list) -> None:
    if isinstance(exp, dict) and isinstance(act, dict):
        for key in exp:
            if key in USER_KEYS and not path:
                continue
            sub = f"{path}.{key}" if path else key
            if key not in act:
                out.append(Mismatch(sub, exp[key], "(missing)"))
            else:
                _compare(exp[key], act[key], sub, tolerances, out)
        for key in act:
            if key not in exp and not (key in NEWER_KEYS and not path):
                out.append(Mismatch(f"{path}.{key}" if path else key, "(missing)", act[key]))
        return
    if path.endswith(BOUND_SUFFIX) and _is_num(exp) and _is_num(act):
        if act > exp * (1 + 1e-9):
            out.append(Mismatch(path, exp, act, "actual bound exceeds the expected bound"))
        return
    if _is_num(exp) and _is_num(act) and not isinstance(exp, bool):
        tol = _tolerance(path, tolerances)
        if abs(act - exp) > tol * (1 + 1e-9) + 1e-12:
            out.append(Mismatch(path, exp, act, f"tolerance {tol:g}" if tol else "exact"))
        return
    if exp != act:
        out.append(Mismatch(path, exp, act))


def _is_num(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


# --------------------------------------------------------------------------- cases


@dataclass
class CaseResult:
    program: Path
    status: str  # "pass" | "fail" | "missing" | "updated" | "error"
    mismatches: list[Mismatch] = field(default_factory=list)
    output_diff: list[str] = field(default_factory=list)
    message: str = ""

    @property
    def name(self) -> str:
        return self.program.stem

    @property
    def ok(self) -> bool:
        return self.status in ("pass", "updated")


def expected_paths(program: Path) -> tuple[Path, Path]:
    stem = program.with_suffix("")
    return Path(f"{stem}.expected.json"), Path(f"{stem}.expected.txt")


def find_programs(directory: Path) -> list[Path]:
    """Every ``*.irl`` name of ``directory``, sorted — also one that is not a regular file
    (a broken link, a folder, a FIFO): :func:`run_case` reports it as an error case
    rather than passing it over."""
    return sorted(Path(directory).glob("*.irl"))


_NOT_A_PROGRAM = {
    "folder": "a folder, not a program file",
    "other": "not a regular file (a pipe or device): never read",
    "missing": "a broken link or a name the system refuses",
}


def _output_text(report: dict) -> str:
    lines = report.get("output") or []
    return "".join(f"{line}\n" for line in lines)


def _dump(doc: dict) -> str:
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"


class ExpectationError(IrlcError, ValueError):
    """An expected file cannot be used: ``FILE: key 'K': reason``."""


RUN_OPTIONS = (  # docs/golden.md
    "ipo",
    "drives",
    "path_tolerance",
    "orientation_tolerance",
    "seed_config",
    "robot",
    "datalist_path",
    "instruction_budget",
    "max_time",
    "max_cycles",
    "override",
    "allow_any_path",
    "allow_collisions",
)


LIFT_REFUSED = (
    "options.allow_any_path: an expectation file cannot lift the file confinement (the "
    "program's robot file and data lists); allow it on the command line: irlc test "
    "--allow-any-path"
)


def load_expectation(path: Path) -> dict:
    """Read and validate ``NAME.expected.json``: an object whose ``options`` is an object of
    run options and whose ``tolerances`` maps keys to non-negative numbers."""

    def error(file: str, reason: str) -> ExpectationError:
        return ExpectationError(f"{file}: {reason}")

    doc = parse_user_json(read_user_text(path, error), path, error)
    if not isinstance(doc, dict):
        raise ExpectationError(f"{path}: expected a JSON object, got {_json_type(doc)}")
    options = doc.get("options", {})
    if not isinstance(options, dict):
        raise ExpectationError(
            f"{path}: key 'options': expected an object, got {_json_type(options)}"
        )
    for key, value in options.items():
        if key not in RUN_OPTIONS:
            raise ExpectationError(
                f"{path}: key 'options.{shown_key(key)}': unknown run option"
                f" (known: {', '.join(RUN_OPTIONS)})"
            )
        problem = _option_problem(key, value)
        if problem is not None:
            raise ExpectationError(f"{path}: key 'options.{key}': {problem}")
    tolerances = doc.get("tolerances", {})
    if not isinstance(tolerances, dict):
        raise ExpectationError(
            f"{path}: key 'tolerances': expected an object, got {_json_type(tolerances)}"
        )
    for key, tol in tolerances.items():
        if not _is_num(tol) or not math.isfinite(tol) or tol < 0:
            raise ExpectationError(
                f"{path}: key 'tolerances.{shown_key(key)}': expected a number ≥ 0,"
                f" got {_json_value(tol)}"
            )
        problem = _tolerance_key_problem(key, doc)
        if problem is not None:
            raise ExpectationError(f"{path}: key 'tolerances.{shown_key(key)}': {problem}")
    return doc


# The numbers a tolerance can widen (the bounds ``…_below`` have none): top-level keys and,
# under joints.NAME / obstacles.NAME, their fields; a cell's clearance: the least distance
# between links and per pair of robots (clearance.A-B), each its min_distance_mm.
TOLERANCE_ROOTS = ("duration_s", "samples", "error_line", "ik_relaxed_cycles", "joints",
                   "obstacles", "clearance")  # fmt: skip
TOLERANCE_FIELDS = {
    "joints": ("min", "max", "end", "max_following_error"),
    "obstacles": ("min_distance_mm",),
    "clearance": ("min_distance_mm",),
}
_NAMED = {"joints": "joint", "obstacles": "obstacle", "clearance": "pair of robots"}


def _tolerance_key_problem(key: str, doc: dict) -> str | None:
    """Why ``key`` names no number of the expectation ``doc`` (a typo such as
    ``duraton_s`` was ignored and the default quantum applied), else ``None``."""
    root, *rest = key.split(".")
    if root.endswith(BOUND_SUFFIX):
        return (
            "a bound (it passes while the actual value is at most the expected one) "
            "takes no tolerance"
        )
    if root not in TOLERANCE_ROOTS:
        return (
            "no number of the expectation has this key (keys: "
            f"{', '.join(TOLERANCE_ROOTS)}, joints.NAME[.FIELD], obstacles.NAME[.FIELD], "
            "clearance[.min_distance_mm], clearance.A-B[.min_distance_mm])"
        )
    fields = TOLERANCE_FIELDS.get(root)
    if fields is None:
        return f"'{root}' is one number: it has no parts" if rest else None
    if root == "clearance" and rest == ["min_distance_mm"]:
        return None  # the least over every pair
    if len(rest) > 2 or (len(rest) == 2 and rest[1] not in fields):
        return f"{root}.NAME has the fields {', '.join(fields)}"
    names = doc.get(root)
    if rest and isinstance(names, dict) and rest[0] not in names:
        if (
            root == "joints"
            and len(rest) == 1
            and any(str(n).startswith(rest[0] + "_") for n in names)
        ):
            return None  # a cell's robot: every joint ROBOT_…
        known = ", ".join(str(n) for n in names if n not in fields) or "none"
        return f"no {_NAMED[root]} '{rest[0]}' in the expectation ({root}: {known})"
    return None


def _option_problem(key: str, value: Any) -> str | None:
    """Why ``value`` cannot be the run option ``key``, else ``None``: the run's own checks
    (:func:`irlc.runtime.run.check_run_option`) and the types of the file options; a long
    value is named by its type, not echoed."""
    from irlc.runtime.run import check_run_option

    shown = _json_value(value)
    if key == "robot":
        ok = isinstance(value, str) and value != ""
        return None if ok else f"expected a robot name or file, got {shown}"
    if key == "datalist_path":
        ok = isinstance(value, str) or (
            isinstance(value, list) and all(isinstance(v, str) for v in value)
        )
        return None if ok else f"expected a folder or a list of folders, got {shown}"
    if key == "allow_any_path":
        return None if isinstance(value, bool) else f"expected true or false, got {shown}"
    problem = check_run_option(key, value)  # it describes the value, never echoes it
    return None if problem is None else problem.replace(f"{key} ", "", 1)


def _json_value(value: Any) -> str:
    """``value`` as JSON when short, else its type (a file's long text is not echoed)."""
    text = json.dumps(value)
    return text if len(text) <= 32 else _json_type(value)


def _json_type(value: Any) -> str:
    names = {dict: "an object", list: "an array", str: "a string", bool: "a boolean"}
    if value is None:
        return "null"
    return names.get(type(value), "a number")


def run_case(
    program: Path, update: bool = False, runner: Runner | None = None, allow_any_path: bool = False
) -> CaseResult:
    """Run one program and check (or, with ``update``, rewrite) its expectations;
    ``allow_any_path`` (``irlc test --allow-any-path``) is that run option for every case."""
    runner = runner or default_runner
    kind = path_kind(program)
    if kind != "file":
        return CaseResult(program, "error", message=f"{program.name}: {_NOT_A_PROGRAM[kind]}")
    json_path, txt_path = expected_paths(program)
    try:
        # anything there but a regular file (a folder, a FIFO) is read and refused
        expected = None if path_kind(json_path) == "missing" else load_expectation(json_path)
    except ExpectationError as e:
        return CaseResult(program, "error", message=str(e))
    user = {k: expected[k] for k in USER_KEYS if expected and k in expected}
    options = dict(user.get("options", {}))
    if options.get("allow_any_path") and not allow_any_path:  # the file is input too
        return CaseResult(program, "error", message=f"{json_path.name}: {LIFT_REFUSED}")
    try:
        if allow_any_path:
            options["allow_any_path"] = True
        report = runner(program, options)
    except Exception as e:
        return CaseResult(program, "error", message=f"{type(e).__name__}: {e}")
    actual = reduce_report(report)
    text = _output_text(report)
    if update:
        try:
            atomic_write_text(json_path, _dump({**actual, **user}))
            if text or txt_path.is_file():
                atomic_write_text(txt_path, text)
        except OSError as e:  # a folder of that name, a read-only folder, a full disk
            reason = f"cannot write {e.filename or json_path}: {e.strerror or e}"
            return CaseResult(program, "error", message=reason)
        return CaseResult(program, "updated", message=_status_note(report, "recorded"))
    if expected is None:
        return CaseResult(program, "missing", message=f"no {json_path.name}; run with --update")
    mismatches = compare(expected, actual, user.get("tolerances"))
    diff: list[str] = []
    if path_kind(txt_path) != "missing":
        try:
            want = read_user_text(txt_path, lambda f, r: ExpectationError(f"{f}: {r}"))
        except ExpectationError as e:
            return CaseResult(program, "error", mismatches, message=str(e))
        if want != text:
            diff = list(
                difflib.unified_diff(
                    want.splitlines(),
                    text.splitlines(),
                    txt_path.name,
                    "actual output",
                    lineterm="",
                )
            )
    if not mismatches and not diff:
        return CaseResult(program, "pass", message=_status_note(report, "expected"))
    return CaseResult(program, "fail", mismatches, diff, _status_note(report, "now"))


def _status_note(report: dict, how: str) -> str:
    """For a case whose result is not a run that went well: what was recorded or is
    expected — a program that does not compile (a data list left behind?) or a failing
    run passes as such, and says so."""
    status = report.get("status")
    if status == "compile_error":
        first = next(iter(report.get("diagnostics") or []), "")
        return f"{how}: it does not compile — {first}" if first else f"{how}: it does not compile"
    if status != "ok":
        message = (report.get("error") or {}).get("message")
        return f"{how}: the run fails — {message}" if message else f"{how}: the run fails"
    return ""


def run_golden(
    directory: Path,
    update: bool = False,
    runner: Runner | None = None,
    jobs: int = 1,
    allow_any_path: bool = False,
):
    """All cases of ``directory`` (``*.irl``, sorted by name); ``jobs`` > 1 runs them on
    that many local processes (the default runner only; same results, same order)."""
    programs = find_programs(directory)
    if jobs <= 1 or runner is not None or len(programs) < 2:
        return [run_case(p, update, runner, allow_any_path) for p in programs]
    from functools import partial

    from irlc.study.runner import ordered_map

    def crashed(program: Path) -> CaseResult:
        return CaseResult(program, "error", message="the worker process died running it")

    one = partial(run_case, update=update, allow_any_path=allow_any_path)
    return ordered_map(one, programs, jobs, crashed)


# --------------------------------------------------------------------------- running


def default_runner(program: Path, options: dict) -> dict:
    """Run ``program`` with the runtime; compile errors become a ``compile_error`` report."""
    from irlc.lang.diagnostics import CompileError
    from irlc.runtime.run import run_file

    try:
        result = run_file(program, **options)
    except CompileError as e:
        return _compile_error_report(program, e.diagnostics)
    diags = getattr(result, "diagnostics", None)
    report = getattr(result, "report", None)
    if report is None and diags:
        return _compile_error_report(program, diags)
    report = dict(report or {})
    if "output" not in report and getattr(result, "output", None) is not None:
        report["output"] = list(result.output)
    return report


def _compile_error_report(program: Path, diagnostics) -> dict:
    heads = []
    for d in diagnostics:
        if getattr(d, "is_error", True):
            head = d.header() if hasattr(d, "header") else str(d)
            heads.append(head.replace(str(program), program.name))
    return {"status": "compile_error", "diagnostics": heads}


# --------------------------------------------------------------------------- rendering


def _show(v: Any) -> str:
    text = json.dumps(v, ensure_ascii=False) if not isinstance(v, str) else v
    return text if len(text) <= 60 else text[:57] + "..."


def _lines(value: Any) -> str:
    """``"12 lines"`` for the printed output (a list of lines), else :func:`_show`."""
    if isinstance(value, list):
        return f"{len(value)} line" + ("" if len(value) == 1 else "s")
    return _show(value)


def render_results(results: list[CaseResult], console) -> None:
    """Print one line per case and, for failures, a table of what changed (rich)."""
    from rich.table import Table
    from rich.text import Text

    style = {"pass": "green", "updated": "cyan", "fail": "red", "missing": "yellow",
             "error": "red"}  # fmt: skip
    for r in results:
        console.print(Text.assemble((f"{r.status.upper():8}", style[r.status]), r.program.name))
        if r.message:  # (a program's name or message is text, never rich markup)
            console.print(f"  {r.message}", markup=False, soft_wrap=True)
        if r.mismatches:
            table = Table(show_header=True, header_style="bold", box=None, padding=(0, 2))
            # the key is what the user looks for: never cut it; values wrap instead
            longest = max(len(m.path) for m in r.mismatches)
            table.add_column("key", no_wrap=True, min_width=longest)
            # values keep their digits together up to 12 characters; the note wraps first
            values = [_show(v) for m in r.mismatches for v in (m.expected, m.actual)]
            widest = min(12, max(map(len, values)))
            table.add_column("expected", overflow="fold", min_width=widest)
            table.add_column("actual", overflow="fold", min_width=widest)
            table.add_column("note", overflow="fold")
            for m in r.mismatches:
                if m.path == "output" and r.output_diff:  # lines: the diff below shows them
                    exp, act = (_lines(v) for v in (m.expected, m.actual))
                    table.add_row(m.path, exp, act, "the diff below")
                    continue
                table.add_row(m.path, _show(m.expected), _show(m.actual), m.note)
            console.print(table)
        for line in r.output_diff:
            colour = "green" if line.startswith("+") else "red" if line.startswith("-") else ""
            console.print(Text("  " + line, style=colour))
    passed = sum(r.ok for r in results)
    failed = len(results) - passed
    summary = f"{passed} passed, {failed} failed" if failed else f"{passed} passed"
    console.print(Text(summary, style="bold red" if failed else "bold green"))
