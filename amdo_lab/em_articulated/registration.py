"""Robust EM registration (Sec. 3.1-3.3, eqs. 17-20), surface fitting (Sec. 3.4) and SoftAssign (Sec. 4)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree
from scipy.special import logsumexp

from amdo_lab.common import MAX_ITERATIONS, MAX_LEVELS, MAX_SAMPLES
from amdo_lab.common import as_finite_array, check_choice, check_in_range, check_positive, check_positive_int
from amdo_lab.common.threads import one_blas_thread

from amdo_lab.em_articulated.hand import (DIGIT_DOFS, FINGERS, MAX_LENGTH_MM, SIDEWAYS_DOFS, HandModel, TextureBinding,
                                          check_binding, check_hand)

__all__ = ["EMResult", "register_em", "e_step_statistics_kdtree", "dof_lever_arms", "PAPER_SETTINGS",
           "OUR_SETTINGS", "fit_surface", "softassign_register", "PAPER_C", "e_step_statistics",
           "SurfaceFitResult", "SoftAssignResult", "fit_known_correspondences", "refine_digits",
           "DigitSearchResult", "e_step_reference", "m_step_targets", "robust_log_likelihood",
           "register_em_reference", "climb_objective"]

#: Outlier constant of eq. (18) with n v << V.
PAPER_C = 3.0 * np.sqrt(np.pi / 2.0)

#: register_em as the paper describes it: the M-step targets G_i of eq. (20), every DOF free at
#: every σ, σ annealed geometrically in five levels from the largest motion to about the noise,
#: EM iterated at each level until Θ stops changing.
PAPER_SETTINGS = {"sigma_max": 20.0, "sigma_min": 3.0, "n_levels": 5, "max_iter": 10,
                  "targets": "paper", "e_step": "kdtree"}
#: Ours (see the chapter's ablation): the same EM with bias-corrected targets; the texture blurred
#: by the same E-step is subtracted, so a perfect fit is a fixed point at every σ.
OUR_SETTINGS = {**PAPER_SETTINGS, "targets": "debiased"}

#: Truncation radius of the k-d tree E-step, in σ.
_KDTREE_RADIUS_SIGMAS = 4.0
#: register_em(e_step="kdtree") switches to the exact dense E-step when more than this share of all
#: pairs lies within the truncation radius: a pair costs several times more on the sparse path than in
#: the dense one's matrix products (crossover about 0.13-0.2 in `benchmarks/bench_01_em_articulated.py`).
DENSE_PAIR_FRACTION = 0.15

#: The EM at one σ stops when no DOF moves by more than this (radians, or mm for the palm).
DEFAULT_TOL = 1e-3

#: Largest σ accepted, mm (σ² and the energies overflow long before 1e308).
MAX_SIGMA_MM = MAX_LENGTH_MM
#: Largest relative damping (and release ratio) accepted: a million times the diagonal already freezes
#: every step; larger factors overflow when they multiply the normal equations.
MAX_DAMPING = 1e6
#: Largest log of the outlier constant c of eq. (17) the E-step accepts: exp(700) is about 1e304, the
#: largest power of e that stays finite with room for the sums over the data around it.
MAX_LOG_C = 700.0
#: Largest per-point weight :func:`fit_surface` accepts (weights are relative: a weight of 1e308 would
#: overflow the weighted normal equations).
MAX_WEIGHT = 1e6


def check_settings(value: object, name: str) -> dict:
    """A copy of ``value`` (a dict of keyword arguments, or None for none), or a ``TypeError`` naming ``name``."""
    if value is not None and not isinstance(value, dict):
        raise TypeError(f"{name} must be a dict of keyword arguments or None, got {type(value).__name__}")
    return dict(value or {})


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


def _check_e_step_inputs(model_points: object, data_points: object, sigma: object,
                         log_c: object) -> tuple[np.ndarray, np.ndarray, float, float]:
    """Validate the arguments shared by the public E-step functions."""
    model = as_finite_array(model_points, "model_points", ndim=2, shape=(None, 3), max_abs=MAX_LENGTH_MM)
    data = as_finite_array(data_points, "data_points", ndim=2, shape=(None, 3), max_abs=MAX_LENGTH_MM)
    sigma = check_in_range(sigma, "sigma", 0.0, MAX_SIGMA_MM, closed="right")
    if not isinstance(log_c, (int, float, np.integer, np.floating)) or isinstance(log_c, (bool, np.bool_)):
        raise TypeError(f"log_c must be a real number, got {type(log_c).__name__}")
    if np.isnan(log_c) or log_c > MAX_LOG_C:  # -inf is allowed: no outlier class (c = 0)
        raise ValueError(f"log_c must be at most {MAX_LOG_C:g} or -inf (c = 0), got {log_c}")
    return model, data, sigma, float(log_c)


def e_step_reference(model_points: object, data_points: object, sigma: float, c: float = PAPER_C) -> np.ndarray:
    """Posterior α_ij that data point Y_j copies texture point T(X_i) (eq. 17), as a full matrix.

    The readable path: every pair at once in plain numpy, memory O(N·M). The EM itself uses the
    streamed, log-domain :func:`e_step_statistics` (and its k-d tree variant), which return sums of
    these α and are tested equal to them.

    Parameters
    ----------
    model_points : array_like, shape (N, 3)
        Moved texture points T(X_i, Θ), mm, within ±1e6.
    data_points : array_like, shape (M, 3)
        Data points Y_j, mm, within ±1e6.
    sigma : float
        σ of the Gaussian of eq. (6), mm, in (0, 1e6].
    c : float, default PAPER_C
        The outlier constant of eq. (18) (> 0); 3√(π/2) by default.

    Returns
    -------
    alpha : numpy.ndarray, shape (N, M)
        Posteriors α_ij; column j sums to the inlier probability of Y_j, below 1.

    Examples
    --------
    One data point next to the first texture point, one far from both: the far one goes to the
    outlier class (its column sums to 0), the near one is shared with it through c.

    >>> import numpy as np
    >>> model = np.array([[0.0, 0.0, 0.0], [10.0, 0.0, 0.0]])
    >>> data = np.array([[0.5, 0.0, 0.0], [100.0, 0.0, 0.0]])
    >>> e_step_reference(model, data, sigma=2.0).round(3)
    array([[0.205, 0.   ],
           [0.   , 0.   ]])

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, ECCV 2006, eqs. (17)-(18).
    """
    model, data, sigma, _ = _check_e_step_inputs(model_points, data_points, sigma, 0.0)
    c = check_positive(c, "c")
    # ||Y_j - T(X_i)||² for every pair (i, j)
    sq_dist = np.sum((model[:, None, :] - data[None, :, :]) ** 2, axis=2)
    # numerator of eq. (17): the Gaussian of eq. (6) without its normalisation (it cancels into c)
    kernel = np.exp(-sq_dist / (2.0 * sigma**2))
    # denominator of eq. (17): Σ_k over the texture points, plus c for the outlier class (eq. 18)
    return kernel / (kernel.sum(axis=0, keepdims=True) + c)


def m_step_targets(alpha: object, data_points: object) -> tuple[np.ndarray, np.ndarray]:
    """Weights λ_i and targets G_i of eq. (20) from the posteriors α_ij of eq. (17).

    λ_i = Σ_j α_ij, G_i = Σ_j α_ij Y_j / λ_i. A texture point with λ_i = 0 gets G_i = 0 (it has no
    weight in eq. 20, so its target is never used).

    Parameters
    ----------
    alpha : array_like, shape (N, M)
        Posteriors α_ij in [0, 1], e.g. :func:`e_step_reference`.
    data_points : array_like, shape (M, 3)
        Data points Y_j, mm, within ±1e6.

    Returns
    -------
    lam : numpy.ndarray, shape (N,)
        Weights λ_i.
    targets : numpy.ndarray, shape (N, 3)
        Centres of gravity G_i, mm.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, ECCV 2006, eq. (20).
    """
    data = as_finite_array(data_points, "data_points", ndim=2, shape=(None, 3), max_abs=MAX_LENGTH_MM)
    alpha = as_finite_array(alpha, "alpha", ndim=2, shape=(None, len(data)))
    if np.any((alpha < 0) | (alpha > 1)):
        raise ValueError("alpha must hold posteriors in [0, 1], got values outside")
    lam = alpha.sum(axis=1)  # eq. (20): λ_i = Σ_j α_ij
    targets = (alpha @ data) / np.maximum(lam, 1e-300)[:, None]  # eq. (20): G_i = Σ_j α_ij Y_j / λ_i
    return lam, targets


def robust_log_likelihood(model_points: object, data_points: object, sigma: float, c: float = PAPER_C) -> float:
    """The objective the EM climbs at one σ: Σ_j log(c + Σ_i exp(-||Y_j - T(X_i)||²/2σ²)).

    Up to a constant that depends on σ only, this is the log-likelihood of the data under the
    mixture of eq. (9) (the Gaussian's normalisation and the priors v/V factor out into c, eq. 18),
    so values at the same σ and c compare poses. Computed by the streamed pass of
    :func:`e_step_statistics` in double precision (log domain: no underflow far from the hand).

    Parameters
    ----------
    model_points : array_like, shape (N, 3)
        Moved texture points T(X_i, Θ), mm, within ±1e6.
    data_points : array_like, shape (M, 3)
        Data points Y_j, mm, within ±1e6.
    sigma : float
        σ, mm, in (0, 1e6].
    c : float, default PAPER_C
        The outlier constant of eq. (18) (> 0).

    Returns
    -------
    float
        The objective, nats; finite for finite input (c > 0 bounds each term below by log c).

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, ECCV 2006, eqs. (9), (17)-(18).
    """
    model, data, sigma, _ = _check_e_step_inputs(model_points, data_points, sigma, 0.0)
    log_c = float(np.log(check_positive(c, "c")))
    with one_blas_thread():
        return _dense_pass(model, data, sigma, log_c, 256, "double")[4]


def robust_log_likelihood_reference(model_points: object, data_points: object, sigma: float,
                                    c: float = PAPER_C) -> float:
    """The objective of :func:`robust_log_likelihood` in plain numpy, every pair at once.

    The readable path of the streamed, log-domain :func:`robust_log_likelihood` (tested equal to
    it); memory O(N·M), and the plain exponentials underflow for data far from every texture point
    (each term then falls back to log c, as the streamed path's does).

    Parameters
    ----------
    model_points : array_like, shape (N, 3)
        Moved texture points T(X_i, Θ), mm.
    data_points : array_like, shape (M, 3)
        Data points Y_j, mm.
    sigma : float
        σ of the Gaussian of eq. (6), mm, in (0, 1e6].
    c : float, default PAPER_C
        The outlier constant of eq. (18) (> 0).

    Returns
    -------
    float
        Σ_j log(c + Σ_i exp(-||Y_j - T(X_i)||²/2σ²)), nats.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, ECCV 2006, eqs. (9) and (18).
    """
    model, data, sigma, _ = _check_e_step_inputs(model_points, data_points, sigma, 0.0)
    c = check_positive(c, "c")
    sq_dist = np.sum((model[:, None, :] - data[None, :, :]) ** 2, axis=2)
    # eq. (8), the mixture f_j = Σ_i Π_i f(Y_j|X_i) + Π_outlier f(Y_j|outlier), written out as eq. (9) and
    # divided by Π_i (2πσ²)^(-3/2) (eq. 18): f_j ∝ Σ_i exp(-||Y_j - T(X_i)||²/2σ²) + c
    mixture = np.exp(-sq_dist / (2.0 * sigma**2)).sum(axis=0) + c
    return float(np.sum(np.log(mixture)))  # the log-likelihood of the data, Σ_j log f_j, up to a constant


def e_step_statistics(model_points: object, data_points: object, sigma: float,
                      log_c: float, chunk: int = 256,
                      precision: str = "single") -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Stream eq. (17) over data chunks in the log domain; memory O(M + N + chunk·N).

    Every output is a sum over pairs, so α itself is never normalised and stored. Per chunk, one
    product of augmented, centred coordinates gives the log kernels −||Y_j − X_i||²/2σ² (double
    precision); the largest term of each normaliser (c included) is factored out before
    exponentiating, so nothing overflows and a point far from every texture point gets α ≈ 0, never
    0/0; one more product, with the data rows divided by their normalisers, gives Σ_j α_ij Y_j and
    Σ_j α_ij together.

    ``precision="single"`` exponentiates and sums the shifted kernels in float32, which is about
    twice as fast on CPUs without vectorised double-precision exp. Each α then carries a relative
    error of about 1e-7 (α below about 1e-38 becomes 0), far below anything the EM can resolve at
    millimetre noise; ``"double"`` keeps every step in float64 (a reference for the tests).

    Parameters
    ----------
    model_points : array_like, shape (N, 3)
        Moved texture points T(X_i, Θ), mm, within ±1e6.
    data_points : array_like, shape (M, 3)
        Data points Y_j, mm, within ±1e6.
    sigma : float
        σ of the Gaussian of eq. (6), mm, in (0, 1e6].
    log_c : float
        log of the outlier constant c of eq. (17), at most :data:`MAX_LOG_C` (exp of more
        overflows); -inf for no outlier class.
    chunk : int, default 256
        Data points per streamed block (≥ 1). At most :data:`amdo_lab.common.MAX_SAMPLES` (1,000,000).
    precision : {"single", "double"}, default "single"
        Precision of the exponentials and their sums.

    Returns
    -------
    weights : numpy.ndarray, shape (N,)
        λ_i = Σ_j α_ij per model point.
    weighted_data : numpy.ndarray, shape (N, 3)
        Σ_j α_ij Y_j, mm.
    inlier_prob : numpy.ndarray, shape (M,)
        Σ_i α_ij per data point, in [0, 1).
    energy : float
        Σ_ij α_ij ||Y_j - T(X_i)||², mm² (eq. 19/20 up to the 1/2σ² factor).

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591; eqs. (17)-(20).
    """
    model_points, data_points, sigma, log_c = _check_e_step_inputs(model_points, data_points, sigma, log_c)
    chunk = check_positive_int(chunk, "chunk", maximum=MAX_SAMPLES)
    check_choice(precision, "precision", ("single", "double"))
    return _dense_statistics(model_points, data_points, sigma, log_c, chunk, precision)


def _dense_statistics(model_points: np.ndarray, data_points: np.ndarray, sigma: float, log_c: float,
                      chunk: int, precision: str) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """:func:`e_step_statistics` on validated (N, 3) and (M, 3) arrays (the EM loop's inner call)."""
    return _dense_pass(model_points, data_points, sigma, log_c, chunk, precision)[:4]


def _dense_pass(model_points: np.ndarray, data_points: np.ndarray, sigma: float, log_c: float, chunk: int,
                precision: str) -> tuple[np.ndarray, np.ndarray, np.ndarray, float, float]:
    """:func:`_dense_statistics` plus the data's log-likelihood under eq. (17)'s mixture,
    Σ_j log(c + Σ_i exp(-||Y_j - X_i||²/2σ²)): Σ_j (top_j + log normaliser_j), from the same pass."""
    dtype = np.float32 if precision == "single" else np.float64
    n_model, n_data = model_points.shape[0], data_points.shape[0]
    centre = data_points.mean(axis=0)  # centred coordinates keep the expanded squared distance accurate
    model_centred, data_centred = model_points - centre, data_points - centre
    inv_var = 1.0 / sigma**2
    # log kernel_ji = [Y_j, ||Y_j||², 1] · [X_i/σ², −1/2σ², −||X_i||²/2σ²]
    model_aug = np.empty((n_model, 5))
    model_aug[:, :3] = model_centred * inv_var
    model_aug[:, 3] = -0.5 * inv_var
    model_aug[:, 4] = -0.5 * inv_var * np.einsum("ij,ij->i", model_centred, model_centred)
    data_aug = np.empty((n_data, 5))
    data_aug[:, :3] = data_centred
    data_aug[:, 3] = np.einsum("ij,ij->i", data_centred, data_centred)
    data_aug[:, 4] = 1.0
    data_one = data_aug[:, [0, 1, 2, 4]].astype(dtype)  # [Y_j − centre, 1]
    shifted = np.empty((min(chunk, n_data), n_model), dtype)
    kernel = np.empty_like(shifted)
    sums = np.zeros((n_model, 4))
    inlier_prob = np.empty(n_data)
    weighted_log_kernel = 0.0  # Σ_ij α_ij log kernel_ji
    log_likelihood = 0.0
    for start in range(0, n_data, chunk):
        rows = slice(start, start + chunk)
        log_kernel = data_aug[rows] @ model_aug.T  # (rows, N)
        top = np.maximum(log_kernel.max(axis=1), log_c)
        block_shifted, block_kernel = shifted[:len(log_kernel)], kernel[:len(log_kernel)]
        np.subtract(log_kernel, top[:, None], out=block_shifted, casting="same_kind")
        np.exp(block_shifted, out=block_kernel)
        row_sum = block_kernel.sum(axis=1, dtype=np.float64)
        normaliser = row_sum + np.exp(log_c - top)  # ≥ 1: the largest term is exp(0)
        inlier_prob[rows] = row_sum / normaliser
        log_likelihood += float(np.sum(top + np.log(normaliser)))
        sums += block_kernel.T @ (data_one[rows] / normaliser[:, None].astype(dtype))
        shifted_sums = np.einsum("ji,ji->j", block_kernel, block_shifted, dtype=np.float64)
        weighted_log_kernel += float(np.sum(shifted_sums / normaliser) + top @ inlier_prob[rows])
    weights = sums[:, 3]
    weighted_data = sums[:, :3] + weights[:, None] * centre
    energy = max(-2 * sigma**2 * weighted_log_kernel, 0.0)  # a sum of squares: no round-off below 0
    return weights, weighted_data, inlier_prob, energy, log_likelihood


def dof_lever_arms(hand: HandModel, binding: TextureBinding, theta: np.ndarray) -> np.ndarray:
    """Largest distance (mm) a unit rotation of each DOF moves a texture point.

    Palm translations get +inf (always resolvable). A DOF whose lever arm is short moves points
    by much less than σ while σ is large, so its estimate there is dominated by the blur of the
    targets G_i (eq. 20) rather than by the data.

    Parameters
    ----------
    hand : HandModel
        The articulated model.
    binding : TextureBinding
        The texture, from :meth:`HandModel.texture_binding`.
    theta : array_like, shape (27,)
        Pose at which the lever arms are measured.

    Returns
    -------
    numpy.ndarray, shape (27,)
        Lever arm per DOF, mm per radian (+inf for DOFs 0-2).

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591; eq. (20) (our coarse-to-fine release, not in the paper).
    """
    check_hand(hand)
    check_binding(binding)
    _, jac = hand.texture_jacobian(binding, hand.check_theta(theta, "theta"))
    lever = np.max(np.linalg.norm(jac, axis=1), axis=0)
    lever[:3] = np.inf
    return lever


def e_step_statistics_kdtree(model_points: object, data_points: object, sigma: float,
                             log_c: float,
                             radius_sigmas: float = _KDTREE_RADIUS_SIGMAS) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Truncated eq. (17): only pairs closer than ``radius_sigmas``·σ, found with a k-d tree.

    Same outputs as :func:`e_step_statistics`. A pair at 4σ has kernel exp(-8) ≈ 3e-4, so the
    dropped mass is negligible next to c; memory is O(M + N + number of close pairs). The kernel
    of a kept pair is at least exp(-radius²/2), so the linear domain cannot underflow here.
    (:func:`register_em` gets the same pairs from a cache that re-measures candidates between
    iterations instead of querying anew.)

    Parameters
    ----------
    model_points : array_like, shape (N, 3)
        Moved texture points T(X_i, Θ), mm, within ±1e6.
    data_points : array_like, shape (M, 3)
        Data points Y_j, mm, within ±1e6.
    sigma : float
        σ of the Gaussian of eq. (6), mm, in (0, 1e6].
    log_c : float
        log of the outlier constant c of eq. (17), at most :data:`MAX_LOG_C` (exp of more
        overflows); -inf for no outlier class.
    radius_sigmas : float, default 4.0
        Truncation radius, in σ (> 0).

    Returns
    -------
    weights : numpy.ndarray, shape (N,)
        λ_i = Σ_j α_ij per model point.
    weighted_data : numpy.ndarray, shape (N, 3)
        Σ_j α_ij Y_j, mm.
    inlier_prob : numpy.ndarray, shape (M,)
        Σ_i α_ij per data point, in [0, 1).
    energy : float
        Σ_ij α_ij ||Y_j - T(X_i)||², mm² (eq. 19/20 up to the 1/2σ² factor).

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591; eq. (17), truncated (ours).
    """
    model_points, data_points, sigma, log_c = _check_e_step_inputs(model_points, data_points, sigma, log_c)
    radius = check_positive(radius_sigmas, "radius_sigmas") * sigma
    pairs = cKDTree(data_points).sparse_distance_matrix(cKDTree(model_points), radius, output_type="ndarray")
    return _statistics_from_pairs(*_pair_arrays(pairs), data_points, len(model_points), sigma, log_c)


def _pair_arrays(pairs: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The fields of ``cKDTree.sparse_distance_matrix(..., output_type="ndarray")`` as contiguous arrays
    (the structured array's strided fields make every later gather several times slower)."""
    return tuple(np.ascontiguousarray(pairs[field]) for field in ("i", "j", "v"))


def _statistics_from_pairs(data_index: np.ndarray, model_index: np.ndarray, dist: np.ndarray, data_points: np.ndarray,
                           n_model: int, sigma: float, log_c: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Eq. (17) on the listed (data, model) pairs only; the outputs of :func:`e_step_statistics`."""
    kernel = np.exp(-dist**2 / (2 * sigma**2))
    row_sum = np.bincount(data_index, kernel, minlength=len(data_points)) + np.exp(log_c)
    alpha = kernel / np.take(row_sum, data_index)
    weights = np.bincount(model_index, alpha, minlength=n_model)
    weighted_data = np.stack([np.bincount(model_index, alpha * np.take(column, data_index), minlength=n_model)
                              for column in data_points.T], axis=1)
    inlier_prob = np.bincount(data_index, alpha, minlength=len(data_points))
    return weights, weighted_data, inlier_prob, float(np.dot(alpha, dist**2))


class ClosePairs:
    """The (data, model) pairs closer than a radius, for a model that moves a little per EM iteration.

    A k-d tree query returns every pair within radius + margin, with the model where it is now;
    later calls only re-measure those candidates, and query again when the radius changes or some
    model point has moved so far that a pair from outside the candidates could have come within
    the radius (more than the margin; half of it when the data are the model itself, whose
    unordered pairs are stored once and mirrored). The pairs returned are exactly those a fresh
    query would give: this saves time, not accuracy. A cache for :func:`register_em`'s k-d tree
    E-step, on checked input (not exported).

    Parameters
    ----------
    data_points : numpy.ndarray, shape (M, 3), or None
        The data Y_j, mm; None when the data are the model points themselves.
    margin_ratio : float, default 0.1
        Margin of the candidate query, as a share of the radius.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591; eq. (17), truncated (ours).
    """

    def __init__(self, data_points: np.ndarray | None, margin_ratio: float = 0.1) -> None:
        self._data, self._margin_ratio = data_points, margin_ratio
        self._tree = None if data_points is None else cKDTree(data_points)
        self._radius = self._fraction_radius = -1.0
        self._anchor = self._data_index = self._model_index = None
        self._fraction = 0.0

    def pair_fraction(self, model_points: np.ndarray, radius: float, n_samples: int = 64) -> float:
        """Share of all (data, model) pairs closer than ``radius``, estimated from about ``n_samples``
        model points spread through the array; re-estimated only when the radius changes.

        Parameters
        ----------
        model_points : numpy.ndarray, shape (N, 3)
            Moved texture points, mm.
        radius : float
            Pair distance, mm.
        n_samples : int, default 64
            About how many model points the estimate queries.

        Returns
        -------
        float
            The share, in [0, 1].
        """
        if radius != self._fraction_radius:
            sample = model_points[::max(1, len(model_points) // n_samples)]
            tree, n_data = ((cKDTree(model_points), len(model_points)) if self._data is None
                            else (self._tree, len(self._data)))
            self._fraction = float(np.mean(tree.query_ball_point(sample, radius, return_length=True))) / n_data
            self._fraction_radius = radius
        return self._fraction

    def __call__(self, model_points: np.ndarray, radius: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        margin = self._margin_ratio * radius
        allowed = margin / 2 if self._data is None else margin  # a self pair closes in from both ends
        fresh = None
        if (radius != self._radius
                or np.max(np.sum((model_points - self._anchor) ** 2, axis=1)) > allowed**2):
            if self._data is None:  # each unordered pair i < j once
                unique = cKDTree(model_points).query_pairs(radius + margin, output_type="ndarray")
                self._data_index, self._model_index = unique[:, 0].copy(), unique[:, 1].copy()
            else:  # the query measures the distances already: no need to measure them again now
                self._data_index, self._model_index, fresh = _pair_arrays(
                    self._tree.sparse_distance_matrix(cKDTree(model_points), radius + margin, output_type="ndarray"))
            self._radius, self._anchor = radius, model_points.copy()
        data = model_points if self._data is None else self._data
        if fresh is None:
            offset = np.take(data, self._data_index, axis=0) - np.take(model_points, self._model_index, axis=0)
            fresh = np.sqrt(np.einsum("ij,ij->i", offset, offset))
        keep = fresh <= radius
        data_index, model_index, dist = self._data_index[keep], self._model_index[keep], fresh[keep]
        if self._data is None:  # both orders of every unordered pair, and every point with itself
            own = np.arange(len(model_points))
            return (np.concatenate([data_index, model_index, own]), np.concatenate([model_index, data_index, own]),
                    np.concatenate([dist, dist, np.zeros(len(own))]))
        return data_index, model_index, dist


def _m_step(hand: HandModel, binding: TextureBinding, theta: np.ndarray, weights: np.ndarray,
            targets: np.ndarray, n_steps: int, damping: float, free: np.ndarray | None = None,
            start: tuple[np.ndarray, np.ndarray] | None = None) -> np.ndarray:
    """Minimise Σ_i w_i ||G_i - T(X_i, Θ)||² (eq. 20) by projected Gauss-Newton over the ``free`` DOFs.

    ``start`` is ``hand.texture_jacobian(binding, theta)`` when the caller has it already.
    """
    limits = hand.joint_limits()
    active = weights > 1e-8
    free = np.ones(hand.n_dof, bool) if free is None else free
    if not np.any(active):
        return theta
    sqrt_w = np.sqrt(weights[active])[:, None]  # √λ_i: eq. (20) as an ordinary least-squares problem
    for step_index in range(n_steps):
        # T(X_i, Θ) and its derivative in each θ_k: ω_k × (T(X_i) - o_k) for a joint of axis ω_k
        # through o_k (blended over the two parts of eq. 3), a unit vector for a palm translation
        moved, jac = start if step_index == 0 and start is not None else hand.texture_jacobian(binding, theta)
        residual = (sqrt_w * (targets[active] - moved[active])).ravel()  # √λ_i (G_i - T(X_i, Θ))
        jac_w = (sqrt_w[:, :, None] * jac[active][:, :, free]).reshape(-1, int(free.sum()))
        # Gauss-Newton normal equations (JᵀJ + damping) ΔΘ = Jᵀ r, a little Levenberg damping for stability
        normal = jac_w.T @ jac_w
        normal += damping * np.diag(np.diag(normal) + 1e-6)
        step = np.zeros(hand.n_dof)
        step[free] = np.linalg.solve(normal, jac_w.T @ residual)
        theta = np.clip(theta + step, limits[:, 0], limits[:, 1])  # projected onto the joint limits
        if np.max(np.abs(step)) < 1e-6:
            break
    return theta


def _check_common(hand: HandModel, model_points: object, data_points: object, theta_init: object,
                  sigma_max: object, sigma_min: object) -> tuple[np.ndarray, np.ndarray, np.ndarray, float, float]:
    check_hand(hand)
    model = as_finite_array(model_points, "model_points", ndim=2, shape=(None, 3), max_abs=MAX_LENGTH_MM)
    data = as_finite_array(data_points, "data_points", ndim=2, shape=(None, 3), max_abs=MAX_LENGTH_MM)
    theta = hand.check_theta(theta_init, "theta_init", within_limits=True)
    sigma_max = check_in_range(sigma_max, "sigma_max", 0.0, MAX_SIGMA_MM, closed="right")
    sigma_min = check_positive(sigma_min, "sigma_min")
    if sigma_min >= sigma_max:
        raise ValueError(f"sigma_min must be smaller than sigma_max, got {sigma_min} >= {sigma_max}")
    return model, data, theta, sigma_max, sigma_min


def register_em(model_points: object, data_points: object, hand: HandModel, theta_init: object,
                sigma_max: float = 20.0, sigma_min: float = 3.0, *, n_levels: int = 5,
                max_iter: int = 10, tol: float = DEFAULT_TOL, outlier_c: float | None = None,
                sigma_mode: str = "anneal", targets: str = "paper", a: float = 2.0,
                gauss_newton_steps: int = 2, damping: float = 1e-3, chunk: int = 256,
                release_ratio: float | None = None, e_step: str = "dense", schedule: str = "levels") -> EMResult:
    """Robust EM alignment of texture points X_i (at ``theta_init``) to data Y_j (Sec. 3).

    At each of ``n_levels`` geometric σ levels from ``sigma_max`` to ``sigma_min`` (Sec. 3.3),
    E-step (eq. 17) and M-step (eq. 20) alternate until no DOF moves by more than ``tol`` or
    ``max_iter`` iterations have run.

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
        Largest σ of the annealing, mm (> ``sigma_min``, at most 1e6): about the largest expected motion.
    sigma_min : float, default 3.0
        Smallest σ, mm (> 0): about the noise.
    n_levels : int, default 5
        Number of geometric σ levels (≥ 1; the paper: about five), at most
        :data:`amdo_lab.common.MAX_LEVELS` (64).
    max_iter : int, default 10
        Most EM iterations at one σ level (≥ 1); a level ends earlier when Θ stops changing.
        At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).
    tol : float, default 1e-3
        Convergence threshold on the largest change of Θ in one iteration (rad; mm for the palm; ≥ 0).
    outlier_c : float or None, default None
        Constant c of eq. (17) (> 0); None: 3√(π/2) (eq. 18). ``sigma_mode="scaled"`` instead
        uses c·(σ/σ_min)^3, i.e. a fixed outlier density rather than a fixed c.
    sigma_mode : {"anneal", "scaled", "estimate"}, default "anneal"
        "anneal" (paper), "scaled" (σ-scaled c, ablation) or "estimate" (σ re-estimated
        in the M-step from the weighted residuals, the variant the paper warns against).
    targets : {"paper", "debiased"}, default "paper"
        "paper" (G_i of eq. 20) or "debiased" (ours): T(X_i) + G_i - B_i, where B_i is the
        same weighted mean computed with the moved texture itself as data. At large σ the G_i are
        blurred towards the middle of the hand, which curls fingers; B_i carries the same blur, so
        data that coincide with the model give zero force at every σ.
    a : float, default 2.0
        Exponent of the bending weights of eq. (3) (in (0, :data:`MAX_BENDING_EXPONENT`]).
    gauss_newton_steps : int, default 2
        Gauss-Newton steps of each M-step (≥ 1); the M-step stops earlier when a step is below 1e-6.
        At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).
    damping : float, default 1e-3
        Levenberg damping of the M-step's normal equations, relative to their diagonal, in
        [0, :data:`MAX_DAMPING`].
    chunk : int, default 256
        Data points per block of the streamed dense E-step (≥ 1), at most
        :data:`amdo_lab.common.MAX_SAMPLES` (1,000,000).
    release_ratio : float or None, default None
        Coarse-to-fine (ours; the paper frees every DOF at every σ, the default None):
        a joint is estimated only once σ is below its lever arm (:func:`dof_lever_arms`) divided
        by this ratio (> 0), so σ-wide blur cannot swing short phalanges.
    e_step : {"dense", "kdtree"}, default "dense"
        "dense" (every pair, streamed in chunks) or "kdtree" (pairs within 4σ only,
        :func:`e_step_statistics_kdtree`). At a σ where the 4σ balls hold more than 15 % of all
        pairs, "kdtree" uses the dense E-step instead: there it is faster and not truncated.
    schedule : {"levels", "per-step"}, default "levels"
        "levels" (our reading of Sec. 3.3, the default): at each σ level, E- and M-steps
        alternate until Θ stops changing. "per-step" (the paper's text read literally,
        σ_{q+1} = κσ_q at every iteration q): one iteration at each σ above ``sigma_min``, then
        iterations at ``sigma_min`` until Θ stops changing (at most ``max_iter``).

    Returns
    -------
    EMResult
        Pose, inlier probabilities, history and moved texture.

    Examples
    --------
    A synthetic problem started 10° off at every joint, registered with our settings:

    >>> from amdo_lab.em_articulated import (OUR_SETTINGS, HandModel, joint_rmse_deg,
    ...                                      make_registration_problem)
    >>> hand = HandModel()
    >>> problem = make_registration_problem(hand, rng=1, joint_error_deg=10.0, noise_mm=1.0,
    ...                                     n_model=300, n_data=300)
    >>> result = register_em(problem.model_points, problem.data_points, hand, problem.theta_init,
    ...                      **OUR_SETTINGS)
    >>> round(joint_rmse_deg(problem.theta_init, problem.theta_true), 1)
    10.0
    >>> round(joint_rmse_deg(result.theta, problem.theta_true), 1)
    2.8

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591; Sec. 3.1-3.3, eqs. (17)-(20).
    """
    setup = _em_setup(hand, model_points, data_points, theta_init, sigma_max, sigma_min, n_levels,
                      max_iter, tol, outlier_c, sigma_mode, targets, a, gauss_newton_steps, damping,
                      chunk, release_ratio, e_step, schedule)
    theta, inlier_prob, history = _em_levels(setup, setup.theta_init, setup.sigmas)
    return EMResult(theta, inlier_prob, history, hand.transform_texture(setup.binding, theta))


def register_em_reference(model_points: object, data_points: object, hand: HandModel, theta_init: object,
                          sigma_max: float = 20.0, sigma_min: float = 3.0, *, n_levels: int = 5,
                          max_iter: int = 10, tol: float = DEFAULT_TOL, targets: str = "paper",
                          a: float = 2.0, gauss_newton_steps: int = 2, damping: float = 1e-3) -> np.ndarray:
    """The annealed EM of Sec. 3.1-3.3 written out plainly: the readable path of :func:`register_em`.

    Dense α matrices (:func:`e_step_reference`), so memory is O(N·M): for reading and for the tests,
    which check that :func:`register_em` (streamed E-step, ``e_step="dense"``) reaches the same pose.
    ``targets="debiased"`` is our correction of the large-σ blur (see :func:`register_em`).

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
        Largest σ of the annealing, mm (> ``sigma_min``, at most 1e6): about the largest expected motion.
    sigma_min : float, default 3.0
        Smallest σ, mm (> 0): about the noise.
    n_levels : int, default 5
        Number of geometric σ levels (≥ 1; the paper: about five).
        At most :data:`amdo_lab.common.MAX_LEVELS` (64).
    max_iter : int, default 10
        Most EM iterations at one σ level (≥ 1); a level ends earlier when Θ stops changing.
        At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).
    tol : float, default 1e-3
        Convergence threshold on the largest change of Θ in one iteration (rad; mm for the palm; ≥ 0).
    targets : {"paper", "debiased"}, default "paper"
        The M-step targets, as for :func:`register_em`.
    a : float, default 2.0
        Exponent of the bending weights of eq. (3) (in (0, :data:`MAX_BENDING_EXPONENT`]).
    gauss_newton_steps : int, default 2
        Gauss-Newton steps of each M-step (≥ 1); the M-step stops earlier when a step is below 1e-6.
        At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).
    damping : float, default 1e-3
        Levenberg damping of the M-step's normal equations, relative to their diagonal, in
        [0, :data:`MAX_DAMPING`].

    Returns
    -------
    theta : numpy.ndarray, shape (27,)
        The estimated pose.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, ECCV 2006, Sec. 3.3 and eqs. (17), (20).
    """
    model, data, theta, sigma_max, sigma_min = _check_common(hand, model_points, data_points, theta_init,
                                                             sigma_max, sigma_min)
    n_levels = check_positive_int(n_levels, "n_levels", maximum=MAX_LEVELS)
    max_iter = check_positive_int(max_iter, "max_iter", maximum=MAX_ITERATIONS)
    tol = check_positive(tol, "tol", allow_zero=True)
    check_choice(targets, "targets", ("paper", "debiased"))
    gauss_newton_steps = check_positive_int(gauss_newton_steps, "gauss_newton_steps", maximum=MAX_ITERATIONS)
    damping = check_in_range(damping, "damping", 0.0, MAX_DAMPING, closed="both")
    binding = hand.texture_binding(model, theta, a)  # eq. (3): the texture's blend weights, fixed at Θ_init
    with one_blas_thread():
        # Sec. 3.3: σ falls geometrically from the largest motion σ_max to the noise level σ_min
        for sigma in np.geomspace(sigma_max, sigma_min, n_levels):
            for _ in range(max_iter):
                moved = hand.transform_texture(binding, theta)  # T(X_i, Θ^q)
                alpha = e_step_reference(moved, data, sigma)  # E-step, eq. (17)
                lam, goal = m_step_targets(alpha, data)  # λ_i, G_i of eq. (20)
                if targets == "debiased":  # ours: subtract the texture's own blur B_i
                    _, blurred = m_step_targets(e_step_reference(moved, moved, sigma), moved)
                    goal = moved + goal - blurred
                # M-step: maximising Q of eq. (19) is, up to terms free of Θ, minimising
                # E(Θ) = Σ_i λ_i ||T(X_i, Θ) - G_i||² (eq. 20), here by Gauss-Newton
                new_theta = _m_step(hand, binding, theta, lam, goal, gauss_newton_steps, damping)
                change, theta = float(np.max(np.abs(new_theta - theta))), new_theta
                if change <= tol:  # the paper's stopping rule: Θ no longer changes
                    break
    return theta


@dataclass(frozen=True)
class _EMSetup:
    """Validated inputs and settings of :func:`register_em`, shared with :func:`refine_digits`."""

    hand: HandModel
    data: np.ndarray
    theta_init: np.ndarray
    binding: TextureBinding
    sigmas: np.ndarray  # the annealing schedule, largest first
    sigma_min: float
    lever: np.ndarray  # dof_lever_arms at theta_init (release_ratio)
    log_c: float  # log of the constant c of eq. (17)
    max_iter: int
    tol: float
    sigma_mode: str
    targets: str
    gauss_newton_steps: int
    damping: float
    chunk: int
    release_ratio: float | None
    e_step: str
    schedule: str = "levels"


def _em_setup(hand: HandModel, model_points: object, data_points: object, theta_init: object,
              sigma_max: float = 20.0, sigma_min: float = 3.0, n_levels: int = 5, max_iter: int = 10,
              tol: float = DEFAULT_TOL, outlier_c: float | None = None, sigma_mode: str = "anneal",
              targets: str = "paper", a: float = 2.0, gauss_newton_steps: int = 2, damping: float = 1e-3,
              chunk: int = 256, release_ratio: float | None = None, e_step: str = "dense",
              schedule: str = "levels") -> _EMSetup:
    """Check :func:`register_em`'s arguments (same names, same defaults) and bind the texture at ``theta_init``."""
    model, data, theta, sigma_max, sigma_min = _check_common(hand, model_points, data_points,
                                                             theta_init, sigma_max, sigma_min)
    n_levels = check_positive_int(n_levels, "n_levels", maximum=MAX_LEVELS)
    max_iter = check_positive_int(max_iter, "max_iter", maximum=MAX_ITERATIONS)
    tol = check_positive(tol, "tol", allow_zero=True)
    check_choice(sigma_mode, "sigma_mode", ("anneal", "scaled", "estimate"))
    check_choice(targets, "targets", ("paper", "debiased"))
    check_choice(e_step, "e_step", ("dense", "kdtree"))
    check_choice(schedule, "schedule", ("levels", "per-step"))
    chunk = check_positive_int(chunk, "chunk", maximum=MAX_SAMPLES)
    gauss_newton_steps = check_positive_int(gauss_newton_steps, "gauss_newton_steps", maximum=MAX_ITERATIONS)
    damping = check_in_range(damping, "damping", 0.0, MAX_DAMPING, closed="both")
    c = PAPER_C if outlier_c is None else check_positive(outlier_c, "outlier_c")
    if release_ratio is not None:
        release_ratio = check_in_range(release_ratio, "release_ratio", 0.0, MAX_DAMPING, closed="right")
    binding = hand.texture_binding(model, theta, a)
    return _EMSetup(hand, data, theta, binding, np.geomspace(sigma_max, sigma_min, n_levels), sigma_min,
                    dof_lever_arms(hand, binding, theta), float(np.log(c)), max_iter, tol, sigma_mode,
                    targets, gauss_newton_steps, damping, chunk, release_ratio, e_step, schedule)


