"""Peer fits of the same table: R's lme4 (through Rscript), statsmodels GEE and logistic GLM."""

from __future__ import annotations

import shutil
import subprocess
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from amdo_lab.common import check_dataframe, check_choice, check_instance, check_names
from amdo_lab.face_glmm.design import group_indices, parse_formula
from amdo_lab.face_glmm.glmm import _design_and_response

__all__ = ["PeerFit", "lme4_available", "fit_with_lme4", "fit_gee", "fit_naive_logistic"]


@dataclass(frozen=True)
class PeerFit:
    """The result of one peer fit of a binomial table (lme4, GEE or naive logistic regression).

    Parameters
    ----------
    method : str
        Which fit: ``"lme4 glmer(nAGQ=0)"``, ``"GEE (exchangeable)"``, ``"GEE (independence)"`` or
        ``"naive logistic"``.
    coefficients : pandas.DataFrame
        Indexed by design column (the names of the fit's design), with ``estimate`` (logit scale)
        and ``se`` (its standard error: lme4's model-based, GEE's robust sandwich, the GLM's
        model-based). Entries are NaN where the peer's iterations diverged (see ``finite``).
    variance_components : dict or None
        Grouping term -> variance sigma_k^2 on the logit scale (lme4); None for the fits without
        random effects.
    seconds : float
        Wall-clock time of the fit alone, s (for lme4, measured inside R around ``glmer``).
    cpu_seconds : float
        User + system CPU time of that fit, s.

    References
    ----------
    Givens et al. (2004), AMDO, LNCS 3179, eq. (2) (the model every peer fits, with or without its
    random effects); Bates et al. (2015), J. Stat. Softw. 67(1) (lme4); Liang & Zeger (1986),
    Biometrika 73 (GEE).
    """

    method: str
    coefficients: pd.DataFrame
    variance_components: dict | None
    seconds: float
    cpu_seconds: float

    @property
    def estimate(self) -> pd.Series:
        """The coefficient estimates (logit scale), by design column."""
        return self.coefficients["estimate"]

    @property
    def se(self) -> pd.Series:
        """Their standard errors, by design column."""
        return self.coefficients["se"]

    @property
    def finite(self) -> bool:
        """False when an estimate or standard error is NaN or inf (the peer's iterations diverged)."""
        return bool(np.all(np.isfinite(self.coefficients.to_numpy())))

_R_SCRIPT = r"""
suppressMessages(library(lme4))
args <- commandArgs(trailingOnly = TRUE)
d <- read.csv(args[1], stringsAsFactors = FALSE)
spec <- readLines(args[2])
fixed <- spec[1]; random <- spec[2]; n_trials <- as.numeric(spec[3]); factors <- strsplit(spec[4], ",")[[1]]
for (f in factors) { lev <- strsplit(spec[4 + match(f, factors)], "|", fixed = TRUE)[[1]]
  d[[f]] <- factor(d[[f]], levels = lev); contrasts(d[[f]]) <- contr.sum(length(lev)) }
for (g in c("t", "p")) if (!is.null(d[[g]])) d[[g]] <- factor(d[[g]])
d$FAIL <- n_trials - d$Y
form <- as.formula(paste("cbind(Y, FAIL) ~", fixed, "+", random))
t0 <- proc.time()
m <- glmer(form, data = d, family = binomial, nAGQ = 0)
dt <- proc.time() - t0
el <- dt[["elapsed"]]
vc <- as.data.frame(VarCorr(m))
cat(sprintf("TIME %.6f\n", el))
cat(sprintf("CPU %.6f\n", dt[["user.self"]] + dt[["sys.self"]]))
cat("FIXED", sprintf("%.10g", fixef(m)), "\n")
cat("SE", sprintf("%.10g", sqrt(diag(as.matrix(vcov(m))))), "\n")
cat("VCNAMES", vc$grp, "\n")
cat("VC", sprintf("%.10g", vc$vcov), "\n")
"""


