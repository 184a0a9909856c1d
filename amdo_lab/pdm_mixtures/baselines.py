"""Baselines on the same data (Beyond the paper) and the embeddings used for Figs. 7-9."""

from __future__ import annotations

import numpy as np

from amdo_lab.common import (as_finite_array, check_fitted, check_in_range, check_positive_int, check_same_shape,
                             make_rng, procrustes_align)
from amdo_lab.pdm_mixtures.pdm import (
    MAX_MAGNITUDE,
    _align_to_reference,
    _ppca_log_density,
    check_articulated_shapes,
    check_training_set,
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


class SingleCartesianPDMClassifier:
    """Baseline: one Cartesian PDM per class on Procrustes-aligned landmark long-vectors.

    A shape goes to the class whose PDM gives it the highest PPCA log-likelihood
    (:func:`~amdo_lab.pdm_mixtures.pdm.ppca_log_density`).

    Parameters
    ----------
    variance_fraction : float
        Variance kept by each class's PDM, in (0, 1].

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 2 (the single PDM per class that the paper's mixtures extend).
    """

    def __init__(self, variance_fraction: float = 0.95) -> None:
        self.variance_fraction = variance_fraction  # stored as given; fit validates it

    def fit(self, shapes: np.ndarray, labels: np.ndarray) -> "SingleCartesianPDMClassifier":
        """Align the training shapes (generalised Procrustes) and fit one PDM per class (eq. 1).

        Parameters
        ----------
        shapes : (T, 13, m, 2) array_like
            Training shapes; no shape may have all its landmarks coincide.
        labels : (T,) array_like
            Class name (or id) of every training shape.

        Returns
        -------
        SingleCartesianPDMClassifier
            This classifier, fitted.
        """
        check_in_range(self.variance_fraction, "variance_fraction", 0, 1, closed="right")
        vectors, labels = _fit_reference(self, shapes, labels)
        self.models_ = [fit_pdm(vectors[labels == c], variance_fraction=self.variance_fraction) for c in self.classes_]
        return self

    def log_likelihoods(self, shapes: np.ndarray) -> np.ndarray:
        """PPCA log-likelihood of every shape under every class's PDM.

        Parameters
        ----------
        shapes : (n, 13, m, 2) array_like
            Articulated shapes, with as many landmarks per limb as the training shapes.

        Returns
        -------
        numpy.ndarray
            ``(n, C)`` log-densities in nats, columns in ``classes_`` order.
        """
        vectors = _aligned_vectors(self, shapes)
        return np.stack([_ppca_log_density(model, vectors) for model in self.models_], axis=1)

    def predict(self, shapes: np.ndarray) -> np.ndarray:
        """Class of highest log-likelihood for every shape.

        Parameters
        ----------
        shapes : (n, 13, m, 2) array_like
            Articulated shapes, with as many landmarks per limb as the training shapes.

        Returns
        -------
        numpy.ndarray
            ``(n,)`` class names from ``classes_``.
        """
        scores = self.log_likelihoods(shapes)  # validates first
        return np.asarray(self.classes_)[np.argmax(scores, axis=1)]


class NearestProcrustesMeanClassifier:
    """Baseline: the class whose Procrustes mean shape is nearest in Procrustes distance.

    The distance is the RMS landmark residual of the similarity fit of a class mean onto the shape,
    divided by the shape's centroid size.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 2 (aligned mean shapes).
    """

    def fit(self, shapes: np.ndarray, labels: np.ndarray) -> "NearestProcrustesMeanClassifier":
        """Compute each class's generalised Procrustes mean shape.

        Parameters
        ----------
        shapes : (T, 13, m, 2) array_like
            Training shapes; no shape may have all its landmarks coincide.
        labels : (T,) array_like
            Class name (or id) of every training shape.

        Returns
        -------
        NearestProcrustesMeanClassifier
            This classifier, fitted.
        """
        shapes, labels = check_training_set(shapes, labels)
        self.classes_ = tuple(dict.fromkeys(labels.tolist()))
        self.means_ = [generalized_procrustes(shapes[labels == c].reshape(-1, shapes.shape[1] * shapes.shape[2], 2))[1]
                       for c in self.classes_]
        return self

    def distances(self, shapes: np.ndarray) -> np.ndarray:
        """Procrustes distance from every shape to every class mean.

        Parameters
        ----------
        shapes : (n, 13, m, 2) array_like
            Articulated shapes, with as many landmarks per limb as the training shapes.

        Returns
        -------
        numpy.ndarray
            ``(n, C)`` RMS residuals divided by each shape's centroid size (dimensionless),
            columns in ``classes_`` order.
        """
        check_fitted(self, "classes_")
        shapes = check_articulated_shapes(shapes, landmarks_per_limb=len(self.means_[0]) // 13)
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
        """Class of the nearest mean for every shape.

        Parameters
        ----------
        shapes : (n, 13, m, 2) array_like
            Articulated shapes, with as many landmarks per limb as the training shapes.

        Returns
        -------
        numpy.ndarray
            ``(n,)`` class names from ``classes_``.
        """
        distances = self.distances(shapes)  # validates first
        return np.asarray(self.classes_)[np.argmin(distances, axis=1)]


def _fit_reference(estimator: object, shapes: object, labels: object) -> tuple[np.ndarray, np.ndarray]:
    """Check a training set, align it by generalised Procrustes and store the estimator's ``reference_``
    and ``classes_`` (in order of first appearance); returns the aligned long-vectors ``(T, 26m)`` and the labels."""
    shapes, labels = check_training_set(shapes, labels)
    aligned, estimator.reference_ = generalized_procrustes(shapes.reshape(len(shapes), -1, 2))
    estimator.classes_ = tuple(dict.fromkeys(labels.tolist()))
    return aligned.reshape(len(shapes), -1), labels


def _aligned_vectors(estimator: object, shapes: object) -> np.ndarray:
    """Shapes for a fitted estimator (as many landmarks per limb as its training shapes), aligned onto
    its ``reference_``, as long-vectors ``(n, 26m)``."""
    check_fitted(estimator, "classes_")
    shapes = check_articulated_shapes(shapes, landmarks_per_limb=len(estimator.reference_) // 13)
    return _align_to_reference(shapes.reshape(len(shapes), -1, 2), estimator.reference_).reshape(len(shapes), -1)


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
    """Peer-library baseline: one scikit-learn ``GaussianMixture`` per class on aligned landmark vectors.

    A shape goes to the class whose mixture (diagonal covariances) gives the highest ``score_samples``.

    Parameters
    ----------
    n_components : int
        Mixture components per class: positive, at most the number of shapes of the smallest class.
    rng : int or numpy.random.Generator
        Seed of each mixture's k-means start (keyword-only, no default): an int is passed to
        scikit-learn as its ``random_state``; a Generator gives each class's mixture an int seed
        drawn from it (scikit-learn does not take a Generator).

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 4 (Gaussian mixtures learnt by EM, eqs. 2-8).
    """

    def __init__(self, n_components: int = 2, *, rng: int | np.random.Generator) -> None:
        # Stored as given (scikit-learn's contract); fit validates them.
        self.n_components = n_components
        self.rng = rng

    def fit(self, shapes: np.ndarray, labels: np.ndarray) -> "SklearnGMMClassifier":
        """Align the training shapes (generalised Procrustes) and fit one mixture per class.

        Parameters
        ----------
        shapes : (T, 13, m, 2) array_like
            Training shapes; no shape may have all its landmarks coincide.
        labels : (T,) array_like
            Class name (or id) of every training shape.

        Returns
        -------
        SklearnGMMClassifier
            This classifier, fitted.
        """
        from sklearn.mixture import GaussianMixture

        generator = make_rng(self.rng, "rng")
        shapes, labels = check_training_set(shapes, labels)  # checked before anything is fitted or stored
        check_positive_int(self.n_components, "n_components",  # at most the smallest class (scikit-learn's rule)
                           maximum=int(min(np.unique(labels, return_counts=True)[1])))
        vectors, labels = _fit_reference(self, shapes, labels)
        if isinstance(self.rng, np.random.Generator):  # scikit-learn takes an int seed, not a Generator
            seeds = [int(generator.integers(2**31 - 1)) for _ in self.classes_]
        else:
            seeds = [int(self.rng)] * len(self.classes_)
        self.models_ = [
            GaussianMixture(self.n_components, covariance_type="diag", reg_covar=1e-6,
                            random_state=seed).fit(vectors[labels == c])
            for c, seed in zip(self.classes_, seeds)
        ]
        return self

    def predict(self, shapes: np.ndarray) -> np.ndarray:
        """Class of highest mixture log-likelihood for every shape.

        Parameters
        ----------
        shapes : (n, 13, m, 2) array_like
            Articulated shapes, with as many landmarks per limb as the training shapes.

        Returns
        -------
        numpy.ndarray
            ``(n,)`` class names from ``classes_``.
        """
        vectors = _aligned_vectors(self, shapes)
        scores = np.stack([m.score_samples(vectors) for m in self.models_], axis=1)
        return np.asarray(self.classes_)[np.argmax(scores, axis=1)]


def pairwise_distances(vectors: np.ndarray) -> np.ndarray:
    """Euclidean distance matrix of the rows of a matrix.

    Parameters
    ----------
    vectors : (n, d) array_like
        Points as rows.

    Returns
    -------
    numpy.ndarray
        ``(n, n)`` symmetric distances, zero on the diagonal, in the vectors' units.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 7, Figs. 7-9 (pairwise distance matrices).
    """
    from scipy.spatial.distance import cdist

    vectors = as_finite_array(vectors, "vectors", ndim=2, max_abs=MAX_MAGNITUDE)
    return cdist(vectors, vectors)


def classical_mds(distances: np.ndarray, n_dims: int = 3) -> np.ndarray:
    """Classical (Torgerson) multidimensional scaling of a distance matrix.

    The coordinates are the leading eigenvectors of the double-centred squared distances, scaled by
    the square roots of their eigenvalues. Signs are fixed so each axis's largest entry is positive.

    Parameters
    ----------
    distances : (n, n) array_like
        Square matrix of non-negative distances.
    n_dims : int
        Embedding dimension, 1 <= n_dims <= n (default 3, as the paper's figures).

    Returns
    -------
    numpy.ndarray
        ``(n, n_dims)`` coordinates, in the distances' units.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 7, Figs. 7 and 9 (MDS embeddings); Torgerson, Psychometrika 17 (1952).
    """
    distances = as_finite_array(distances, "distances", ndim=2, bounds=(0, MAX_MAGNITUDE))
    n = distances.shape[0]
    check_same_shape(distances, distances.T, "distances", "its transpose")  # square
    n_dims = check_positive_int(n_dims, "n_dims", maximum=n)  # at most the number of points
    centring = np.eye(n) - 1.0 / n
    gram = -0.5 * centring @ (distances**2) @ centring
    values, vectors = np.linalg.eigh(gram)
    order = np.argsort(values)[::-1][:n_dims]
    coords = vectors[:, order] * np.sqrt(np.clip(values[order], 0.0, None))
    return coords * np.sign(coords[np.argmax(np.abs(coords), axis=0), np.arange(n_dims)])


def pca_embedding(vectors: np.ndarray, n_dims: int = 3) -> np.ndarray:
    """Projection of centred vectors on their leading principal axes.

    Signs are fixed so each axis's largest entry is positive (as :func:`classical_mds`).

    Parameters
    ----------
    vectors : (n, d) array_like
        Points as rows.
    n_dims : int
        Number of principal axes, 1 <= n_dims <= min(n, d) (default 3, as the paper's figures).

    Returns
    -------
    numpy.ndarray
        ``(n, n_dims)`` principal-component scores, in the vectors' units.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 7, Fig. 8 (PCA embedding).
    """
    vectors = as_finite_array(vectors, "vectors", ndim=2, max_abs=MAX_MAGNITUDE)
    n_dims = check_positive_int(n_dims, "n_dims", maximum=min(vectors.shape))  # at most min(n, d)
    centred = vectors - vectors.mean(axis=0)
    _, _, vt = np.linalg.svd(centred, full_matrices=False)
    coords = centred @ vt[:n_dims].T
    return coords * np.sign(coords[np.argmax(np.abs(coords), axis=0), np.arange(n_dims)])
