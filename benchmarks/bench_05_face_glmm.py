"""Chapter 5 benchmark: the binomial GLMM fit at full size, ours against lme4's glmer(nAGQ=0).

Two tables of 65,536 binomial rows (n = 30), crossed random intercepts t, p and t:p:
  chapter  the chapter's factorial experiment (8 training sets x 256 probes, 2,048 t:p cells);
  crossed  a simulated table with many more groups (16 training sets x 256 probes, 4,096 t:p
           cells, 16 configurations U x M x D per cell), so that speed cannot hinge on one design.
For each: seconds (ours: wall clock of fit_binomial_glmm; lme4: R's own elapsed timer around
glmer only), the lme4/ours ratio, the largest |coefficient difference|, the largest relative
variance-component difference, and the Laplace deviance of both estimates evaluated by our code
(the lower one is the better optimum of the same objective). One BLAS thread each.

Run:  .venv/bin/python benchmarks/bench_05_face_glmm.py [--tables chapter crossed] [--no-lme4]
      [--repeats 3] [--json PATH]
"""

from __future__ import annotations

import time
from pathlib import Path

from _harness import Benchmark  # first: pins BLAS threads before numpy is imported


def _crossed_table(rng: int):
    import pandas as pd

    from amdo_lab import face_glmm as fg

    grid = pd.MultiIndex.from_product(
        [range(16), range(256), ["none", "shift", "reflection", "noise"], ["l2", "soft_l2"], ["fixed", "e90"]],
        names=["t", "p", "U", "M", "D"]).to_frame(index=False)
    formula = "Y ~ U * M * D"
    beta = [1.2, -0.3, 0.2, 0.25, -0.4, 0.6, 0.05, -0.05, 0.02, 0.1, 0.0, -0.1, 0.08, 0.0, 0.03, -0.02]
    grid["Y"] = fg.simulate_binomial_glmm(grid, formula, beta, {"t": 0.02, "p": 2.0, "t:p": 0.3}, 30, rng=rng)
    return grid, formula


def _time_ours(table, formula, random, repeats):
    """Best wall-clock and CPU seconds of ``repeats`` fits (CPU time is robust to a shared machine)."""
    from amdo_lab import face_glmm as fg

    wall, cpu, fit = float("inf"), float("inf"), None
    for _ in range(repeats):
        start, start_cpu = time.perf_counter(), time.process_time()
        fit = fg.fit_binomial_glmm(table, formula, random, 30)
        wall = min(wall, time.perf_counter() - start)
        cpu = min(cpu, time.process_time() - start_cpu)
    return fit, wall, cpu


def main() -> None:
    bench = Benchmark(__doc__, repeats=3)
    bench.parser.add_argument("--tables", nargs="+", choices=("chapter", "crossed"), default=["chapter", "crossed"])
    bench.parser.add_argument("--no-lme4", action="store_true", help="time our fitter only")
    args = bench.parse()

    import numpy as np

    from amdo_lab import face_glmm as fg

    random = ["t", "p", "t:p"]
    use_lme4 = not args.no_lme4 and fg.lme4_available()
    report = bench.table("table", "rows", "t:p cells", "ours s", "lme4 s", "ratio", "max|dcoef|", "max rel dvar",
                         "dev ours", "dev lme4", "lower dev",
                         title="seconds: wall clock / CPU (user + system), ours the best of --repeats; "
                               "ratio = lme4 / ours, on CPU seconds")
    for name in args.tables:
        if name == "chapter":
            # the chapter's own cache (build/, keyed on the code), so the table is the chapter's
            table, _ = fg.load_or_run_experiment(fg.paper_design(), Path(__file__).resolve().parents[1] / "build",
                                                  rng=2004)
            formula = fg.PAPER_FORMULA
        else:
            table, formula = _crossed_table(rng=7)
        fit, ours_s, ours_cpu = _time_ours(table, formula, random, args.repeats)
        cells = int(fg.group_indices(table, "t:p").max() + 1)
        line = [name, len(table), cells, f"{ours_s:.2f}/{ours_cpu:.2f}"]
        if use_lme4:
            peer = fg.fit_with_lme4(table, formula, random, 30)
            coef = np.max(np.abs(fit.coefficients.to_numpy() - peer.estimate.to_numpy()))
            # relative to the larger of the two (a component at its bound 0 in one fit would divide by zero)
            rel = max(abs(fit.variance_components[k] - peer.variance_components[k])
                      / max(fit.variance_components[k], peer.variance_components[k], 1e-300) for k in random)
            sds = [[np.sqrt(fit.variance_components[k]) for k in random],
                   [np.sqrt(peer.variance_components[k]) for k in random]]
            dev_ours, dev_lme4 = fg.laplace_deviance(table, formula, random, sds, 30)
            lme4_s = f"{peer.seconds:.2f}/{peer.cpu_seconds:.2f}"
            line += [lme4_s, round(peer.cpu_seconds / ours_cpu, 1), f"{coef:.1e}", f"{rel:.1e}",
                     f"{float(dev_ours):.4f}", f"{float(dev_lme4):.4f}",
                     "ours" if dev_ours <= dev_lme4 else "lme4"]
        else:
            line += ["(lme4 not run)"] + [""] * 6
        report.add(*line)
        print(f"table {name} done", flush=True)
    bench.finish()


if __name__ == "__main__":
    main()
