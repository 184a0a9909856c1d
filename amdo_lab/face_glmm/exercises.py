"""Chapter 5's exercises as data: hints, tolerances and the recorded wrong answers, never a target.

The check cells of ``notebooks/05_glmm_face_recognition.ipynb`` register each target as a literal
in a hidden test (``EXERCISES.expect(k, ...)``) and call ``EXERCISES.check(k, answer_k)``; the
worked solutions compute the targets in the notebook. Exercise 6 ("implement it") is checked
against the package's readable Laplace deviance on toys the notebook does not show. See
:mod:`amdo_lab.common.exercises` for the mechanism.

References
----------
Givens, Beveridge, Draper & Bolme (2004), "Using a Generalized Linear Mixed Model to Study the
Configuration Space of a PCA+LDA Human Face Recognition Algorithm", AMDO 2004, LNCS 3179, pp. 1-11;
Breslow & Clayton (1993), JASA 88, eqs. (5)-(7) (the Laplace approximation).
"""

from __future__ import annotations

import numpy as np
from scipy.special import expit, xlogy

from amdo_lab.common.exercises import Exercise, ExerciseSet, WrongAnswer
from amdo_lab.face_glmm.laplace import laplace_deviance_reference

__all__ = ["EXERCISES", "COMMON_CHOICES", "make_toy_case", "toy_laplace_deviance"]

COMMON_CHOICES = ("configuration factors only", "the inclusion flag F", "the PCA dimension D")


def make_toy_case(seed: int) -> dict:
    """A toy like the chapter's: probes x two configurations, Y ~ Bin(n, expit(L + M_c + b_p)).

    The number of probes (12-30), the binomial size (10, 20 or 30), sigma and the effects are drawn
    from ``seed``; returns the keyword arguments of :func:`toy_laplace_deviance`.
    """
    rng = np.random.default_rng(seed)
    n_probes = int(rng.integers(12, 31))
    n_trials = int(rng.choice([10, 20, 30]))
    sigma = float(rng.uniform(0.4, 2.5))
    probe = np.repeat(np.arange(n_probes), 2)
    config = np.tile([1.0, -1.0], n_probes)
    x = np.column_stack([np.ones(2 * n_probes), config])
    eta = rng.uniform(-0.5, 1.0) + rng.uniform(-0.8, 0.8) * config + rng.normal(0, sigma, n_probes)[probe]
    y = rng.binomial(n_trials, expit(eta)).astype(float)
    return {"sigma": float(rng.uniform(0.5, 2.0)), "y": y, "x": x, "z": np.eye(n_probes)[probe],
            "n_trials": n_trials}


def toy_laplace_deviance(sigma, y, x, z, n_trials):
    """(F3) of the toy (one random intercept of sd ``sigma``): the package's readable path."""
    return float(laplace_deviance_reference(y, float(n_trials), x, z, np.full(z.shape[1], float(sigma)))[2])


def _parts(sigma, y, x, z, n_trials):
    """d(y, mu), |u|^2, Z'WZ at the joint mode (the pieces the wrong functions recombine)."""
    beta, u, _, _ = laplace_deviance_reference(y, float(n_trials), x, z, np.full(z.shape[1], float(sigma)))
    mu = n_trials * expit(x @ beta + sigma * z @ u)
    deviance = 2 * np.sum(xlogy(y, y / mu) + xlogy(n_trials - y, (n_trials - y) / (n_trials - mu)))
    ztwz = z.T @ ((mu * (1 - mu / n_trials))[:, None] * z)
    return float(deviance), float(u @ u), ztwz


def _no_logdet(sigma, y, x, z, n_trials):
    deviance, uu, _ = _parts(sigma, y, x, z, n_trials)
    return deviance + uu


def _no_penalty(sigma, y, x, z, n_trials):
    deviance, _, ztwz = _parts(sigma, y, x, z, n_trials)
    return deviance + np.linalg.slogdet(sigma**2 * ztwz + np.eye(len(ztwz)))[1]


def _logdet_without_sigma(sigma, y, x, z, n_trials):
    deviance, uu, ztwz = _parts(sigma, y, x, z, n_trials)
    return deviance + uu + np.linalg.slogdet(ztwz + np.eye(len(ztwz)))[1]


def _logdet_without_identity(sigma, y, x, z, n_trials):
    deviance, uu, ztwz = _parts(sigma, y, x, z, n_trials)
    return deviance + uu + np.linalg.slogdet(sigma**2 * ztwz)[1]


