"""The exercises of chapter 0 (the Procrustes warm-up), checked by ``EXERCISES.check``.

Exercise 1 asks for the expected root-mean-square residual of a 2-D similarity fit of the 60-point
outline under Gaussian noise of standard deviation 0.02 on each coordinate (a count of degrees of
freedom); exercise 2 measures it on every fifth point; exercise 3 asks which fit falls further below the
naive sigma * sqrt(2); exercise 4 has the reader write Umeyama's scale, checked on point sets the
notebook does not show. The targets sit in the check cells' hidden tests of the instructor's
notebook, never here: this module records only what is not secret (hints, the plausible wrong
answers with a hint each, tolerances, points).

References
----------
S. Umeyama. Least-squares estimation of transformation parameters between two point patterns.
IEEE TPAMI 13(4), 1991, pp. 376-380.
"""

from __future__ import annotations

import numpy as np

from amdo_lab.common import procrustes_align
from amdo_lab.common.validation import check_seed
from amdo_lab.common.exercises import Exercise, ExerciseSet, WrongAnswer

__all__ = ["EXERCISES", "scale_case"]


def _umeyama_scale(source, target):
    """The reference of exercise 4: the scale of the package's Procrustes fit of ``source`` onto ``target``."""
    return procrustes_align(source, target).scale


def scale_case(seed: int) -> dict:
    """A case of exercise 4: two 2-D point sets related by a similarity (mirrored for odd seeds) plus noise.

    Parameters
    ----------
    seed : int
        Picks the case (a non-negative integer); the notebook shows ``scale_case(0)``.

    Returns
    -------
    dict
        ``{"source": (n, 2) array, "target": (n, 2) array}``, the keyword arguments of the
        reader's function.
    """
    seed = check_seed(seed, "seed")
    rng = np.random.default_rng(seed)
    n = int(rng.integers(6, 16))
    source = rng.normal(size=(n, 2)) * np.array([1.5, 0.7])
    angle = rng.uniform(-np.pi, np.pi)
    rotation = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    target = rng.uniform(0.5, 2.5) * source @ rotation.T + rng.normal(size=2)
    if seed % 2:
        target[:, 0] = -target[:, 0]  # a mirror image: the best proper rotation needs the guard S
    target += rng.normal(scale=0.1, size=target.shape)
    return {"source": source, "target": target}


def _svd_parts(source, target):
    source, target = np.asarray(source, float), np.asarray(target, float)
    x, y = source - source.mean(axis=0), target - target.mean(axis=0)
    singular = np.linalg.svd(y.T @ x / len(x), compute_uv=False)
    return x, y, singular


def _scale_without_guard(source, target):
    x, _, singular = _svd_parts(source, target)
    return singular.sum() / np.mean(np.sum(x**2, axis=1))


def _scale_over_target_spread(source, target):
    source, target = np.asarray(source, float), np.asarray(target, float)
    return _umeyama_scale(source, target) * np.mean(np.sum((source - source.mean(0))**2, axis=1)) / np.mean(
        np.sum((target - target.mean(0))**2, axis=1))


def _spread_ratio(source, target):
    x, y, _ = _svd_parts(source, target)
    return np.sqrt(np.mean(np.sum(y**2, axis=1)) / np.mean(np.sum(x**2, axis=1)))


EXERCISES = ExerciseSet(chapter=0, exercises=[
    Exercise(
        1, None,
        hint="count the numbers the noise perturbs and the parameters the fit chooses, then use the rule "
             "above the exercise",
        wrong_answers=(
            WrongAnswer(0.0283, "the naive sigma * sqrt(2)",
                        hint="that is the residual of the true transform; the fitted one absorbs part of the noise"),
            WrongAnswer(0.02, "sigma: the noise of one coordinate only",
                        hint="a point's noise is a 2-D vector: both coordinates add to its length"),
            WrongAnswer(0.0279, "3 absorbed directions (the shift counted once, or the scale forgotten)",
                        hint="count the similarity's parameters again: scale, angle and a shift in x and y"),
            WrongAnswer(0.0277, "5 absorbed directions",
                        hint="in 2-D a similarity has fewer parameters than that: list them"),
        ),
        rtol=0.0, atol=6e-5,  # four decimals: 3 and 5 absorbed directions give 0.0279 and 0.0277
    ),
    Exercise(
        2, None,
        hint="keep every 5th point (step = 5) and run simulated_rms on those points",
        wrong_answers=(
            WrongAnswer(0.0268, "the unchanged experiment (step = 3: 20 points)", unchanged_experiment=True,
                        variable="experiment_2",
                        hint="that is the 20-point residual: set step = 5 in the answer cell and run it again"),
            WrongAnswer(0.0283, "the naive sigma * sqrt(2)",
                        hint="measure it with simulated_rms on outline[::step] rather than quote sigma * sqrt(2)"),
        ),
        rtol=0.0, atol=1.5e-4, experiment=True, points=2, why_points=1,
    ),
    Exercise(
        3, None,
        hint="compare each rms residual with sigma * sqrt(2): how many noise directions can the fit absorb, "
             "out of how many?",
        wrong_answers=(
            WrongAnswer("60 points", "more points, more freedom",
                        hint="more points give the noise more directions; does the fit get more parameters?"),
            WrongAnswer("the same", "the absorbed part does not depend on n",
                        hint="the absorbed count does not depend on n, but its share of the 2n directions does"),
        ),
        choices=("60 points", "12 points", "the same"), why_points=1,
    ),
    Exercise(
        4, None,
        hint="centre both sets, take the SVD of the cross-covariance C, set S = diag(1, det(U V^T)) and "
             "divide tr(D S) by the source's spread",
        wrong_answers=(
            WrongAnswer(_scale_without_guard, "tr(D) without the reflection guard",
                        hint="on a mirrored pair the best rotation is not a reflection: use tr(D S) with "
                             "S = diag(1, det(U V^T)), not tr(D)"),
            WrongAnswer(_scale_over_target_spread, "divided by the target's spread",
                        hint="divide by the spread v_x of the points being moved (the source), not the target's"),
            WrongAnswer(_spread_ratio, "the ratio of the two spreads",
                        hint="the ratio of spreads counts the noise as scale; Umeyama's s = tr(D S) / v_x "
                             "uses the cross-covariance"),
        ),
        kind="function", reference=_umeyama_scale, make_case=scale_case, example_seed=0, rtol=1e-6, atol=1e-9,
    ),
])
