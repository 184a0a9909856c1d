"""Chapter 3 benchmark: CAT viscous-fluid registration versus Christensen's SOR anchor, the exact FFT
solve of the same PDE, and DIPY's SymmetricDiffeomorphicRegistration, on the pairs A, B, C (256x256).

Goals checked: a 256x256 CAT registration in under 1 s on one core, and at least 20x faster
than the SOR anchor (100 registration iterations x 250 SOR sweeps, as in the paper) at equal or
lower residual.

    .venv/bin/python benchmarks/bench_03_cat_fluid.py [--pairs A B C] [--sor-iterations 100]
        [--sor-sweeps 250] [--long-iterations 100] [--skip-dipy] [--paper-gap]
        [--noise-seeds 0 1 2 3 4 5] [--claim-seeds 0 1 2 3 4] [--grid-convergence 0 1 2 3 4 5 6 7 8 9]

The defaults are the full-size anchor (about 1-2 minutes of SOR per pair). "residual" is the
mean |deformed template - study| in grey levels of 0-255 (Table 1's measure) on the whole image;
"masked" the same on the foreground mask; RMSE is the displacement error against the known warp
on the mask, in pixels; "folded" the share of pixels with det(I - grad u) <= 0. A separate CAT run of
--target-iterations looks for the first iteration that reaches SOR's final residual (its time
from the run's own history); the speed-up is SOR's time over that time. The notebook's reduced
SOR setting (--reduced-sweeps per solve) is run too, to show how it compares with the full anchor.

--noise-seeds asks whether "CAT residual <= SOR residual" is a property of the
methods or of one draw: each seed of make_pair draws another warp and, for A and B, other noise; it
prints both residuals beside the residual of the true warp, and per pair the mean and sd of the
difference and on how many draws CAT is at most SOR (about 35 s per seed and pair). With the full 250
sweeps, ``--noise-seeds 0 1 2 --pairs C A`` printed CAT lower on 3 of 3 draws of C and on 1 of 3 draws of A
(differences of hundredths of a grey level either way).

--claim-seeds measures, over draws of the pairs, every threshold the chapter asserts on seed 0: CAT and
the finite differences solved exactly by FFT (FD-FFT) at 10 and 100 iterations, SOR 100 x 25, DIPY SyN;
per claim it prints the smallest and largest margin. Seeds 0-4 printed: |CAT - FD-FFT| at most 0.091 grey
levels (seed 0: 0.015), the gain of CAT from 10 to 100 iterations at least 0.169 (seed 0: 0.178), SOR below
CAT-10 by 0.184 at least, SyN's RMSE above CAT-100's on A and C on every draw, below it on B on 4 of 5.

--grid-convergence solves a random smooth periodic velocity field's exact force with each stencil on
16-128 grids: both second order; CAT's error 1.2 to 2.1 times the finite differences' (seeds 0-9).

Caveat on the speed ratios: our SOR is vectorised numpy (one colour of one component per array
operation, about 1.5-2 ms per sweep on 256x256); a compiled SOR would be several times faster, so the
ratios measure these implementations, not the algorithms alone. Each exact CAT solve is two FFTs.
BLAS/FFT threads are limited to one (benchmarks/_harness.py); ``--json PATH`` writes the tables.
"""

from __future__ import annotations

from _harness import Benchmark  # first: pins BLAS threads before numpy is imported

GREY = 255.0
PAIR_NAMES = ("A", "B", "C")  # cat_fluid.PAIR_NAMES, spelled here so --help needs no import
COLUMNS = ("pair", "method", "iterations", "time s", "residual", "masked", "RMSE px", "min det", "folded %")


def _load():
    """numpy and the chapter's package, imported after the arguments are parsed."""
    import numpy as np

    from amdo_lab import cat_fluid as cf

    assert tuple(cf.PAIR_NAMES) == PAIR_NAMES, "update PAIR_NAMES to the package's pairs"
    return np, cf


def row(pair, label: str, warped, displacement, seconds: float, iterations: str) -> dict:
    np, cf = _load()
    det = cf.jacobian_determinant(displacement)
    return {
        "pair": pair.name, "method": label, "iterations": iterations, "seconds": seconds,
        "residual": cf.grey_level_difference(warped, pair.study, scale=GREY)[0],
        "masked": cf.grey_level_difference(warped, pair.study, pair.mask, scale=GREY)[0],
        "rmse": cf.displacement_rmse(displacement, pair.true_displacement, pair.mask),
        "min_det": float(det.min()), "folded_pct": 100.0 * float(np.mean(det <= 0)),
    }