def _em_levels(setup: _EMSetup, theta: np.ndarray, sigmas: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The EM of :func:`register_em` from pose ``theta`` through the σ levels ``sigmas``.

    Returns the pose, the inlier probabilities Σ_i α_ij of the last E-step and the history rows.
    """
    hand, data, binding = setup.hand, setup.data, setup.binding
    data_pairs = ClosePairs(data) if setup.e_step == "kdtree" else None
    self_pairs = ClosePairs(None) if setup.e_step == "kdtree" else None

    def statistics(points: np.ndarray, observed: np.ndarray, sigma: float, log_c: float, pairs=None) -> tuple:
        radius = _KDTREE_RADIUS_SIGMAS * sigma
        if setup.e_step == "kdtree" and pairs.pair_fraction(points, radius) <= DENSE_PAIR_FRACTION:
            # truncated at 4σ, as e_step_statistics_kdtree
            return _statistics_from_pairs(*pairs(points, radius), observed, len(points), sigma, log_c)
        return _dense_statistics(points, observed, sigma, log_c, setup.chunk, "single")

    history = []
    sigma = sigmas[0]
    inlier_prob = np.zeros(data.shape[0])
    with one_blas_thread():  # small dense algebra: BLAS threads only contend
        for level, level_sigma in enumerate(sigmas):
            # per-step schedule: σ falls after every iteration until it reaches the last level
            n_iterations = 1 if setup.schedule == "per-step" and level < len(sigmas) - 1 else setup.max_iter
            free = np.ones(hand.n_dof, bool)
            if setup.release_ratio is not None:
                free &= setup.lever >= setup.release_ratio * level_sigma
            for _ in range(n_iterations):
                if setup.sigma_mode != "estimate":
                    sigma = level_sigma
                log_c = setup.log_c + (3 * np.log(sigma / setup.sigma_min) if setup.sigma_mode == "scaled" else 0.0)
                moved, jac = hand.texture_jacobian(binding, theta)  # the M-step's first linearisation too
                weights, weighted, inlier_prob, energy = statistics(moved, data, sigma, log_c, data_pairs)
                history.append((sigma, energy))
                goal = weighted / np.maximum(weights, 1e-300)[:, None]
                if setup.targets == "debiased":
                    self_weights, self_weighted, _, _ = statistics(moved, moved, sigma, log_c, self_pairs)
                    goal = moved + goal - self_weighted / np.maximum(self_weights, 1e-300)[:, None]
                new_theta = _m_step(hand, binding, theta, weights, goal, setup.gauss_newton_steps, setup.damping, free,
                                    start=(moved, jac))
                change = float(np.max(np.abs(new_theta - theta)))
                theta = new_theta
                if setup.sigma_mode == "estimate":
                    _, _, _, new_energy = statistics(hand.transform_texture(binding, theta), data, sigma, log_c, data_pairs)
                    sigma = max(np.sqrt(new_energy / max(3 * weights.sum(), 1e-12)), 1e-3)
                if change <= setup.tol:
                    break
    return theta, inlier_prob, np.array(history)


def climb_objective(model_points: object, data_points: object, hand: HandModel, theta_init: object,
                    theta_start: object, sigma: float = 3.0, *, max_iter: int = 60,
                    tol: float = 1e-5) -> np.ndarray:
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
    max_iter : int, default 60
        Most EM iterations (≥ 1). At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).
    tol : float, default 1e-5
        The climb stops when no DOF moves by more than this in one iteration (rad; mm for the palm).

    Returns
    -------
    theta : numpy.ndarray, shape (27,)
        Pose at the local maximum (or after ``max_iter`` iterations).

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, ECCV 2006, eqs. (9), (17), (20).
    """
    sigma = check_in_range(sigma, "sigma", 0.0, MAX_SIGMA_MM / 2, closed="right")
    max_iter = check_positive_int(max_iter, "max_iter", maximum=MAX_ITERATIONS)
    setup = _em_setup(hand, model_points, data_points, theta_init, sigma_max=2.0 * sigma,
                      sigma_min=sigma, n_levels=1, max_iter=max_iter,
                      tol=tol, targets="paper", e_step="dense")
    start = hand.check_theta(theta_start, "theta_start", within_limits=True)
    return _em_levels(setup, start, np.array([sigma]))[0]


#: Per digit (thumb, index, middle, ring, little): its DOFs, the one that swings it sideways at the
#: knuckle, and the ones that curl it.
_DIGIT_DOFS = tuple(np.array(dofs) for dofs in DIGIT_DOFS)
_DIGIT_ABDUCTION = tuple(dofs[0] for dofs in DIGIT_DOFS)
_DIGIT_FLEXION = tuple(np.setdiff1d(dofs, SIDEWAYS_DOFS) for dofs in DIGIT_DOFS)


@dataclass(frozen=True)
class DigitSearchResult:
    """Result of :func:`refine_digits`.

    Parameters
    ----------
    theta : numpy.ndarray, shape (27,)
        The refined pose.
    inlier_prob : numpy.ndarray, shape (M,)
        Σ_i α_ij per data point at that pose and σ_min.
    log_likelihood : float
        The criterion at ``theta``, nats.
    start_log_likelihood : float
        The criterion at the pose the search started from, nats.
    accepted : tuple of (str, float)
        (digit name, gain of the criterion in nats) per accepted move, in order.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591; eq. (17) (the criterion); the search itself is ours.
    """

    theta: np.ndarray
    inlier_prob: np.ndarray
    log_likelihood: float
    start_log_likelihood: float
    accepted: tuple[tuple[str, float], ...]


def _robust_log_likelihood(model_points: np.ndarray, data_points: np.ndarray, sigma: float, log_c: float,
                           chunk: int = 256) -> tuple[float, np.ndarray]:
    """Σ_j log(c + Σ_i exp(-||Y_j - X_i||²/2σ²)) and the inlier probabilities Σ_i α_ij of eq. (17).

    The log-likelihood of the data under eq. (17)'s mixture (equal weights, a uniform outlier class)
    up to a constant, so values at the same σ and c can be compared between poses. It is a by-product
    of the dense E-step's pass (double precision: the search compares values that differ by ~1).
    """
    _, _, inlier_prob, _, log_likelihood = _dense_pass(model_points, data_points, sigma, log_c, chunk, "double")
    return log_likelihood, inlier_prob


def digit_starts(hand: HandModel, theta: np.ndarray, digit: int, abduction_step: float,
                  flexion_step: float) -> np.ndarray:
    """Alternative starts (K, 27) that differ from ``theta`` in one digit's joint angles only.

    The digit at its rest pose; swung sideways by ± ``abduction_step`` (towards either neighbour);
    its knuckle flexed by ± ``flexion_step``; all its flexion joints by ± ``flexion_step``. Clipped to
    the joint limits; a start the clip brings back onto ``theta`` is dropped. The restarts of
    :func:`refine_digits`, on its checked input (not exported).

    Parameters
    ----------
    hand : HandModel
        The articulated model.
    theta : numpy.ndarray, shape (27,)
        The pose to start from, inside the joint limits.
    digit : int
        0 (thumb) to 4 (little finger).
    abduction_step : float
        Sideways swing, radians.
    flexion_step : float
        Flexion step, radians.

    Returns
    -------
    numpy.ndarray, shape (K, 27)
        The starts, 1 ≤ K ≤ 7.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, ECCV 2006, eq. (17) (the criterion the restarts climb); the
    search is ours, not in the paper.
    """
    dofs, abduction, flexion = _DIGIT_DOFS[digit], _DIGIT_ABDUCTION[digit], _DIGIT_FLEXION[digit]
    shifts = np.zeros((7, hand.n_dof))
    shifts[0, dofs] = hand.rest_pose()[dofs] - theta[dofs]
    shifts[1:3, abduction] = [-abduction_step, abduction_step]
    shifts[3:5, flexion[0]] = [-flexion_step, flexion_step]
    shifts[5, flexion], shifts[6, flexion] = -flexion_step, flexion_step
    limits = hand.joint_limits()
    starts = np.clip(theta + shifts, limits[:, 0], limits[:, 1])
    return starts[np.max(np.abs(starts - theta), axis=1) > 1e-3]


def refine_digits(model_points: object, data_points: object, hand: HandModel, theta_init: object, theta: object,
                  *, search_levels: int = 2, abduction_step_deg: float = 20.0, flexion_step_deg: float = 25.0,
                  max_passes: int = 2, min_gain: float = 1.0, **em_settings) -> DigitSearchResult:
    """Re-seed one digit at a time from the pose ``theta`` :func:`register_em` converged to (beyond the paper).

    The annealed EM can end with a finger on its neighbour's points, a local optimum it does not
    leave at small σ. This search first re-runs the last ``search_levels`` σ levels of the EM from
    ``theta``; then, for each digit (thumb, index, middle, ring, little) in turn, it restarts those
    levels from a few poses that differ from the current one in that digit's joint angles only
    (the digit's rest pose, its abduction ± ``abduction_step_deg``, its knuckle
    flexion and its whole curl ± ``flexion_step_deg``), the rest of the hand where it is. The best of
    a digit's restarts replaces the current pose when it raises the criterion by more than
    ``min_gain``; passes over the five digits repeat, up to ``max_passes``, while some restart is
    accepted.

    The criterion uses the data only (no ground truth): the log-likelihood of the data under the
    mixture of eq. (17) at σ_min, Σ_j log(c + Σ_i exp(-||Y_j - T(X_i, Θ)||²/2σ_min²)). The pose
    returned never has a lower criterion than ``theta``. Not part of Dewaele et al. (2006).

    Parameters
    ----------
    model_points : array_like, shape (N, 3)
        Texture points X_i at pose ``theta_init``, mm, within ±1e6 (as for :func:`register_em`).
    data_points : array_like, shape (M, 3)
        Observed points Y_j, mm, within ±1e6.
    hand : HandModel
        The articulated model.
    theta_init : array_like, shape (27,)
        Pose where the texture was observed, inside the joint limits.
    theta : array_like, shape (27,)
        Pose to refine, inside the joint limits (e.g. ``register_em(...).theta``).
    search_levels : int, default 2
        How many of the EM's last σ levels each restart runs (1 to ``n_levels``).
        At most :data:`amdo_lab.common.MAX_LEVELS` (64).
    abduction_step_deg : float, default 20.0
        Sideways swing of a digit's restarts, degrees (> 0).
    flexion_step_deg : float, default 25.0
        Knuckle and whole-curl flexion of a digit's restarts, degrees (> 0).
    max_passes : int, default 2
        Most passes over the five digits (≥ 0; 0: only the re-run from ``theta``).
        At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).
    min_gain : float, default 1.0
        Smallest rise of the criterion that accepts a restart, nats (≥ 0): a margin against
        moves that only fit the noise.
    **em_settings
        Keyword arguments of :func:`register_em` (``sigma_max``, ``sigma_min``,
        ``n_levels``, ``targets``, ``e_step``, ...), e.g. ``**OUR_SETTINGS``; the same as the EM that
        produced ``theta``, so the restarts are that EM's last levels.

    Returns
    -------
    DigitSearchResult
        The refined pose, its inlier probabilities and criterion, and the accepted moves.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, "The alignment between 3-D data and articulated shapes with
    bending surfaces", ECCV 2006, LNCS 3953, pp. 578-591; eq. (17) (the criterion); the search is
    ours, not in the paper.
    """
    setup = _em_setup(hand, model_points, data_points, theta_init, **em_settings)
    theta = hand.check_theta(theta, "theta", within_limits=True)
    search_levels = check_positive_int(search_levels, "search_levels", maximum=MAX_LEVELS)
    if search_levels > len(setup.sigmas):
        raise ValueError(f"search_levels must be at most n_levels ({len(setup.sigmas)}), got {search_levels}")
    abduction_step = np.radians(check_positive(abduction_step_deg, "abduction_step_deg"))
    flexion_step = np.radians(check_positive(flexion_step_deg, "flexion_step_deg"))
    max_passes = check_positive_int(max_passes, "max_passes", minimum=0, maximum=MAX_ITERATIONS)
    min_gain = check_positive(min_gain, "min_gain", allow_zero=True)
    sigmas = setup.sigmas[-search_levels:]

    def criterion(pose: np.ndarray) -> tuple[float, np.ndarray]:
        with one_blas_thread():
            return _robust_log_likelihood(setup.hand.transform_texture(setup.binding, pose), setup.data,
                                          setup.sigma_min, setup.log_c)

    def restart(start: np.ndarray) -> tuple[np.ndarray, float, np.ndarray]:
        pose = _em_levels(setup, start, sigmas)[0]
        return (pose, *criterion(pose))

    best, inlier_prob = criterion(theta)
    start_log_likelihood = best
    polished, polished_value, polished_prob = restart(theta)
    if polished_value >= best:  # the re-run only finishes the EM's convergence: no margin needed
        theta, best, inlier_prob = polished, polished_value, polished_prob
    accepted = []
    for _ in range(max_passes):
        changed = False
        for digit, name in enumerate(FINGERS):
            restarts = [restart(start) for start in digit_starts(hand, theta, digit, abduction_step, flexion_step)]
            if not restarts:
                continue
            pose, value, prob = max(restarts, key=lambda result: result[1])
            if value > best + min_gain:
                accepted.append((name, value - best))
                theta, best, inlier_prob, changed = pose, value, prob, True
        if not changed:
            break
    return DigitSearchResult(theta, inlier_prob, best, start_log_likelihood, tuple(accepted))


def fit_known_correspondences(model_points: object, matched_points: object, hand: HandModel, theta_init: object,
                              *, a: float = 2.0, max_iter: int = 30) -> np.ndarray:
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
    a : float, default 2.0
        Exponent of the bending weights of eq. (3) (in (0, :data:`MAX_BENDING_EXPONENT`]).
    max_iter : int, default 30
        Most Gauss-Newton steps (≥ 1); the fit stops earlier when a step is below 1e-6.
        At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).

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
    model = as_finite_array(model_points, "model_points", ndim=2, shape=(None, 3), max_abs=MAX_LENGTH_MM)
    matched = as_finite_array(matched_points, "matched_points", ndim=2, shape=(len(model), 3), max_abs=MAX_LENGTH_MM)
    theta = hand.check_theta(theta_init, "theta_init", within_limits=True)
    max_iter = check_positive_int(max_iter, "max_iter", maximum=MAX_ITERATIONS)
    with one_blas_thread():
        binding = hand.texture_binding(model, theta, a)
        return _m_step(hand, binding, theta, np.ones(len(model)), matched, max_iter, 1e-3)


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
                sigma: float | None = 3.0, max_iter: int = 3, damping: float = 1e-2,
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
    damping : float, default 1e-2
        Initial Levenberg-Marquardt damping, relative to the normal equations' diagonal (≥ 0).
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
    data = as_finite_array(data_points, "data_points", ndim=2, shape=(None, 3), max_abs=MAX_LENGTH_MM)
    theta = hand.check_theta(theta_init, "theta_init", within_limits=True)
    w = np.ones(len(data)) if weights is None else as_finite_array(weights, "weights", ndim=1, shape=(len(data),),
                                                                    max_abs=MAX_WEIGHT)
    if np.any(w < 0):
        raise ValueError("weights must be non-negative")
    if sigma is not None:
        sigma = check_in_range(sigma, "sigma", 0.0, MAX_SIGMA_MM, closed="right")
    damping = check_in_range(damping, "damping", 0.0, MAX_DAMPING, closed="both")
    if epsilon_mm is not None:
        epsilon_mm = check_positive(epsilon_mm, "epsilon_mm")
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
            lm = damping
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


