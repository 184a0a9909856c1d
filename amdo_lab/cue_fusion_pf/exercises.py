"""The exercises of chapter 6, specified as data: hints and the wrong answers each check rejects.

The targets are not here: each check cell of the instructor's notebook registers its exercise's
target in a hidden test (``EXERCISES.expect``), so the package the reader installs holds only the
hints, the tolerances and the plausible wrong answers. Exercises 3, 4 and 5 are experiments (the
unchanged experiment's value is recorded among the wrong answers, with the notebook variable that
holds it); exercise 6 is "implement it": one weighting-and-resampling step of the filter, checked
against :func:`~amdo_lab.cue_fusion_pf.weigh_and_resample` on cases the notebook does not show.
"""

from __future__ import annotations

import numpy as np

from amdo_lab.common.exercises import Exercise, ExerciseSet, WrongAnswer
from amdo_lab.cue_fusion_pf.tracker import weigh_and_resample

__all__ = ["EXERCISES", "resampling_case"]

#: Exercise 6: the case the notebook shows.
EXAMPLE_SEED = 6


def resampling_case(seed: int) -> dict:
    """Exercise 6's inputs for ``seed``: two cues' log-likelihoods of N particles and one uniform number.

    The log-likelihoods carry an offset of several hundred (they are defined up to a constant), as
    a product of many edge lines gives; N is between 40 and 120.

    Parameters
    ----------
    seed : int
        Seed of the case.

    Returns
    -------
    dict
        ``{"cue_log_likelihoods": (2, N) array, "u": float}``, the keyword arguments of the step.
    """
    rng = np.random.default_rng(seed)
    n = int(rng.integers(40, 121))
    offsets = rng.choice([-1.0, 1.0]) * rng.uniform(800.0, 1500.0, size=(2, 1))  # one sign: they never cancel
    spreads = rng.uniform(0.3, 1.5, size=(2, 1))
    return {"cue_log_likelihoods": offsets + spreads * rng.standard_normal((2, n)), "u": float(rng.random())}


def _pointers(n: int, u: float) -> np.ndarray:
    return (u + np.arange(n)) / n


def _draw(weights: np.ndarray, pointers: np.ndarray) -> np.ndarray:
    return np.minimum(np.searchsorted(np.cumsum(weights), pointers, side="right"), len(weights) - 1)


def _exp_without_shift(cue_log_likelihoods, u):
    """Wrong: exp of the fused log-likelihoods as they are (over- or underflows to 0/0 = NaN)."""
    fused = np.sum(cue_log_likelihoods, axis=0)
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        weights = np.exp(fused)
        weights = weights / weights.sum()
    return _draw(weights, _pointers(fused.size, u))


def _weights_not_summing_to_one(cue_log_likelihoods, u):
    """Wrong: exp(l - max) used as weights without dividing by their sum."""
    fused = np.sum(cue_log_likelihoods, axis=0)
    return _draw(np.exp(fused - fused.max()), _pointers(fused.size, u))


def _likelihoods_added(cue_log_likelihoods, u):
    """Wrong: the cues' normalised likelihoods added (a mixture), not multiplied as eq. (6) does."""
    logs = np.asarray(cue_log_likelihoods, dtype=float)
    per_cue = np.exp(logs - logs.max(axis=1, keepdims=True))
    mixture = (per_cue / per_cue.sum(axis=1, keepdims=True)).sum(axis=0)
    return _draw(mixture / mixture.sum(), _pointers(logs.shape[1], u))


def _log_likelihoods_as_weights(cue_log_likelihoods, u):
    """Wrong: the fused log-likelihoods normalised as if they were weights (no exponential)."""
    fused = np.sum(cue_log_likelihoods, axis=0)
    return _draw(fused / fused.sum(), _pointers(fused.size, u))


def _pointer_not_divided(cue_log_likelihoods, u):
    """Wrong: the pointers u + i/N (u not divided by N), which run past the last cumulative weight."""
    fused = np.sum(cue_log_likelihoods, axis=0)
    weights = np.exp(fused - fused.max())
    return _draw(weights / weights.sum(), u + np.arange(fused.size) / fused.size)


