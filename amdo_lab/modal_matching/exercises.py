"""The exercises of chapter 9, checked from the notebook's check cells (see ``amdo_lab.common.exercises``)."""

from __future__ import annotations

import numpy as np

from amdo_lab.common.exercises import Exercise, ExerciseSet, WrongAnswer
from amdo_lab.modal_matching.element import gaussian_element, mean_spacing
from amdo_lab.modal_matching.matching import match_objects
from amdo_lab.modal_matching.modes import modal_analysis
from amdo_lab.modal_matching.pedobarography import ObjectPair, correct_share

__all__ = ["EXERCISES", "frequency_ratio", "shifted_share", "sign_share"]


def frequency_ratio(nodes: np.ndarray, young: float, density: float) -> float:
    """omega_4 of an element of material (young, density) over omega_4 of the unit material.

    Parameters
    ----------
    nodes : ndarray, shape (m, 2)
        The object's nodes (mm).
    young, density : float
        Young's modulus and density of the changed material.

    Returns
    -------
    float
        The ratio of the first non-rigid frequencies.

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 4 (the virtual material).
    """
    h = mean_spacing(nodes)
    changed = modal_analysis(gaussian_element(nodes, sigma=h, young=young, density=density))
    unit = modal_analysis(gaussian_element(nodes, sigma=h))
    return float(changed.omega[3] / unit.omega[3])


def sign_share(pair: ObjectPair, sigma_in_spacings: float) -> float:
    """Correct share of the global, sign-aligned match of a pair with sigma a multiple of object 1's spacing.

    Parameters
    ----------
    pair : ObjectPair
        The objects and the truth.
    sigma_in_spacings : float
        sigma / h.

    Returns
    -------
    float
        The share of the one-to-one pairs that are correct.

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 4-5.
    """
    sigma = sigma_in_spacings * mean_spacing(pair.X1)
    result = match_objects(pair.X1, pair.X2, sigma=sigma, align="sign")
    return correct_share(result.pairs, pair.truth, pair.X2)


def shifted_share(pair: ObjectPair, shift_mm: float) -> float:
    """Correct share of the global, Procrustes-aligned match after moving object 2 by ``shift_mm`` along x.

    Parameters
    ----------
    pair : ObjectPair
        The objects and the truth.
    shift_mm : float
        The shift of object 2 (and of the truth) along x (mm).

    Returns
    -------
    float
        The share of the one-to-one pairs that are correct.

    References
    ----------
    Bastos & Tavares, AMDO 2004, Sec. 4-5.
    """
    shift = np.array([shift_mm, 0.0])
    result = match_objects(pair.X1, pair.X2 + shift)
    return correct_share(result.pairs, pair.truth + shift, pair.X2 + shift)


EXERCISES = ExerciseSet(chapter=9, exercises=[
    Exercise(
        1, lambda toy_X1: frequency_ratio(toy_X1, 4.0, 9.0),
        "K grows with E and M with rho; omega squared is their ratio",
        (WrongAnswer(4.0 / 9.0, "E / rho without the square root"),
         WrongAnswer(1.5, "sqrt(rho / E): the ratio upside down")),
        context=("toy_X1",), rtol=0.0, atol=0.006),
    Exercise(
        2, lambda contours: sign_share(contours, 2.0),
        "match the contour pair with sigma=2 * h and align='sign', then score result.pairs with correct_share",
        (WrongAnswer(lambda ns: sign_share(ns["contours"], 1.0), "the unchanged experiment (sigma = h)",
                     unchanged_experiment=True),
         WrongAnswer(1.0, "the Procrustes-aligned share")),
        context=("contours",), rtol=0.0, atol=0.006, experiment=True),
    Exercise(
        3, lambda contours: shifted_share(contours, 40.0),
        "add 40 mm to the x coordinates of object 2 and of the truth, then match with the default alignment",
        (WrongAnswer(lambda ns: shifted_share(ns["contours"], 0.0), "the unchanged experiment (no shift)",
                     unchanged_experiment=True),
         WrongAnswer(0.0, "no pair right at all")),
        context=("contours",), rtol=0.0, atol=0.006, experiment=True),
    Exercise(
        4, lambda: "always",
        "count how many pairs a one-to-one assignment of an m1 x m2 matrix returns, whatever its entries",
        (WrongAnswer("only for a good Z", "the share depends on the affinity matrix"),
         WrongAnswer("never", "the excess nodes lower it")),
        choices=("always", "only for a good Z", "never")),
])
