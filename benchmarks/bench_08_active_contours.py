"""Chapter 8 benchmark: greedy, dynamic-programming and variational snakes on a synthetic ham MRI study.

Tables, one BLAS thread, one run (so every ratio compares calls made on the same machine state):
  costs    ms per iteration of the dynamic-programming snake at 9, 25 and 49 candidates (the m^3 of Sec. 3.1
           predicts x7.5 from 25 to 49) and of the greedy snake, on a 100-point snake; the log-log slope in n
           (50, 100, 200 points); energy evaluations per iteration (n m and about n m^3);
  study    make_ham_study(rng=seed): both muscles on every slice of the 15 hams (the paper: 1,104 images of the
           six hams scanned at all four stages) by the greedy and variational snakes and by scikit-image's
           active_contour on our potential (smoothed by 2 px), dynamic programming on every fifth slice: mean |area error| (%),
           ms per contour, seconds per slice of pre-processing; (--quick: three of the six hams scanned at all
           stages, every fourth slice, dynamic programming on every eighth);
  volumes  the mean volume reduction per stage of each method against the reduction of the true areas and of
           the solids' exact volumes, over the hams scanned at all four stages;
  ablations (--ablations; --ablations-only skips the three tables above) on the probe contours (ham 0, raw
           stage, every seventh slice, both muscles; the same seeded starts for every row): the greedy snake
           with Williams & Shah's neighbourhood-maximum normalisation of every term (eq. 7's e_max read for
           E_cont and E_curv too) against ours (dbar, dbar^2); the variational snake on the raw gradient vector
           flow against the unit-length flow; d_min, d_max of the variable n for greedy and variational;
  peers    (with --ablations) scikit-image's morphological_geodesic_active_contour (MorphGAC, balloon=-1,
           200 iterations, smoothing 1) from the same starts, on our potential scaled to [0, 1] (balloon threshold
           "auto", the 40th percentile, and 0.2: the balloon stops 3 px from an edge) and on
           inverse_gaussian_gradient of the image (its gallery's stopping function, "auto"; its default sigma,
           5 px, and 1.4 px, the sigma of Sec. 3.2's 7 x 7 Gaussian; the septa are 3.5 px wide): mean |area error|,
           the worst contour, CPU seconds per contour (area: pixels inside the final level set).

Run:  .venv/bin/python benchmarks/bench_08_active_contours.py [--quick] [--ablations | --ablations-only] [--json PATH]
"""

from __future__ import annotations

import time

from _harness import Benchmark  # first: pins BLAS threads before numpy is imported


def _dp_ms(ac, np, potential, n, window, iterations=3):
    theta = np.linspace(0, 2 * np.pi, n, endpoint=False)
    ring = np.rint(200 + 80 * np.column_stack([np.sin(theta), np.cos(theta)]))
    start = time.perf_counter()
    result = ac.dp_snake(potential, ring, window=window, max_iter=iterations, d_min_px=0.1, d_max_px=100)
    return 1e3 * (time.perf_counter() - start) / result.n_iter, result.energy_evaluations // result.n_iter


def _greedy_ms(ac, np, potential, n, window, iterations=20):
    theta = np.linspace(0, 2 * np.pi, n, endpoint=False)
    ring = np.rint(200 + 80 * np.column_stack([np.sin(theta), np.cos(theta)]))
    start = time.perf_counter()
    result = ac.greedy_snake(potential, ring, window=window, max_iter=iterations, d_min_px=0.1, d_max_px=100)
    return 1e3 * (time.perf_counter() - start) / result.n_iter, result.energy_evaluations // result.n_iter


def _probe(ac, np, seed, every=7):
    """(slice, muscle, start) of the probe contours: ham 0 raw, every ``every``-th slice, seeded starts."""
    study = ac.make_ham_study(rng=seed)
    probe = []
    for index in range(0, len(study.slice_positions(0, 0)), every):
        ham_slice = study.slice(0, 0, index)
        for j, muscle in enumerate(ac.MUSCLES):
            if muscle in ham_slice.contours:
                init = ac.initial_contour(ham_slice, muscle, rng=np.random.default_rng([seed, 0, 0, index, j]))
                probe.append((ham_slice, muscle, init))
    return probe


def _in_crop(np, snake, potential, init, margin=24, **options):
    """``snake`` run on a crop round ``init`` (as segment_contour does); the points in slice pixels."""
    low = np.maximum(np.floor(init.min(axis=0)) - margin, 0).astype(int)
    high = np.minimum(np.ceil(init.max(axis=0)) + margin + 1, potential.shape).astype(int)
    local = potential[low[0]:high[0], low[1]:high[1]]
    return snake(local, init - low, **options).points + low


#: OpenCV's sigma for a 7 x 7 Gaussian given none, 0.3 ((7 - 1) / 2 - 1) + 0.8: the smoothing of Sec. 3.2.
OPENCV_SIGMA_7 = 1.4


