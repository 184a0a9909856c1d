"""Gaussian-mixture EM (Sec. 4, eqs. 2-8), written out so a reader can follow every step."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from amdo_lab.common import MAX_ITERATIONS, as_finite_array, check_positive, check_positive_int
from amdo_lab.pdm_mixtures.pdm import MAX_MAGNITUDE

__all__ = ["GaussianMixtureResult", "fit_gaussian_mixture"]


@dataclass(frozen=True)
class GaussianMixtureResult:
    """A Gaussian mixture after EM, with the last E-step's posteriors and the likelihood history.

    Parameters
    ----------
    weights : (K,) numpy.ndarray
        Mixing weights ``pi_w`` (eq. 5), positive, summing to 1.
    means : (K, d) numpy.ndarray
        Component means ``Y_w`` (eq. 7).
    covariances : (K, d, d) numpy.ndarray
        Component covariances ``Sigma_w`` (eq. 8), ridge included.
    responsibilities : (T, K) numpy.ndarray
        Posteriors ``P(t in w | X_t)`` of the last E-step (eq. 4); rows sum to 1.
    log_likelihood : (n_iter,) numpy.ndarray
        Mean log-likelihood per training vector (eq. 3 divided by T) before each M-step, in nats.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 4, eqs. 2-8.
    """

    weights: np.ndarray
    means: np.ndarray
    covariances: np.ndarray
    responsibilities: np.ndarray
    log_likelihood: np.ndarray


def _check_positive_definite(matrices: np.ndarray, name: str) -> None:
    """Refuse a stack of matrices of which one is not positive definite (its Cholesky factorisation fails)."""
    try:
        np.linalg.cholesky(matrices)
    except np.linalg.LinAlgError:
        raise ValueError(f"{name} must be positive definite (every (d, d) matrix)") from None


def gaussian_log_density_reference(points: np.ndarray, means: np.ndarray, covariances: np.ndarray) -> np.ndarray:
    """Eq. 6 as printed, one component at a time: the reference path of ``_gaussian_log_density``.

    ``ln p(X_t | Y_w, Sigma_w) = -1/2 [ d ln(2 pi) + ln|Sigma_w| + (X_t - Y_w)^T Sigma_w^-1 (X_t - Y_w) ]``
    (the paper's ``(2 pi)^L`` is ``(2 pi)^(d/2)`` for long vectors of ``d = 2L`` coordinates).
    Plain numpy for reading and for the tests (not exported; nothing is validated here).

    Parameters
    ----------
    points : (T, d) numpy.ndarray
        Long-vectors ``X_t`` as rows.
    means : (K, d) numpy.ndarray
        Component means ``Y_w``.
    covariances : (K, d, d) numpy.ndarray
        Symmetric positive-definite component covariances ``Sigma_w``.

    Returns
    -------
    numpy.ndarray
        ``(T, K)`` log-densities, nats.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 4, eq. 6.
    """
    n_dim = points.shape[1]
    out = np.empty((len(points), len(means)))
    for w, (mean, covariance) in enumerate(zip(means, covariances)):
        diff = points - mean  # X_t - Y_w
        # ln of eq. (6): -1/2 [d ln 2π + ln|Σ_w| + (X_t - Y_w)^T Σ_w^-1 (X_t - Y_w)]
        mahalanobis = np.sum(diff @ np.linalg.inv(covariance) * diff, axis=1)
        out[:, w] = -0.5 * (n_dim * np.log(2 * np.pi) + np.linalg.slogdet(covariance)[1] + mahalanobis)
    return out


def _gaussian_log_density(points: np.ndarray, means: np.ndarray, covariances: np.ndarray) -> np.ndarray:
    """Log of eq. 6 for every point ``(T, d)`` and component (means ``(K, d)``, positive-definite
    covariances ``(K, d, d)``): ``(T, K)``, all components at once through Cholesky factors, with no
    explicit inverse. The EM loop's inner call, on checked arrays (not exported)."""
    n_dim = points.shape[1]
    chol = np.linalg.cholesky(covariances)  # (K, d, d)
    diff = points[None, :, :] - means[:, None, :]  # (K, T, d)
    # L^-1 (X_t - Y_w) by one small inverse per component: cheaper than a solve with T right-hand sides
    solved = np.linalg.inv(chol) @ np.swapaxes(diff, 1, 2)  # (K, d, T)
    mahalanobis = np.sum(solved**2, axis=1)  # (K, T)
    log_det = 2.0 * np.sum(np.log(np.diagonal(chol, axis1=1, axis2=2)), axis=1)  # (K,)
    return (-0.5 * (n_dim * np.log(2 * np.pi) + log_det[:, None] + mahalanobis)).T


def fit_gaussian_mixture(
    X: np.ndarray,
    n_components: int,
    *,
    means_init: np.ndarray,
    covariances_init: np.ndarray,
    weights_init: np.ndarray | None = None,
    n_iter: int = 100,
    reg_covar: float = 0.0,
) -> GaussianMixtureResult:
    """Maximum-likelihood Gaussian mixture by EM from a given initialisation.

    Each iteration is an E-step (eq. 4: posteriors by Bayes' rule with the mixing weights of eq. 5)
    followed by an M-step: weights (eq. 5), means (eq. 7) and covariances (eq. 8). Eqs. 7-8 as
    printed omit the normalisation by ``sum_t P(t in w)`` and use the old mean in eq. 8; we use the
    standard ML updates (normalised, new mean), which is what maximises eq. 3 and what
    scikit-learn's ``GaussianMixture`` does. ``reg_covar`` is added to every covariance diagonal.

    Parameters
    ----------
    X : (T, d) array_like
        Training vectors.
    n_components : int
        Number of mixture components K.
    means_init, covariances_init : (K, d) and (K, d, d) array_like
        Starting parameters.
    weights_init : (K,) array_like, optional
        Starting mixing weights (uniform when omitted).
    n_iter : int
        Number of EM iterations, at most ``MAX_ITERATIONS`` (fixed: no tolerance test, so runs are reproducible).
    reg_covar : float
        Non-negative ridge added to covariance diagonals.

    Returns
    -------
    GaussianMixtureResult
        Weights, means and covariances after ``n_iter`` iterations, the responsibilities of the
        last E-step and the mean log-likelihood of each iteration.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 4, eqs. 2-8 (E-step eq. 4, M-step eqs. 5, 7, 8).
    """
    points = as_finite_array(X, "X", ndim=2, max_abs=MAX_MAGNITUDE)
    t, d = points.shape
    k = check_positive_int(n_components, "n_components", maximum=t)  # at most one component per row of X
    n_iter = check_positive_int(n_iter, "n_iter", maximum=MAX_ITERATIONS)
    reg_covar = check_positive(reg_covar, "reg_covar", allow_zero=True)
    means = as_finite_array(means_init, "means_init (like X)", shape=(k, d), max_abs=MAX_MAGNITUDE)
    covariances = as_finite_array(covariances_init, "covariances_init", shape=(k, d, d))
    _check_positive_definite(covariances, "covariances_init")
    weights = np.full(k, 1.0 / k) if weights_init is None else as_finite_array(
        weights_init, "weights_init", shape=(k,), bounds=(0, 1), closed="right")
    if not np.isclose(weights.sum(), 1.0):
        raise ValueError(f"weights_init must sum to 1, got {weights.sum():g}")
    # history: the mean over the patterns of ln sum_w pi_w p(X_t | w), the log-likelihood of eq. (2) with the
    # weights of eq. (5); each M-step below maximises Q of eq. (3) at the posteriors of the E-step.
    history = []
    for _ in range(n_iter):
        # E-step (eq. 4): P(t in w | X_t) = pi_w p(X_t | w) / sum_w' pi_w' p(X_t | w'), in log space.
        log_joint = _gaussian_log_density(points, means, covariances) + np.log(weights)
        log_norm = np.logaddexp.reduce(log_joint, axis=1)
        responsibilities = np.exp(log_joint - log_norm[:, None])
        history.append(float(np.mean(log_norm)))
        # M-step. Eq. 5: pi_w = (1/T) sum_t P(t in w | X_t).
        counts = responsibilities.sum(axis=0) + 10 * np.finfo(float).eps
        weights = counts / t
        # Eq. 7, normalised: Y_w = sum_t P(t in w | X_t) X_t / sum_t P(t in w | X_t).
        means = (responsibilities.T @ points) / counts[:, None]
        # Eq. 8, normalised and about the new mean Y_w.
        diff = points[None, :, :] - means[:, None, :]
        # sum_t P(t in w) (X_t - Y_w)(X_t - Y_w)^T, one matrix product per component
        covariances = np.stack([(responsibilities[:, j, None] * diff[j]).T @ diff[j] for j in range(k)])
        covariances = covariances / counts[:, None, None]
        covariances = covariances + reg_covar * np.eye(d)
    return GaussianMixtureResult(weights, means, covariances, responsibilities, np.asarray(history))


def fit_gaussian_mixtures_batch(points: np.ndarray, means: np.ndarray, covariances: np.ndarray, n_iter: int,
                                 reg_covar: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Fast path: B independent runs of :func:`fit_gaussian_mixture` (uniform start weights) at once.

    The same E- and M-steps (eqs. 4, 5, 7, 8) with one more leading axis, so the recogniser's 13
    limb mixtures cost one loop of ``n_iter`` steps instead of 13; tested equal to the one-run
    function. A kernel for callers that have checked their input (the recogniser): nothing is
    validated here, so a user calls :func:`fit_gaussian_mixture`.

    Parameters
    ----------
    points : (B, T, d) numpy.ndarray
        ``T`` points of dimension ``d`` for each of the ``B`` runs.
    means : (B, K, d) numpy.ndarray
        Starting means of the ``K`` components of each run.
    covariances : (B, K, d, d) numpy.ndarray
        Starting covariances.
    n_iter : int
        Number of EM iterations (fixed, no convergence test).
    reg_covar : (B,) numpy.ndarray
        Ridge added to every covariance's diagonal, per run.

    Returns
    -------
    weights : (B, K) numpy.ndarray
        Mixing weights (eq. 5).
    means : (B, K, d) numpy.ndarray
        Component means (eq. 7).
    covariances : (B, K, d, d) numpy.ndarray
        Component covariances (eq. 8), ridge included.
    responsibilities : (B, T, K) numpy.ndarray
        Posteriors of the last E-step (eq. 4).

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 4, eqs. 4-8.
    """
    b, t, d = points.shape
    k = means.shape[1]
    weights = np.full((b, k), 1.0 / k)
    ridge = reg_covar[:, None, None, None] * np.eye(d)
    for _ in range(n_iter):
        # E-step (eq. 4), every run and component at once.
        chol = np.linalg.cholesky(covariances)  # (B, K, d, d)
        diff = points[:, None, :, :] - means[:, :, None, :]  # (B, K, T, d)
        solved = np.linalg.inv(chol) @ np.swapaxes(diff, -1, -2)  # L^-1 (X - Y): (B, K, d, T)
        log_det = 2.0 * np.sum(np.log(np.diagonal(chol, axis1=-2, axis2=-1)), axis=-1)  # (B, K)
        log_density = -0.5 * (d * np.log(2 * np.pi) + log_det[..., None] + np.sum(solved**2, axis=-2))
        log_joint = np.swapaxes(log_density, 1, 2) + np.log(weights)[:, None, :]  # (B, T, K)
        log_norm = np.logaddexp.reduce(log_joint, axis=2)
        responsibilities = np.exp(log_joint - log_norm[..., None])
        # M-step (eqs. 5, 7, 8), normalised, covariance about the new mean.
        counts = responsibilities.sum(axis=1) + 10 * np.finfo(float).eps  # (B, K)
        weights = counts / t
        means = np.swapaxes(responsibilities, 1, 2) @ points / counts[..., None]
        diff = points[:, None, :, :] - means[:, :, None, :]
        weighted = np.swapaxes(responsibilities, 1, 2)[..., None] * diff  # (B, K, T, d)
        covariances = np.swapaxes(weighted, -1, -2) @ diff / counts[..., None, None] + ridge
    return weights, means, covariances, responsibilities
