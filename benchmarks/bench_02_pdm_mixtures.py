"""Chapter 2 benchmark: training and recognition times of the hierarchical PDM-mixture recogniser
and of the baselines (single Cartesian PDM, nearest Procrustes mean, scikit-learn GaussianMixture).

Goal from the issue: train on 20 x 14 shapes and recognise 1,200 in under 10 s on one core.
Default run: all 14 poses, 20 training shapes each, 1,200 test shapes drawn from the 14 poses (the six
Table-1 classes have two articulation modes each, the other eight one); ours learns a 2-component
mixture of polar PDMs per class by EM.

    .venv/bin/python benchmarks/bench_02_pdm_mixtures.py [--train-per-class 20] [--n-test 1200] [--seed 2004]

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
    parser.add_argument("--train-per-class", type=int, default=20)
    parser.add_argument("--n-test", type=int, default=1200)
    parser.add_argument("--seed", type=int, default=2004)
    args = parser.parse_args()
    classes = tuple(pm.POSES)
    train_rng, test_rng = spawn_rngs(args.seed, 2)
    train = pm.generate_pose_dataset(classes, args.train_per_class, train_rng)
    per_class = -(-args.n_test // len(classes))
    test = pm.generate_pose_dataset(classes, per_class, test_rng)
    test_shapes, test_labels = test.shapes[: args.n_test], test.labels[: args.n_test]
    models = {
        "hierarchical PDM mixture (ours)": pm.ArticulatedShapeRecognizer(),
        "single Cartesian PDM": pm.SingleCartesianPDMClassifier(),
        "nearest Procrustes mean": pm.NearestProcrustesMeanClassifier(),
        "sklearn GaussianMixture": pm.SklearnGMMClassifier(),
    }
    print(f"{len(classes)} classes, {len(train.labels)} training shapes, {len(test_labels)} test shapes, one BLAS thread")
    print(f"{'method':34s} {'train s':>8s} {'recognise s':>12s} {'total s':>8s} {'rate':>6s} {'total / ours':>12s}")
    rows = []
    for name, model in models.items():
        start = time.perf_counter()
        model.fit(train.shapes, train.labels)
        trained = time.perf_counter()
        predicted = model.predict(test_shapes)
        done = time.perf_counter()
        rows.append((name, trained - start, done - trained, float(np.mean(predicted == test_labels))))
    ours_total = rows[0][1] + rows[0][2]
    for name, fit_s, rec_s, rate in rows:
        print(f"{name:34s} {fit_s:8.2f} {rec_s:12.2f} {fit_s + rec_s:8.2f} {rate:6.3f} {(fit_s + rec_s) / ours_total:12.2f}")
    print(f"goal (< 10 s for ours, train + recognise): {'met' if ours_total < 10 else 'NOT met'}")


if __name__ == "__main__":
    main()
