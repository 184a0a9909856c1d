"""Chapter 5: every threshold the chapter asserts, measured on several seeds of the experiment.

For each seed the full factorial experiment is run (or read from the chapter's cache under build/,
keyed on the code), eq. (2) is fitted with and without the configuration x training-set term, and
with the image-size terms, and every quantity the chapter compares with a threshold is printed: one
row per quantity, one column per seed, then the minimum and maximum over seeds and the chapter's
threshold. Seed 2004 is the chapter's.

    .venv/bin/python benchmarks/dev_05_seed_spread.py [--seeds 2004 1 2 3 4] [--json PATH]
"""

from __future__ import annotations

from pathlib import Path

from _harness import Benchmark  # first: pins BLAS threads before numpy is imported

ROOT = Path(__file__).resolve().parents[1]


def measure(seed: int) -> dict:
    """The chapter's asserted quantities for one seed of the experiment."""
    import numpy as np
    import pandas as pd
    from scipy.special import expit

    from amdo_lab import face_glmm as fg
    from amdo_lab.common import make_rng

    table, _ = fg.load_or_run_experiment(fg.paper_design(), ROOT / "build", rng=seed)
    fit = fg.fit_binomial_glmm(table, fg.PAPER_FORMULA, ["t", "p", "t:p"], 30)
    extended = fg.fit_binomial_glmm(table, fg.PAPER_FORMULA, ["t", "p", "t:p", "t:U:M:D"], 30)
    size_fit = fg.fit_binomial_glmm(table, fg.SIZE_FORMULA, ["t", "p", "t:p"], 30)
    size_ext = fg.fit_binomial_glmm(table, fg.SIZE_FORMULA, ["t", "p", "t:p", "t:U:M:D:S"], 30)
    out = {}
    e90 = table[table.D == "e90"].groupby(["U", "S"], observed=True).k.agg(["min", "max"]).unstack("S")
    out["E90 standard min (>= 64)"] = e90["min"]["standard"].min()
    out["E90 standard max (<= 107)"] = e90["max"]["standard"].max()
    out["E90 standard min - small max, per U (> 0)"] = (e90["min"]["standard"] - e90["max"]["small"]).min()
    out["E90 shift/refl min - none max (> 0)"] = (e90["min"].loc[["shift", "reflection"]]
                                                  - e90["max"].loc["none"]).min().min()
    table2 = fg.table2_comparison(fit)
    config_only = [t for t in table2.index if "F" not in t.split(":")]
    drop = fit.tests.F / extended.tests.F
    to_paper = extended.tests.F.reindex(table2.index) / table2["F paper"]
    out["F drop, config-only terms, min (> 10)"] = drop[config_only].min()
    out["F drop, config-only terms, argmin"] = drop[config_only].idxmin()
    out["F drop, terms with F, min (>= 0.8)"] = drop.drop(config_only).min()
    out["F drop, terms with F, max (<= 1.25)"] = drop.drop(config_only).max()
    out["F(+t:U:M:D)/paper, config-only but U, min (>= 1/4)"] = to_paper[config_only].drop("U").min()
    out["F(+t:U:M:D)/paper, config-only but U, max (<= 4)"] = to_paper[config_only].drop("U").max()
    out["F(+t:U:M:D)/paper, U (> 4)"] = to_paper["U"]
    out["F(+t:U:M:D)/paper, terms with F, argmax (D:F)"] = to_paper.drop(config_only).idxmax()
    out["largest config-only F, eq. (2) / extended (D)"] = (fit.tests.F[config_only].idxmax() + " / "
                                                            + extended.tests.F[config_only].idxmax())
    rate = table.groupby(["S", "F"], observed=True).Y.mean().unstack() / 30
    out["rate standard - small, min over F (> 0)"] = (rate.loc["standard"] - rate.loc["small"]).min()
    size_terms = [t for t in size_fit.tests.index if "S" in t.split(":")]
    out["size terms, largest p with t:U:M:D:S (< 0.05)"] = size_ext.tests.p_value[size_terms].max()
    vc = fit.variance_components
    out["training-set / probe variance (< 0.05)"] = vc["t"] / vc["p"]
    out["training-set variance, eq. (2)"] = vc["t"]
    out["rho (> 0.70)"] = fit.probe_correlation
    eq2, ext = fg.findings(fit, size_fit), fg.findings(extended, size_ext)
    out["findings holding, eq. (2) / extended"] = f"{int(eq2['holds for ours'].sum())} / {int(ext['holds for ours'].sum())}"
    out["verdicts equal under both models"] = bool((eq2["holds for ours"] == ext["holds for ours"]).all())

    def logit_marginal(result, **levels):
        p = float(result.predict_marginal(pd.DataFrame({k: [v] for k, v in levels.items()})).p.iloc[0])
        return np.log(p / (1 - p))

    ratio = {}
    for name, f in (("supplement range", lambda F: np.ptp([logit_marginal(fit, U=u, F=F) for u in table.U.cat.categories])),
                    ("soft L2 gain", lambda F: logit_marginal(fit, M="soft_l2", F=F) - logit_marginal(fit, M="l2", F=F)),
                    ("E90 loss", lambda F: logit_marginal(fit, D="fixed", F=F) - logit_marginal(fit, D="e90", F=F))):
        ratio[name] = f("yes") / f("no")
    out["logit yes/no, soft L2 gain (> 2)"] = ratio["soft L2 gain"]
    out["logit yes/no, E90 loss (> 2)"] = ratio["E90 loss"]
    out["logit yes/no, supplement range (> 1)"] = ratio["supplement range"]
    incl = {(m, d): logit_marginal(fit, M=m, D=d, F="yes") - logit_marginal(fit, M=m, D=d, F="no")
            for m in ("l2", "soft_l2") for d in ("fixed", "e90")}
    order = sorted(incl, key=incl.get)
    out["inclusion effect, smallest cell (l2, e90)"] = ", ".join(order[0])
    out["inclusion effect, l2/e90 value"] = incl[("l2", "e90")]
    out["inclusion effect, second smallest - smallest"] = incl[order[1]] - incl[order[0]]
    gee = fg.fit_gee(table, fg.PAPER_FORMULA, group="p", correlation="independence")
    coef = fit.coefficients
    slope = np.polyfit(coef.iloc[1:], gee.estimate.iloc[1:], 1)[0]
    sigma2 = sum(vc.values())
    approx = 1 / np.sqrt(1 + 0.346 * sigma2)
    out["GEE/GLMM slope - approximation (> 0.02)"] = slope - approx
    b_hat = fit.random_effects["p"][table.p.to_numpy()] + fit.random_effects["t:p"][fg.group_indices(table, "t:p")]
    eta_fixed = fit.design.matrix @ fit.coefficients.to_numpy()
    cells_eta = np.unique(np.round(eta_fixed, 10))

    def attenuation(draws_b):
        marginal = np.array([np.mean(expit(e + draws_b)) for e in cells_eta])
        return np.polyfit(cells_eta, np.log(marginal / (1 - marginal)), 1)[0]

    over_normal = attenuation(np.sqrt(sigma2) * make_rng(0).standard_normal(4000))
    over_fitted = attenuation(b_hat[::16])
    out["|average over normal b - approximation| (< 0.05)"] = abs(over_normal - approx)
    out["over normal < over fitted < GEE slope"] = bool(over_normal < over_fitted < slope)
    perfect = table.groupby("p").Y.apply(lambda y: np.mean(y == 30))
    out["probes perfect in every row"] = float(np.mean(perfect == 1))
    out["probes perfect in >= 90 % of rows"] = float(np.mean(perfect >= 0.9))
    draws = fg.experiment_draws(fg.paper_design(), rng=seed)
    faces = fg.preprocess_images(draws.population.images).reshape(256, 4, *fg.STANDARD_SHAPE)
    identity = faces.mean(axis=1)

    def odd_share(variation):
        return float(np.sum(((variation - variation[..., ::-1]) / 2) ** 2) / np.sum(variation**2))

    out["odd share within / identity (> 2)"] = (odd_share(faces - identity[:, None])
                                                / odd_share(identity - identity.mean(axis=0)))
    out["odd share between probes (< real faces' 0.47)"] = odd_share(faces[:, 0] - faces[:, 0].mean(axis=0))
    half = table[table.p < 128].reset_index(drop=True)
    half_fit = fg.fit_binomial_glmm(half, fg.PAPER_FORMULA, ["t", "p", "t:p", "t:U:M:D"], 30)
    half_to_full = half_fit.tests.F / extended.tests.F
    with_f = [t for t in half_to_full.index if "F" in t.split(":")]
    out["half/full F: config-only min - with-F max (> 0)"] = half_to_full.drop(with_f).min() - half_to_full[with_f].max()
    out["half table: terms with p > 0.05"] = ", ".join(sorted(half_fit.tests.index[half_fit.tests.p_value > 0.05])) or "none"
    out["F drop > 10, set"] = ", ".join(sorted(drop.index[drop > 10]))
    return out


def main() -> None:
    bench = Benchmark(__doc__, repeats=1)
    bench.parser.add_argument("--seeds", nargs="+", type=int, default=[2004, 1, 2, 3, 4])
    args = bench.parse()
    import pandas as pd

    columns = {}
    for seed in args.seeds:
        columns[seed] = measure(seed)
        print(f"seed {seed} done", flush=True)
    frame = pd.DataFrame(columns)
    numeric = frame.apply(lambda row: pd.to_numeric(row, errors="coerce"), axis=1)
    report = bench.table("quantity (threshold)", *[str(s) for s in args.seeds], "min", "max",
                         title="the chapter's asserted quantities per seed (2004: the chapter's)")
    for name, row in frame.iterrows():
        values = numeric.loc[name]
        cells = [f"{v:.4g}" if isinstance(v, float) else str(v) for v in row]
        spread = [f"{values.min():.4g}", f"{values.max():.4g}"] if values.notna().all() else ["", ""]
        report.add(name, *cells, *spread)
    bench.finish()


if __name__ == "__main__":
    main()
