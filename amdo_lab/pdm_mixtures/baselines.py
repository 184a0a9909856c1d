"""Baselines on the same data (Beyond the paper) and the embeddings used for Figs. 7-9."""

from __future__ import annotations

import numpy as np

from amdo_lab.common import as_finite_array, check_positive_int, procrustes_align
from amdo_lab.pdm_mixtures.pdm import (
    _check_labels,
    _align_to_reference,
    _check_point_set_sizes,
    _check_variance_fraction,
    _ppca_log_density,
    fit_pdm,
    generalized_procrustes,
)

__all__ = [
    "SingleCartesianPDMClassifier",
    "NearestProcrustesMeanClassifier",
    "SklearnGMMClassifier",
    "classical_mds",
    "pca_embedding",
    "pairwise_distances",
]


def _check(shapes: object) -> np.ndarray:
    shapes = as_finite_array(shapes, "shapes", shape=(None, 13, None, 2))
    _check_point_set_sizes(shapes.reshape(len(shapes), -1, 2), "shapes")
    return shapes


def _check_fitted(classifier: object) -> None:
    if not hasattr(classifier, "classes_"):
        raise ValueError(f"the {type(classifier).__name__} must be fitted before it scores or predicts shapes")


def _check_landmarks(shapes: np.ndarray, n_points: int) -> None:
    """``shapes`` have as many landmarks (``n_points`` in all) as the training shapes."""
    if shapes.shape[1] * shapes.shape[2] != n_points:
        raise ValueError(f"shapes must have {n_points // shapes.shape[1]} landmarks per limb (as in training), "
                         f"got {shapes.shape[2]}")


class SingleCartesianPDMClassifier:
    """One Cartesian PDM per class on Procrustes-aligned landmark long-vectors; class = highest
    PPCA log-likelihood (:func:`~amdo_lab.pdm_mixtures.pdm.ppca_log_density`)."""

    def __init__(self, variance_fraction: float = 0.95) -> None:
        self.variance_fraction = _check_variance_fraction(variance_fraction)

    def fit(self, shapes: np.ndarray, labels: np.ndarray) -> "SingleCartesianPDMClassifier":
        shapes = _check(shapes)
        aligned, self.reference_ = generalized_procrustes(shapes.reshape(len(shapes), -1, 2))
        vectors = aligned.reshape(len(shapes), -1)
        labels = _check_labels(labels, len(shapes))
        self.classes_ = tuple(dict.fromkeys(labels.tolist()))
        self.models_ = [fit_pdm(vectors[labels == c], variance_fraction=self.variance_fraction) for c in self.classes_]
        return self

    def log_likelihoods(self, shapes: np.ndarray) -> np.ndarray:
        _check_fitted(self)
        shapes = _check(shapes)
        _check_landmarks(shapes, len(self.reference_))
        vectors = _align_to_reference(shapes.reshape(len(shapes), -1, 2), self.reference_).reshape(len(shapes), -1)
        return np.stack([_ppca_log_density(model, vectors) for model in self.models_], axis=1)

    def predict(self, shapes: np.ndarray) -> np.ndarray:
        scores = self.log_likelihoods(shapes)  # validates first
        return np.asarray(self.classes_)[np.argmax(scores, axis=1)]


class NearestProcrustesMeanClassifier:
    """Class whose Procrustes mean shape is nearest in Procrustes (similarity-aligned RMS) distance."""

    def fit(self, shapes: np.ndarray, labels: np.ndarray) -> "NearestProcrustesMeanClassifier":
        shapes = _check(shapes)
        labels = _check_labels(labels, len(shapes))
        self.classes_ = tuple(dict.fromkeys(labels.tolist()))
        self.means_ = [generalized_procrustes(shapes[labels == c].reshape(-1, shapes.shape[1] * shapes.shape[2], 2))[1]
                       for c in self.classes_]
        return self

    def distances(self, shapes: np.ndarray) -> np.ndarray:
        _check_fitted(self)
        shapes = _check(shapes)
        _check_landmarks(shapes, len(self.means_[0]))
        flat = shapes.reshape(len(shapes), -1, 2)
        # Align each class mean onto the test shape; normalise by the test shape's size.
        sizes = np.sqrt(np.sum((flat - flat.mean(axis=1, keepdims=True)) ** 2, axis=(1, 2)))
        return np.stack([_procrustes_rms(mean, flat) for mean in self.means_], axis=1) / sizes[:, None]

    def _distances_loop(self, shapes: np.ndarray) -> np.ndarray:
        """Reference path of :meth:`distances`: one SVD Procrustes fit per shape and class."""
        flat = np.asarray(shapes, float).reshape(len(shapes), -1, 2)
        sizes = np.sqrt(np.sum((flat - flat.mean(axis=1, keepdims=True)) ** 2, axis=(1, 2)))
        return np.array([[procrustes_align(mean, points).rms_error / size for mean in self.means_]
                         for points, size in zip(flat, sizes)])

    def predict(self, shapes: np.ndarray) -> np.ndarray:
        distances = self.distances(shapes)  # validates first
        return np.asarray(self.classes_)[np.argmin(distances, axis=1)]


