"""A binomial GLMM with crossed random intercepts, fitted by the Laplace approximation.

Model (eq. 2 of Givens et al.): Y ~ Bin(n, p), logit p = X beta + sum_k Z_k b_k, with
b_k ~ N(0, sigma_k^2 I) for each grouping term k (e.g. t, p, t:p). We follow lme4's
``glmer(nAGQ=0)``: for a given sigma, penalised IRLS finds the joint mode of
(beta, u) with b = Lambda u; sigma then minimises the Laplace deviance
    dev(y, eta) + |u|^2 + log det(Lambda Z' W Z Lambda + I).
Every row lies in exactly one level of each grouping term, so Z_k' W Z_k is diagonal:
the largest term (t:p) is eliminated by a diagonal Schur complement, leaving a small
dense system. That is what makes a 65,536-row fit take seconds.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd
import scipy.linalg
import scipy.optimize
import scipy.sparse as sp
from scipy import stats
from scipy.special import expit, log_expit, xlogy


from amdo_lab.common import as_finite_array, check_positive
from amdo_lab.common.threads import one_blas_thread
from amdo_lab.face_glmm.design import DesignMatrix, build_design, group_indices, parse_formula

__all__ = ["GlmmResult", "fit_binomial_glmm", "binomial_deviance"]


@dataclass(frozen=True)
class GlmmResult:
    """A fitted binomial GLMM.

    ``fixed_effects`` and ``standard_errors`` map a term name ("(Intercept)", "M",
    "M:D", ...) to its estimate: a float for one-degree-of-freedom terms, an array
    (one entry per sum-to-zero column) otherwise. ``coefficients`` has every column.
    """

    formula: str
    random: tuple[str, ...]
    trials: int
    coefficients: pd.Series
    covariance: pd.DataFrame
    fixed_effects: dict
    standard_errors: dict
    variance_components: dict       # term -> variance sigma^2
    tests: pd.DataFrame             # per-term Wald chi2, F = chi2 / df, p-value
    deviance: float                 # Laplace objective (nAGQ=0) at the optimum
    n_obs: int
    n_iterations: int
    random_effects: dict = field(repr=False)  # term -> conditional modes b_k
    design: DesignMatrix = field(repr=False)

    @property
    def probe_correlation(self) -> float:
        """rho = sigma_p^2 / (sigma_p^2 + sigma_tp^2): our reading of the compound symmetry."""
        vc = self.variance_components
        if "p" not in vc or "t:p" not in vc:
            raise ValueError("probe_correlation needs random terms 'p' and 't:p'")
        total = vc["p"] + vc["t:p"]
        return float(vc["p"] / total) if total > 0 else float("nan")

    def predict_marginal(self, grid: pd.DataFrame, ci: float | None = None) -> pd.DataFrame:
        """Like :meth:`predict`, but factors absent from ``grid`` are averaged on the logit scale.

        With sum-to-zero coding the average over a factor's levels is obtained by
        setting every column of every term that contains it to 0.
        """
        _check_frame(grid, "grid")
        _check_ci(ci)
        full = grid.copy()
        absent = [v for v, lev in self.design.levels.items() if v not in grid.columns]
        for v in absent:
            if self.design.levels[v] is None:
                raise ValueError(f"grid must give numeric variable {v!r}")
            full[v] = self.design.levels[v][0]
        _, terms = parse_formula(self.formula)
        design = build_design(full, terms, self.design.levels)
        x = design.matrix.copy()
        for term, cols in design.term_columns.items():
            if any(v in absent for v in term.split(":")):
                x[:, cols] = 0.0
        return self._predict_rows(x, grid.index, ci)

    def _predict_rows(self, design: np.ndarray, index, ci):
        eta = design @ self.coefficients.to_numpy()
        out = pd.DataFrame({"p": expit(eta)}, index=index)
        if ci is not None:
            se = np.sqrt(np.einsum("ij,jk,ik->i", design, self.covariance.to_numpy(), design))
            z = stats.norm.ppf(0.5 + ci / 2)
            out["lower"], out["upper"] = expit(eta - z * se), expit(eta + z * se)
        return out

    def predict(self, newdata: pd.DataFrame, ci: float | None = None) -> pd.DataFrame:
        """Rank-1 probability for a typical probe and training set (random effects 0).

        Returns columns ``p`` (and ``lower``/``upper`` for a Wald interval on the logit
        scale when ``ci`` is given).
        """
        _check_frame(newdata, "newdata")
        _check_ci(ci)
        _, terms = parse_formula(self.formula)
        design = build_design(newdata, terms, self.design.levels).matrix
        return self._predict_rows(design, newdata.index, ci)


def _check_frame(frame: object, name: str) -> None:
    if not isinstance(frame, pd.DataFrame):
        raise TypeError(f"{name} must be a pandas DataFrame, got {type(frame).__name__}")
    if frame.empty:
        raise ValueError(f"{name} must have at least one row, got an empty DataFrame")


def _check_ci(ci: object) -> None:
    """A Wald interval level strictly between 0 and 1 (or None for no interval)."""
    if ci is not None and not check_positive(ci, "ci") < 1:
        raise ValueError(f"ci must be in (0, 1), got {ci}")


def _response_counts(table: pd.DataFrame, response: str, trials: int) -> np.ndarray:
    """The response column as float counts, each an integer in [0, trials]."""
    if response not in table.columns:
        raise ValueError(f"response {response!r} is not a column of table")
    if pd.api.types.is_bool_dtype(table[response]):
        raise TypeError(f"response {response!r} must hold counts, got booleans")
    y = pd.to_numeric(table[response], errors="coerce").to_numpy(dtype=float)
    if not np.all(np.isfinite(y)):
        raise ValueError(f"response {response!r} must be finite counts, got NaN/non-numeric values")
    if np.any(y < 0) or np.any(y > trials) or np.any(y != np.round(y)):
        raise ValueError(f"response {response!r} must hold integer counts in [0, trials={trials}]")
    return y


def _check_random_terms(random: object) -> tuple[str, ...]:
    """Grouping terms: a non-empty sequence of distinct names such as "t", "p" or "t:p"."""
    if isinstance(random, str):
        random = [random]
    if not hasattr(random, "__iter__"):
        raise TypeError(f"random must be a sequence of grouping terms, got {type(random).__name__}")
    random = tuple(random)
    if not random:
        raise ValueError("random must name at least one grouping term")
    bad = [term for term in random if not isinstance(term, str) or not term.strip()]
    if bad:
        raise TypeError(f"random must hold grouping terms as non-empty strings, got {bad[0]!r}")
    if len(set(random)) != len(random):
        raise ValueError(f"random must not repeat a grouping term, got {random}")
    return random


def binomial_deviance(y: np.ndarray, trials: np.ndarray, eta: np.ndarray) -> float:
    """Binomial deviance 2 sum[y log(y/mu) + (n-y) log((n-y)/(n-mu))], mu = n expit(eta).

    Written with log-expit of the linear predictor so that p -> 0 or 1 stays finite.

    Parameters
    ----------
    y : array_like
        Success counts, each in [0, trials].
    trials : float or array_like
        Positive binomial sizes n, one per count or one for all.
    eta : array_like
        Linear predictor, the shape of ``y``.
    """
    y = as_finite_array(y, "y")
    eta = as_finite_array(eta, "eta", shape=y.shape)
    trials = as_finite_array(trials, "trials")
    if trials.shape not in ((), y.shape):
        raise ValueError(f"trials must be a number or have the shape of y {y.shape}, got {trials.shape}")
    if np.any(trials <= 0):
        raise ValueError("trials must be positive")
    if np.any(y < 0) or np.any(y > trials):
        raise ValueError("y must hold counts in [0, trials]")
    return _binomial_deviance(y, trials, eta)


def _binomial_deviance(y: np.ndarray, trials: np.ndarray, eta: np.ndarray) -> float:
    """:func:`binomial_deviance` on validated arrays (the IRLS loop's inner call)."""
    saturated = xlogy(y, y / trials) + xlogy(trials - y, (trials - y) / trials)
    fitted = y * log_expit(eta) + (trials - y) * log_expit(-eta)
    return float(2.0 * np.sum(saturated - fitted))


class _Problem:
    """Pre-computed sparse structure of one fit."""

    def __init__(self, y, trials, x, groups):
        self.y, self.trials, self.x = y, trials, x
        self.n, self.p = x.shape
        self.sizes = [int(g.max()) + 1 for g in groups]
        self.big = int(np.argmax(self.sizes))
        self.rest = [k for k in range(len(groups)) if k != self.big]
        self.g_big = groups[self.big]
        rows = np.arange(self.n)
        self.z_big = sp.csr_matrix((np.ones(self.n), (rows, self.g_big)), shape=(self.n, self.sizes[self.big]))
        rest_blocks = [sp.csr_matrix((np.ones(self.n), (rows, groups[k])), shape=(self.n, self.sizes[k]))
                       for k in self.rest]
        self.z_rest = sp.hstack(rest_blocks, format="csr") if rest_blocks else sp.csr_matrix((self.n, 0))
        self.rest_term_of_col = np.concatenate([np.full(self.sizes[k], k) for k in self.rest]) if self.rest \
            else np.zeros(0, dtype=int)
        self.q_rest = self.z_rest.shape[1]
        self.groups = groups

    def solve(self, theta, beta, u_rest, u_big, tol=1e-10, max_iter=60):
        """Penalised IRLS at fixed theta; returns (beta, u_rest, u_big, objective, pieces)."""
        lam_rest = theta[self.rest_term_of_col] if self.q_rest else np.zeros(0)
        lam_big = theta[self.big]
        z_rest_l = self.z_rest @ sp.diags(lam_rest) if self.q_rest else self.z_rest

        def eta_of(b, ur, ub):
            return self.x @ b + z_rest_l @ ur + lam_big * ub[self.g_big]

        def pdev(eta, ur, ub):
            return _binomial_deviance(self.y, self.trials, eta) + ur @ ur + ub @ ub

        eta = eta_of(beta, u_rest, u_big)
        current = pdev(eta, u_rest, u_big)
        for iteration in range(max_iter):
            prob = np.clip(expit(eta), 1e-12, 1 - 1e-12)
            w = self.trials * prob * (1 - prob)
            z = eta + (self.y - self.trials * prob) / w
            system = self._normal_equations(w, z, z_rest_l, lam_big)
            new_v, new_big = self._solve_system(*system)
            nr = self.q_rest
            cand = (new_v[nr:], new_v[:nr], new_big)
            step = 1.0
            for _ in range(30):  # step halving keeps the penalised deviance decreasing
                trial = tuple(old + step * (c - old) for old, c in zip((beta, u_rest, u_big), cand))
                eta_t = eta_of(*trial)
                value = pdev(eta_t, trial[1], trial[2])
                if value <= current + 1e-10 * abs(current):
                    break
                step /= 2
            change = current - value
            beta, u_rest, u_big, eta = trial[0], trial[1], trial[2], eta_t
            current = value
            if abs(change) < tol * (abs(current) + 1.0):
                break
        prob = np.clip(expit(eta), 1e-12, 1 - 1e-12)
        w = self.trials * prob * (1 - prob)
        system = self._normal_equations(w, np.zeros(self.n), z_rest_l, lam_big)
        a_vv, a_vb, a_bb = system[0], system[1], system[2]
        schur = a_vv - (a_vb / a_bb) @ a_vb.T
        nr = self.q_rest
        logdet = float(np.sum(np.log(a_bb)))
        if nr:
            logdet += 2.0 * float(np.sum(np.log(np.diag(scipy.linalg.cholesky(schur[:nr, :nr])))))
        objective = current + logdet
        return beta, u_rest, u_big, objective, schur, iteration + 1

    def _normal_equations(self, w, z, z_rest_l, lam_big):
        xw = self.x * w[:, None]
        wz_big = sp.csr_matrix((w, (np.arange(self.n), self.g_big)), shape=self.z_big.shape)
        a_bb = lam_big**2 * np.asarray(wz_big.sum(axis=0)).ravel() + 1.0
        rhs_b = lam_big * np.bincount(self.g_big, weights=w * z, minlength=self.z_big.shape[1])
        a_xb = lam_big * (wz_big.T @ self.x).T
        a_xx = self.x.T @ xw
        rhs_x = xw.T @ z
        if self.q_rest:
            zw = z_rest_l.T @ sp.diags(w)
            a_rr = (zw @ z_rest_l).toarray() + np.eye(self.q_rest)
            a_rx = np.asarray(zw @ self.x)
            a_rb = lam_big * (zw @ self.z_big).toarray()
            rhs_r = zw @ z
            a_vv = np.block([[a_rr, a_rx], [a_rx.T, a_xx]])
            a_vb = np.vstack([a_rb, a_xb])
            rhs_v = np.concatenate([rhs_r, rhs_x])
        else:
            a_vv, a_vb, rhs_v = a_xx, a_xb, rhs_x
        return a_vv, a_vb, a_bb, rhs_v, rhs_b

    @staticmethod
    def _solve_system(a_vv, a_vb, a_bb, rhs_v, rhs_b):
        schur = a_vv - (a_vb / a_bb) @ a_vb.T
        reduced = rhs_v - a_vb @ (rhs_b / a_bb)
        v = scipy.linalg.cho_solve(scipy.linalg.cho_factor(schur), reduced)
        big = (rhs_b - a_vb.T @ v) / a_bb
        return v, big


def fit_binomial_glmm(
    table: pd.DataFrame,
    fixed: str = "Y ~ M * D + U",
    random: list[str] | tuple[str, ...] = ("t", "p", "t:p"),
    trials: int = 30,
    *,
    start_sd: float = 0.5,
) -> GlmmResult:
    """Fit the binomial GLMM of eq. (2) by the Laplace approximation (lme4's nAGQ=0).

    Parameters
    ----------
    table : pandas.DataFrame
        One row per binomial observation.
    fixed : str
        Fixed-effects formula; text/categorical columns are factors with sum-to-zero
        coding (as SAS's Type III tests assume), numeric columns enter as they are.
    random : sequence of str
        Grouping terms, each a random intercept ("t", "p", "t:p", "t:U", ...).
    trials : int
        Binomial size n (30 galleries in the paper).

    Returns
    -------
    GlmmResult

    Notes
    -----
    BLAS is limited to one thread during the fit: the matrices are small (n x 20,
    300 x 300) and multi-threaded BLAS on a shared machine was 40x slower here.
    """
    with one_blas_thread():
        return _fit(table, fixed, random, trials, start_sd)


def _fit(table, fixed, random, trials, start_sd) -> GlmmResult:
    if not isinstance(table, pd.DataFrame):
        raise TypeError(f"table must be a pandas DataFrame, got {type(table).__name__}")
    if table.empty:
        raise ValueError("table must have at least one row, got an empty DataFrame")
    random = _check_random_terms(random)
    if not isinstance(trials, (int, np.integer)) or isinstance(trials, bool) or trials < 1:
        raise ValueError(f"trials must be a positive int, got {trials!r}")
    start_sd = check_positive(start_sd, "start_sd", allow_zero=True)  # L-BFGS-B would clip a negative one silently
    response, terms = parse_formula(fixed)
    y = _response_counts(table, response, trials)
    design = build_design(table, terms)
    x = design.matrix
    if np.linalg.matrix_rank(x) < x.shape[1]:
        raise ValueError(f"fixed design is singular (rank {np.linalg.matrix_rank(x)} < {x.shape[1]} columns)")
    groups = [group_indices(table, term) for term in random]
    problem = _Problem(y, np.full(y.shape, float(trials)), x, groups)

    # Start beta from the pooled logistic fit's crude version: logit of the mean rate.
    rate = np.clip(y.mean() / trials, 1e-3, 1 - 1e-3)
    state = {"beta": np.r_[np.log(rate / (1 - rate)), np.zeros(x.shape[1] - 1)],
             "u_rest": np.zeros(problem.q_rest), "u_big": np.zeros(problem.sizes[problem.big]),
             "iters": 0}

    def objective(theta):
        beta, ur, ub, value, _, iters = problem.solve(theta, state["beta"], state["u_rest"], state["u_big"])
        state.update(beta=beta, u_rest=ur, u_big=ub)
        state["iters"] += iters
        return value

    theta0 = np.full(len(random), float(start_sd))
    opt = scipy.optimize.minimize(objective, theta0, method="L-BFGS-B",
                                  bounds=[(0.0, None)] * len(random),
                                  options={"ftol": 1e-12, "gtol": 1e-7, "eps": 1e-6, "maxiter": 200})
    theta = np.asarray(opt.x)
    beta, ur, ub, value, schur, _ = problem.solve(theta, state["beta"], state["u_rest"], state["u_big"])
    nr = problem.q_rest
    inverse = scipy.linalg.cho_solve(scipy.linalg.cho_factor(schur), np.eye(schur.shape[0]))
    cov = inverse[nr:, nr:]
    names = list(design.column_names)
    coefficients = pd.Series(beta, index=names)
    covariance = pd.DataFrame(cov, index=names, columns=names)
    fixed_effects, standard_errors, rows = {}, {}, []
    for term, cols in design.term_columns.items():
        est, block = beta[cols], cov[cols, cols]
        se = np.sqrt(np.diag(block))
        fixed_effects[term] = float(est[0]) if est.size == 1 else est
        standard_errors[term] = float(se[0]) if se.size == 1 else se
        if term == "(Intercept)":
            continue
        chi2 = float(est @ np.linalg.solve(block, est))
        df = est.size
        rows.append({"term": term, "df": df, "chi2": chi2, "F": chi2 / df,
                     "p_value": float(stats.chi2.sf(chi2, df))})
    tests = pd.DataFrame(rows).set_index("term")
    random_effects = {}
    for k, term in enumerate(random):
        if k == problem.big:
            random_effects[term] = theta[k] * ub
        else:
            random_effects[term] = theta[k] * ur[problem.rest_term_of_col == k]
    return GlmmResult(
        formula=fixed, random=random, trials=int(trials), coefficients=coefficients, covariance=covariance,
        fixed_effects=fixed_effects, standard_errors=standard_errors,
        variance_components={term: float(theta[k] ** 2) for k, term in enumerate(random)},
        tests=tests, deviance=float(value), n_obs=int(y.size), n_iterations=int(state["iters"]),
        random_effects=random_effects, design=design,
    )
