"""Chapter 8: the notebook's asserted claims over seeds (probe area errors, peers, failure, volumes).

For the chapter's seeds and five others:
  probe    four slices (seeds base .. base + 3), both muscles, starts 10-20 % larger: mean |area error|
           and mean signed error (%) of the greedy, dynamic-programming and variational snakes; scikit-image's
           active_contour with the gallery's weights and on our potential (smoothed by 2 px); the greedy snake
           from starts 15 % and 30 % larger; greedy and dynamic programming on the thinned-ridge potential;
  toy      the 24-point greedy snake on the noisy 64 x 64 disc: area error (%) for noise seeds;
  volumes  (unless --skip-volumes) every eighth slice of hams 0 and 1 of make_ham_study(rng=seed), greedy and
           variational: the largest gap (points) between the mean volume reduction from the snakes and from
           the true areas; the share of greedy contours more than 7 % inside the truth, raw and dry-cured.

    .venv/bin/python benchmarks/dev_08_seed_spread.py [--bases 2004 3000 3010 3020 3030 3040]
        [--studies 2004 1 2 3 4 5] [--skip-volumes] [--json PATH]
"""

from __future__ import annotations

from _harness import Benchmark  # first: pins BLAS threads before numpy is imported


def main() -> None:
    bench = Benchmark(__doc__, seed=2004)
    bench.parser.add_argument("--bases", type=int, nargs="+", default=[2004, 3000, 3010, 3020, 3030, 3040])
    bench.parser.add_argument("--studies", type=int, nargs="+", default=[2004, 1, 2, 3, 4, 5])
    bench.parser.add_argument("--skip-volumes", action="store_true")
    args = bench.parse()

    import numpy as np
    from scipy import ndimage
    from skimage.segmentation import active_contour

    from amdo_lab import active_contours as ac

    table = bench.table("base seed", "greedy |e| %", "dynamic |e| %", "variational |e| %", "greedy mean %",
                        "dynamic mean %", "gallery |e| %", "peer on P |e| %", "greedy 15 % |e|", "greedy 30 % |e|",
                        "greedy ridge |e| %", "dynamic ridge |e| %",
                        title="probe: 8 contours per base seed")
    for base in args.bases:
        errors = {name: [] for name in ("greedy", "dynamic", "variational", "gallery", "peer", "far15", "far30",
                                        "ridge greedy", "ridge dynamic")}
        for k in range(4):
            ham = ac.make_ham_slice(rng=base + k)
            potential = ac.potential_field(ham.image)
            ridge = ac.potential_field(ham.image, edges="ridge")
            smooth = ac.smooth_7x7(ham.image)
            for j, muscle in enumerate(ac.MUSCLES):
                true = ham.areas_mm2[muscle]
                init = ac.initial_contour(ham, muscle, rng=100 * k + j)
                for method in ac.METHODS:
                    points = ac.segment_contour(potential, init, method)
                    errors[method].append(100 * (ac.polygon_area_mm2(points) / true - 1))
                gallery = active_contour(smooth, init, alpha=0.015, beta=10, gamma=0.001)
                errors["gallery"].append(100 * (ac.polygon_area_mm2(gallery) / true - 1))
                field = -ndimage.gaussian_filter(potential, 2.0) / potential.max()
                peer = active_contour(field, init, alpha=0.01, beta=1.0, gamma=0.01, w_line=1.0, w_edge=0.0)
                errors["peer"].append(100 * (ac.polygon_area_mm2(peer) / true - 1))
                for method in ("greedy", "dynamic"):
                    points = ac.segment_contour(ridge, init, method)
                    errors["ridge " + method].append(100 * (ac.polygon_area_mm2(points) / true - 1))
                for enlarge, key in ((0.15, "far15"), (0.30, "far30")):
                    start = ac.initial_contour(ham, muscle, rng=7, enlarge=(enlarge, enlarge))
                    points = ac.segment_contour(potential, start, "greedy")
                    errors[key].append(100 * (ac.polygon_area_mm2(points) / true - 1))
        mean_abs = {key: float(np.mean(np.abs(values))) for key, values in errors.items()}
        table.add(base, *(round(mean_abs[m], 1) for m in ac.METHODS), round(float(np.mean(errors["greedy"])), 1),
                  round(float(np.mean(errors["dynamic"])), 1), round(mean_abs["gallery"], 1),
                  round(mean_abs["peer"], 1), round(mean_abs["far15"], 1), round(mean_abs["far30"], 1),
                  round(mean_abs["ridge greedy"], 1), round(mean_abs["ridge dynamic"], 1))
        print(f"base {base} done", flush=True)

    toy = bench.table("noise seed", "toy area error %", title="toy: 24-point greedy snake, noisy 64 x 64 disc")
    grid = np.hypot(*(np.mgrid[:64, :64] - 31.5))
    theta = np.linspace(0, 2 * np.pi, 24, endpoint=False)
    start = np.rint(31.5 + 24 * np.column_stack([np.sin(theta), np.cos(theta)]))
    for seed in (8, 1, 2, 3, 4, 5):
        image = 0.2 + 0.6 * (grid < 16) + 0.08 * np.random.default_rng(seed).normal(size=(64, 64))
        snake = ac.greedy_snake(ac.potential_field(image, edge_share=0.05, cap_px=8.0), start, d_min_px=0.5,
                                d_max_px=40)
        toy.add(seed, round(100 * (ac.polygon_area_mm2(snake.points, (1, 1)) / (np.pi * 256) - 1), 1))

    if not args.skip_volumes:
        import pandas as pd
        volumes_table = bench.table("study seed", "greedy gap (points)", "variational gap (points)",
                                    "true reduction at dry-cured %", "greedy > 7 % inside, raw",
                                    "greedy > 7 % inside, dry-cured", title="volume reduction per stage, 2 hams")
        for seed in args.studies:
            study = ac.make_ham_study(rng=seed)
            gaps = []
            for method in ("greedy", "variational"):
                found = pd.DataFrame(ac.segment_study(study, method, every=8, hams=(0, 1)))
                volumes = found.groupby(["ham", "muscle", "stage"])[["true_mm2", "found_mm2"]].sum()
                reduction = 100 * (1 - volumes / volumes.xs(0, level="stage"))
                gap = (reduction["found_mm2"] - reduction["true_mm2"]).groupby("stage").mean().abs()
                gaps.append(round(float(gap.max()), 1))
                if method == "greedy":
                    inside = (found["found_mm2"] < 0.93 * found["true_mm2"]).groupby(found["stage"]).mean()
            volumes_table.add(seed, *gaps, round(float(100 * (1 - np.nanmean(study.volume_fraction[:2, 3]))), 1),
                              round(float(inside[0]), 2), round(float(inside[3]), 2))
            print(f"study {seed} done", flush=True)
    bench.finish()


if __name__ == "__main__":
    main()
