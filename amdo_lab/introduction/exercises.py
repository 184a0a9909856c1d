"""The exercises of chapter 0 (the Procrustes warm-up), checked by ``EXERCISES.check``.

Exercise 1 asks for the root-mean-square residual of a Procrustes fit of the 60-point outline
under Gaussian noise of standard deviation ``noise_sigma``; exercise 2 repeats the measurement with
every fifth point (12 points); exercise 3 asks which of the two falls further below the naive
``noise_sigma * sqrt(2)``. The expected values are measured by :func:`simulated_rms` over
``N_DRAWS`` noise draws: over seeds they scatter by about 0.1 % (60 points) and 0.3 % (12 points),
well inside the tolerances, while the naive value is 1.7 % (60 points) and 9.5 % (12 points) away.

References
----------
S. Umeyama. Least-squares estimation of transformation parameters between two point patterns.
IEEE TPAMI 13(4), 1991, pp. 376-380.
"""

from __future__ import annotations

import numpy as np

from amdo_lab.common import (as_finite_array, check_in_range, make_rng,
                             procrustes_align)
from amdo_lab.common.exercises import Exercise, ExerciseSet, WrongAnswer

__all__ = ["EXERCISES", "MAX_MAGNITUDE", "N_DRAWS", "SUBSET_STEP", "simulated_rms"]

#: Noise draws behind each simulated rms residual (about 0.4 s for 60 points).
N_DRAWS = 2000
#: Exercise 2 keeps every ``SUBSET_STEP``-th point of the outline.
SUBSET_STEP = 5
#: Largest coordinate or noise level accepted: the fit squares and sums them (float64 ends near 1.8e308).
MAX_MAGNITUDE = 1e150


def simulated_rms(template: np.ndarray, clean: np.ndarray, noise: float, *, rng: int | np.random.Generator) -> float:
    """Root-mean-square Procrustes residual of ``template`` fitted to noisy copies of ``clean``.

    Each of ``N_DRAWS`` draws adds independent Gaussian noise of standard deviation ``noise`` to every coordinate
    of ``clean``, aligns ``template`` onto it with :func:`amdo_lab.common.procrustes_align` and
    records the squared rms residual; the result is the square root of their mean.

    Parameters
    ----------
    template : (n, d) array_like
        The points that are moved (the outline), each coordinate at most ``MAX_MAGNITUDE`` in size.
    clean : (n, d) array_like
        Their noise-free image under a similarity transform, of the shape of ``template``.
    noise : float
        Standard deviation of the noise on each coordinate, in (0, ``MAX_MAGNITUDE``].
    rng : int or numpy.random.Generator
        Seed or generator of the noise draws (the checks use ``rng=11``).

    Returns
    -------
    float
        The rms residual over the draws.

    References
    ----------
    S. Umeyama. Least-squares estimation of transformation parameters between two point patterns.
    IEEE TPAMI 13(4), 1991, pp. 376-380.
    """
    template = as_finite_array(template, "template", ndim=2, max_abs=MAX_MAGNITUDE)
    clean = as_finite_array(clean, "clean (like template)", shape=template.shape, max_abs=MAX_MAGNITUDE)
    noise = check_in_range(noise, "noise", 0, MAX_MAGNITUDE, closed="right")
    rng = make_rng(rng, "rng")
    squares = [procrustes_align(template, clean + rng.normal(scale=noise, size=clean.shape)).rms_error ** 2
               for _ in range(N_DRAWS)]
    return float(np.sqrt(np.mean(squares)))


def _rms_all(outline, moved, noise_sigma):
    return simulated_rms(outline, moved, noise_sigma, rng=11)


def _rms_subset(outline, moved, noise_sigma):
    return simulated_rms(outline[::SUBSET_STEP], moved[::SUBSET_STEP], noise_sigma, rng=11)


def _further_below(outline, moved, noise_sigma):
    naive = noise_sigma * np.sqrt(2)
    shortfall_all = 1 - _rms_all(outline, moved, noise_sigma) / naive
    shortfall_subset = 1 - _rms_subset(outline, moved, noise_sigma) / naive
    return "12 points" if shortfall_subset > shortfall_all else "60 points"


_CONTEXT = ("outline", "moved", "noise_sigma")

EXERCISES = ExerciseSet(chapter=0, exercises=[
    Exercise(
        1, _rms_all,
        hint="a point's noise is a 2-D vector; and the fit itself can undo part of the noise: which part?",
        wrong_answers=(
            WrongAnswer(lambda ns: round(ns["noise_sigma"] * np.sqrt(2), 4), "the naive sigma * sqrt(2)"),
            WrongAnswer(lambda ns: ns["noise_sigma"], "sigma: the noise of one coordinate only"),
        ),
        context=_CONTEXT, rtol=0.005,  # three significant figures (about 0.2 %); the naive value is 1.7 % off
    ),
    Exercise(
        2, _rms_subset,
        hint=f"keep every {SUBSET_STEP}th point (step = {SUBSET_STEP}) and run simulated_rms on those points",
        wrong_answers=(
            WrongAnswer(lambda ns: round(_rms_all(ns["outline"], ns["moved"], ns["noise_sigma"]), 4),
                        "the unchanged experiment (all 60 points)", unchanged_experiment=True),
            WrongAnswer(lambda ns: round(ns["noise_sigma"] * np.sqrt(2), 4), "the naive sigma * sqrt(2)"),
        ),
        context=_CONTEXT, rtol=0.01, experiment=True, points=2,
    ),
    Exercise(
        3, _further_below,
        hint="compare each rms residual with sigma * sqrt(2): how many noise directions can the fit absorb, "
             "out of how many?",
        wrong_answers=(
            WrongAnswer("60 points", "more points, more freedom"),
            WrongAnswer("the same", "the absorbed part does not depend on n"),
        ),
        context=_CONTEXT, choices=("60 points", "12 points", "the same"),
    ),
])
