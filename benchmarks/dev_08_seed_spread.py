"""Chapter 8: every quantity the notebook asserts, over seeds the chapter does not use (and its own first).

For the chapter's seeds and ten others:
  toy      the 24-point greedy snake on the noisy 64 x 64 disc (default potential, d 0.5 / 40 px): area error (%);
  disc     a bright disc of radius 40 px on 128 x 128 (noise 0.05) started at radii 36, 44, 48: the largest
           |area error| (%) of the default greedy snake, and the area error from radius 36 with eq. (7) printed
           literally (image_norm="max");
  probe    four slices (seeds base .. base + 3), both muscles, starts 10-20 % larger: mean |area error| and
           mean signed error (%) of the greedy, dynamic-programming and variational snakes; scikit-image's
           active_contour with the gallery's weights and on our potential (smoothed by 2 px); the greedy snake
           from starts 15 % and 30 % larger; greedy and dynamic programming on the unthinned Sobel band and on
           the thinned ridge;
  volumes  every eighth slice of hams 0 and 1 of make_ham_study(rng=seed), greedy, dynamic programming and
           variational: the largest gap (points) between the mean volume reduction from the snakes and from
           the true areas of the same slices.

    .venv/bin/python benchmarks/dev_08_seed_spread.py [--bases 2004 3000 ... 3090] [--studies 2004 1 ... 10]
        [--noise-seeds 8 1 ... 10] [--skip-probe] [--skip-volumes] [--json PATH]

Each part takes several minutes on a loaded machine; run the probe and the volumes as two processes
(``--skip-volumes`` and ``--skip-probe``).
"""

from __future__ import annotations

from _harness import Benchmark  # first: pins BLAS threads before numpy is imported