def _morphgac_mm2(np, ac, stopping, init, threshold, iterations=200):
    """Area (mm^2) of MorphGAC's final level set from the polygon of ``init``, balloon -1 (shrinking)."""
    from skimage.draw import polygon
    from skimage.segmentation import morphological_geodesic_active_contour

    level = np.zeros(stopping.shape, dtype=np.int8)
    level[polygon(init[:, 0], init[:, 1], stopping.shape)] = 1
    final = morphological_geodesic_active_contour(stopping, iterations, init_level_set=level, smoothing=1,
                                                  threshold=threshold, balloon=-1)
    return float(final.sum()) * ac.PIXEL_MM[0] * ac.PIXEL_MM[1]


def _ablations(bench, ac, np, seed) -> None:
    """The ablation and MorphGAC tables on the probe contours."""
    from skimage.segmentation import inverse_gaussian_gradient

    probe = _probe(ac, np, seed)
    weights = {name: dict(alpha=w.alpha, beta=w.beta, gamma=w.gamma) for name, w in ac.TABLE_1.items()}
    def greedy(potential, init, **options):
        return _in_crop(np, ac.greedy_snake, potential, init, **weights["greedy"], **options)
    def variational(potential, init, **options):
        edge = potential.max() - potential
        return _in_crop(np, ac.variational_snake, edge, init, **weights["variational"], **options)
    variants = [("greedy", "ours: E_cont/dbar, E_curv/dbar^2", greedy, {}),
                ("greedy", "eq. 7 literally: every term / neighbourhood max", greedy, {"normalise": "neighbourhood"}),
                ("variational", "ours: unit-length GVF", variational, {}),
                ("variational", "raw GVF", variational, {"unit_flow": False})]
    for d_min, d_max in ((1.0, 3.0), (2.0, 6.0), (4.0, 12.0)):
        for name, run in (("greedy", greedy), ("variational", variational)):
            variants.append((name, f"d_min {d_min:g}, d_max {d_max:g} px", run,
                             {"d_min_px": d_min, "d_max_px": d_max}))
    table = bench.table("snake", "variant", "contours", "mean |area error| %", "mean error %", "worst %",
                        "CPU ms per contour (median)", title=f"ablations on {len(probe)} probe contours")
    potentials = {id(s): ac.potential_field(s.image) for s, _, _ in probe}
    for name, label, run, options in variants:
        errors, seconds = [], []
        for ham_slice, muscle, init in probe:
            start = time.process_time()                       # CPU time: the machine may be shared
            points = run(potentials[id(ham_slice)], init, **options)
            seconds.append(time.process_time() - start)
            errors.append(100 * (ac.polygon_area_mm2(points) / ham_slice.areas_mm2[muscle] - 1))
        errors = np.array(errors)
        table.add(name, label, len(errors), round(float(np.abs(errors).mean()), 1), round(float(errors.mean()), 1),
                  round(float(errors[np.argmax(np.abs(errors))]), 1), round(1e3 * float(np.median(seconds))))
    peers = bench.table("peer", "stopping function", "threshold", "contours", "mean |area error| %",
                        "|error| <= 10 %", "mean error %", "worst %", "CPU s per contour (median)",
                        title="MorphGAC, balloon -1, 200 iterations, same starts")
    scaled = (lambda s: potentials[id(s)] / potentials[id(s)].max())
    for label, stopping_of, threshold in (("our potential / its max", scaled, "auto"),
                                          ("our potential / its max", scaled, 0.2),
                                          ("inverse_gaussian_gradient(image)",
                                           lambda s: inverse_gaussian_gradient(s.image), "auto"),
                                          (f"inverse_gaussian_gradient(image, sigma={OPENCV_SIGMA_7})",
                                           lambda s: inverse_gaussian_gradient(s.image, sigma=OPENCV_SIGMA_7),
                                           "auto")):
        errors, seconds = [], []
        for ham_slice, muscle, init in probe:
            start = time.process_time()                       # CPU time: the machine may be shared
            area = _morphgac_mm2(np, ac, stopping_of(ham_slice), init, threshold)
            seconds.append(time.process_time() - start)
            errors.append(100 * (area / ham_slice.areas_mm2[muscle] - 1))
        errors = np.array(errors)
        peers.add("MorphGAC", label, threshold, len(errors), round(float(np.abs(errors).mean()), 1),
                  int(np.sum(np.abs(errors) <= 10)), round(float(errors.mean()), 1),
                  round(float(errors[np.argmax(np.abs(errors))]), 1),
                  round(float(np.median(seconds)), 1))


