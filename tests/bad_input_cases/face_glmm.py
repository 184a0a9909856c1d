"""Bad-input table of ``amdo_lab.face_glmm``: a valid call and the kind of each argument.

The valid inputs are tiny (8 x 8 faces, a 32-row GLMM table, a one-training-set design of 4
subjects), so a spoiled call that is wrongly accepted still runs in well under a second.
"""

from __future__ import annotations

import tempfile

import numpy as np

from bad_input_cases._core import Case

#: (callable, argument, spoiled label) calls known to fail the test, with the reason; each must
#: still fail (remove it once fixed).
KNOWN_FAILURES: dict[tuple[str, str, str], str] = {}

#: Public names not called with user input, with the reason.
EXEMPT = {
    "lme4_available": "takes no argument",
    "paper_design": "takes no argument",
    "reduced_design": "takes no argument",
    "DesignMatrix": "a result record, built by fit_binomial_glmm from checked input (GlmmResult.design)",
    "ExperimentDraws": "a result record, built by experiment_draws from checked input",
    "FacePopulation": "a result record, built by make_face_population from checked input",
    "GlmmResult": "a result record, built by fit_binomial_glmm (its predict methods are tabled)",
    "PeerFit": "a result record, built by fit_with_lme4, fit_gee and fit_naive_logistic",
    "RecoverySummary": "a result record, built by recovery_study from checked input",
}


#: A stack of images one column wider (8 x 9) is valid wherever any image size is.
_ANY_WIDTH = frozenset({("images", "a wrong trailing axis")})


def _tiny_table(n_t: int = 2, n_p: int = 4):
    """A balanced t x p x M x D table of Y counts out of 10 (n_t * n_p * 4 rows)."""
    import pandas as pd

    grid = pd.MultiIndex.from_product([range(n_t), range(n_p), ["l2", "soft_l2"], ["fixed", "e90"]],
                                      names=["t", "p", "M", "D"]).to_frame(index=False)
    grid["Y"] = np.random.default_rng(0).integers(0, 11, len(grid))
    return grid


def _paper_table():
    """A tiny table with the paper's factors U, M, D, F, S (for the report functions)."""
    import pandas as pd

    grid = pd.MultiIndex.from_product(
        [range(2), range(3), ["none", "shift", "reflection", "noise"], ["l2", "soft_l2"], ["fixed", "e90"], ["yes", "no"],
         ["standard", "small"]], names=["t", "p", "U", "M", "D", "F", "S"]).to_frame(index=False)
    grid["Y"] = np.random.default_rng(1).integers(0, 11, len(grid))
    return grid