def lme4_available() -> bool:
    """True when ``Rscript`` is on the PATH and can load the R package lme4.

    Returns
    -------
    bool
        Whether :func:`fit_with_lme4` can run on this machine (it starts one ``Rscript`` process).

    References
    ----------
    Bates, Maechler, Bolker & Walker (2015), "Fitting Linear Mixed-Effects Models Using lme4",
    J. Stat. Softw. 67(1): the peer fitter of the GLMM of eq. (2) in Givens et al. (2004), AMDO, LNCS 3179.
    """
    if shutil.which("Rscript") is None:
        return False
    done = subprocess.run(["Rscript", "-e", "suppressMessages(library(lme4))"], capture_output=True)
    return done.returncode == 0


def fit_with_lme4(table: pd.DataFrame, fixed: str, random=("t", "p", "t:p"), n_trials: int = 30) -> PeerFit:
    """Fit the GLMM of eq. (2) with R's ``glmer(cbind(Y, n-Y) ~ fixed + (1|...), nAGQ=0)``.

    Factors get sum-to-zero contrasts (``contr.sum``), as in our design, so the coefficients are
    comparable column by column with :func:`fit_binomial_glmm`.

    Parameters
    ----------
    table : pandas.DataFrame
        One row per binomial observation, holding the response and every column ``fixed`` and
        ``random`` name.
    fixed : str
        Fixed-effects formula ``"Y ~ U + M + ..."`` (see :func:`parse_formula`).
    random : sequence of str, default ("t", "p", "t:p")
        Grouping terms, each a random intercept ``(1|term)``; a term joins columns with ``:``.
    n_trials : int, default 30
        Binomial size n of every row (the number of galleries), at least 1; the response must hold
        integer counts in [0, n_trials].

    Returns
    -------
    PeerFit
        ``method`` "lme4 glmer(nAGQ=0)"; ``coefficients`` with ``estimate`` and model-based ``se`` over
        our design's column names (in the same order for formulas whose interactions have at most one
        multi-level factor first); ``variance_components`` (grouping term -> variance sigma_k^2 on the
        logit scale); ``seconds`` (R's elapsed wall-clock time of ``glmer`` alone) and ``cpu_seconds``
        (R's user + system CPU time of that fit).

    Raises
    ------
    RuntimeError
        When Rscript or lme4 is missing (see :func:`lme4_available`) or the R fit fails.

    References
    ----------
    Bates et al. (2015), J. Stat. Softw. 67(1) (``glmer``, the Laplace fit with nAGQ=0); the model is
    eq. (2) of Givens et al. (2004), AMDO, LNCS 3179.
    """
    design, _, n_trials = _design_and_response(table, fixed, n_trials)
    random = check_names(random, "random", accept_single=True)
    for term in random:
        group_indices(table, term)  # its columns exist and have no missing values
    if not lme4_available():
        raise RuntimeError("Rscript with lme4 is not available")
    response, terms = parse_formula(fixed)
    factors = [v for v, lev in design.levels.items() if lev is not None]
    rhs = " + ".join(":".join(term) for term in terms)
    random_part = " + ".join(f"(1|{g})" for g in random)
    columns = sorted({v for term in terms for v in term} | {g for r in random for g in r.split(":")})
    with tempfile.TemporaryDirectory() as tmp:
        data_path, spec_path, script_path = (Path(tmp) / n for n in ("d.csv", "spec.txt", "fit.R"))
        frame = table[columns].astype({v: str for v in factors}).copy()
        frame["Y"] = table[response].to_numpy()
        frame.to_csv(data_path, index=False)
        lines = [rhs, random_part, str(n_trials), ",".join(factors)]
        lines += ["|".join(map(str, design.levels[v])) for v in factors]
        spec_path.write_text("\n".join(lines) + "\n")
        script_path.write_text(_R_SCRIPT)
        done = subprocess.run(["Rscript", str(script_path), str(data_path), str(spec_path)],
                              capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"lme4 fit failed: {done.stderr[-500:]}")
    out = {}
    for line in done.stdout.splitlines():
        key, *values = line.split()
        out[key] = values
    coefficients = pd.DataFrame({"estimate": np.array(out["FIXED"], dtype=float),
                                 "se": np.array(out["SE"], dtype=float)}, index=list(design.column_names))
    variances = {name: float(v) for name, v in zip(out["VCNAMES"], np.array(out["VC"], dtype=float))}
    return PeerFit("lme4 glmer(nAGQ=0)", coefficients, variances, float(out["TIME"][0]), float(out["CPU"][0]))