def _procrustes_rms(source: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """RMS residual of the similarity Procrustes fit of ``source (L, 2)`` onto each of ``targets
    (n, L, 2)``, all at once, by the closed form of 2-D Procrustes in complex numbers (the best
    ``s R`` is ``a = sum conj(z_i) y_i / sum |z_i|^2`` for centred source ``z`` and target ``y``)."""
    z = source[:, 0] + 1j * source[:, 1]
    z = z - z.mean()
    y = targets[..., 0] + 1j * targets[..., 1]
    y = y - y.mean(axis=1, keepdims=True)
    factor = (y @ np.conj(z)) / np.sum(np.abs(z) ** 2)  # (n,)
    return np.sqrt(np.mean(np.abs(factor[:, None] * z - y) ** 2, axis=1))


class SklearnGMMClassifier:
    """One scikit-learn ``GaussianMixture`` per class on aligned flat landmark vectors (a peer
    library baseline); class = highest ``score_samples``."""

    def __init__(self, n_components: int = 2, covariance_type: str = "diag", seed: int = 0) -> None:
        self.n_components = check_positive_int(n_components, "n_components")
        self.covariance_type = covariance_type
        self.seed = seed

    def fit(self, shapes: np.ndarray, labels: np.ndarray) -> "SklearnGMMClassifier":
        from sklearn.mixture import GaussianMixture

        shapes = _check(shapes)
        aligned, self.reference_ = generalized_procrustes(shapes.reshape(len(shapes), -1, 2))
        vectors = aligned.reshape(len(shapes), -1)
        labels = _check_labels(labels, len(shapes))
        self.classes_ = tuple(dict.fromkeys(labels.tolist()))
        self.models_ = [
            GaussianMixture(self.n_components, covariance_type=self.covariance_type, reg_covar=1e-6,
                            random_state=self.seed).fit(vectors[labels == c])
            for c in self.classes_
        ]
        return self

    def predict(self, shapes: np.ndarray) -> np.ndarray:
        _check_fitted(self)
        shapes = _check(shapes)
        _check_landmarks(shapes, len(self.reference_))
        vectors = _align_to_reference(shapes.reshape(len(shapes), -1, 2), self.reference_).reshape(len(shapes), -1)
        scores = np.stack([m.score_samples(vectors) for m in self.models_], axis=1)
        return np.asarray(self.classes_)[np.argmax(scores, axis=1)]


def pairwise_distances(vectors: np.ndarray) -> np.ndarray:
    """Euclidean distance matrix of the rows of ``vectors`` ``(n, d)``."""
    from scipy.spatial.distance import cdist

    vectors = as_finite_array(vectors, "vectors", ndim=2)
    return cdist(vectors, vectors)


def classical_mds(distances: np.ndarray, n_dims: int = 3) -> np.ndarray:
    """Classical (Torgerson) MDS: eigenvectors of the double-centred squared distances, scaled by
    the square roots of their eigenvalues. Signs are fixed so each axis's largest entry is positive.

    ``distances`` is a square ``(n, n)`` matrix of non-negative distances; 1 <= ``n_dims`` <= n."""
    distances = as_finite_array(distances, "distances", ndim=2)
    n = distances.shape[0]
    if distances.shape != (n, n):
        raise ValueError(f"distances must be a square (n, n) matrix, got shape {distances.shape}")
    if np.any(distances < 0):
        raise ValueError("distances must be non-negative")
    n_dims = check_positive_int(n_dims, "n_dims")
    if n_dims > n:
        raise ValueError(f"n_dims must be at most the number of points {n}, got {n_dims}")
    centring = np.eye(n) - 1.0 / n
    gram = -0.5 * centring @ (distances**2) @ centring
    values, vectors = np.linalg.eigh(gram)
    order = np.argsort(values)[::-1][:n_dims]
    coords = vectors[:, order] * np.sqrt(np.clip(values[order], 0.0, None))
    return coords * np.sign(coords[np.argmax(np.abs(coords), axis=0), np.arange(n_dims)])


def pca_embedding(vectors: np.ndarray, n_dims: int = 3) -> np.ndarray:
    """Projection of centred ``vectors`` ``(n, d)`` on their leading principal axes (sign-fixed as
    above); 1 <= ``n_dims`` <= min(n, d)."""
    vectors = as_finite_array(vectors, "vectors", ndim=2)
    n_dims = check_positive_int(n_dims, "n_dims")
    if n_dims > min(vectors.shape):
        raise ValueError(f"n_dims must be at most min(n, d) = {min(vectors.shape)} for vectors of shape "
                         f"{vectors.shape}, got {n_dims}")
    centred = vectors - vectors.mean(axis=0)
    _, _, vt = np.linalg.svd(centred, full_matrices=False)
    coords = centred @ vt[:n_dims].T
    return coords * np.sign(coords[np.argmax(np.abs(coords), axis=0), np.arange(n_dims)])