EXERCISES = ExerciseSet(chapter=5, exercises=[
    Exercise(
        1, None,
        hint="add the intercept and every main effect and interaction at the levels asked (noise, l2, e90, "
             "F = no), then apply expit",
        wrong_answers=(
            WrongAnswer(0.968, "the intercept alone", hint="the intercept is the average over every level; add "
                        "the coefficients of the levels asked, interactions included"),
            WrongAnswer(1.844, "the logit, without expit", hint="that is a logit; a probability needs expit"),
            WrongAnswer(0.873, "the probe in training (F = yes)", hint="the prompt asks for a probe that is not in "
                        "training: F = no, in every term with F"),
            WrongAnswer(0.932, "the last levels (noise, e90) taken as 0", hint="with sum-to-zero coding the last "
                        "level of a factor is minus the sum of the others' coefficients, not 0"),
            WrongAnswer(0.805, "the main effects only", hint="add the interaction columns too: each is the product "
                        "of its factors' columns at the levels asked"),
            WrongAnswer(0.919, "the baseline (none, l2, fixed) of the table after Fig. 2",
                        hint="that is the baseline configuration; this one uses the noise supplement and E90"),
        ),
        rtol=0.0, atol=6e-4),
    Exercise(
        2, None,
        hint="simulate with the new sigma in the answer cell, fit the new toy both ways and divide the naive M[A] "
             "by the GLMM's M_A (beta[1] of fit_toy)",
        wrong_answers=(
            WrongAnswer(0.74, "the unchanged toy (sigma = 1.5)", unchanged_experiment=True, variable="ratio_toy",
                        hint="that is the chapter's toy at sigma = 1.5: set toy_sigma = 3.0 and run again"),
            WrongAnswer(2.15, "GLMM / naive, inverted", hint="divide the naive M[A] by the GLMM's, not the other way"),
            WrongAnswer(0.52, "the approximation 1/sqrt(1 + 0.346 sigma^2) at sigma = 3",
                        hint="that is the approximation; the exercise asks for the fitted ratio"),
        ),
        rtol=0.0, atol=0.006, experiment=True, why_points=1),
    Exercise(
        3, None,
        hint="divide fit.tests.F by extended.tests.F term by term and answer the name of the term with the "
             "largest ratio, as a string",
        wrong_answers=(
            WrongAnswer("D", "the largest F value, or the largest fall in absolute terms",
                        hint="the exercise asks for the largest factor, F in fit divided by F in extended, not the "
                             "largest difference"),
            WrongAnswer("U:D", "the second largest factor",
                        hint="one term falls by a larger factor still: compare every ratio"),
            WrongAnswer("M:F", "the ratio inverted (extended over fit)",
                        hint="divide fit's F by extended's: the term asked falls, it does not rise"),
        ),
        rtol=0.0),
    Exercise(
        4, None,
        hint="look at which factors the terms of Exercise 3 are built from, and at which factor none of them holds",
        wrong_answers=(WrongAnswer(COMMON_CHOICES[1], "the inclusion flag",
                                   hint="none of the terms of Exercise 3 contains F"),
                       WrongAnswer(COMMON_CHOICES[2], "the PCA dimension",
                                   hint="U and M:U are among them and contain no D")),
        choices=COMMON_CHOICES, why_points=2),
    Exercise(
        5, None,
        hint="refit on table[table.p < 128] with the t:U:M:D term and divide its F value of the term 'M:F' by "
             "extended's, to three decimals",
        wrong_answers=(
            WrongAnswer(1.0, "the unchanged experiment (all 256 probes)", unchanged_experiment=True,
                        hint="with probes_kept = 256 the refit is the whole table: keep p < 128"),
            WrongAnswer(0.5, "exactly half, guessed from the number of probes",
                        hint="the ratio is measured, not half by construction: run the refit"),
            WrongAnswer(0.555, "the inclusion main effect F instead of M:F",
                        hint="that is the term F; the exercise asks for the metric x inclusion term M:F"),
            WrongAnswer(1.957, "full / half, inverted", hint="divide the half table's F by the whole table's"),
        ),
        rtol=0.0, atol=6e-4, experiment=True, why_points=1),
    Exercise(
        6, None,
        hint="(F3) is d(y, mu) + |u|^2 + log det(sigma^2 Z'WZ + I), all at the joint mode that pirls returns, "
             "with mu = n expit(X beta + sigma Z u) and W = diag(mu (1 - mu / n))",
        kind="function", reference=toy_laplace_deviance, make_case=make_toy_case, example_seed=0,
        wrong_answers=(
            WrongAnswer(_no_logdet, "without the log-determinant term",
                        hint="the Gaussian integral over u leaves a log-determinant: add log det(sigma^2 Z'WZ + I)"),
            WrongAnswer(_no_penalty, "without |u|^2",
                        hint="the prior of u, N(0, I), contributes |u|^2 at the mode"),
            WrongAnswer(_logdet_without_sigma, "log det(Z'WZ + I), sigma left out",
                        hint="b = sigma u, so Z'WZ enters the determinant scaled by sigma^2"),
            WrongAnswer(_logdet_without_identity, "log det(sigma^2 Z'WZ), the identity left out",
                        hint="the prior's precision I is part of the curvature: sigma^2 Z'WZ + I"),
        ),
        rtol=1e-6, atol=1e-6),
])
