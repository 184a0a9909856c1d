"""The robust EM of Sec. 3.1-3.3: its settings, the M-step (eq. 20) and the annealed loop (eqs. 17-20)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from amdo_lab.common import MAX_ITERATIONS, MAX_LEVELS
from amdo_lab.common import as_finite_array, check_choice, check_in_range, check_instance, check_positive_int
from amdo_lab.common.threads import one_blas_thread

from amdo_lab.em_articulated.estep import (CHUNK, MAX_SIGMA_MM, PAPER_C, _posterior_matrix, _weighted_targets,
                                           dense_e_step)
from amdo_lab.em_articulated.hand import MAX_LENGTH_MM, HandModel, TextureBinding, check_hand, check_points
from amdo_lab.em_articulated.kdtree import DENSE_PAIR_FRACTION, KDTREE_RADIUS_SIGMAS, ClosePairs, statistics_from_pairs

__all__ = ["EMSettings", "PAPER_SETTINGS", "OUR_SETTINGS", "EMResult", "gauss_newton_step", "register_em",
           "register_em_reference", "check_registration_input", "check_em_settings", "m_step_pose", "run_em"]

#: The EM at one σ stops when no DOF moves by more than this (radians, or mm for the palm).
DEFAULT_TOL = 1e-3
#: Gauss-Newton steps of each M-step (it stops earlier when a step is below 1e-6).
GAUSS_NEWTON_STEPS = 2
#: Levenberg damping of the M-step's normal equations, relative to their diagonal.
M_STEP_DAMPING = 1e-3
#: Largest damping :func:`gauss_newton_step` accepts: a million times the diagonal already freezes
#: every step; larger factors overflow when they multiply the normal equations.
MAX_DAMPING = 1e6
#: Largest weight λ_i :func:`gauss_newton_step` accepts (λ_i are relative; larger ones overflow the normal equations).
MAX_WEIGHT = 1e6


@dataclass(frozen=True)
class EMSettings:
    """Settings of :func:`register_em`: the annealing schedule, the targets and the E-step.

    The defaults are the EM as the paper's Sec. 3 describes it with the exact, dense E-step;
    :data:`PAPER_SETTINGS` and :data:`OUR_SETTINGS` are the two named settings the chapter compares.
    Change one field with ``dataclasses.replace(OUR_SETTINGS, sigma_max=15.0)``.

    Parameters
    ----------
    sigma_max : float, default 20.0
        Largest σ of the annealing, mm, in (0, 1e6]: about the largest expected motion.
    sigma_min : float, default 3.0
        Smallest σ, mm, in (0, ``sigma_max``): about the noise.
    n_levels : int, default 5
        Number of geometric σ levels (≥ 1; the paper: about five), at most
        :data:`amdo_lab.common.MAX_LEVELS` (64).
    max_iter : int, default 10
        Most EM iterations at one σ level (≥ 1); a level ends earlier when Θ stops changing
        (no DOF moves by more than 1e-3). At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).
    targets : {"paper", "debiased"}, default "paper"
        "paper" (G_i of eq. 20) or "debiased" (ours): T(X_i) + G_i - B_i, where B_i is the
        same weighted mean computed with the moved texture itself as data. At large σ the G_i are
        blurred towards the middle of the hand, which curls fingers; B_i carries the same blur, so
        data that coincide with the model give zero force at every σ.
    e_step : {"dense", "kdtree"}, default "dense"
        "dense" (every pair, streamed in chunks) or "kdtree" (pairs within 4σ only,
        :func:`e_step_statistics_kdtree`). At a σ where the 4σ balls hold more than 15 % of all
        pairs, "kdtree" uses the dense E-step instead: there it is faster and not truncated.
    sigma_mode : {"anneal", "estimate"}, default "anneal"
        "anneal" (the paper) or "estimate" (σ re-estimated in the M-step from the weighted
        residuals, the variant the paper warns against).
    schedule : {"levels", "per-step"}, default "levels"
        "levels" (our reading of Sec. 3.3): at each σ level, E- and M-steps alternate until Θ
        stops changing. "per-step" (the paper's text read literally, σ_{q+1} = κσ_q at every
        iteration q): one iteration at each σ above ``sigma_min``, then iterations at ``sigma_min``
        until Θ stops changing (at most ``max_iter``).

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591; Sec. 3.3.
    """

    sigma_max: float = 20.0
    sigma_min: float = 3.0
    n_levels: int = 5
    max_iter: int = 10
    targets: str = "paper"
    e_step: str = "dense"
    sigma_mode: str = "anneal"
    schedule: str = "levels"

    def __post_init__(self) -> None:
        check_in_range(self.sigma_max, "sigma_max", 0.0, MAX_SIGMA_MM, closed="right")
        check_in_range(self.sigma_min, "sigma_min", 0.0, self.sigma_max)
        check_positive_int(self.n_levels, "n_levels", maximum=MAX_LEVELS)
        check_positive_int(self.max_iter, "max_iter", maximum=MAX_ITERATIONS)
        check_choice(self.targets, "targets", ("paper", "debiased"))
        check_choice(self.e_step, "e_step", ("dense", "kdtree"))
        check_choice(self.sigma_mode, "sigma_mode", ("anneal", "estimate"))
        check_choice(self.schedule, "schedule", ("levels", "per-step"))

    @property
    def sigmas(self) -> np.ndarray:
        """The annealing schedule of Sec. 3.3: ``n_levels`` σ from ``sigma_max`` down to ``sigma_min``, mm."""
        return np.geomspace(self.sigma_max, self.sigma_min, self.n_levels)


#: register_em as the paper describes it: the M-step targets G_i of eq. (20), every DOF free at
#: every σ, σ annealed geometrically in five levels from the largest motion to about the noise,
#: EM iterated at each level until Θ stops changing (k-d tree E-step: the same EM, faster).
PAPER_SETTINGS = EMSettings(e_step="kdtree")
#: Ours (see the chapter's ablation): the same EM with bias-corrected targets; the texture blurred
#: by the same E-step is subtracted, so a perfect fit is a fixed point at every σ.
OUR_SETTINGS = EMSettings(targets="debiased", e_step="kdtree")


@dataclass(frozen=True)
class EMResult:
    """Result of :func:`register_em`.

    Parameters
    ----------
    theta : numpy.ndarray, shape (27,)
        Estimated pose.
    inlier_prob : numpy.ndarray, shape (M,)
        Σ_i α_ij per data point at the last E-step, in [0, 1).
    history : numpy.ndarray, shape (n_iterations, 2)
        One row per EM iteration: [σ in mm, energy Σ_ij α_ij ||Y_j - T(X_i)||² in mm²].
    model_points : numpy.ndarray, shape (N, 3)
        The texture moved to ``theta``, mm.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591; eqs. (17)-(20).
    """

    theta: np.ndarray
    inlier_prob: np.ndarray
    history: np.ndarray
    model_points: np.ndarray


def check_em_settings(settings: object) -> EMSettings:
    """``settings`` itself (an :class:`EMSettings`, checked when it was built), or a ``TypeError``.

    Parameters
    ----------
    settings : EMSettings
        The value to check.

    Returns
    -------
    EMSettings
        ``settings``.
    """
    return check_instance(settings, "settings", EMSettings, what="an EMSettings (e.g. OUR_SETTINGS)")


def check_registration_input(model_points: object, data_points: object, hand: object,
                             theta_init: object) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The checked texture (N, 3), data (M, 3) and start pose of a registration.

    Parameters
    ----------
    model_points, data_points : array_like, shape (N, 3) and (M, 3)
        Texture points at ``theta_init`` and data points, mm, within ±1e6.
    hand : HandModel
        The articulated model.
    theta_init : array_like, shape (27,)
        Pose of the texture and start of the registration, inside the joint limits.

    Returns
    -------
    tuple of numpy.ndarray
        The texture, the data and the pose.
    """
    check_hand(hand)
    model = check_points(model_points, "model_points")
    data = check_points(data_points, "data_points")
    return model, data, hand.check_theta(theta_init, "theta_init", within_limits=True)


