"""Cache the factorial experiment's table under build/ (git-ignored); recompute when absent."""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

import pandas as pd

from amdo_lab.face_glmm.experiment import FactorialDesign, run_factorial_experiment

__all__ = ["load_or_run_experiment"]


def load_or_run_experiment(design: FactorialDesign, seed: int, cache_dir: str | Path) -> tuple[pd.DataFrame, bool]:
    """Return (table, loaded_from_cache). The cache key hashes the design and the seed."""
    if not isinstance(design, FactorialDesign):
        raise TypeError(f"design must be a FactorialDesign, got {type(design).__name__}")
    if not isinstance(seed, int) or isinstance(seed, bool):
        raise TypeError(f"seed must be an int, got {type(seed).__name__}")
    if not isinstance(cache_dir, (str, os.PathLike)):
        raise TypeError(f"cache_dir must be a path (str or pathlib.Path), got {type(cache_dir).__name__}")
    key = hashlib.sha1(repr((design, sorted(design.population_kwargs.items()), seed)).encode()).hexdigest()[:12]
    path = Path(cache_dir) / f"face_glmm_experiment_{key}.pkl"
    if path.exists():
        return pd.read_pickle(path), True
    table = run_factorial_experiment(design, seed)
    path.parent.mkdir(parents=True, exist_ok=True)
    table.to_pickle(path)
    return table, False
