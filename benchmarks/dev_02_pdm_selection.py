"""Chapter 2: validation study of the choices the paper leaves open (not the notebook's test set).

The recogniser's settings that Al-Shaher & Hancock do not fix (mixture components per class, the
shape-level EM ridge, EM restarts, PDM modes kept, limb labels per limb, the label-error
probability p of eq. 18) are compared one at a time with the single Cartesian PDM and the nearest
Procrustes mean. Every seed draws a fresh training set (20 shapes per class, as in the chapter;
``--train-per-class 40`` gives the paper's count if each class's two articulation modes are read as
two of its "poses" with 20 examples each) and a validation set (100 per class) with
``spawn_rngs(seed, 2)``; the notebook's test set comes from
``spawn_rngs(2004, 4)`` and is never used here. Selection seeds 201-210, confirmation seeds
301-310 (a variant chosen on the first set must hold on the second).

    .venv/bin/python benchmarks/dev_02_pdm_selection.py [--seeds 201 ... 210] [--per-class 100]
                                                        [--train-per-class 20] [--only defaults]
    .venv/bin/python benchmarks/dev_02_pdm_selection.py --held-out      # about 10 s
    .venv/bin/python benchmarks/dev_02_pdm_selection.py --em-restarts   # about 5 s
    .venv/bin/python benchmarks/dev_02_pdm_selection.py --seed-spread   # about 3 minutes

``--held-out``: on the notebook's training set (``spawn_rngs(2004, 4)[0]``, never its test set),
each class's polar vectors are scored by ``pm.held_out_log_likelihood`` (5 folds, nats per shape) for
M = 1, 2, 3 components and larger ridges; the generative criterion for the choices Sec. 4 leaves open.
``--em-restarts``: for kicking and shooting, the shape-level EM (block-scaled S, as in the recogniser)
is rerun from 12 k-means partitions and once from the true articulation modes; the final training
log-likelihood and the adjusted Rand index of the split against the true modes say whether EM finds
the modes and whether a higher likelihood means a better split.
``--seed-spread``: every threshold the notebook asserts on its full-size data, recomputed with the
notebook's own pipeline for its seed (2004) and five others (``spawn_rngs(seed, 4)`` gives the
training, test, noisy and sweep sets as in the notebook), and the Section 5 per-term claim for the
seeds 3000-3004 at s = 2; each row prints the quantity per seed, so the margin of an assertion can be
set larger than the spread between seeds.
"""

from __future__ import annotations

from _harness import Benchmark  # first: pins BLAS threads before numpy is imported

VARIANTS = {
    "defaults (2 components, ridge 1e-3)": {},
    "1 component per class": dict(n_shape_components=1),
    "3 components per class": dict(n_shape_components=3),
    "shape ridge 3e-3": dict(shape_ridge=3e-3),
    "shape ridge 1e-2": dict(shape_ridge=1e-2),
    "shape ridge 1e-1": dict(shape_ridge=1e-1),
    "5 EM restarts": dict(n_restarts=5),
    "shape ridge 1e-2, 5 EM restarts": dict(shape_ridge=1e-2, n_restarts=5),
    "variance fraction 0.90": dict(variance_fraction=0.90),
    "variance fraction 0.98": dict(variance_fraction=0.98),
    "3 limb labels": dict(n_limb_labels=3),
    "p = 0.05": dict(label_error_probability=0.05),
    "p = 0.45": dict(label_error_probability=0.45),
}
BASELINES = {"single Cartesian PDM": ("SingleCartesianPDMClassifier", {}),  # classes of amdo_lab.pdm_mixtures
             "nearest Procrustes mean": ("NearestProcrustesMeanClassifier", {}),
             "sklearn GaussianMixture (diag)": ("SklearnGMMClassifier", {"rng": 0})}


def held_out_study(bench: Benchmark) -> None:
    """Held-out log-likelihood (nats per shape) of each class's polar-PDM mixture, per setting."""
    from amdo_lab import pdm_mixtures as pm
    from amdo_lab.common import spawn_rngs

    settings = {"M=1": dict(n_components=1), "M=2 (ours)": dict(n_components=2), "M=3": dict(n_components=3),
                "M=2, ridge 1e-2": dict(n_components=2, shape_ridge=1e-2),
                "M=2, ridge 1e-1": dict(n_components=2, shape_ridge=1e-1)}
    train = pm.make_pose_dataset(pm.TABLE1_CLASSES, 20, rng=spawn_rngs(2004, 4)[0])
    recogniser = pm.ArticulatedShapeRecogniser(rng=0).fit(train.shapes, train.labels)
    polar = pm.polar_shape_vector(recogniser.align(train.shapes))
    table = bench.table("class", *settings, "preferred",
                        title="held-out log-likelihood, nats per shape (5 folds, the notebook's training set)")
    for j, name in enumerate(recogniser.classes_):
        vectors = polar[train.labels == name]
        vectors[:, :13] = pm.wrap_angle(vectors[:, :13] - recogniser.angle_means_[j])
        scores = {label: pm.held_out_log_likelihood(vectors, rng=0, **options) for label, options in settings.items()}
        table.add(name, *(round(float(v), 1) for v in scores.values()), max(scores, key=scores.get))


