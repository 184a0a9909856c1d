"""Chapter 5's exercises as data: expected values computed from the notebook's objects, wrong answers recorded.

The check cells of ``notebooks/05_glmm_face_recognition.ipynb`` call ``EXERCISES.check(k, answer_k, ...)``;
the expected values are computed here, so they are not in plain view under the answer cells. See
:mod:`amdo_lab.common.exercises` for the mechanism.

References
----------
Givens, Beveridge, Draper & Bolme (2004), "Using a Generalized Linear Mixed Model to Study the
Configuration Space of a PCA+LDA Human Face Recognition Algorithm", AMDO 2004, LNCS 3179, pp. 1-11.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy.special import expit

from amdo_lab.common.exercises import Exercise, ExerciseSet, WrongAnswer
from amdo_lab.face_glmm.crosscheck import fit_naive_logistic
from amdo_lab.face_glmm.design import PAPER_FORMULA
from amdo_lab.face_glmm.glmm import fit_binomial_glmm

__all__ = ["EXERCISES", "F_DROP_FACTOR", "WIDE_TOY_SIGMA", "HALF_PROBES"]

#: Exercise 3: the factor by which an F value must fall when the t:U:M:D term is added.
F_DROP_FACTOR = 3.0
#: Exercise 2: the probes' spread of the wider toy.
WIDE_TOY_SIGMA = 3.0
#: Exercise 5: the probes kept (p < HALF_PROBES).
HALF_PROBES = 128
COMMON_CHOICES = ("configuration factors only", "the inclusion flag F", "the PCA dimension D")
_EXTENDED_RANDOM = ["t", "p", "t:p", "t:U:M:D"]
_BASELINE = {"U": ["none"], "M": ["l2"], "D": ["fixed"]}


def _baseline_probability(fit, included: str = "no") -> float:
    return float(fit.predict(pd.DataFrame({**_BASELINE, "F": [included]})).p.iloc[0])


def _wide_toy_ratio(simulate_toy, fit_toy, sigma: float = WIDE_TOY_SIGMA) -> float:
    """Naive M[A] / the from-scratch GLMM's M_A on the toy simulated with ``sigma`` (seed 5)."""
    wide = simulate_toy(sigma, rng=5)
    return float(fit_naive_logistic(wide, "Y ~ M").estimate["M[A]"] / fit_toy(wide.Y.to_numpy(dtype=float))[1][1])


def _wide_toy_approximation(simulate_toy, fit_toy, sigma: float = WIDE_TOY_SIGMA) -> float:
    sigma_hat = fit_toy(simulate_toy(sigma, rng=5).Y.to_numpy(dtype=float))[0]
    return float(1 / np.sqrt(1 + 0.346 * sigma_hat**2))


def _f_drop(fit, extended) -> pd.Series:
    return fit.tests.F / extended.tests.F


def _terms_falling(fit, extended) -> set:
    drop = _f_drop(fit, extended)
    return set(drop.index[drop > F_DROP_FACTOR])


def _config_only(fit) -> set:
    return {term for term in fit.tests.index if "F" not in term.split(":")}


def _same_set(target: set):
    """A predicate accepting a set, list or tuple of term names equal to ``target`` as a set."""
    def matches(answer) -> bool:
        return (isinstance(answer, (set, frozenset, list, tuple))
                and all(isinstance(term, str) for term in answer) and {t.strip() for t in answer} == target)
    return matches


def _common_property(fit, extended) -> str:
    falling = _terms_falling(fit, extended)
    if falling == _config_only(fit):
        return COMMON_CHOICES[0]
    if falling and all("F" in term.split(":") for term in falling):
        return COMMON_CHOICES[1]
    return COMMON_CHOICES[2]


_HALF_FITS: dict = {}


def _half_fit(table):
    """Eq. (2) + t:U:M:D on the probes p < HALF_PROBES, computed once per table object."""
    key = (id(table), len(table))
    if key not in _HALF_FITS:
        half = table[table.p < HALF_PROBES].reset_index(drop=True)
        _HALF_FITS.clear()
        _HALF_FITS[key] = fit_binomial_glmm(half, PAPER_FORMULA, random=_EXTENDED_RANDOM, n_trials=30)
    return _HALF_FITS[key]