def gauss_newton_step(jacobian: object, residuals: object, weights: object, *,
                      damping: float = M_STEP_DAMPING) -> np.ndarray:
    """One Gauss-Newton step ΔΘ on E(Θ) = Σ_i λ_i ||G_i - T(X_i, Θ)||² (eq. 20), the M-step's core.

    Linearising T(X_i, Θ + ΔΘ) ≈ T(X_i, Θ) + J_i ΔΘ makes eq. (20) an ordinary least-squares problem
    in √λ_i (G_i - T(X_i, Θ) - J_i ΔΘ); its normal equations, with a little Levenberg damping on their
    diagonal for stability, give ΔΘ.

    Parameters
    ----------
    jacobian : array_like, shape (N, D, K)
        J_i = ∂T(X_i, Θ)/∂Θ per texture point, in D dimensions and K parameters; within ±1e6.
    residuals : array_like, shape (N, D)
        G_i - T(X_i, Θ), mm, within ±1e6.
    weights : array_like, shape (N,)
        λ_i, in [0, 1e6] (posterior sums: at most the number of data points).
    damping : float, default 1e-3
        Levenberg damping relative to the normal equations' diagonal, in [0, 1e6]; 0 is plain
        Gauss-Newton (then the weighted J must have full column rank).

    Returns
    -------
    numpy.ndarray, shape (K,)
        The step ΔΘ.

    Examples
    --------
    One parameter moving two points along x: the step is the weighted mean residual.

    >>> import numpy as np
    >>> jacobian = np.array([[[1.0], [0.0]], [[1.0], [0.0]]])
    >>> gauss_newton_step(jacobian, [[1.0, 0.0], [4.0, 0.0]], [2.0, 1.0], damping=0.0)
    array([2.])

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591; eq. (20).
    """
    jac = as_finite_array(jacobian, "jacobian", ndim=3, max_abs=MAX_LENGTH_MM)
    res = as_finite_array(residuals, "residuals", shape=jac.shape[:2], max_abs=MAX_LENGTH_MM)
    lam = as_finite_array(weights, "weights", shape=(len(jac),), bounds=(0.0, MAX_WEIGHT))
    damping = check_in_range(damping, "damping", 0.0, MAX_DAMPING, closed="both")
    return _gauss_newton_step(jac, res, lam, damping)


