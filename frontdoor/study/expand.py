"""The variants of a study, in their fixed order (the order of the rows of results.csv).

* ``[grid]``: every combination of the listed values; the first key varies slowest
  (``itertools.product`` over the keys in file order).
* ``[random]``: ``n`` samples; key ``k`` (file order) draws its ``n`` values at once from
  ``numpy.random.Generator(PCG64(seed))`` — ``uniform(a, b)`` on [a, b), ``normal(mu,
  sigma)`` — so sample ``i`` is the same on every machine and for every worker count.
* both: grid-major — variant ``g·n + i`` is grid point ``g`` with random sample ``i``.

A variant is ``(index, values)`` with ``values`` in the order of :attr:`Study.keys`.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator

import numpy as np
from irlc.study.spec import Study

Variant = tuple[int, tuple]


def random_samples(study: Study) -> list[tuple[float, ...]]:
    """The ``n`` random samples (one tuple of values per sample, keys in file order)."""
    if not study.random:
        return [()]
    rng = np.random.Generator(np.random.PCG64(study.seed))
    columns = []
    for axis in study.random:
        a, b = axis.params
        draw = (
            rng.uniform(a, b, study.n)
            if axis.distribution == "uniform"
            else rng.normal(a, b, study.n)
        )
        columns.append([float(v) for v in draw])
    return list(zip(*columns, strict=True))


def variants(study: Study) -> Iterator[Variant]:
    """All variants in order (see the module doc)."""
    samples = random_samples(study)
    grid = itertools.product(*(a.values for a in study.grid)) if study.grid else [()]
    index = 0
    for point in grid:
        for sample in samples:
            yield index, (*point, *sample)
            index += 1


def axis_values(study: Study) -> dict[str, list]:
    """Per key, the values to check before anything runs: a grid's listed values; for a
    random key the smallest and the largest sample (ranges are intervals, so the extremes
    decide)."""
    out: dict[str, list] = {a.key: list(a.values) for a in study.grid}
    samples = random_samples(study)
    for k, axis in enumerate(study.random):
        col = [s[k] for s in samples]
        out[axis.key] = sorted({min(col), max(col)})
    return out