EXERCISES = ExerciseSet(chapter=6, exercises=[
    Exercise(
        1, None,
        "build a1 = -exp(-2βτ) and a0 = 2exp(-βτ) with β = 10, τ = 1/25 s; the printed order's characteristic "
        "polynomial is z² - a1 z - a0: take the larger modulus of its two roots",
        (WrongAnswer(1.850, "the translation's β = 2 (printed in the chapter)",
                     hint="1.85 is the translation's (β = 2); redo the roots with the scale's β = 10"),
         WrongAnswer(0.955, "the smaller of the two moduli",
                     hint="that is the smaller root; the model's stability is decided by the larger modulus"),
         WrongAnswer(0.670, "the corrected order's double root exp(-βτ)",
                     hint="that is the corrected order's root exp(-βτ); the question asks for eq. (4) as printed, "
                          "a1 on x_{k-1} and a0 on x_{k-2}")),
        rtol=0.0, atol=6e-4),
    Exercise(
        2, None,
        "eq. (13): P0 + (1 - P0)/λ · Σ_j G(z_j), with G the Gaussian density of σ_e; a line with no feature has "
        "an empty sum",
        (WrongAnswer((0.220, 0.0), "G(1) alone, and 0 for no feature",
                     hint="that is G(1) alone: eq. (13) adds P0 and scales G by (1 - P0)/λ, and an empty line keeps P0"),
         WrongAnswer((0.209, 0.2), "multiplied by λ instead of divided",
                     hint="(1 - P0) is divided by λ, not multiplied: a feature is rarer than clutter when λ is small"),
         WrongAnswer((2.938, 0.2), "exp(-z²/σ²) without the 2",
                     hint="G is the Gaussian density: exp(-z²/(2σ_e²)), with the 2"),
         WrongAnswer((2.136, 0.2), "σ_e taken as 2 instead of √2",
                     hint="σ_e = √2 px is the standard deviation; σ_e² = 2")),
        rtol=0.0, atol=6e-4),
    Exercise(
        3, None,
        "set half_length = 30 in the answer cell, run it, and count the frames where tracked_long and "
        "tracked_short differ",
        (WrongAnswer(0, "the unchanged experiment (both runs at ±12 px)", unchanged_experiment=True,
                     variable="lines_differ",
                     hint="both runs still use ±12 px lines: set half_length = 30 and run the answer cell again"),
         WrongAnswer(13, "the frames the ±30 px run loses",
                     hint="that counts the frames the long lines lose; the question asks where the two runs disagree"),
         WrongAnswer(28, "every agile frame",
                     hint="not every frame differs: compare tracked_long with tracked_short frame by frame"),
         WrongAnswer(1, "the two shares differ by 0 frames, guessed as one",
                     hint="equal shares do not mean the same frames: count where the two masks differ")),
        rtol=0.0, atol=0.0, experiment=True, why_points=1),
    Exercise(
        4, None,
        "set n_particles = 30 in the answer cell, run it, and give the share of frames 81-163 with IoU >= 0.5 "
        "(three decimals)",
        (WrongAnswer(0.976, "the unchanged experiment (300 particles)", unchanged_experiment=True,
                     variable="share_tried",
                     hint="that is the 300-particle run: set n_particles = 30 and run the answer cell again"),
         WrongAnswer(0.084, "the share of frames lost",
                     hint="that is the share of frames lost; the question asks for the share tracked"),
         WrongAnswer(0.99, "the three-cue share of the whole sequence, read off the chapter",
                     hint="that is the chapter's 300-particle run of the whole sequence; run the answer cell with "
                          "30 particles")),
        rtol=0.0, atol=6e-4, experiment=True, why_points=1),
    Exercise(
        5, None,
        "set walker_std = 400 in the answer cell, run it, and give the share of the walker's frames with box "
        "IoU >= 0.5 (two decimals)",
        (WrongAnswer(0.26, "the unchanged experiment (100 px)", unchanged_experiment=True,
                     variable="weak_pull_share",
                     hint="that is the chapter's σ = 100 px: set walker_std = 400 and run the answer cell again"),
         WrongAnswer(0.84, "colour alone, read off the chapter",
                     hint="that is colour alone; the exercise runs colour × edges with wider dynamics"),
         WrongAnswer(0.98, "the tempered edges, read off the chapter",
                     hint="that is the tempered run; the exercise keeps the edges untempered and widens the dynamics")),
        rtol=0.0, atol=5e-3, experiment=True, why_points=2),
    Exercise(
        6, None,
        "fuse the cues by adding their log-likelihoods (eq. 6), turn the fused values into weights that sum to 1 "
        "without overflow, then walk the N pointers (u + i)/N through the cumulative weights",
        (WrongAnswer(_exp_without_shift, "exp of the fused log-likelihoods without subtracting their maximum",
                     hint="exp of log-likelihoods of several hundred over- or underflows (0/0 gives NaN weights): "
                          "subtract the largest fused log-likelihood before exponentiating"),
         WrongAnswer(_weights_not_summing_to_one, "weights not divided by their sum",
                     hint="normalise the weights: the cumulative weights must end at 1 for the pointers to "
                          "reach every particle"),
         WrongAnswer(_likelihoods_added, "the cues' likelihoods added instead of multiplied",
                     hint="eq. (6) multiplies the cues' likelihoods, so their log-likelihoods add; adding the "
                          "likelihoods makes a mixture"),
         WrongAnswer(_log_likelihoods_as_weights, "log-likelihoods normalised as weights",
                     hint="weights are likelihoods, not log-likelihoods: exponentiate the fused values first"),
         WrongAnswer(_pointer_not_divided, "pointers u + i/N",
                     hint="the pointers are (u + i)/N: u is divided by N too, so they stay in [0, 1) and are "
                          "spaced 1/N apart")),
        kind="function", reference=weigh_and_resample, make_case=resampling_case, example_seed=EXAMPLE_SEED,
        rtol=0.0, atol=0.0, points=2),
])