def add_rows(bench: Benchmark, rows: list[dict], title: str = "") -> None:
    table = bench.table(*COLUMNS, title=title)
    for r in rows:
        table.add(r["pair"], r["method"], r["iterations"], round(r["seconds"], 2), round(r["residual"], 3),
                  round(r["masked"], 3), round(r["rmse"], 3), round(r["min_det"], 3), round(r["folded_pct"], 2))


def paper_gap(bench: Benchmark, pairs: list[str], sor_iterations: int, sor_sweeps: int) -> None:
    """Could the paper's table (CAT after 10 iterations better than SOR after 100 x 250) come from a
    weaker SOR or from larger CAT steps? A cold-started Gauss-Seidel SOR (omega = 1, each solve from
    zero) is the weakest plausible anchor; CAT's step bound is raised from 1 to 8 pixels."""
    _, cf = _load()
    rows = []
    for name in pairs:
        pair = cf.make_pair(name, rng=0)
        for step in (1.0, 2.0, 4.0, 8.0):
            cat = cf.register_fluid(pair.template, pair.study, method="cat", n_iter=10, max_step_px=step)
            rows.append(row(pair, f"CAT, max_step_px {step:.0f}", cat.warped, cat.displacement, cat.seconds, "10"))
        for label, options in (("SOR warm, default omega", {}),
                               ("SOR cold, omega 1", {"sor_warm_start": False, "sor_omega": 1.0})):
            sor = cf.register_fluid(pair.template, pair.study, method="sor", n_iter=sor_iterations,
                                    sor_n_sweeps=sor_sweeps, **options)
            rows.append(row(pair, label, sor.warped, sor.displacement, sor.seconds, f"{sor_iterations}x{sor_sweeps}"))
    add_rows(bench, rows, "the paper's CAT-10 vs SOR-100 gap: larger CAT steps, a weaker SOR")


def noise_seeds(bench: Benchmark, pairs: list[str], seeds: list[int], cat_iterations: int, sor_iterations: int,
                sor_sweeps: int) -> None:
    """Is "CAT residual <= SOR residual" a property of the methods or of one draw? Each seed of
    ``make_pair`` draws another smooth warp and, for A and B, other sensor noise; CAT and the full SOR
    anchor register every draw. The residual of the true warp (template warped by the known
    displacement) is printed beside them: below it, a method is fitting the noise, the blob or the
    drift rather than recovering the warp."""
    np, cf = _load()
    table = bench.table("pair", "seed", "true warp", "CAT res", "SOR res", "CAT-SOR", "CAT RMSE", "SOR RMSE",
                        title=f"CAT {cat_iterations} iterations, SOR {sor_iterations}x{sor_sweeps}; residual = mean "
                              "|deformed - study| in grey levels, RMSE = displacement error on the mask in pixels")
    for name in pairs:
        differences = []
        for seed in seeds:
            pair = cf.make_pair(name, rng=seed)
            truth = cf.grey_level_difference(cf.warp_image(pair.template, pair.true_displacement), pair.study,
                                             scale=GREY)[0]
            cat = cf.register_fluid(pair.template, pair.study, method="cat", n_iter=cat_iterations)
            sor = cf.register_fluid(pair.template, pair.study, method="sor", n_iter=sor_iterations, sor_n_sweeps=sor_sweeps)
            cat_residual, sor_residual = GREY * cat.residuals[-1], GREY * sor.residuals[-1]
            differences.append(cat_residual - sor_residual)
            table.add(name, seed, round(float(truth), 3), round(float(cat_residual), 3), round(float(sor_residual), 3),
                      f"{differences[-1]:+.3f}",
                      round(float(cf.displacement_rmse(cat.displacement, pair.true_displacement, pair.mask)), 3),
                      round(float(cf.displacement_rmse(sor.displacement, pair.true_displacement, pair.mask)), 3))
            print(f"pair {name}, seed {seed} done", flush=True)
        differences = np.array(differences)
        spread = differences.std(ddof=1) if differences.size > 1 else float("nan")
        bench.note(f"{name:4} CAT-SOR residual: mean {differences.mean():+.3f}, sd {spread:.3f}; "
                   f"CAT <= SOR on {int(np.sum(differences <= 0))} of {differences.size} draws")