def cases() -> dict[str, Case]:
    """The public callables of ``amdo_lab.face_glmm``, by name."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import pandas as pd

    from amdo_lab import face_glmm as f
    from amdo_lab.face_glmm import PAPER_FORMULA, SIZE_FORMULA

    table = _tiny_table()
    fit = f.fit_binomial_glmm(table, "Y ~ M", ["p"], 10)
    paper_table = _paper_table()
    paper_fit = f.fit_binomial_glmm(paper_table[paper_table.S == "standard"], PAPER_FORMULA, ["p"], 10)
    size_fit = f.fit_binomial_glmm(paper_table, SIZE_FORMULA, ["p"], 10)
    figure, axes = plt.subplots(1, 4)
    design = f.FactorialDesign(n_subjects=4, n_training_sets=1, n_train_subjects=2, n_galleries=2,
                               supplements=("none",), shape=(8, 8))
    cache_dir = tempfile.mkdtemp(prefix="bad_input_face_glmm_")
    population = f.make_face_population(3, 3, rng=0, shape=(8, 8))
    images = f.preprocess_images(population.images)
    labels = population.labels
    model = f.PcaLda(2).fit(images, labels)
    samples = images.reshape(len(images), -1)
    coefficients = fit.coefficients

    return {
        # --- population ------------------------------------------------------------------------
        "make_face_population": Case(
            f.make_face_population,
            {"n_subjects": 3, "images_per_subject": 2, "rng": 0, "shape": (8, 8), "nuisance": 1.0,
             "texture_slope": 2.0, "texture_amplitude": 0.5},
            {"n_subjects": "count", "images_per_subject": "count", "rng": "seed", "shape": "array",
             "nuisance": "non_negative",
             "texture_slope": "positive", "texture_amplitude": "non_negative"},
            # texture_slope=None is the default: the cosine texture only
            accept=frozenset({("texture_slope", "None")})),
        "downsample_by_two": Case(f.downsample_by_two, {"images": population.images}, {"images": "image"}),
        "preprocess_images": Case(f.preprocess_images, {"images": population.images}, {"images": "image"},
                                  accept=_ANY_WIDTH),
        # --- PCA + LDA -------------------------------------------------------------------------
        "pca_basis": Case(f.pca_basis, {"samples": samples}, {"samples": "array"},
                          accept=frozenset({("samples", "a wrong trailing axis")})),  # 65 pixels a row: valid
        "e90_dimension": Case(f.e90_dimension, {"eigenvalues": np.array([3.0, 2.0, 1.0]), "energy": 0.9},
                              {"eigenvalues": "array", "energy": "probability"}),
        "weighted_sq_distances": Case(f.weighted_sq_distances,
                                      {"a": samples[:3, :4], "b": samples[3:5, :4], "weights": np.ones(4)},
                                      {"a": "points", "b": "points", "weights": "array"}),
        "PcaLda": Case(lambda pca_dimension, base_images_per_class: f.PcaLda(pca_dimension,
                                                                              base_images_per_class).fit(images, labels),
                       {"pca_dimension": 2, "base_images_per_class": 2},
                       {"pca_dimension": "count", "base_images_per_class": "count"}),
        "PcaLda.fit": Case(lambda images, labels, basis: f.PcaLda(2).fit(images, labels, basis),
                           {"images": images, "labels": labels, "basis": None},
                           {"images": "image", "labels": "array", "basis": "object"},
                           accept=frozenset({("basis", "None")})),  # None: computed from the images
        "PcaLda.transform": Case(lambda images: model.transform(images), {"images": images}, {"images": "image"}),
        "PcaLda.distances": Case(lambda probes, gallery, metric: model.distances(probes, gallery, metric),
                                 {"probes": images[:2], "gallery": images[2:5], "metric": "l2"},
                                 {"probes": "image", "gallery": "image", "metric": "name"}),
        # --- the factorial experiment --------------------------------------------------------
        "FactorialDesign": Case(
            f.FactorialDesign,
            {"n_subjects": 4, "n_training_sets": 1, "n_train_subjects": 2, "n_galleries": 2,
             "supplements": ("none",), "shape": (8, 8), "nuisance": 0.95, "population_kwargs": {}},
            {"n_subjects": "count", "n_training_sets": "count", "n_train_subjects": "count", "n_galleries": "count",
             "supplements": "object", "shape": "array", "nuisance": "positive", "population_kwargs": "object"}),
        "make_supplement": Case(f.make_supplement, {"images": images[:2], "kind": "noise", "rng": 0},
                                {"images": "image", "kind": "name", "rng": "seed"}, accept=_ANY_WIDTH),
        "experiment_draws": Case(f.experiment_draws, {"design": design, "rng": 0},
                                 {"design": "object", "rng": "seed"}),
        "run_factorial_experiment": Case(f.run_factorial_experiment, {"design": design, "rng": 0},
                                         {"design": "object", "rng": "seed"}),
        "load_or_run_experiment": Case(f.load_or_run_experiment, {"design": design, "cache_dir": cache_dir, "rng": 0},
                                       {"design": "object", "cache_dir": "name", "rng": "seed"}),
        # --- formula, design, GLMM -----------------------------------------------------------
        "parse_formula": Case(f.parse_formula, {"formula": "Y ~ M * D"}, {"formula": "name"}),
        "group_indices": Case(f.group_indices, {"table": table, "term": "t:p"}, {"table": "object", "term": "name"}),
        "laplace_deviance_reference": Case(
            f.laplace_deviance_reference,
            {"y": np.array([3.0, 5.0, 9.0, 2.0]), "n_trials": np.full(4, 10.0),
             "x": np.array([[1.0, 0.0], [1.0, 1.0], [1.0, 0.0], [1.0, 1.0]]),
             "z": np.array([[1.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.0, 1.0]]), "sd_of_columns": np.array([0.5, 0.5])},
            {"y": "array", "n_trials": "array", "x": "array", "z": "array", "sd_of_columns": "array"}),
        "laplace_deviance": Case(f.laplace_deviance,
                                 {"table": table, "fixed": "Y ~ M", "random": ["p"], "sd": np.array([[0.5], [1.0]]),
                                  "n_trials": 10},
                                 {"table": "object", "fixed": "name", "random": "object", "sd": "array",
                                  "n_trials": "count"}),
        "fit_binomial_glmm": Case(f.fit_binomial_glmm,
                                  {"table": table, "fixed": "Y ~ M", "random": ["p"], "n_trials": 10},
                                  {"table": "object", "fixed": "name", "random": "object", "n_trials": "count"}),
        "GlmmResult.predict": Case(lambda newdata, ci: fit.predict(newdata, ci),
                                   {"newdata": pd.DataFrame({"M": ["l2"]}), "ci": 0.95},
                                   {"newdata": "object", "ci": "probability"},
                                   accept=frozenset({("ci", "None")})),  # None: no interval
        "GlmmResult.predict_marginal": Case(lambda grid, ci: fit.predict_marginal(grid, ci),
                                            {"grid": pd.DataFrame({"M": ["l2"]}), "ci": 0.95},
                                            {"grid": "object", "ci": "probability"},
                                            accept=frozenset({("ci", "None")})),  # None: no interval
        # --- simulation ------------------------------------------------------------------------
        "simulate_binomial_glmm": Case(f.simulate_binomial_glmm,
                                       {"table": table, "fixed": "Y ~ M", "coefficients": np.array([0.2, -0.3]),
                                        "variances": {"p": 0.5}, "n_trials": 10, "rng": 0},
                                       {"table": "object", "fixed": "name", "coefficients": "array",
                                        "variances": "object", "n_trials": "count", "rng": "seed"}),
        "recovery_study": Case(f.recovery_study,
                               {"table": table, "fixed": "Y ~ M", "coefficients": coefficients,
                                "variances": {"p": 0.5}, "n_replicates": 1, "rng": 0, "n_trials": 10, "level": 0.95},
                               {"table": "object", "fixed": "name", "coefficients": "object", "variances": "object",
                                "n_replicates": "count", "rng": "seed", "n_trials": "count", "level": "probability"}),
        # --- peers -----------------------------------------------------------------------------
        "fit_with_lme4": Case(f.fit_with_lme4, {"table": table, "fixed": "Y ~ M", "random": ["p"], "n_trials": 10},
                              {"table": "object", "fixed": "name", "random": "object", "n_trials": "count"}),
        "fit_gee": Case(f.fit_gee,
                                     {"table": table, "fixed": "Y ~ M", "group": "p", "n_trials": 10,
                                      "correlation": "exchangeable"},
                                     {"table": "object", "fixed": "name", "group": "name", "n_trials": "count",
                                      "correlation": "name"}),
        "fit_naive_logistic": Case(f.fit_naive_logistic, {"table": table, "fixed": "Y ~ M", "n_trials": 10},
                                   {"table": "object", "fixed": "name", "n_trials": "count"}),
        # --- report ----------------------------------------------------------------------------
        "table2_comparison": Case(f.table2_comparison, {"result": paper_fit}, {"result": "object"}),
        "cell_predictions": Case(f.cell_predictions, {"result": paper_fit, "ci": 0.95},
                                 {"result": "object", "ci": "probability"},
                                 accept=frozenset({("ci", "None")})),  # None: no interval
        "findings": Case(f.findings, {"result": paper_fit, "size_result": size_fit},
                         {"result": "object", "size_result": "object"},
                         accept=frozenset({("size_result", "None")})),  # None: no image-size findings
        "plot_figure1": Case(f.plot_figure1, {"result": paper_fit, "ax": axes[0]}, {"result": "object", "ax": "object"}),
        "plot_figure2": Case(f.plot_figure2, {"result": paper_fit, "axes": axes[1:]},
                             {"result": "object", "axes": "object"}),
    }
