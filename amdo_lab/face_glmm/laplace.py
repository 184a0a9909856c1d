"""The Laplace deviance of eq. (2): the binomial deviance, a dense reference path and the fast path.

For given random-effect standard deviations σ, penalised IRLS finds the joint mode of (β, u) with
b = Λu, and the Laplace deviance is dev(y, η) + |u|² + log det(Λ Z'WZ Λ + I) (lme4's ``nAGQ=0``).
Two paths compute it:

- :func:`laplace_deviance_reference`: plain dense numpy, one line per equation (read this first);
- :class:`CrossedProblem`: the same numbers fast. Every row lies in exactly one level of each
  grouping term, so every block of Z'WZ and Z'WX is a table of weight sums over level pairs; the
  largest term (t:p) has a diagonal block and is eliminated by a Schur complement; when the other
  terms are nested in it (t and p in t:p) all blocks follow from sums over its levels.

Tests check that the two paths agree to 1e-10. :mod:`amdo_lab.face_glmm.glmm` fits the model with them.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import scipy.linalg
import scipy.sparse as sp
from scipy.special import expit, xlogy

from amdo_lab.common import as_finite_array, check_positive_int

__all__ = ["CrossedProblem", "MAX_ABS_ETA", "MAX_SD", "MAX_TRIALS", "laplace_deviance_reference"]


#: Largest binomial size accepted (integers up to it are exact floats).
MAX_TRIALS = 1e15
#: Largest |linear predictor| accepted, logit units.
MAX_ABS_ETA = 1e6
#: Largest random-effect standard deviation accepted (logit units): sd = 1e3 already puts every
#: probability at 0 or 1 to machine precision, and larger ones overflow the penalised IRLS.
MAX_SD = 1e3


def _binomial_deviance(y: np.ndarray, n_trials: np.ndarray, eta: np.ndarray, saturated: float | None = None) -> float:
    """Binomial deviance 2 sum[y log(y/mu) + (n-y) log((n-y)/(n-mu))], mu = n expit(eta), on checked
    counts, sizes and linear predictor (the IRLS loop's inner call), written with log-expit of the
    linear predictor so that p -> 0 or 1 stays finite (the dev(y, eta) term of eq. (2)'s Laplace deviance).

    ``saturated`` = sum[y log(y/n) + (n-y) log((n-y)/n)], which does not depend on eta, may be
    passed in once; the fitted log-likelihood uses y log p + (n-y) log(1-p) = y eta + n log(1-p).
    """
    if saturated is None:
        saturated = float(np.sum(xlogy(y, y / n_trials) + xlogy(n_trials - y, (n_trials - y) / n_trials)))
    log_one_minus_p = -np.logaddexp(0.0, eta)  # log(1 - expit(eta)), finite for any eta
    fitted = y @ eta + (n_trials @ log_one_minus_p if np.ndim(n_trials) else n_trials * np.sum(log_one_minus_p))
    return float(2.0 * (saturated - fitted))


def _laplace_deviance_reference(y: np.ndarray, n_trials: np.ndarray, x: np.ndarray, z: np.ndarray,
                                lam: np.ndarray, *, tol: float = 1e-12, max_iter: int = 100) -> tuple:
    """Plain dense numpy: penalised IRLS to the joint mode, then the Laplace deviance.

    The readable version of what :class:`CrossedProblem` computes fast; tests check they agree.

    Parameters
    ----------
    y, n_trials : (n,) success counts and binomial sizes.
    x : (n, p) fixed-effects design.
    z : (n, q) dense 0/1 random-effects design, one column per level of every grouping term.
    lam : (q,) the standard deviation sigma_k of the term each column belongs to (Lambda's diagonal).

    Returns
    -------
    (beta, u, objective, hessian): the joint mode, the Laplace deviance and the penalised Hessian
    ``[[Lambda Z'WZ Lambda + I, Lambda Z'WX], [X'WZ Lambda, X'WX]]`` at the mode.

    References
    ----------
    Bates, Maechler, Bolker & Walker (2015), J. Stat. Softw. 67, Sec. 3 (penalised least squares);
    Breslow & Clayton (1993), JASA 88, eqs. (5)-(7) (the Laplace approximation); the model is eq. (2)
    of Givens et al. (2004) with b = Lambda u.
    """
    n, p = x.shape
    q = z.shape[1]
    # eq. (2): Y ~ Binomial(n, expit(η)), η = Xβ + Zb with b = Λu, u ~ N(0, I): η = [ZΛ, X] (u, β)
    design = np.hstack([z * lam, x])                 # [Z Lambda, X]: columns u first, then beta
    penalty = np.r_[np.ones(q), np.zeros(p)]         # |u|^2 penalises u only
    coef = np.zeros(q + p)
    rate = np.clip(y.sum() / n_trials.sum(), 1e-3, 1 - 1e-3)
    coef[q] = np.log(rate / (1 - rate))               # start: the pooled logit, first column = intercept

    def penalised_deviance(c):
        return _binomial_deviance(y, n_trials, design @ c) + c[:q] @ c[:q]

    current = penalised_deviance(coef)
    for _ in range(max_iter):
        eta = design @ coef
        prob = np.clip(expit(eta), 1e-12, 1 - 1e-12)
        w = n_trials * prob * (1 - prob)              # IRLS weights
        working = eta + (y - n_trials * prob) / w     # working response
        # Penalised weighted least squares: (A'WA + diag(penalty)) c = A'W working
        hessian = design.T @ (w[:, None] * design) + np.diag(penalty)
        proposal = np.linalg.solve(hessian, design.T @ (w * working))
        step = 1.0
        for _ in range(30):                           # step halving: the penalised deviance must not rise
            trial = coef + step * (proposal - coef)
            value = penalised_deviance(trial)
            if value <= current + 1e-10 * abs(current):
                break
            step /= 2
        change, coef, current = current - value, trial, value
        if abs(change) < tol * (abs(current) + 1.0):
            break
    eta = design @ coef
    prob = np.clip(expit(eta), 1e-12, 1 - 1e-12)
    w = n_trials * prob * (1 - prob)
    hessian = design.T @ (w[:, None] * design) + np.diag(penalty)
    # Laplace deviance (lme4's nAGQ=0): dev(y, eta) + |u|^2 + log det(Lambda Z'WZ Lambda + I)
    _, logdet = np.linalg.slogdet(hessian[:q, :q])
    return coef[q:], coef[:q], current + logdet, hessian



def laplace_deviance_reference(y: np.ndarray, n_trials: np.ndarray, x: np.ndarray, z: np.ndarray,
                               sd_of_columns: np.ndarray) -> tuple[np.ndarray, np.ndarray, float, np.ndarray]:
    """The Laplace deviance of eq. (2) by plain dense numpy: penalised IRLS to the joint mode, then the deviance.

    The readable path of what :func:`amdo_lab.face_glmm.fit_binomial_glmm` minimises (its fast path,
    :class:`CrossedProblem`, gives the same numbers; the tests check it to 1e-10).

    Parameters
    ----------
    y : array_like, shape (n,)
        Success counts, each in [0, n_trials].
    n_trials : float or array_like, shape (n,)
        Binomial sizes, one per count or one for all, each in (0, 1e15].
    x : array_like, shape (n, p)
        Fixed-effects design of full rank, entries within ±1e6, the first column the intercept.
    z : array_like, shape (n, q)
        Dense 0/1 random-effects design: one column per level of every grouping term.
    sd_of_columns : array_like, shape (q,)
        Λ's diagonal: the standard deviation σ_k of the term each column of ``z`` belongs to, in [0, 1e3].

    Returns
    -------
    beta : numpy.ndarray
        (p,) fixed effects at the joint mode.
    u : numpy.ndarray
        (q,) spherical random effects at the mode (b = Λu).
    deviance : float
        The Laplace deviance dev(y, η) + |u|² + log det(Λ Z'WZ Λ + I).
    hessian : numpy.ndarray
        (q + p, q + p) penalised Hessian ``[[Λ Z'WZ Λ + I, Λ Z'WX], [X'WZ Λ, X'WX]]`` at the mode.

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, eq. (2); Bates, Maechler, Bolker & Walker (2015),
    J. Stat. Softw. 67, Sec. 3; Breslow & Clayton (1993), JASA 88, eqs. (5)-(7).
    """
    y = as_finite_array(y, "y", bounds=(0.0, MAX_TRIALS))
    n_trials = as_finite_array(n_trials, "n_trials", bounds=(0.0, MAX_TRIALS), closed="right")
    if n_trials.shape not in ((), y.shape):
        raise ValueError(f"n_trials must be a number or have the shape of y {y.shape}, got {n_trials.shape}")
    if np.any(y > n_trials):
        raise ValueError("y must hold counts in [0, n_trials]")
    n_trials = np.broadcast_to(n_trials, y.shape)
    x = as_finite_array(x, "x", shape=(y.size, None), max_abs=MAX_ABS_ETA)
    z = as_finite_array(z, "z", shape=(y.size, None), bounds=(0.0, 1.0))
    # one entry per column of z: the message names both, since either may be the one at fault
    sd_of_columns = as_finite_array(sd_of_columns, "sd_of_columns (like the columns of z)", shape=z.shape[1:],
                                    bounds=(0.0, MAX_SD))
    check_positive_int(int(np.linalg.matrix_rank(x)), "the column rank of x", minimum=x.shape[1])  # full rank
    return _laplace_deviance_reference(y, n_trials, x, z, sd_of_columns)


class _PairSums:
    """Sums of a row weight over the (a, b) level pairs of two index arrays, with a fixed sparsity.

    ``sums(w)`` is the (n_a, n_b) matrix ``A' diag(w) B`` of the 0/1 indicator matrices A and B,
    computed as one ``bincount`` over the pairs that occur (found once, at construction).
    """

    def __init__(self, a: np.ndarray, n_a: int, b: np.ndarray, n_b: int):
        self.pair_of_row, codes = pd.factorize(a.astype(np.int64) * n_b + b, sort=True)
        self.rows, self.cols = codes // n_b, codes % n_b
        self.shape = (n_a, n_b)
        self.indptr = np.r_[0, np.cumsum(np.bincount(self.rows, minlength=n_a))]

    def sums(self, w: np.ndarray) -> np.ndarray:
        return np.bincount(self.pair_of_row, weights=w, minlength=self.rows.size)

    def sparse(self, w: np.ndarray) -> sp.csr_matrix:
        return self.sparse_from_sums(self.sums(w))

    def sparse_from_sums(self, sums: np.ndarray) -> sp.csr_matrix:
        return sp.csr_matrix((sums, self.cols, self.indptr), shape=self.shape)

    def dense_from_sums(self, sums: np.ndarray) -> np.ndarray:
        table = np.zeros(self.shape)
        table[self.rows, self.cols] = sums
        return table


class _SparseCoupling:
    """The u_rest-u_big block A_rb of the penalised Hessian as a scipy sparse matrix (general case)."""

    def __init__(self, matrix: sp.csr_matrix):
        self.matrix = matrix

    def matvec(self, x_big):
        return self.matrix @ x_big

    def rmatvec(self, v_rest):
        return self.matrix.T @ v_rest

    def times(self, dense_big):
        return self.matrix @ dense_big

    def gram(self, d_big):
        """A_rb diag(d) A_rb' as a dense (q_rest, q_rest) matrix."""
        return (self.matrix @ sp.diags(d_big) @ self.matrix.T).toarray()


class CrossedProblem:
    """The fast path of :func:`_laplace_deviance_reference` for crossed random intercepts.

    Every row lies in exactly one level of each grouping term, so every block of Z'WZ and Z'WX
    is a table of weight sums over level pairs (:class:`_PairSums`), never an n-row product. The
    penalised Hessian is factorised by block elimination in a fill-reducing order fixed once, from
    the structure, at construction (the "symbolic analysis", reused at every evaluation):

    1. the largest term ("big", e.g. t:p) has a *diagonal* block: it is eliminated first (a Schur
       complement costing one pass over its levels);
    2. when every other term is nested in the big one (t and p in t:p: each t:p level has one t and
       one p), every other term's own block of that Schur complement is diagonal too, so the largest
       of them (p on a design with many probes) is eliminated next, again at the cost of one pass
       over the big levels; only the remaining small terms (t) and the fixed effects are factorised
       densely (Cholesky of a (q_small + p) matrix). Cost per IRLS step: O(n + q_big p + q_small^3);
    3. otherwise (terms not nested in the big one: t:U, row-level terms) the other terms and the
       fixed effects form one dense system (q_rest + p unknowns).

    The sums run over the smallest units that carry them: the big levels when every other term is
    nested in the big one; the (big level, distinct X row) cells when every other term is a function
    of the cell (t:U:M:D); the rows otherwise.
    """

    def __init__(self, y, n_trials, x, groups):
        self.y, self.n_trials, self.x = y, n_trials, x
        self.n, self.p = x.shape
        self.sizes = [int(g.max()) + 1 for g in groups]
        self.big = int(np.argmax(self.sizes))
        self.rest = [k for k in range(len(groups)) if k != self.big]
        self.q_big = self.sizes[self.big]
        self.g_big = groups[self.big]
        offsets = np.cumsum([0] + [self.sizes[k] for k in self.rest])
        self.rest_offsets = offsets
        self.rest_cols = [offsets[i] + groups[k] for i, k in enumerate(self.rest)]  # columns of u_rest
        self.q_rest = int(offsets[-1])
        self.rest_term_of_col = np.concatenate([np.full(self.sizes[k], k) for k in self.rest]) \
            if self.rest else np.zeros(0, dtype=int)
        # distinct rows of X, found by hashing each row's bytes (np.unique(axis=0) sorts, 10x slower)
        self.x_row, distinct = pd.factorize(np.ascontiguousarray(x).view(f"S{x.itemsize * self.p}").ravel())
        first_row = np.empty(distinct.size, dtype=np.int64)
        first_row[self.x_row[::-1]] = np.arange(self.n)[::-1]   # the first row holding each distinct X row
        self.x_unique = x[first_row]
        self.saturated = float(np.sum(xlogy(y, y / n_trials) + xlogy(n_trials - y, (n_trials - y) / n_trials)))
        r = self.x_unique.shape[0]
        n_rest = len(self.rest)
        q_rest = max(self.q_rest, 1)
        # Cells: the distinct (big level, X row) pairs. Every block is a sum over cells whenever each
        # rest term is a function of the cell (t:U:M:D is: t from t:p, U, M, D from the X row).
        self.big_x = _PairSums(self.g_big, self.q_big, self.x_row, r)
        cell_of_row = self.big_x.pair_of_row
        n_cells = self.big_x.rows.size
        self.cell_cols = []
        for cols in self.rest_cols:
            per_cell = np.zeros(n_cells, dtype=np.int64)
            per_cell[cell_of_row] = cols
            if not np.array_equal(per_cell[cell_of_row], cols):
                self.cell_cols = None
                break
            self.cell_cols.append(per_cell)
        self.sum_over_cells = self.cell_cols is not None
        # Nested: each rest term is a function of the big level (parent[k] = its rest column).
        self.parents = []
        for cols in self.rest_cols:
            parent = np.zeros(self.q_big, dtype=np.int64)
            parent[self.g_big] = cols
            if not np.array_equal(parent[self.g_big], cols):
                self.parents = []
                break
            self.parents.append(parent)
        self.nested = bool(self.parents)
        self.n_rest = n_rest
        if self.nested:
            self._plan_nested()
            return
        # General case: pair tables over stacked copies of the units (cells when possible, else
        # rows; one copy per rest term, or per pair of terms); the unit weights are tiled alike.
        unit_cols = self.cell_cols if self.sum_over_cells else self.rest_cols
        unit_big = self.big_x.rows if self.sum_over_cells else self.g_big
        unit_x = self.big_x.cols if self.sum_over_cells else self.x_row
        empty = np.zeros(0, dtype=int)
        all_rest = np.concatenate(unit_cols) if n_rest else empty
        self.rest_rest = _PairSums(np.concatenate([a for a in unit_cols for _ in unit_cols]) if n_rest else empty,
                                   q_rest,
                                   np.concatenate([b for _ in unit_cols for b in unit_cols]) if n_rest else empty,
                                   q_rest)
        self.rest_big = _PairSums(all_rest, q_rest, np.tile(unit_big, n_rest), self.q_big)
        self.rest_x = _PairSums(all_rest, q_rest, np.tile(unit_x, n_rest), r)
        self.all_rest = all_rest

    def _plan_nested(self):
        """The elimination order of the nested case, fixed once: big, then the largest rest term
        ("second"), then the other rest terms ("small") with beta, densely."""
        sizes = [self.sizes[k] for k in self.rest]
        self.second = int(np.argmax(sizes))                       # position in self.rest
        self.small = [i for i in range(self.n_rest) if i != self.second]
        self.q_second = sizes[self.second]
        q_big = self.q_big
        local = [self.parents[i] - self.rest_offsets[i] for i in range(self.n_rest)]  # level within its term
        # R' of the second term: (q_second, q_big), one 1 per column
        self.second_parent = local[self.second]
        self.second_of_big = sp.csr_matrix((np.ones(q_big), (local[self.second], np.arange(q_big))),
                                           shape=(self.q_second, q_big))
        # Z_b'WX = (sums over the (big level, X row) cells) @ X_unique: a fixed sparsity pattern
        self.big_x_matrix = self.big_x.sparse_from_sums(np.zeros(self.big_x.rows.size))
        small_offsets = np.cumsum([0] + [sizes[i] for i in self.small])
        self.q_small = int(small_offsets[-1])
        self.small_cols = (np.concatenate([self.rest_offsets[i] + np.arange(sizes[i]) for i in self.small])
                           if self.small else np.zeros(0, dtype=np.int64))   # their columns in u_rest
        self.second_cols = self.rest_offsets[self.second] + np.arange(self.q_second)
        if self.small:
            small_parent = [small_offsets[j] + local[i] for j, i in enumerate(self.small)]
            n_small = len(self.small)
            stacked = np.concatenate(small_parent)
            self.small_of_big = sp.csr_matrix((np.ones(stacked.size), (stacked, np.tile(np.arange(q_big), n_small))),
                                              shape=(self.q_small, q_big))           # R' of the small terms
            self.small_pairs = _PairSums(np.concatenate([a for a in small_parent for _ in small_parent]), self.q_small,
                                         np.concatenate([b for _ in small_parent for b in small_parent]), self.q_small)
            self.small_second = _PairSums(stacked, self.q_small, np.tile(local[self.second], n_small), self.q_second)

    def _tile(self, w, times):
        return np.tile(w, times) if times > 1 else w

    def _linear_predictor(self, beta, u_rest, u_big, theta):
        """eta = X beta + Z Λ u (eq. 2), gathered from the distinct X rows and the levels."""
        b_rest = theta[self.rest_term_of_col] * u_rest
        if self.nested:  # every term is a function of the big level: one gather per row
            b_big = theta[self.big] * u_big + sum(b_rest[parent] for parent in self.parents)
            return (self.x_unique @ beta)[self.x_row] + b_big[self.g_big]
        eta = (self.x_unique @ beta)[self.x_row] + theta[self.big] * u_big[self.g_big]
        for cols in self.rest_cols:
            eta += b_rest[cols]
        return eta

    def _big_sums(self, w, wz):
        """Z_b'W 1, Z_b'Wz, Z_b'WX, X'WX and X'Wz (the last three via the distinct rows of X)."""
        x_u, n_x = self.x_unique, self.x_unique.shape[0]
        if self.nested or self.sum_over_cells:  # one pass over the rows: sums per (big level, X row) cell
            cell_w, cell_wz = self.big_x.sums(w), self.big_x.sums(wz)
            x_w = np.bincount(self.big_x.cols, cell_w, minlength=n_x)
            x_wz = np.bincount(self.big_x.cols, cell_wz, minlength=n_x)
            big_w = np.bincount(self.big_x.rows, cell_w, minlength=self.q_big)
            big_wz = np.bincount(self.big_x.rows, cell_wz, minlength=self.q_big)
            if self.nested:   # the pattern is fixed: refill the matrix built at construction
                self.big_x_matrix.data[:] = cell_w
                big_x = self.big_x_matrix @ x_u                          # Z_b'WX, (q_big, p)
            else:
                big_x = self.big_x.sparse_from_sums(cell_w) @ x_u
        else:
            cell_w = cell_wz = None
            x_w = np.bincount(self.x_row, w, minlength=n_x)
            x_wz = np.bincount(self.x_row, wz, minlength=n_x)
            big_w = np.bincount(self.g_big, w, minlength=self.q_big)
            big_wz = np.bincount(self.g_big, wz, minlength=self.q_big)
            big_x = self.big_x.sparse(w) @ x_u
        a_xx = x_u.T @ (x_w[:, None] * x_u)                              # X'WX
        rhs_x = x_u.T @ x_wz                                             # X'Wz
        return big_w, big_wz, big_x, a_xx, rhs_x, cell_w, cell_wz

    def _step_nested(self, w, wz, theta):
        """Newton direction, log det(Λ Z'WZ Λ + I) and the Cholesky factor of beta's precision (nested case).

        Blocks of the penalised Hessian H (b = big, r = rest, x = beta; R' sums big levels into their
        rest levels; g = 1 / a_bb): H_bb = diag(a_bb), a_bb = λ_b² w_b + 1; H_rb = Λ_r R' diag(λ_b w_b);
        H_xb = λ_b B', B = Z_b'WX. Eliminating b leaves S_rr = Λ_r R' diag(w_b g) R Λ_r + I,
        S_rx = Λ_r R' diag(g) B, S_xx = X'WX - λ_b² B' diag(g) B (as 1 - λ_b² w_b g = g).
        """
        big_w, big_wz, big_x, a_xx, rhs_x, _, _ = self._big_sums(w, wz)
        lam_b = theta[self.big]
        a_bb = lam_b**2 * big_w + 1.0                  # Λ_b Z_b'WZ_b Λ_b + I, diagonal
        g = 1.0 / a_bb
        w_g, wz_g, b_g = big_w * g, big_wz * g, g[:, None] * big_x
        # Schur complement of the big block: S_xx and the reduced right-hand sides
        s_xx = a_xx - lam_b**2 * (big_x.T @ b_g)
        r_x = rhs_x - lam_b**2 * (big_x.T @ wz_g)
        # the second term's block of S_rr is diagonal (each big level has one parent): eliminate it next
        lam_2 = theta[self.rest[self.second]]
        d_2 = lam_2**2 * np.bincount(self.second_parent, w_g, minlength=self.q_second) + 1.0
        inv_d = 1.0 / d_2
        s_2x = lam_2 * (self.second_of_big @ b_g)                      # (q_second, p)
        r_2 = lam_2 * np.bincount(self.second_parent, wz_g, minlength=self.q_second)
        qs = self.q_small
        if qs:
            n_small = len(self.small)
            lam_s = theta[self.rest_term_of_col[self.small_cols]]
            s_ss = lam_s[:, None] * self.small_pairs.dense_from_sums(
                self.small_pairs.sums(self._tile(w_g, n_small**2))) * lam_s[None, :] + np.eye(qs)
            s_sx = lam_s[:, None] * (self.small_of_big @ b_g)
            r_s = lam_s * (self.small_of_big @ wz_g)
            s_s2 = (lam_s * lam_2)[:, None] * self.small_second.dense_from_sums(
                self.small_second.sums(self._tile(w_g, n_small)))       # (q_small, q_second), dense
            # Schur complement of the second block: T = S_vv - S_v2 diag(1/d_2) S_2v, v = (small, beta)
            s_v2 = np.vstack([s_s2, s_2x.T])
            t_mat = np.block([[s_ss, s_sx], [s_sx.T, s_xx]]) - (s_v2 * inv_d) @ s_v2.T
            rhs_v = np.r_[r_s, r_x] - s_v2 @ (inv_d * r_2)
        else:
            s_s2 = None
            t_mat = s_xx - s_2x.T @ (inv_d[:, None] * s_2x)
            rhs_v = r_x - s_2x.T @ (inv_d * r_2)
        chol = scipy.linalg.cholesky(t_mat)            # upper: T = U'U
        v = scipy.linalg.cho_solve((chol, False), rhs_v)
        u_small, beta = v[:qs], v[qs:]
        u_2 = (r_2 - s_2x @ beta - (s_s2.T @ u_small if qs else 0.0)) * inv_d
        u_rest = np.empty(self.q_rest)
        u_rest[self.second_cols], u_rest[self.small_cols] = u_2, u_small
        lam_r = theta[self.rest_term_of_col] * u_rest          # b_rest = Λ_r u_r
        b_r_of_big = sum(lam_r[parent] for parent in self.parents)
        u_big = lam_b * (big_wz - big_w * b_r_of_big - big_x @ beta) * g
        # log det(Λ Z'WZ Λ + I) = log det H_bb + log det S_22 + log det T_ss
        logdet = float(np.sum(np.log(a_bb)) + np.sum(np.log(d_2)) + 2.0 * np.sum(np.log(np.diag(chol)[:qs])))
        return (beta, u_rest, u_big), logdet, chol[qs:, qs:]

    def _blocks(self, w, wz, theta):
        """The penalised normal equations in blocks (general case): v = (u_rest, beta) dense, u_big diagonal.

        Returns ``(a_vv, a_rb, a_xb, a_bb, rhs_v, rhs_b)``: the dense (u_rest, beta) block, the sparse
        u_rest-u_big and dense beta-u_big couplings, the diagonal of the u_big block, right-hand sides.
        """
        lam_r, lam_b = theta[self.rest_term_of_col], theta[self.big]
        big_w, big_wz, big_x, a_xx, rhs_x, cell_w, cell_wz = self._big_sums(w, wz)
        a_xb = lam_b * big_x.T                                           # X'WZ_b Lambda_b
        a_bb = lam_b**2 * big_w + 1.0                                    # Lambda_b Z_b'WZ_b Lambda_b + I (diagonal)
        rhs_b = lam_b * big_wz
        if not self.q_rest:
            return a_xx, None, a_xb, a_bb, rhs_x, rhs_b
        units_w, units_wz = (cell_w, cell_wz) if self.sum_over_cells else (w, wz)
        w_k = self._tile(units_w, self.n_rest)
        rest_rest = np.zeros(self.rest_rest.shape)
        rest_rest[self.rest_rest.rows, self.rest_rest.cols] = self.rest_rest.sums(
            self._tile(units_w, self.n_rest**2))
        rest_big = self.rest_big.sparse(w_k)
        rest_x = self.rest_x.sparse(w_k) @ self.x_unique
        rest_wz = np.bincount(self.all_rest, self._tile(units_wz, self.n_rest), minlength=self.q_rest)
        a_rb = _SparseCoupling(sp.diags(lam_r * lam_b) @ rest_big)
        a_rr = lam_r[:, None] * rest_rest * lam_r[None, :] + np.eye(self.q_rest)
        a_rx = lam_r[:, None] * rest_x
        a_vv = np.block([[a_rr, a_rx], [a_rx.T, a_xx]])
        return a_vv, a_rb, a_xb, a_bb, np.r_[lam_r * rest_wz, rhs_x], rhs_b

    def _schur(self, a_vv, a_rb, a_xb, a_bb):
        """a_vv - A_vb diag(1/a_bb) A_vb', with A_vb = [a_rb (a coupling operator); a_xb (dense)]."""
        inv_bb = 1.0 / a_bb
        nr = self.q_rest
        schur = a_vv.copy()
        schur[nr:, nr:] -= (a_xb * inv_bb) @ a_xb.T
        if nr:
            schur[:nr, :nr] -= a_rb.gram(inv_bb)
            cross = a_rb.times(inv_bb[:, None] * a_xb.T)
            schur[:nr, nr:] -= cross
            schur[nr:, :nr] -= cross.T
        return schur

    def _step_general(self, w, wz, theta):
        """Newton direction, log det(Λ Z'WZ Λ + I) and the Cholesky factor of beta's precision (general case)."""
        nr = self.q_rest
        a_vv, a_rb, a_xb, a_bb, rhs_v, rhs_b = self._blocks(w, wz, theta)
        chol = scipy.linalg.cholesky(self._schur(a_vv, a_rb, a_xb, a_bb))
        a_vb_rhs = np.r_[a_rb.matvec(rhs_b / a_bb), a_xb @ (rhs_b / a_bb)] if nr else a_xb @ (rhs_b / a_bb)
        v = scipy.linalg.cho_solve((chol, False), rhs_v - a_vb_rhs)
        new_big = (rhs_b - (a_rb.rmatvec(v[:nr]) if nr else 0.0) - a_xb.T @ v[nr:]) / a_bb
        # log det(Lambda Z'WZ Lambda + I) = log det(A_bb) + log det(the u_rest block of the Schur complement)
        logdet = float(np.sum(np.log(a_bb)) + 2.0 * np.sum(np.log(np.diag(chol)[:nr])))
        return (v[nr:], v[:nr], new_big), logdet, chol[nr:, nr:]

    def solve(self, theta, beta, u_rest, u_big, tol=1e-12, max_iter=100):
        """Penalised IRLS at fixed theta, warm-started from (beta, u_rest, u_big).

        Returns ``(beta, u_rest, u_big, objective, chol_beta, iterations)``: the joint mode, the Laplace
        deviance and the upper Cholesky factor of beta's precision (the inverse of its covariance).
        """
        step_of = self._step_nested if self.nested else self._step_general
        coef = (beta, u_rest, u_big)
        eta = self._linear_predictor(*coef, theta)
        current = _binomial_deviance(self.y, self.n_trials, eta, self.saturated) + u_rest @ u_rest + u_big @ u_big
        for iteration in range(max_iter):
            prob = np.clip(expit(eta), 1e-12, 1 - 1e-12)
            w = self.n_trials * prob * (1 - prob)
            wz = w * eta + (self.y - self.n_trials * prob)          # W times the working response
            proposal, _, _ = step_of(w, wz, theta)
            eta_new = self._linear_predictor(*proposal, theta)
            step, eta_t, trial = 1.0, eta_new, proposal
            for _ in range(30):  # step halving: eta is linear in the coefficients
                value = (_binomial_deviance(self.y, self.n_trials, eta_t, self.saturated)
                         + trial[1] @ trial[1] + trial[2] @ trial[2])
                if value <= current + 1e-10 * abs(current):
                    break
                step /= 2
                eta_t = eta + step * (eta_new - eta)
                trial = tuple(old + step * (new - old) for old, new in zip(coef, proposal))
            change, coef, eta, current = current - value, trial, eta_t, value
            if abs(change) < tol * (abs(current) + 1.0):
                break
        prob = np.clip(expit(eta), 1e-12, 1 - 1e-12)
        w = self.n_trials * prob * (1 - prob)
        _, logdet, chol_beta = step_of(w, w * eta, theta)
        return coef[0], coef[1], coef[2], current + logdet, chol_beta, iteration + 1
