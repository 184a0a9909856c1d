"""Fitting the pose to the hand's surface (Sec. 3.4, eqs. 21-22): robust Gauss-Newton on d(Y_j, Θ)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from amdo_lab.common import MAX_ITERATIONS
from amdo_lab.common import as_finite_array, check_in_range, check_positive, check_positive_int
from amdo_lab.common.threads import one_blas_thread

from amdo_lab.em_articulated.estep import MAX_SIGMA_MM
from amdo_lab.em_articulated.hand import HandModel, check_hand, check_points

__all__ = ["SurfaceFitResult", "fit_surface"]

#: Initial Levenberg-Marquardt damping of the surface fit, relative to the normal equations' diagonal.
SURFACE_DAMPING = 1e-2

#: Largest per-point weight :func:`fit_surface` accepts (weights are relative: a weight of 1e308 would
#: overflow the weighted normal equations).
MAX_WEIGHT = 1e6


@dataclass(frozen=True)
class SurfaceFitResult:
    """Result of :func:`fit_surface`.

    Parameters
    ----------
    theta : numpy.ndarray, shape (27,)
        The refined pose.
    rms_distance : float
        Weighted RMS point-to-surface distance at that pose, mm.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591; Sec. 3.4, eqs. (21)-(22).
    """

    theta: np.ndarray
    rms_distance: float


def fit_surface(data_points: object, hand: HandModel, theta_init: object, *, weights: object = None,
                sigma: float | None = 3.0, max_iter: int = 3,
                epsilon_mm: float | None = None) -> SurfaceFitResult:
    """Refine Θ by minimising Σ_j β_j d(Y_j, Θ)² (Sec. 3.4, eq. 21; d from eq. 2).

    Gauss-Newton with the analytic Jacobian of eq. (2) (:meth:`HandModel.surface_distance_jacobian`),
    clipped to the joint limits. At every step β_j = exp(-d(Y_j)²/σ²) (eq. 22), so points far
    from the surface lose their weight (``sigma=None`` drops eq. 22: β_j = 1). These β_j are the
    iteratively-reweighted form of Welsch's robust loss σ²(1 - exp(-d²/σ²)); a step is kept only
    if it lowers that loss, otherwise the damping grows tenfold (Levenberg-Marquardt), and the fit
    stops early when no step helps. ``weights`` (per data point, e.g. the EM inlier
    probabilities) multiply β_j. With ``epsilon_mm`` each step uses only the points within ε of
    the current surface.

    Parameters
    ----------
    data_points : array_like, shape (M, 3)
        Data points Y_j, mm, within ±1e6; at least one.
    hand : HandModel
        The articulated model.
    theta_init : array_like, shape (27,)
        Start pose, inside the joint limits.
    weights : array_like, shape (M,), optional
        Per-point weights multiplying β_j, in [0, 1e6] (relative weights, such as the EM's inlier
        probabilities in [0, 1]; None: all 1).
    sigma : float or None, default 3.0
        σ of eq. (22), mm, in (0, 1e6]; None drops eq. (22).
    max_iter : int, default 3
        Most Gauss-Newton steps (≥ 0); the fit stops earlier when no step lowers the loss.
        At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).
    epsilon_mm : float or None, default None
        Use only the points within this distance of the current surface, mm (> 0); None: all.

    Returns
    -------
    SurfaceFitResult
        The refined pose and its weighted RMS distance.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591; Sec. 3.4, eqs. (2), (21)-(22).
    """
    check_hand(hand)
    data = check_points(data_points, "data_points")
    theta = hand.check_theta(theta_init, "theta_init", within_limits=True)
    w = np.ones(len(data)) if weights is None else as_finite_array(weights, "weights", shape=(len(data),),
                                                                    bounds=(0.0, MAX_WEIGHT))
    sigma = None if sigma is None else check_in_range(sigma, "sigma", 0.0, MAX_SIGMA_MM, closed="right")
    epsilon_mm = None if epsilon_mm is None else check_positive(epsilon_mm, "epsilon_mm")
    max_iter = check_positive_int(max_iter, "max_iter", minimum=0, maximum=MAX_ITERATIONS)
    limits = hand.joint_limits()

    def step_weights(dist: np.ndarray) -> np.ndarray:
        beta = w if sigma is None else w * np.exp(-dist**2 / sigma**2)  # eq. (22): β_j = exp(-d(Y_j)²/σ²)
        return beta if epsilon_mm is None else beta * (np.abs(dist) < epsilon_mm)

    def cost(dist: np.ndarray) -> float:
        # β_j of eq. (22) reweight Welsch's loss σ²(1 - exp(-d²/σ²)): the cost every accepted step lowers
        if sigma is not None:
            return float(np.sum(w * sigma**2 * (1.0 - np.exp(-dist**2 / sigma**2))))
        squared = dist**2 if epsilon_mm is None else np.minimum(dist**2, epsilon_mm**2)
        return float(np.sum(w * squared))

    with one_blas_thread():
        dist, jac = hand.surface_distance_jacobian(data, theta)
        current = cost(dist)
        for _ in range(max_iter):
            # eq. (21): Σ_j β_j d(Y_j, Θ)² as least squares in √β_j d_j, one Gauss-Newton step on its
            # normal equations
            sqrt_w = np.sqrt(step_weights(dist))
            jac_w = sqrt_w[:, None] * jac
            normal = jac_w.T @ jac_w
            gradient = jac_w.T @ (sqrt_w * dist)
            lm = SURFACE_DAMPING
            for _attempt in range(6):  # Levenberg-Marquardt: raise the damping until the step pays
                trial = np.clip(theta - np.linalg.solve(normal + lm * np.diag(np.diag(normal) + 1e-6), gradient),
                                limits[:, 0], limits[:, 1])
                trial_dist, trial_jac = hand.surface_distance_jacobian(data, trial)
                trial_cost = cost(trial_dist)
                if trial_cost <= current:
                    theta, dist, jac, current = trial, trial_dist, trial_jac, trial_cost
                    break
                lm *= 10.0
            else:
                break  # no step lowers the cost: converged
    final = step_weights(dist)
    return SurfaceFitResult(theta, float(np.sqrt(np.sum(final * dist**2) / max(final.sum(), 1e-12))))
