"""The exercises of chapter 2 (mixtures of point distribution models): hints and wrong answers.

The targets are not here: each check cell of the chapter's source registers its own (a literal in a
hidden test, ``EXERCISES.expect``), so the package the reader installs does not hold them (see
:mod:`amdo_lab.common.exercises`). Exercise 6 ("implement it") is checked against one iteration of
:func:`amdo_lab.pdm_mixtures.fit_gaussian_mixture` started from diagonal covariances, on cases
drawn by :func:`_em_step_case`.

References
----------
A. A. Al-Shaher, E. R. Hancock, "A Probabilistic Framework for Articulated Shape Recognition",
AMDO 2004, LNCS 3179, pp. 62-75: eqs. 1-8 (Exercises 3 and 6), eq. 18 (Exercise 1), Secs. 2-4.
"""

from __future__ import annotations

import numpy as np

from amdo_lab.common.exercises import Exercise, ExerciseSet, WrongAnswer
from amdo_lab.pdm_mixtures.gmm import fit_gaussian_mixture

__all__ = ["EXERCISES"]


def _diagonal_em_step(X: np.ndarray, weights: np.ndarray, means: np.ndarray,
                      variances: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One EM iteration (eqs. 4-8) of a mixture whose covariances are diagonal, ``variances`` (K, d).

    From diagonal covariances the E-step is the diagonal one, and the diagonal of the M-step's
    covariance (eq. 8) is the diagonal M-step, so one step of the package's EM gives it exactly.
    """
    fit = fit_gaussian_mixture(X, len(weights), means_init=means,
                               covariances_init=np.stack([np.diag(v) for v in variances]),
                               weights_init=weights, n_iter=1, reg_covar=0.0)
    return fit.weights, fit.means, np.stack([np.diag(c) for c in fit.covariances])


def _em_step_case(seed: int) -> dict:
    """One input of Exercise 6: 30-60 points from 2-3 clusters in 2-4 dimensions, and a start."""
    rng = np.random.default_rng(seed)
    k, d = int(rng.integers(2, 4)), int(rng.integers(2, 5))
    centres = rng.normal(0.0, 3.0, (k, d))
    X = centres[rng.integers(0, k, int(rng.integers(30, 61)))]
    X = X + rng.normal(0.0, 1.0, X.shape)
    weights = rng.dirichlet(np.full(k, 4.0))
    means = X[rng.choice(len(X), k, replace=False)] + rng.normal(0.0, 0.5, (k, d))
    variances = X.var(axis=0) * rng.uniform(0.3, 1.5, (k, d))
    return dict(X=X, weights=weights, means=means, variances=variances)


def _posteriors(X, weights, means, variances, *, use_weights=True):
    log_p = -0.5 * np.sum(np.log(2 * np.pi * variances)[None] + (X[:, None] - means[None]) ** 2 / variances[None],
                          axis=2)
    if use_weights:
        log_p = log_p + np.log(weights)
    return np.exp(log_p - np.logaddexp.reduce(log_p, axis=1, keepdims=True))


def _old_mean(X, weights, means, variances):
    post = _posteriors(X, weights, means, variances)
    counts = post.sum(axis=0)
    new_means = post.T @ X / counts[:, None]
    new_variances = np.stack([post[:, j] @ (X - means[j]) ** 2 for j in range(len(means))]) / counts[:, None]
    return counts / len(X), new_means, new_variances


def _unnormalised(X, weights, means, variances):
    post = _posteriors(X, weights, means, variances)
    new_means = post.T @ X
    new_variances = np.stack([post[:, j] @ (X - new_means[j]) ** 2 for j in range(len(means))])
    return post.sum(axis=0) / len(X), new_means, new_variances


def _without_mixing_weights(X, weights, means, variances):
    post = _posteriors(X, weights, means, variances, use_weights=False)
    counts = post.sum(axis=0)
    new_means = post.T @ X / counts[:, None]
    new_variances = np.stack([post[:, j] @ (X - new_means[j]) ** 2 for j in range(len(means))]) / counts[:, None]
    return counts / len(X), new_means, new_variances


def _full_covariances(X, weights, means, variances):
    fit = fit_gaussian_mixture(X, len(weights), means_init=means,
                               covariances_init=np.stack([np.diag(v) for v in variances]),
                               weights_init=weights, n_iter=1, reg_covar=0.0)
    return fit.weights, fit.means, fit.covariances


EXERCISES = ExerciseSet(chapter=2, exercises=[
    Exercise(
        1, None,
        "write ln P(L|Lambda) = ln K_p - k_p H and see what one more mismatch (H -> H + 1) subtracts",
        (WrongAnswer(-2.20, "a sign slip: ln(p / (1 - p))",
                     hint="the question asks by how much ln P drops: a positive number of nats"),
         WrongAnswer(2.30, "-ln p, the cost of a mismatch without the match term",
                     hint="a mismatch also loses the factor (1 - p) of a match: the cost is k_p = ln((1 - p)/p)"),
         WrongAnswer(0.95, "log10 instead of the natural logarithm", hint="nats: use the natural logarithm"),
         WrongAnswer(1.37, "-K ln(1 - p), the constant ln K_p instead of k_p",
                     hint="K_p does not depend on H; the drop per mismatch is k_p"),
         WrongAnswer(1.39, "the chapter's p = 0.2", hint="the exercise sets p = 0.1, not the chapter's 0.2")),
        atol=0.005, rtol=0.0),
    Exercise(
        2, None,
        "set mode_deg = 15.0 in the answer cell, run it, and subtract the mixture's ln p from the single PDM's",
        (WrongAnswer(148.8, "the unchanged toy (modes at +-50 degrees)", unchanged_experiment=True,
                     variable="straight_gap",
                     hint="that is the unchanged toy with its modes at ±50°: set mode_deg = 15.0 and run again"),
         WrongAnswer(-5.1, "a sign slip: mixture minus single",
                     hint="the single PDM's ln p minus the mixture's, not the other way round"),
         WrongAnswer(13.1, "the single PDM's ln p alone", hint="give the difference of the two ln p, not one of them")),
        atol=0.05, rtol=0.0, experiment=True, why_points=1),
    Exercise(
        3, None,
        "fit_pdm(vectors).n_modes with vectors of shape (20, 156); 95 % of the variance is the default",
        (WrongAnswer(19, "every mode 20 shapes allow",
                     hint="20 shapes allow 19 modes, but the PDM keeps only those holding 95 % of the variance"),
         WrongAnswer(156, "the length of the long vector",
                     hint="156 is the length of a long vector; count the modes fit_pdm keeps"),
         WrongAnswer(6, "one mode too many", hint="count again: n_modes of the fitted PDM"),
         WrongAnswer(4, "one mode too few", hint="count again: n_modes of the fitted PDM")),
        atol=0.0, rtol=0.0, why_points=1),
    Exercise(
        4, None,
        "set separation = 3.0 in the answer cell and average the single polar PDM's rate over the five seeds",
        (WrongAnswer(0.82, "the unchanged experiment (s = 2)", unchanged_experiment=True, variable="single_polar_mean",
                     hint="that is s = 2, the unchanged cell: set separation = 3.0 and run again"),
         WrongAnswer(0.98, "the mixture's rate instead of the single polar PDM's",
                     hint="that is the mixture of PDMs; the exercise asks for the single polar PDM"),
         WrongAnswer(0.13, "the mixture's lead instead of the rate",
                     hint="give the single polar PDM's rate itself, not the mixture's lead over it")),
        atol=0.005, rtol=0.0, experiment=True, why_points=1),
    Exercise(
        5, None,
        "sum the squared entries of each mode column over the first 13 rows (the angles); take the smallest",
        (WrongAnswer(1.0, "the largest share instead of the smallest",
                     hint="that is the largest share; the exercise asks for the smallest"),
         WrongAnswer(0.33, "13 of 39 coordinates, the share of an even mode",
                     hint="13/39 is what a mode spread evenly over all coordinates would give: measure the modes"),
         WrongAnswer(0.06, "the centres' share", hint="that is the share on the 26 centre rows; take the 13 angle rows")),
        atol=0.005, rtol=0.0, why_points=1),
    Exercise(
        6, None,
        "E-step: P(t in w | X_t) proportional to pi_w times the diagonal Gaussian (eqs. 4, 6); M-step: the new "
        "weights (eq. 5), then means and variances as posterior-weighted averages divided by sum_t P(t in w | X_t), "
        "the variances about the new means (eqs. 7-8 as the chapter reads them)",
        (WrongAnswer(_old_mean, "eq. 8 as printed, about the old mean",
                     hint="eq. 8 as printed uses the old mean; the likelihood is maximised about the new one"),
         WrongAnswer(_unnormalised, "eqs. 7-8 as printed, without the division",
                     hint="eqs. 7-8 as printed omit the division by sum_t P(t in w | X_t): your means are sums"),
         WrongAnswer(_without_mixing_weights, "the E-step without the mixing weights",
                     hint="Bayes' rule (eq. 4) multiplies each component's density by its weight pi_w"),
         WrongAnswer(_full_covariances, "full covariance matrices instead of the variances",
                     hint="return the variances, the diagonal of eq. 8, as a (K, d) array")),
        kind="function", reference=_diagonal_em_step, make_case=_em_step_case, example_seed=0,
        rtol=1e-6, atol=1e-10),
])
