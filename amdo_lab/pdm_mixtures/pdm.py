"""Point distribution models (Sec. 2) and generalised Procrustes alignment of landmark sets."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from amdo_lab.common import as_finite_array, check_positive_int, procrustes_align

__all__ = [
    "PointDistributionModel",
    "fit_pdm",
    "pdm_from_moments",
    "fit_modes",
    "reconstruct",
    "generalized_procrustes",
    "normalise_shape",
]


@dataclass(frozen=True)
class PointDistributionModel:
    """Mean long-vector ``mean (D,)``, modal matrix ``modes (D, M)`` (columns = eigenvectors),
    eigenvalues ``variances (M,)`` and the mean discarded eigenvalue ``residual_variance``."""

    mean: np.ndarray
    modes: np.ndarray
    variances: np.ndarray
    residual_variance: float

    @property
    def n_modes(self) -> int:
        return int(self.modes.shape[1])


def pdm_from_moments(
    mean: np.ndarray, covariance: np.ndarray, *, variance_fraction: float = 0.95, max_modes: int | None = None,
    min_residual_variance: float = 1e-12,
) -> PointDistributionModel:
    """Build a PDM from a mean and covariance: keep the leading eigenmodes of ``covariance``
    (``Sigma phi = alpha phi``) that explain ``variance_fraction`` of the variance."""
    eigenvalues, eigenvectors = np.linalg.eigh(covariance)
    order = np.argsort(eigenvalues)[::-1]
    eigenvalues = np.clip(eigenvalues[order], 0.0, None)  # round-off negatives of a PSD matrix
    eigenvectors = eigenvectors[:, order]
    total = eigenvalues.sum()
    n_modes = int(np.searchsorted(np.cumsum(eigenvalues), variance_fraction * total) + 1) if total > 0 else 1
    limit = len(eigenvalues) - 1 if max_modes is None else min(max_modes, len(eigenvalues) - 1)
    n_modes = max(1, min(n_modes, limit))
    residual = float(max(eigenvalues[n_modes:].mean(), min_residual_variance))
    return PointDistributionModel(np.asarray(mean, float), eigenvectors[:, :n_modes], eigenvalues[:n_modes], residual)


def fit_pdm(long_vectors: np.ndarray, *, variance_fraction: float = 0.95, max_modes: int | None = None) -> PointDistributionModel:
    """PDM of a training set ``(T, D)``: mean ``Y``, covariance of eq. 1 (1/T), leading eigenmodes.

    At most ``T - 1`` modes are kept (the rank of eq. 1), so the residual variance is positive.
    """
    vectors = as_finite_array(long_vectors, "long_vectors", ndim=2)
    t = vectors.shape[0]
    if t < 3:
        raise ValueError(f"long_vectors needs at least 3 training examples for a covariance, got {t}")
    mean = vectors.mean(axis=0)
    centred = vectors - mean
    covariance = centred.T @ centred / t  # eq. 1
    cap = t - 1 if max_modes is None else min(max_modes, t - 1)
    return pdm_from_moments(mean, covariance, variance_fraction=variance_fraction, max_modes=cap)


def fit_modes(model: PointDistributionModel, observed: np.ndarray, *, clamp: bool = True) -> np.ndarray:
    """Least-squares modal coefficients ``gamma = Phi^T (X_o - Y)`` for rows of ``observed``.

    The paper prints ``1/2 (Phi + Phi^T)(X_o - Y)``, which is not even defined for a non-square
    Phi; for orthonormal modes the least-squares solution is ``Phi^T (X_o - Y)``. With ``clamp``,
    each coefficient is limited to ``+-3 sqrt(alpha_k)`` (Sec. 4).
    """
    gamma = (observed - model.mean) @ model.modes
    if clamp:
        bound = 3.0 * np.sqrt(model.variances)
        gamma = np.clip(gamma, -bound, bound)
    return gamma


def reconstruct(model: PointDistributionModel, gamma: np.ndarray) -> np.ndarray:
    """Model instance ``X_hat = Y + Phi gamma``."""
    return model.mean + gamma @ model.modes.T


def normalise_shape(points: np.ndarray) -> np.ndarray:
    """Centre a point set ``(L, 2)`` and scale it to unit centroid size."""
    centred = points - points.mean(axis=0)
    return centred / np.sqrt(np.sum(centred**2))


def generalized_procrustes(point_sets: np.ndarray, *, n_iter: int = 5) -> tuple[np.ndarray, np.ndarray]:
    """Align ``(T, L, 2)`` point sets to their common mean by iterated similarity Procrustes.

    Returns ``(aligned (T, L, 2), reference (L, 2))``; the reference has unit centroid size and
    is re-aligned to its predecessor each round so its orientation does not drift.
    """
    sets = as_finite_array(point_sets, "point_sets", shape=(None, None, 2))
    check_positive_int(n_iter, "n_iter")
    reference = normalise_shape(sets[0])
    aligned = sets
    for _ in range(n_iter):
        aligned = align_to_reference(sets, reference)
        new_reference = normalise_shape(aligned.mean(axis=0))
        reference = procrustes_align(new_reference, reference).aligned
        reference = normalise_shape(reference)
    return align_to_reference(sets, reference), reference


def align_to_reference(point_sets: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Similarity-align every ``(L, 2)`` set in ``point_sets`` onto ``reference`` (Procrustes)."""
    return np.stack([procrustes_align(points, reference).aligned for points in point_sets])
