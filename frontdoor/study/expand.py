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


CHUNK = 65_536  # samples drawn at a time: memory stays bounded for n up to 10,000,000


def _draw(rng: np.random.Generator, axis, count: int) -> np.ndarray:
    a, b = axis.params
    if axis.distribution == "uniform":
        return rng.uniform(a, b, count)
    return rng.normal(a, b, count)


def _column(study: Study, k: int) -> Iterator[np.ndarray]:
    """Random key ``k``'s ``n`` values, in pieces of at most :data:`CHUNK`: the stream
    drawn once for the keys before it (and dropped), then its own. A Generator's draws in
    pieces are the draws at once (uniform and normal consume the stream value by value),
    so the values are the documented ones without holding ``n`` of them."""
    rng = np.random.Generator(np.random.PCG64(study.seed))
    for axis in study.random[: k + 1]:
        mine = axis is study.random[k]
        for start in range(0, study.n, CHUNK):
            piece = _draw(rng, axis, min(CHUNK, study.n - start))
            if mine:
                yield piece


def random_samples(study: Study) -> Iterator[tuple[float, ...]]:
    """The ``n`` random samples in order (one tuple of values per sample, keys in file
    order), made as they are used: a 10-million-sample study held ≈ 1.1 GB of tuples
    before its first row when they were made at once."""
    if not study.random:
        yield ()
        return
    columns = [_column(study, k) for k in range(len(study.random))]
    for pieces in zip(*columns, strict=True):
        yield from zip(*(piece.tolist() for piece in pieces), strict=True)


def variants(study: Study) -> Iterator[Variant]:
    """All variants in order (see the module doc), made as they are used: the random
    samples are drawn again for each grid point (the same stream each time)."""
    grid = itertools.product(*(a.values for a in study.grid)) if study.grid else [()]
    index = 0
    for point in grid:
        for sample in random_samples(study):
            yield index, (*point, *sample)
            index += 1


def axis_values(study: Study) -> dict[str, list]:
    """Per key, the values to check before anything runs: a grid's listed values; for a
    random key the smallest and the largest sample (ranges are intervals, so the extremes
    decide), found piece by piece."""
    out: dict[str, list] = {a.key: list(a.values) for a in study.grid}
    for k, axis in enumerate(study.random):
        low, high = np.inf, -np.inf
        for piece in _column(study, k):
            low, high = min(low, float(piece.min())), max(high, float(piece.max()))
        out[axis.key] = sorted({low, high})
    return out