def claim_seeds(bench: Benchmark, pairs: list[str], seeds: list[int], sor_sweeps: int, skip_dipy: bool) -> None:
    """The spread over draws of every threshold the chapter asserts on the pairs (seed 0 in the chapter).

    Each seed of ``make_pair`` draws another warp and, for A and B, other noise. Per draw: CAT and the
    finite differences solved exactly by FFT, at 10 and 100 iterations; SOR 100 x ``sor_sweeps``
    (the chapter's setting); DIPY SyN; the displacement RMSE on the mask and the folded share. The
    notes give, per claim, the smallest margin over the draws (positive: the claim holds on all)."""
    np, cf = _load()
    table = bench.table("pair", "seed", "CAT10", "FFT10", "CAT100", "FFT100", "SOR", "RMSE CAT100", "RMSE FFT100",
                        "RMSE SOR", "RMSE SyN", "folded %", "blob: CAT", "blob: true",
                        title=f"residual (mean |deformed - study|, grey levels) and RMSE (px, mask); SOR 100x{sor_sweeps}")
    margins: dict[str, list[float]] = {}

    def margin(claim: str, value: float) -> None:
        margins.setdefault(claim, []).append(float(value))

    for name in pairs:
        for seed in seeds:
            pair = cf.make_pair(name, rng=seed)
            runs = {(method, n): cf.register_fluid(pair.template, pair.study, method=method, n_iter=n)
                    for method in ("cat", "fft") for n in (10, 100)}
            runs["sor"] = cf.register_fluid(pair.template, pair.study, method="sor", sor_n_sweeps=sor_sweeps)
            res = {key: GREY * run.residuals[-1] for key, run in runs.items()}
            rmse = {key: cf.displacement_rmse(run.displacement, pair.true_displacement, pair.mask)
                    for key, run in runs.items()}
            folded = max(100.0 * float(np.mean(cf.jacobian_determinant(run.displacement) <= 0)) for run in runs.values())
            syn = float("nan")
            if not skip_dipy:
                peer = cf.register_dipy(pair.template, pair.study)
                syn = cf.displacement_rmse(peer.displacement, pair.true_displacement, pair.mask)
                folded = max(folded, 100.0 * float(np.mean(cf.jacobian_determinant(peer.displacement) <= 0)))
            blob_cat = blob_true = float("nan")
            if name == "A":
                rows, cols = np.indices(pair.template.shape)
                centre = np.multiply(cf.BLOB_CENTRE_FRACTION, pair.template.shape)
                near = np.hypot(rows - centre[0], cols - centre[1]) < 2.4 * cf.BLOB_SD
                true_warped = cf.warp_image(pair.template, pair.true_displacement)
                blob_cat = GREY * np.abs(runs["cat", 100].warped - pair.study)[near].mean()
                blob_true = GREY * np.abs(true_warped - pair.study)[near].mean()
                margin("A: near the blob, CAT 100 residual < true warp's", blob_true - blob_cat)
            table.add(name, seed, *(round(float(res[k]), 3) for k in (("cat", 10), ("fft", 10), ("cat", 100),
                                                                      ("fft", 100), "sor")),
                      *(round(float(rmse[k]), 3) for k in (("cat", 100), ("fft", 100), "sor")), round(syn, 3),
                      round(folded, 2), round(float(blob_cat), 1), round(float(blob_true), 1))
            gain = res["cat", 10] - res["cat", 100]
            margin("SOR 100xN residual < CAT 10 (every pair)", res["cat", 10] - res["sor"])
            margin("|CAT - FFT| at 10 and 100 it. < 0.1", 0.1 - max(abs(res["cat", 10] - res["fft", 10]),
                                                                    abs(res["cat", 100] - res["fft", 100])))
            margin("|CAT 100 - SOR| < 0.1", 0.1 - abs(res["cat", 100] - res["sor"]))
            margin("gain of CAT from 10 to 100 it. > 0.1", gain - 0.1)
            margin("no folded pixel (%)", -folded)
            if name == "C":
                margin("C: RMSE > 1 px for CAT, FFT, SOR (and SyN)",
                       min(rmse["cat", 100], rmse["fft", 100], rmse["sor"], rmse["cat", 10],
                           syn if syn == syn else np.inf) - 1.0)
            if not skip_dipy:
                if name == "B":
                    margin("B: SyN RMSE < CAT 100", rmse["cat", 100] - syn)
                else:
                    margin(f"{name}: SyN RMSE > CAT 100", syn - rmse["cat", 100])
            print(f"pair {name}, seed {seed} done", flush=True)
    for claim, values in margins.items():
        values = np.array(values)
        bench.note(f"{claim}: smallest margin {values.min():+.3f}, largest {values.max():+.3f} over {values.size} draws")