def _half_f_ratio(table, extended) -> float:
    return float(_half_fit(table).tests.F["F"] / extended.tests.F["F"])


EXERCISES = ExerciseSet(chapter=5, exercises=[
    Exercise(
        1, lambda fit: _baseline_probability(fit),
        hint="add the intercept and every main effect and interaction at the baseline levels (none, l2, fixed, "
             "F = no), then apply expit",
        wrong_answers=(
            WrongAnswer(lambda ns: float(expit(ns["fit"].coefficients["(Intercept)"])), "the intercept alone"),
            WrongAnswer(lambda ns: float(np.log(_baseline_probability(ns["fit"])
                                                / (1 - _baseline_probability(ns["fit"])))),
                        "the logit, without expit"),
            WrongAnswer(lambda ns: _baseline_probability(ns["fit"], "yes"), "the probe in training (F = yes)"),
            WrongAnswer(lambda ns: float(ns["table"].query("U == 'none' and M == 'l2' and D == 'fixed' and F == 'no'")
                                         .Y.mean() / 30), "the observed rate of those rows (an average probe)"),
        ),
        context=("fit",), rtol=0.0, atol=6e-4),
    Exercise(
        2, lambda simulate_toy, fit_toy: _wide_toy_ratio(simulate_toy, fit_toy),
        hint="simulate with the new sigma in the answer cell, fit the new toy both ways and divide the naive M[A] "
             "by the GLMM's M_A (beta[1] of fit_toy)",
        wrong_answers=(
            WrongAnswer(lambda ns: float(ns["ratio_toy"]), "the unchanged toy (sigma = 1.5)", unchanged_experiment=True),
            WrongAnswer(lambda ns: 1 / _wide_toy_ratio(ns["simulate_toy"], ns["fit_toy"]), "GLMM / naive, inverted"),
            WrongAnswer(lambda ns: _wide_toy_approximation(ns["simulate_toy"], ns["fit_toy"]),
                        "the approximation 1/sqrt(1 + 0.346 sigma^2) instead of the fitted ratio"),
        ),
        context=("simulate_toy", "fit_toy"), rtol=0.0, atol=0.006, experiment=True),
    Exercise(
        3, lambda fit, extended: _same_set(_terms_falling(fit, extended)),
        hint="divide fit.tests.F by extended.tests.F term by term and keep the terms whose ratio exceeds 3; "
             "answer a set of term names such as {'U', 'M'}",
        wrong_answers=(
            WrongAnswer(lambda ns: set(ns["fit"].tests.index), "every term"),
            WrongAnswer(set(), "the empty set"),
            WrongAnswer(lambda ns: set(ns["fit"].tests.index) - _config_only(ns["fit"]), "the terms with F"),
            WrongAnswer(lambda ns: {t for t in _config_only(ns["fit"]) if ":" not in t}, "the main effects only"),
        ),
        context=("fit", "extended")),
    Exercise(
        4, lambda fit, extended: _common_property(fit, extended),
        hint="look at which factors the terms of Exercise 3 are built from, and at which factor none of them holds",
        wrong_answers=(WrongAnswer(COMMON_CHOICES[1], "the inclusion flag"),
                       WrongAnswer(COMMON_CHOICES[2], "the PCA dimension")),
        context=("fit", "extended"), choices=COMMON_CHOICES),
    Exercise(
        5, lambda table, extended: _half_f_ratio(table, extended),
        hint="refit on table[table.p < 128] with the t:U:M:D term and divide its F value of the term 'F' by "
             "extended's",
        wrong_answers=(
            WrongAnswer(1.0, "the unchanged experiment (all 256 probes)", unchanged_experiment=True),
            WrongAnswer(0.5, "exactly half, guessed from the number of probes"),
            WrongAnswer(lambda ns: 1 / _half_f_ratio(ns["table"], ns["extended"]), "full / half, inverted"),
        ),
        context=("table", "extended"), rtol=0.0, atol=0.006, experiment=True),
])