@dataclass(frozen=True)
class SoftAssignResult:
    """Result of :func:`softassign_register`.

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


def softassign_register(model_points: object, data_points: object, hand: HandModel, theta_init: object,
                        sigma_max: float = 20.0, sigma_min: float = 2.0, *, slack: float = 1e-2,
                        n_levels: int = 5, n_iter: int = 3, n_sweeps: int = 30,
                        a: float = 2.0) -> SoftAssignResult:
    """SoftAssign (Gold, Rangarajan et al.) baseline of Sec. 4, Sinkhorn in the log domain.

    The (N+1)x(M+1) match matrix has a slack row and column initialised to ``slack``; rows and
    columns (except the slack ones) are alternately normalised to sum 1. Dense: O(N·M) memory.

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
    n_sweeps : int, default 30
        Sinkhorn row-and-column normalisation sweeps per iteration (≥ 1).
        At most :data:`amdo_lab.common.MAX_ITERATIONS` (100,000).
    a : float, default 2.0
        Exponent of the bending weights of eq. (3) (in (0, :data:`MAX_BENDING_EXPONENT`]).

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
    model, data, theta, sigma_max, sigma_min = _check_common(hand, model_points, data_points,
                                                             theta_init, sigma_max, sigma_min)
    slack = check_positive(slack, "slack")
    n_levels = check_positive_int(n_levels, "n_levels", maximum=MAX_LEVELS)
    n_iter = check_positive_int(n_iter, "n_iter", maximum=MAX_ITERATIONS)
    n_sweeps = check_positive_int(n_sweeps, "n_sweeps", maximum=MAX_ITERATIONS)
    binding = hand.texture_binding(model, theta, a)
    n_model, n_data = len(model), len(data)
    inlier_prob = np.zeros(n_data)
    for sigma in np.geomspace(sigma_max, sigma_min, n_levels):
        for _ in range(n_iter):
            moved = hand.transform_texture(binding, theta)
            sq = np.sum((moved[:, None, :] - data[None, :, :]) ** 2, axis=2)
            log_m = np.full((n_model + 1, n_data + 1), np.log(slack))
            log_m[:n_model, :n_data] = -sq / (2 * sigma**2)
            for _ in range(n_sweeps):
                log_m[:n_model] -= logsumexp(log_m[:n_model], axis=1, keepdims=True)
                log_m[:, :n_data] -= logsumexp(log_m[:, :n_data], axis=0, keepdims=True)
            match = np.exp(log_m[:n_model, :n_data])
            weights = match.sum(axis=1)
            targets = (match @ data) / np.maximum(weights, 1e-300)[:, None]
            theta = _m_step(hand, binding, theta, weights, targets, 2, 1e-3)
            inlier_prob = match.sum(axis=0)
    return SoftAssignResult(theta, inlier_prob)
