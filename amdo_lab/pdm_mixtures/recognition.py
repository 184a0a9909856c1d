"""One recognition step (Secs. 5-6): the gated class score (eq. 11), the winning class (eq. 13) and the
relabelling of the limbs given the winner (eq. 14).

Each public function checks its arrays and calls a check-free kernel; the recogniser's loop calls the
kernels. The terms they combine come from the limb layer (eq. 10), the label strings (eqs. 17-18)
and the shape layer (eq. 12).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from amdo_lab.common import as_finite_array, check_choice, check_in_range, check_names
from amdo_lab.pdm_mixtures.labels import dictionary_log_probs

__all__ = ["EQ11_READINGS", "ScoreComponents", "RecognitionTrace", "gated_component_scores",
           "winning_components", "relabel_limbs", "run_recognition"]

#: How eq. 11 combines the gates ``G = P(L | Lambda) prod_k P(lambda_k | z_k)`` with the polar density p:
#: ``"G p"`` (a product of probabilities, the recogniser's default) or ``"G ln p"`` (as printed).
EQ11_READINGS = ("G p", "G ln p")
#: Upper bound on the recognition iterations (class scores, eq. 13, then relabelling, eq. 14); the loop
#: stops earlier once the limb labels no longer change.
MAX_RECOGNITION_ITER = 10
#: Largest magnitude of a log-score term: their exponentials and sums stay finite in float64 (in nats).
MAX_LOG_TERM = 1e150


def _check_terms(shape_log_lik: object, limb_gate: object, string_log_prob: object,
                 log_weights: object) -> tuple[np.ndarray, ...]:
    """The four ``(n, C, M)``, ``(n, C, M)``, ``(n, C, M)``, ``(C, M)`` terms of eq. 11, finite and consistent."""
    shape_log_lik = as_finite_array(shape_log_lik, "shape_log_lik", ndim=3, max_abs=MAX_LOG_TERM)
    shape, log_range = shape_log_lik.shape, (-MAX_LOG_TERM, 0)  # the other three: log-probabilities shaped like it
    limb_gate = as_finite_array(limb_gate, "limb_gate (like shape_log_lik)", shape=shape, bounds=log_range)
    string_log_prob = as_finite_array(string_log_prob, "string_log_prob (like shape_log_lik)", shape=shape, bounds=log_range)
    log_weights = as_finite_array(log_weights, "log_weights (like shape_log_lik)", shape=shape[1:], bounds=log_range)
    return shape_log_lik, limb_gate, string_log_prob, log_weights


def gated_component_scores(shape_log_lik: np.ndarray, limb_gate: np.ndarray, string_log_prob: np.ndarray,
                           log_weights: np.ndarray, *, reading: str = "G p") -> np.ndarray:
    """Eq. 11 per class ``w`` and mixture component ``m``: the polar density gated by the limb labels.

    With the gate ``G_wm = P(L | Lambda_wm) prod_k P(lambda_k^wm | z_k)``, the reading ``"G p"`` gives
    ``ln(pi_wm G_wm p(S | Phi_wm, Gamma_wm*))``, a log-probability; ``"G ln p"`` reads eq. 11 as
    printed, ``pi_wm G_wm ln p(S | Phi_wm, Gamma_wm*)``, which is a score and not a log-probability.

    Parameters
    ----------
    shape_log_lik : (n, C, M) array_like
        ``ln p(S | Phi_wm, Gamma_wm*)`` of every shape under every class component (eq. 12), nats.
    limb_gate : (n, C, M) array_like
        ``sum_k ln P(lambda_k^wm | z_k)`` over the component's dictionary string (eq. 10), at most 0.
    string_log_prob : (n, C, M) array_like
        ``ln P(L | Lambda_wm)`` of the shape's label string (eq. 18), at most 0.
    log_weights : (C, M) array_like
        Log mixing weights ``ln pi_wm``, at most 0.
    reading : {"G p", "G ln p"}
        How the gates combine with the density (``EQ11_READINGS``).

    Returns
    -------
    numpy.ndarray
        ``(n, C, M)`` component scores.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 5, eq. 11.

    Examples
    --------
    >>> gated_component_scores(np.full((1, 1, 1), -2.0), np.full((1, 1, 1), -1.0), np.zeros((1, 1, 1)),
    ...                        np.zeros((1, 1))).ravel().tolist()
    [-3.0]
    """
    terms = _check_terms(shape_log_lik, limb_gate, string_log_prob, log_weights)
    reading = check_choice(reading, "reading", EQ11_READINGS)
    return _gated_component_scores(*terms, reading)


def _gated_component_scores(shape_log_lik: np.ndarray, limb_gate: np.ndarray, string_log_prob: np.ndarray,
                            log_weights: np.ndarray, reading: str) -> np.ndarray:
    if reading == "G ln p":
        # eq. (11) as printed: pi_wm G_wm ln p(S | Phi_wm, Gamma_wm*), with G_wm = P(L|Lambda_wm) prod_k P(lambda_k|z_k)
        return np.exp(log_weights)[None] * np.exp(limb_gate + string_log_prob) * shape_log_lik
    # eq. (11) read as G p: ln pi_wm + ln p(S|Phi_wm, Gamma_wm*) + sum_k ln P(lambda_k^wm|z_k) + ln P(L|Lambda_wm)
    return log_weights[None] + shape_log_lik + limb_gate + string_log_prob


def _one_hot(scores: np.ndarray) -> np.ndarray:
    """1 at the largest entry of the last axis, 0 elsewhere."""
    return (np.arange(scores.shape[-1]) == np.argmax(scores, axis=-1)[..., None]).astype(float)


def _class_posteriors(scores: np.ndarray, class_log_prior: np.ndarray,
                      reading: str) -> tuple[np.ndarray, np.ndarray]:
    """Class posteriors ``P(w | X)`` ``(n, C)`` from eq. 11's component scores ``(n, C, M)`` and the log
    class priors ``(C,)``, and each class's component shares ``(n, C, M)`` (the loop's kernel, unchecked).

    Under ``"G p"`` a class sums its components, ``ln P(w) + ln sum_m exp(score_wm)``, and Bayes' rule
    normalises over the classes; the shares are the components' responsibilities within the class.
    Under ``"G ln p"`` the scores are no probabilities: a class's score is ``sum_m score_wm``, its
    "posterior" is 1 for the highest-scoring class and 0 elsewhere, and the share is 1 for the
    component of largest score (eq. 13 decides by argmax).
    """
    if reading == "G ln p":  # a score, not a probability: its decision only (eq. 13)
        return _one_hot(scores.sum(axis=2)), _one_hot(scores)
    class_joint = np.logaddexp.reduce(scores, axis=2)  # ln sum_m pi_wm G_wm p_wm, eq. (11)
    log_score = class_log_prior + class_joint  # ln P(w) + ..., Bayes' rule's numerator
    posterior = np.exp(log_score - np.logaddexp.reduce(log_score, axis=1, keepdims=True))
    return posterior, np.exp(scores - class_joint[..., None])


def winning_components(posterior: np.ndarray, component_scores: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Eq. 13: the MAP class ``w* = argmax_w P(w | X)``, and the component ``m*`` of largest score within it.

    Parameters
    ----------
    posterior : (n, C) array_like
        Class posteriors, each in [0, 1] (rows sum to 1).
    component_scores : (n, C, M) array_like
        Eq. 11's component scores (from :func:`gated_component_scores`).

    Returns
    -------
    best_class : numpy.ndarray
        ``(n,)`` class indices ``w*``.
    best_component : numpy.ndarray
        ``(n,)`` component indices ``m*`` of ``w*``.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 5, eq. 13.
    """
    posterior = as_finite_array(posterior, "posterior", ndim=2, bounds=(0, 1))
    scores = as_finite_array(component_scores, "component_scores (like posterior)", shape=(*posterior.shape, None))
    return _winning_components(posterior, scores)


