"""Robust EM registration (Sec. 3.1-3.3, eqs. 17-20), surface fitting (Sec. 3.4) and SoftAssign (Sec. 4)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.special import logsumexp

from amdo_lab.common import as_finite_array, check_choice, check_positive, check_positive_int

from amdo_lab.em_articulated.hand import HandModel, TextureBinding

__all__ = ["EMResult", "register_em", "e_step_statistics_kdtree", "dof_lever_arms", "PAPER_SETTINGS", "COARSE_TO_FINE_SETTINGS", "fit_surface", "softassign_register", "PAPER_C",
           "e_step_statistics", "SurfaceFitResult", "SoftAssignResult"]

#: Outlier constant of eq. (18) with n v << V.
PAPER_C = 3.0 * np.sqrt(np.pi / 2.0)

#: register_em settings as in the paper: every DOF free at every σ, c of eq. (18), σ down to the noise.
PAPER_SETTINGS = {"sigma_max": 20.0, "sigma_min": 2.0, "iterations_per_level": 3}
#: Our settings for sparse, independently sampled texture and data (see the chapter's ablation):
#: σ floor at about half the texture spacing, a smaller c so sparse inliers keep their weight,
#: the palm alone while σ is wider than half a finger pitch, short-lever joints released last.
COARSE_TO_FINE_SETTINGS = {"sigma_max": 20.0, "sigma_min": 4.0, "iterations_per_level": 6,
                           "outlier_c": 0.1, "release_ratio": 4.0, "release_sigma": 9.0}


@dataclass(frozen=True)
class EMResult:
    """Result of :func:`register_em`.

    theta : (27,) estimated pose; inlier_prob : (M,) Σ_i α_ij per data point;
    history : (n_iter, 2) rows of [σ, energy of eq. (20)]; model_points : (N, 3) moved texture.
    """

    theta: np.ndarray
    inlier_prob: np.ndarray
    history: np.ndarray
    model_points: np.ndarray


def e_step_statistics(model_points: np.ndarray, data_points: np.ndarray, sigma: float,
                      log_c: float, chunk: int = 256) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Stream eq. (17) over data chunks in the log domain; memory O(M + N + chunk·N).

    Returns
    -------
    weights : (N,) Σ_j α_ij per model point
    weighted_data : (N, 3) Σ_j α_ij Y_j
    inlier_prob : (M,) Σ_i α_ij per data point
    energy : float, Σ_ij α_ij ||Y_j - T(X_i)||² (eq. 19/20 up to the 1/2σ² factor)
    """
    n_model = model_points.shape[0]
    weights = np.zeros(n_model)
    weighted_data = np.zeros((n_model, 3))
    inlier_prob = np.empty(data_points.shape[0])
    energy = 0.0
    model_sq = np.sum(model_points**2, axis=1)
    for start in range(0, data_points.shape[0], chunk):
        block = data_points[start:start + chunk]
        sq = np.maximum(np.sum(block**2, axis=1)[:, None] + model_sq[None, :] - 2 * block @ model_points.T, 0.0)
        log_kernel = -sq / (2 * sigma**2)
        log_norm = np.logaddexp(logsumexp(log_kernel, axis=1), log_c)
        alpha = np.exp(log_kernel - log_norm[:, None])  # (chunk, N), never underflows to NaN
        weights += alpha.sum(axis=0)
        weighted_data += alpha.T @ block
        inlier_prob[start:start + chunk] = alpha.sum(axis=1)
        energy += float(np.sum(alpha * sq))
    return weights, weighted_data, inlier_prob, energy


def dof_lever_arms(hand: HandModel, binding: TextureBinding, theta: np.ndarray) -> np.ndarray:
    """Largest distance (mm) a unit rotation of each DOF moves a texture point, shape (27,).

    Palm translations get +inf (always resolvable). A DOF whose lever arm is short moves points
    by much less than σ while σ is large, so its estimate there is dominated by the blur of the
    targets G_i (eq. 20) rather than by the data.
    """
    _, jac = hand.texture_jacobian(binding, theta)
    lever = np.max(np.linalg.norm(jac, axis=1), axis=0)
    lever[:3] = np.inf
    return lever


