"""A binomial GLMM with crossed random intercepts, fitted by the Laplace approximation.

Model (eq. 2 of Givens et al.): Y ~ Bin(n, p), logit p = X beta + sum_k Z_k b_k, with
b_k ~ N(0, sigma_k^2 I) for each grouping term k (e.g. t, p, t:p). We follow lme4's
``glmer(nAGQ=0)``: for a given sigma, penalised IRLS finds the joint mode of
(beta, u) with b = Lambda u; sigma then minimises the Laplace deviance
    dev(y, eta) + |u|^2 + log det(Lambda Z' W Z Lambda + I).

It is computed in :mod:`amdo_lab.face_glmm.laplace`: a dense reference path and the fast one.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd
import scipy.linalg
import scipy.optimize
from scipy import stats
from scipy.special import expit

from amdo_lab.common import MAX_SAMPLES, as_finite_array, check_dataframe, check_in_range, check_names, check_positive_int
from amdo_lab.common.threads import one_blas_thread
from amdo_lab.face_glmm.design import DesignMatrix, _build_design, group_indices, parse_formula
from amdo_lab.face_glmm.laplace import MAX_SD, CrossedProblem

#: Starting value of every random-effect standard deviation (logit scale) in the fit's optimiser.
START_SD = 0.5

__all__ = ["GlmmResult", "fit_binomial_glmm", "laplace_deviance", "response_counts"]


@dataclass(frozen=True)
class GlmmResult:
    """A fitted binomial GLMM (the estimates of eq. 2).

    ``fixed_effects`` and ``standard_errors`` map a term name ("(Intercept)", "M", "M:D", ...) to its
    estimate: a float for one-degree-of-freedom terms, an array (one entry per sum-to-zero column)
    otherwise. ``coefficients`` has every column.

    Parameters
    ----------
    formula : str
        The fixed-effects formula fitted.
    random : tuple of str
        The grouping terms, each a random intercept.
    n_trials : int
        Binomial size n of every row.
    coefficients : pandas.Series
        beta on the logit scale, one entry per design column.
    covariance : pandas.DataFrame
        Covariance matrix of ``coefficients`` (inverse of the Schur complement at the optimum).
    fixed_effects : dict
        Term -> estimate (float or ndarray), as above.
    standard_errors : dict
        Term -> standard error(s), as above.
    variance_components : dict
        Grouping term -> variance sigma_k^2 (logit scale, >= 0).
    tests : pandas.DataFrame
        Per term (intercept excluded): ``df``, Wald ``chi2``, ``F`` = chi2 / df and ``p_value``.
    deviance : float
        The Laplace deviance (lme4's nAGQ=0 objective) at the optimum.
    n_obs : int
        Number of rows fitted.
    n_iterations : int
        Penalised-IRLS iterations summed over every deviance evaluation of the optimiser.
    random_effects : dict
        Grouping term -> ndarray of conditional modes b_k, one per level (in the order of
        :func:`group_indices`).
    design : DesignMatrix
        The fixed-effects design, with the levels used to code new data.

    References
    ----------
    Givens, Beveridge, Draper & Bolme (2004), "Using a Generalized Linear Mixed Model to Study the
    Configuration Space of a PCA+LDA Human Face Recognition Algorithm", AMDO 2004, LNCS 3179, pp. 1-11, eq. (2).
    """

    formula: str
    random: tuple[str, ...]
    n_trials: int
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

        With sum-to-zero coding the average over a factor's levels is obtained by setting every column of
        every term that contains it to 0.

        Parameters
        ----------
        grid : pandas.DataFrame
            At least one row; columns give levels of some of the fit's factors (every numeric variable
            must be given).
        ci : float or None, default None
            Level in (0, 1) of a Wald interval on the logit scale; None for no interval.

        Returns
        -------
        pandas.DataFrame
            Indexed like ``grid``: ``p`` (probability in [0, 1]), and ``lower``/``upper`` when ``ci`` is given.
        """
        _check_rows(grid, "grid")
        _check_ci(ci)
        full = grid.copy()
        absent = [v for v, lev in self.design.levels.items() if v not in grid.columns]
        for v in absent:
            if self.design.levels[v] is None:
                raise ValueError(f"grid must give numeric variable {v!r}")
            full[v] = self.design.levels[v][0]
        _, terms = parse_formula(self.formula)
        design = _build_design(full, terms, self.design.levels)
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
        """Rank-1 probability for a typical probe and training set (every random effect 0).

        Parameters
        ----------
        newdata : pandas.DataFrame
            At least one row, with a column for every variable of the fixed formula (levels as fitted).
        ci : float or None, default None
            Level in (0, 1) of a Wald interval on the logit scale; None for no interval.

        Returns
        -------
        pandas.DataFrame
            Indexed like ``newdata``: ``p`` = expit(x beta) in [0, 1], and ``lower``/``upper`` when ``ci``
            is given.
        """
        _check_rows(newdata, "newdata")
        _check_ci(ci)
        _, terms = parse_formula(self.formula)
        design = _build_design(newdata, terms, self.design.levels).matrix
        return self._predict_rows(design, newdata.index, ci)


def _check_rows(frame: object, name: str) -> None:
    """A pandas DataFrame with at least one row (an empty design has no rows to fit or predict)."""
    if check_dataframe(frame, name).empty:
        raise ValueError(f"{name} must have at least one row, got an empty DataFrame")


def _check_ci(ci: object) -> None:
    """A Wald interval level strictly between 0 and 1 (or None for no interval)."""
    if ci is not None:
        check_in_range(ci, "ci", 0, 1)


def response_counts(table: pd.DataFrame, response: str, n_trials: int) -> np.ndarray:
    """The response column of a binomial table as float counts, each an integer in [0, n_trials].

    Shared by :func:`fit_binomial_glmm` and the peer fits of :mod:`amdo_lab.face_glmm.crosscheck`.

    Parameters
    ----------
    table : pandas.DataFrame
        The table holding the response column.
    response : str
        The response column's name (the left side of the fixed-effects formula).
    n_trials : int
        The binomial size n (already checked to be a positive int).

    Returns
    -------
    ndarray of float, shape (len(table),)
        The counts y of eq. (2), each an integer in [0, n_trials].

    Raises
    ------
    ValueError
        When the column is missing, holds NaN or non-numeric values, or counts outside [0, n_trials].
    TypeError
        When the column holds booleans.

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, eq. (2) (Y, rank-1 matches out of n galleries).
    """
    check_dataframe(table, "table (the response of fixed)", columns=[response])
    if pd.api.types.is_bool_dtype(table[response]):
        raise TypeError(f"response {response!r} must hold counts, got booleans")
    y = pd.to_numeric(table[response], errors="coerce").to_numpy(dtype=float)  # non-numeric values become NaN
    # finite whole numbers in [0, n_trials]: as_finite_array refuses NaN, fractions and counts outside the range
    as_finite_array(y, f"response {response!r} (integer counts, n_trials={n_trials})", dtype=np.int64,
                    bounds=(0, n_trials))
    return y


def laplace_deviance(table: pd.DataFrame, fixed: str, random: list[str] | tuple[str, ...],
                     sd: np.ndarray, n_trials: int = 30) -> np.ndarray:
    """The Laplace deviance that :func:`fit_binomial_glmm` minimises, at given random-effect sds.

    For each row of ``sd`` (one standard deviation per term of ``random``), penalised IRLS finds the
    joint mode of (beta, u) and the objective dev(y, eta) + |u|^2 + log det(Lambda Z'WZ Lambda + I)
    is returned: lme4's ``glmer(nAGQ=0)`` deviance. Used to draw the deviance along one sd (the flat
    direction of a near-separated table) and to compare two fitters' optima on one scale.

    Parameters
    ----------
    table : pandas.DataFrame
        One row per binomial observation, as for :func:`fit_binomial_glmm`.
    fixed : str
        Fixed-effects formula, as for :func:`fit_binomial_glmm`.
    random : sequence of str
        Distinct grouping terms, each a random intercept.
    sd : array_like, shape (len(random),) or (m, len(random))
        Non-negative standard deviations sigma_k (logit scale), each at most 1e3, one row per
        evaluation.
    n_trials : int, default 30
        Binomial size n of every row, 1 to :data:`amdo_lab.common.MAX_SAMPLES` (1,000,000).

    Returns
    -------
    ndarray, shape (m,)
        The Laplace deviance at each row of ``sd`` (m = 1 for a single row).

    References
    ----------
    Bates et al. (2015), J. Stat. Softw. 67(1), eq. (36) with the profiled fixed effects of nAGQ=0;
    the model is eq. (2) of Givens et al. (2004), AMDO, LNCS 3179.
    """
    random = check_names(random, "random", accept_single=True)  # grouping terms such as "t", "p", "t:p"
    # one column per random term, one row per evaluation (a single row may be given as a vector)
    sd = as_finite_array(np.atleast_2d(sd), "sd", shape=(None, len(random)), bounds=(0.0, MAX_SD))
    with one_blas_thread():
        problem, start = _setup(table, fixed, random, n_trials)
        beta, u_rest, u_big = start
        out = []
        for row in sd:
            beta, u_rest, u_big, value, _, _ = problem.solve(row, beta, u_rest, u_big)
            out.append(value)
    return np.array(out)


def _design_and_response(table: object, fixed: str, n_trials: object) -> tuple[DesignMatrix, np.ndarray, int]:
    """The fixed design, the response counts and ``n_trials``, after checking the table (a DataFrame
    with rows), the formula and ``n_trials`` (shared by the fit and the peers' fits)."""
    _check_rows(table, "table")
    n_trials = check_positive_int(n_trials, "n_trials", maximum=MAX_SAMPLES)
    response, terms = parse_formula(fixed)
    y = response_counts(table, response, n_trials)
    return _build_design(table, terms), y, n_trials


def _setup(table, fixed, random, n_trials):
    """Check the inputs, build the fast problem and the starting coefficients."""
    design, y, n_trials = _design_and_response(table, fixed, n_trials)
    x = design.matrix
    check_positive_int(int(np.linalg.matrix_rank(x)), "the column rank of the fixed design (singular)", minimum=x.shape[1])
    groups = [group_indices(table, term) for term in random]
    problem = CrossedProblem(y, np.full(y.shape, float(n_trials)), x, groups)
    problem.design = design
    # Start beta from the logit of the mean rate (intercept only), u from 0.
    rate = np.clip(y.mean() / n_trials, 1e-3, 1 - 1e-3)
    beta = np.r_[np.log(rate / (1 - rate)), np.zeros(x.shape[1] - 1)]
    return problem, (beta, np.zeros(problem.q_rest), np.zeros(problem.q_big))


def fit_binomial_glmm(
    table: pd.DataFrame,
    fixed: str = "Y ~ M * D + U",
    random: list[str] | tuple[str, ...] = ("t", "p", "t:p"),
    n_trials: int = 30,
) -> GlmmResult:
    """Fit the binomial GLMM of eq. (2) by the Laplace approximation (lme4's nAGQ=0).

    For given random-effect standard deviations sigma, penalised IRLS finds the joint mode of
    (beta, u) with b = Lambda u; sigma then minimises the Laplace deviance
    dev(y, eta) + |u|^2 + log det(Lambda Z'WZ Lambda + I) (L-BFGS-B, sigma >= 0).

    Parameters
    ----------
    table : pandas.DataFrame
        One row per binomial observation, with the response and every column the formula and the
        grouping terms name.
    fixed : str, default "Y ~ M * D + U"
        Fixed-effects formula; text/categorical columns are factors with sum-to-zero coding (as SAS's
        Type III tests assume), numeric columns enter as they are. The design must have full rank.
    random : sequence of str, default ("t", "p", "t:p")
        Grouping terms, each a random intercept ("t", "p", "t:p", "t:U", ...), distinct.
    n_trials : int, default 30
        Binomial size n of every row (30 galleries in the paper), 1 to 1,000,000; the response must hold
        integer counts in [0, n_trials].

    Returns
    -------
    GlmmResult
        Estimates, covariance, Wald tests, variance components and conditional modes.

    Notes
    -----
    BLAS is limited to one thread during the fit: the matrices are small (n x 20, 300 x 300) and
    multi-threaded BLAS on a shared machine was 40x slower here.

    References
    ----------
    Givens, Beveridge, Draper & Bolme (2004), "Using a Generalized Linear Mixed Model to Study the
    Configuration Space of a PCA+LDA Human Face Recognition Algorithm", AMDO 2004, LNCS 3179, pp. 1-11, eq. (2) (the model) and Table 2 (its tests). Bates, Maechler, Bolker & Walker (2015),
    J. Stat. Softw. 67(1) (the nAGQ=0 Laplace fit followed here).

    Examples
    --------
    Forty probes, each scored under two metrics, with a probe random intercept of variance 1:

    >>> import pandas as pd
    >>> from amdo_lab.face_glmm import fit_binomial_glmm, simulate_binomial_glmm
    >>> table = pd.MultiIndex.from_product([range(40), ["l2", "soft_l2"]], names=["p", "M"]).to_frame(index=False)
    >>> table["Y"] = simulate_binomial_glmm(table, "Y ~ M", [1.0, -0.5], {"p": 1.0}, 30, rng=0)
    >>> fit = fit_binomial_glmm(table, "Y ~ M", random=["p"], n_trials=30)
    >>> fit.coefficients.round(1).tolist()
    [0.8, -0.5]
    """
    with one_blas_thread():
        return _fit(table, fixed, random, n_trials)


def _fit(table, fixed, random, n_trials) -> GlmmResult:
    random = check_names(random, "random", accept_single=True)  # grouping terms such as "t", "p", "t:p"
    problem, (beta0, u_rest0, u_big0) = _setup(table, fixed, random, n_trials)
    design = problem.design
    y = problem.y
    state = {"beta": beta0, "u_rest": u_rest0, "u_big": u_big0, "iters": 0}

    def objective(theta):
        beta, ur, ub, value, _, iters = problem.solve(theta, state["beta"], state["u_rest"], state["u_big"])
        state.update(beta=beta, u_rest=ur, u_big=ub)
        state["iters"] += iters
        return value

    theta0 = np.full(len(random), START_SD)
    bounds = [(0.0, None)] * len(random)
    # Two stages: cheap forward-difference gradients to get close, then central differences to
    # polish (a forward difference with step h biases the optimum by about h / 2).
    rough = scipy.optimize.minimize(objective, theta0, method="L-BFGS-B", bounds=bounds,
                                    options={"ftol": 1e-10, "gtol": 1e-5, "eps": 1e-6, "maxiter": 200})
    opt = scipy.optimize.minimize(objective, rough.x, method="L-BFGS-B", jac="3-point", bounds=bounds,
                                  options={"ftol": 1e-12, "gtol": 1e-7, "maxiter": 200})
    theta = np.asarray(opt.x)
    beta, ur, ub, value, chol_beta, _ = problem.solve(theta, state["beta"], state["u_rest"], state["u_big"])
    # beta's covariance: the inverse of its precision U'U (the Schur complement of every u block)
    cov = scipy.linalg.cho_solve((chol_beta, False), np.eye(chol_beta.shape[0]))
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
        formula=fixed, random=random, n_trials=int(n_trials), coefficients=coefficients, covariance=covariance,
        fixed_effects=fixed_effects, standard_errors=standard_errors,
        variance_components={term: float(theta[k] ** 2) for k, term in enumerate(random)},
        tests=tests, deviance=float(value), n_obs=int(y.size), n_iterations=int(state["iters"]),
        random_effects=random_effects, design=design,
    )
