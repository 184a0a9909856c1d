"""Seeded multi-trial registration experiments shared by the notebook and the benchmark."""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from amdo_lab.common import MAX_ITERATIONS
from amdo_lab.common import RateInterval, check_bool, check_positive_int, make_rng, rate_interval, spawn_rngs

from amdo_lab.em_articulated.data import (RegistrationProblem, joint_rmse_deg, make_registration_problem,
                                          worst_joint_deg)
from amdo_lab.em_articulated.hand import HandModel, check_hand
from amdo_lab.em_articulated.diagnostics import climb_objective, fit_known_correspondences
from amdo_lab.em_articulated.digits import refine_digits
from amdo_lab.em_articulated.em import OUR_SETTINGS, EMSettings, check_em_settings, register_em
from amdo_lab.em_articulated.estep import robust_log_likelihood
from amdo_lab.em_articulated.surface import fit_surface
from amdo_lab.em_articulated.tracking import EPSILON_MM

__all__ = ["TrialSummary", "run_registration_trials", "SUCCESS_DEG", "ObjectiveCheck", "objective_check"]

#: A trial succeeds when every one of the 21 finger/thumb joints ends within this many degrees.
SUCCESS_DEG = 10.0


def check_settings(value: object, name: str) -> dict:
    """A copy of ``value`` (a dict of keyword arguments, or None for none), or a ``TypeError`` naming ``name``.

    Parameters
    ----------
    value : dict or None
        Keyword arguments, e.g. of :func:`make_registration_problem`.
    name : str
        The argument's name, for the message.

    Returns
    -------
    dict
        A copy of ``value`` ({} for None).
    """
    if value is not None and not isinstance(value, dict):
        raise TypeError(f"{name} must be a dict of keyword arguments or None, got {type(value).__name__}")
    return dict(value or {})


@dataclass(frozen=True)
class TrialSummary:
    """Per-trial joint RMSE and worst joint error (degrees) and run time (s) of EM + surface fit.

    Parameters
    ----------
    rmse_deg : numpy.ndarray, shape (T,)
        Joint RMSE of each trial (:func:`joint_rmse_deg`), degrees.
    max_error_deg : numpy.ndarray, shape (T,)
        Worst finger/thumb joint of each trial (:func:`worst_joint_deg`), degrees.
    seconds : numpy.ndarray, shape (T,)
        Wall-clock time of each trial's registration, seconds.
    oracle_rmse_deg : numpy.ndarray, shape (T,)
        Joint RMSE of :func:`fit_known_correspondences` on the same points with the true matches
        (NaN without shared features): the noise floor of the trial, degrees.
    oracle_max_error_deg : numpy.ndarray, shape (T,)
        The noise floor's worst finger joint, degrees.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591, Sec. 5.
    """

    rmse_deg: np.ndarray
    max_error_deg: np.ndarray
    seconds: np.ndarray
    oracle_rmse_deg: np.ndarray
    oracle_max_error_deg: np.ndarray

    @property
    def median_rmse_deg(self) -> float:
        """Median joint RMSE over the trials, degrees."""
        return float(np.median(self.rmse_deg))

    @property
    def success_rate(self) -> float:
        """Share of trials with every joint within :data:`SUCCESS_DEG`."""
        return float(np.mean(self.max_error_deg < SUCCESS_DEG))

    def success_interval(self, confidence: float = 0.95) -> RateInterval:
        """:attr:`success_rate` with its Wilson interval (at 100 trials, about ±6 points around 90 %).

        Parameters
        ----------
        confidence : float, default 0.95
            Coverage of the interval, in (0, 1).

        Returns
        -------
        RateInterval
            The success rate and the interval's bounds.
        """
        return rate_interval(self.max_error_deg < SUCCESS_DEG, confidence)

    @property
    def oracle_success_rate(self) -> float:
        """Share of trials whose noise-floor fit has every joint within :data:`SUCCESS_DEG` (NaN if none has a floor)."""
        finite = self.oracle_max_error_deg[np.isfinite(self.oracle_max_error_deg)]
        return float(np.mean(finite < SUCCESS_DEG)) if finite.size else float("nan")


def _check_trials(hand: object, n_trials: object, rng: object,
                  problem: object) -> tuple[list[np.random.Generator], dict]:
    """The arguments every trial function shares, checked: one random stream per trial, and the problem's keywords."""
    check_hand(hand)
    rng = make_rng(rng, "rng")
    n_trials = check_positive_int(n_trials, "n_trials", maximum=MAX_ITERATIONS)
    problem = check_settings(problem, "problem")
    return spawn_rngs(rng, n_trials), problem


