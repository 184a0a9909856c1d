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

BLAS is limited to one thread (set before numpy is imported) so the timing is single-core.
"""

from __future__ import annotations

import os

for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from amdo_lab.common import spawn_rngs  # noqa: E402
from amdo_lab import pdm_mixtures as pm  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--setting", choices=("14-poses", "table1"), default="14-poses")
    parser.add_argument("--train-per-class", type=int, default=20)
    parser.add_argument("--n-test", type=int, default=1200)
    parser.add_argument("--seed", type=int, default=2004)
    parser.add_argument("--separation", action="store_true", help="run the mode-separation experiment instead")
    parser.add_argument("--levels", type=float, nargs="+", default=[0.0, 0.5, 1.0, 1.5, 2.0, 3.0])
    parser.add_argument("--seeds", type=int, nargs="+", default=list(range(3000, 3030)))
    parser.add_argument("--separation-test", type=int, default=50)
    args = parser.parse_args()
    if args.separation:
        separation_experiment(args.levels, args.seeds, args.separation_test)
        return
    classes = tuple(pm.POSES) if args.setting == "14-poses" else pm.TABLE1_CLASSES
    train_rng, test_rng = spawn_rngs(args.seed, 2)  # the notebook's first two streams
    train = pm.generate_pose_dataset(classes, args.train_per_class, train_rng)
    per_class = -(-args.n_test // len(classes))
    test = pm.generate_pose_dataset(classes, per_class, test_rng)
    test_shapes, test_labels = test.shapes[: args.n_test], test.labels[: args.n_test]
    models = {
        "hierarchical PDM mixture (ours)": pm.ArticulatedShapeRecognizer(),
        "ours, joint polar PDM": pm.ArticulatedShapeRecognizer(polar_model="joint"),
        "ours, 1 polar PDM per class": pm.ArticulatedShapeRecognizer(n_shape_components=1),
        "single Cartesian PDM": pm.SingleCartesianPDMClassifier(),
        "nearest Procrustes mean": pm.NearestProcrustesMeanClassifier(),
        "sklearn GaussianMixture": pm.SklearnGMMClassifier(),
    }
    print(f"{len(classes)} classes, {len(train.labels)} training shapes, {len(test_labels)} test shapes, one BLAS thread")
    print(f"{'method':34s} {'train s':>8s} {'recognise s':>12s} {'total s':>8s} {'rate':>6s} {'total / ours':>12s}")
    rows, predictions = [], {}
    for name, model in models.items():
        start = time.perf_counter()
        model.fit(train.shapes, train.labels)
        trained = time.perf_counter()
        predictions[name] = model.predict(test_shapes)
        done = time.perf_counter()
        rows.append((name, trained - start, done - trained, float(np.mean(predictions[name] == test_labels))))
    ours_total = rows[0][1] + rows[0][2]
    for name, fit_s, rec_s, rate in rows:
        print(f"{name:34s} {fit_s:8.2f} {rec_s:12.2f} {fit_s + rec_s:8.2f} {rate:6.3f} {(fit_s + rec_s) / ours_total:12.2f}")
    print(f"goal (< 10 s for ours, train + recognise): {'met' if ours_total < 10 else 'NOT met'}")
    if args.setting == "table1":
        print("\ncorrect per class (Table 1; paper: boxing 198, kicking 163, relaxing 197, picking 181, "
              "stretching 200, shooting 179, overall 93.16 %)")
        print(f"{'method':34s} " + " ".join(f"{c:>10s}" for c in classes) + f" {'overall %':>10s}")
        for name, predicted in predictions.items():
            counts = [int(np.sum(predicted[test_labels == c] == c)) for c in classes]
            print(f"{name:34s} " + " ".join(f"{k:10d}" for k in counts)
                  + f" {100 * np.mean(predicted == test_labels):10.2f}")


def separation_experiment(levels: list[float], seeds: list[int], n_test: int) -> None:
    """Print the mode-separation experiment (see the module docstring)."""
    from scipy.stats import wilcoxon

    from amdo_lab.common import rate_interval

    names = pm.SEPARATION_MODELS
    print(f"{len(seeds)} seeds per level, 20 training and {n_test} test shapes per class, one BLAS thread")
    print(f"{'separation':>10s} " + " ".join(f"{n:>30s}" for n in names) + f" {'mixture - single polar':>24s} {'p':>8s}"
          + f" {'mixture - Cartesian':>20s} {'p':>8s}")
    for level in levels:
        start = time.perf_counter()
        trials = [pm.mode_separation_trial(level, seed, n_test=n_test) for seed in seeds]
        cells = []
        for name in names:
            interval = rate_interval(np.concatenate([t.correct[name] for t in trials]))
            cells.append(f"{interval.rate:.3f} [{interval.low:.3f}, {interval.high:.3f}]")
        rates = {name: np.array([t.rate(name) for t in trials]) for name in names}
        gaps = []
        for other in names[1:]:
            gap = rates[names[0]] - rates[other]
            p = wilcoxon(gap).pvalue if np.any(gap != 0) else 1.0
            gaps.append(f"{gap.mean():+24.3f} {p:8.1e}")
        print(f"{level:10.2f} " + " ".join(f"{c:>30s}" for c in cells) + " " + " ".join(gaps)
              + f"   ({time.perf_counter() - start:.0f} s)", flush=True)


if __name__ == "__main__":
    main()
