"""The E-step of the robust EM (eqs. 17-18), its M-step targets (eq. 20) and the objective it climbs (eq. 9).

Each quantity has a readable reference path, every pair at once in plain numpy
(:func:`e_step_reference`, :func:`robust_log_likelihood_reference`), and the streamed, log-domain
path the EM calls (:func:`e_step_statistics`, :func:`dense_e_step`), tested equal to it. The
truncated k-d tree E-step is in :mod:`amdo_lab.em_articulated.kdtree`.
"""

from __future__ import annotations

import numpy as np

from amdo_lab.common import MAX_SAMPLES
from amdo_lab.common import as_finite_array, check_choice, check_in_range, check_positive, check_positive_int
from amdo_lab.common.threads import one_blas_thread

from amdo_lab.em_articulated.hand import MAX_LENGTH_MM, check_points

__all__ = ["PAPER_C", "e_step_reference", "m_step_targets", "robust_log_likelihood",
           "robust_log_likelihood_reference", "e_step_statistics", "dense_e_step", "check_e_step_inputs"]

#: Outlier constant of eq. (18) with n v << V.
PAPER_C = 3.0 * np.sqrt(np.pi / 2.0)

#: Data points per block of the streamed E-step (memory O(CHUNK·N)).
CHUNK = 256
#: Largest σ accepted, mm (σ² and the energies overflow long before 1e308).
MAX_SIGMA_MM = MAX_LENGTH_MM
#: Largest log of the outlier constant c of eq. (17) the E-step accepts: exp(700) is about 1e304, the
#: largest power of e that stays finite with room for the sums over the data around it.
MAX_LOG_C = 700.0


def check_e_step_inputs(model_points: object, data_points: object, sigma: object,
                        log_c: object) -> tuple[np.ndarray, np.ndarray, float, float]:
    """The checked (N, 3) texture, (M, 3) data, σ and log c shared by the public E-step functions.

    Parameters
    ----------
    model_points, data_points : array_like, shape (N, 3) and (M, 3)
        Moved texture points and data points, mm, within ±1e6.
    sigma : float
        σ, mm, in (0, 1e6].
    log_c : float
        log of the outlier constant c, at most :data:`MAX_LOG_C`, or -inf (no outlier class).

    Returns
    -------
    tuple
        The four checked values, in that order.
    """
    model = check_points(model_points, "model_points")
    data = check_points(data_points, "data_points")
    sigma = check_in_range(sigma, "sigma", 0.0, MAX_SIGMA_MM, closed="right")
    # -inf is allowed: no outlier class (c = 0)
    log_c = -np.inf if log_c == -np.inf else check_in_range(log_c, "log_c", -np.inf, MAX_LOG_C, closed="right")
    return model, data, sigma, log_c


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
    model, data, sigma, _ = check_e_step_inputs(model_points, data_points, sigma, 0.0)
    return _posterior_matrix(model, data, sigma, check_positive(c, "c"))


def _posterior_matrix(model: np.ndarray, data: np.ndarray, sigma: float, c: float) -> np.ndarray:
    """Eq. (17) in plain numpy on checked input: the kernel of :func:`e_step_reference`.

    Parameters
    ----------
    model, data : numpy.ndarray, shape (N, 3) and (M, 3)
        Moved texture points T(X_i, Θ) and data points Y_j, mm.
    sigma, c : float
        σ in mm and the outlier constant c of eq. (18).

    Returns
    -------
    numpy.ndarray, shape (N, M)
        Posteriors α_ij.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, ECCV 2006, eqs. (17)-(18).
    """
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
    data = check_points(data_points, "data_points")
    alpha = as_finite_array(alpha, "alpha", ndim=2, shape=(None, len(data)), bounds=(0.0, 1.0))
    return _weighted_targets(alpha, data)


def _weighted_targets(alpha: np.ndarray, data: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """λ_i and G_i of eq. (20) on checked input: the kernel of :func:`m_step_targets`.

    Parameters
    ----------
    alpha : numpy.ndarray, shape (N, M)
        Posteriors α_ij.
    data : numpy.ndarray, shape (M, 3)
        Data points Y_j, mm.

    Returns
    -------
    tuple of numpy.ndarray
        λ_i (N,) and G_i (N, 3).

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, ECCV 2006, eq. (20).
    """
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
    model, data, sigma, _ = check_e_step_inputs(model_points, data_points, sigma, 0.0)
    log_c = float(np.log(check_positive(c, "c")))
    with one_blas_thread():
        return dense_e_step(model, data, sigma, log_c, CHUNK, "double")[4]


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
    model, data, sigma, _ = check_e_step_inputs(model_points, data_points, sigma, 0.0)
    c = check_positive(c, "c")
    sq_dist = np.sum((model[:, None, :] - data[None, :, :]) ** 2, axis=2)
    # eq. (8), the mixture f_j = Σ_i Π_i f(Y_j|X_i) + Π_outlier f(Y_j|outlier), written out as eq. (9) and
    # divided by Π_i (2πσ²)^(-3/2) (eq. 18): f_j ∝ Σ_i exp(-||Y_j - T(X_i)||²/2σ²) + c
    mixture = np.exp(-sq_dist / (2.0 * sigma**2)).sum(axis=0) + c
    return float(np.sum(np.log(mixture)))  # the log-likelihood of the data, Σ_j log f_j, up to a constant


def e_step_statistics(model_points: object, data_points: object, sigma: float,
                      log_c: float, chunk: int = CHUNK,
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
    model_points, data_points, sigma, log_c = check_e_step_inputs(model_points, data_points, sigma, log_c)
    chunk = check_positive_int(chunk, "chunk", maximum=MAX_SAMPLES)
    check_choice(precision, "precision", ("single", "double"))
    return dense_e_step(model_points, data_points, sigma, log_c, chunk, precision)[:4]


def dense_e_step(model_points: np.ndarray, data_points: np.ndarray, sigma: float, log_c: float, chunk: int,
                 precision: str) -> tuple[np.ndarray, np.ndarray, np.ndarray, float, float]:
    """The outputs of :func:`e_step_statistics` and the data's log-likelihood, from one streamed pass.

    The check-free kernel of :func:`e_step_statistics` and :func:`robust_log_likelihood`, which the
    EM's loops call on checked input (not exported). The log-likelihood under eq. (17)'s mixture,
    Σ_j log(c + Σ_i exp(-||Y_j - X_i||²/2σ²)), is Σ_j (top_j + log normaliser_j) of the same pass.

    Parameters
    ----------
    model_points, data_points : numpy.ndarray, shape (N, 3) and (M, 3)
        Checked moved texture points and data points, mm.
    sigma, log_c : float
        σ in mm and log c, checked.
    chunk : int
        Data points per block.
    precision : {"single", "double"}
        Precision of the exponentials and their sums.

    Returns
    -------
    tuple
        weights (N,), weighted_data (N, 3), inlier_prob (M,), energy and log-likelihood.

    References
    ----------
    Dewaele, Devernay, Horaud & Forbes, ECCV 2006, eqs. (9), (17)-(20).
    """
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
