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


class _NestedCoupling:
    """A_rb = diag(lam_r) R' diag(c) when every rest term is nested in the big one.

    R maps each big level to its level of every rest term (``parents``), so products with A_rb are
    gathers and bincounts over the q_big levels, never over the n rows.
    """

    def __init__(self, problem, lam_r, c_big):
        self.problem, self.lam_r, self.c = problem, lam_r, c_big

    def matvec(self, x_big):
        return self.lam_r * self.problem.rest_sums(self.c * x_big)

    def rmatvec(self, v_rest):
        scaled = self.lam_r * v_rest
        return self.c * sum(scaled[parent] for parent in self.problem.parents)

    def times(self, dense_big):
        return self.lam_r[:, None] * (self.problem.rest_of_big @ (self.c[:, None] * dense_big))

    def gram(self, d_big):
        return self.lam_r[:, None] * self.problem.rest_pair_table(self.c**2 * d_big) * self.lam_r[None, :]


class CrossedProblem:
    """The fast path of :func:`_laplace_deviance_reference` for crossed random intercepts.

    Every row lies in exactly one level of each grouping term, so every block of Z'WZ and Z'WX
    is a table of weight sums over level pairs (:class:`_PairSums`), never an n-row product:
    - the largest term ("big", e.g. t:p) has a *diagonal* block Z_b'WZ_b; it is eliminated by a
      Schur complement, and its coupling to the other terms is a sparse matrix;
    - the remaining terms and the fixed effects form a small dense system (q_rest + p unknowns);
    - X has few distinct rows (factor codings), so X'WX and Z'WX are sums over those rows.
    The sums run over the smallest units that carry them: the big levels when every other term is
    nested in the big one (t, p in t:p: ``_NestedCoupling``); the (big level, distinct X row) cells
    when every other term is a function of the cell (t:U:M:D); the rows otherwise.
    Cost per IRLS step: a few passes over the n rows plus O(q_big p^2 + (q_rest + p)^3).
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
        # units: the things the general pair tables sum over (cells when possible, else rows)
        unit_cols = self.cell_cols if self.sum_over_cells else self.rest_cols
        unit_big = self.big_x.rows if self.sum_over_cells else self.g_big
        unit_x = self.big_x.cols if self.sum_over_cells else self.x_row
        # Pair tables over stacked copies of the units (one copy per rest term, or per pair of
        # terms); the unit weights are tiled the same number of times.
        empty = np.zeros(0, dtype=int)
        all_rest = np.concatenate(unit_cols) if n_rest else empty
        self.rest_rest = _PairSums(np.concatenate([a for a in unit_cols for _ in unit_cols]) if n_rest else empty,
                                   q_rest,
                                   np.concatenate([b for _ in unit_cols for b in unit_cols]) if n_rest else empty,
                                   q_rest)
        self.rest_big = _PairSums(all_rest, q_rest, np.tile(unit_big, n_rest), self.q_big)
        self.rest_x = _PairSums(all_rest, q_rest, np.tile(unit_x, n_rest), r)
        self.all_rest = all_rest
        self.n_rest = n_rest
        # When every other term is nested in the big one (t and p in t:p: each t:p cell has one t and
        # one p), Z_rest = Z_big R for a 0/1 matrix R, and every block follows from sums over the
        # (big level, distinct X row) cells: Z_rest'WZ_rest = R' diag(Z_b'WZ_b) R, and so on.
        self.rest_of_big, self.parents = None, []
        if n_rest:
            for cols in self.rest_cols:
                parent = np.zeros(self.q_big, dtype=np.int64)
                parent[self.g_big] = cols
                if not np.array_equal(parent[self.g_big], cols):
                    self.parents = []
                    break
                self.parents.append(parent)
        if self.parents:
            stacked = np.concatenate(self.parents)
            self.rest_of_big = sp.csr_matrix(     # R', (q_rest, q_big)
                (np.ones(stacked.size), (stacked, np.tile(np.arange(self.q_big), n_rest))),
                shape=(self.q_rest, self.q_big))
            self.nested_pairs = _PairSums(np.concatenate([a for a in self.parents for _ in self.parents]), q_rest,
                                          np.concatenate([b for _ in self.parents for b in self.parents]), q_rest)

    def rest_sums(self, values_big):
        """R' values: per rest column, the sum over the big levels nested in it."""
        return np.bincount(np.concatenate(self.parents), self._tile(values_big, self.n_rest), minlength=self.q_rest)

    def rest_pair_table(self, weights_big):
        """R' diag(weights) R as a dense (q_rest, q_rest) matrix."""
        table = np.zeros((self.q_rest, self.q_rest))
        pairs = self.nested_pairs
        table[pairs.rows, pairs.cols] = pairs.sums(self._tile(weights_big, self.n_rest**2))
        return table

    def _tile(self, w, times):
        return np.tile(w, times) if times > 1 else w

    def _linear_predictor(self, beta, u_rest, u_big, theta):
        eta = (self.x_unique @ beta)[self.x_row] + theta[self.big] * u_big[self.g_big]
        b_rest = theta[self.rest_term_of_col] * u_rest
        for cols in self.rest_cols:
            eta += b_rest[cols]
        return eta

    def _blocks(self, w, wz, theta):
        """The penalised normal equations in blocks: v = (u_rest, beta) dense, u_big diagonal.

        Returns ``(a_vv, a_rb, a_xb, a_bb, rhs_v, rhs_b)``: the dense (u_rest, beta) block, the sparse
        u_rest-u_big and dense beta-u_big couplings, the diagonal of the u_big block, right-hand sides.
        """
        lam_r, lam_b = theta[self.rest_term_of_col], theta[self.big]
        x_u, n_x = self.x_unique, self.x_unique.shape[0]
        nested = self.rest_of_big is not None
        if nested or self.sum_over_cells:  # one pass over the rows: sums per (big level, X row) cell
            cell_w, cell_wz = self.big_x.sums(w), self.big_x.sums(wz)
            x_w = np.bincount(self.big_x.cols, cell_w, minlength=n_x)
            x_wz = np.bincount(self.big_x.cols, cell_wz, minlength=n_x)
            big_w = np.bincount(self.big_x.rows, cell_w, minlength=self.q_big)
            big_wz = np.bincount(self.big_x.rows, cell_wz, minlength=self.q_big)
            big_x = self.big_x.sparse_from_sums(cell_w) @ x_u          # Z_b'WX, (q_big, p)
        else:
            x_w = np.bincount(self.x_row, w, minlength=n_x)
            x_wz = np.bincount(self.x_row, wz, minlength=n_x)
            big_w = np.bincount(self.g_big, w, minlength=self.q_big)
            big_wz = np.bincount(self.g_big, wz, minlength=self.q_big)
            big_x = self.big_x.sparse(w) @ x_u
        a_xx = x_u.T @ (x_w[:, None] * x_u)                              # X'WX
        rhs_x = x_u.T @ x_wz                                             # X'Wz
        a_xb = lam_b * big_x.T                                           # X'WZ_b Lambda_b
        a_bb = lam_b**2 * big_w + 1.0                                    # Lambda_b Z_b'WZ_b Lambda_b + I (diagonal)
        rhs_b = lam_b * big_wz
        if not self.q_rest:
            return a_xx, None, a_xb, a_bb, rhs_x, rhs_b
        if nested:
            a_rb = _NestedCoupling(self, lam_r, lam_b * big_w)          # Z_r'WZ_b = R' diag(Z_b'WZ_b)
            rest_rest = self.rest_pair_table(big_w)                      # Z_r'WZ_r = R' diag(Z_b'WZ_b) R
            rest_x = self.rest_of_big @ big_x                            # Z_r'WX = R' Z_b'WX
            rest_wz = self.rest_sums(big_wz)
        else:
            units_w, units_wz = (cell_w, cell_wz) if self.sum_over_cells else (w, wz)
            w_k = self._tile(units_w, self.n_rest)
            rest_rest = np.zeros(self.rest_rest.shape)
            rest_rest[self.rest_rest.rows, self.rest_rest.cols] = self.rest_rest.sums(
                self._tile(units_w, self.n_rest**2))
            rest_big = self.rest_big.sparse(w_k)
            rest_x = self.rest_x.sparse(w_k) @ x_u
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

    def solve(self, theta, beta, u_rest, u_big, tol=1e-12, max_iter=100):
        """Penalised IRLS at fixed theta, warm-started; returns (beta, u_rest, u_big, objective, schur, iters)."""
        nr = self.q_rest
        coef = (beta, u_rest, u_big)
        eta = self._linear_predictor(*coef, theta)
        current = _binomial_deviance(self.y, self.n_trials, eta, self.saturated) + u_rest @ u_rest + u_big @ u_big
        for iteration in range(max_iter):
            prob = np.clip(expit(eta), 1e-12, 1 - 1e-12)
            w = self.n_trials * prob * (1 - prob)
            wz = w * eta + (self.y - self.n_trials * prob)          # W times the working response
            a_vv, a_rb, a_xb, a_bb, rhs_v, rhs_b = self._blocks(w, wz, theta)
            schur = self._schur(a_vv, a_rb, a_xb, a_bb)
            a_vb_rhs = np.r_[a_rb.matvec(rhs_b / a_bb), a_xb @ (rhs_b / a_bb)] if nr else a_xb @ (rhs_b / a_bb)
            v = scipy.linalg.cho_solve(scipy.linalg.cho_factor(schur), rhs_v - a_vb_rhs)
            new_big = (rhs_b - (a_rb.rmatvec(v[:nr]) if nr else 0.0) - a_xb.T @ v[nr:]) / a_bb
            proposal = (v[nr:], v[:nr], new_big)
            eta_new = self._linear_predictor(*proposal, theta)
            step = 1.0
            for _ in range(30):  # step halving: eta is linear in the coefficients
                eta_t = eta + step * (eta_new - eta)
                trial = tuple(old + step * (new - old) for old, new in zip(coef, proposal))
                value = (_binomial_deviance(self.y, self.n_trials, eta_t, self.saturated)
                         + trial[1] @ trial[1] + trial[2] @ trial[2])
                if value <= current + 1e-10 * abs(current):
                    break
                step /= 2
            change, coef, eta, current = current - value, trial, eta_t, value
            if abs(change) < tol * (abs(current) + 1.0):
                break
        prob = np.clip(expit(eta), 1e-12, 1 - 1e-12)
        w = self.n_trials * prob * (1 - prob)
        a_vv, a_rb, a_xb, a_bb, _, _ = self._blocks(w, w * eta, theta)
        schur = self._schur(a_vv, a_rb, a_xb, a_bb)
        # log det(Lambda Z'WZ Lambda + I) = log det(A_bb) + log det(the u_rest block of the Schur complement)
        logdet = float(np.sum(np.log(a_bb)))
        if nr:
            logdet += 2.0 * float(np.sum(np.log(np.diag(scipy.linalg.cholesky(schur[:nr, :nr])))))
        return coef[0], coef[1], coef[2], current + logdet, schur, iteration + 1
