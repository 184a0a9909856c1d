"""One way to make seeded random generators, used by every notebook and data generator."""

from __future__ import annotations

import numpy as np

from amdo_lab.common.validation import check_positive_int, check_seed

__all__ = ["MAX_GENERATORS", "make_rng", "spawn_rngs"]

#: Most generators :func:`spawn_rngs` makes at once (one per trial or frame; 100,000 take about a second).
MAX_GENERATORS = 100_000


def make_rng(seed: int | np.random.Generator, name: str = "seed") -> np.random.Generator:
    """Return a ``numpy.random.Generator`` for an explicit integer seed.

    Parameters
    ----------
    seed : int or numpy.random.Generator
        A non-negative integer seed, or a generator, which is returned as it is (so functions can
        accept either). ``None`` is refused: every random draw in the workbook is reproducible.
    name : str
        The caller's argument name, used in error messages (a function's ``rng`` argument passes
        ``"rng"``).

    Returns
    -------
    numpy.random.Generator
        A PCG64 generator.
    """
    if isinstance(seed, np.random.Generator):
        return seed
    return np.random.default_rng(check_seed(seed, name))


def spawn_rngs(seed: int | np.random.Generator, n: int) -> list[np.random.Generator]:
    """Return ``n`` statistically independent generators derived from one seed.

    Use this for trials of a benchmark or frames of a sequence: trial ``k`` gets the same stream
    whatever the number of trials run before it.

    Parameters
    ----------
    seed : int or numpy.random.Generator
        As for :func:`make_rng`.
    n : int
        Number of generators, from 1 to :data:`MAX_GENERATORS`.

    Returns
    -------
    list of numpy.random.Generator
        ``n`` independent generators.
    """
    n = check_positive_int(n, "n", maximum=MAX_GENERATORS)
    return list(make_rng(seed).spawn(n))
