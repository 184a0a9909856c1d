"""Simulate binomial responses from a known GLMM (for the recovery study)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy.special import expit

from amdo_lab.common import MAX_ITERATIONS, MAX_SAMPLES, as_finite_array, check_dataframe, check_in_range, check_instance, check_positive, check_positive_int, make_rng
from amdo_lab.face_glmm.laplace import MAX_ABS_ETA
from amdo_lab.face_glmm.design import _build_design, group_indices, parse_formula

__all__ = ["simulate_binomial_glmm", "RecoverySummary", "recovery_study"]


def simulate_binomial_glmm(table: pd.DataFrame, fixed: str, coefficients: np.ndarray,
                           variances: dict, n_trials: int, *, rng: int | np.random.Generator) -> np.ndarray:
    """Draw responses from a known GLMM: Y ~ Bin(n, expit(X beta + sum_k b_k)), b_k ~ N(0, sigma_k^2).

    One random intercept is drawn per level of each grouping term, in the order of ``variances``,
    then the binomial responses.

    Parameters
    ----------
    table : pandas.DataFrame
        The rows to simulate, with every column ``fixed`` and the grouping terms name.
    fixed : str
        Fixed-effects formula (see :func:`parse_formula`); its response name is not used.
    coefficients : array_like, shape (n_columns,)
        Finite beta, one entry per column of the design of ``fixed`` (logit scale), each within ±1e6.
    variances : dict
        Grouping term (``"t"``, ``"p"``, ``"t:p"``) -> finite variance sigma_k^2 >= 0; may be empty.
    n_trials : int
        Binomial size n of every row, 1 to :data:`amdo_lab.common.MAX_SAMPLES` (1,000,000).
    rng : int or numpy.random.Generator
        Seed or generator (via :func:`amdo_lab.common.make_rng`).

    Returns
    -------
    ndarray of int, shape (len(table),)
        Success counts in [0, n_trials].

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, eq. (2) (the model simulated).

    Examples
    --------
    >>> import pandas as pd
    >>> from amdo_lab.face_glmm import simulate_binomial_glmm
    >>> table = pd.DataFrame({"p": [0, 0, 1, 1], "M": ["l2", "soft_l2", "l2", "soft_l2"]})
    >>> counts = simulate_binomial_glmm(table, "Y ~ M", [1.0, -0.5], {"p": 1.0}, 30, rng=0)
    >>> counts.shape, bool(((counts >= 0) & (counts <= 30)).all())
    ((4,), True)
    """
    n_trials = check_positive_int(n_trials, "n_trials", maximum=MAX_SAMPLES)
    _check_variances(variances)
    gen = make_rng(rng, "rng")
    _, terms = parse_formula(fixed)
    x = _build_design(table, terms).matrix
    coefficients = as_finite_array(coefficients, "coefficients", shape=(x.shape[1],), max_abs=MAX_ABS_ETA)
    eta = x @ coefficients
    for term, variance in variances.items():
        idx = group_indices(table, term)
        eta = eta + np.sqrt(variance) * gen.standard_normal(idx.max() + 1)[idx]
    return gen.binomial(n_trials, expit(eta))


@dataclass(frozen=True)
class RecoverySummary:
    """Bias and Wald-interval coverage of simulation replicates.

    Parameters
    ----------
    table : pandas.DataFrame
        Indexed by coefficient, with ``true``, ``mean_estimate``, ``bias`` (mean estimate - true),
        ``coverage`` (share of replicates whose interval covers the truth, in [0, 1]) and
        ``relative_bias`` (|bias| / |true|; inf or NaN where the true value is 0).

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, eq. (2) (the model whose estimates are checked).
    """

    table: pd.DataFrame  # per coefficient: true, mean estimate, bias, relative bias, coverage


def _summarise_recovery(true: pd.Series, estimates: np.ndarray, ses: np.ndarray, level: float) -> RecoverySummary:
    """Per-coefficient bias, relative bias and the share of Wald intervals ``estimate +- z se`` (z the
    normal quantile of ``level``) covering the truth, from the ``(n_replicates, p)`` estimates and
    standard errors of :func:`recovery_study`'s refits (checked there)."""
    from scipy import stats

    z = stats.norm.ppf(0.5 + level / 2)
    covered = np.abs(estimates - true.to_numpy()) <= z * ses
    mean = estimates.mean(axis=0)
    frame = pd.DataFrame({"true": true.to_numpy(), "mean_estimate": mean, "bias": mean - true.to_numpy(),
                          "coverage": covered.mean(axis=0)}, index=true.index)
    frame["relative_bias"] = np.abs(frame["bias"]) / np.abs(frame["true"])
    return RecoverySummary(frame)