def e_step_statistics_kdtree(model_points: np.ndarray, data_points: np.ndarray, sigma: float,
                             log_c: float, radius_sigmas: float = 4.0) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Truncated eq. (17): only pairs closer than ``radius_sigmas``·σ, found with a k-d tree.

    Same outputs as :func:`e_step_statistics`. A pair at 4σ has kernel exp(-8) ≈ 3e-4, so the
    dropped mass is negligible next to c; memory is O(M + N + number of close pairs). The kernel
    of a kept pair is at least exp(-radius²/2), so the linear domain cannot underflow here.
    """
    from scipy.spatial import cKDTree  # local: only this variant needs it

    radius = radius_sigmas * sigma
    pairs = cKDTree(data_points).sparse_distance_matrix(cKDTree(model_points), radius, output_type="ndarray")
    data_index, model_index, dist = pairs["i"], pairs["j"], pairs["v"]
    kernel = np.exp(-dist**2 / (2 * sigma**2))
    row_sum = np.bincount(data_index, kernel, minlength=len(data_points)) + np.exp(log_c)
    alpha = kernel / row_sum[data_index]
    n_model = len(model_points)
    weights = np.bincount(model_index, alpha, minlength=n_model)
    weighted_data = np.stack([np.bincount(model_index, alpha * data_points[data_index, k], minlength=n_model)
                              for k in range(3)], axis=1)
    inlier_prob = np.bincount(data_index, alpha, minlength=len(data_points))
    return weights, weighted_data, inlier_prob, float(np.sum(alpha * dist**2))


def _m_step(hand: HandModel, binding: TextureBinding, theta: np.ndarray, weights: np.ndarray,
            targets: np.ndarray, n_steps: int, damping: float, free: np.ndarray | None = None) -> np.ndarray:
    """Minimise Σ_i w_i ||G_i - T(X_i, Θ)||² (eq. 20) by projected Gauss-Newton over the ``free`` DOFs."""
    limits = hand.joint_limits()
    active = weights > 1e-8
    free = np.ones(hand.n_dof, bool) if free is None else free
    if not np.any(active):
        return theta
    sqrt_w = np.sqrt(weights[active])[:, None]
    for _ in range(n_steps):
        moved, jac = hand.texture_jacobian(binding, theta)
        residual = (sqrt_w * (targets[active] - moved[active])).ravel()
        jac_w = (sqrt_w[:, :, None] * jac[active][:, :, free]).reshape(-1, int(free.sum()))
        normal = jac_w.T @ jac_w
        normal += damping * np.diag(np.diag(normal) + 1e-6)
        step = np.zeros(hand.n_dof)
        step[free] = np.linalg.solve(normal, jac_w.T @ residual)
        theta = np.clip(theta + step, limits[:, 0], limits[:, 1])
        if np.max(np.abs(step)) < 1e-6:
            break
    return theta


def _check_common(hand: HandModel, model_points: object, data_points: object, theta_init: object,
                  sigma_max: object, sigma_min: object) -> tuple[np.ndarray, np.ndarray, np.ndarray, float, float]:
    if not isinstance(hand, HandModel):
        raise TypeError(f"hand must be a HandModel, got {type(hand).__name__}")
    model = as_finite_array(model_points, "model_points", ndim=2, shape=(None, 3))
    data = as_finite_array(data_points, "data_points", ndim=2, shape=(None, 3))
    theta = hand.check_theta(theta_init, "theta_init", within_limits=True)
    sigma_max = check_positive(sigma_max, "sigma_max")
    sigma_min = check_positive(sigma_min, "sigma_min")
    if sigma_min >= sigma_max:
        raise ValueError(f"sigma_min must be smaller than sigma_max, got {sigma_min} >= {sigma_max}")
    return model, data, theta, sigma_max, sigma_min


def register_em(model_points: object, data_points: object, hand: HandModel, theta_init: object,
                sigma_max: float = 20.0, sigma_min: float = 2.0, *, n_levels: int = 5,
                iterations_per_level: int = 3, outlier_c: float | None = None,
                sigma_mode: str = "anneal", a: float = 2.0, gauss_newton_steps: int = 2,
                damping: float = 1e-3, chunk: int = 256, release_ratio: float | None = None,
                release_sigma: float | None = None, e_step: str = "dense") -> EMResult:
    """Robust EM alignment of texture points X_i (at ``theta_init``) to data Y_j (Sec. 3).

    Parameters
    ----------
    model_points : (N, 3) texture points lying on the hand at pose ``theta_init``.
    data_points : (M, 3) observed points (inliers and outliers).
    hand : HandModel
    theta_init : (27,) start pose, inside the joint limits.
    sigma_max, sigma_min : annealing range in mm (largest expected motion, noise level).
    n_levels : number of geometric σ levels (the paper uses about five).
    outlier_c : constant c of eq. (17); default 3√(π/2) (eq. 18). ``sigma_mode="scaled"`` instead
        uses c·(σ/σ_min)^3, i.e. a fixed outlier density rather than a fixed c.
    sigma_mode : "anneal" (paper), "scaled" (σ-scaled c, ablation) or "estimate" (σ re-estimated
        in the M-step from the weighted residuals, the variant the paper warns against).
    release_ratio, release_sigma : coarse-to-fine schedule, ours (the paper frees every DOF at
        every σ, which is the default ``None``). With ``release_ratio`` a joint is estimated only
        once σ is below its lever arm (:func:`dof_lever_arms`) divided by the ratio; with
        ``release_sigma`` no finger DOF is estimated while σ exceeds it (only the palm's six).
        Both keep a blurred E-step (σ wider than a finger) from curling or crossing fingers.
    e_step : "dense" (every pair, streamed in chunks) or "kdtree" (pairs within 4σ only,
        :func:`e_step_statistics_kdtree`).
    """
    model, data, theta, sigma_max, sigma_min = _check_common(hand, model_points, data_points,
                                                             theta_init, sigma_max, sigma_min)
    if model.shape[0] == 0 or data.shape[0] == 0:
        raise ValueError("model_points and data_points must be non-empty")
    n_levels = check_positive_int(n_levels, "n_levels")
    iterations_per_level = check_positive_int(iterations_per_level, "iterations_per_level")
    check_choice(sigma_mode, "sigma_mode", ("anneal", "scaled", "estimate"))
    check_choice(e_step, "e_step", ("dense", "kdtree"))

    def statistics(points: np.ndarray, sigma: float, log_c: float) -> tuple:
        if e_step == "kdtree":
            return e_step_statistics_kdtree(points, data, sigma, log_c)
        return e_step_statistics(points, data, sigma, log_c, chunk)

    c = PAPER_C if outlier_c is None else check_positive(outlier_c, "outlier_c")
    if release_ratio is not None:
        release_ratio = check_positive(release_ratio, "release_ratio")
    if release_sigma is not None:
        release_sigma = check_positive(release_sigma, "release_sigma")
    binding = hand.texture_binding(model, theta, a)
    sigmas = np.geomspace(sigma_max, sigma_min, n_levels)
    lever = dof_lever_arms(hand, binding, theta)
    history = []
    sigma = sigma_max
    inlier_prob = np.zeros(data.shape[0])
    for level in range(n_levels):
        for _ in range(iterations_per_level):
            if sigma_mode != "estimate":
                sigma = sigmas[level]
            log_c = np.log(c) + (3 * np.log(sigma / sigma_min) if sigma_mode == "scaled" else 0.0)
            moved = hand.transform_texture(binding, theta)
            weights, weighted, inlier_prob, energy = statistics(moved, sigma, log_c)
            history.append((sigma, energy))
            targets = weighted / np.maximum(weights, 1e-300)[:, None]
            # coarse-to-fine: a DOF is estimated once σ is below its lever arm / release_ratio
            scale = min(sigma, sigmas[level])
            free = np.ones(hand.n_dof, bool)
            if release_ratio is not None:
                free &= lever >= release_ratio * scale
            if release_sigma is not None and scale > release_sigma:
                free[6:] = False
            theta = _m_step(hand, binding, theta, weights, targets, gauss_newton_steps, damping, free)
            if sigma_mode == "estimate":
                _, _, _, new_energy = statistics(hand.transform_texture(binding, theta), sigma, log_c)
                sigma = max(np.sqrt(new_energy / max(3 * weights.sum(), 1e-12)), 1e-3)
    return EMResult(theta, inlier_prob, np.array(history), hand.transform_texture(binding, theta))


@dataclass(frozen=True)
class SurfaceFitResult:
    """Result of :func:`fit_surface`: pose and RMS point-to-surface distance (mm)."""

    theta: np.ndarray
    rms_distance: float


def fit_surface(data_points: object, hand: HandModel, theta_init: object, *, weights: object = None,
                n_steps: int = 3, damping: float = 1e-2, fd_step: float = 1e-4,
                epsilon_mm: float | None = None) -> SurfaceFitResult:
    """Refine Θ by minimising Σ_j w_j d(Y_j, Θ)² (Sec. 3.4, eqs. 21-22; d from eq. 2).

    Gauss-Newton with a forward-difference Jacobian of eq. (2) in Θ, clipped to the joint limits.
    ``weights`` (per data point, e.g. the EM inlier probabilities) default to 1. With
    ``epsilon_mm`` each step uses only the points within ε of the current surface, so clutter a
    few centimetres away (which eq. 22 would square) cannot pull the hand.
    """
    if not isinstance(hand, HandModel):
        raise TypeError(f"hand must be a HandModel, got {type(hand).__name__}")
    data = as_finite_array(data_points, "data_points", ndim=2, shape=(None, 3))
    theta = hand.check_theta(theta_init, "theta_init", within_limits=True)
    w = np.ones(len(data)) if weights is None else as_finite_array(weights, "weights", ndim=1, shape=(len(data),))
    if np.any(w < 0):
        raise ValueError("weights must be non-negative")
    if epsilon_mm is not None:
        epsilon_mm = check_positive(epsilon_mm, "epsilon_mm")
    limits = hand.joint_limits()
    for _ in range(n_steps):
        dist = hand.surface_distance(data, theta)
        sqrt_w = np.sqrt(w if epsilon_mm is None else w * (np.abs(dist) < epsilon_mm))
        jac = np.empty((len(data), hand.n_dof))
        for k in range(hand.n_dof):
            shifted = theta.copy()
            shifted[k] += fd_step
            jac[:, k] = (hand.surface_distance(data, shifted) - dist) / fd_step
        jac_w = sqrt_w[:, None] * jac
        normal = jac_w.T @ jac_w
        normal += damping * np.diag(np.diag(normal) + 1e-6)
        theta = np.clip(theta - np.linalg.solve(normal, jac_w.T @ (sqrt_w * dist)), limits[:, 0], limits[:, 1])
    dist = hand.surface_distance(data, theta)
    if epsilon_mm is not None:
        w = w * (np.abs(dist) < epsilon_mm)
    return SurfaceFitResult(theta, float(np.sqrt(np.sum(w * dist**2) / max(w.sum(), 1e-12))))


@dataclass(frozen=True)
class SoftAssignResult:
    """Result of :func:`softassign_register`: pose and per-data-point match mass (1 - slack)."""

    theta: np.ndarray
    inlier_prob: np.ndarray


def softassign_register(model_points: object, data_points: object, hand: HandModel, theta_init: object,
                        sigma_max: float = 20.0, sigma_min: float = 2.0, *, slack: float = 1e-2,
                        n_levels: int = 5, iterations_per_level: int = 3, sinkhorn_iterations: int = 30,
                        a: float = 2.0) -> SoftAssignResult:
    """SoftAssign (Gold, Rangarajan et al.) baseline of Sec. 4, Sinkhorn in the log domain.

    The (N+1)x(M+1) match matrix has a slack row and column initialised to ``slack``; rows and
    columns (except the slack ones) are alternately normalised to sum 1. Dense: O(N·M) memory.
    """
    model, data, theta, sigma_max, sigma_min = _check_common(hand, model_points, data_points,
                                                             theta_init, sigma_max, sigma_min)
    if model.shape[0] == 0 or data.shape[0] == 0:
        raise ValueError("model_points and data_points must be non-empty")
    slack = check_positive(slack, "slack")
    binding = hand.texture_binding(model, theta, a)
    n_model, n_data = len(model), len(data)
    inlier_prob = np.zeros(n_data)
    for sigma in np.geomspace(sigma_max, sigma_min, n_levels):
        for _ in range(iterations_per_level):
            moved = hand.transform_texture(binding, theta)
            sq = np.sum((moved[:, None, :] - data[None, :, :]) ** 2, axis=2)
            log_m = np.full((n_model + 1, n_data + 1), np.log(slack))
            log_m[:n_model, :n_data] = -sq / (2 * sigma**2)
            for _ in range(sinkhorn_iterations):
                log_m[:n_model] -= logsumexp(log_m[:n_model], axis=1, keepdims=True)
                log_m[:, :n_data] -= logsumexp(log_m[:, :n_data], axis=0, keepdims=True)
            match = np.exp(log_m[:n_model, :n_data])
            weights = match.sum(axis=1)
            targets = (match @ data) / np.maximum(weights, 1e-300)[:, None]
            theta = _m_step(hand, binding, theta, weights, targets, 2, 1e-3)
            inlier_prob = match.sum(axis=0)
    return SoftAssignResult(theta, inlier_prob)
