"""Bad-input table of ``amdo_lab.common``: a valid call and the kind of each argument."""

from __future__ import annotations

import numpy as np

from bad_input_cases._core import Case, rotation_problem

#: (callable, argument, spoiled label) calls known to fail the test, with the reason; each must
#: still fail (remove it once fixed).
KNOWN_FAILURES: dict[tuple[str, str, str], str] = {}

#: Public names not called with user input, with the reason.
EXEMPT = {
    "check_answer": "an exercise check prints its verdict and never raises, by design",
    "check_overflow": "checks a result the package computed from already-checked input, not user input",
    "check_same_shape": "compares two arrays already converted by as_finite_array, not user input",
    "one_blas_thread": "takes no argument",
    "use_style": "takes no argument",
    "RateInterval": "a result record, built by rate_interval from checked input",
    "PairedComparison": "a result record, built by paired_comparison from checked input",
}


def cases() -> dict[str, Case]:
    """The public callables of ``amdo_lab.common``, by name."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import pandas as pd

    from amdo_lab import common as c

    figure, axes = plt.subplots()
    points3 = np.arange(12.0).reshape(4, 3)
    points2 = np.arange(8.0).reshape(4, 2)
    right, wrong = np.array([True, False, True, True]), np.array([True, True, False, True])

    class Fitted:
        coef_ = np.ones(2)

    # The validators' ``name`` is the caller's argument name, written by a developer, not user input:
    # it is not spoiled.
    return {
        "apply_rigid": Case(c.apply_rigid, {"transform": np.eye(4), "points": points3},
                            {"transform": "array", "points": "points"},
                            accept=frozenset({("points", "an empty array")})),
        "apply_similarity_2d": Case(c.apply_similarity_2d,
                                    {"points": points2, "scale": 2.0, "angle": 0.3, "translation": [1.0, 2.0]},
                                    {"points": "points", "scale": "positive", "angle": "real", "translation": "array"},
                                    accept=frozenset({("points", "an empty array")})),
        "as_bool_mask": Case(c.as_bool_mask, {"value": right, "name": "mask"}, {"value": "bool_array"},
                             names={"value": "mask"},  # without a required shape any boolean array is a mask
                             accept=frozenset({("value", "a bool"), ("value", "one more axis"),
                                               ("value", "a wrong trailing axis")})),
        "as_finite_array": Case(c.as_finite_array, {"value": points3, "name": "points", "shape": (None, 3)},
                                {"value": "points"}, names={"value": "points"}),
        "as_outcomes": Case(c.as_outcomes, {"value": right, "name": "outcomes"},
                            {"value": "bool_array"}, names={"value": "outcomes"},
                            accept=frozenset({("value", "a wrong trailing axis")})),  # any number of items
        "check_seed": Case(c.check_seed, {"value": 3, "name": "rng"}, {"value": "seed"}, names={"value": "rng"}),
        "as_points": Case(c.as_points, {"value": points2, "name": "points", "dim": 2, "allow_empty": False},
                          {"value": "points"}, names={"value": "points"}),
        "as_probabilities": Case(c.as_probabilities, {"value": [0.25, 0.75], "name": "weights"},
                                 {"value": "array"}, names={"value": "weights"}),
        "as_rotation": Case(c.as_rotation, {"value": np.eye(3), "name": "rotation"},
                            {"value": "array"}, names={"value": "rotation"},
                            accept=frozenset({("value", "one more axis")})),  # a stack of one rotation
        "as_weights": Case(c.as_weights, {"value": [1.0, 2.0], "name": "weights", "n": 2},
                           {"value": "array"}, names={"value": "weights"}),
        "as_image_pair": Case(c.as_image_pair, {"first": np.ones((4, 4)), "second": np.zeros((4, 4))},
                              {"first": "image", "second": "image"},
                              names={"first": "template", "second": "study"}),
        "check_axes": Case(c.check_axes, {"ax": axes}, {"ax": "object"}),
        "check_bool": Case(c.check_bool, {"value": True, "name": "verbose"}, {"value": "flag"},
                           names={"value": "verbose"}),
        "check_choice": Case(c.check_choice, {"value": "l2", "name": "metric", "choices": ("l2", "soft_l2")},
                             {"value": "object"}, names={"value": "metric"}),
        "check_dataframe": Case(c.check_dataframe, {"value": pd.DataFrame({"correct": [1]}), "name": "table",
                                                    "columns": ("correct",)},
                                {"value": "object"}, names={"value": "table"}),
        "check_fitted": Case(c.check_fitted, {"estimator": Fitted(), "attributes": "coef_"},
                             {"estimator": "object"}, names={"estimator": "not fitted"}),
        "check_image_shape": Case(c.check_image_shape, {"shape": (6, 5), "name": "size", "minimum": 2},
                                  {"shape": "object"}, names={"shape": "size"}),
        "check_in_range": Case(c.check_in_range, {"value": 0.5, "name": "p", "low": 0, "high": 1},
                               {"value": "probability"}, names={"value": "p"}),
        "check_names": Case(c.check_names, {"values": ("fist", "point"), "name": "classes",
                                            "allowed": ("fist", "point", "open")},
                            {"values": "object"}, names={"values": "classes"}),
        "check_instance": Case(c.check_instance, {"value": 1.0, "name": "sigma", "expected": float},
                               {"value": "object"}, names={"value": "sigma"}),
        "check_sequence_of": Case(c.check_sequence_of, {"values": [1.0, 2.0], "name": "scales", "expected": float,
                                                        "what": "a float"},
                                  {"values": "object"}, names={"values": "scales"}),
        "check_odd_int": Case(c.check_odd_int, {"value": 3, "name": "window", "maximum": 99},
                              {"value": "count"}, names={"value": "window"}),
        "check_positive": Case(c.check_positive, {"value": 2.0, "name": "sigma"},
                               {"value": "positive"}, names={"value": "sigma"}),
        "check_positive_int": Case(c.check_positive_int, {"value": 3, "name": "n_iter", "maximum": 1000},
                                   {"value": "count"}, names={"value": "n_iter"}),
        "make_rng": Case(c.make_rng, {"seed": 0, "name": "rng"}, {"seed": "seed"}, names={"seed": "rng"}),
        "paired_comparison": Case(c.paired_comparison, {"first": right, "second": wrong},
                                  {"first": "bool_array", "second": "bool_array"}),
        "planar_chain": Case(c.planar_chain, {"angles": np.array([0.3, -0.2]), "lengths": np.array([2.0, 1.0]),
                                              "base": np.zeros(2)},
                             {"angles": "array", "lengths": "array", "base": "array"},
                             accept=frozenset({("angles", "one more axis")})),  # a batch of one chain
        "effective_sample_size": Case(c.effective_sample_size, {"weights": np.array([0.2, 0.5, 0.3])},
                                      {"weights": "array"}),
        "normalised_weights": Case(c.normalised_weights, {"log_weights": np.array([-3.0, -1.0, -2.0])},
                                   {"log_weights": "array"},
                                   accept=frozenset({("log_weights", "a wrong trailing axis")}),  # any N
                                   check=lambda w, a: None if np.isclose(np.sum(w), 1.0) and np.all(w >= 0)
                                   else f"weights summing to {np.sum(w)}"),
        "systematic_resample": Case(c.systematic_resample, {"weights": np.array([0.2, 0.5, 0.3]), "u": 0.4},
                                    {"weights": "array", "u": "probability"}),
        "procrustes_align": Case(c.procrustes_align, {"source": points2, "target": points2[::-1].copy(),
                                                      "allow_scale": True, "allow_reflection": False,
                                                      "weights": np.ones(len(points2))},
                                 {"source": "points", "target": "points", "allow_scale": "flag",
                                  "allow_reflection": "flag", "weights": "array"},
                                 accept=frozenset({("weights", "None")}),  # None: equal weights
                                 check=lambda result, a: rotation_problem(result.rotation)),
        "rate_interval": Case(c.rate_interval, {"outcomes": right, "confidence": 0.95},
                              {"outcomes": "bool_array", "confidence": "probability"},
                              accept=frozenset({("outcomes", "a wrong trailing axis")})),  # 5 items instead of 4
        "RateInterval.contains": Case(c.rate_interval(right).contains, {"value": 0.5},
                                      {"value": "probability"},
                                      # a number outside [0, 1] is outside every interval: False, correctly
                                      accept=frozenset({("value", "below 0"), ("value", "above 1")})),
        "rigid_transform": Case(c.rigid_transform, {"rotation": np.eye(3), "translation": [1.0, 2.0, 3.0]},
                                {"rotation": "array", "translation": "array"},
                                accept=frozenset({("rotation", "one more axis")})),  # a stack of one rotation
        "rotation_2d": Case(c.rotation_2d, {"angle": 0.3}, {"angle": "real"},
                            check=lambda r, a: rotation_problem(r, a["angle"])),
        "rotation_matrix": Case(c.rotation_matrix, {"axis": [0.0, 0.0, 1.0], "angle": 0.3},
                                {"axis": "array", "angle": "real"},
                                check=lambda r, a: rotation_problem(r, a["angle"], a["axis"])),
        "rotation_x": Case(c.rotation_x, {"angle": 0.3}, {"angle": "real"},
                             check=lambda r, a: rotation_problem(r, a["angle"], np.eye(3)[0])),
        "rotation_y": Case(c.rotation_y, {"angle": 0.3}, {"angle": "real"},
                             check=lambda r, a: rotation_problem(r, a["angle"], np.eye(3)[1])),
        "rotation_z": Case(c.rotation_z, {"angle": 0.3}, {"angle": "real"},
                             check=lambda r, a: rotation_problem(r, a["angle"], np.eye(3)[2])),
        "savefig": Case(c.savefig, {"fig": figure, "name": "figure"}, {"fig": "object", "name": "name"}),
        "spawn_rngs": Case(c.spawn_rngs, {"seed": 0, "n": 2}, {"seed": "seed", "n": "count"}),
    }