def _winning_components(posterior: np.ndarray, scores: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    best = np.argmax(posterior, axis=1)  # eq. (13): w* = argmax_w P(w | X)
    return best, np.argmax(scores[np.arange(len(best)), best], axis=1)  # its most responsible component m*


def relabel_limbs(limb_log_posteriors: np.ndarray, winning_strings: np.ndarray,
                  error_probability: float) -> np.ndarray:
    """Eq. 14: each limb's label given the winning class component's dictionary string.

    ``l_k = argmax_lambda P(lambda | z_k) P(L(lambda, k) | Lambda_w*m*)``: a label that disagrees with
    the string's label of limb k adds one mismatch to the Hamming distance, which eq. 18 charges
    ``k_p = ln((1 - p) / p)`` nats.

    Parameters
    ----------
    limb_log_posteriors : (n, K, labels) array_like
        ``ln P(lambda | z_k)`` of every limb and label (eq. 10), at most 0.
    winning_strings : (n, K) array_like of int
        The dictionary string ``Lambda_w*m*`` of every shape's winner, labels in 0 .. labels - 1.
    error_probability : float
        Label error probability p of eq. 18, in (0, 0.5).

    Returns
    -------
    numpy.ndarray
        ``(n, K)`` int labels.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 6, eqs. 14 and 18.
    """
    log_post = as_finite_array(limb_log_posteriors, "limb_log_posteriors", ndim=3, bounds=(-MAX_LOG_TERM, 0))
    strings = as_finite_array(winning_strings, "winning_strings", shape=log_post.shape[:2], dtype=int,
                              bounds=(0, log_post.shape[2] - 1))
    error_probability = check_in_range(error_probability, "error_probability", 0, 0.5)
    return _relabel_limbs(log_post, strings, error_probability)


def _relabel_limbs(limb_log_posteriors: np.ndarray, winning_strings: np.ndarray, error_probability: float) -> np.ndarray:
    k_p = np.log((1 - error_probability) / error_probability)  # the cost of one mismatch, eq. (18)
    agrees = winning_strings[:, :, None] == np.arange(limb_log_posteriors.shape[2])
    # eq. (14): l_k = argmax_lambda ln P(lambda | z_k) + ln P(L(lambda, k) | Lambda_w*m*)
    return np.argmax(limb_log_posteriors + np.where(agrees, 0.0, -k_p), axis=2)


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
            One or more distinct names of ``"limb_gate"``, ``"label_string"``, ``"shape"``.

        Returns
        -------
        numpy.ndarray
            ``(n, C)``: ``ln P(w) + ln sum_m pi_wm exp(sum of the chosen terms)``, in nats.
        """
        terms = check_names(terms, "terms", allowed=("limb_gate", "label_string", "shape"))  # one or more, distinct
        joint = self.log_weights[None] + sum(getattr(self, term) for term in terms)
        return self.class_log_prior + np.logaddexp.reduce(joint, axis=2)

    def printed_eq11_scores(self) -> np.ndarray:
        """Class scores of eq. 11 read as printed: the gates multiply the log-likelihood.

        ``sum_m pi_wm G_wm ln p(S | Phi_wm, Gamma_wm*)`` (:func:`gated_component_scores` with
        ``reading="G ln p"``, summed over the components). A class whose gates vanish scores near 0,
        above every class whose ``ln p`` is negative.

        Returns
        -------
        numpy.ndarray
            ``(n, C)`` scores; their argmax over classes is the printed reading's decision.

        References
        ----------
        Al-Shaher & Hancock, AMDO 2004, LNCS 3179, pp. 62-75, Sec. 5, eq. 11.
        """
        return _gated_component_scores(self.shape, self.limb_gate, self.label_string, self.log_weights,
                                       "G ln p").sum(axis=2)


@dataclass(frozen=True)
class RecognitionTrace:
    """Per-iteration record of hierarchical recognition.

    Parameters
    ----------
    posteriors : (n_iter, n, C) numpy.ndarray
        Class posteriors ``P(w | shape)`` (eq. 13's argument), columns in ``classes_`` order; under
        the printed reading of eq. 11, 1 for the winning class and 0 elsewhere.
    label_strings : (n_iter, n, K) numpy.ndarray
        Limb labels in use at each iteration (eq. 10 at the first, eq. 14 later).
    reconstructions : (n_iter, n, 3K) numpy.ndarray
        Posterior-weighted polar model fits S (eq. 12), angles in radians.
    n_iter : int
        Number of iterations run, at most the recogniser's ``MAX_RECOGNITION_ITER`` (10).

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Secs. 5-6, eqs. 9-18.
    """

    posteriors: np.ndarray
    label_strings: np.ndarray
    reconstructions: np.ndarray
    n_iter: int


def run_recognition(limb_log_posteriors: np.ndarray, shape_log_lik: np.ndarray, fits: np.ndarray,
                    limb_gate: np.ndarray, log_weights: np.ndarray, class_log_prior: np.ndarray,
                    dictionary: np.ndarray, error_probability: float, reading: str) -> RecognitionTrace:
    """The recognition loop: eqs. 11-13 score the classes, eq. 14 relabels the limbs, until the labels settle.

    The recogniser's kernel (:meth:`ArticulatedShapeRecogniser.recognise` checks the shapes and
    computes the terms): nothing is validated here. At most ``MAX_RECOGNITION_ITER`` iterations.

    Parameters
    ----------
    limb_log_posteriors : (n, K, labels) numpy.ndarray
        ``ln P(lambda | z_k)`` (eq. 10).
    shape_log_lik : (n, C, M) numpy.ndarray
        ``ln p(S | Phi_wm, Gamma_wm*)`` (eq. 12).
    fits : (C, M, n, 3K) numpy.ndarray
        Each component's clamped fit of S (eq. 12), angles absolute.
    limb_gate : (n, C, M) numpy.ndarray
        ``sum_k ln P(lambda_k^wm | z_k)`` of every dictionary string.
    log_weights : (C, M) numpy.ndarray
        ``ln pi_wm``.
    class_log_prior : (C,) numpy.ndarray
        ``ln P(w)``.
    dictionary : (C, M, K) numpy.ndarray of int
        The permissible label strings.
    error_probability : float
        p of eq. 18, in (0, 0.5).
    reading : {"G p", "G ln p"}
        The reading of eq. 11.

    Returns
    -------
    RecognitionTrace
        Posteriors, label strings and posterior-weighted fits of every iteration.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Secs. 5-6, eqs. 10-18.
    """
    label_strings = np.argmax(limb_log_posteriors, axis=2)  # eq. 10: MAP limb labels
    history_post, history_labels, history_fit = [], [], []
    for _ in range(MAX_RECOGNITION_ITER):
        # Eq. 11: every component's polar likelihood gated by its limb posteriors and by
        # P(L | Lambda) of its dictionary string; a class sums its components.
        string_log_prob = dictionary_log_probs(label_strings, dictionary, error_probability)
        joint = _gated_component_scores(shape_log_lik, limb_gate, string_log_prob, log_weights, reading)
        posterior, within = _class_posteriors(joint, class_log_prior, reading)
        history_post.append(posterior)
        history_labels.append(label_strings)
        history_fit.append(np.einsum("nc,ncm,cmnd->nd", posterior, within, fits))
        best, component = _winning_components(posterior, joint)  # eq. 13
        # Eq. 14: relabel limbs using the winning class component's dictionary string as prior.
        refined = _relabel_limbs(limb_log_posteriors, dictionary[best, component], error_probability)
        if np.array_equal(refined, label_strings):
            break
        label_strings = refined
    return RecognitionTrace(np.stack(history_post), np.stack(history_labels), np.stack(history_fit),
                            len(history_post))
