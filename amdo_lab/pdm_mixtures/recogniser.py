"""Hierarchical recognition with mixtures of limb PDMs and polar limb-arrangement PDMs (Secs. 4-6)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from amdo_lab.common import (
    as_finite_array,
    check_bool,
    check_choice,
    check_fitted,
    check_in_range,
    check_positive,
    check_positive_int,
    make_rng,
    procrustes_align,
)
from amdo_lab.common.threads import one_blas_thread
from amdo_lab.pdm_mixtures.gmm import fit_gaussian_mixture, fit_gaussian_mixtures_batch
from amdo_lab.pdm_mixtures.pdm import (
    MAX_MAGNITUDE,
    PointDistributionModel,
    align_to_reference,
    check_labels,
    check_point_set_sizes,
    fit_modes,
    fit_pdm,
    generalized_procrustes,
    pdm_from_moments,
    ppca_log_density,
    reconstruct,
)
from amdo_lab.pdm_mixtures.representation import centred_limbs, polar_shape_vector, wrap_angle

__all__ = [
    "ArticulatedShapeRecogniser",
    "PolarPDM",
    "RecognitionTrace",
    "ScoreComponents",
    "AlignmentTrace",
    "hamming_distance",
    "label_string_log_prob",
    "held_out_log_likelihood",
]

N_LIMBS = 13
MIN_PER_CLASS = 3


def hamming_distance(label_strings: np.ndarray, dictionary: np.ndarray) -> np.ndarray:
    """Hamming distance: the number of mismatching limb labels between label strings and dictionary items.

    Eq. 17 as printed sums a Kronecker delta of *equal* labels, which counts matches; a Hamming
    distance counts mismatches, ``sum_i (1 - delta(l_i, lambda_i))``, which is what we compute.

    Parameters
    ----------
    label_strings : (n, K) array_like of int
        Limb-label indices of ``n`` shapes.
    dictionary : (C, K) array_like of int
        Permissible label strings.

    Returns
    -------
    numpy.ndarray
        ``(n, C)`` int distances, each in [0, K].

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 6, eq. 17 (read as a distance).

    Examples
    --------
    >>> hamming_distance([[0, 1, 2]], [[0, 1, 2], [0, 2, 2]])
    array([[0, 1]])
    """
    strings = as_finite_array(label_strings, "label_strings", ndim=2, dtype=int)
    dictionary = as_finite_array(dictionary, "dictionary", ndim=2, dtype=int)
    if dictionary.shape[1] != strings.shape[1]:
        raise ValueError(f"label_strings and dictionary must have as many columns (limbs), "
                         f"got {strings.shape[1]} and {dictionary.shape[1]}")
    return _hamming_distance(strings, dictionary)


def _hamming_distance(label_strings: np.ndarray, dictionary: np.ndarray) -> np.ndarray:
    """Fast path of :func:`hamming_distance_reference`: all pairs at once by broadcasting."""
    return np.sum(label_strings[:, None, :] != dictionary[None, :, :], axis=2)


def hamming_distance_reference(label_strings: np.ndarray, dictionary: np.ndarray) -> np.ndarray:
    """Eq. 17 read as a distance, one pair at a time: ``H(L, Lambda) = sum_i (1 - delta(l_i, lambda_i))``.

    The reference path of :func:`hamming_distance`, for reading and for the tests (not exported;
    nothing is validated here).

    Parameters
    ----------
    label_strings : (n, K) numpy.ndarray of int
        Limb-label indices of ``n`` shapes.
    dictionary : (C, K) numpy.ndarray of int
        Permissible label strings.

    Returns
    -------
    numpy.ndarray of int
        ``(n, C)`` distances.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 6, eq. 17.
    """
    distances = np.zeros((len(label_strings), len(dictionary)), dtype=int)
    for a, string in enumerate(label_strings):
        for b, item in enumerate(dictionary):
            for label, permitted in zip(string, item):
                distances[a, b] += 1 - int(label == permitted)  # 1 - Kronecker delta, eq. 17
    return distances


def label_string_log_prob(hamming: np.ndarray, n_limbs: int, error_probability: float) -> np.ndarray:
    """ln P(L | Lambda) = ln K_p - k_p H with K_p = (1 - p)^K, k_p = ln((1 - p) / p) (eq. 18).

    Parameters
    ----------
    hamming : array_like of int
        Hamming distances H, each in [0, n_limbs].
    n_limbs : int
        Number of limbs K (positive).
    error_probability : float
        Label error probability p, in (0, 1).

    Returns
    -------
    numpy.ndarray
        ``ln P(L | Lambda)`` in nats, the shape of ``hamming``.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 6, eq. 18.
    """
    n_limbs = check_positive_int(n_limbs, "n_limbs")
    p = check_in_range(error_probability, "error_probability", 0, 1)
    distances = as_finite_array(hamming, "hamming", dtype=int)
    if np.any((distances < 0) | (distances > n_limbs)):
        raise ValueError(f"hamming must hold distances in [0, n_limbs={n_limbs}], "
                         f"got {distances.min()}..{distances.max()}")
    return _label_string_log_prob(distances, n_limbs, p)


def _label_string_log_prob(hamming: np.ndarray, n_limbs: int, error_probability: float) -> np.ndarray:
    p = error_probability
    log_k_p = n_limbs * np.log1p(-p)  # ln K_p = K ln(1 - p), eq. 18
    k_p = np.log((1 - p) / p)  # k_p = ln((1 - p) / p), eq. 18
    return log_k_p - k_p * hamming


@dataclass(frozen=True)
class PolarPDM:
    """One polar point distribution model of S = (Theta, C): one PDM per block of S (Sec. 4).

    With ``polar_model="block"`` (our default) the K angle rows and the 2K centre rows of S each get
    their own PDM, so the angle eigenvalues alpha_k that clamp the angle parameters come from the
    covariance of the angles alone, as Sec. 4 describes; with ``"joint"`` one PDM spans all 3K rows.

    Parameters
    ----------
    blocks : tuple of slice
        The rows of S each PDM models (angles ``0:K`` and centres ``K:3K``, or all ``0:3K``).
    pdms : tuple of PointDistributionModel
        One PDM per block, in deviation coordinates (angles relative to the class's circular mean).

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 4 (the polar PDM of S) and Sec. 5, eq. 12 (its clamped fit).
    """

    blocks: tuple[slice, ...]
    pdms: tuple[PointDistributionModel, ...]

    @property
    def mean(self) -> np.ndarray:
        """The mean vector S (in deviation coordinates), ``(3K,)``."""
        return np.concatenate([pdm.mean for pdm in self.pdms])

    @property
    def n_modes(self) -> int:
        """Total number of kept eigenmodes over the blocks."""
        return sum(pdm.n_modes for pdm in self.pdms)

    def project(self, deviation: np.ndarray) -> np.ndarray:
        """Project polar vectors onto the model: the clamped modal fit of every block (eq. 12), reconstructed.

        Parameters
        ----------
        deviation : (n, 3K) array_like
            Polar vectors S with angles relative to the class's circular mean (radians, wrapped).

        Returns
        -------
        numpy.ndarray
            ``(n, 3K)``: each block's model instance ``Y + Phi gamma`` with ``gamma`` clamped to
            ``+-3 sqrt(alpha_k)``.
        """
        return self._project(self._check_deviation(deviation))

    def log_density(self, deviation: np.ndarray) -> np.ndarray:
        """``ln p(S | Phi, Gamma*)``: the sum over blocks of each PDM's Gaussian (PPCA) density.

        Parameters
        ----------
        deviation : (n, 3K) array_like
            Polar vectors S with angles relative to the class's circular mean (radians, wrapped).

        Returns
        -------
        numpy.ndarray
            ``(n,)`` log-densities in nats.
        """
        return self._log_density(self._check_deviation(deviation))

    def _check_deviation(self, deviation: object) -> np.ndarray:
        width = max(block.stop for block in self.blocks)
        return as_finite_array(deviation, "deviation", shape=(None, width), max_abs=MAX_MAGNITUDE)

    def _project(self, deviation: np.ndarray) -> np.ndarray:
        return np.concatenate([reconstruct(pdm, fit_modes(pdm, deviation[:, block]))
                               for pdm, block in zip(self.pdms, self.blocks)], axis=1)

    def _log_density(self, deviation: np.ndarray) -> np.ndarray:
        total = np.zeros(deviation.shape[0])
        for pdm, block in zip(self.pdms, self.blocks):
            data = deviation[:, block]
            total += ppca_log_density(pdm, data)
        return total


@dataclass(frozen=True)
class RecognitionTrace:
    """Per-iteration record of hierarchical recognition.

    Parameters
    ----------
    posteriors : (n_iter, n, C) numpy.ndarray
        Class posteriors ``P(w | shape)`` (eq. 13's argument), columns in ``classes_`` order.
    label_strings : (n_iter, n, K) numpy.ndarray
        Limb labels in use at each iteration (eq. 10 at the first, eq. 14 later).
    reconstructions : (n_iter, n, 3K) numpy.ndarray
        Posterior-weighted polar model fits S (eq. 12), angles in radians.
    n_iter : int
        Number of iterations run, at most the recogniser's ``max_iter``.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Secs. 5-6, eqs. 9-18.
    """

    posteriors: np.ndarray
    label_strings: np.ndarray
    reconstructions: np.ndarray
    n_iter: int


@dataclass(frozen=True)
class ScoreComponents:
    """The terms of the first-iteration score of every class ``w`` and mixture component ``m``.

    Parameters
    ----------
    limb_gate : (n, C, M) numpy.ndarray
        Limb gates ``sum_k ln P(lambda_k^wm | z_k)`` (eq. 11).
    label_string : (n, C, M) numpy.ndarray
        ``ln P(L | Lambda_wm)`` of the MAP labels (eq. 18).
    shape : (n, C, M) numpy.ndarray
        Polar-PDM log-likelihoods ``ln p(S | Phi_wm, Gamma_wm*)``.
    log_weights : (C, M) numpy.ndarray
        Log mixing weights ``ln pi_wm``.
    class_log_prior : (C,) numpy.ndarray
        Log class priors ``ln P(w)`` (training frequencies).

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Secs. 5-6, eqs. 11 and 18.
    """

    limb_gate: np.ndarray
    label_string: np.ndarray
    shape: np.ndarray
    log_weights: np.ndarray
    class_log_prior: np.ndarray

    def class_scores(self, *terms: str) -> np.ndarray:
        """Class log-scores from a subset of the terms.

        Parameters
        ----------
        *terms : str
            One or more of ``"limb_gate"``, ``"label_string"``, ``"shape"``.

        Returns
        -------
        numpy.ndarray
            ``(n, C)``: ``ln P(w) + ln sum_m pi_wm exp(sum of the chosen terms)``, in nats.
        """
        unknown = [t for t in terms if t not in ("limb_gate", "label_string", "shape")]
        if unknown or not terms:
            raise ValueError(f"terms must be some of 'limb_gate', 'label_string', 'shape', got {terms}")
        joint = self.log_weights[None] + sum(getattr(self, t) for t in terms)
        return self.class_log_prior + np.logaddexp.reduce(joint, axis=2)

    def printed_eq11_scores(self) -> np.ndarray:
        """Class scores of eq. 11 read as printed: the gates multiply the log-likelihood.

        ``sum_m pi_wm G_wm ln p(S | Phi_wm, Gamma_wm*)`` with the gate
        ``G_wm = P(L | Lambda_wm) prod_k P(lambda_k^wm | z_k)``. This is not a log-probability: a
        class whose gates vanish scores near 0, above every class whose ``ln p`` is negative. The
        recogniser's own reading is :meth:`class_scores` with all three terms, which adds ``ln G`` to
        ``ln p`` (the class posterior is proportional to ``G p``).

        Returns
        -------
        numpy.ndarray
            ``(n, C)`` scores; their argmax over classes is the printed reading's decision.

        References
        ----------
        Al-Shaher & Hancock, AMDO 2004, LNCS 3179, pp. 62-75, Sec. 5, eq. 11.
        """
        gates = np.exp(self.limb_gate + self.label_string)  # G_wm, (n, C, M)
        return np.sum(np.exp(self.log_weights)[None] * gates * self.shape, axis=2)


@dataclass(frozen=True)
class AlignmentTrace:
    """Record of the iterative alignment of one class model to one shape.

    Parameters
    ----------
    model_shapes : (n_iter, K, m, 2) numpy.ndarray
        Model instances drawn in the test shape's frame, one per iteration of the alternating
        pose / modal fit.
    centre_rms : (n_iter,) numpy.ndarray
        RMS misfit of the posed model limb centres to the shape's, per iteration, in the shape's units.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 5, eqs. 12 and 15.
    """

    model_shapes: np.ndarray
    centre_rms: np.ndarray


def _check_class_names(classes: object) -> tuple:
    """The recogniser's ``classes``: a non-empty sequence of distinct class names."""
    if isinstance(classes, str) or not hasattr(classes, "__iter__"):
        raise TypeError(f"classes must be a sequence of class names, got {classes!r}")
    names = tuple(classes)
    if not names:
        raise ValueError("classes must name at least one class, got an empty sequence")
    try:
        distinct = len(set(names))
    except TypeError:
        raise TypeError(f"classes must hold hashable class names, got {names!r}") from None
    if distinct != len(names):
        raise ValueError(f"classes must not repeat a name, got {names}")
    return names


def _circular_mean(angles: np.ndarray) -> np.ndarray:
    return np.arctan2(np.sin(angles).mean(axis=0), np.cos(angles).mean(axis=0))


def polar_blocks(polar_model: str) -> tuple[slice, ...]:
    """The column blocks of the polar vector S that get one PDM each (not exported).

    Parameters
    ----------
    polar_model : {"block", "joint"}
        "block": the 13 angles and the 26 centre coordinates apart; "joint": all 39 together.

    Returns
    -------
    tuple of slice
        The blocks, in column order.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 3 (the vector S).
    """
    if polar_model == "block":
        return (slice(0, N_LIMBS), slice(N_LIMBS, 3 * N_LIMBS))
    return (slice(0, 3 * N_LIMBS),)


class ArticulatedShapeRecogniser:
    """Two-layer recogniser: limb PDM mixtures + label dictionary + per-class mixtures of polar PDMs.

    Follows scikit-learn's estimator contract: the settings are stored as given and checked by
    :meth:`fit`, which returns the recogniser; learned attributes end with an underscore; using it
    unfitted raises ``sklearn.exceptions.NotFittedError``.

    Parameters
    ----------
    rng : int or numpy.random.Generator
        Seed or generator of the k-means++ starts of the shape-level EM (keyword-only, no default;
        an int seed gives the same starts at every ``fit``).
    n_limb_labels : int
        Mixture components (limb labels) learnt by EM for each of the 13 limbs (positive).
    n_shape_components : int
        Polar-PDM mixture components learnt by EM for each class (1 gives one polar PDM per class).
        Each component has its own permissible label string in the class's dictionary.
    shape_ridge : float
        Ridge added to every shape-level EM covariance (eq. 8), as a multiple of the mean variance
        of the block-scaled S (positive; the paper leaves it open, default 1e-3). It also sets the
        smallest eigenvalues a component PDM can have, hence its residual variance.
    n_restarts : int
        Seeded k-means++ starts of each class's shape-level EM; the run with the highest final
        training log-likelihood (eq. 3) is kept (default 1, a single start).
    label_error_probability : float
        p of eq. 18, in (0, 0.5).
    variance_fraction : float
        Fraction of the variance kept by each PDM's eigenmodes, in (0, 1].
    max_iter : int
        Upper bound on the recognition iterations (class scores, eq. 13, then relabelling, eq. 14);
        the loop stops earlier once the limb labels no longer change. Positive.
    n_em_iter : int
        Fixed number of iterations of every EM fit (eqs. 2-8), positive.
    polar_model : {"block", "joint"}
        ``"block"``: separate PDMs for the angle rows and the centre rows of S (Sec. 4: the first K
        rows of Gamma are the angles, constrained by the eigenvalues of the angle covariance);
        ``"joint"``: one PDM over all of S, whose eigenmodes radians then dominate (an ablation).
    limb_likelihood : {"gaussian", "residual"}
        How a limb's label posterior (eq. 10) is computed: ``"gaussian"``, the label component's
        Gaussian (eq. 6) restricted to its PDM (in-model Mahalanobis term on gamma plus residual);
        ``"residual"``, the isotropic fit residual alone (eq. 16), the paper's "in practice" choice.
    classes : sequence of str, optional
        The expected class names; then every one must have training examples.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Secs. 4-6, eqs. 2-18.

    Examples
    --------
    >>> from amdo_lab.pdm_mixtures import TABLE1_CLASSES, generate_pose_dataset
    >>> train = generate_pose_dataset(TABLE1_CLASSES, 20, rng=1)
    >>> test = generate_pose_dataset(TABLE1_CLASSES, 10, rng=2)
    >>> recogniser = ArticulatedShapeRecogniser(rng=0).fit(train.shapes, train.labels)
    >>> recogniser.predict(test.shapes[:3]).tolist()
    ['boxing', 'boxing', 'boxing']
    >>> round(float(np.mean(recogniser.predict(test.shapes) == test.labels)), 2)
    0.97
    """

    def __init__(
        self,
        *,
        rng: int | np.random.Generator,
        n_limb_labels: int = 4,
        n_shape_components: int = 2,
        shape_ridge: float = 1e-3,
        n_restarts: int = 1,
        label_error_probability: float = 0.2,
        variance_fraction: float = 0.95,
        max_iter: int = 10,
        n_em_iter: int = 30,
        polar_model: str = "block",
        limb_likelihood: str = "gaussian",
        classes: tuple[str, ...] | None = None,
    ) -> None:
        # Stored as given (scikit-learn's contract); fit validates them.
        self.n_limb_labels = n_limb_labels
        self.n_shape_components = n_shape_components
        self.rng = rng
        self.shape_ridge = shape_ridge
        self.n_restarts = n_restarts
        self.label_error_probability = label_error_probability
        self.variance_fraction = variance_fraction
        self.max_iter = max_iter
        self.n_em_iter = n_em_iter
        self.polar_model = polar_model
        self.limb_likelihood = limb_likelihood
        self.classes = classes

    def _check_params(self) -> tuple | None:
        """Validate the settings given to ``__init__`` (called by :meth:`fit`); returns ``classes``
        as a tuple (or None)."""
        make_rng(self.rng, "rng")
        check_positive_int(self.n_limb_labels, "n_limb_labels")
        check_positive_int(self.n_shape_components, "n_shape_components")
        check_positive(self.shape_ridge, "shape_ridge")
        check_positive_int(self.n_restarts, "n_restarts")
        check_in_range(self.label_error_probability, "label_error_probability", 0, 0.5)
        check_in_range(self.variance_fraction, "variance_fraction", 0, 1, closed="right")
        check_positive_int(self.max_iter, "max_iter")
        check_positive_int(self.n_em_iter, "n_em_iter")
        check_choice(self.polar_model, "polar_model", ("block", "joint"))
        check_choice(self.limb_likelihood, "limb_likelihood", ("gaussian", "residual"))
        return None if self.classes is None else _check_class_names(self.classes)

    # ------------------------------------------------------------------ validation
    def _check_shapes(self, shapes: object, name: str = "shapes") -> np.ndarray:
        array = as_finite_array(shapes, name, shape=(None, N_LIMBS, None, 2))
        if array.shape[2] < 2:
            raise ValueError(f"{name} must have at least 2 landmarks per limb, got {array.shape[2]}")
        check_point_set_sizes(array.reshape(len(array), -1, 2), name)
        if hasattr(self, "landmarks_per_limb_") and array.shape[2] != self.landmarks_per_limb_:
            raise ValueError(
                f"{name} must have {self.landmarks_per_limb_} landmarks per limb (as in training), got {array.shape[2]}"
            )
        return array

    # ------------------------------------------------------------------ training
    def fit(self, shapes: np.ndarray, labels: np.ndarray) -> "ArticulatedShapeRecogniser":
        """Learn the limb mixtures, the class polar-PDM mixtures and the label dictionary.

        Parameters
        ----------
        shapes : (T, 13, m, 2) array_like
            Training shapes, ``m >= 2`` landmarks per limb; no shape may have all its landmarks coincide.
        labels : (T,) array_like
            Class name of every training shape; every class needs ``3 * n_shape_components`` shapes.

        Returns
        -------
        ArticulatedShapeRecogniser
            This recogniser, fitted.
        """
        with one_blas_thread():  # small matrices: BLAS threads only contend on a shared machine
            return self._fit(shapes, labels)

    def _fit(self, shapes: np.ndarray, labels: np.ndarray) -> "ArticulatedShapeRecogniser":
        expected_classes = self._check_params()
        for learned in [name for name in vars(self) if name.endswith("_")]:
            delattr(self, learned)  # a refit starts afresh (the landmark count may change)
        shapes = self._check_shapes(shapes)
        labels = check_labels(labels, shapes.shape[0])
        present = tuple(dict.fromkeys(labels.tolist()))
        if expected_classes is not None:
            unknown = sorted(set(present) - set(expected_classes))
            if unknown:
                raise ValueError(f"labels contains class name(s) {unknown} not in classes={expected_classes}")
            empty = [c for c in expected_classes if c not in present]
            if empty:
                raise ValueError(f"class(es) {empty} have no training examples")
            present = expected_classes
        counts = {c: int(np.sum(labels == c)) for c in present}
        needed = MIN_PER_CLASS * self.n_shape_components
        few = {c: k for c, k in counts.items() if k < needed}
        if few:
            raise ValueError(
                f"every class needs at least {needed} training examples for a covariance "
                f"({MIN_PER_CLASS} per shape component), got {few}"
            )
        self.classes_ = present
        self.landmarks_per_limb_ = shapes.shape[2]
        flat = shapes.reshape(shapes.shape[0], -1, 2)
        aligned, self.reference_ = generalized_procrustes(flat)
        aligned = aligned.reshape(shapes.shape)
        self._fit_limb_layer(aligned)
        self.training_label_strings_ = np.argmax(self._limb_log_posteriors(aligned), axis=2)  # (n, K), eq. 10
        responsibilities = self._fit_shape_layer(aligned, labels)
        # Dictionary (Sec. 5): one permissible label string per class and mixture component, the most
        # frequent MAP label of each limb over the class's training shapes, each shape counted with
        # its EM responsibility for the component.
        one_hot = self.training_label_strings_[..., None] == np.arange(self.n_limb_labels)  # (n, K, labels)
        self.dictionary_ = np.stack([
            np.argmax(np.einsum("tm,tkl->mkl", resp, one_hot[labels == c]), axis=2)
            for c, resp in zip(self.classes_, responsibilities)
        ])  # (C, M, K)
        self.class_log_prior_ = np.log(np.array([counts[c] for c in self.classes_], float) / len(labels))
        return self

    def _fit_limb_layer(self, aligned: np.ndarray) -> None:
        """One Gaussian mixture per limb by EM (eqs. 2-8), all 13 limbs in one batched loop (each
        limb's run is :func:`fit_gaussian_mixture` from a farthest-point start and its pooled
        covariance); each component becomes a limb-label PDM."""
        limbs = np.swapaxes(centred_limbs(aligned), 0, 1)  # (K, n, 2m)
        d = limbs.shape[2]
        starts = np.stack([data[_farthest_point_init(data, self.n_limb_labels)] for data in limbs])
        spreads = np.stack([np.cov(data.T, bias=True) + 1e-6 * np.eye(d) for data in limbs])
        ridges = 1e-3 * np.trace(spreads, axis1=1, axis2=2) / d
        weights, means, covariances, _ = fit_gaussian_mixtures_batch(
            limbs, starts, np.repeat(spreads[:, None], self.n_limb_labels, axis=1), self.n_em_iter, ridges)
        self.limb_models_: list[list[PointDistributionModel]] = []
        self.limb_weights_ = weights
        self.limb_noise_ = np.empty(N_LIMBS)
        for k in range(N_LIMBS):
            models = [pdm_from_moments(m, c, variance_fraction=self.variance_fraction)
                      for m, c in zip(means[k], covariances[k])]
            self.limb_models_.append(models)
            # Isotropic residual variance of eq. 16, from each example's best-fitting label.
            errors = np.stack([_fit_error(mdl, limbs[k]) for mdl in models], axis=1)
            self.limb_noise_[k] = max(float(errors.min(axis=1).mean()) / d, 1e-12)

    def _limb_log_posteriors(self, aligned: np.ndarray) -> np.ndarray:
        """log P(lambda | z_k) for every shape, limb and label (eqs. 4, 9, 10): ``(n, K, labels)``.

        The class-conditional density of a label is its PDM's Gaussian (``limb_likelihood=
        "gaussian"``) or the isotropic residual of the clamped fit (``"residual"``, eq. 16)."""
        limbs = centred_limbs(aligned)
        log_lik = np.empty((aligned.shape[0], N_LIMBS, self.n_limb_labels))
        for k in range(N_LIMBS):
            data = limbs[:, k]
            if self.limb_likelihood == "gaussian":
                log_lik[:, k] = np.stack([ppca_log_density(model, data) for model in self.limb_models_[k]], axis=1)
            else:
                errors = np.stack([_fit_error(mdl, data) for mdl in self.limb_models_[k]], axis=1)
                log_lik[:, k] = -errors / (2 * self.limb_noise_[k])  # ln of eq. (16): isotropic fit residual
            log_lik[:, k] += np.log(self.limb_weights_[k])
        # Bayes' rule over the labels: ln P(λ | z_k, γ_λ, Φ_λ), the posterior that eq. (10) maximises
        return log_lik - np.logaddexp.reduce(log_lik, axis=2, keepdims=True)

    def _fit_shape_layer(self, aligned: np.ndarray, labels: np.ndarray) -> list[np.ndarray]:
        """Per class, a mixture of polar PDMs learnt by EM (Sec. 4, eqs. 2-8) on S relative to the
        class's circular mean angles; EM starts from a seeded k-means++ partition. Returns each
        class's training responsibilities ``(T_c, M)``."""
        vectors = polar_shape_vector(aligned)
        blocks = polar_blocks(self.polar_model)
        rng = make_rng(self.rng, "rng")
        self.angle_means_ = []
        self.shape_models_: list[list[PolarPDM]] = []
        self.shape_weights_: list[np.ndarray] = []
        responsibilities = []
        for c in self.classes_:
            class_vectors = vectors[labels == c]
            angle_mean = _circular_mean(class_vectors[:, :N_LIMBS])
            self.angle_means_.append(angle_mean)
            deviation = self._deviation(class_vectors, angle_mean)
            models, weights, resp = fit_polar_mixture(deviation, self.n_shape_components, blocks, rng,
                                                       self.n_em_iter, self.variance_fraction,
                                                       ridge=self.shape_ridge, n_restarts=self.n_restarts)
            self.shape_models_.append(models)
            self.shape_weights_.append(weights)
            responsibilities.append(resp)
        # The most responsible component of every training shape, per class (for inspection).
        self.training_components_ = [
            np.argmax(self._component_log_likelihoods(self._deviation(vectors[labels == c], a), j)[0], axis=1)
            for j, (c, a) in enumerate(zip(self.classes_, self.angle_means_))
        ]
        return responsibilities

    @staticmethod
    def _deviation(vectors: np.ndarray, angle_mean: np.ndarray) -> np.ndarray:
        """S relative to the class's circular mean angles (wrapped), so the PDM never sees a flip."""
        out = vectors.copy()
        out[:, :N_LIMBS] = wrap_angle(vectors[:, :N_LIMBS] - angle_mean)
        return out

    def _component_log_likelihoods(self, deviation: np.ndarray, j: int) -> tuple[np.ndarray, np.ndarray]:
        """``ln pi_m + ln p(S | Phi_m, Gamma_m*)`` for every component m of class j, ``(n, M)``, and
        the clamped modal fits ``(M, n, 3K)`` (in deviation coordinates)."""
        scores = np.stack([np.log(weight) + model._log_density(deviation)
                           for model, weight in zip(self.shape_models_[j], self.shape_weights_[j])], axis=1)
        fits = np.stack([model._project(deviation) for model in self.shape_models_[j]])
        return scores, fits

    def _shape_terms(self, aligned: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Polar-PDM log-likelihoods ``(n, C, M)`` (without the mixing weights) and model fits
        ``(C, M, n, 3K)`` with the angles put back in absolute terms."""
        vectors = polar_shape_vector(aligned)
        log_lik, fits = [], []
        for j, angle_mean in enumerate(self.angle_means_):
            scores, component_fits = self._component_log_likelihoods(self._deviation(vectors, angle_mean), j)
            log_lik.append(scores - np.log(self.shape_weights_[j]))
            component_fits[..., :N_LIMBS] = wrap_angle(component_fits[..., :N_LIMBS] + angle_mean)
            fits.append(component_fits)
        return np.stack(log_lik, axis=1), np.stack(fits)

    def _gates(self, limb_log_post: np.ndarray) -> np.ndarray:
        """Eq. 11's first gate, ``sum_k ln P(lambda_k^wm | z_k)`` for every dictionary string: ``(n, C, M)``."""
        n = limb_log_post.shape[0]
        strings = self.dictionary_.reshape(-1, N_LIMBS)  # (C*M, K)
        picked = np.take_along_axis(limb_log_post[:, None], strings[None, :, :, None], axis=3)[..., 0]
        return picked.sum(axis=2).reshape(n, *self.dictionary_.shape[:2])

    def _string_log_prob(self, label_strings: np.ndarray) -> np.ndarray:
        """Eq. 18's ``ln P(L | Lambda_wm)`` for every dictionary string: ``(n, C, M)``."""
        hamming = _hamming_distance(label_strings, self.dictionary_.reshape(-1, N_LIMBS))
        return _label_string_log_prob(hamming, N_LIMBS, self.label_error_probability).reshape(
            len(label_strings), *self.dictionary_.shape[:2])

    # ------------------------------------------------------------------ recognition
    def align(self, shapes: np.ndarray) -> np.ndarray:
        """Procrustes-align shapes onto the training reference (removes the global similarity).

        Parameters
        ----------
        shapes : (n, 13, m, 2) array_like
            Articulated shapes, with as many landmarks per limb (``m``) as the training shapes.

        Returns
        -------
        numpy.ndarray
            ``(n, 13, m, 2)`` aligned shapes, in the reference's frame (unit centroid size).
        """
        check_fitted(self, "classes_")
        shapes = self._check_shapes(shapes)
        flat = shapes.reshape(shapes.shape[0], -1, 2)
        return align_to_reference(flat, self.reference_).reshape(shapes.shape)

    def recognise(self, shapes: np.ndarray) -> RecognitionTrace:
        """Run the hierarchical EM (eqs. 9-18) and return the full per-iteration trace.

        Parameters
        ----------
        shapes : (n, 13, m, 2) array_like
            Articulated shapes, with as many landmarks per limb (``m``) as the training shapes.

        Returns
        -------
        RecognitionTrace
            Class posteriors, limb labels and model fits of every iteration until the labels stop
            changing (at most ``max_iter``).
        """
        with one_blas_thread():
            return self._recognise(shapes)

    def _recognise(self, shapes: np.ndarray) -> RecognitionTrace:
        check_fitted(self, "classes_")
        aligned = self.align(shapes)
        limb_log_post = self._limb_log_posteriors(aligned)  # (n, K, labels)
        shape_log_lik, fits = self._shape_terms(aligned)  # (n, C, M), (C, M, n, 3K)
        gate = self._gates(limb_log_post)  # (n, C, M)
        log_weights = np.log(np.stack(self.shape_weights_))  # (C, M)
        k_p = np.log((1 - self.label_error_probability) / self.label_error_probability)
        label_strings = np.argmax(limb_log_post, axis=2)  # eq. 10: MAP limb labels
        history_post, history_labels, history_fit = [], [], []
        rows = np.arange(len(aligned))
        for _ in range(self.max_iter):
            # Eqs. 11-13: every component's polar likelihood gated by its limb posteriors and by
            # P(L | Lambda) of its dictionary string; a class sums its components.
            joint = log_weights[None] + shape_log_lik + gate + self._string_log_prob(label_strings)
            class_joint = np.logaddexp.reduce(joint, axis=2)  # (n, C)
            log_score = self.class_log_prior_ + class_joint
            posterior = np.exp(log_score - np.logaddexp.reduce(log_score, axis=1, keepdims=True))
            within = np.exp(joint - class_joint[..., None])  # component responsibilities per class
            history_post.append(posterior)
            history_labels.append(label_strings)
            history_fit.append(np.einsum("nc,ncm,cmnd->nd", posterior, within, fits))
            best = np.argmax(posterior, axis=1)  # eq. 13
            component = np.argmax(joint[rows, best], axis=1)
            # Eq. 14: relabel limbs using the winning class component's dictionary string as prior.
            consistent = self.dictionary_[best, component][:, :, None] == np.arange(self.n_limb_labels)
            refined = np.argmax(limb_log_post + np.where(consistent, 0.0, -k_p), axis=2)
            if np.array_equal(refined, label_strings):
                break
            label_strings = refined
        return RecognitionTrace(np.stack(history_post), np.stack(history_labels), np.stack(history_fit),
                                len(history_post))

    def limb_label_posteriors(self, shapes: np.ndarray, *, log: bool = False) -> np.ndarray:
        """Label posteriors ``P(lambda | z_k)`` of every limb of every shape (eqs. 9-10).

        Each label's PDM is fitted to the limb and Bayes' rule applied with the label's mixing weight.

        Parameters
        ----------
        shapes : (n, 13, m, 2) array_like
            Articulated shapes, with as many landmarks per limb (``m``) as the training shapes.
        log : bool
            Return the logarithms instead (exact where the posteriors underflow to 0).

        Returns
        -------
        numpy.ndarray
            ``(n, K, n_limb_labels)`` posteriors (rows sum to 1), or their logarithms.
        """
        check_fitted(self, "classes_")
        log = check_bool(log, "log")
        log_posteriors = self._limb_log_posteriors(self.align(shapes))
        return log_posteriors if log else np.exp(log_posteriors)

    def score_components(self, shapes: np.ndarray) -> ScoreComponents:
        """The separate terms of the first-iteration class score (for ablations).

        Parameters
        ----------
        shapes : (n, 13, m, 2) array_like
            Articulated shapes, with as many landmarks per limb (``m``) as the training shapes.

        Returns
        -------
        ScoreComponents
            The limb gates, label-string and polar-PDM terms, weights and priors.
        """
        check_fitted(self, "classes_")
        aligned = self.align(shapes)
        limb_log_post = self._limb_log_posteriors(aligned)
        shape_log_lik, _ = self._shape_terms(aligned)
        return ScoreComponents(self._gates(limb_log_post), self._string_log_prob(np.argmax(limb_log_post, axis=2)),
                               shape_log_lik, np.log(np.stack(self.shape_weights_)), self.class_log_prior_)

    def iterative_alignment(self, shape: np.ndarray, class_name: str, n_iter: int = 4) -> AlignmentTrace:
        """Fit one class's polar PDM to one shape, alternating a pose fit with the modal fit.

        Each iteration poses the model's limb centres onto the shape's (similarity Procrustes), then
        refits the clamped modes (eq. 12) in the model frame; iteration 1 is the mean shape posed
        onto the data, later iterations also fit each limb's dictionary-label PDM to the data limb
        (eq. 15). The class's mixture component that best explains the shape is used.

        Parameters
        ----------
        shape : (13, m, 2) array_like
            One articulated shape.
        class_name : str
            A name in ``classes_``.
        n_iter : int
            Fixed number of iterations (positive; default 4).

        Returns
        -------
        AlignmentTrace
            The posed model shape and the limb-centre RMS misfit of every iteration.
        """
        check_fitted(self, "classes_")
        if class_name not in self.classes_:
            raise ValueError(f"class_name must be one of {self.classes_}, got {class_name!r}")
        n_iter = check_positive_int(n_iter, "n_iter")
        shape = self._check_shapes(np.asarray(shape)[None])[0]
        j = self.classes_.index(class_name)
        angle_mean = self.angle_means_[j]
        # Use the class's mixture component that best explains the shape as first posed.
        start = self._deviation(polar_shape_vector(self.align(shape[None])), angle_mean)
        best = int(np.argmax(self._component_log_likelihoods(start, j)[0][0]))
        model, labels = self.shape_models_[j][best], self.dictionary_[j, best]
        data_centres = shape.mean(axis=1)
        model_vector = model.mean.copy()
        model_vector[:N_LIMBS] = wrap_angle(model_vector[:N_LIMBS] + angle_mean)
        drawn, misfit = [], []
        for _ in range(n_iter):
            model_centres = model_vector[N_LIMBS:].reshape(N_LIMBS, 2)
            pose = procrustes_align(model_centres, data_centres)
            # The data mapped into the model frame (inverse of the pose), limbs included.
            shape_in_model = ((shape - pose.translation) @ pose.rotation) / pose.scale
            limbs_in_model = centred_limbs(shape_in_model[None])[0]
            model_shape = self._model_limbs(model_vector, labels, None if not drawn else limbs_in_model)
            drawn.append(pose.scale * model_shape @ pose.rotation.T + pose.translation)
            misfit.append(pose.rms_error)
            deviation = self._deviation(polar_shape_vector(shape_in_model[None]), angle_mean)
            model_vector = model._project(deviation)[0]
            model_vector[:N_LIMBS] = wrap_angle(model_vector[:N_LIMBS] + angle_mean)
        return AlignmentTrace(np.stack(drawn), np.array(misfit))

    def predict_proba(self, shapes: np.ndarray) -> np.ndarray:
        """Class posteriors at the last iteration of :meth:`recognise`.

        Parameters
        ----------
        shapes : (n, 13, m, 2) array_like
            Articulated shapes, with as many landmarks per limb (``m``) as the training shapes.

        Returns
        -------
        numpy.ndarray
            ``(n, C)`` posteriors (rows sum to 1), columns in ``classes_`` order.
        """
        return self.recognise(shapes).posteriors[-1]

    def predict(self, shapes: np.ndarray) -> np.ndarray:
        """MAP class names (eq. 13).

        Parameters
        ----------
        shapes : (n, 13, m, 2) array_like
            Articulated shapes, with as many landmarks per limb (``m``) as the training shapes.

        Returns
        -------
        numpy.ndarray
            ``(n,)`` class names from ``classes_``.
        """
        proba = self.predict_proba(shapes)
        return np.asarray(self.classes_)[np.argmax(proba, axis=1)]

    def model_limbs(self, polar_vector: np.ndarray, label_string: np.ndarray,
                    observed_limbs: np.ndarray | None = None) -> np.ndarray:
        """Draw a model shape at the limb centres of a polar vector S.

        Parameters
        ----------
        polar_vector : (3K,) array_like
            Polar vector S: K angles (radians, unused here), then the 2K limb centres.
        label_string : (K,) array_like of int
            One limb label in 0 .. n_limb_labels - 1 per limb.
        observed_limbs : (K, 2m) array_like, optional
            Centred observed limb vectors; when given each limb is its label's clamped PDM fit to
            them (eq. 15), otherwise its label's mean stroke.

        Returns
        -------
        numpy.ndarray
            ``(K, m, 2)`` limb strokes placed at the centres of S.
        """
        check_fitted(self, "classes_")
        polar_vector = as_finite_array(polar_vector, "polar_vector", shape=(3 * N_LIMBS,))
        label_string = as_finite_array(label_string, "label_string", shape=(N_LIMBS,), dtype=int)
        if np.any((label_string < 0) | (label_string >= self.n_limb_labels)):
            raise ValueError(f"label_string must hold limb labels in 0..{self.n_limb_labels - 1}, "
                             f"got {label_string.min()}..{label_string.max()}")
        if observed_limbs is not None:
            observed_limbs = as_finite_array(observed_limbs, "observed_limbs",
                                             shape=(N_LIMBS, 2 * self.landmarks_per_limb_))
        return self._model_limbs(polar_vector, label_string, observed_limbs)

    def _model_limbs(self, polar_vector: np.ndarray, label_string: np.ndarray,
                     observed_limbs: np.ndarray | None = None) -> np.ndarray:
        """:meth:`model_limbs` on validated input (the alignment loop's inner call)."""
        centres = polar_vector[N_LIMBS:].reshape(N_LIMBS, 2)
        strokes = []
        for k in range(N_LIMBS):
            model = self.limb_models_[k][label_string[k]]
            if observed_limbs is None:
                strokes.append(model.mean)
            else:  # eq. (15): the limb's label PDM at its best-fit (clamped) parameters γ_k
                strokes.append(reconstruct(model, fit_modes(model, observed_limbs[k][None]))[0])
        return np.stack(strokes).reshape(N_LIMBS, -1, 2) + centres[:, None, :]


def _kmeans_partition(data: np.ndarray, n_clusters: int, rng: np.random.Generator, n_iter: int = 10) -> np.ndarray:
    """Seeded k-means++ start followed by Lloyd iterations; returns a cluster index per row."""
    centres = [data[rng.integers(len(data))]]
    for _ in range(1, n_clusters):
        distance = np.min(np.sum((data[:, None] - np.array(centres)[None]) ** 2, axis=2), axis=1)
        centres.append(data[rng.choice(len(data), p=distance / distance.sum())])
    centres = np.array(centres)
    for _ in range(n_iter):
        assign = np.argmin(np.sum((data[:, None] - centres[None]) ** 2, axis=2), axis=1)
        centres = np.array([data[assign == k].mean(axis=0) if np.any(assign == k) else centres[k]
                            for k in range(n_clusters)])
    return assign


def fit_polar_mixture(data: np.ndarray, n_components: int, blocks: tuple[slice, ...], rng: np.random.Generator,
                       n_iter: int, variance_fraction: float, *, ridge: float = 1e-3,
                       n_restarts: int = 1) -> tuple[list[PolarPDM], np.ndarray, np.ndarray]:
    """Mixture of polar PDMs on ``data (T, 3K)`` by EM (eqs. 2-8); returns the components, the
    mixing weights and the training responsibilities ``(T, M)``.

    One component is the PDM of every block (eq. 1, no ridge). For several, EM runs on S with each
    block divided by the square root of its total variance (so radians and shape units weigh the
    same in the k-means++ start and in the ridge; a full-covariance EM is otherwise unaffected by
    the scaling): k-means++ means, the pooled covariance as every starting covariance, a ridge of
    ``ridge`` times the mean variance (T < 3K makes component covariances singular). With
    ``n_restarts`` > 1, EM runs from that many k-means++ starts drawn in turn from ``rng`` and the
    run with the highest final log-likelihood (eq. 3) is kept. Each component's mean and covariance
    blocks, scaled back, become one PDM per block (at most ``round(T pi_m) - 1`` modes). The
    recogniser's shape layer on its checked input (not exported).

    Parameters
    ----------
    data : (T, 3K) numpy.ndarray
        Polar vectors, angles relative to the class's circular mean.
    n_components : int
        Number of mixture components M.
    blocks : tuple of slice
        Column blocks, from :func:`polar_blocks`.
    rng : numpy.random.Generator
        Source of the k-means++ starts.
    n_iter : int
        EM iterations per run.
    variance_fraction : float
        Fraction of the variance each PDM keeps, in (0, 1].
    ridge : float, default 1e-3
        Ridge on the covariances, relative to the mean variance.
    n_restarts : int, default 1
        EM runs from independent starts; the most likely is kept.

    Returns
    -------
    models : list of PolarPDM
        The components.
    weights : numpy.ndarray
        ``(M,)`` mixing weights.
    responsibilities : numpy.ndarray
        ``(T, M)`` posteriors of the training vectors.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, eqs. 1-8 (the PDM and its Gaussian mixture, applied to S).
    """
    if n_components == 1:
        pdms = tuple(fit_pdm(data[:, block], variance_fraction=variance_fraction) for block in blocks)
        return [PolarPDM(blocks, pdms)], np.ones(1), np.ones((len(data), 1))
    scale = np.empty(data.shape[1])
    for block in blocks:
        scale[block] = 1.0 / np.sqrt(data[:, block].var(axis=0).sum())
    scaled = data * scale
    spread = np.cov(scaled.T, bias=True)
    reg = ridge * float(np.trace(spread)) / data.shape[1]
    mixture = None
    for _ in range(n_restarts):
        assign = _kmeans_partition(scaled, n_components, rng)
        means_init = np.stack([scaled[assign == k].mean(axis=0) if np.any(assign == k) else scaled[k]
                               for k in range(n_components)])
        candidate = fit_gaussian_mixture(scaled, n_components, means_init=means_init,
                                         covariances_init=np.repeat(spread[None] + reg * np.eye(data.shape[1]),
                                                                    n_components, axis=0),
                                         n_iter=n_iter, reg_covar=reg)
        if mixture is None or candidate.log_likelihood[-1] > mixture.log_likelihood[-1]:
            mixture = candidate
    models = []
    for mean, cov, weight in zip(mixture.means / scale, mixture.covariances / np.outer(scale, scale), mixture.weights):
        cap = max(1, int(round(weight * len(data))) - 1)
        models.append(PolarPDM(blocks, tuple(
            pdm_from_moments(mean[block], cov[block, block], variance_fraction=variance_fraction, max_modes=cap)
            for block in blocks)))
    return models, np.clip(mixture.weights, 1e-12, None), mixture.responsibilities


def held_out_log_likelihood(
    polar_vectors: np.ndarray,
    n_components: int,
    *,
    shape_ridge: float = 1e-3,
    n_folds: int = 5,
    variance_fraction: float = 0.95,
    n_em_iter: int = 30,
    polar_model: str = "block",
    rng: int | np.random.Generator,
) -> float:
    """Mean held-out log-density of one class's polar vectors under a mixture of polar PDMs.

    A generative criterion for the choices Sec. 4 leaves open (number of components, covariance
    ridge), computed from the training set alone: the rows are split into ``n_folds`` seeded folds;
    for each fold the mixture is learnt by EM (eqs. 2-8, as in the recogniser) on the other folds
    and the held-out rows are scored with ``ln sum_m pi_m p(S | Phi_m, Gamma_m*)``, the same
    clamped PPCA density the recogniser uses.

    Parameters
    ----------
    polar_vectors : (T, 3K) array_like
        Polar vectors S of one class, angles relative to the class's circular mean (wrapped).
    n_components : int
        Mixture components M.
    shape_ridge : float
        Positive EM ridge, as ``ArticulatedShapeRecogniser(shape_ridge=...)``.
    n_folds : int
        Number of folds (at least 2); every training split needs ``3 * n_components`` rows.
    variance_fraction, n_em_iter, polar_model
        As for ``ArticulatedShapeRecogniser``.
    rng : int or numpy.random.Generator
        Seed or generator of the fold split and of the k-means++ starts (keyword-only, no default).

    Returns
    -------
    float
        Held-out log-density summed over the folds, divided by T (nats per shape).

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 4, eqs. 2-8 (the mixture it scores); the criterion is ours.
    """
    vectors = as_finite_array(polar_vectors, "polar_vectors", shape=(None, 3 * N_LIMBS), max_abs=MAX_MAGNITUDE)
    n_components = check_positive_int(n_components, "n_components")
    shape_ridge = check_positive(shape_ridge, "shape_ridge")
    n_folds = check_positive_int(n_folds, "n_folds", minimum=2)
    variance_fraction = check_in_range(variance_fraction, "variance_fraction", 0, 1, closed="right")
    n_em_iter = check_positive_int(n_em_iter, "n_em_iter")
    blocks = polar_blocks(check_choice(polar_model, "polar_model", ("block", "joint")))
    t = len(vectors)
    smallest_split = t - -(-t // n_folds)
    if smallest_split < MIN_PER_CLASS * n_components:
        raise ValueError(f"polar_vectors needs at least {MIN_PER_CLASS * n_components} rows outside every fold "
                         f"(n_components={n_components}, n_folds={n_folds}), got {smallest_split} of {t}")
    rng = make_rng(rng, "rng")
    folds = np.empty(t, dtype=int)
    folds[rng.permutation(t)] = np.arange(t) % n_folds
    total = 0.0
    for fold in range(n_folds):
        held = folds == fold
        models, weights, _ = fit_polar_mixture(vectors[~held], n_components, blocks, rng, n_em_iter,
                                                variance_fraction, ridge=shape_ridge)
        scores = np.stack([np.log(w) + model._log_density(vectors[held]) for model, w in zip(models, weights)], axis=1)
        total += float(np.logaddexp.reduce(scores, axis=1).sum())
    return total / t


def _fit_error(model: PointDistributionModel, data: np.ndarray) -> np.ndarray:
    """Squared residual of the clamped least-squares modal fit, per row."""
    return np.sum((data - reconstruct(model, fit_modes(model, data))) ** 2, axis=1)


def _farthest_point_init(data: np.ndarray, n_components: int) -> np.ndarray:
    """Deterministic EM start: the row farthest from the mean, then repeatedly the farthest row."""
    chosen = [int(np.argmax(np.sum((data - data.mean(axis=0)) ** 2, axis=1)))]
    distance = np.sum((data - data[chosen[0]]) ** 2, axis=1)
    for _ in range(1, n_components):
        chosen.append(int(np.argmax(distance)))
        distance = np.minimum(distance, np.sum((data - data[chosen[-1]]) ** 2, axis=1))
    return np.array(chosen)