def recovery_study(table: pd.DataFrame, fixed: str, coefficients: pd.Series, variances: dict,
                   n_replicates: int, *, rng: int | np.random.Generator, n_trials: int = 30, level: float = 0.95) -> tuple[RecoverySummary, pd.DataFrame]:
    """Simulate ``n_replicates`` tables from known effects, refit each, summarise bias and coverage.

    Every input is checked before the first (slow) refit. Replicate k draws from the k-th generator
    spawned from ``rng``, so it is the same whatever the number of replicates.

    Parameters
    ----------
    table : pandas.DataFrame
        The design rows to simulate on (the factors and grouping columns).
    fixed : str
        Fixed-effects formula, simulated and refitted.
    coefficients : pandas.Series
        True beta, named like the fit's columns (e.g. a previous fit's ``coefficients``).
    variances : dict
        Grouping term -> true variance sigma_k^2 >= 0; at least one term (the refits need one).
    n_replicates : int
        Number of simulated tables, 1 to :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).
    rng : int or numpy.random.Generator
        Seed or generator (via :func:`amdo_lab.common.make_rng`).
    n_trials : int, default 30
        Binomial size n of every row, 1 to :data:`amdo_lab.common.MAX_SAMPLES` (1,000,000).
    level : float, default 0.95
        Wald interval level in (0, 1).

    Returns
    -------
    summary : RecoverySummary
        Bias and coverage per coefficient.
    components : pandas.DataFrame
        One row per replicate, one column per grouping term: the fitted variances.

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, eq. (2) (the model whose fit is checked).
    """
    from amdo_lab.common import spawn_rngs
    from amdo_lab.face_glmm.glmm import fit_binomial_glmm

    # Everything is checked before the first (slow) refit (n_trials by the first simulation).
    gen = make_rng(rng, "rng")
    check_dataframe(table, "table")
    check_instance(coefficients, "coefficients", pd.Series, what="a pandas Series (named like the fit's)")
    _check_variances(variances)
    check_positive_int(len(variances), "the terms of variances (the refits need a random effect)")
    n_replicates = check_positive_int(n_replicates, "n_replicates", maximum=MAX_ITERATIONS)
    check_in_range(level, "level", 0, 1)
    estimates, ses, components = [], [], []
    for replicate_rng in spawn_rngs(gen, n_replicates):
        sim = table.assign(Y=simulate_binomial_glmm(table, fixed, coefficients.to_numpy(), variances, n_trials,
                                                    rng=replicate_rng))
        fit = fit_binomial_glmm(sim, fixed, list(variances), n_trials)
        estimates.append(fit.coefficients.to_numpy())
        ses.append(np.sqrt(np.diag(fit.covariance.to_numpy())))
        components.append(fit.variance_components)
    return _summarise_recovery(coefficients, np.array(estimates), np.array(ses), level), pd.DataFrame(components)


def _check_variances(variances: object) -> None:
    check_instance(variances, "variances", Mapping, what="a mapping of grouping terms to variances")
    for term, variance in variances.items():
        check_positive(variance, f"variances[{term!r}]", allow_zero=True)