def _floor_pose(hand: HandModel, case: RegistrationProblem) -> np.ndarray | None:
    """The pose fitted with the true matches (the noise floor); None without shared features."""
    model_index, data_index = case.true_matches()
    if not len(model_index):
        return None
    return fit_known_correspondences(case.model_points[model_index], case.data_points[data_index], hand,
                                     case.theta_init)


def _floor_errors(hand: HandModel, case: RegistrationProblem) -> tuple[float, float]:
    """Joint RMSE and worst joint (degrees) of the fit with the true matches; NaN without shared features."""
    floor = _floor_pose(hand, case)
    if floor is None:
        return np.nan, np.nan
    return joint_rmse_deg(floor, case.theta_true), worst_joint_deg(floor, case.theta_true)


def noise_floor_trials(hand: HandModel, n_trials: int, *, rng: np.random.Generator | int,
                       problem: dict | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The noise floor alone: joint errors of the least-squares fit with the true matches.

    The fit is :func:`fit_known_correspondences` from the start pose, on the same problems as
    :func:`run_registration_trials` with the same ``rng`` (its ``oracle_*`` fields), but without
    running the EM.

    Parameters
    ----------
    hand : HandModel
        The hand of every problem.
    n_trials : int
        Number of seeded problems (≥ 1). At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).
    rng : int or numpy.random.Generator
        Seed (≥ 0) or generator of the trials' random streams (:func:`amdo_lab.common.spawn_rngs`).
    problem : dict, optional
        Keyword arguments of :func:`make_registration_problem`.

    Returns
    -------
    rmse_deg : numpy.ndarray, shape (n_trials,)
        Joint RMSE per trial, degrees (NaN for trials without shared features).
    max_error_deg : numpy.ndarray, shape (n_trials,)
        Worst joint per trial, degrees (NaN likewise).

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591, eq. (20) with known matches.
    """
    trial_rngs, problem = _check_trials(hand, n_trials, rng, problem)
    errors = [_floor_errors(hand, make_registration_problem(hand, rng=trial_rng, **problem))
              for trial_rng in trial_rngs]
    return np.array([e[0] for e in errors]), np.array([e[1] for e in errors])


def run_registration_trials(hand: HandModel, n_trials: int, *, rng: np.random.Generator | int,
                            problem: dict | None = None, settings: EMSettings = OUR_SETTINGS,
                            surface_max_iter: int = 10, digit_search: bool = False) -> TrialSummary:
    """Seeded registration trials: EM, optional digit search, then surface fit, scored against the truth.

    Draws ``n_trials`` problems (:func:`make_registration_problem` with ``problem``), runs
    :func:`register_em` with ``settings`` then :func:`fit_surface` (Sec. 3.4) on the points
    within 5 mm of the surface, weighted by the EM inlier probabilities.

    Parameters
    ----------
    hand : HandModel
        The hand of every problem.
    n_trials : int
        Number of seeded problems (≥ 1). At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).
    rng : int or numpy.random.Generator
        Seed (≥ 0) or generator of the trials' random streams (:func:`amdo_lab.common.spawn_rngs`):
        trial k draws the same problem whatever ``n_trials``.
    problem : dict, optional
        Keyword arguments of :func:`make_registration_problem`.
    settings : EMSettings, default OUR_SETTINGS
        Settings of :func:`register_em`.
    surface_max_iter : int, default 10
        Most Gauss-Newton steps of the surface fit (≥ 0; 0 skips it).
        At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).
    digit_search : bool, default False
        Whether :func:`refine_digits` runs between the EM and the surface fit, with the same
        ``settings``; the surface fit then uses its inlier probabilities.

    Returns
    -------
    TrialSummary
        Per-trial errors, run times and noise floors.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591, Sec. 3 (eqs. 17-22) and Sec. 5.
    """
    trial_rngs, problem = _check_trials(hand, n_trials, rng, problem)
    settings = check_em_settings(settings)
    surface_max_iter = check_positive_int(surface_max_iter, "surface_max_iter", minimum=0, maximum=MAX_ITERATIONS)
    digit_search = check_bool(digit_search, "digit_search")
    rmse, worst, seconds, oracle, oracle_worst = [], [], [], [], []
    for trial_rng in trial_rngs:
        case = make_registration_problem(hand, rng=trial_rng, **problem)
        start = time.perf_counter()
        em = register_em(case.model_points, case.data_points, hand, case.theta_init, settings=settings)
        theta, inlier_prob = em.theta, em.inlier_prob
        if digit_search:
            search = refine_digits(case.model_points, case.data_points, hand, case.theta_init, theta,
                                   settings=settings)
            theta, inlier_prob = search.theta, search.inlier_prob
        if surface_max_iter:
            theta = fit_surface(case.data_points, hand, theta, weights=inlier_prob, max_iter=surface_max_iter,
                                epsilon_mm=EPSILON_MM).theta
        seconds.append(time.perf_counter() - start)
        floor_rmse, floor_worst = _floor_errors(hand, case)
        oracle.append(floor_rmse)
        oracle_worst.append(floor_worst)
        rmse.append(joint_rmse_deg(theta, case.theta_true))
        worst.append(worst_joint_deg(theta, case.theta_true))
    return TrialSummary(np.array(rmse), np.array(worst), np.array(seconds), np.array(oracle), np.array(oracle_worst))



@dataclass(frozen=True)
class ObjectiveCheck:
    """Per trial of :func:`objective_check`: joint RMSE (degrees) and the EM's objective at several poses.

    The poses: ``em`` (the pose :func:`register_em` returns), ``floor`` (the pose fitted with the
    true matches), ``truth`` (the true pose; RMSE 0, not stored), ``climbed`` (the local maximum of
    the objective reached from the floor pose, :func:`climb_objective`). The objective is
    :func:`robust_log_likelihood` at ``sigma``.

    Parameters
    ----------
    em_rmse_deg, floor_rmse_deg, climbed_rmse_deg : numpy.ndarray, shape (T,)
        Joint RMSE of each pose per trial, degrees.
    em_log_likelihood, floor_log_likelihood, truth_log_likelihood, climbed_log_likelihood : numpy.ndarray, shape (T,)
        The objective at each pose per trial, nats (compare within a trial only).
    sigma : float
        σ the objective is taken at, mm.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591, eqs. (9), (17)-(18).
    """

    em_rmse_deg: np.ndarray
    floor_rmse_deg: np.ndarray
    climbed_rmse_deg: np.ndarray
    em_log_likelihood: np.ndarray
    floor_log_likelihood: np.ndarray
    truth_log_likelihood: np.ndarray
    climbed_log_likelihood: np.ndarray
    sigma: float


def objective_check(hand: HandModel, n_trials: int, *, rng: np.random.Generator | int, problem: dict | None = None,
                    settings: EMSettings = OUR_SETTINGS) -> ObjectiveCheck:
    """Optimizer or objective: where the EM's own objective puts its maximum, on seeded problems.

    On ``n_trials`` seeded problems, run :func:`register_em` and fit the
    pose with the true matches (the noise floor); evaluate the EM's own objective (the robust
    log-likelihood of eq. 17's mixture at the EM's final σ) at both poses and at the truth, and climb
    it from the floor pose to its nearest local maximum.

    If the EM's pose scores higher than the floor pose and the climb from the floor ends as far
    from the truth as the EM, the objective (not the optimizer) sets the error.

    Parameters
    ----------
    hand : HandModel
        The hand of every problem.
    n_trials : int
        Number of seeded problems (≥ 1). At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).
    rng : int or numpy.random.Generator
        Seed (≥ 0) or generator of the trials' random streams (:func:`amdo_lab.common.spawn_rngs`).
    problem : dict, optional
        Keyword arguments of :func:`make_registration_problem`.
    settings : EMSettings, default OUR_SETTINGS
        Settings of :func:`register_em`; the objective is taken at their ``sigma_min``.

    Returns
    -------
    ObjectiveCheck
        Per-trial errors and objective values.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, ECCV 2006, eqs. (9), (17)-(18) (the objective).
    """
    trial_rngs, problem = _check_trials(hand, n_trials, rng, problem)
    settings = check_em_settings(settings)
    sigma = float(settings.sigma_min)
    rows = []
    for trial_rng in trial_rngs:
        case = make_registration_problem(hand, rng=trial_rng, **problem)
        em = register_em(case.model_points, case.data_points, hand, case.theta_init, settings=settings)
        floor = _floor_pose(hand, case)
        climbed = climb_objective(case.model_points, case.data_points, hand, case.theta_init, floor, sigma)
        binding = hand.texture_binding(case.model_points, case.theta_init)

        def objective(theta: np.ndarray) -> float:
            return robust_log_likelihood(hand.transform_texture(binding, theta), case.data_points, sigma)

        rows.append((joint_rmse_deg(em.theta, case.theta_true), joint_rmse_deg(floor, case.theta_true),
                     joint_rmse_deg(climbed, case.theta_true), objective(em.theta), objective(floor),
                     objective(case.theta_true), objective(climbed)))
    columns = np.array(rows).T
    return ObjectiveCheck(*columns, sigma)
