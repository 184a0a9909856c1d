"""Bad-input table of ``amdo_lab.pdm_mixtures``: a valid call and the kind of each argument."""

from __future__ import annotations

import numpy as np

from bad_input_cases._core import Case

#: (callable, argument, spoiled label) calls known to fail the test, with the reason; each must
#: still fail (remove it once fixed).
KNOWN_FAILURES: dict[tuple[str, str, str], str] = {}

#: Public names not called with user input, with the reason.
EXEMPT = {
    "AlignmentTrace": "a result record, built by ArticulatedShapeRecogniser.iterative_alignment",
    "GaussianMixtureResult": "a result record, built by fit_gaussian_mixture from checked input",
    "PolarPDM": "a result record, built by the recogniser's fit (its methods are tabled below)",
    "PoseDataset": "a result record, built by make_pose_dataset from checked input",
    "RecognitionTrace": "a result record, built by ArticulatedShapeRecogniser.recognise",
    "ScoreComponents": "a result record, built by ArticulatedShapeRecogniser.score_components",
    "SeparationTrial": "a result record, built by mode_separation_trial from checked input",
    "ScoreComponents.printed_eq11_scores": "takes no argument",
}

CLASSES = ("boxing", "kicking")


def cases() -> dict[str, Case]:
    """The public callables of ``amdo_lab.pdm_mixtures``, by name (small inputs: 2 classes, 4 shapes
    each, 2 landmarks per limb, few iterations)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from amdo_lab import pdm_mixtures as p
    from amdo_lab.pdm_mixtures.recognition import _class_posteriors
    from amdo_lab.pdm_mixtures.representation import _centred_limbs

    _, axes = plt.subplots()
    data = p.make_pose_dataset(CLASSES, 4, rng=0, landmarks_per_limb=2)
    shapes, labels = data.shapes, data.labels
    int_labels = np.repeat([0, 1], 4)  # numbers, so that NaN/inf labels can be spoiled in
    polar = p.polar_shape_vector(shapes)
    centres = p.limb_centres(shapes)
    rng = np.random.default_rng(0)
    long_vectors = rng.normal(size=(8, 6))
    model = p.fit_pdm(long_vectors, variance_fraction=0.9)
    point_sets = rng.normal(size=(3, 5, 2))
    gmm_points = np.concatenate([rng.normal(size=(6, 2)), rng.normal(size=(6, 2)) + 4.0])
    one_component = p.RecogniserSettings(n_shape_components=1)
    recogniser = p.ArticulatedShapeRecogniser(one_component, rng=0)
    recogniser.fit(shapes, labels)
    polar_pdm = recogniser.shape_models_[0][0]
    cartesian = p.SingleCartesianPDMClassifier().fit(shapes, int_labels)
    nearest = p.NearestProcrustesMeanClassifier().fit(shapes, int_labels)
    sk_gmm = p.SklearnGMMClassifier(1, rng=0).fit(shapes, int_labels)
    components = recogniser.score_components(shapes[:2])
    terms = {"shape_log_lik": components.shape, "limb_gate": components.limb_gate,
             "string_log_prob": components.label_string, "log_weights": components.log_weights}
    joint = p.gated_component_scores(**terms)
    posterior, _ = _class_posteriors(joint, components.class_log_prior, "G p")
    limb_log_post = recogniser.limb_label_posteriors(shapes[:2], log=True)
    trial = p.mode_separation_trial(1.0, rng=0, n_train=6, n_test=1, classes=CLASSES)
    label_strings = np.array([[0, 1, 2], [1, 1, 0]])
    dictionary = np.array([[0, 1, 1], [2, 2, 2], [1, 0, 0]])
    distances = p.pairwise_distances(long_vectors)
    first = shapes[:1]
    # a string or a number for ``shapes`` must fail: shapes spoilt as "points"-kind arrays
    fitted_shape_cases = {
        "ArticulatedShapeRecogniser.align": recogniser.align,
        "ArticulatedShapeRecogniser.recognise": recogniser.recognise,
        "ArticulatedShapeRecogniser.score_components": recogniser.score_components,
        "ArticulatedShapeRecogniser.predict_proba": recogniser.predict_proba,
        "ArticulatedShapeRecogniser.predict": recogniser.predict,
        "SingleCartesianPDMClassifier.log_likelihoods": cartesian.log_likelihoods,
        "SingleCartesianPDMClassifier.predict": cartesian.predict,
        "NearestProcrustesMeanClassifier.distances": nearest.distances,
        "NearestProcrustesMeanClassifier.predict": nearest.predict,
        "SklearnGMMClassifier.predict": sk_gmm.predict,
    }

    settings_valid = {"n_limb_labels": 4, "n_shape_components": 1, "shape_ridge": 1e-3, "n_restarts": 1,
                      "label_error_probability": 0.2, "variance_fraction": 0.95, "polar_model": "block",
                      "limb_likelihood": "gaussian", "eq11_reading": "G p"}
    settings_kinds = {"n_limb_labels": "count", "n_shape_components": "count", "shape_ridge": "positive",
                      "n_restarts": "count", "label_error_probability": "probability",
                      "variance_fraction": "probability", "polar_model": "name", "limb_likelihood": "name",
                      "eq11_reading": "name"}

    def recogniser_fit(shapes, labels, settings, rng):
        return p.ArticulatedShapeRecogniser(settings, rng=rng).fit(shapes, labels)

    table = {
        # ------------------------------------------------------------ estimators: constructor + fit
        "RecogniserSettings": Case(p.RecogniserSettings, settings_valid, settings_kinds),
        "ArticulatedShapeRecogniser": Case(
            recogniser_fit, {"shapes": shapes, "labels": labels, "settings": one_component, "rng": 0},
            {"shapes": "points", "labels": "object", "settings": "object", "rng": "seed"}),
        "ArticulatedShapeRecogniser.fit": Case(
            lambda shapes, labels: p.ArticulatedShapeRecogniser(one_component, rng=0).fit(shapes, labels),
            {"shapes": shapes, "labels": int_labels}, {"shapes": "points", "labels": "array"}),
        "ArticulatedShapeRecogniser.limb_label_posteriors": Case(
            recogniser.limb_label_posteriors, {"shapes": first, "log": False}, {"shapes": "points", "log": "flag"}),
        "ArticulatedShapeRecogniser.iterative_alignment": Case(
            recogniser.iterative_alignment, {"shape": shapes[0], "class_name": CLASSES[0], "n_iter": 2},
            {"shape": "points", "class_name": "name", "n_iter": "count"}),
        "ArticulatedShapeRecogniser.model_limbs": Case(
            recogniser.model_limbs,
            {"polar_vector": polar[0], "label_string": np.zeros(13, int), "observed_limbs": _centred_limbs(first)[0]},
            {"polar_vector": "array", "label_string": "array", "observed_limbs": "points"},
            accept=frozenset({("observed_limbs", "None")})),  # None, the default: no observed limbs to fit
        "SingleCartesianPDMClassifier": Case(
            lambda shapes, labels, variance_fraction: p.SingleCartesianPDMClassifier(variance_fraction).fit(
                shapes, labels),
            {"shapes": shapes, "labels": int_labels, "variance_fraction": 0.95},
            {"shapes": "points", "labels": "array", "variance_fraction": "probability"}),
        "NearestProcrustesMeanClassifier": Case(
            lambda shapes, labels: p.NearestProcrustesMeanClassifier().fit(shapes, labels),
            {"shapes": shapes, "labels": int_labels}, {"shapes": "points", "labels": "array"}),
        "SingleCartesianPDMClassifier.fit": Case(p.SingleCartesianPDMClassifier().fit,
                                                 {"shapes": shapes, "labels": int_labels},
                                                 {"shapes": "points", "labels": "array"}),
        "NearestProcrustesMeanClassifier.fit": Case(p.NearestProcrustesMeanClassifier().fit,
                                                    {"shapes": shapes, "labels": int_labels},
                                                    {"shapes": "points", "labels": "array"}),
        "SklearnGMMClassifier.fit": Case(p.SklearnGMMClassifier(1, rng=0).fit,
                                         {"shapes": shapes, "labels": int_labels},
                                         {"shapes": "points", "labels": "array"}),
        "SklearnGMMClassifier": Case(
            lambda shapes, labels, n_components, rng: p.SklearnGMMClassifier(n_components, rng=rng).fit(shapes, labels),
            {"shapes": shapes, "labels": int_labels, "n_components": 1, "rng": 0},
            {"shapes": "points", "labels": "array", "n_components": "count", "rng": "seed"}),
        "ScoreComponents.class_scores": Case(lambda terms: components.class_scores(terms), {"terms": "shape"},
                                             {"terms": "name"}),
        "SeparationTrial.rate": Case(trial.rate, {"model": "mixture of PDMs"}, {"model": "name"}),
        # ------------------------------------------------------------ generator and representation
        "make_pose_dataset": Case(
            p.make_pose_dataset,
            {"classes": CLASSES, "n_per_class": 2, "rng": 0, "noise": 0.01, "joint_jitter_deg": 10.0,
             "length_jitter": 0.06, "landmarks_per_limb": 2, "max_rotation_deg": 15.0, "mode_separation": 1.0},
            {"classes": "object", "n_per_class": "count", "rng": "seed", "noise": "non_negative",
             "joint_jitter_deg": "non_negative", "length_jitter": "non_negative", "landmarks_per_limb": "count",
             "max_rotation_deg": "non_negative", "mode_separation": "non_negative"}),
        "skeleton_strokes": Case(
            p.skeleton_strokes,
            {"directions_deg": np.full((1, 13), 30.0),
             "lengths": data.limb_lengths[:1], "landmarks_per_limb": 2},
            {"directions_deg": "array", "lengths": "array", "landmarks_per_limb": "count"}),
        "wrap_angle": Case(p.wrap_angle, {"angles": np.array([0.5, 4.0, -7.0])}, {"angles": "array"},
                           # angles of any shape, even empty, are wrapped elementwise
                           accept=frozenset({("angles", "an empty array"), ("angles", "one more axis"),
                                             ("angles", "a wrong trailing axis")})),
        "limb_centres": Case(p.limb_centres, {"shapes": shapes}, {"shapes": "points"}),
        "articulation_centre": Case(p.articulation_centre, {"centres": centres}, {"centres": "points"}),
        "limb_angles": Case(p.limb_angles, {"centres": centres}, {"centres": "points"}),
        "polar_shape_vector": Case(p.polar_shape_vector, {"shapes": shapes}, {"shapes": "points"}),
        "draw_shape": Case(
            p.draw_shape, {"ax": axes, "shape": shapes[0], "color": "black", "linewidth": 1.5, "alpha": 1.0,
                           "label": "a shape"},
            {"ax": "object", "shape": "points", "linewidth": "positive", "alpha": "probability", "color": "object",
             "label": "name"},
            accept=frozenset({("label", "None")})),  # None: no legend entry
        # ------------------------------------------------------------ point distribution models
        "fit_pdm": Case(p.fit_pdm, {"long_vectors": long_vectors, "variance_fraction": 0.9},
                        {"long_vectors": "array", "variance_fraction": "probability"},
                        accept=frozenset({("long_vectors", "a wrong trailing axis")})),  # long-vectors of any length D
        "PointDistributionModel": Case(
            p.PointDistributionModel,
            {"mean": model.mean, "modes": model.modes, "variances": model.variances,
             "residual_variance": model.residual_variance},
            {"mean": "array", "modes": "array", "variances": "array", "residual_variance": "positive"}),
        "fit_modes": Case(p.fit_modes, {"model": model, "observed": long_vectors[0], "clamp": True},
                          {"model": "object", "observed": "array", "clamp": "flag"},
                          accept=frozenset({("observed", "one more axis")})),  # (1, D): one row of the (n, D) form
        "reconstruct": Case(p.reconstruct, {"model": model, "gamma": np.zeros(model.n_modes)},
                            {"model": "object", "gamma": "array"},
                            accept=frozenset({("gamma", "one more axis")})),  # (1, M): one row of the (n, M) form
        "ppca_log_density": Case(p.ppca_log_density, {"model": model, "observed": long_vectors[:2]},
                                 {"model": "object", "observed": "points"}),
        "generalized_procrustes": Case(p.generalized_procrustes, {"point_sets": point_sets, "n_iter": 2},
                                       {"point_sets": "points", "n_iter": "count"}),
        # ------------------------------------------------------------ mixtures and recognition
        "fit_gaussian_mixture": Case(
            p.fit_gaussian_mixture,
            {"X": gmm_points, "n_components": 2, "means_init": np.array([[0.0, 0.0], [4.0, 4.0]]),
             "covariances_init": np.stack([np.eye(2), np.eye(2)]), "weights_init": np.array([0.5, 0.5]),
             "n_iter": 3, "reg_covar": 1e-6},
            {"X": "points", "n_components": "count", "means_init": "array", "covariances_init": "array",
             "weights_init": "array", "n_iter": "count", "reg_covar": "non_negative"},
            # None is the documented default of weights_init (equal weights)
            accept=frozenset({("weights_init", "None")})),
        "hamming_distance": Case(p.hamming_distance, {"label_strings": label_strings, "dictionary": dictionary},
                                 {"label_strings": "array", "dictionary": "array"}),
        "label_string_log_prob": Case(p.label_string_log_prob,
                                      {"hamming": np.array([[0, 1], [3, 2]]), "n_limbs": 3, "error_probability": 0.2},
                                      {"hamming": "array", "n_limbs": "count", "error_probability": "probability"},
                                      # distances of any shape, elementwise; zeros are valid distances
                                      accept=frozenset({("hamming", "one more axis"),
                                                        ("hamming", "a wrong trailing axis")})),
        "held_out_log_likelihood": Case(
            p.held_out_log_likelihood,
            {"polar_vectors": polar, "n_components": 1, "shape_ridge": 1e-3, "n_folds": 2, "rng": 0},
            {"polar_vectors": "array", "n_components": "count", "shape_ridge": "positive", "n_folds": "count",
             "rng": "seed"}),
        "gated_component_scores": Case(
            p.gated_component_scores, {**terms, "reading": "G p"},
            {"shape_log_lik": "array", "limb_gate": "array", "string_log_prob": "array", "log_weights": "array",
             "reading": "name"}),
        "winning_components": Case(p.winning_components, {"posterior": posterior, "component_scores": joint},
                                   {"posterior": "array", "component_scores": "array"},
                                   accept=frozenset({("component_scores", "a wrong trailing axis")})),  # any M
        "relabel_limbs": Case(
            p.relabel_limbs, {"limb_log_posteriors": limb_log_post, "winning_strings": np.zeros((2, 13), int),
                              "error_probability": 0.2},
            {"limb_log_posteriors": "array", "winning_strings": "array", "error_probability": "probability"},
            accept=frozenset({("limb_log_posteriors", "a wrong trailing axis")})),  # any number of labels
        "mode_separation_trial": Case(
            p.mode_separation_trial,
            {"separation": 1.0, "rng": 0, "n_train": 6, "n_test": 1, "classes": CLASSES},
            {"separation": "non_negative", "rng": "seed", "n_train": "count", "n_test": "count",
             "classes": "object"}),
        # ------------------------------------------------------------ baselines
        "pairwise_distances": Case(p.pairwise_distances, {"vectors": long_vectors}, {"vectors": "array"},
                                   accept=frozenset({("vectors", "a wrong trailing axis")})),  # vectors of any length
        "classical_mds": Case(p.classical_mds, {"distances": distances, "n_dims": 2},
                              {"distances": "array", "n_dims": "count"}),
        "pca_embedding": Case(p.pca_embedding, {"vectors": long_vectors, "n_dims": 2},
                              {"vectors": "array", "n_dims": "count"},
                              accept=frozenset({("vectors", "a wrong trailing axis")})),  # vectors of any length
    }
    table |= {name: Case(method, {"shapes": shapes[:2]}, {"shapes": "points"})
              for name, method in fitted_shape_cases.items()}
    width = polar_pdm.mean.shape[0]
    table["PolarPDM.project"] = Case(polar_pdm.project, {"deviation": np.zeros((2, width))}, {"deviation": "points"})
    table["PolarPDM.log_density"] = Case(polar_pdm.log_density, {"deviation": np.zeros((2, width))},
                                         {"deviation": "points"})
    return table
