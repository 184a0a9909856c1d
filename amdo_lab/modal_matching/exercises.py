"""The exercises of chapter 9, checked from the notebook's check cells (see ``amdo_lab.common.exercises``).

The targets live in the chapter's hidden tests; this module records only the hints, the plausible
wrong answers and, for the "implement it" exercise, the cases its function is checked on.
"""

from __future__ import annotations

import numpy as np

from amdo_lab.common.exercises import Exercise, ExerciseSet, WrongAnswer
from amdo_lab.modal_matching.element import gaussian_element, mean_spacing
from amdo_lab.modal_matching.matching import procrustes_alignment
from amdo_lab.modal_matching.modes import modal_analysis

__all__ = ["EXERCISES", "alignment_case"]


def _outline(angle: np.ndarray, coefficients: np.ndarray, stretch: float, shift: np.ndarray) -> np.ndarray:
    a, b, phase = coefficients
    radius = 10 * (1 + a * np.cos(2 * angle - phase) + b * np.sin(3 * angle))  # mm
    return np.c_[stretch * radius * np.cos(angle) + shift[0], radius * np.sin(angle) + shift[1]]


def alignment_case(seed: int) -> dict:
    """Two outlines like the chapter's toy, of 10 to 16 nodes, sampled apart; their modes and a mode count.

    Parameters
    ----------
    seed : int
        Seed of the shape, the node counts, the stretch and the shift of object 2.

    Returns
    -------
    dict
        The keyword arguments of :func:`procrustes_alignment`: ``modes1``, ``modes2`` (Gaussian
        elements with sigma the node spacing of object 1) and ``n_modes``.
    """
    draw = np.random.default_rng(seed)
    coefficients = np.r_[draw.uniform(0.1, 0.3), draw.uniform(0.0, 0.15), draw.uniform(0, np.pi)]
    m1, m2 = draw.integers(12, 17), draw.integers(10, 15)
    start = draw.uniform(0, 2 * np.pi)
    X1 = _outline(start + np.linspace(0, 2 * np.pi, m1, endpoint=False), coefficients, 1.3, np.zeros(2))
    X2 = _outline(start + draw.uniform(0.1, 0.4) + np.linspace(0, 2 * np.pi, m2, endpoint=False), coefficients,
                  draw.uniform(1.3, 1.5), draw.uniform(-2, 2, 2))
    sigma = mean_spacing(X1)
    return {"modes1": modal_analysis(gaussian_element(X1, sigma=sigma)),
            "modes2": modal_analysis(gaussian_element(X2, sigma=sigma)), "n_modes": 6}


def _scaled(modes1, modes2, n_modes):
    Phi1, Phi2 = modes1.shapes[:, :n_modes], modes2.shapes[:, :n_modes]
    return Phi1 / np.sqrt(np.mean(Phi1**2, axis=0)), Phi2 / np.sqrt(np.mean(Phi2**2, axis=0))


def _fields(model, Phi, points, use_interpolants=True):
    d2 = np.sum((points[:, None, :] - model.nodes[None, :, :]) ** 2, axis=-1)
    H = np.exp(-d2 / (2 * model.sigma**2))
    if use_interpolants:
        H = H @ model.interpolation
    m = len(model.nodes)
    return np.vstack([H @ Phi[a * m:(a + 1) * m] for a in range(model.dimension)])


def _gaussians_not_interpolants(modes1, modes2, n_modes):
    Phi1, Phi2 = _scaled(modes1, modes2, n_modes)
    U, _, Vt = np.linalg.svd(Phi2.T @ _fields(modes1.model, Phi1, modes2.model.nodes, use_interpolants=False))
    return U @ Vt


def _transposed(modes1, modes2, n_modes):
    Phi1, Phi2 = _scaled(modes1, modes2, n_modes)
    U, _, Vt = np.linalg.svd(Phi2.T @ _fields(modes1.model, Phi1, modes2.model.nodes))
    return (U @ Vt).T


def _least_squares(modes1, modes2, n_modes):
    Phi1, Phi2 = _scaled(modes1, modes2, n_modes)
    return np.linalg.lstsq(Phi2, _fields(modes1.model, Phi1, modes2.model.nodes), rcond=None)[0]


