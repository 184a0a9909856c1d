"""Incremental thin SVD with the mean carried along (Melenchón, Meler & Iriondo, AMDO 2004, Sec. 2).

Columns are observations (the paper's ``M`` is p x q: p pixels, q frames). A model is the thin SVD of
the centred data plus the mean, eq. (2): ``M = U diag(s) V^T + m 1^T``.

- :func:`brand_update` appends columns to a thin SVD (eq. 11, Brand 2002);
- :func:`update_with_mean` appends columns and moves the mean with them (eqs. 7-15);
- :func:`extract_mean` takes the mean out of an existing thin SVD (Sec. 2.4);
- :func:`ross_update` is the mean-correction column of Ross et al. (2008), which needs no ``V``;
- :class:`IncrementalSVD` learns from a stream of frames with any of the three (scikit-learn's contract).

Each function is written first as the paper reads it; where a cheaper order of the same products
exists (``fast=True``) it sits beside it and ``tests/test_incremental_svd.py`` checks they agree.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

from amdo_lab.common import (
    as_finite_array,
    check_bool,
    check_choice,
    check_fitted,
    check_in_range,
    check_positive,
    check_positive_int,
    MAX_SAMPLES,
    MAX_SIDE,
    one_blas_thread,
)

__all__ = ["MEAN_MODES", "NOISE_KERNEL", "IncrementalSVD", "SvdState", "brand_update", "estimate_noise", "extract_mean",
           "noise_edge", "ross_update", "tau_schedule", "update_with_mean"]

#: A residual column whose QR diagonal is below this fraction of the data's scale is dropped (eq. 11).
RESIDUAL_RTOL = 1e-10

_REFERENCE = ("Melenchón, J., Meler, L., Iriondo, I. On-the-Fly Training. AMDO 2004, LNCS 3179, "
              "pp. 146-153.")


class SvdState(tuple):
    """A thin SVD with its mean: ``(U, s, V, mean)``; ``U`` p x r, ``s`` (r,), ``V`` q x r, ``mean`` (p,).

    A plain tuple (it unpacks as ``U, s, V, mean = state``) with named fields for reading.

    Parameters
    ----------
    U : ndarray, shape (p, r)
        Left singular vectors.
    s : ndarray, shape (r,)
        Singular values, descending.
    V : ndarray, shape (q, r) or None
        Right singular vectors (None for a model that does not keep them).
    mean : ndarray, shape (p,)
        The mean column.

    References
    ----------
    Melenchón, Meler & Iriondo, AMDO 2004, eq. (2).
    """

    __slots__ = ()

    def __new__(cls, U: np.ndarray, s: np.ndarray, V: np.ndarray | None, mean: np.ndarray) -> SvdState:
        return super().__new__(cls, (U, s, V, mean))

    def __getnewargs__(self) -> tuple:
        """The four fields, so that pickle and copy rebuild the state through :meth:`__new__`."""
        return tuple(self)

    @property
    def U(self) -> np.ndarray:
        """Left singular vectors, p x r."""
        return self[0]

    @property
    def s(self) -> np.ndarray:
        """Singular values, descending, (r,)."""
        return self[1]

    @property
    def V(self) -> np.ndarray | None:
        """Right singular vectors, q x r (None for a model that does not keep them)."""
        return self[2]

    @property
    def mean(self) -> np.ndarray:
        """The mean column, (p,)."""
        return self[3]


#: Largest accepted magnitude of an input value: products of two such values stay finite.
MAX_ABS = 1e100


def _check_basis(U: object, s: object) -> tuple[np.ndarray, np.ndarray]:
    """The left factor (p x r, p >= 1) and its r non-negative singular values."""
    U = as_finite_array(U, "U", ndim=2, allow_empty=True, max_abs=MAX_ABS)
    check_positive_int(U.shape[0], "U's number of rows (pixels)")
    # a length mismatch names both: either may be at fault
    s = as_finite_array(s, "s (one per U column)", shape=U.shape[1:], allow_empty=True, bounds=(0, MAX_ABS))
    return U, s


def _check_factors(U: object, s: object, V: object, *,
                   min_rows: int = 0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A thin SVD ``(U, s, V)``: the basis of :func:`_check_basis` and the right factor, r orthonormal
    columns, so at least max(r, ``min_rows``) rows, one per column seen."""
    U, s = _check_basis(U, s)
    V = as_finite_array(V, "V", shape=(None, s.size), allow_empty=True, max_abs=MAX_ABS)
    check_positive_int(V.shape[0], "V's number of rows (one per column seen)", minimum=max(s.size, min_rows))
    return U, s, V


