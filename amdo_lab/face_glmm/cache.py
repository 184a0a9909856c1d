"""Cache the factorial experiment's table under build/ (git-ignored); recompute when absent.

The file name carries a key that hashes everything the table depends on: the design, the seed
and the source code of the modules that generate the faces and run the recogniser. Editing any of
them (a generator constant, a preprocessing step, a distance) gives a new key, so the experiment
is run again instead of an old table being returned.
"""

from __future__ import annotations

import hashlib
import importlib
import inspect
import os
from pathlib import Path
from types import ModuleType

import numpy as np
import pandas as pd

from amdo_lab.common import check_instance, make_rng
from amdo_lab.face_glmm.experiment import FactorialDesign, run_factorial_experiment

__all__ = ["load_or_run_experiment", "RESULT_MODULES"]

#: The modules whose code determines the experiment's table: the driver, the face generator
#: with its preprocessing, and the PCA+LDA recogniser.
RESULT_MODULES = ("amdo_lab.face_glmm.experiment", "amdo_lab.face_glmm.population",
                  "amdo_lab.face_glmm.pcalda")


def _module_source(module: str | ModuleType) -> str:
    """The source text of a module given as an object or a dotted name."""
    return inspect.getsource(importlib.import_module(module) if isinstance(module, str) else module)


def _experiment_cache_key(design: FactorialDesign, *, rng: int | np.random.Generator,
                          modules: tuple[str | ModuleType, ...] = RESULT_MODULES) -> str:
    """A 16-hex-digit key hashing the design, the seed and the source of ``modules``.

    Parameters
    ----------
    design : FactorialDesign
        The experiment's sizes and population settings.
    rng : int or numpy.random.Generator
        The experiment's seed: a non-negative int, keyed as the number, or a generator, keyed on its
        seed sequence (entropy, spawn key, children spawned) and its bit generator's state.
    modules : tuple of modules or dotted names, default RESULT_MODULES
        Whose source text enters the key; the order matters.

    Returns
    -------
    str
        16 lowercase hexadecimal digits (the start of a SHA-256 digest).

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, Sec. 4 and Table 1 (the experiment the key stands for).
    """
    digest = hashlib.sha256()
    digest.update(repr((design, sorted(design.population_kwargs.items()), _rng_key(rng))).encode())
    for module in modules:
        digest.update(b"\0module\0")
        digest.update(_module_source(module).encode())
    return digest.hexdigest()[:16]


def load_or_run_experiment(design: FactorialDesign, cache_dir: str | Path, *,
                           rng: int | np.random.Generator) -> tuple[pd.DataFrame, bool]:
    """Return the table of :func:`run_factorial_experiment` from the cache, or compute and store it.

    The table is read from ``cache_dir`` when a file with the same ``_experiment_cache_key``
    exists, and otherwise computed and written there. A generator passed as ``rng`` is advanced
    (it spawns the experiment's streams) only when the table is computed.

    Parameters
    ----------
    design : FactorialDesign
        The experiment's sizes and population settings.
    cache_dir : str or pathlib.Path
        Directory of the cached tables (created when absent).
    rng : int or numpy.random.Generator
        Seed or generator of the experiment (via :func:`amdo_lab.common.make_rng`).

    Returns
    -------
    table : pandas.DataFrame
        The response table (see :func:`run_factorial_experiment`).
    loaded_from_cache : bool
        True when the table was read, False when it was computed.

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, Sec. 4 and Table 1 (the factorial experiment).
    """
    check_instance(design, "design", FactorialDesign, what="a FactorialDesign")
    check_instance(cache_dir, "cache_dir", (str, os.PathLike), what="a path (str or pathlib.Path)")
    key = _experiment_cache_key(design, rng=rng, modules=RESULT_MODULES)  # refuses a bad rng, naming it
    path = Path(cache_dir) / f"face_glmm_experiment_{key}.pkl"
    if path.exists():
        return pd.read_pickle(path), True
    table = run_factorial_experiment(design, rng=rng)
    path.parent.mkdir(parents=True, exist_ok=True)
    table.to_pickle(path)
    return table, False


def _rng_key(rng: object) -> object:
    """What of ``rng`` fixes the experiment's draws: the int seed, or a generator's seed sequence and state.

    The experiment spawns its streams from the generator's seed sequence, so a generator is keyed on
    that sequence (entropy, spawn key, children already spawned) and on its bit generator's state.
    """
    gen = make_rng(rng, "rng")  # refuses anything but a non-negative int or a Generator, naming rng
    if rng is not gen:
        return int(rng)  # an int seed: keyed as the number itself
    seq = gen.bit_generator.seed_seq
    return ("Generator", seq.entropy, seq.spawn_key, seq.n_children_spawned, repr(gen.bit_generator.state))
