"""Particle-filter building blocks shared by the chapters: weights, effective sample size, resampling.

Chapter 6 (Li & Chaumette) and chapter 10 (Pantrigo et al.) both weigh, normalise and resample
particles; the three steps live here so that both filters read the same code.
"""

from __future__ import annotations

import numpy as np

from amdo_lab.common.validation import as_finite_array, as_probabilities, check_in_range

__all__ = ["effective_sample_size", "normalised_weights", "systematic_resample"]

#: Log-weights beyond this magnitude are refused: exp of their differences must stay finite.
MAX_LOG_WEIGHT = 1e300


def normalised_weights(log_weights: np.ndarray) -> np.ndarray:
    """Normalised weights ``w_i = exp(l_i) / sum_j exp(l_j)`` from log-weights, without overflow.

    The largest log-weight is subtracted before the exponential (the log-sum-exp trick), so costs of
    thousands of pixels (weights ``exp(-alpha C)`` far below the smallest float) still give weights.

    Parameters
    ----------
    log_weights : numpy.ndarray
        (N,) log-weights, finite (within ±1e300), N >= 1. A caller whose log-weights are computed
        from checked data, and may be -inf for a particle ruled out, calls the kernel
        ``_normalised_weights`` instead (chapter 6's filter does).

    Returns
    -------
    numpy.ndarray
        (N,) non-negative weights summing to 1.

    References
    ----------
    Pantrigo, Sánchez, Gianikellis & Montemayor, AMDO 2004, Sec. 2 (the weights are normalised) and
    eq. (7); Li & Chaumette, AMDO 2004, Fig. 1, step 3.

    Examples
    --------
    >>> normalised_weights(np.array([0.0, np.log(3.0)])).round(2)
    array([0.25, 0.75])
    """
    log_weights = as_finite_array(log_weights, "log_weights", ndim=1, max_abs=MAX_LOG_WEIGHT)
    return _normalised_weights(log_weights)


def _normalised_weights(log_weights: np.ndarray) -> np.ndarray:
    """The kernel of :func:`normalised_weights`, for log-weights computed from checked data: no checks.

    Besides finite log-weights it takes -inf entries (a particle ruled out gets weight exactly 0),
    provided at least one entry is finite: the maximum subtracted is then finite.
    """
    # eq. (15) of Li & Chaumette (eq. 7 of Pantrigo et al.): w_i ∝ exp(l_i), normalised by their sum; the maximum is
    # subtracted first, as exp(-1e4) alone would underflow to 0/0
    shifted = np.exp(log_weights - log_weights.max())
    return shifted / shifted.sum()


def effective_sample_size(weights: np.ndarray) -> float:
    """Effective sample size ``1 / sum_i w_i^2`` of normalised weights: N for equal weights, 1 for one.

    Parameters
    ----------
    weights : numpy.ndarray
        (N,) normalised weights (non-negative, summing to 1).

    Returns
    -------
    float
        The effective sample size, between 1 and N.

    References
    ----------
    Arulampalam et al., IEEE TSP 2002 (ref. [16] of Pantrigo et al., AMDO 2004), the degeneracy measure.

    Examples
    --------
    >>> effective_sample_size(np.full(4, 0.25))
    4.0
    """
    weights = as_probabilities(weights, "weights")
    return float(1.0 / np.sum(weights**2))


def systematic_resample(weights: np.ndarray, u: float) -> np.ndarray:
    """Indices drawn by systematic resampling (Fig. 1, step 5) with one uniform ``u`` in [0, 1).

    The N pointers ``(u + i) / N`` walk through the cumulative weights, so particle i is copied
    ``floor`` or ``ceil`` of ``N w_i`` times: lower variance than N independent draws.

    Parameters
    ----------
    weights : numpy.ndarray
        (N,) normalised weights (non-negative, summing to 1).
    u : float
        One uniform number in [0, 1).

    Returns
    -------
    numpy.ndarray
        (N,) indices of the chosen particles, in increasing order.

    References
    ----------
    Li & Chaumette, AMDO 2004, Fig. 1, step 5; Pantrigo et al., AMDO 2004, Sec. 2 (the selection step).

    Examples
    --------
    >>> systematic_resample(np.array([0.5, 0.25, 0.25]), 0.5)
    array([0, 1, 2])
    """
    weights = as_probabilities(weights, "weights")
    u = check_in_range(u, "u", 0.0, 1.0, closed="left")
    n = len(weights)
    cumulative = np.cumsum(weights)
    cumulative[-1] = 1.0  # guard against round-off
    return np.searchsorted(cumulative, (u + np.arange(n)) / n, side="right").clip(max=n - 1)
