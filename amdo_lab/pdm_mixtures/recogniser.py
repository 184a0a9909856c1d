"""The hierarchical recogniser (Secs. 5-6): the limb layer (eqs. 9-10, 15-16) and the recognition loop.

The recogniser learns one Gaussian mixture of limb PDMs per limb (its labels), a mixture of polar
PDMs per class (:mod:`~amdo_lab.pdm_mixtures.polar_mixture`) and a dictionary of permissible label
strings; it recognises a shape by iterating eqs. 11-14 (:mod:`~amdo_lab.pdm_mixtures.recognition`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from amdo_lab.common import (
    MAX_ITERATIONS,
    as_finite_array,
    check_bool,
    check_choice,
    check_fitted,
    check_instance,
    check_in_range,
    check_positive,
    check_positive_int,
    make_rng,
    procrustes_align,
)
from amdo_lab.common.threads import one_blas_thread
from amdo_lab.pdm_mixtures.gmm import fit_gaussian_mixtures_batch
from amdo_lab.pdm_mixtures.labels import dictionary_log_probs
from amdo_lab.pdm_mixtures.pdm import (
    MAX_MAGNITUDE,
    PointDistributionModel,
    _align_to_reference,
    _fit_modes,
    _pdm_from_moments,
    _ppca_log_density,
    _reconstruct,
    check_articulated_shapes,
    check_training_set,
    generalized_procrustes,
)
from amdo_lab.pdm_mixtures.polar_mixture import (MAX_COMPONENTS, MIN_PER_CLASS, N_EM_ITER, PolarPDM, angles_about_mean,
                                                 circular_mean, fit_polar_mixture, polar_blocks)
from amdo_lab.pdm_mixtures.recognition import (EQ11_READINGS, RecognitionTrace, ScoreComponents,
                                               run_recognition)
from amdo_lab.pdm_mixtures.representation import _centred_limbs, polar_shape_vector, wrap_angle

__all__ = ["RecogniserSettings", "PAPER_SETTINGS", "OUR_SETTINGS", "ArticulatedShapeRecogniser", "AlignmentTrace",
           "MAX_LABELS", "MAX_RESTARTS"]

N_LIMBS = 13
#: Largest number of limb labels: each is an EM component fitted to the training limbs, so far more than
#: this would leave components without data.
MAX_LABELS = 100
#: Largest number of EM starts of a class's shape layer (each is a full EM run).
MAX_RESTARTS = 1_000


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


@dataclass(frozen=True)
class RecogniserSettings:
    """Settings of :class:`ArticulatedShapeRecogniser`: the two layers' model sizes and the readings of the paper.

    The defaults are ours; :data:`PAPER_SETTINGS` and :data:`OUR_SETTINGS` are the two named settings
    the chapter compares. ``RecogniserSettings(n_shape_components=1)`` is ours with one field changed
    (as ``dataclasses.replace(OUR_SETTINGS, n_shape_components=1)``). Each field is checked when the
    settings are built.

    Parameters
    ----------
    n_limb_labels : int, default 4
        Mixture components (limb labels) learnt by EM for each of the 13 limbs, from 1 to :data:`MAX_LABELS`.
    n_shape_components : int, default 2
        Polar-PDM mixture components learnt by EM for each class (1 gives one polar PDM per class), from 1
        to :data:`~amdo_lab.pdm_mixtures.polar_mixture.MAX_COMPONENTS`. Each component has its own
        permissible label string in the class's dictionary.
    shape_ridge : float, default 1e-3
        Ridge added to every shape-level EM covariance (eq. 8), as a multiple of the mean variance
        of the block-scaled S (positive; the paper leaves it open). It also sets the smallest
        eigenvalues a component PDM can have, hence its residual variance.
    n_restarts : int, default 1
        Seeded k-means++ starts of each class's shape-level EM, from 1 to :data:`MAX_RESTARTS`; the run
        with the highest final training log-likelihood (eq. 3) is kept.
    label_error_probability : float, default 0.2
        p of eq. 18, in (0, 0.5).
    variance_fraction : float, default 0.95
        Fraction of the variance kept by each PDM's eigenmodes, in (0, 1].
    polar_model : {"block", "joint"}, default "block"
        ``"block"``: separate PDMs for the angle rows and the centre rows of S (Sec. 4: the first K
        rows of Gamma are the angles, constrained by the eigenvalues of the angle covariance);
        ``"joint"``: one PDM over all of S, whose eigenmodes radians then dominate.
    limb_likelihood : {"gaussian", "residual"}, default "gaussian"
        How a limb's label posterior (eq. 10) is computed: ``"gaussian"``, the label component's
        Gaussian (eq. 6) restricted to its PDM (in-model Mahalanobis term on gamma plus residual);
        ``"residual"``, the isotropic fit residual alone (eq. 16), the paper's "in practice" choice.
    eq11_reading : {"G p", "G ln p"}, default "G p"
        How eq. 11 combines the gates ``G`` with the polar density ``p``: ``"G p"``, a product of
        probabilities, so the class posterior is proportional to ``G p``; ``"G ln p"``, as printed, a
        score whose argmax decides (its posteriors are 1 for the winner, 0 elsewhere).

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Secs. 4-6.
    """

    n_limb_labels: int = 4
    n_shape_components: int = 2
    shape_ridge: float = 1e-3
    n_restarts: int = 1
    label_error_probability: float = 0.2
    variance_fraction: float = 0.95
    polar_model: str = "block"
    limb_likelihood: str = "gaussian"
    eq11_reading: str = "G p"

    def __post_init__(self) -> None:
        check_positive_int(self.n_limb_labels, "n_limb_labels", maximum=MAX_LABELS)
        check_positive_int(self.n_shape_components, "n_shape_components", maximum=MAX_COMPONENTS)
        check_positive(self.shape_ridge, "shape_ridge")
        check_positive_int(self.n_restarts, "n_restarts", maximum=MAX_RESTARTS)
        check_in_range(self.label_error_probability, "label_error_probability", 0, 0.5)
        check_in_range(self.variance_fraction, "variance_fraction", 0, 1, closed="right")
        check_choice(self.polar_model, "polar_model", ("block", "joint"))
        check_choice(self.limb_likelihood, "limb_likelihood", ("gaussian", "residual"))
        check_choice(self.eq11_reading, "eq11_reading", EQ11_READINGS)


#: The recogniser as the paper prints it: one PDM over all of S (Sec. 4), the limb label posterior
#: from the isotropic fit residual (eq. 16, its "in practice" choice), eq. 11's gates multiplying ln p.
PAPER_SETTINGS = RecogniserSettings(polar_model="joint", limb_likelihood="residual", eq11_reading="G ln p")
#: Ours (the chapter's box of readings): one PDM per block of S, each label's own Gaussian, gates times p.
OUR_SETTINGS = RecogniserSettings()


class ArticulatedShapeRecogniser:
    """Two-layer recogniser: limb PDM mixtures + label dictionary + per-class mixtures of polar PDMs.

    Follows scikit-learn's estimator contract: the settings are stored as given and :meth:`fit`
    returns the recogniser; learned attributes end with an underscore; using it unfitted raises
    ``sklearn.exceptions.NotFittedError``.

    Parameters
    ----------
    settings : RecogniserSettings, default OUR_SETTINGS
        Model sizes and readings of the paper (:data:`PAPER_SETTINGS` for the paper's).
    rng : int or numpy.random.Generator
        Seed or generator of the k-means++ starts of the shape-level EM (keyword-only, no default;
        an int seed gives the same starts at every ``fit``).

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Secs. 4-6, eqs. 2-18.

    Examples
    --------
    >>> from amdo_lab.pdm_mixtures import TABLE1_CLASSES, make_pose_dataset
    >>> train = make_pose_dataset(TABLE1_CLASSES, 20, rng=1)
    >>> test = make_pose_dataset(TABLE1_CLASSES, 10, rng=2)
    >>> recogniser = ArticulatedShapeRecogniser(rng=0).fit(train.shapes, train.labels)
    >>> recogniser.predict(test.shapes[:3]).tolist()
    ['boxing', 'boxing', 'boxing']
    >>> round(float(np.mean(recogniser.predict(test.shapes) == test.labels)), 2)
    0.97
    """

    def __init__(self, settings: RecogniserSettings = OUR_SETTINGS, *, rng: int | np.random.Generator) -> None:
        # Stored as given (scikit-learn's contract); fit checks them.
        self.settings = settings
        self.rng = rng

    def _check_shapes(self, shapes: object, name: str = "shapes") -> np.ndarray:
        """Articulated shapes; once fitted, with as many landmarks per limb as in training."""
        return check_articulated_shapes(shapes, name, landmarks_per_limb=getattr(self, "landmarks_per_limb_", None))

    # ------------------------------------------------------------------ training
    def fit(self, shapes: np.ndarray, labels: np.ndarray) -> "ArticulatedShapeRecogniser":
        """Learn the limb mixtures, the class polar-PDM mixtures and the label dictionary.

        Parameters
        ----------
        shapes : (T, 13, m, 2) array_like
            Training shapes, ``m >= 2`` landmarks per limb; no shape may have all its landmarks coincide.
        labels : (T,) array_like
            Class name of every training shape; every class needs ``3 * settings.n_shape_components`` shapes.

        Returns
        -------
        ArticulatedShapeRecogniser
            This recogniser, fitted.
        """
        with one_blas_thread():  # small matrices: BLAS threads only contend on a shared machine
            return self._fit(shapes, labels)

    def _fit(self, shapes: np.ndarray, labels: np.ndarray) -> "ArticulatedShapeRecogniser":
        check_instance(self.settings, "settings", RecogniserSettings)
        make_rng(self.rng, "rng")
        for learned in [name for name in vars(self) if name.endswith("_")]:
            delattr(self, learned)  # a refit starts afresh (the landmark count may change)
        shapes, labels = check_training_set(shapes, labels)  # no landmark count to match: learned ones deleted
        self.classes_ = tuple(dict.fromkeys(labels.tolist()))
        counts = {c: int(np.sum(labels == c)) for c in self.classes_}
        if min(counts.values()) < MIN_PER_CLASS * self.settings.n_shape_components:  # a covariance per component
            raise ValueError(f"labels: every class needs {MIN_PER_CLASS} shapes per shape component, got {counts}")
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
        one_hot = self.training_label_strings_[..., None] == np.arange(self.settings.n_limb_labels)  # (n, K, labels)
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
        limbs = np.swapaxes(_centred_limbs(aligned), 0, 1)  # (K, n, 2m)
        d = limbs.shape[2]
        starts = np.stack([data[_farthest_point_init(data, self.settings.n_limb_labels)] for data in limbs])
        spreads = np.stack([np.cov(data.T, bias=True) + 1e-6 * np.eye(d) for data in limbs])
        ridges = 1e-3 * np.trace(spreads, axis1=1, axis2=2) / d
        weights, means, covariances, _ = fit_gaussian_mixtures_batch(
            limbs, starts, np.repeat(spreads[:, None], self.settings.n_limb_labels, axis=1), N_EM_ITER, ridges)
        self.limb_models_: list[list[PointDistributionModel]] = []
        self.limb_weights_ = weights
        self.limb_noise_ = np.empty(N_LIMBS)
        for k in range(N_LIMBS):
            models = [_pdm_from_moments(m, c, self.settings.variance_fraction, None)
                      for m, c in zip(means[k], covariances[k])]
            self.limb_models_.append(models)
            # Isotropic residual variance of eq. 16, from each example's best-fitting label.
            errors = np.stack([_fit_error(mdl, limbs[k]) for mdl in models], axis=1)
            self.limb_noise_[k] = max(float(errors.min(axis=1).mean()) / d, 1e-12)

    def _limb_log_posteriors(self, aligned: np.ndarray) -> np.ndarray:
        """log P(lambda | z_k) for every shape, limb and label (eqs. 4, 9, 10): ``(n, K, labels)``.

        The class-conditional density of a label is its PDM's Gaussian (``limb_likelihood=
        "gaussian"``) or the isotropic residual of the clamped fit (``"residual"``, eq. 16)."""
        limbs = _centred_limbs(aligned)
        log_lik = np.empty((aligned.shape[0], N_LIMBS, self.settings.n_limb_labels))
        for k in range(N_LIMBS):
            data = limbs[:, k]
            if self.settings.limb_likelihood == "gaussian":
                log_lik[:, k] = np.stack([_ppca_log_density(model, data) for model in self.limb_models_[k]], axis=1)
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
        settings = self.settings
        blocks = polar_blocks(settings.polar_model)
        rng = make_rng(self.rng, "rng")
        self.angle_means_ = []
        self.shape_models_: list[list[PolarPDM]] = []
        self.shape_weights_: list[np.ndarray] = []
        responsibilities = []
        for c in self.classes_:
            class_vectors = vectors[labels == c]
            angle_mean = circular_mean(class_vectors[:, :N_LIMBS])
            self.angle_means_.append(angle_mean)
            deviation = angles_about_mean(class_vectors, angle_mean)
            models, weights, resp = fit_polar_mixture(deviation, settings.n_shape_components, blocks, rng,
                                                       N_EM_ITER, settings.variance_fraction,
                                                       ridge=settings.shape_ridge, n_restarts=settings.n_restarts)
            self.shape_models_.append(models)
            self.shape_weights_.append(weights)
            responsibilities.append(resp)
        # The most responsible component of every training shape, per class (for inspection).
        self.training_components_ = [
            np.argmax(self._component_log_likelihoods(angles_about_mean(vectors[labels == c], a), j)[0], axis=1)
            for j, (c, a) in enumerate(zip(self.classes_, self.angle_means_))
        ]
        return responsibilities

    def _component_log_likelihoods(self, deviation: np.ndarray, j: int) -> tuple[np.ndarray, np.ndarray]:
        """``ln pi_m + ln p(S | Phi_m, Gamma_m*)`` for every component m of class j, ``(n, M)``, and
        the clamped modal fits ``(M, n, 3K)`` (in deviation coordinates)."""
        scores = np.stack([np.log(weight) + model.log_density(deviation)
                           for model, weight in zip(self.shape_models_[j], self.shape_weights_[j])], axis=1)
        fits = np.stack([model.project(deviation) for model in self.shape_models_[j]])
        return scores, fits

    def _shape_terms(self, aligned: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Polar-PDM log-likelihoods ``(n, C, M)`` (without the mixing weights) and model fits
        ``(C, M, n, 3K)`` with the angles put back in absolute terms."""
        vectors = polar_shape_vector(aligned)
        log_lik, fits = [], []
        for j, angle_mean in enumerate(self.angle_means_):
            scores, component_fits = self._component_log_likelihoods(angles_about_mean(vectors, angle_mean), j)
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
        return _align_to_reference(flat, self.reference_).reshape(shapes.shape)

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
            changing (at most ``MAX_RECOGNITION_ITER``).
        """
        with one_blas_thread():
            return self._recognise(shapes)

    def _recognise(self, shapes: np.ndarray) -> RecognitionTrace:
        aligned = self.align(shapes)  # checked here
        limb_log_post = self._limb_log_posteriors(aligned)  # (n, K, labels), eq. 10
        shape_log_lik, fits = self._shape_terms(aligned)  # (n, C, M), (C, M, n, 3K), eq. 12
        log_weights = np.log(np.stack(self.shape_weights_))  # (C, M)
        return run_recognition(limb_log_post, shape_log_lik, fits, self._gates(limb_log_post), log_weights,
                               self.class_log_prior_, self.dictionary_, self.settings.label_error_probability,
                               self.settings.eq11_reading)

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
        log = check_bool(log, "log")
        log_posteriors = self._limb_log_posteriors(self.align(shapes))  # align checks the fit and the shapes
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
        aligned = self.align(shapes)  # checks the fit and the shapes
        limb_log_post = self._limb_log_posteriors(aligned)
        shape_log_lik, _ = self._shape_terms(aligned)
        return ScoreComponents(self._gates(limb_log_post), dictionary_log_probs(
            np.argmax(limb_log_post, axis=2), self.dictionary_, self.settings.label_error_probability),
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
        j = self.classes_.index(check_choice(class_name, "class_name", self.classes_))
        n_iter = check_positive_int(n_iter, "n_iter", maximum=MAX_ITERATIONS)
        shape = self._check_shapes(as_finite_array(shape, "shape", ndim=3)[None], "shape")[0]
        angle_mean = self.angle_means_[j]
        # Use the class's mixture component that best explains the shape as first posed.
        start = angles_about_mean(polar_shape_vector(self.align(shape[None])), angle_mean)
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
            limbs_in_model = _centred_limbs(shape_in_model[None])[0]
            model_shape = self._model_limbs(model_vector, labels, None if not drawn else limbs_in_model)
            drawn.append(pose.scale * model_shape @ pose.rotation.T + pose.translation)
            misfit.append(pose.rms_error)
            deviation = angles_about_mean(polar_shape_vector(shape_in_model[None]), angle_mean)
            model_vector = model.project(deviation)[0]
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
        labels = (0, self.settings.n_limb_labels - 1)
        label_string = as_finite_array(label_string, "label_string", shape=(N_LIMBS,), dtype=int, bounds=labels)
        if observed_limbs is not None:  # None: each label's mean stroke
            observed_limbs = as_finite_array(observed_limbs, "observed_limbs",
                                             shape=(N_LIMBS, 2 * self.landmarks_per_limb_), max_abs=MAX_MAGNITUDE)
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
                strokes.append(_reconstruct(model, _fit_modes(model, observed_limbs[k][None], clamp=True))[0])
        return np.stack(strokes).reshape(N_LIMBS, -1, 2) + centres[:, None, :]


def _fit_error(model: PointDistributionModel, data: np.ndarray) -> np.ndarray:
    """Squared residual of the clamped least-squares modal fit, per row."""
    return np.sum((data - _reconstruct(model, _fit_modes(model, data, clamp=True))) ** 2, axis=1)


def _farthest_point_init(data: np.ndarray, n_components: int) -> np.ndarray:
    """Deterministic EM start: the row farthest from the mean, then repeatedly the farthest row."""
    chosen = [int(np.argmax(np.sum((data - data.mean(axis=0)) ** 2, axis=1)))]
    distance = np.sum((data - data[chosen[0]]) ** 2, axis=1)
    for _ in range(1, n_components):
        chosen.append(int(np.argmax(distance)))
        distance = np.minimum(distance, np.sum((data - data[chosen[-1]]) ** 2, axis=1))
    return np.array(chosen)
