"""Chapter 5 benchmark: the binomial GLMM fit at full size, ours against lme4's glmer(nAGQ=0).

Two tables of 65,536 binomial rows (n = 30), crossed random intercepts t, p and t:p:
  chapter  the chapter's factorial experiment (8 training sets x 256 probes, 2,048 t:p cells);
  crossed  a simulated table with many more groups (16 training sets x 256 probes, 4,096 t:p
           cells, 16 configurations U x M x D per cell), so that speed cannot hinge on one design.
For each: seconds (ours: wall clock of fit_binomial_glmm; lme4: R's own elapsed timer around
glmer only), the lme4/ours ratio, the largest |coefficient difference|, the largest relative
variance-component difference, and the Laplace deviance of both estimates evaluated by our code
(the lower one is the better optimum of the same objective). One BLAS thread each.

Scaling (``--scaling``; issue 48): the number of rows fixed (76,800 and 16,384; 307,200 with
``--large``), the split between training sets and probes swept (8 x 600, 16 x 300, 40 x 120,
120 x 40 at 76,800 rows: 4,800 t:p cells of 16 rows, U (4 levels) x M x D), each table drawn by
this script's own small generator (``_split_table``, not the chapter's face generator). Per design:
our fit's wall seconds, lme4's wall seconds of the whole call (writing the CSV, starting R,
loading lme4, glmer) and of glmer alone, the ratio lme4 (whole call) / ours, the largest
differences in fixed effects and standard deviations, and, per row count, the exponent of a
log-log fit of each fitter's seconds against the number of groups (training sets + probes). At the
chapter's size (8 x 256 x 32 = 65,536 rows) the peak resident memory of each fit, each in a fresh
process. ``--phases`` profiles our fit on 8 x 600 (cProfile and CPU seconds per phase).

Run:  .venv/bin/python benchmarks/bench_05_face_glmm.py [--tables chapter crossed] [--no-lme4]
      [--repeats 3] [--json PATH]
      nice .venv/bin/python benchmarks/bench_05_face_glmm.py --scaling [--large] [--no-lme4]
      .venv/bin/python benchmarks/bench_05_face_glmm.py --phases
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


SPLITS = {16_384: [(8, 128), (16, 64), (64, 16), (128, 8)],
          76_800: [(8, 600), (16, 300), (40, 120), (120, 40)],
          307_200: [(8, 2400), (16, 1200), (40, 480), (120, 160)]}
SCALING_FORMULA = "Y ~ M * D + U"
RANDOM = ["t", "p", "t:p"]


def _split_table(n_t: int, n_p: int, n_u: int = 4, seed: int = 0):
    """A crossed binomial table of n_t training sets x n_p probes x U (n_u levels) x M x D, n = 30.

    Our own small generator (not the chapter's face generator): logit p = 0.8 + U + M + D + M:D
    + b_t + b_p + b_tp with sds 0.3, 1.5 and 0.5.
    """
    import numpy as np
    import pandas as pd

    rng = np.random.default_rng(seed)
    u_levels = [f"u{k}" for k in range(n_u)]
    grid = pd.MultiIndex.from_product([range(n_t), range(n_p), u_levels, ["l2", "soft_l2"], ["fixed", "e90"]],
                                      names=["t", "p", "U", "M", "D"]).to_frame(index=False)
    u_effect = np.linspace(-0.4, 0.3, n_u)[pd.Categorical(grid.U, categories=u_levels).codes]
    m = np.where(grid.M == "l2", 0.25, -0.25)
    d = np.where(grid.D == "fixed", 0.2, -0.2)
    t, p = grid.t.to_numpy(), grid.p.to_numpy()
    eta = (0.8 + u_effect + m + d + 0.5 * m * d + rng.normal(0, 0.3, n_t)[t] + rng.normal(0, 1.5, n_p)[p]
           + rng.normal(0, 0.5, n_t * n_p)[t * n_p + p])
    grid["Y"] = rng.binomial(30, 1 / (1 + np.exp(-eta)))
    return grid


def _peak_rss_mb(which: str) -> float:
    """Peak resident memory (MB) of one fit at the chapter's size, in a fresh process."""
    import subprocess
    import sys

    code = (f"import resource, sys; sys.path.insert(0, {str(Path(__file__).parent)!r}); "
            "import bench_05_face_glmm as b; from amdo_lab import face_glmm as fg; "
            "table = b._split_table(8, 256, n_u=8); "
            "before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss; "
            f"fit = (fg.fit_binomial_glmm if {which!r} == 'ours' else fg.fit_with_lme4)"
            "(table, b.SCALING_FORMULA, b.RANDOM, 30); "
            "own = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss; "
            "child = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss; "
            f"print(own if {which!r} == 'ours' else child, before)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    peak, before = (int(v) for v in done.stdout.split()[-2:])
    return peak / 1024, before / 1024


def _phases(bench) -> None:
    """cProfile and CPU seconds per phase of our fit on the 8 x 600 design (a single fit)."""
    import cProfile
    import io
    import pstats

    import scipy.linalg

    from amdo_lab import face_glmm as fg
    from amdo_lab.face_glmm import laplace

    spent = {"assembly": 0.0, "step": 0.0, "dense factorisation": 0.0, "solve": 0.0, "evaluations": 0}

    def timed(name, function, count=False):
        def wrapper(*args, **kwargs):
            start = time.process_time()
            try:
                return function(*args, **kwargs)
            finally:
                spent[name] += time.process_time() - start
                if count:
                    spent["evaluations"] += 1
        return wrapper

    problem = laplace.CrossedProblem
    patches = [(problem, "_big_sums", "assembly"), (problem, "_step_nested", "step"),
               (problem, "_step_general", "step"), (problem, "solve", "solve")]
    originals = [(owner, name, getattr(owner, name)) for owner, name, _ in patches]
    for owner, name, phase in patches:
        setattr(owner, name, timed(phase, getattr(owner, name), count=name == "solve"))
    cholesky = scipy.linalg.cholesky
    scipy.linalg.cholesky = timed("dense factorisation", cholesky)
    table = _split_table(8, 600)
    profile = cProfile.Profile(time.process_time)
    start = time.process_time()
    try:
        profile.enable()
        fit = fg.fit_binomial_glmm(table, SCALING_FORMULA, RANDOM, 30)
        profile.disable()
    finally:
        for owner, name, function in originals:
            setattr(owner, name, function)
        scipy.linalg.cholesky = cholesky
    total = time.process_time() - start
    report = bench.table("phase", "CPU s", "share", title="our fit on 8 x 600 (76,800 rows), CPU seconds per phase")
    eliminations = spent["step"] - spent["assembly"] - spent["dense factorisation"]
    rows = [("Hessian assembly (sums over rows/cells)", spent["assembly"]),
            ("Schur complements (t:p, then the largest other term)", eliminations),
            ("dense factorisation of the rest (Cholesky)", spent["dense factorisation"]),
            ("IRLS row passes (eta, weights, deviance, step halving)", spent["solve"] - spent["step"]),
            ("outer optimisation (L-BFGS-B) and setup", total - spent["solve"])]
    for name, seconds in rows:
        report.add(name, round(seconds, 2), f"{seconds / total:.0%}")
    report.add(f"total ({spent['evaluations']} deviance evaluations, {fit.n_iterations} IRLS steps)",
               round(total, 2), "100%")
    out = io.StringIO()
    pstats.Stats(profile, stream=out).sort_stats("tottime").print_stats(12)
    bench.note(out.getvalue())


def _scaling(bench, args) -> None:
    """Ours against lme4 over splits of a fixed number of rows; the growth exponents; peak RSS."""
    import resource

    import numpy as np

    from amdo_lab import face_glmm as fg

    use_lme4 = not args.no_lme4 and fg.lme4_available()
    sizes = args.rows or ([76_800, 16_384] + ([307_200] if args.large else []))
    report = bench.table("rows", "t x p", "groups", "ours s", "lme4 s (whole call)", "lme4 s (glmer)",
                         "ratio wall", "ratio CPU", "max|dbeta|", "max|dsd|",
                         title="seconds of one fit each, wall / CPU (user + system), one BLAS thread; lme4's "
                               "whole call includes writing the CSV, R's start and loading lme4; ratios = lme4 "
                               "whole call / ours")
    growth = bench.table("rows", "exponent ours (wall)", "exponent ours (CPU)", "exponent lme4 (wall)",
                         "exponent lme4 (CPU)",
                         title="slope of log(seconds) against log(training sets + probes) at fixed rows")
    for rows in sizes:
        seconds = {"ours": [], "ours cpu": [], "lme4": [], "lme4 cpu": []}
        groups = []
        splits = [s for s in SPLITS[rows] if not args.splits or f"{s[0]}x{s[1]}" in args.splits]
        for n_t, n_p in splits:
            table = _split_table(n_t, n_p)
            start, start_cpu = time.perf_counter(), time.process_time()
            fit = fg.fit_binomial_glmm(table, SCALING_FORMULA, RANDOM, 30)
            ours_s, ours_cpu = time.perf_counter() - start, time.process_time() - start_cpu
            seconds["ours"].append(ours_s)
            seconds["ours cpu"].append(ours_cpu)
            groups.append(n_t + n_p)
            line = [rows, f"{n_t} x {n_p}", n_t + n_p, f"{ours_s:.2f} / {ours_cpu:.2f}"]
            if use_lme4:
                children = resource.getrusage(resource.RUSAGE_CHILDREN)
                start = time.perf_counter()
                peer = fg.fit_with_lme4(table, SCALING_FORMULA, RANDOM, 30)
                whole = time.perf_counter() - start
                after = resource.getrusage(resource.RUSAGE_CHILDREN)
                whole_cpu = (after.ru_utime + after.ru_stime) - (children.ru_utime + children.ru_stime)
                seconds["lme4"].append(whole)
                seconds["lme4 cpu"].append(whole_cpu)
                dbeta = np.max(np.abs(fit.coefficients.to_numpy() - peer.estimate.to_numpy()))
                dsd = max(abs(np.sqrt(fit.variance_components[k]) - np.sqrt(peer.variance_components[k]))
                          for k in RANDOM)
                line += [f"{whole:.2f} / {whole_cpu:.2f}", f"{peer.seconds:.2f} / {peer.cpu_seconds:.2f}",
                         round(whole / ours_s, 1), round(whole_cpu / ours_cpu, 1), f"{dbeta:.1e}", f"{dsd:.1e}"]
            else:
                line += ["(not run)", "", "", "", "", ""]
            report.add(*line)
            print(" | ".join(map(str, line)), flush=True)
        slope = {k: float(np.polyfit(np.log(groups), np.log(v), 1)[0]) if len(v) == len(groups) > 1 else float("nan")
                 for k, v in seconds.items()}
        growth.add(rows, *(round(slope[k], 2) for k in ("ours", "ours cpu", "lme4", "lme4 cpu")))
    if args.no_rss:
        return
    memory = bench.table("fit", "peak RSS MB", "RSS before the fit MB",
                         title="peak resident memory at the chapter's size (8 x 256 x 32 = 65,536 rows), fresh process "
                               "(lme4: the R process)")
    for which in ["ours"] + (["lme4"] if use_lme4 else []):
        peak, before = _peak_rss_mb(which)
        memory.add(which, round(peak), round(before) if which == "ours" else "")


def main() -> None:
    bench = Benchmark(__doc__, repeats=3)
    bench.parser.add_argument("--tables", nargs="+", choices=("chapter", "crossed"), default=["chapter", "crossed"])
    bench.parser.add_argument("--no-lme4", action="store_true", help="time our fitter only")
    bench.parser.add_argument("--scaling", action="store_true", help="the split sweep at fixed rows (issue 48)")
    bench.parser.add_argument("--large", action="store_true", help="with --scaling: also 307,200 rows")
    bench.parser.add_argument("--phases", action="store_true", help="profile our fit on 8 x 600")
    bench.parser.add_argument("--rows", type=int, nargs="+", choices=sorted(SPLITS), help="with --scaling: these row counts")
    bench.parser.add_argument("--splits", nargs="+", help="with --scaling: only these splits, e.g. 8x600 40x120")
    bench.parser.add_argument("--no-rss", action="store_true", help="with --scaling: skip the peak-RSS table")
    args = bench.parse()
    if args.phases or args.scaling:
        if args.phases:
            _phases(bench)
        if args.scaling:
            _scaling(bench, args)
        bench.finish()
        return

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
