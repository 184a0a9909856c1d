"""PCA+LDA as in the CSU system (Sec. 3) with the L2 and Zhao's soft-L2 distances (eq. 1)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from amdo_lab.common import (MAX_SAMPLES, as_finite_array, check_choice, check_fitted, check_in_range, check_instance,
                             check_positive, check_positive_int, check_same_shape)

__all__ = ["PcaLda", "PcaBasis", "pca_basis", "e90_dimension", "fisher_basis", "METRICS"]

METRICS = ("l2", "soft_l2")
SOFT_L2_POWER = 0.2  # eq. (1): weight lambda_i ** 0.2
#: Fisher eigenvalues at most this share of the largest count as 0 (scikit-learn's LDA: 1e-4 on
#: singular values, i.e. 1e-8 on their squares, the eigenvalues here).
FISHER_RANK_TOLERANCE = 1e-8


@dataclass(frozen=True)
class PcaBasis:
    """Eigen-decomposition of the training images (shared by every PCA dimension).

    Parameters
    ----------
    mean : ndarray, shape (n_pixels,)
        The mean training image, as a row vector.
    vectors : ndarray, shape (n_pixels, rank)
        Unit eigenvectors as columns, in decreasing order of variance.
    eigenvalues : ndarray, shape (rank,)
        Their variances (grey value^2), positive and decreasing.

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, Sec. 3 (the PCA step of the CSU PCA+LDA system).
    """

    mean: np.ndarray        # (n_pixels,)
    vectors: np.ndarray     # (n_pixels, rank), unit columns, decreasing variance
    eigenvalues: np.ndarray  # (rank,)


def pca_basis(samples: np.ndarray) -> PcaBasis:
    """PCA of row-vector samples by a thin SVD (the 'eigenfaces' of Sec. 3).

    Parameters
    ----------
    samples : array_like, shape (n, n_pixels)
        Finite training images as rows, n >= 2, each value at most 1e100 in magnitude (beyond, the
        variances overflow).

    Returns
    -------
    PcaBasis
        Mean, eigenvectors and eigenvalues; the rank is at most n - 1 (directions whose singular value
        is below 1e-10 of the largest are dropped).

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, Sec. 3.
    """
    samples = as_finite_array(samples, "samples", ndim=2, max_abs=_MAX_MAGNITUDE)
    check_positive_int(len(samples), "the rows of samples (for a covariance)", minimum=2)
    return _pca_basis(samples)


def _pca_basis(samples: np.ndarray) -> PcaBasis:
    """:func:`pca_basis` on validated samples (once per configuration of the experiment)."""
    mean = samples.mean(axis=0)
    _, singular, vt = np.linalg.svd(samples - mean, full_matrices=False)
    rank = max(1, min(samples.shape[0] - 1, int(np.sum(singular > singular[0] * 1e-10))))
    return PcaBasis(mean, vt[:rank].T, singular[:rank] ** 2 / (samples.shape[0] - 1))


def e90_dimension(eigenvalues: np.ndarray, energy: float = 0.90) -> int:
    """Number of leading eigenvectors holding ``energy`` of the total variance (E90 for 0.90).

    Parameters
    ----------
    eigenvalues : array_like, shape (rank,)
        Non-negative, in decreasing order, with a positive sum.
    energy : float, default 0.90
        Share of the total in (0, 1].

    Returns
    -------
    int
        The smallest k with sum(eigenvalues[:k]) >= energy * sum(eigenvalues), in [1, rank].

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, Sec. 4 (the E90 PCA dimension, after Kirby, their ref. [7]).
    """
    eigenvalues = as_finite_array(eigenvalues, "eigenvalues", ndim=1, bounds=(0.0, np.inf))
    check_positive(eigenvalues.sum(), "the sum of eigenvalues")
    check_in_range(energy, "energy", 0, 1, closed="right")
    return _e90_dimension(eigenvalues / eigenvalues.max(), energy)  # the share is scale-free: no overflow


def _e90_dimension(eigenvalues: np.ndarray, energy: float = 0.90) -> int:
    cumulative = np.cumsum(eigenvalues) / np.sum(eigenvalues)
    return int(np.searchsorted(cumulative, energy) + 1)


def fisher_basis(projected: np.ndarray, labels: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Fisher directions from S_b v = lambda S_w v in PCA coordinates, with a rank decision.

    The paper's system keeps the C-1 largest eigenvalues. When S_b restricted to the k PCA directions
    has rank r < C-1 (e.g. a reflection supplement: every class mean is left-right symmetric, so S_b
    is 0 on the odd PCA directions), C-1-r of those eigenvalues are 0 up to round-off and their
    eigenvectors are an arbitrary basis of a degenerate eigenspace, chosen by the rounding of the
    BLAS kernel. As scikit-learn's ``LinearDiscriminantAnalysis(solver="svd")`` does, only the
    directions whose eigenvalue exceeds ``FISHER_RANK_TOLERANCE`` times the largest are kept.

    Parameters
    ----------
    projected : ndarray, shape (n, k)
        Training images in PCA coordinates, with a non-singular within-class scatter.
    labels : ndarray, shape (n,)
        Subject of each row, at least 2 distinct.

    Returns
    -------
    vectors : ndarray, shape (k, r)
        Generalised eigenvectors for the r <= C-1 largest eigenvalues above the tolerance
        (C = number of subjects; r = C-1 when S_b has full rank C-1 in PCA space).
    eigenvalues : ndarray, shape (r,)
        Those eigenvalues, the lambda_i of eq. (1), positive and decreasing.

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, Sec. 3 and eq. (1).
    Pedregosa et al. (2011), scikit-learn, JMLR 12, ``LinearDiscriminantAnalysis`` (the relative rank tolerance).
    """
    classes, inverse = np.unique(labels, return_inverse=True)
    counts = np.bincount(inverse).astype(float)
    class_means = np.zeros((classes.size, projected.shape[1]))
    np.add.at(class_means, inverse, projected)
    class_means /= counts[:, None]
    overall = projected.mean(axis=0)
    within = projected - class_means[inverse]
    scatter_w = within.T @ within
    centred_means = (class_means - overall) * np.sqrt(counts)[:, None]
    scatter_b = centred_means.T @ centred_means
    eigenvalues, vectors = scipy.linalg.eigh(scatter_b, scatter_w)
    eigenvalues, vectors = eigenvalues[::-1][: classes.size - 1], vectors[:, ::-1][:, : classes.size - 1]
    # rank decision: eigenvalues at round-off level (relative to the largest) have no defined direction
    rank = max(1, int(np.sum(eigenvalues > FISHER_RANK_TOLERANCE * eigenvalues[0])))
    return vectors[:, :rank], np.clip(eigenvalues[:rank], 0.0, None)


