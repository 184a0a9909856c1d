"""The exercises of chapter 2 (mixtures of point distribution models), specified as data.

Each entry computes its expected answer from the notebook objects its check cell passes
(``EXERCISES.check(2, answer_2, toy_scores=toy_scores)``), so the value is not in plain view under
the answer cell, and records the plausible wrong answers the check must reject (see
:mod:`amdo_lab.common.exercises`).

References
----------
A. A. Al-Shaher, E. R. Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
AMDO 2004, LNCS 3179, pp. 62-75: eq. 18 (Exercise 1), Secs. 2 and 4 (Exercises 2-5).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np

from amdo_lab.common.exercises import Exercise, ExerciseSet, WrongAnswer
from amdo_lab.pdm_mixtures.experiments import SEPARATION_MODELS
from amdo_lab.pdm_mixtures.pdm import fit_pdm
from amdo_lab.pdm_mixtures.labels import label_string_log_prob

__all__ = ["EXERCISES"]

_SINGLE_POLAR = SEPARATION_MODELS[1]
_MIXTURE = SEPARATION_MODELS[0]


def _mismatch_cost() -> float:
    # Eq. 18 with p = 0.2 and K = 13: ln P(L | Lambda) at H = 0 minus at H = 1.
    return float(-np.diff(label_string_log_prob(np.array([0, 1]), 13, 0.2))[0])


def _straight_arm_gap(toy_scores: Callable, mode_deg: float) -> float:
    # ln p single minus ln p mixture of the toy's straight arm, toy drawn with seed 7.
    (single, mixture), _ = toy_scores(mode_deg, seed=7)
    return float(single[0] - mixture[0])


def _kicking_modes(train_aligned: np.ndarray, train: object) -> int:
    kicking = train_aligned[np.asarray(train.labels) == "kicking"]
    return int(fit_pdm(kicking.reshape(len(kicking), -1)).n_modes)


def _mean_rate(separation_trials_at: Callable, level: float, model: str) -> float:
    return float(np.mean([trial.rate(model) for trial in separation_trials_at(level)]))


def _angle_shares(baselines: Mapping) -> np.ndarray:
    # Share of each joint polar-PDM eigenmode's squared norm on the 13 angle rows of S.
    joint = baselines["ours with a joint polar PDM"]
    return np.concatenate([np.sum(component.pdms[0].modes[:13] ** 2, axis=0)
                           for components in joint.shape_models_ for component in components])


def _dominant_block(baselines: Mapping) -> str:
    shares = _angle_shares(baselines)
    return "angles" if np.all(shares > 0.5) else "centres" if np.all(shares < 0.5) else "both"


EXERCISES = ExerciseSet(chapter=2, exercises=[
    Exercise(
        1, _mismatch_cost,
        "write ln P(L|Lambda) = ln K_p - k_p H and see what one more mismatch (H -> H + 1) subtracts",
        (WrongAnswer(-1.39, "a sign slip: ln(p / (1 - p))"),
         WrongAnswer(1.61, "-ln p, the cost of a mismatch without the match term"),
         WrongAnswer(0.60, "log10 instead of the natural logarithm"),
         WrongAnswer(2.90, "-K ln(1 - p), the constant ln K_p instead of k_p")),
        atol=0.006, rtol=0.0),
    Exercise(
        2, lambda toy_scores: _straight_arm_gap(toy_scores, 15.0),
        "set mode_deg = 15.0 in the answer cell, run it, and subtract the mixture's ln p from the single PDM's",
        (WrongAnswer(lambda ns: round(_straight_arm_gap(ns["toy_scores"], 50.0), 1),
                     "the unchanged toy (modes at +-50 degrees)", unchanged_experiment=True),
         WrongAnswer(lambda ns: round(-_straight_arm_gap(ns["toy_scores"], 15.0), 1),
                     "a sign slip: mixture minus single"),
         WrongAnswer(lambda ns: round(float(ns["toy_scores"](15.0, seed=7)[0][0][0]), 1),
                     "the single PDM's ln p alone")),
        context=("toy_scores",), atol=0.06, rtol=0.0, experiment=True),
    Exercise(
        3, _kicking_modes,
        "fit_pdm(vectors).n_modes with vectors of shape (20, 156); 95 % of the variance is the default",
        (WrongAnswer(19, "every mode 20 shapes allow"),
         WrongAnswer(156, "the length of the long vector"),
         WrongAnswer(lambda ns: _kicking_modes(ns["train_aligned"], ns["train"]) + 1, "one mode too many")),
        context=("train_aligned", "train"), atol=0.0, rtol=0.0),
    Exercise(
        4, lambda separation_trials_at: _mean_rate(separation_trials_at, 3.0, _SINGLE_POLAR),
        "set separation = 3.0 in the answer cell and average the single polar PDM's rate over the five seeds",
        (WrongAnswer(lambda ns: round(_mean_rate(ns["separation_trials_at"], 2.0, _SINGLE_POLAR), 2),
                     "the unchanged experiment (s = 2)", unchanged_experiment=True),
         WrongAnswer(lambda ns: round(_mean_rate(ns["separation_trials_at"], 3.0, _MIXTURE), 2),
                     "the mixture's rate instead of the single polar PDM's"),
         WrongAnswer(lambda ns: round(_mean_rate(ns["separation_trials_at"], 3.0, _MIXTURE)
                                      - _mean_rate(ns["separation_trials_at"], 3.0, _SINGLE_POLAR), 2),
                     "the mixture's lead instead of the rate")),
        context=("separation_trials_at",), atol=0.006, rtol=0.0, experiment=True),
    Exercise(
        5, _dominant_block,
        "sum the squared entries of each mode column over the first 13 rows (the angles) and compare with 1/2",
        (WrongAnswer("centres", "the block with more coordinates (26 of 39)"),
         WrongAnswer("both", "modes that mix the two blocks evenly")),
        context=("baselines",), choices=("angles", "centres", "both")),
])