def fit_gee(table: pd.DataFrame, fixed: str, group: str = "p", n_trials: int = 30,
            correlation: str = "exchangeable") -> PeerFit:
    """Population-averaged fit: statsmodels GEE on binomial proportions, correlated within ``group``.

    Parameters
    ----------
    table : pandas.DataFrame
        One row per binomial observation.
    fixed : str
        Fixed-effects formula (see :func:`parse_formula`); its response column holds counts.
    group : str, default "p"
        Column whose rows share a working correlation (the probe, as the paper's compound symmetry).
    n_trials : int, default 30
        Binomial size n of every row, at least 1.
    correlation : {"exchangeable", "independence"}, default "exchangeable"
        The GEE working correlation within a group.

    Returns
    -------
    PeerFit
        ``method`` "GEE (exchangeable)" or "GEE (independence)"; ``coefficients`` with ``estimate``
        (logit scale) and robust sandwich ``se`` by design column (``finite`` is False when
        statsmodels' iterations diverged); ``variance_components`` None; the fit's wall and CPU seconds.

    References
    ----------
    Liang & Zeger (1986), Biometrika 73, "Longitudinal data analysis using generalized linear models"
    (GEE); the population-averaged counterpart of the subject-specific eq. (2) of Givens et al. (2004), AMDO, LNCS 3179.
    """
    import statsmodels.api as sm

    check_choice(correlation, "correlation", ("exchangeable", "independence"))
    structure = sm.cov_struct.Exchangeable() if correlation == "exchangeable" else sm.cov_struct.Independence()
    design, y, n_trials = _design_and_response(table, fixed, n_trials)
    check_instance(group, "group", str, what="a column name (str)")
    check_dataframe(table, "table (its group column)", columns=[group])
    order = np.argsort(table[group].to_numpy(), kind="stable")
    wall, cpu = time.perf_counter(), time.process_time()
    model = sm.GEE(y[order] / n_trials, design.matrix[order], groups=table[group].to_numpy()[order],
                   family=sm.families.Binomial(), cov_struct=structure)
    # statsmodels' logit-link derivative overflows harmlessly for cells with p ~ 1
    with np.errstate(over="ignore", invalid="ignore"):
        fitted = model.fit()
    seconds, cpu_seconds = time.perf_counter() - wall, time.process_time() - cpu
    frame = pd.DataFrame({"estimate": fitted.params, "se": fitted.bse}, index=list(design.column_names))
    return PeerFit(f"GEE ({correlation})", frame, None, seconds, cpu_seconds)


def fit_naive_logistic(table: pd.DataFrame, fixed: str, n_trials: int = 30) -> PeerFit:
    """Ordinary binomial GLM that ignores all grouping (the naive analysis).

    Parameters
    ----------
    table : pandas.DataFrame
        One row per binomial observation.
    fixed : str
        Fixed-effects formula (see :func:`parse_formula`); its response column holds counts.
    n_trials : int, default 30
        Binomial size n of every row, at least 1.

    Returns
    -------
    PeerFit
        ``method`` "naive logistic"; ``coefficients`` with ``estimate`` (logit scale) and model-based
        ``se`` by design column (too small when rows of one probe are correlated);
        ``variance_components`` None; the fit's wall and CPU seconds.

    References
    ----------
    McCullagh & Nelder (1989), Generalized Linear Models, 2nd ed., Ch. 4 (binomial GLM); eq. (2) of
    Givens et al. (2004), AMDO, LNCS 3179 without its random effects.
    """
    import statsmodels.api as sm

    design, y, n_trials = _design_and_response(table, fixed, n_trials)
    endog = np.column_stack([y, n_trials - y])
    wall, cpu = time.perf_counter(), time.process_time()
    fitted = sm.GLM(endog, design.matrix, family=sm.families.Binomial()).fit()
    seconds, cpu_seconds = time.perf_counter() - wall, time.process_time() - cpu
    frame = pd.DataFrame({"estimate": fitted.params, "se": fitted.bse}, index=list(design.column_names))
    return PeerFit("naive logistic", frame, None, seconds, cpu_seconds)
