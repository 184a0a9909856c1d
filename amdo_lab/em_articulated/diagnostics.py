"""Diagnostics of the EM: the noise floor of any matching and a climb of the EM's own objective."""

from __future__ import annotations

import numpy as np

from amdo_lab.common import as_finite_array, check_in_range
from amdo_lab.common.threads import one_blas_thread

from amdo_lab.em_articulated.em import EMSettings, check_registration_input, m_step_pose, run_em
from amdo_lab.em_articulated.estep import MAX_SIGMA_MM
from amdo_lab.em_articulated.hand import MAX_LENGTH_MM, HandModel, check_hand, check_points

__all__ = ["climb_objective", "fit_known_correspondences"]

#: Most EM iterations of :func:`climb_objective`, and its stopping threshold on the largest change of
#: a DOF in one iteration (rad; mm for the palm): tighter than the EM's, to reach the maximum itself.
CLIMB_MAX_ITER, CLIMB_TOL = 60, 1e-5
#: Most Gauss-Newton steps of :func:`fit_known_correspondences` (it stops earlier when a step is below 1e-6).
FLOOR_MAX_ITER = 30

def climb_objective(model_points: object, data_points: object, hand: HandModel, theta_init: object,
                    theta_start: object, sigma: float = 3.0) -> np.ndarray:
    """The plain EM at one fixed σ from ``theta_start``: a climb of :func:`robust_log_likelihood`.

    With the paper's targets G_i and σ held fixed, every EM iteration raises the data's
    log-likelihood under eq. (9)'s mixture (the EM property, Sec. 3.2), so the pose returned is the
    local maximum of that objective nearest ``theta_start``. The texture is bound at
    ``theta_init``, where it was observed, as in :func:`register_em`. Used to ask where the
    objective itself puts its maximum, e.g. started from the pose fitted with the true matches.

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
    theta_start : array_like, shape (27,)
        Pose the climb starts from, inside the joint limits.
    sigma : float, default 3.0
        The fixed σ, mm, in (0, 5e5].

    Returns
    -------
    theta : numpy.ndarray, shape (27,)
        Pose at the local maximum (or after 60 iterations).

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, ECCV 2006, eqs. (9), (17), (20).
    """
    model, data, theta_init = check_registration_input(model_points, data_points, hand, theta_init)
    start = hand.check_theta(theta_start, "theta_start", within_limits=True)
    sigma = check_in_range(sigma, "sigma", 0.0, MAX_SIGMA_MM / 2, closed="right")
    settings = EMSettings(sigma_max=2.0 * sigma, sigma_min=sigma, n_levels=1, max_iter=CLIMB_MAX_ITER)
    binding = hand.texture_binding(model, theta_init)
    return run_em(hand, binding, data, start, settings, np.array([sigma]), tol=CLIMB_TOL)[0]


def fit_known_correspondences(model_points: object, matched_points: object, hand: HandModel, theta_init: object
                              ) -> np.ndarray:
    """Least-squares pose when every texture point's match is known: the M-step (eq. 20) with α = 1.

    The noise floor of point registration: no assignment can do better than the true one.
    ``matched_points`` (N, 3) are the observations of ``model_points`` (N, 3) at the unknown pose.

    Parameters
    ----------
    model_points : array_like, shape (N, 3)
        Texture points at ``theta_init``, mm, within ±1e6.
    matched_points : array_like, shape (N, 3)
        Observation of each texture point at the unknown pose, mm, within ±1e6.
    hand : HandModel
        The articulated model.
    theta_init : array_like, shape (27,)
        Pose of the texture and start of the fit, inside the joint limits.

    Returns
    -------
    numpy.ndarray, shape (27,)
        The least-squares pose.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591; eq. (20) with α_ij = 1 for the true pairs.
    """
    check_hand(hand)
    model = check_points(model_points, "model_points")
    matched = as_finite_array(matched_points, "matched_points", shape=model.shape, max_abs=MAX_LENGTH_MM)
    theta = hand.check_theta(theta_init, "theta_init", within_limits=True)
    with one_blas_thread():
        binding = hand.texture_binding(model, theta)
        return m_step_pose(hand, binding, theta, np.ones(len(model)), matched, n_steps=FLOOR_MAX_ITER)