def _gauss_newton_step(jac: np.ndarray, residuals: np.ndarray, weights: np.ndarray, damping: float) -> np.ndarray:
    """:func:`gauss_newton_step` on checked arrays (the M-step's loop calls this one)."""
    sqrt_w = np.sqrt(weights)[:, None]  # √λ_i: eq. (20) as an ordinary least-squares problem
    residual = (sqrt_w * residuals).ravel()  # √λ_i (G_i - T(X_i, Θ))
    jac_w = (sqrt_w[:, :, None] * jac).reshape(-1, jac.shape[2])
    # Gauss-Newton normal equations (JᵀJ + damping) ΔΘ = Jᵀ r, a little Levenberg damping for stability
    normal = jac_w.T @ jac_w
    normal += damping * np.diag(np.diag(normal) + 1e-6)
    return np.linalg.solve(normal, jac_w.T @ residual)


def m_step_pose(hand: HandModel, binding: TextureBinding, theta: np.ndarray, weights: np.ndarray,
                targets: np.ndarray, n_steps: int = GAUSS_NEWTON_STEPS,
                start: tuple[np.ndarray, np.ndarray] | None = None) -> np.ndarray:
    """Minimise Σ_i λ_i ||G_i - T(X_i, Θ)||² (eq. 20) by Gauss-Newton steps projected on the joint limits.

    The M-step of :func:`register_em`, on checked input (not exported): each step is
    :func:`gauss_newton_step` on the texture points that carry weight, then clipped to the limits.

    Parameters
    ----------
    hand : HandModel
        The articulated model.
    binding : TextureBinding
        The texture, from :meth:`HandModel.texture_binding`.
    theta : numpy.ndarray, shape (27,)
        The pose the M-step starts from.
    weights, targets : numpy.ndarray, shape (N,) and (N, 3)
        λ_i and G_i of eq. (20).
    n_steps : int, default 2
        Most Gauss-Newton steps; the M-step stops earlier when a step is below 1e-6.
    start : tuple of numpy.ndarray, optional
        ``hand.texture_jacobian(binding, theta)`` when the caller has it already.

    Returns
    -------
    numpy.ndarray, shape (27,)
        The new pose.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, ECCV 2006, eq. (20).
    """
    limits = hand.joint_limits()
    active = weights > 1e-8
    if not np.any(active):
        return theta
    for step_index in range(n_steps):
        # T(X_i, Θ) and its derivative in each θ_k: ω_k × (T(X_i) - o_k) for a joint of axis ω_k
        # through o_k (blended over the two parts of eq. 3), a unit vector for a palm translation
        moved, jac = start if step_index == 0 and start is not None else hand._texture_jacobian(binding, theta)
        step = _gauss_newton_step(jac[active], targets[active] - moved[active], weights[active], M_STEP_DAMPING)
        theta = np.clip(theta + step, limits[:, 0], limits[:, 1])  # projected onto the joint limits
        if np.max(np.abs(step)) < 1e-6:
            break
    return theta