def main() -> None:
    bench = Benchmark(__doc__, seed=2004)
    bench.parser.add_argument("--bases", type=int, nargs="+", default=[2004] + list(range(3000, 3100, 10)))
    bench.parser.add_argument("--studies", type=int, nargs="+", default=[2004] + list(range(1, 11)))
    bench.parser.add_argument("--noise-seeds", type=int, nargs="+", default=[8] + list(range(1, 11)))
    bench.parser.add_argument("--skip-probe", action="store_true")
    bench.parser.add_argument("--skip-volumes", action="store_true")
    args = bench.parse()

    import numpy as np
    from scipy import ndimage
    from skimage.segmentation import active_contour

    from amdo_lab import active_contours as ac

    def error(points, true, pixel_mm=ac.PIXEL_MM):
        return 100 * (ac.polygon_area_mm2(points, pixel_mm) / true - 1)

    toy = bench.table("noise seed", "toy area error %", "disc max |e| % (36/44/48)", "disc literal eq. 7 from 36 %",
                      title="toy (64 x 64, radius 16) and plain disc (128 x 128, radius 40)")
    theta24 = np.linspace(0, 2 * np.pi, 24, endpoint=False)
    theta60 = np.linspace(0, 2 * np.pi, 60, endpoint=False)
    for seed in args.noise_seeds:
        grid = np.hypot(*(np.mgrid[:64, :64] - 31.5))
        image = 0.2 + 0.6 * (grid < 16) + 0.08 * np.random.default_rng(seed).normal(size=(64, 64))
        start = np.rint(31.5 + 24 * np.column_stack([np.sin(theta24), np.cos(theta24)]))
        snake = ac.greedy_snake(ac.potential_field(image), start, d_min_px=0.5, d_max_px=40)
        toy_error = error(snake.points, np.pi * 256, (1, 1))
        grid = np.hypot(*(np.mgrid[:128, :128] - 63.5))
        disc = (grid < 40) + 0.05 * np.random.default_rng(seed).normal(size=(128, 128))
        potential = ac.potential_field(disc)
        disc_errors, literal = [], None
        for radius in (36, 44, 48):
            init = 63.5 + radius * np.column_stack([np.sin(theta60), np.cos(theta60)])
            disc_errors.append(error(ac.greedy_snake(potential, init).points, np.pi * 1600, (1, 1)))
            if radius == 36:
                literal = error(ac.greedy_snake(potential, init, image_norm="max").points, np.pi * 1600, (1, 1))
        toy.add(seed, round(toy_error, 1), round(max(map(abs, disc_errors)), 1), round(literal, 1))

    if not args.skip_probe:
        table = bench.table("base seed", "greedy |e| %", "dynamic |e| %", "variational |e| %", "greedy mean %",
                            "dynamic mean %", "gallery |e| %", "peer on P |e| %", "greedy 15 % |e|",
                            "greedy 30 % |e|", "greedy band |e| %", "dynamic band |e| %", "greedy ridge |e| %",
                            "dynamic ridge |e| %", title="probe: 8 contours per base seed")
        for base in args.bases:
            errors = {name: [] for name in ("greedy", "dynamic", "variational", "gallery", "peer", "far15", "far30",
                                            "band greedy", "band dynamic", "ridge greedy", "ridge dynamic")}
            for k in range(4):
                ham = ac.make_ham_slice(rng=base + k)
                potential = ac.potential_field(ham.image)
                others = {"band": ac.potential_field(ham.image, thin=False),
                          "ridge": ac.potential_field(ham.image, edges="ridge")}
                smooth = ac.smooth_7x7(ham.image)
                for j, muscle in enumerate(ac.MUSCLES):
                    true = ham.areas_mm2[muscle]
                    init = ac.initial_contour(ham, muscle, rng=100 * k + j)
                    for method in ac.METHODS:
                        errors[method].append(error(ac.segment_contour(potential, init, method), true))
                    gallery = active_contour(smooth, init, alpha=0.015, beta=10, gamma=0.001)
                    errors["gallery"].append(error(gallery, true))
                    field = -ndimage.gaussian_filter(potential, 2.0) / potential.max()
                    peer = active_contour(field, init, alpha=0.01, beta=1.0, gamma=0.01, w_line=1.0, w_edge=0.0)
                    errors["peer"].append(error(peer, true))
                    for name, other in others.items():
                        for method in ("greedy", "dynamic"):
                            errors[f"{name} {method}"].append(error(ac.segment_contour(other, init, method), true))
                    for enlarge, key in ((0.15, "far15"), (0.30, "far30")):
                        start = ac.initial_contour(ham, muscle, rng=7, enlarge=(enlarge, enlarge))
                        errors[key].append(error(ac.segment_contour(potential, start, "greedy"), true))
            mean_abs = {key: float(np.mean(np.abs(values))) for key, values in errors.items()}
            table.add(base, *(round(mean_abs[m], 1) for m in ac.METHODS),
                      round(float(np.mean(errors["greedy"])), 1), round(float(np.mean(errors["dynamic"])), 1),
                      *(round(mean_abs[key], 1) for key in ("gallery", "peer", "far15", "far30", "band greedy",
                                                            "band dynamic", "ridge greedy", "ridge dynamic")))
            print(f"base {base} done", flush=True)

    if not args.skip_volumes:
        import pandas as pd
        volumes_table = bench.table("study seed", "greedy gap (points)", "dynamic gap (points)",
                                    "variational gap (points)", title="volume reduction per stage, 2 hams")
        for seed in args.studies:
            study = ac.make_ham_study(rng=seed)
            gaps = []
            for method in ac.METHODS:
                found = pd.DataFrame(ac.segment_study(study, method, every=8, hams=(0, 1)))
                volumes = found.groupby(["ham", "muscle", "stage"])[["true_mm2", "found_mm2"]].sum()
                reduction = 100 * (1 - volumes / volumes.xs(0, level="stage"))
                gap = (reduction["found_mm2"] - reduction["true_mm2"]).groupby("stage").mean().abs()
                gaps.append(round(float(gap.max()), 1))
            volumes_table.add(seed, *gaps)
            print(f"study {seed} done", flush=True)
    bench.finish()


if __name__ == "__main__":
    main()
