"""Point distribution models (Sec. 2) and generalised Procrustes alignment of landmark sets."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from amdo_lab.common import (MAX_ITERATIONS, as_finite_array, as_points, check_bool, check_choice, check_in_range,
                             check_instance, check_positive_int, check_same_shape, procrustes_align)
from amdo_lab.pdm_mixtures.representation import MAX_MAGNITUDE

__all__ = [
    "PointDistributionModel",
    "fit_pdm",
    "fit_modes",
    "reconstruct",
    "ppca_log_density",
    "generalized_procrustes",
]


@dataclass(frozen=True)
class PointDistributionModel:
    """A point distribution model: mean long-vector, leading eigenmodes and their variances.

    Each field is checked when the record is built (a user may build one and pass it to
    :func:`fit_modes` or :func:`reconstruct`): finite, ``mean`` and ``variances`` at most 1e150 in
    magnitude, ``variances`` non-negative, ``modes`` entries within +-1.

    Parameters
    ----------
    mean : (D,) numpy.ndarray
        Mean long-vector ``Y`` (D coordinates, in the training vectors' units).
    modes : (D, M) numpy.ndarray
        Modal matrix ``Phi``: orthonormal eigenvectors of the covariance as columns, ``1 <= M < D``.
    variances : (M,) numpy.ndarray
        Eigenvalues ``alpha_k`` of the kept modes, non-negative and decreasing (units squared).
    residual_variance : float
        ``sigma^2``: the mean of the ``D - M`` discarded eigenvalues (positive, floored at 1e-12).

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 2 (eq. 1 and its eigenmodes).
    """

    mean: np.ndarray
    modes: np.ndarray
    variances: np.ndarray
    residual_variance: float

    def __post_init__(self) -> None:
        # a record a user may build: each field checked once, then stored as a float array
        mean = as_finite_array(self.mean, "mean", ndim=1, max_abs=MAX_MAGNITUDE)
        modes = as_finite_array(self.modes, "modes", ndim=2, max_abs=1 + 1e-9)  # orthonormal columns
        variances = as_finite_array(self.variances, "variances", ndim=1, bounds=(0, MAX_MAGNITUDE))
        residual = check_in_range(self.residual_variance, "residual_variance", 0, MAX_MAGNITUDE, closed="right")
        if modes.shape != (len(mean), len(variances)) or len(variances) >= len(mean):
            raise ValueError(f"mean, modes, variances need shapes (D,), (D, M), (M,) with M < D, got {modes.shape}")
        for name, value in (("mean", mean), ("modes", modes), ("variances", variances), ("residual_variance", residual)):
            object.__setattr__(self, name, value)

    @property
    def n_modes(self) -> int:
        """Number of kept eigenmodes M."""
        return int(self.modes.shape[1])


def _check_model(model: object) -> PointDistributionModel:
    return check_instance(model, "model", PointDistributionModel)


def _pdm_from_moments(mean: np.ndarray, covariance: np.ndarray, variance_fraction: float,
                      max_modes: int | None) -> PointDistributionModel:
    """A PDM from a mean ``(D,)`` and covariance ``(D, D)``: the leading eigenmodes of the covariance
    (``Sigma phi = alpha phi``, Sec. 2) that explain ``variance_fraction`` of the variance, at least 1
    and at most ``max_modes`` (and D - 1), with the mean of the discarded eigenvalues (floored at
    1e-12) as the residual variance. The package's callers pass checked moments (not exported)."""
    eigenvalues, eigenvectors = np.linalg.eigh(covariance)  # Sigma phi_i = alpha_i phi_i (Sec. 2)
    order = np.argsort(eigenvalues)[::-1]
    eigenvalues = np.clip(eigenvalues[order], 0.0, None)  # round-off negatives of a PSD matrix
    eigenvectors = eigenvectors[:, order]
    total = eigenvalues.sum()
    n_modes = int(np.searchsorted(np.cumsum(eigenvalues), variance_fraction * total) + 1) if total > 0 else 1
    limit = len(eigenvalues) - 1 if max_modes is None else min(max_modes, len(eigenvalues) - 1)
    n_modes = max(1, min(n_modes, limit))
    residual = float(max(eigenvalues[n_modes:].mean(), 1e-12))  # floored: the PPCA density divides by it
    return PointDistributionModel(mean, eigenvectors[:, :n_modes], eigenvalues[:n_modes], residual)


def fit_pdm(long_vectors: np.ndarray, *, variance_fraction: float = 0.95) -> PointDistributionModel:
    """PDM of a training set: mean ``Y``, covariance of eq. 1 (normalised by 1/T), leading eigenmodes.

    At most ``T - 1`` modes are kept (the rank of eq. 1), so the residual variance is positive.

    Parameters
    ----------
    long_vectors : (T, D) array_like
        Training long-vectors as rows, ``T >= 3`` examples of ``D >= 2`` coordinates.
    variance_fraction : float
        Fraction of the total variance the kept modes explain, in (0, 1].

    Returns
    -------
    PointDistributionModel
        The model of the training set.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 2, eq. 1.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> pdm = fit_pdm(rng.standard_normal((50, 4)) * [3.0, 1.0, 0.1, 0.1], variance_fraction=0.9)
    >>> pdm.n_modes, pdm.variances.round(2).tolist()
    (1, [7.74])
    """
    vectors = as_finite_array(long_vectors, "long_vectors", ndim=2, max_abs=MAX_MAGNITUDE)
    t = vectors.shape[0]
    if t < 3 or vectors.shape[1] < 2:  # a covariance; one mode kept and one discarded
        raise ValueError(f"long_vectors needs at least 3 rows (examples) and 2 columns, got shape {vectors.shape}")
    variance_fraction = check_in_range(variance_fraction, "variance_fraction", 0, 1, closed="right")
    mean = vectors.mean(axis=0)  # Y = (1/T) sum_t X_t
    centred = vectors - mean
    covariance = centred.T @ centred / t  # eq. 1
    return _pdm_from_moments(mean, covariance, variance_fraction, t - 1)  # at most T - 1 modes: the rank of eq. 1


def fit_modes(model: PointDistributionModel, observed: np.ndarray, *, clamp: bool = True) -> np.ndarray:
    """Least-squares modal coefficients ``gamma = Phi^T (X_o - Y)`` for rows of ``observed``.

    The paper prints ``1/2 (Phi + Phi^T)(X_o - Y)``, which is not even defined for a non-square
    Phi; for orthonormal modes the least-squares solution is ``Phi^T (X_o - Y)``.

    Parameters
    ----------
    model : PointDistributionModel
        The PDM, with ``D`` coordinates and ``M`` modes.
    observed : (n, D) or (D,) array_like
        Observed long-vectors ``X_o``.
    clamp : bool
        Limit each coefficient to ``+-3 sqrt(alpha_k)`` (Sec. 4); default True.

    Returns
    -------
    numpy.ndarray
        Coefficients ``gamma``, ``(n, M)`` (or ``(M,)`` for one vector).

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 2 (modal fit, read as least squares) and Sec. 4 (the +-3 sqrt(alpha_k) clamp).
    """
    model = _check_model(model)
    observed = as_points(observed, "observed", dim=len(model.mean), allow_empty=False)  # like the model mean
    clamp = check_bool(clamp, "clamp")
    return _fit_modes(model, observed, clamp)


def _fit_modes(model: PointDistributionModel, observed: np.ndarray, clamp: bool = True) -> np.ndarray:
    """:func:`fit_modes` on checked input."""
    # eqs. (9) and (15): the best-fit γ = argmax_γ p(z | Φ, γ), for a Gaussian the least-squares γ = Φ^T (X_o - Y)
    gamma = (observed - model.mean) @ model.modes  # gamma = Phi^T (X_o - Y), least squares (Sec. 2)
    if clamp:  # -3 sqrt(alpha_k) <= gamma_k <= 3 sqrt(alpha_k) (Sec. 4)
        bound = 3.0 * np.sqrt(model.variances)
        gamma = np.clip(gamma, -bound, bound)
    return gamma


def reconstruct(model: PointDistributionModel, gamma: np.ndarray) -> np.ndarray:
    """Model instance ``X_hat = Y + Phi gamma`` for rows of modal coefficients.

    Parameters
    ----------
    model : PointDistributionModel
        The PDM, with ``D`` coordinates and ``M`` modes.
    gamma : (n, M) or (M,) array_like
        Modal coefficients (as from :func:`fit_modes`).

    Returns
    -------
    numpy.ndarray
        Long-vectors ``X_hat``, ``(n, D)`` (or ``(D,)``), in the model's units.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 2 (X = Y + Phi gamma).
    """
    model = _check_model(model)
    gamma = as_points(gamma, "gamma", dim=model.n_modes, allow_empty=False)  # one coefficient per mode
    return _reconstruct(model, gamma)


def _reconstruct(model: PointDistributionModel, gamma: np.ndarray) -> np.ndarray:
    """:func:`reconstruct` on checked input."""
    return model.mean + gamma @ model.modes.T  # X_hat = Y + Phi gamma (Sec. 2)


def ppca_log_density(model: PointDistributionModel, observed: np.ndarray) -> np.ndarray:
    """Gaussian log-density of rows of ``observed`` ``(n, D)`` under a PDM (probabilistic PCA).

    The PDM keeps M eigenmodes with variances ``alpha_k`` and replaces the D - M discarded
    eigenvalues by their mean ``sigma^2`` (``residual_variance``). With the clamped least-squares
    coefficients ``gamma = Phi^T (X_o - Y)`` and residual ``r = X_o - Y - Phi gamma``,

        ln p = -1/2 [ sum_k gamma_k^2 / alpha_k + |r|^2 / sigma^2
                      + sum_k ln alpha_k + (D - M) ln sigma^2 + D ln(2 pi) ].

    Without the clamp this is eq. 6 with the covariance ``Phi diag(alpha) Phi^T + sigma^2 (I - Phi Phi^T)``;
    the residual term alone is the paper's isotropic alignment error (eq. 16). This is the one
    density used for limb labels, polar PDMs and the single Cartesian PDM baseline.

    Parameters
    ----------
    model : PointDistributionModel
        The PDM, with ``D`` coordinates and ``M`` modes.
    observed : (n, D) array_like
        Observed long-vectors ``X_o`` as rows.

    Returns
    -------
    numpy.ndarray
        ``ln p`` of every row, ``(n,)``, in nats.

    References
    ----------
    Al-Shaher & Hancock, AMDO 2004, eqs. 6 and 16; Tipping & Bishop, JRSS B 61 (1999).
    """
    model = _check_model(model)
    observed = as_finite_array(observed, "observed", shape=(None, len(model.mean)), max_abs=MAX_MAGNITUDE)
    return _ppca_log_density(model, observed)


def _ppca_log_density(model: PointDistributionModel, observed: np.ndarray) -> np.ndarray:
    """:func:`ppca_log_density` on checked input (the recogniser's and the polar PDMs' inner call)."""
    d, m = observed.shape[1], model.n_modes
    gamma = _fit_modes(model, observed)  # clamped to +-3 sqrt(alpha_k)
    residual = np.sum((observed - _reconstruct(model, gamma)) ** 2, axis=1)  # |r|^2, eq. 16
    return -0.5 * (
        np.sum(gamma**2 / model.variances, axis=1) + residual / model.residual_variance
        + np.sum(np.log(model.variances)) + (d - m) * np.log(model.residual_variance) + d * np.log(2 * np.pi)
    )


def _normalise_shape(points: np.ndarray) -> np.ndarray:
    """Centre a point set ``(L, 2)`` and scale it to unit centroid size (its points must not all coincide)."""
    centred = points - points.mean(axis=0)
    return centred / np.sqrt(np.sum(centred**2))


def _check_point_set_sizes(point_sets: np.ndarray, name: str) -> None:
    """Refuse point sets whose points all coincide (they have no size to normalise or align).

    Parameters
    ----------
    point_sets : (T, L, 2) numpy.ndarray
        Finite point sets, already converted by ``as_finite_array`` with ``max_abs=MAX_MAGNITUDE``.
    name : str
        The argument's name, used in error messages.

    Raises
    ------
    ValueError
        Naming ``name``, for a set of coincident points.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 2 (aligned landmarks).
    """
    # compared exactly: a centroid size computed from such a set is round-off, not always zero
    coincident = np.all(point_sets == point_sets[:, :1], axis=(1, 2))
    if np.any(coincident):
        raise ValueError(f"{name} must not contain a point set whose points all coincide "
                         f"(zero centroid size at index {int(np.argmax(coincident))})")


def check_articulated_shapes(shapes: object, name: str = "shapes", *,
                             landmarks_per_limb: int | None = None) -> np.ndarray:
    """Articulated shapes ``(n, 13, m, 2)``: finite, ``m >= 2`` (or ``landmarks_per_limb``), none a single point.

    Parameters
    ----------
    shapes : (n, 13, m, 2) array_like
        The user's input.
    name : str
        The argument's name, used in error messages.
    landmarks_per_limb : int, optional
        The ``m`` a fitted model was trained with.

    Returns
    -------
    numpy.ndarray
        ``shapes`` as a float array.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 3 (a shape as K limbs of landmarks).
    """
    array = as_finite_array(shapes, name, shape=(None, 13, landmarks_per_limb, 2), max_abs=MAX_MAGNITUDE)
    check_positive_int(array.shape[2], f"the landmarks per limb of {name}", minimum=2)
    _check_point_set_sizes(array.reshape(len(array), -1, 2), name)
    return array


#: Largest float class id accepted: every whole number up to 2**53 is exactly a float64, so no two ids merge.
MAX_FLOAT_LABEL = 2.0**53


def _check_labels(labels: object, n_shapes: int) -> np.ndarray:
    """One class label per shape: class names (str) or integer class ids.

    Ids stored as floats are accepted when they are whole numbers within ±2**53 (exact in float64).
    NaN and inf are refused (NaN matches no class, so its shape would be dropped), and so are
    fractional or larger floats, which are no class id.

    Parameters
    ----------
    labels : (T,) array_like
        The class of every shape.
    n_shapes : int
        Number of shapes T.

    Returns
    -------
    numpy.ndarray
        ``labels`` as an array (the dtype as given).

    Raises
    ------
    ValueError
        Naming ``labels``, when it breaks one of these rules.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75 (the shape classes recognised).
    """
    labels = np.asarray(labels)
    check_same_shape(labels, np.arange(n_shapes), "labels", "shapes (first axis)")  # one label per shape
    check_choice(labels.dtype.kind, "labels (dtype kind: U for names, i/u/f for ids)", ("U", "i", "u", "f"))
    if labels.dtype.kind == "f":  # ids as floats: whole numbers, exact in float64
        as_finite_array(labels, "labels", dtype=np.int64, max_abs=MAX_FLOAT_LABEL)
    return labels


def check_training_set(shapes: object, labels: object) -> tuple[np.ndarray, np.ndarray]:
    """Training shapes ``(T, 13, m, 2)`` (:func:`check_articulated_shapes`) and one label each (:func:`_check_labels`).

    Parameters
    ----------
    shapes : (T, 13, m, 2) array_like
        The training shapes.
    labels : (T,) array_like
        The class of every shape.

    Returns
    -------
    tuple of numpy.ndarray
        ``shapes`` as a float array and ``labels`` as an array.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 3 (labelled training shapes).
    """
    shapes = check_articulated_shapes(shapes)
    labels = _check_labels(labels, len(shapes))
    return shapes, labels


def generalized_procrustes(point_sets: np.ndarray, *, n_iter: int = 5) -> tuple[np.ndarray, np.ndarray]:
    """Align point sets to their common mean by iterated similarity Procrustes.

    The reference starts as the first set; each round aligns every set to it and replaces it by the
    normalised mean, re-aligned to its predecessor so its orientation does not drift.

    Parameters
    ----------
    point_sets : (T, L, 2) array_like
        ``T`` sets of ``L`` landmarks; no set may have all its points coincide.
    n_iter : int
        Fixed number of rounds, from 1 to ``MAX_ITERATIONS`` (default 5).

    Returns
    -------
    aligned : numpy.ndarray
        ``(T, L, 2)``: every set similarity-aligned onto the final reference.
    reference : numpy.ndarray
        ``(L, 2)``: the mean shape, centred, of unit centroid size.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 2 (training shapes aligned before the PDM); Gower, Psychometrika 40 (1975).
    """
    sets = as_finite_array(point_sets, "point_sets", shape=(None, None, 2), max_abs=MAX_MAGNITUDE)
    check_positive_int(n_iter, "n_iter", maximum=MAX_ITERATIONS)
    _check_point_set_sizes(sets, "point_sets")
    reference = _normalise_shape(sets[0])
    aligned = sets
    for _ in range(n_iter):
        aligned = _align_to_reference(sets, reference)
        new_reference = _normalise_shape(aligned.mean(axis=0))
        reference = procrustes_align(new_reference, reference).aligned
        reference = _normalise_shape(reference)
    return _align_to_reference(sets, reference), reference


def _align_to_reference(point_sets: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Similarity-align (translation, rotation, scale) every point set ``(T, L, 2)`` onto a reference
    ``(L, 2)``: the closed form of 2-D Procrustes, all sets at once (fast path of
    :func:`_align_to_reference_loop`); callers pass sets checked by :func:`_check_point_set_sizes`.

    Written as complex numbers ``z = x + iy`` with centred source ``z`` and target ``y``, the best
    ``s R`` is the complex factor ``a = sum conj(z_i) y_i / sum |z_i|^2`` (a least-squares fit of
    ``y ~ a z``), and ``|a|``, ``arg a`` are the scale and the rotation angle.
    """
    source = point_sets[..., 0] + 1j * point_sets[..., 1]  # (T, L)
    target = reference[:, 0] + 1j * reference[:, 1]  # (L,)
    source_centred = source - source.mean(axis=1, keepdims=True)
    target_mean = target.mean()
    factor = (np.conj(source_centred) @ (target - target_mean)) / np.sum(np.abs(source_centred) ** 2, axis=1)
    aligned = factor[:, None] * source_centred + target_mean
    return np.stack([aligned.real, aligned.imag], axis=-1)


def _align_to_reference_loop(point_sets: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Reference path of ``_align_to_reference``: one SVD Procrustes fit per set (Umeyama).

    Plain loop for reading and for the tests (not exported; nothing is validated here).

    Parameters
    ----------
    point_sets : (T, L, 2) numpy.ndarray
        ``T`` sets of ``L`` landmarks.
    reference : (L, 2) numpy.ndarray
        The target landmarks.

    Returns
    -------
    numpy.ndarray
        ``(T, L, 2)``: each set under its least-squares similarity onto ``reference``.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 2 (aligned landmarks); Umeyama, IEEE PAMI 13 (1991).
    """
    return np.stack([procrustes_align(points, reference).aligned for points in point_sets])