def grid_convergence(bench: Benchmark, seeds: list[int], sizes: tuple[int, ...] = (16, 32, 64, 128)) -> None:
    """The error of an exact velocity solve against the continuous solution, CAT stencil vs finite
    differences, on random smooth periodic velocity fields (six waves, wave numbers -3..3 per unit length,
    Gaussian amplitudes) whose force is the continuous operator applied exactly. Prints the error at each
    grid size, the observed order between the two finest grids and the CAT / FD error ratio."""
    np, cf = _load()
    lam, mu = 1.0, 5.0
    table = bench.table("seed", *(f"CAT n={n}" for n in sizes), *(f"FD n={n}" for n in sizes), "order CAT",
                        "order FD", "CAT/FD (finest)",
                        title="max |v_h - v| / max |v| of an exact solve on an n x n grid of the unit square")
    ratios, orders = [], []
    for seed in seeds:
        rng = np.random.default_rng(seed)
        waves = [(2 * np.pi * rng.integers(-3, 4, 2).astype(float), rng.normal(size=2)) for _ in range(6)]
        waves = [(w if w.any() else np.array([2 * np.pi, 0.0]), e) for w, e in waves]
        errors = {"cat": [], "fft": []}
        for n in sizes:
            x1, x2 = (np.indices((n, n)) + 0.5) / n
            velocity, force = np.zeros((2, n, n)), np.zeros((2, n, n))
            for w, e in waves:
                wave = np.cos(w[0] * x1 + w[1] * x2)
                velocity += e[:, None, None] * wave
                force -= (mu * (w @ w) * e + (lam + mu) * w * (w @ e))[:, None, None] * wave
            for method in errors:
                solved = cf.solve_velocity(force / n ** 2, method, lam, mu)  # K v = h^2 F, h = 1/n
                errors[method].append(np.abs(solved - velocity).max() / np.abs(velocity).max())
        order = {m: np.log2(e[-2] / e[-1]) for m, e in errors.items()}
        ratios.append(errors["cat"][-1] / errors["fft"][-1])
        orders += list(order.values())
        table.add(seed, *(f"{e:.2e}" for e in errors["cat"]), *(f"{e:.2e}" for e in errors["fft"]),
                  round(order["cat"], 2), round(order["fft"], 2), round(ratios[-1], 2))
    bench.note(f"CAT / FD error ratio on the finest grid: {min(ratios):.2f} to {max(ratios):.2f}; "
               f"observed orders {min(orders):.2f} to {max(orders):.2f}")


def main() -> None:
    bench = Benchmark(__doc__)
    parser = bench.parser
    parser.add_argument("--pairs", nargs="+", default=list(PAIR_NAMES), choices=PAIR_NAMES)
    parser.add_argument("--sor-iterations", type=int, default=100)
    parser.add_argument("--sor-sweeps", type=int, default=250)
    parser.add_argument("--long-iterations", type=int, default=100,
                        help="iterations of the longer CAT and FFT runs (default: SOR's 100)")
    parser.add_argument("--target-iterations", type=int, default=300,
                        help="iterations of the CAT run that looks for SOR's final residual")
    parser.add_argument("--reduced-sweeps", type=int, default=25,
                        help="SOR sweeps per solve of the notebook's reduced setting (0 to skip)")
    parser.add_argument("--skip-dipy", action="store_true")
    parser.add_argument("--paper-gap", action="store_true",
                        help="only test two explanations of the paper's CAT-10 vs SOR-100 gap (about 5 min)")
    parser.add_argument("--noise-seeds", type=int, nargs="+", default=None,
                        help="only compare CAT (--long-iterations) with SOR over these seeds of make_pair "
                             "(other warps and noise; about 1 min per seed and pair)")
    parser.add_argument("--claim-seeds", type=int, nargs="+", default=None,
                        help="only the spread over these seeds of the thresholds the chapter asserts "
                             "(CAT, FFT, SOR 100x--reduced-sweeps, SyN; about 40 s per seed and pair)")
    parser.add_argument("--grid-convergence", type=int, nargs="+", default=None, metavar="SEED",
                        help="only the exact-solve error against grid spacing, CAT vs FD, on random fields")
    args = bench.parse()
    if args.claim_seeds is not None:
        claim_seeds(bench, args.pairs, args.claim_seeds, args.reduced_sweeps, args.skip_dipy)
    elif args.grid_convergence is not None:
        grid_convergence(bench, args.grid_convergence)
    elif args.noise_seeds is not None:
        noise_seeds(bench, args.pairs, args.noise_seeds, args.long_iterations, args.sor_iterations, args.sor_sweeps)
    elif args.paper_gap:
        paper_gap(bench, args.pairs, args.sor_iterations, args.sor_sweeps)
    else:
        speed_and_accuracy(bench, args)
    bench.finish()