class PcaLda:
    """PCA followed by LDA, composed into one projection with unit-length axes.

    Parameters
    ----------
    pca_dimension : int or {"fixed", "e90"}, default "fixed"
        Number of PCA eigenvectors kept: an int in [1, 1,000,000] (capped by the data), ``"e90"`` (90 % of the energy) or
        ``"fixed"`` (60 % of the PCA rank of the *unsupplemented* training set, i.e. 114 for
        64 subjects x 3 images, the paper's choice). Always capped at ``n_images - n_classes`` so that
        the within-class scatter is non-singular.
    base_images_per_class : int, default 3
        Images per subject before any supplement (3 in the paper), 1 to 1,000,000; defines "fixed".

    References
    ----------
    Givens, Beveridge, Draper & Bolme (2004), "Using a Generalized Linear Mixed Model to Study the
    Configuration Space of a PCA+LDA Human Face Recognition Algorithm", AMDO 2004, LNCS 3179, pp. 1-11, Sec. 3 (the CSU PCA+LDA system) and eq. (1) (its two distances).
    """

    def __init__(self, pca_dimension: int | str = "fixed", base_images_per_class: int = 3):
        # stored as given and checked in fit (scikit-learn's estimator contract)
        self.pca_dimension = pca_dimension
        self.base_images_per_class = base_images_per_class

    def fit(self, images: np.ndarray, labels: np.ndarray, basis: PcaBasis | None = None) -> "PcaLda":
        """Learn the PCA basis, the PCA dimension and the Fisher directions from labelled images.

        Parameters
        ----------
        images : array_like, shape (n, rows, cols) or (n, pixels)
            Finite training images, each value at most 1e100 in magnitude.
        labels : array_like, shape (n,)
            Subject of each image (numbers or strings; no NaN, inf or None), at least 2 subjects, with n - C >= C - 1.
        basis : PcaBasis, optional
            A precomputed :func:`pca_basis` of the same images (shared between PCA dimensions).

        Returns
        -------
        PcaLda
            ``self``, with ``basis_``, ``n_pca_``, ``projection_`` (pixels x r, r <= C-1 Fisher directions
            whose eigenvalue passes the rank decision of :func:`fisher_basis`) and ``eigenvalues_``.
        """
        pca_dimension = self.pca_dimension
        if isinstance(pca_dimension, str):
            check_choice(pca_dimension, "pca_dimension", ("fixed", "e90"))
        else:  # a number of PCA axes: at most the number of images, itself bounded by MAX_SAMPLES
            check_positive_int(pca_dimension, "pca_dimension", maximum=MAX_SAMPLES)
        images_per_class = check_positive_int(self.base_images_per_class, "base_images_per_class", maximum=MAX_SAMPLES)
        samples = _as_samples(images)
        labels = np.asarray(labels)
        check_same_shape(labels, samples[:, 0], "labels", "images (one label per image)")
        check_choice(labels.dtype.kind, "labels (dtype kind: U for names, i/u/f for ids)", ("U", "i", "u", "f"))
        if labels.dtype.kind in "fc":  # subject ids as numbers: every image needs a finite one
            as_finite_array(labels, "labels")
        if basis is not None:  # a precomputed PCA of images with as many pixels
            check_instance(basis, "basis", PcaBasis, what="a PcaBasis (from pca_basis)")
            as_finite_array(basis.mean, "basis (the mean image of its images)", shape=samples.shape[1:])
        n_classes = check_positive_int(np.unique(labels).size, "the subjects in labels (for LDA)", minimum=2)
        n_images = samples.shape[0]
        check_positive_int(n_images - n_classes, f"too few images for LDA: the within-class degrees of freedom of "
                           f"images ({n_images} images of {n_classes} subjects)", minimum=n_classes - 1)
        self.basis_ = basis if basis is not None else _pca_basis(samples)
        cap = min(samples.shape[0] - n_classes, self.basis_.vectors.shape[1])
        if pca_dimension == "e90":
            k = _e90_dimension(self.basis_.eigenvalues)
        elif pca_dimension == "fixed":
            k = int(0.6 * (n_classes * images_per_class - 1))  # 114 for 64 x 3
        else:
            k = int(pca_dimension)
        self.n_pca_ = int(min(k, cap))
        pca_vectors = self.basis_.vectors[:, : self.n_pca_]
        projected = (samples - self.basis_.mean) @ pca_vectors
        try:
            fisher, eigenvalues = fisher_basis(projected, labels)
        except np.linalg.LinAlgError:  # scipy's eigh: S_w not positive definite
            raise ValueError("images give a singular within-class scatter in PCA space (identical or constant "
                             "images?): LDA needs images that vary within each subject") from None
        projection = pca_vectors @ fisher
        self.projection_ = projection / np.linalg.norm(projection, axis=0)
        self.eigenvalues_ = eigenvalues
        return self

    def transform(self, images: np.ndarray) -> np.ndarray:
        """Coordinates of images in the PCA+LDA space.

        Parameters
        ----------
        images : array_like, shape (n, rows, cols) or (n, pixels)
            Finite images (each value at most 1e100 in magnitude) with the training images' number of pixels.

        Returns
        -------
        ndarray, shape (n, r)
            (image - mean) projected on the r <= C-1 unit-length PCA+LDA axes.
        """
        check_fitted(self, ("basis_", "projection_", "eigenvalues_"))
        return self._project(images, "images")

    def _project(self, images: np.ndarray, name: str) -> np.ndarray:
        """:meth:`transform`, with errors naming the caller's argument ``name``."""
        samples = _as_samples(images, name)
        check_same_shape(samples[0], self.basis_.mean, f"the pixels of {name}", "those of the training images")
        return (samples - self.basis_.mean) @ self.projection_

    def distances(self, probes: np.ndarray, gallery: np.ndarray, metric: str = "l2") -> np.ndarray:
        """Eq. (1) distance matrix between two image sets.

        Parameters
        ----------
        probes : array_like, shape (n_probes, rows, cols) or (n_probes, pixels)
            Query images.
        gallery : array_like, shape (n_gallery, rows, cols) or (n_gallery, pixels)
            Gallery images.
        metric : {"l2", "soft_l2"}, default "l2"
            L2, or Zhao's soft L2 weighting axis i by lambda_i ** 0.2.

        Returns
        -------
        ndarray, shape (n_probes, n_gallery)
            Weighted squared distances, >= 0.
        """
        check_choice(metric, "metric", METRICS)
        check_fitted(self, ("basis_", "projection_", "eigenvalues_"))
        return _weighted_sq_distances(self._project(probes, "probes"), self._project(gallery, "gallery"),
                                     self._metric_weights(metric))

    def _metric_weights(self, metric: str) -> np.ndarray:
        """Per-axis weights ``(r,)`` of the eq. (1) distance of a fitted model for a checked ``metric``: L2
        (all weights 1) or soft L2 (lambda_i ** 0.2, lambda_i the Fisher eigenvalues)."""
        if metric == "l2":
            return np.ones_like(self.eigenvalues_)
        return self.eigenvalues_ ** SOFT_L2_POWER



