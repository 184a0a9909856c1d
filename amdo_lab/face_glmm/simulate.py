"""Simulate binomial responses from a known GLMM (for the recovery study)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy.special import expit

from amdo_lab.common import make_rng
from amdo_lab.face_glmm.design import build_design, group_indices, parse_formula

__all__ = ["simulate_binomial_glmm", "RecoverySummary", "summarise_recovery", "recovery_study"]


def simulate_binomial_glmm(table: pd.DataFrame, fixed: str, coefficients: np.ndarray,
                           variances: dict, trials: int, rng) -> np.ndarray:
    """Draw Y ~ Bin(trials, expit(X beta + sum_k b_k)), b_k ~ N(0, variances[k]) per level."""
    gen = make_rng(rng)
    _, terms = parse_formula(fixed)
    x = build_design(table, terms).matrix
    coefficients = np.asarray(coefficients, dtype=float)
    if coefficients.shape != (x.shape[1],):
        raise ValueError(f"coefficients must have shape ({x.shape[1]},), got {coefficients.shape}")
    eta = x @ coefficients
    for term, variance in variances.items():
        if variance < 0:
            raise ValueError(f"variances[{term!r}] must be >= 0, got {variance}")
        idx = group_indices(table, term)
        eta = eta + np.sqrt(variance) * gen.standard_normal(idx.max() + 1)[idx]
    return gen.binomial(trials, expit(eta))


@dataclass(frozen=True)
class RecoverySummary:
    """Bias and Wald-interval coverage over simulation replicates."""

    table: pd.DataFrame  # per coefficient: true, mean estimate, bias, relative bias, coverage


def summarise_recovery(true: pd.Series, estimates: np.ndarray, ses: np.ndarray, level: float = 0.95) -> RecoverySummary:
    """Per-coefficient bias, |bias| / |true| and the share of intervals covering the truth."""
    from scipy import stats

    z = stats.norm.ppf(0.5 + level / 2)
    covered = np.abs(estimates - true.to_numpy()) <= z * ses
    mean = estimates.mean(axis=0)
    frame = pd.DataFrame({"true": true.to_numpy(), "mean_estimate": mean, "bias": mean - true.to_numpy(),
                          "coverage": covered.mean(axis=0)}, index=true.index)
    frame["relative_bias"] = np.abs(frame["bias"]) / np.abs(frame["true"])
    return RecoverySummary(frame)


def recovery_study(table: pd.DataFrame, fixed: str, coefficients: pd.Series, variances: dict,
                   n_replicates: int, rng, trials: int = 30, level: float = 0.95) -> tuple[RecoverySummary, pd.DataFrame]:
    """Simulate ``n_replicates`` responses from known effects, refit each, summarise.

    Returns the per-coefficient summary and a frame of fitted variance components.
    """
    from amdo_lab.common import spawn_rngs
    from amdo_lab.face_glmm.glmm import fit_binomial_glmm

    if not isinstance(rng, int):
        raise TypeError("rng must be an int seed for recovery_study")
    estimates, ses, components = [], [], []
    for gen in spawn_rngs(rng, n_replicates):
        sim = table.assign(Y=simulate_binomial_glmm(table, fixed, coefficients.to_numpy(), variances, trials, gen))
        fit = fit_binomial_glmm(sim, fixed, list(variances), trials)
        estimates.append(fit.coefficients.to_numpy())
        ses.append(np.sqrt(np.diag(fit.covariance.to_numpy())))
        components.append(fit.variance_components)
    return summarise_recovery(coefficients, np.array(estimates), np.array(ses), level), pd.DataFrame(components)
