"""Every published number of the seeds irlc can compute, laid beside the book's.

One line per reference: the reference first, then irlc's numbers in the book's units and
order, then the book's, the verdict and how the number was obtained::

    (4.23) L-1 line P-K max |e_qs| [rad]: 0.017 0.018 … | book: 0.76 0.76 1.50 … | NOT …

The rows are :mod:`irlc.fidelity`'s (docs/fidelity.md explains them). Usage::

    python bench/fidelity.py                   # every row (≈ 4 min on one core)
    python bench/fidelity.py --fast            # the rows that take seconds
    python bench/fidelity.py --only "(4.23)" O8
    python bench/fidelity.py --write-doc       # + the table of docs/fidelity.md
    python bench/fidelity.py --figures         # + docs/img/fidelity_*.png (extra 'plot')

``--write-doc`` computes every row (``--only`` / ``--fast`` are refused with it) and
rewrites the table between the markers of docs/fidelity.md; tests/tool/test_fidelity.py
checks the table against fresh computations, so the two cannot drift.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from irlc.fidelity.references import all_rows, compute, select
from irlc.fidelity.table import doc_table, line, replace_table

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "fidelity.md"
IMG = ROOT / "docs" / "img"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fast", action="store_true", help="only the rows that take seconds")
    parser.add_argument("--only", nargs="+", default=(), metavar="REF", help="these rows")
    parser.add_argument("--write-doc", action="store_true", help="rewrite docs/fidelity.md")
    parser.add_argument("--figures", action="store_true", help="write docs/img/fidelity_*.png")
    parser.add_argument("--timing", action="store_true", help="print each row's seconds")
    args = parser.parse_args(argv)
    if args.write_doc and (args.only or args.fast):
        parser.error("--write-doc computes every row: drop --only / --fast")
    rows = select(all_rows(), args.only, args.fast)
    if args.only and not rows:
        known = ", ".join(r.ref for r in all_rows())
        parser.error(f"no row named {' or '.join(args.only)} (known: {known})")
    done = []
    for row in rows:
        start = time.perf_counter()
        result = compute(row)
        done.append((row, result))
        took = f"  [{time.perf_counter() - start:.1f} s]" if args.timing else ""
        print(line(row, result) + took, flush=True)
    if args.write_doc:
        DOC.write_text(replace_table(DOC.read_text("utf-8"), doc_table(done)), "utf-8")
        print(f"wrote {DOC.relative_to(ROOT)}", file=sys.stderr)
    if args.figures:
        from irlc.fidelity.figures import write_figures

        for path in write_figures(IMG):
            print(f"wrote {path.relative_to(ROOT)}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