def weighted_sq_distances(a: np.ndarray, b: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Weighted squared distances sum_i w_i (a_i - b_i)^2 of all pairs, by the expanded square (eq. 1).

    Parameters
    ----------
    a : array_like, shape (n, k)
        Points as rows, each coordinate at most 1e100 in magnitude (beyond, the squares overflow).
    b : array_like, shape (m, k)
        Points as rows, each coordinate at most 1e100 in magnitude.
    weights : array_like, shape (k,)
        Non-negative per-axis weights (ones: L2; lambda_i ** 0.2: soft L2), each at most 1e100.

    Returns
    -------
    ndarray, shape (n, m)
        The distances, clipped at 0 against rounding.

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, eq. (1).
    """
    a = as_finite_array(a, "a", ndim=2, max_abs=_MAX_MAGNITUDE)
    # as many axes as a: the messages name a too, since either may be the one at fault
    b = as_finite_array(b, "b (like a)", shape=(None, a.shape[1]), max_abs=_MAX_MAGNITUDE)
    weights = as_finite_array(weights, "weights (like a)", shape=a.shape[1:], bounds=(0.0, _MAX_MAGNITUDE))
    return _weighted_sq_distances(a, b, weights)


def _weighted_sq_distances(a: np.ndarray, b: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """:func:`weighted_sq_distances` on validated arrays (the experiment's inner call)."""
    # eq. (1): Σ_i w_i (a_i - b_i)² (w = 1: L2; w = λ_i^0.2: soft L2) for every pair, expanded as
    # Σ_i w_i a_i² + Σ_i w_i b_i² - 2 Σ_i w_i a_i b_i so that the cross term is one matrix product
    aw = a * weights
    sq = np.sum(aw * a, axis=1)[:, None] + np.sum(b * b * weights, axis=1)[None, :] - 2.0 * aw @ b.T
    return np.maximum(sq, 0.0)


#: Largest pixel magnitude accepted: squares and sums of squares of such values stay finite.
_MAX_MAGNITUDE = 1e100


def _as_samples(images: np.ndarray, name: str = "images") -> np.ndarray:
    images = as_finite_array(images, name, max_abs=_MAX_MAGNITUDE)
    if images.ndim == 3:
        return images.reshape(images.shape[0], -1)
    if images.ndim != 2:
        raise ValueError(f"{name} must have shape (n, rows, cols) or (n, pixels), got {images.shape}")
    return images