def main() -> None:
    bench = Benchmark(__doc__, seed=2004)
    bench.parser.add_argument("--quick", action="store_true", help="three hams, every fourth slice (a few minutes)")
    bench.parser.add_argument("--skip-costs", action="store_true", help="skip the cost table")
    bench.parser.add_argument("--ablations", action="store_true",
                              help="also the ablation and MorphGAC tables on the probe contours")
    bench.parser.add_argument("--ablations-only", action="store_true",
                              help="only the ablation and MorphGAC tables (a few minutes)")
    args = bench.parse()

    import numpy as np
    import pandas as pd
    from scipy import ndimage
    from skimage.segmentation import active_contour

    from amdo_lab import active_contours as ac

    if args.ablations or args.ablations_only:
        _ablations(bench, ac, np, args.seed)
    if args.ablations_only:
        bench.finish()
        return
    if not args.skip_costs:
        potential = ac.potential_field(ac.make_ham_slice(rng=args.seed).image)
        costs = bench.table("snake", "window", "m", "n", "ms per iteration", "evaluations per iteration",
                            title="cost per iteration (Sec. 3.1)")
        dp_by_window = {}
        for window in (3, 5, 7):
            ms, count = _dp_ms(ac, np, potential, 100, window)
            dp_by_window[window] = ms
            costs.add("dynamic", window, window ** 2, 100, round(ms, 1), count)
            ms, count = _greedy_ms(ac, np, potential, 100, window)
            costs.add("greedy", window, window ** 2, 100, round(ms, 2), count)
        slopes = {}
        for name, timer in (("dynamic", _dp_ms), ("greedy", _greedy_ms)):
            times = [timer(ac, np, potential, n, 3)[0] for n in (50, 100, 200)]
            slopes[name] = float(np.polyfit(np.log([50, 100, 200]), np.log(times), 1)[0])
        bench.note(f"dynamic programming, 25 -> 49 candidates: x{dp_by_window[7] / dp_by_window[5]:.1f} "
                   f"(m^3 predicts x{(49 / 25) ** 3:.1f}); slope in n: dynamic {slopes['dynamic']:.2f}, "
                   f"greedy {slopes['greedy']:.2f}")

    study = ac.make_ham_study(rng=args.seed)
    hams = range(3) if args.quick else range(study.n_hams)
    every, dp_every = (4, 8) if args.quick else (1, 5)
    rows, prep_seconds = [], []
    for ham in hams:
        for stage in range(4):
            if ham not in study.hams_at(stage):
                continue
            for index in range(0, len(study.slice_positions(ham, stage)), every):
                ham_slice = study.slice(ham, stage, index)
                start = time.perf_counter()
                potential = ac.potential_field(ham_slice.image)
                prep_seconds.append(time.perf_counter() - start)
                ridge = ac.potential_field(ham_slice.image, edges="ridge")
                for j, muscle in enumerate(ac.MUSCLES):
                    if muscle not in ham_slice.contours:
                        continue
                    seed = np.random.default_rng([args.seed, ham, stage, index, j])
                    init = ac.initial_contour(ham_slice, muscle, rng=seed)
                    true = ham_slice.areas_mm2[muscle]
                    methods = list(ac.METHODS) if index % dp_every == 0 else ["greedy", "variational"]
                    for method in methods + ["greedy (ridge)", "active_contour"]:
                        start = time.perf_counter()
                        if method == "greedy (ridge)":
                            points = ac.segment_contour(ridge, init, "greedy")
                        elif method == "active_contour":
                            field = -ndimage.gaussian_filter(potential, 2.0) / potential.max()
                            points = active_contour(field, init, alpha=0.01, beta=1.0, gamma=0.01, w_line=1.0,
                                                    w_edge=0.0)
                        else:
                            points = ac.segment_contour(potential, init, method)
                        rows.append({"ham": ham, "stage": stage, "index": index, "muscle": muscle, "method": method,
                                     "true_mm2": true, "found_mm2": ac.polygon_area_mm2(points),
                                     "seconds": time.perf_counter() - start})
        print(f"ham {ham} done", flush=True)
    found = pd.DataFrame(rows)
    found["error"] = 100 * (found["found_mm2"] / found["true_mm2"] - 1)
    accuracy = bench.table("method", "contours", "mean |area error| %", "mean error %", "ms per contour (median)",
                           title=f"study: {found.groupby(['ham', 'stage', 'index']).ngroups} slices")
    for method, group in found.groupby("method"):
        accuracy.add(method, len(group), round(float(group["error"].abs().mean()), 1),
                     round(float(group["error"].mean()), 1), round(1e3 * float(group["seconds"].median()), 0))
    bench.note(f"pre-processing (potential) per slice: median {1e3 * np.median(prep_seconds):.0f} ms")

    volumes = bench.table("method", "stage", "reduction from snakes %", "from true areas %", "from solids %",
                          title="mean volume reduction against raw, hams scanned at all stages")
    complete = found[found["ham"].isin(study.hams_at(3))]
    for method, group in complete.groupby("method"):
        step = (dp_every if method == "dynamic" else 1) * every
        sums = group.groupby(["ham", "muscle", "stage"])[["true_mm2", "found_mm2"]].sum() * step * ac.SLICE_MM
        reduction = 100 * (1 - sums / sums.xs(0, level="stage"))
        for stage in range(1, 4):
            part = reduction.xs(stage, level="stage")
            solids = 100 * (1 - np.mean(study.volume_fraction[study.hams_at(3), stage]))
            volumes.add(method, ac.STAGES[stage], round(float(part["found_mm2"].mean()), 1),
                        round(float(part["true_mm2"].mean()), 1), round(float(solids), 1))
    bench.finish()


if __name__ == "__main__":
    main()