def register_em(model_points: object, data_points: object, hand: HandModel, theta_init: object, *,
                settings: EMSettings = OUR_SETTINGS) -> EMResult:
    """Robust EM alignment of texture points X_i (at ``theta_init``) to data Y_j (Sec. 3).

    At each of the σ levels of ``settings`` (Sec. 3.3), E-step (eq. 17) and M-step (eq. 20)
    alternate until no DOF moves by more than 1e-3 or ``settings.max_iter`` iterations have run.

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
    settings : EMSettings, default OUR_SETTINGS
        The schedule, targets and E-step (:data:`PAPER_SETTINGS` for the paper's EM).

    Returns
    -------
    EMResult
        Pose, inlier probabilities, history and moved texture.

    Examples
    --------
    A synthetic problem started 10° off at every joint, registered with our settings:

    >>> from amdo_lab.em_articulated import HandModel, joint_rmse_deg, make_registration_problem
    >>> hand = HandModel()
    >>> problem = make_registration_problem(hand, rng=1, joint_error_deg=10.0, noise_mm=1.0,
    ...                                     n_model=300, n_data=300)
    >>> result = register_em(problem.model_points, problem.data_points, hand, problem.theta_init)
    >>> round(joint_rmse_deg(problem.theta_init, problem.theta_true), 1)
    10.0
    >>> round(joint_rmse_deg(result.theta, problem.theta_true), 1)
    2.8

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591; Sec. 3.1-3.3, eqs. (17)-(20).
    """
    model, data, theta = check_registration_input(model_points, data_points, hand, theta_init)
    settings = check_em_settings(settings)
    binding = hand.texture_binding(model, theta)
    theta, inlier_prob, history = run_em(hand, binding, data, theta, settings, settings.sigmas)
    return EMResult(theta, inlier_prob, history, hand.transform_texture(binding, theta))


def register_em_reference(model_points: object, data_points: object, hand: HandModel, theta_init: object, *,
                          settings: EMSettings = OUR_SETTINGS) -> np.ndarray:
    """The annealed EM of Sec. 3.1-3.3 written out plainly: the readable path of :func:`register_em`.

    Dense α matrices (:func:`e_step_reference`), so memory is O(N·M): for reading and for the tests,
    which check that :func:`register_em` (with ``e_step="dense"``) reaches the same pose. It follows
    ``settings``' σ levels, iterations and targets; σ is annealed by levels (``sigma_mode="anneal"``,
    ``schedule="levels"``), and every pair is kept whatever ``settings.e_step``.

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
    settings : EMSettings, default OUR_SETTINGS
        The schedule and targets, as for :func:`register_em`.

    Returns
    -------
    theta : numpy.ndarray, shape (27,)
        The estimated pose.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, ECCV 2006, Sec. 3.3 and eqs. (17), (19), (20).
    """
    model, data, theta = check_registration_input(model_points, data_points, hand, theta_init)
    settings = check_em_settings(settings)
    binding = hand.texture_binding(model, theta)  # eq. (3): the texture's blend weights, fixed at Θ_init
    with one_blas_thread():
        # Sec. 3.3: σ falls geometrically from the largest motion σ_max to the noise level σ_min
        for sigma in settings.sigmas:
            for _ in range(settings.max_iter):
                moved = hand._transform_texture(binding, theta)  # T(X_i, Θ^q)
                alpha = _posterior_matrix(moved, data, sigma, PAPER_C)  # E-step, eq. (17)
                lam, goal = _weighted_targets(alpha, data)  # λ_i, G_i of eq. (20)
                if settings.targets == "debiased":  # ours: subtract the texture's own blur B_i
                    _, blurred = _weighted_targets(_posterior_matrix(moved, moved, sigma, PAPER_C), moved)
                    goal = moved + goal - blurred
                # M-step: maximising Q of eq. (19) is, up to terms free of Θ, minimising
                # E(Θ) = Σ_i λ_i ||T(X_i, Θ) - G_i||² (eq. 20), here by Gauss-Newton
                new_theta = m_step_pose(hand, binding, theta, lam, goal)
                change, theta = float(np.max(np.abs(new_theta - theta))), new_theta
                if change <= DEFAULT_TOL:  # the paper's stopping rule: Θ no longer changes
                    break
    return theta


