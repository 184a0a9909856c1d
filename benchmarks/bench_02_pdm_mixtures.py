"""Chapter 2 benchmark: training and recognition times and rates of the hierarchical PDM-mixture
recogniser, two of its ablations, and the baselines (single Cartesian PDM, nearest Procrustes mean,
scikit-learn GaussianMixture), all on the same data.

Speed goal: train on 20 x 14 shapes and recognise 1,200 in under 10 s on one core.

    .venv/bin/python benchmarks/bench_02_pdm_mixtures.py [--setting 14-poses|table1] [--train-per-class 20]
                                                         [--n-test 1200] [--seed 2004]

``--setting 14-poses`` (default, the speed goal): all 14 poses, 20 training shapes each, 1,200 test
shapes drawn from the 14 poses (the six Table-1 classes have two articulation modes each, the other
eight one). ``--setting table1``: the six Table-1 classes, 20 training and 200 test shapes per class,
drawn from the same seeded streams as the notebook, so the per-class table printed at the end is the
notebook's Table 1 (with the default seed).

``--separation``: the controlled experiment of the chapter's "Where a mixture pays off" at full
size: the mixture of polar PDMs (2 per class), a single polar PDM and a single Cartesian PDM,
trained on 20 shapes per class and tested on ``--separation-test`` per class, for every separation
in ``--levels`` and every seed in ``--seeds`` (seed s draws ``spawn_rngs(s, 2)``); per level the
mean rates, Wilson 95 % intervals of the pooled rates, the mean per-seed gap of the mixture and
the Wilcoxon signed-rank p over seeds (about 1 s per level and seed on one core).

BLAS is limited to one thread (benchmarks/_harness.py) so the timing is single-core; ``--json PATH``
writes the tables.
"""

from __future__ import annotations

from _harness import Benchmark  # first: pins BLAS threads before numpy is imported


def main() -> None:
    bench = Benchmark(__doc__, seed=2004)
    parser = bench.parser
    parser.add_argument("--setting", choices=("14-poses", "table1"), default="14-poses")
    parser.add_argument("--train-per-class", type=int, default=20)
    parser.add_argument("--n-test", type=int, default=1200)
    parser.add_argument("--separation", action="store_true", help="run the mode-separation experiment instead")
    parser.add_argument("--levels", type=float, nargs="+", default=[0.0, 0.5, 1.0, 1.5, 2.0, 3.0])
    parser.add_argument("--seeds", type=int, nargs="+", default=list(range(3000, 3030)))
    parser.add_argument("--separation-test", type=int, default=50)
    args = bench.parse()
    if args.separation:
        separation_experiment(bench, args.levels, args.seeds, args.separation_test)
    else:
        speed_and_rates(bench, args)
    bench.finish()


def speed_and_rates(bench, args) -> None:
    """Train and recognise with ours, two ablations and three baselines on the same shapes."""
    import numpy as np

    from amdo_lab import pdm_mixtures as pm
    from amdo_lab.common import spawn_rngs

    classes = tuple(pm.POSES) if args.setting == "14-poses" else pm.TABLE1_CLASSES
    train_rng, test_rng = spawn_rngs(args.seed, 2)  # the notebook's first two streams
    train = pm.make_pose_dataset(classes, args.train_per_class, rng=train_rng)
    per_class = -(-args.n_test // len(classes))
    test = pm.make_pose_dataset(classes, per_class, rng=test_rng)
    test_shapes, test_labels = test.shapes[: args.n_test], test.labels[: args.n_test]
    models = {
        "hierarchical PDM mixture (ours)": lambda: pm.ArticulatedShapeRecogniser(rng=0),
        "ours, joint polar PDM":
            lambda: pm.ArticulatedShapeRecogniser(pm.RecogniserSettings(polar_model="joint"), rng=0),
        "ours, 1 polar PDM per class":
            lambda: pm.ArticulatedShapeRecogniser(pm.RecogniserSettings(n_shape_components=1), rng=0),
        "single Cartesian PDM": pm.SingleCartesianPDMClassifier,
        "nearest Procrustes mean": pm.NearestProcrustesMeanClassifier,
        "sklearn GaussianMixture": lambda: pm.SklearnGMMClassifier(rng=0),
    }
    table = bench.table("method", "train s (best)", "recognise s (best)", "total s", "rate", "total / ours",
                        title=f"{len(classes)} classes, {len(train.labels)} training shapes, "
                              f"{len(test_labels)} test shapes, one BLAS thread")
    predictions, ours_total = {}, None
    for name, make_model in models.items():
        model = make_model()
        fit_timing, _ = bench.time(lambda: model.fit(train.shapes, train.labels))
        recognise_timing, predicted = bench.time(lambda: model.predict(test_shapes))
        predictions[name] = predicted
        total = fit_timing.best + recognise_timing.best
        ours_total = ours_total or total
        table.add(name, round(fit_timing.best, 2), round(recognise_timing.best, 2), round(total, 2),
                  round(float(np.mean(predicted == test_labels)), 3), round(total / ours_total, 2))
    bench.note(f"speed goal (< 10 s for ours, train + recognise): {'met' if ours_total < 10 else 'NOT met'}")
    if args.setting == "table1":
        per_class_table = bench.table("method", *classes, "overall %",
                                      title="correct per class (Table 1; paper: boxing 198, kicking 163, relaxing 197, "
                                            "picking 181, stretching 200, shooting 179, overall 93.16 %)")
        for name, predicted in predictions.items():
            counts = [int(np.sum(predicted[test_labels == c] == c)) for c in classes]
            per_class_table.add(name, *counts, round(100 * float(np.mean(predicted == test_labels)), 2))


def separation_experiment(bench, levels: list[float], seeds: list[int], n_test: int) -> None:
    """The mode-separation experiment (see the module docstring), one row per level."""
    import time

    import numpy as np
    from scipy.stats import wilcoxon

    from amdo_lab import pdm_mixtures as pm
    from amdo_lab.common import rate_interval

    names = pm.SEPARATION_MODELS
    table = bench.table("separation", *names, "mixture - single polar", "p", "mixture - Cartesian", "p", "seconds",
                        title=f"{len(seeds)} seeds per level, 20 training and {n_test} test shapes per class, "
                              "one BLAS thread; rates with Wilson 95 % intervals, Wilcoxon p over seeds")
    for level in levels:
        start = time.perf_counter()
        trials = [pm.mode_separation_trial(level, rng=seed, n_test=n_test) for seed in seeds]
        cells = []
        for name in names:
            interval = rate_interval(np.concatenate([t.correct[name] for t in trials]))
            cells.append(f"{interval.rate:.3f} [{interval.low:.3f}, {interval.high:.3f}]")
        rates = {name: np.array([t.rate(name) for t in trials]) for name in names}
        gaps = []
        for other in names[1:]:
            gap = rates[names[0]] - rates[other]
            p = float(wilcoxon(gap).pvalue) if np.any(gap != 0) else 1.0
            gaps += [round(float(gap.mean()), 3), f"{p:.1e}"]
        table.add(level, *cells, *gaps, round(time.perf_counter() - start, 1))
        print(f"separation {level:.2f} done", flush=True)


if __name__ == "__main__":
    main()
