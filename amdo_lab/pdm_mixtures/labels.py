"""Label strings and the dictionary's error model (Sec. 6): Hamming distance (eq. 17), P(L | Lambda) (eq. 18)."""

from __future__ import annotations

import numpy as np

from amdo_lab.common import as_finite_array, check_in_range, check_positive_int

__all__ = ["hamming_distance", "hamming_distance_reference", "label_string_log_prob", "dictionary_log_probs",
           "MAX_LIMBS"]

#: Largest number of limbs K a label string may have (eq. 18's K_p = (1 - p)^K stays representable).
MAX_LIMBS = 1_000


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
    # as many limbs as label_strings: the message names both, since either may be the one at fault
    dictionary = as_finite_array(dictionary, "dictionary (like label_strings)", shape=(None, strings.shape[1]), dtype=int)
    return _hamming_distance(strings, dictionary)


def _hamming_distance(label_strings: np.ndarray, dictionary: np.ndarray) -> np.ndarray:
    """Fast path of :func:`hamming_distance_reference`: all pairs at once by broadcasting."""
    return np.sum(label_strings[:, None, :] != dictionary[None, :, :], axis=2)


def hamming_distance_reference(label_strings: np.ndarray, dictionary: np.ndarray) -> np.ndarray:
    """Eq. 17 read as a distance, one pair at a time: ``H(L, Lambda) = sum_i (1 - delta(l_i, lambda_i))``.

    The reference path of :func:`hamming_distance`, for reading and for the tests (nothing is
    validated here).

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
        Number of limbs K, from 1 to ``MAX_LIMBS``.
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
    n_limbs = check_positive_int(n_limbs, "n_limbs", maximum=MAX_LIMBS)
    p = check_in_range(error_probability, "error_probability", 0, 1)
    distances = as_finite_array(hamming, "hamming", dtype=int, bounds=(0, n_limbs))
    return _label_string_log_prob(distances, n_limbs, p)


def _label_string_log_prob(hamming: np.ndarray, n_limbs: int, error_probability: float) -> np.ndarray:
    p = error_probability
    log_k_p = n_limbs * np.log1p(-p)  # ln K_p = K ln(1 - p), eq. 18
    k_p = np.log((1 - p) / p)  # k_p = ln((1 - p) / p), eq. 18
    return log_k_p - k_p * hamming



def dictionary_log_probs(label_strings: np.ndarray, dictionary: np.ndarray, error_probability: float) -> np.ndarray:
    """``ln P(L | Lambda_wm)`` of label strings under every string of a dictionary (eqs. 17-18).

    A kernel for checked input (the recogniser's loop): nothing is validated here.

    Parameters
    ----------
    label_strings : (n, K) numpy.ndarray of int
        Limb labels of ``n`` shapes.
    dictionary : (C, M, K) numpy.ndarray of int
        One permissible string per class and mixture component.
    error_probability : float
        p of eq. 18, in (0, 1).

    Returns
    -------
    numpy.ndarray
        ``(n, C, M)`` log-probabilities, nats.

    References
    ----------
    Al-Shaher & Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
    AMDO 2004, LNCS 3179, pp. 62-75, Sec. 6, eqs. 17-18.
    """
    hamming = _hamming_distance(label_strings, dictionary.reshape(-1, dictionary.shape[-1]))  # eq. 17
    log_prob = _label_string_log_prob(hamming, dictionary.shape[-1], error_probability)  # eq. 18
    return log_prob.reshape(len(label_strings), *dictionary.shape[:2])
