"""Baselines on the same data (Beyond the paper) and the embeddings used for Figs. 7-9."""

from __future__ import annotations

import numpy as np

from amdo_lab.common import as_finite_array, check_positive_int, procrustes_align
from amdo_lab.pdm_mixtures.pdm import align_to_reference, fit_modes, fit_pdm, generalized_procrustes, reconstruct

__all__ = [
    "SingleCartesianPDMClassifier",
    "NearestProcrustesMeanClassifier",
    "SklearnGMMClassifier",
    "classical_mds",
    "pca_embedding",
    "pairwise_distances",
]


def _check(shapes: object) -> np.ndarray:
    return as_finite_array(shapes, "shapes", shape=(None, 13, None, 2))


class SingleCartesianPDMClassifier:
    """One Cartesian PDM per class on Procrustes-aligned landmark long-vectors; class = highest
    PPCA log-likelihood (in-model Mahalanobis + isotropic residual)."""

    def __init__(self, variance_fraction: float = 0.95) -> None:
        self.variance_fraction = variance_fraction

    def fit(self, shapes: np.ndarray, labels: np.ndarray) -> "SingleCartesianPDMClassifier":
        shapes = _check(shapes)
        aligned, self.reference_ = generalized_procrustes(shapes.reshape(len(shapes), -1, 2))
        vectors = aligned.reshape(len(shapes), -1)
        labels = np.asarray(labels)
        self.classes_ = tuple(dict.fromkeys(labels.tolist()))
        self.models_ = [fit_pdm(vectors[labels == c], variance_fraction=self.variance_fraction) for c in self.classes_]
        return self

    def log_likelihoods(self, shapes: np.ndarray) -> np.ndarray:
        shapes = _check(shapes)
        vectors = align_to_reference(shapes.reshape(len(shapes), -1, 2), self.reference_).reshape(len(shapes), -1)
        d = vectors.shape[1]
        out = np.empty((len(vectors), len(self.models_)))
        for j, model in enumerate(self.models_):
            gamma = fit_modes(model, vectors)
            residual = np.sum((vectors - reconstruct(model, gamma)) ** 2, axis=1)
            out[:, j] = -0.5 * (np.sum(gamma**2 / model.variances, axis=1) + residual / model.residual_variance
                                + np.sum(np.log(model.variances)) + (d - model.n_modes) * np.log(model.residual_variance))
        return out

    def predict(self, shapes: np.ndarray) -> np.ndarray:
        return np.asarray(self.classes_)[np.argmax(self.log_likelihoods(shapes), axis=1)]


class NearestProcrustesMeanClassifier:
    """Class whose Procrustes mean shape is nearest in Procrustes (similarity-aligned RMS) distance."""

    def fit(self, shapes: np.ndarray, labels: np.ndarray) -> "NearestProcrustesMeanClassifier":
        shapes = _check(shapes)
        labels = np.asarray(labels)
        self.classes_ = tuple(dict.fromkeys(labels.tolist()))
        self.means_ = [generalized_procrustes(shapes[labels == c].reshape(-1, shapes.shape[1] * shapes.shape[2], 2))[1]
                       for c in self.classes_]
        return self

    def distances(self, shapes: np.ndarray) -> np.ndarray:
        shapes = _check(shapes)
        flat = shapes.reshape(len(shapes), -1, 2)
        # Align each class mean onto the test shape; normalise by the test shape's size.
        sizes = np.sqrt(np.sum((flat - flat.mean(axis=1, keepdims=True)) ** 2, axis=(1, 2)))
        return np.array([[procrustes_align(mean, points).rms_error / size for mean in self.means_]
                         for points, size in zip(flat, sizes)])

    def predict(self, shapes: np.ndarray) -> np.ndarray:
        return np.asarray(self.classes_)[np.argmin(self.distances(shapes), axis=1)]


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
        labels = np.asarray(labels)
        self.classes_ = tuple(dict.fromkeys(labels.tolist()))
        self.models_ = [
            GaussianMixture(self.n_components, covariance_type=self.covariance_type, reg_covar=1e-6,
                            random_state=self.seed).fit(vectors[labels == c])
            for c in self.classes_
        ]
        return self

    def predict(self, shapes: np.ndarray) -> np.ndarray:
        shapes = _check(shapes)
        vectors = align_to_reference(shapes.reshape(len(shapes), -1, 2), self.reference_).reshape(len(shapes), -1)
        scores = np.stack([m.score_samples(vectors) for m in self.models_], axis=1)
        return np.asarray(self.classes_)[np.argmax(scores, axis=1)]


def pairwise_distances(vectors: np.ndarray) -> np.ndarray:
    """Euclidean distance matrix of the rows of ``vectors``."""
    from scipy.spatial.distance import cdist

    return cdist(vectors, vectors)


def classical_mds(distances: np.ndarray, n_dims: int = 3) -> np.ndarray:
    """Classical (Torgerson) MDS: eigenvectors of the double-centred squared distances, scaled by
    the square roots of their eigenvalues. Signs are fixed so each axis's largest entry is positive."""
    n = distances.shape[0]
    centring = np.eye(n) - 1.0 / n
    gram = -0.5 * centring @ (distances**2) @ centring
    values, vectors = np.linalg.eigh(gram)
    order = np.argsort(values)[::-1][:n_dims]
    coords = vectors[:, order] * np.sqrt(np.clip(values[order], 0.0, None))
    return coords * np.sign(coords[np.argmax(np.abs(coords), axis=0), np.arange(n_dims)])


def pca_embedding(vectors: np.ndarray, n_dims: int = 3) -> np.ndarray:
    """Projection of centred ``vectors`` on their leading principal axes (sign-fixed as above)."""
    centred = vectors - vectors.mean(axis=0)
    _, _, vt = np.linalg.svd(centred, full_matrices=False)
    coords = centred @ vt[:n_dims].T
    return coords * np.sign(coords[np.argmax(np.abs(coords), axis=0), np.arange(n_dims)])
