"""Compile-time benchmark: generate a 10,000-line IRL program, time check + compile.

Goals: < 2 s for 10,000 lines (issue 2); a 1 MB program (``--mb 1``, about 48,000 lines)
at >= 10,000 lines/s, i.e. compile time linear in the program's length (issue 11). Usage::

    python bench/bench_compile.py [--lines 10000 | --mb 1] [--repeat 3]

The program mixes declarations, routines, expressions, control flow, motion and the
redundancy constructs (about one statement per line). Times: the first compile in a fresh
process (includes building the LALR tables) and the best of the repeats.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable

from irlc.lang import SimpleRobot, compile_source, write_code

ROBOT = SimpleRobot("koch11", ("revolute",) * 9 + ("prismatic", "revolute"))
K = "(2.158, -75, -102, 110.633, -91.115, -121.5, 99.792, 47.095, -76.742, 18.11, 39.975)"


def block(i: int) -> list[str]:
    """One 20-line unit of statements."""
    return [
        f"  x := x + {i} * 0.5 - y / 3;",
        "  IF x > 1000 THEN",
        "    x := 0;",
        "  ELSIF x < -1000 THEN",
        "    x := 1;",
        "  ELSE",
        "    y := y + 1;",
        "  ENDIF;",
        f"  FOR i := 1 TO {i % 5 + 1} DO",
        "    y := y + SIN(x) * COS(y);",
        "  ENDFOR;",
        f"  p := (11500, {i % 900}, 3500, 0, 0, 0);",
        "  MOVE LIN p WITH SPEED := 500;",
        "  JOINTLIMIT lo, hi;",
        "  MOVE LIN p, q WITH RECONFIGURATION (k, k);",
        "  JOINTLIMITEND;",
        "  CYCLICSTART;",
        "  corner(p);",
        "  CYCLICEND;",
        "  WRITELN('step ', i, ' ', x);",
    ]


def program_of_size(megabytes: float) -> str:
    """The generated program with the most lines whose UTF-8 size is <= ``megabytes``."""
    target = int(megabytes * 1_000_000)
    per_line = len(program(2000).encode()) / 2000
    lines = int(target / per_line)
    while len(program(lines).encode()) > target:
        lines -= 20
    return program(lines)


def program(lines: int) -> str:
    head = [
        "PROGRAM bench;",
        "ROBOT r := koch11;",
        "VAR REAL: x, y; INTEGER: i; POSE: p, q; MAIN_JOINT: k;",
        "  MAIN_JOINT_MIN: lo; MAIN_JOINT_MAX: hi;",
        "PROCEDURE corner(POSE: c);",
        "BEGIN",
        "  MOVE LIN c;",
        "ENDPROC;",
        "BEGIN",
        "  x := 0; y := 0;",
        "  q := (11000, 0, 3500, 0, 0, 0);",
        f"  k := {K};",
        "  lo := (-180, -150, -180, 0, -180, -180, -180, -60, -180, -500, -20);",
        "  hi := (180, 0, 0, 180, 0, 0, 180, 60, 180, 500, 60);",
    ]
    body: list[str] = []
    i = 0
    while len(head) + len(body) + 20 + 1 <= lines:  # whole 20-line blocks ...
        body += block(i)
        i += 1
    while len(head) + len(body) + 1 < lines:  # ... then pad to the exact line count
        body.append("  x := x + 1;")
    return "\n".join([*head, *body, "ENDPROGRAM"]) + "\n"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    size = ap.add_mutually_exclusive_group()
    size.add_argument("--lines", type=int, default=10_000)
    size.add_argument("--mb", type=float, default=None, help="program size in MB instead")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    text = program(args.lines) if args.mb is None else program_of_size(args.mb)
    n_lines = text.count("\n")

    def run(clock: Callable[[], float] = time.perf_counter) -> tuple[float, int]:
        t0 = clock()
        result = compile_source(text, "bench.irl", resolve_robot=lambda name: ROBOT)
        dt = clock() - t0
        if not result.ok:
            raise SystemExit("benchmark program does not compile: " + result.errors[0].header())
        return dt, len(result.code.code)

    first, n_ins = run()
    best = min(run()[0] for _ in range(args.repeat))
    cpu = min(run(time.process_time)[0] for _ in range(args.repeat))
    t0 = time.perf_counter()
    write_code(compile_source(text, "bench.irl", resolve_robot=lambda name: ROBOT).code)
    with_write = time.perf_counter() - t0
    print(f"lines: {n_lines}, bytes: {len(text.encode()):,}, instructions: {n_ins}")
    print(f"first compile (incl. LALR table build): {first:.3f} s")
    print(f"best of {args.repeat} check+compile: {best:.3f} s  ({n_lines / best:,.0f} lines/s)")
    print(f"best of {args.repeat} check+compile, CPU: {cpu:.3f} s  ({n_lines / cpu:,.0f} lines/s)")
    print(f"check+compile+write_code: {with_write:.3f} s")
    if args.mb is None:
        print("goal < 2 s:", "met" if max(first, best) < 2.0 else "NOT met")
    else:
        print("goal >= 10,000 lines/s:", "met" if n_lines / best >= 10_000 else "NOT met")


if __name__ == "__main__":
    main()