def em_restarts_study(bench: Benchmark, n_starts: int = 12) -> None:
    """Shape-level EM of kicking and shooting from k-means starts and from the true modes."""
    import numpy as np
    from sklearn.cluster import KMeans
    from sklearn.metrics import adjusted_rand_score

    from amdo_lab import pdm_mixtures as pm
    from amdo_lab.common import spawn_rngs

    train = pm.make_pose_dataset(pm.TABLE1_CLASSES, 20, rng=spawn_rngs(2004, 4)[0])
    recogniser = pm.ArticulatedShapeRecogniser(rng=0).fit(train.shapes, train.labels)

    def run_em(scaled: np.ndarray, partition: np.ndarray) -> pm.GaussianMixtureResult:
        pooled = np.cov(scaled.T, bias=True)
        ridge = 1e-3 * np.trace(pooled) / scaled.shape[1]
        start = np.stack([scaled[partition == k].mean(axis=0) for k in range(2)])
        return pm.fit_gaussian_mixture(scaled, 2, means_init=start, n_iter=30, reg_covar=ridge,
                                       covariances_init=np.stack([pooled + ridge * np.eye(scaled.shape[1])] * 2))

    table = bench.table("class", "best start ll", "best start ARI", "worst start ll", "true modes ll",
                        "true modes ARI", title=f"shape-level EM from {n_starts} k-means starts and from the true modes")
    for name in ("kicking", "shooting"):
        mask = train.labels == name
        vectors = pm.polar_shape_vector(recogniser.align(train.shapes[mask]))
        vectors[:, :13] = pm.wrap_angle(vectors[:, :13] - recogniser.angle_means_[recogniser.classes_.index(name)])
        scaled = np.concatenate([block / np.sqrt(block.var(axis=0).sum()) for block in (vectors[:, :13], vectors[:, 13:])],
                                axis=1)
        modes = train.modes[mask]
        fits = [run_em(scaled, KMeans(2, n_init=1, init="random", random_state=seed).fit(scaled).labels_)
                for seed in range(n_starts)]
        best = max(fits, key=lambda fit: fit.log_likelihood[-1])
        truth = run_em(scaled, (modes == modes[0]).astype(int))
        table.add(name, round(float(best.log_likelihood[-1]), 2),
                  round(float(adjusted_rand_score(modes, best.responsibilities.argmax(axis=1))), 2),
                  round(float(min(fit.log_likelihood[-1] for fit in fits)), 2),
                  round(float(truth.log_likelihood[-1]), 2),
                  round(float(adjusted_rand_score(modes, truth.responsibilities.argmax(axis=1))), 2))


