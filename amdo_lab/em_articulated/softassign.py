"""SoftAssign, the baseline of Sec. 4: a match matrix with slack, normalised by Sinkhorn sweeps."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.special import logsumexp

from amdo_lab.common import MAX_ITERATIONS
from amdo_lab.common import check_positive, check_positive_int

from amdo_lab.em_articulated.em import EMSettings, check_registration_input, m_step_pose
from amdo_lab.em_articulated.hand import HandModel

__all__ = ["SoftAssignResult", "register_softassign"]

#: Sinkhorn row-and-column normalisation sweeps per match-and-pose iteration.
N_SWEEPS = 30


@dataclass(frozen=True)
class SoftAssignResult:
    """Result of :func:`register_softassign`.

    Parameters
    ----------
    theta : numpy.ndarray, shape (27,)
        The estimated pose.
    inlier_prob : numpy.ndarray, shape (M,)
        Match mass per data point (1 - its slack entry), in [0, 1].

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591; Sec. 4 (the SoftAssign comparison).
    """

    theta: np.ndarray
    inlier_prob: np.ndarray


def register_softassign(model_points: object, data_points: object, hand: HandModel, theta_init: object,
                        sigma_max: float = 20.0, sigma_min: float = 2.0, *, slack: float = 1e-2,
                        n_levels: int = 5, n_iter: int = 3) -> SoftAssignResult:
    """SoftAssign (Gold, Rangarajan et al.) baseline of Sec. 4, Sinkhorn in the log domain.

    The (N+1)x(M+1) match matrix has a slack row and column initialised to ``slack``; rows and
    columns (except the slack ones) are alternately normalised to sum 1, 30 sweeps per iteration.
    Dense: O(N·M) memory.

    Parameters
    ----------
    model_points : array_like, shape (N, 3)
        Texture points X_i lying on the hand at pose ``theta_init``, mm, within ±1e6.
    data_points : array_like, shape (M, 3)
        Observed points Y_j (inliers and outliers), mm, within ±1e6.
    hand : HandModel
        The articulated model.
    theta_init : array_like, shape (27,)
        Pose where the texture was observed and the EM starts, inside the joint limits.
    sigma_max : float, default 20.0
        Largest σ of the annealing, mm (> ``sigma_min``, at most 1e6).
    sigma_min : float, default 2.0
        Smallest σ, mm (> 0).
    slack : float, default 1e-2
        Initial slack entry (> 0).
    n_levels : int, default 5
        Number of geometric σ levels (≥ 1). At most :data:`amdo_lab.common.MAX_LEVELS` (64).
    n_iter : int, default 3
        Match-and-pose iterations at each σ level (≥ 1).
        At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).

    Returns
    -------
    SoftAssignResult
        Pose and match mass per data point.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591; Sec. 4.

    Gold & Rangarajan, "A graduated assignment algorithm for graph matching", IEEE TPAMI 18 (1996)
    377-388; Rangarajan, Chui & Bookstein, "The softassign Procrustes matching algorithm", IPMI 1997,
    29-42 (the paper's [11], [12]).
    """
    model, data, theta = check_registration_input(model_points, data_points, hand, theta_init)
    sigmas = EMSettings(sigma_max=sigma_max, sigma_min=sigma_min, n_levels=n_levels).sigmas  # as the EM's (Sec. 3.3)
    slack = check_positive(slack, "slack")
    n_iter = check_positive_int(n_iter, "n_iter", maximum=MAX_ITERATIONS)
    binding = hand.texture_binding(model, theta)
    n_model, n_data = len(model), len(data)
    inlier_prob = np.zeros(n_data)
    for sigma in sigmas:
        for _ in range(n_iter):
            moved = hand._transform_texture(binding, theta)
            sq = np.sum((moved[:, None, :] - data[None, :, :]) ** 2, axis=2)
            log_m = np.full((n_model + 1, n_data + 1), np.log(slack))
            log_m[:n_model, :n_data] = -sq / (2 * sigma**2)
            for _ in range(N_SWEEPS):
                log_m[:n_model] -= logsumexp(log_m[:n_model], axis=1, keepdims=True)
                log_m[:, :n_data] -= logsumexp(log_m[:, :n_data], axis=0, keepdims=True)
            match = np.exp(log_m[:n_model, :n_data])
            weights = match.sum(axis=1)
            targets = (match @ data) / np.maximum(weights, 1e-300)[:, None]
            theta = m_step_pose(hand, binding, theta, weights, targets)
            inlier_prob = match.sum(axis=0)
    return SoftAssignResult(theta, inlier_prob)