def _unscaled(modes1, modes2, n_modes):
    Phi1, Phi2 = modes1.shapes[:, :n_modes], modes2.shapes[:, :n_modes]
    U, _, Vt = np.linalg.svd(Phi2.T @ _fields(modes1.model, Phi1, modes2.model.nodes))
    return U @ Vt


def _signs_only(modes1, modes2, n_modes):
    Phi1, Phi2 = _scaled(modes1, modes2, n_modes)
    overlap = np.diag(Phi2.T @ _fields(modes1.model, Phi1, modes2.model.nodes))
    return np.diag(np.where(overlap < 0, -1.0, 1.0))


EXERCISES = ExerciseSet(chapter=9, exercises=[
    Exercise(
        1, None,
        "K grows with E and M with rho, the mode shapes do not change, and omega squared is their ratio",
        (WrongAnswer(0.44, "E / rho without the square root",
                     hint="the eigenvalues are omega squared: take the square root of their ratio"),
         WrongAnswer(1.5, "sqrt(rho / E): the ratio upside down",
                     hint="a stiffer material vibrates faster, a heavier one slower: which goes on top?"),
         WrongAnswer(2.25, "rho / E", hint="a stiffer material vibrates faster, a heavier one slower, and the "
                                           "eigenvalues are omega squared")),
        rtol=0.0, atol=0.006),
    Exercise(
        2, None,
        "set sigma_factor_2 = 2.0 in the answer cell, run it, and give the share it prints",
        (WrongAnswer(0.78, "the unchanged experiment (sigma = h)", unchanged_experiment=True,
                     hint="that is sigma = h: change sigma_factor_2 to 2 and run the cell again",
                     variable="experiment_2"),
         WrongAnswer(1.0, "the Procrustes-aligned share",
                     hint="keep align='sign': the exercise is about the sign-aligned match")),
        rtol=0.0, atol=0.006, experiment=True, why_points=1),
    Exercise(
        3, None,
        "extend shifts_3 to 0, 2, 4, ..., 40 mm and find the first shift whose share is below 0.5",
        (WrongAnswer(40.0, "the failure case's shift",
                     hint="40 mm is where the failure case starts; the share falls below 0.5 before that"),
         WrongAnswer(0.02, "a correct share, not a shift",
                     hint="give the shift in mm at which the share first falls below 0.5"),
         WrongAnswer(0.0, "the unchanged experiment (only 0 mm tried)", unchanged_experiment=True,
                     hint="at 0 mm the share is still high: extend the list of shifts and run the cell again"),
         WrongAnswer(10.0, "the first shift with a wrong pair",
                     hint="the share first drops there, but it is still above 0.5")),
        rtol=0.0, atol=0.5, experiment=True, why_points=1),
    Exercise(
        4, None,
        "scale each mode to a root-mean-square entry of 1, evaluate object 1's modes as fields at object 2's "
        "nodes (h = A g), and take R = U V^T from the SVD of Phi2^T P",
        (WrongAnswer(_gaussians_not_interpolants, "the Gaussians g in place of the interpolants h",
                     hint="the fields are u(x) = sum_i h_i(x) U_i with h = A g: multiply the Gaussians by "
                          "modes1.model.interpolation"),
         WrongAnswer(_transposed, "the transpose of R",
                     hint="R multiplies object 2's modes (Phi2 @ R): take the SVD of Phi2^T P, not of P^T Phi2"),
         WrongAnswer(_least_squares, "least squares, not orthogonal",
                     hint="R must be orthogonal (it may only flip and rotate modes): U V^T from the SVD"),
         WrongAnswer(_unscaled, "the modes without the unit root-mean-square scaling",
                     hint="scale each mode to a root-mean-square entry of 1 first, as eq. (3)'s features are"),
         WrongAnswer(_signs_only, "a sign per mode only",
                     hint="a sign per mode cannot undo two modes rotated into each other: fit the full "
                          "orthogonal matrix")),
        kind="function", reference=procrustes_alignment, make_case=alignment_case, example_seed=9,
        rtol=1e-6, atol=1e-6, points=2),
])