def seed_spread_study(bench: Benchmark, seeds: list[int]) -> None:
    """The notebook's asserted quantities for several seeds of its data (one column per seed)."""
    import numpy as np

    from amdo_lab import pdm_mixtures as pm
    from amdo_lab.common import paired_comparison, rate_interval, spawn_rngs

    paper = rate_interval(np.arange(1200) < 1118)
    rows: dict[str, list] = {}

    def put(name: str, value: object) -> None:
        rows.setdefault(name, []).append(round(float(value), 3) if not isinstance(value, str) else value)

    for seed in seeds:
        train_rng, test_rng, noisy_rng, sweep_rng = spawn_rngs(seed, 4)
        train = pm.make_pose_dataset(pm.TABLE1_CLASSES, 20, rng=train_rng)
        test = pm.make_pose_dataset(pm.TABLE1_CLASSES, 200, rng=test_rng)
        models = {"ours": pm.ArticulatedShapeRecogniser(rng=0),
                  "1 polar PDM": pm.ArticulatedShapeRecogniser(pm.RecogniserSettings(n_shape_components=1), rng=0),
                  "joint polar PDM": pm.ArticulatedShapeRecogniser(pm.RecogniserSettings(polar_model="joint"), rng=0),
                  "Cartesian PDM": pm.SingleCartesianPDMClassifier(),
                  "nearest mean": pm.NearestProcrustesMeanClassifier(),
                  "diagonal GMM": pm.SklearnGMMClassifier(rng=0)}
        for model in models.values():
            model.fit(train.shapes, train.labels)
        ours = models["ours"]
        right = {name: model.predict(test.shapes) == test.labels for name, model in models.items()}
        interval = rate_interval(right["ours"])
        put("Table 1: our rate", interval.rate)
        put("Table 1: |ours - paper| / larger half-width", abs(interval.rate - paper.rate)
            / max(interval.high - interval.rate, interval.rate - interval.low, paper.high - paper.rate))
        put("Table 1: our shooting rate", np.mean(right["ours"][test.labels == "shooting"]))
        shooting_ours = rate_interval(right["ours"][test.labels == "shooting"])
        put("Table 1: shooting, paper's interval low - our high (> 0: disjoint)",
            rate_interval(np.arange(200) < 179).low - shooting_ours.high)
        printed = pm.ArticulatedShapeRecogniser(pm.RecogniserSettings(eq11_reading="G ln p"), rng=0).fit(
            train.shapes, train.labels)
        put("eq. 11: ours - as printed, eq11_reading='G ln p' (> 0.1)",
            interval.rate - np.mean(printed.predict(test.shapes) == test.labels))
        confidence = ours.predict_proba(test.shapes).max(axis=1)
        put("reliability: errors with a posterior above 0.99 (> 0.5)", np.mean(confidence[~right["ours"]] > 0.99))
        put("baselines: diagonal GMM - ours", np.mean(right["diagonal GMM"]) - interval.rate)
        put("baselines: McNemar p, GMM vs ours", paired_comparison(right["ours"], right["diagonal GMM"]).p_value)
        put("baselines: ours - Cartesian PDM", interval.rate - np.mean(right["Cartesian PDM"]))
        arms_low = (test.labels == "shooting") & (test.modes == "arms low")
        parts = ours.score_components(test.shapes[arms_low])
        kick, shoot = ours.classes_.index("kicking"), ours.classes_.index("shooting")
        medians = {term: float(np.median(parts.class_scores(term)[:, kick] - parts.class_scores(term)[:, shoot]))
                   for term in ("shape", "limb_gate", "label_string")}
        put("arms-low shots: median polar - gates (> 0)", medians["shape"] - medians["limb_gate"])
        put("arms-low shots: median gates (> 0)", medians["limb_gate"])
        put("arms-low shots: |median label string| (< ln 4)", abs(medians["label_string"]))
        level_rng = spawn_rngs(sweep_rng, 4)[3]
        noisy = pm.make_pose_dataset(pm.TABLE1_CLASSES, 40, rng=level_rng, noise=0.08)
        polar_only = np.asarray(ours.classes_)[np.argmax(ours.score_components(noisy.shapes).class_scores("shape"), 1)]
        put("noise 0.08: ours - polar term only (< 0)",
            np.mean(ours.predict(noisy.shapes) == noisy.labels) - np.mean(polar_only == noisy.labels))
        subset = slice(None, None, 4)
        missing = test.shapes[subset].copy()
        shin = pm.LIMB_NAMES.index("right shin")
        missing[:, shin] = missing[:, shin, :1]
        for name, model in models.items():
            change = np.mean(model.predict(missing) == test.labels[subset]) - np.mean(right[name][subset])
            put(f"missing shin: change, {name}", change)
        sample = np.concatenate([np.flatnonzero(test.labels == c)[:9] for c in pm.TABLE1_CLASSES])
        fitted = ours.recognise(test.shapes[sample]).reconstructions[-1]
        coords = pm.classical_mds(pm.pairwise_distances(fitted), 3)
        labels = test.labels[sample]
        medians_xy = np.stack([np.median(coords[labels == c], axis=0) for c in labels])
        far = np.linalg.norm(coords - medians_xy, axis=1) > 2.0
        put("Figs. 7-8: classes of far shapes", "/".join(sorted(set(labels[far]))) or "none")
        noisy_set = pm.make_pose_dataset(pm.TABLE1_CLASSES, 15, rng=noisy_rng, noise=0.04)
        put("Fig. 9: recognition at noise 0.04", np.mean(ours.predict(noisy_set.shapes) == noisy_set.labels))
        print(f"seed {seed} done", flush=True)
    table = bench.table("quantity", *[str(seed) for seed in seeds],
                        title=f"the notebook's asserted quantities per seed of its data (first: the notebook's)")
    for name, values in rows.items():
        table.add(name, *values)
    why = bench.table("seed", "gap: 1 PDM - 2, polar only (>= 0)", "gap: 2 - 1 PDM, gates only (> 0)",
                      "gap: 2 - 1 PDM, all terms (> 0)", title="Section 5 at s = 2, rates per term (20 test shapes per class)")
    for seed in range(3000, 3005):
        train_rng, test_rng = spawn_rngs(seed, 2)
        train = pm.make_pose_dataset(pm.TABLE1_CLASSES, 20, rng=train_rng, mode_separation=2.0)
        test = pm.make_pose_dataset(pm.TABLE1_CLASSES, 20, rng=test_rng, mode_separation=2.0)
        rates = {}
        for components in (2, 1):
            settings = pm.RecogniserSettings(n_shape_components=components)
            model = pm.ArticulatedShapeRecogniser(settings, rng=0).fit(train.shapes, train.labels)
            parts = model.score_components(test.shapes)
            rates[components] = {terms: np.mean(np.asarray(model.classes_)[np.argmax(parts.class_scores(*terms), 1)]
                                                == test.labels)
                                 for terms in (("shape",), ("limb_gate",), ("shape", "limb_gate", "label_string"))}
        why.add(seed, *(round(float(sign * (rates[1][terms] - rates[2][terms])), 3) for sign, terms in
                        ((1, ("shape",)), (-1, ("limb_gate",)), (-1, ("shape", "limb_gate", "label_string")))))