def run_em(hand: HandModel, binding: TextureBinding, data: np.ndarray, theta: np.ndarray, settings: EMSettings,
           sigmas: np.ndarray, tol: float = DEFAULT_TOL) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The EM of :func:`register_em` from pose ``theta`` through the σ levels ``sigmas``, on checked input.

    The loop that :func:`register_em`, :func:`refine_digits` (the EM's last levels from new starts)
    and :func:`climb_objective` (one fixed σ) share (not exported).

    Parameters
    ----------
    hand : HandModel
        The articulated model.
    binding : TextureBinding
        The texture, bound at the pose where it was observed.
    data : numpy.ndarray, shape (M, 3)
        The data, mm.
    theta : numpy.ndarray, shape (27,)
        The start pose.
    settings : EMSettings
        Iterations per level, targets, E-step, σ mode and schedule (its σ range is ``sigmas``').
    sigmas : numpy.ndarray
        The σ levels, largest first, mm.
    tol : float, default 1e-3
        A level ends when no DOF moves by more than this in one iteration.

    Returns
    -------
    tuple of numpy.ndarray
        The pose, the inlier probabilities Σ_i α_ij of the last E-step, and the history rows
        [σ, energy] of :class:`EMResult`.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, ECCV 2006, Sec. 3.3, eqs. (17)-(20).
    """
    kdtree = settings.e_step == "kdtree"
    data_pairs, self_pairs = (ClosePairs(data), ClosePairs(None)) if kdtree else (None, None)
    log_c = float(np.log(PAPER_C))

    def statistics(points: np.ndarray, observed: np.ndarray, sigma: float, pairs: ClosePairs | None) -> tuple:
        radius = KDTREE_RADIUS_SIGMAS * sigma
        if kdtree and pairs.pair_fraction(points, radius) <= DENSE_PAIR_FRACTION:
            # truncated at 4σ, as e_step_statistics_kdtree
            return statistics_from_pairs(*pairs(points, radius), observed, len(points), sigma, log_c)
        return dense_e_step(points, observed, sigma, log_c, CHUNK, "single")[:4]

    history = []
    sigma = sigmas[0]
    inlier_prob = np.zeros(data.shape[0])
    with one_blas_thread():  # small dense algebra: BLAS threads only contend
        for level, level_sigma in enumerate(sigmas):
            # per-step schedule: σ falls after every iteration until it reaches the last level
            last_level = level == len(sigmas) - 1
            n_iterations = 1 if settings.schedule == "per-step" and not last_level else settings.max_iter
            for _ in range(n_iterations):
                if settings.sigma_mode == "anneal":
                    sigma = level_sigma
                moved, jac = hand._texture_jacobian(binding, theta)  # the M-step's first linearisation too
                weights, weighted, inlier_prob, energy = statistics(moved, data, sigma, data_pairs)
                history.append((sigma, energy))
                goal = weighted / np.maximum(weights, 1e-300)[:, None]  # G_i of eq. (20)
                if settings.targets == "debiased":  # ours: subtract the texture's own blur B_i
                    self_weights, self_weighted, _, _ = statistics(moved, moved, sigma, self_pairs)
                    goal = moved + goal - self_weighted / np.maximum(self_weights, 1e-300)[:, None]
                new_theta = m_step_pose(hand, binding, theta, weights, goal, start=(moved, jac))
                change = float(np.max(np.abs(new_theta - theta)))
                theta = new_theta
                if settings.sigma_mode == "estimate":  # σ² from the weighted residuals at the new pose
                    moved = hand._transform_texture(binding, theta)
                    new_energy = statistics(moved, data, sigma, data_pairs)[3]
                    sigma = max(np.sqrt(new_energy / max(3 * weights.sum(), 1e-12)), 1e-3)
                if change <= tol:
                    break
    return theta, inlier_prob, np.array(history)
