"""Chapter 5 benchmark: full-size binomial GLMM fit (65,536 rows, crossed t, p, t:p).

Prints one table: our fitter vs lme4's glmer(nAGQ=0) when Rscript + lme4 are present,
with the largest coefficient and variance-component differences from the same run.

Run:  .venv/bin/python benchmarks/bench_05_face_glmm.py
"""

from __future__ import annotations

import tempfile
import time

import numpy as np

from amdo_lab import face_glmm as fg


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        table, _ = fg.load_or_run_experiment(fg.paper_design(), 2004, tmp)
        experiment_s = time.perf_counter() - start
    start = time.perf_counter()
    ours = fg.fit_binomial_glmm(table, fg.PAPER_FORMULA, ["t", "p", "t:p"], 30)
    ours_s = time.perf_counter() - start
    rows = [("factorial experiment (full design)", experiment_s, "", ""),
            ("our GLMM fit (Laplace, nAGQ=0 objective)", ours_s, "", "")]
    if fg.lme4_available():
        lme4 = fg.fit_with_lme4(table, fg.PAPER_FORMULA, ["t", "p", "t:p"], 30)
        coef_diff = np.max(np.abs(ours.coefficients.to_numpy() - lme4["coefficients"].to_numpy()))
        vc_diff = max(abs(ours.variance_components[k] - lme4["variance_components"][k])
                      for k in ours.variance_components)
        rows.append(("lme4 glmer(nAGQ=0), R's own timer", lme4["seconds"], f"{coef_diff:.2e}", f"{vc_diff:.2e}"))
        rows.append(("ratio lme4 / ours", lme4["seconds"] / ours_s, "", ""))
    else:
        rows.append(("lme4 glmer(nAGQ=0)", float("nan"), "Rscript/lme4 absent", ""))
    print(f"rows = {len(table):,}; variance components ours = "
          f"{ {k: round(v, 4) for k, v in ours.variance_components.items()} }")
    print(f"{'task':<44}{'seconds':>10}  {'max |coef diff|':>16}  {'max |var diff|':>15}")
    for name, seconds, c, v in rows:
        print(f"{name:<44}{seconds:>10.2f}  {c:>16}  {v:>15}")


if __name__ == "__main__":
    main()