def speed_and_accuracy(bench: Benchmark, args) -> None:
    """Every solver on every pair, then how long CAT takes to reach SOR's final residual."""
    np, cf = _load()
    rows, summary = [], []
    for name in args.pairs:
        pair = cf.make_pair(name, rng=0)
        rows.append(row(pair, "start (identity)", pair.template, np.zeros((2,) + pair.template.shape), 0.0, "0"))
        runs = {}
        for method, n_iter in (("cat", 10), ("fft", 10), ("cat", args.long_iterations), ("fft", args.long_iterations)):
            result = cf.register_fluid(pair.template, pair.study, method=method, n_iter=n_iter)
            runs[(method, n_iter)] = result
            rows.append(row(pair, f"{method.upper()} exact solve", result.warped, result.displacement,
                            result.seconds, str(n_iter)))
        sor = cf.register_fluid(pair.template, pair.study, method="sor", n_iter=args.sor_iterations,
                                sor_n_sweeps=args.sor_sweeps)
        rows.append(row(pair, "SOR (Christensen)", sor.warped, sor.displacement, sor.seconds,
                        f"{args.sor_iterations}x{args.sor_sweeps}"))
        if args.reduced_sweeps:
            reduced = cf.register_fluid(pair.template, pair.study, method="sor", n_iter=args.sor_iterations,
                                        sor_n_sweeps=args.reduced_sweeps)
            rows.append(row(pair, "SOR (notebook setting)", reduced.warped, reduced.displacement, reduced.seconds,
                            f"{args.sor_iterations}x{args.reduced_sweeps}"))
        if not args.skip_dipy:
            peer = cf.register_dipy(pair.template, pair.study)
            rows.append(row(pair, "DIPY SyN (CC)", peer.warped, peer.displacement, peer.seconds, "100/100/25"))
        target_run = cf.register_fluid(pair.template, pair.study, method="cat", n_iter=args.target_iterations)
        reached = np.flatnonzero(target_run.residuals <= sor.residuals[-1])
        near = np.flatnonzero(target_run.residuals <= 1.01 * sor.residuals[-1])
        first = int(reached[0]) if reached.size else None
        first_near = int(near[0]) if near.size else None
        summary.append({
            "pair": name, "sor_seconds": sor.seconds, "sor_residual": GREY * sor.residuals[-1],
            "cat10_seconds": runs[("cat", 10)].seconds, "cat10_residual": GREY * runs[("cat", 10)].residuals[-1],
            "catlong_residual": GREY * runs[("cat", args.long_iterations)].residuals[-1],
            "best_residual": GREY * target_run.residuals.min(),
            "first": first, "first_seconds": None if first is None else float(target_run.history[first, 1]),
            "near": first_near, "near_seconds": None if first_near is None else float(target_run.history[first_near, 1]),
        })

    add_rows(bench, rows)
    table = bench.table("pair", "CAT10 s", "SOR s", "SOR/CAT10", "CAT10 res", "SOR res",
                        f"CAT{args.long_iterations} res", "CAT best", "reach: iter", "s", "speed-up",
                        "1%: iter", "s", "speed-up",
                        title=f"CAT runs of {args.target_iterations} iterations: the first iteration whose residual is "
                              "<= SOR's final residual (and <= 1.01 x it), with the time taken to get there; "
                              "speed-up = SOR time / that time")

    def reach(iteration, seconds, sor_seconds):
        if iteration is None:
            return ["not reached", "-", "-"]
        return [iteration, round(seconds, 2), f"{sor_seconds / seconds:.0f}x"]

    for s in summary:
        table.add(s["pair"], round(s["cat10_seconds"], 2), round(s["sor_seconds"], 1),
                  f"{s['sor_seconds'] / s['cat10_seconds']:.0f}x", round(s["cat10_residual"], 3),
                  round(s["sor_residual"], 3), round(s["catlong_residual"], 3), round(s["best_residual"], 3),
                  *reach(s["first"], s["first_seconds"], s["sor_seconds"]),
                  *reach(s["near"], s["near_seconds"], s["sor_seconds"]))
    under_one_second = all(s["cat10_seconds"] < 1.0 for s in summary)
    goal = all(s["first"] is not None and s["sor_seconds"] / s["first_seconds"] >= 20 for s in summary)
    bench.note(f"goal 1 (CAT, paper's 10 iterations, under 1 s on one core): {'met' if under_one_second else 'NOT met'}")
    bench.note(f"goal 2 (CAT >= 20x faster than SOR at equal or lower residual, every pair): {'met' if goal else 'NOT met'}")


if __name__ == "__main__":
    main()