def main() -> None:
    bench = Benchmark(__doc__)
    parser = bench.parser
    parser.add_argument("--seeds", type=int, nargs="+", default=list(range(201, 211)))
    parser.add_argument("--per-class", type=int, default=100)
    parser.add_argument("--train-per-class", type=int, default=20)
    parser.add_argument("--only", nargs="+", metavar="PREFIX", default=None,
                        help="run only the settings whose names start with one of these prefixes (baselines always run)")
    parser.add_argument("--held-out", action="store_true", help="held-out log-likelihood per class and setting, then stop")
    parser.add_argument("--em-restarts", action="store_true", help="shape-level EM from many starts, then stop")
    parser.add_argument("--seed-spread", action="store_true",
                        help="the notebook's asserted quantities for its seed 2004 and 5 others, then stop")
    args = bench.parse()
    if args.seed_spread:
        seed_spread_study(bench, [2004, 11, 12, 13, 14, 15])
        bench.finish()
        return
    if args.held_out or args.em_restarts:
        if args.held_out:
            held_out_study(bench)
        if args.em_restarts:
            em_restarts_study(bench)
        bench.finish()
        return
    if 2004 in args.seeds:
        parser.error("seed 2004 draws the notebook's test set; use other seeds")
    variants = {name: options for name, options in VARIANTS.items()
                if args.only is None or any(name.startswith(prefix) for prefix in args.only)}
    if not variants:
        parser.error(f"--only matched no setting; settings are: {', '.join(VARIANTS)}")
    import numpy as np

    from amdo_lab import pdm_mixtures as pm
    from amdo_lab.common import spawn_rngs

    rates = {name: [] for name in list(variants) + list(BASELINES)}
    for seed in args.seeds:
        fit_rng, check_rng = spawn_rngs(seed, 2)
        fit_set = pm.make_pose_dataset(pm.TABLE1_CLASSES, args.train_per_class, rng=fit_rng)
        check_set = pm.make_pose_dataset(pm.TABLE1_CLASSES, args.per_class, rng=check_rng)
        models = {name: pm.ArticulatedShapeRecogniser(pm.RecogniserSettings(**options), rng=0)
                  for name, options in variants.items()}
        models |= {name: getattr(pm, class_name)(**options) for name, (class_name, options) in BASELINES.items()}
        for name, model in models.items():
            predicted = model.fit(fit_set.shapes, fit_set.labels).predict(check_set.shapes)
            rates[name].append(float(np.mean(predicted == check_set.labels)))
    reference = np.array(rates["single Cartesian PDM"])
    table = bench.table("setting", "mean", "sd", "min", "max", "- single PDM", "wins",
                        title=f"validation seeds {args.seeds}, {args.train_per_class} training and "
                              f"{args.per_class} validation shapes per class")
    for name, values in rates.items():
        values = np.array(values)
        gap = values - reference
        spread = lambda v: round(float(v.std(ddof=1)), 3) if len(v) > 1 else float("nan")  # noqa: E731
        table.add(name, round(float(values.mean()), 3), spread(values), round(float(values.min()), 3),
                  round(float(values.max()), 3), f"{gap.mean():+.3f}±{spread(gap):.3f}", f"{int(np.sum(gap > 0))}/{len(gap)}")
    bench.finish()


if __name__ == "__main__":
    main()