def _residual_basis(U: np.ndarray, I_hat: np.ndarray, scale: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Eq. (11)'s projections: ``L = U^T I``, and ``Q R`` of the residual ``I - U L``, thin directions dropped."""
    L = U.T @ I_hat
    H = I_hat - U @ L
    correction = U.T @ H                      # a second Gram-Schmidt pass: "twice is enough"
    H -= U @ correction
    L += correction
    Q, R, order = scipy.linalg.qr(H, mode="economic", pivoting=True)
    keep = np.abs(np.diag(R)) > RESIDUAL_RTOL * max(scale, np.finfo(float).tiny)
    R_full = np.empty_like(R)
    R_full[:, order] = R                      # undo the column pivoting: H = Q R_full
    return L, Q[:, keep], R_full[keep]


def brand_update(U: np.ndarray, s: np.ndarray, V: np.ndarray, I: np.ndarray) -> SvdState:
    """Append columns ``I`` to the thin SVD ``U diag(s) V^T`` (Brand's update, eq. 11).

    The residual of ``I`` outside ``span(U)`` is factorised ``Q R``; the small core
    ``[[diag(s), U^T I], [0, R]]`` of size (r + c') is decomposed, and its factors rotate
    ``[U Q]`` and ``blockdiag(V, I_c)``. Residual directions whose ``|R_jj|`` is below
    ``RESIDUAL_RTOL`` times the data's scale are dropped: normalising a residual made of rounding
    errors would add a column that is not orthogonal to ``U``.

    Parameters
    ----------
    U : ndarray, shape (p, r)
        Orthonormal left factor (r may be 0).
    s : ndarray, shape (r,)
        Singular values, non-negative.
    V : ndarray, shape (q, r)
        Orthonormal right factor, one row per column already seen.
    I : ndarray, shape (p, c)
        The new columns.

    Returns
    -------
    SvdState
        ``(U_t, s_t, V_t, mean)`` with ``U_t`` p x r', ``V_t`` (q + c) x r', r' <= r + c, and a
        zero mean (this update carries none).

    References
    ----------
    Melenchón, Meler & Iriondo, AMDO 2004, eq. (11); M. Brand, Incremental singular value
    decomposition of uncertain data with missing values, ECCV 2002.

    Examples
    --------
    >>> import numpy as np
    >>> M = np.random.default_rng(0).normal(size=(6, 4))
    >>> U, s, Vt = np.linalg.svd(M[:, :3], full_matrices=False)
    >>> Ut, st, Vt_new, _ = brand_update(U, s, Vt.T, M[:, 3:])
    >>> bool(np.allclose(st, np.linalg.svd(M, compute_uv=False)))
    True
    """
    U, s, V = _check_factors(U, s, V)
    return _brand_update(U, s, V, as_finite_array(I, "I", shape=(U.shape[0], None), max_abs=MAX_ABS))


def _brand_update(U: np.ndarray, s: np.ndarray, V: np.ndarray, I: np.ndarray) -> SvdState:
    Q, U_d, s_t, V_d_small, V_d_new = _brand_core(U, s, I)
    # eq. (11): U_t = [U_i Q_i] U_d, V_t = blockdiag(V_i, I_c) V_d (the printed "1" is I_c)
    V_t = np.vstack([V @ V_d_small, V_d_new])
    return SvdState(_rotate(U, Q, U_d), s_t, V_t, np.zeros(U.shape[0]))


def _brand_core(U: np.ndarray, s: np.ndarray, I_hat: np.ndarray):
    """Eq. (11) without forming ``U_t``: ``Q``, ``U_d``, ``s_d`` and the two blocks of ``V_d`` (rows r, c).

    ``U_t = U U_d[:r] + Q U_d[r:]`` (see :func:`_rotate`), so a caller that rotates ``U_t`` again
    can compose the small rotations first and touch the p x r matrix once.
    """
    r, c = s.size, I_hat.shape[1]
    scale = max(float(s.max(initial=0.0)), float(np.linalg.norm(I_hat, axis=0).max(initial=0.0)))
    L, Q, R = _residual_basis(U, I_hat, scale)
    # eq. (11): the core [[Σ_i, U_i^T Î], [0, Q_i^T Î]] = U_d Σ_d V_d^T
    K = np.zeros((r + Q.shape[1], r + c))
    K[:r, :r] = np.diag(s)
    K[:r, r:] = L
    K[r:, r:] = R
    U_d, s_d, V_d_t = np.linalg.svd(K, full_matrices=False)
    V_d = V_d_t.T
    return Q, U_d, s_d, V_d[:r], V_d[r:]


def _rotate(U: np.ndarray, Q: np.ndarray, W: np.ndarray) -> np.ndarray:
    """``[U Q] W`` without stacking ``U`` and ``Q`` (eq. 11's ``U_t = [U_i Q_i] U_d`` when ``W = U_d``)."""
    r = U.shape[1]
    return U @ W[:r] + Q @ W[r:]


def _centre_right_factor(s_t: np.ndarray, V_t: np.ndarray, *, U_t: np.ndarray | None = None, fast: bool):
    """Eqs. (12)-(13): take the mean of the rows of ``V_t`` out and re-diagonalise.

    Returns ``(A or U_f, s_f, V_f, v̄_t)``: with ``fast`` the r x r rotation ``A`` (``U_f = U_t A``),
    else ``U_f`` itself from the paper's p x r SVD (``U_t`` must then be given).
    """
    # eq. (12): v̄_t is the mean of the q + c rows of V_t (an r-vector); m̄_t = U_t Σ_t v̄_t
    v_bar = V_t.mean(axis=0)
    V_hat = V_t - v_bar
    # eq. (13): V̂_t = Q_v R_v
    Q_v, R_v = np.linalg.qr(V_hat)
    if fast:
        # eq. (13), the r x r order: Σ_t R_v^T = A Σ_f V_u^T, so U_f = U_t A
        left, s_f, V_u_t = np.linalg.svd(s_t[:, None] * R_v.T)
    else:
        # eq. (13) as printed: the thin SVD of the p x r matrix U_t Σ_t R_v^T = U_f Σ_f V_u^T
        left, s_f, V_u_t = np.linalg.svd(U_t @ (s_t[:, None] * R_v.T), full_matrices=False)
    # eq. (13): V_f = Q_v V_u (Table 1's last row, with its arrow read this way)
    V_f = Q_v @ V_u_t.T
    return left, s_f, V_f, v_bar


def _truncate(state: SvdState, *, max_rank: int | None = None, tol: float | None = None) -> SvdState:
    """Step 4 of the paper's loop ("trim U and V according to Σ"): keep the directions whose singular
    value exceeds ``tol`` (with ``tol=None`` only those below 1e-12 times the largest go), at most
    ``max_rank`` of them; the mean is unchanged. Check-free: :class:`IncrementalSVD` checks both options."""
    U, s, V, mean = state
    floor = 1e-12 * float(s.max(initial=0.0)) if tol is None else float(tol)
    keep = int(np.count_nonzero(s > floor))
    if max_rank is not None:
        keep = min(keep, int(max_rank))
    return SvdState(U[:, :keep], s[:keep], None if V is None else V[:, :keep], mean)


def update_with_mean(U: np.ndarray, s: np.ndarray, V: np.ndarray, mean: np.ndarray, I: np.ndarray, *,
                     fast: bool = True) -> SvdState:
    """Append columns ``I`` to the model ``U diag(s) V^T + mean 1^T`` and move the mean (eqs. 7-15).

    The new columns are centred on the old mean (eq. 8), appended by Brand's update (eqs. 10-11),
    then the mean of the rows of the new right factor is taken out (eqs. 12-13) and added to the
    old mean (eqs. 14-15). No truncation (:class:`IncrementalSVD` trims after each update).

    Parameters
    ----------
    U : ndarray, shape (p, r)
        Orthonormal left factor of the centred data (r may be 0).
    s : ndarray, shape (r,)
        Singular values.
    V : ndarray, shape (q, r)
        Right factor, one row per column seen; its columns sum to zero (centred data).
    mean : ndarray, shape (p,)
        Mean of the q columns seen.
    I : ndarray, shape (p, c)
        The new columns.
    fast : bool
        True: decompose the r x r matrix ``Σ_t R_v^T`` and rotate ``U_t`` once; False: the
        paper's thin SVD of the p x r matrix ``U_t Σ_t R_v^T``. Both give the same model.

    Returns
    -------
    SvdState
        The model of all q + c columns: ``U_f`` p x r', ``s_f``, ``V_f`` (q + c) x r', ``m̄_f``.

    References
    ----------
    Melenchón, Meler & Iriondo, AMDO 2004, eqs. (7)-(15) and Table 1.

    Examples
    --------
    >>> import numpy as np
    >>> M = np.random.default_rng(0).normal(size=(5, 4))
    >>> state = update_with_mean(np.zeros((5, 0)), np.zeros(0), np.zeros((0, 0)), np.zeros(5), M)
    >>> bool(np.allclose(state.mean, M.mean(axis=1)))
    True
    """
    U, s, V = _check_factors(U, s, V)
    mean = as_finite_array(mean, "mean", shape=(U.shape[0],), max_abs=MAX_ABS)
    I = as_finite_array(I, "I", shape=(U.shape[0], None), max_abs=MAX_ABS)
    fast = check_bool(fast, "fast")
    return _update_with_mean(U, s, V, mean, I, fast=fast)


def _update_with_mean(U: np.ndarray, s: np.ndarray, V: np.ndarray, mean: np.ndarray, I: np.ndarray, *,
                      fast: bool = True) -> SvdState:
    # eq. (5): the model in, M_i = U_i Σ_i V_i^T + m̄_i 1; eq. (6): the model out, of [M_i I]
    # eqs. (7)-(9): Î = I - m̄_i 1, so that [M̂_i Î] = [M_i I] - m̄_i 1
    I_hat = I - mean[:, None]
    # eqs. (10)-(11): [M̂_i Î] = U_t Σ_t V_t^T by Brand's update, U_t = [U_i Q_i] U_d
    Q, U_d, s_t, V_small, V_new = _brand_core(U, s, I_hat)
    V_t = np.vstack([V @ V_small, V_new])
    if fast:
        # eqs. (12)-(13) with U_f = U_t A = [U_i Q_i] (U_d A): one product with the p x r factor
        A, s_f, V_f, v_bar = _centre_right_factor(s_t, V_t, fast=True)
        U_f = _rotate(U, Q, U_d @ A)
        m_bar_t = _rotate(U, Q, U_d @ (s_t * v_bar))
    else:
        U_t = _rotate(U, Q, U_d)
        U_f, s_f, V_f, v_bar = _centre_right_factor(s_t, V_t, U_t=U_t, fast=False)
        m_bar_t = U_t @ (s_t * v_bar)       # eq. (12): m̄_t = U_t Σ_t v̄_t
    # eqs. (14)-(15): m̄_f = m̄_t + m̄_i
    return SvdState(U_f, s_f, V_f, mean + m_bar_t)


def extract_mean(U: np.ndarray, s: np.ndarray, V: np.ndarray, *, fast: bool = True) -> SvdState:
    """Express ``S = U diag(s) V^T`` as ``U_f diag(s_f) V_f^T + s̄ 1^T`` (Sec. 2.4).

    Eqs. (12)-(15) with ``[M̂_i Î] = S`` and the *old* mean ``m̄_i = 0``; the mean extracted is
    eq. (12)'s ``m̄_t``. (Setting ``m̄_t = 0``, as Sec. 2.4 prints, would extract nothing.)

    Parameters
    ----------
    U : ndarray, shape (p, r)
        Orthonormal left factor.
    s : ndarray, shape (r,)
        Singular values.
    V : ndarray, shape (q, r)
        Orthonormal right factor.
    fast : bool
        As in :func:`update_with_mean`.

    Returns
    -------
    SvdState
        ``(U_f, s_f, V_f, s̄)``: the thin SVD of the centred columns and their mean.

    References
    ----------
    Melenchón, Meler & Iriondo, AMDO 2004, Sec. 2.4 and eqs. (12)-(15).

    Examples
    --------
    >>> import numpy as np
    >>> S = np.random.default_rng(1).normal(size=(5, 4))
    >>> U, s, Vt = np.linalg.svd(S, full_matrices=False)
    >>> bool(np.allclose(extract_mean(U, s, Vt.T).mean, S.mean(axis=1)))
    True
    """
    U, s, V = _check_factors(U, s, V, min_rows=1)
    fast = check_bool(fast, "fast")
    # Sec. 2.4: eqs. (12)-(13) applied to S itself; the old mean m̄_i is zero, so m̄_f = m̄_t
    left, s_f, V_f, v_bar = _centre_right_factor(s, V, U_t=U, fast=fast)
    U_f = U @ left if fast else left
    return SvdState(U_f, s_f, V_f, U @ (s * v_bar))


def ross_update(U: np.ndarray, s: np.ndarray, mean: np.ndarray, n_seen: int, I: np.ndarray) -> SvdState:
    """Append columns to a centred thin SVD without its right factor (Ross et al.'s mean correction).

    The new columns, centred on their own mean, are appended with one more column,
    ``sqrt(n c / (n + c)) (ī - m̄)``, that accounts for the shift of the mean; then Brand's update
    (eq. 11) without ``V``. Same ``U``, ``s`` and mean as :func:`update_with_mean`, at a cost that does
    not grow with the number of columns seen.

    Parameters
    ----------
    U : ndarray, shape (p, r)
        Orthonormal left factor of the centred data.
    s : ndarray, shape (r,)
        Singular values.
    mean : ndarray, shape (p,)
        Mean of the ``n_seen`` columns seen.
    n_seen : int
        Number of columns seen (0 for an empty model).
    I : ndarray, shape (p, c)
        The new columns.

    Returns
    -------
    SvdState
        ``(U, s, None, mean)`` of all ``n_seen + c`` columns.

    References
    ----------
    D. A. Ross, J. Lim, R.-S. Lin, M.-H. Yang. Incremental learning for robust visual tracking.
    IJCV 77, 2008 (Sec. 3.1); Melenchón, Meler & Iriondo, AMDO 2004, eq. (11) for the update.
    """
    U, s = _check_basis(U, s)
    mean = as_finite_array(mean, "mean", shape=(U.shape[0],), max_abs=MAX_ABS)
    I = as_finite_array(I, "I", shape=(U.shape[0], None), max_abs=MAX_ABS)
    n_seen = check_positive_int(n_seen, "n_seen", minimum=0, maximum=MAX_SAMPLES)
    return _ross_update(U, s, mean, n_seen, I)


def _ross_update(U: np.ndarray, s: np.ndarray, mean: np.ndarray, n_seen: int, I: np.ndarray) -> SvdState:
    c = I.shape[1]
    batch_mean = I.mean(axis=1)
    correction = np.sqrt(n_seen * c / (n_seen + c)) * (batch_mean - mean)
    B = np.column_stack([I - batch_mean[:, None], correction])
    Q, U_d, s_t, _, _ = _brand_core(U, s, B)
    U_t = _rotate(U, Q, U_d)
    new_mean = (n_seen * mean + c * batch_mean) / (n_seen + c)
    return SvdState(U_t, s_t, None, new_mean)


#: The paper's τ (Sec. 3.2): from 0.5 down to 0.5e-3 over the first second at 25 frames/s.
TAU_START, TAU_END, TAU_FRAMES = 0.5, 5e-4, 25


def tau_schedule(t: int) -> float:
    """The threshold τ of Sec. 3.2 at frame ``t``: from 0.5 down to 0.5·10⁻³ over the first 25 frames.

    The paper gives the two ends and the duration (one second at 25 frames/s) but not the shape;
    we read it as geometric, ``TAU_START (TAU_END / TAU_START)^(t / TAU_FRAMES)``, constant at
    ``TAU_END`` afterwards.

    Parameters
    ----------
    t : int
        Frame index, 0 for the first frame; at most 1,000,000.

    Returns
    -------
    float
        τ at frame ``t``.

    References
    ----------
    Melenchón, Meler & Iriondo, AMDO 2004, Sec. 3.2.

    Examples
    --------
    >>> round(tau_schedule(25), 6)
    0.0005
    """
    t = check_positive_int(t, "t", minimum=0, maximum=MAX_SAMPLES)
    return float(TAU_START * (TAU_END / TAU_START) ** (min(t, TAU_FRAMES) / TAU_FRAMES))


def noise_edge(sigma: float, p: int, q: int) -> float:
    """The largest singular value expected of a p x q matrix of i.i.d. noise of std ``sigma``.

    ``sigma (sqrt(p) + sqrt(q))``: directions whose singular value is below it cannot be told from
    noise, a threshold with the data's units that the paper's τ lacks.

    Parameters
    ----------
    sigma : float
        Noise standard deviation per pixel, positive.
    p, q : int
        Rows (pixels) and columns (frames).

    Returns
    -------
    float
        The edge, in the data's units.

    References
    ----------
    Melenchón, Meler & Iriondo, AMDO 2004, Sec. 3.2 (the threshold it replaces).

    Examples
    --------
    >>> noise_edge(0.01, 100, 25)
    0.15
    """
    sigma = check_in_range(sigma, "sigma", 0, MAX_ABS, closed="right")
    p, q = check_positive_int(p, "p", maximum=MAX_SIDE**2), check_positive_int(q, "q", maximum=MAX_SAMPLES)
    return float(sigma * (np.sqrt(p) + np.sqrt(q)))


#: The 3 x 3 kernel of Immerkær (1996): the difference of two discrete Laplacians. It removes every
#: constant, linear and bilinear patch, so on a smooth image it leaves little but the noise, with
#: variance (1 + 4 + 1 + 4 + 16 + 4 + 1 + 4 + 1) σ² = 36 σ².
NOISE_KERNEL = np.array([[1.0, -2.0, 1.0], [-2.0, 4.0, -2.0], [1.0, -2.0, 1.0]])
#: Median absolute value of a standard normal variable: MAD / 0.6745 estimates σ.
_MAD_TO_SIGMA = 1.482602218505602


def estimate_noise(image: np.ndarray) -> float:
    """Pixel noise σ of one image, estimated from the image alone (no clean frame, no oracle).

    The image is filtered with :data:`NOISE_KERNEL`, which cancels smooth content; the median absolute
    response, robust to the few edges the kernel does not cancel, gives σ:
    ``1.4826 median|K * I| / 6``. Used by the trainers for the noise edge when no σ is given.

    Parameters
    ----------
    image : ndarray, shape (rows, cols)
        One grey-level image, at least 3 x 3, finite.

    Returns
    -------
    float
        The estimated σ, in the image's units.

    References
    ----------
    J. Immerkær. Fast noise variance estimation. Computer Vision and Image Understanding 64(2), 1996
    (the kernel; the median instead of the mean absolute response is our choice, for robustness to edges).
    Melenchón, Meler & Iriondo, AMDO 2004, Sec. 3.2 (the threshold the noise edge replaces).

    Examples
    --------
    >>> import numpy as np
    >>> noisy = np.random.default_rng(0).normal(0.5, 0.02, (200, 200))
    >>> round(estimate_noise(noisy), 2)
    0.02
    """
    image = as_finite_array(image, "image", ndim=2, max_abs=MAX_ABS)
    check_positive_int(min(image.shape), "image's smaller side", minimum=3, maximum=MAX_SIDE)
    rows, cols = image.shape
    response = np.zeros((rows - 2, cols - 2))
    for i in range(3):
        for j in range(3):
            response += NOISE_KERNEL[i, j] * image[i:i + rows - 2, j:j + cols - 2]
    return float(_MAD_TO_SIGMA * np.median(np.abs(response)) / 6.0)


#: How the mean travels: the paper's V-centring, Ross et al.'s correction column, or no mean at all.
MEAN_MODES = ("paper", "ross", "none")


class IncrementalSVD:
    """Thin SVD and mean of a stream of frames, updated by :meth:`partial_fit` (rows are frames).

    Parameters
    ----------
    max_rank : int, optional
        Largest number of directions kept after each update (step 4 of the paper's loop), 1 to 4,096.
    tol : float, optional
        Singular values at or below ``tol`` are dropped after each update (the paper's τ; same
        units as the pixels). ``None`` drops only numerically null directions. May be changed
        between calls (a schedule such as :func:`tau_schedule`).
    mean : {"paper", "ross", "none"}
        ``"paper"``: eqs. (7)-(15), which keep the right factor ``V``; ``"ross"``: Ross et al.'s
        mean-correction column, no ``V``; ``"none"``: Brand's update of the uncentred frames.

    Attributes
    ----------
    U_ : ndarray, shape (p, r)
        Orthonormal basis of the centred frames.
    singular_values_ : ndarray, shape (r,)
        Descending.
    V_ : ndarray, shape (n_seen_, r) or None
        Right factor (None for ``mean="ross"``).
    mean_ : ndarray, shape (p,)
        Mean frame (zeros for ``mean="none"``).
    n_seen_ : int
        Frames seen.

    References
    ----------
    Melenchón, Meler & Iriondo. On-the-Fly Training. AMDO 2004, LNCS 3179, eqs. (7)-(15) and Sec. 3.2.

    Examples
    --------
    >>> import numpy as np
    >>> frames = np.random.default_rng(0).normal(size=(10, 6))
    >>> model = IncrementalSVD()
    >>> for frame in frames:
    ...     _ = model.partial_fit(frame[None])
    >>> bool(np.allclose(model.mean_, frames.mean(axis=0)))
    True
    """

    def __init__(self, *, max_rank: int | None = None, tol: float | None = None, mean: str = "paper") -> None:
        self.max_rank = max_rank
        self.tol = tol
        self.mean = mean

    def partial_fit(self, X: np.ndarray) -> IncrementalSVD:
        """Add the frames ``X`` (one per row) to the model.

        Parameters
        ----------
        X : ndarray, shape (c, p)
            New frames, finite; p must match the frames seen before.

        Returns
        -------
        IncrementalSVD
            ``self``.
        """
        # step 4's options: a rank cap and a threshold τ >= 0 (the data's units)
        if self.max_rank is not None:
            check_positive_int(self.max_rank, "max_rank", maximum=MAX_SIDE)
        if self.tol is not None:
            check_positive(self.tol, "tol", allow_zero=True)
        check_choice(self.mean, "mean", MEAN_MODES)
        fitted = getattr(self, "U_", None) is not None  # then X must have the model's p pixels (columns)
        X = as_finite_array(X, "X", shape=(None, self.U_.shape[0] if fitted else None), max_abs=MAX_ABS)
        if not fitted:
            p = X.shape[1]
            self.U_, self.singular_values_ = np.zeros((p, 0)), np.zeros(0)
            self.V_ = None if self.mean == "ross" else np.zeros((0, 0))
            self.mean_, self.n_seen_ = np.zeros(p), 0
        I = X.T
        with one_blas_thread():  # thin products (p x r by r x r): more threads only contend
            if self.mean == "paper":
                state = _update_with_mean(self.U_, self.singular_values_, self.V_, self.mean_, I)
            elif self.mean == "ross":
                state = _ross_update(self.U_, self.singular_values_, self.mean_, self.n_seen_, I)
            else:
                state = _brand_update(self.U_, self.singular_values_, self.V_, I)
        U, s, V, mean = _truncate(state, max_rank=self.max_rank, tol=self.tol)
        self.U_, self.singular_values_, self.V_, self.mean_ = U, s, V, mean
        self.n_seen_ += X.shape[0]
        return self

    @property
    def state(self) -> SvdState:
        """The model as ``(U, s, V, mean)``."""
        check_fitted(self, ["U_", "mean_"])
        return SvdState(self.U_, self.singular_values_, self.V_, self.mean_)

    def transform(self, X: np.ndarray) -> np.ndarray:
        """Coefficients of the frames ``X`` in the basis: ``(X - mean) U`` (the paper's ``C^T``).

        Parameters
        ----------
        X : ndarray, shape (n, p)
            Frames.

        Returns
        -------
        ndarray, shape (n, r)
            Coefficients.
        """
        U, _, _, mean = self.state  # the state checks that the model is fitted
        X = as_finite_array(X, "X", shape=(None, U.shape[0]), max_abs=MAX_ABS)
        return (X - mean) @ U

    def reconstruct(self, X: np.ndarray) -> np.ndarray:
        """Project the frames ``X`` on the model: ``mean + (X - mean) U U^T``.

        Parameters
        ----------
        X : ndarray, shape (n, p)
            Frames.

        Returns
        -------
        ndarray, shape (n, p)
            Their reconstructions from ``r`` coefficients each.
        """
        # eq. (2): a frame is m̄ + U c, with its coefficients c = U^T (x - m̄) (:meth:`transform`, which checks X)
        return self.mean_ + self.transform(X) @ self.U_.T

    def memory_bytes(self) -> int:
        """Bytes held by the model's arrays ``U``, ``s``, ``V`` and the mean.

        Returns
        -------
        int
            ``8 (p r + r + q r + p)`` for float64 arrays.
        """
        arrays = self.state  # the state checks that the model is fitted; V is None under mean="ross"
        return int(sum(a.nbytes for a in arrays if a is not None))
