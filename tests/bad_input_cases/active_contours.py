"""Bad-input table of ``amdo_lab.active_contours``: a valid call and the kind of each argument.

The valid inputs are small: a 40 x 40 disc, its potential, a 12-point snake round it.
"""

from __future__ import annotations

import numpy as np

from bad_input_cases._core import Case

#: (callable, argument, spoiled label) calls known to fail the test, with the reason; each must
#: still fail (remove it once fixed).
KNOWN_FAILURES: dict[tuple[str, str, str], str] = {}

#: Public names not called with user input, with the reason.
EXEMPT = {
    "HamSlice": "a result record, built by make_ham_slice and HamStudy.slice from checked input",
    "MuscleShape": "a record of a drawn solid, built by the generators from checked input",
    "MuscleShape.volume_mm3": "takes no argument",
    "SnakeResult": "a result record, built by the snakes from checked input",
    "SnakeWeights": "a record of three weights (Table 1), checked where a snake receives them",
}


def cases() -> dict[str, Case]:
    """The public callables of ``amdo_lab.active_contours``, by name."""
    from amdo_lab import active_contours as ac

    disc = (np.hypot(*(np.mgrid[:40, :40] - 19.5)) < 10).astype(float)
    potential = ac.potential_field(disc)
    theta = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    init = np.rint(19.5 + 14 * np.column_stack([np.sin(theta), np.cos(theta)]))
    snake = {"alpha": 0.4, "beta": 0.4, "gamma": 1.2, "window": 3, "d_min_px": 2.0, "d_max_px": 6.0,
             "max_iter": 5}
    kinds = {"alpha": "non_negative", "beta": "non_negative", "gamma": "non_negative", "window": "count",
             "d_min_px": "positive", "d_max_px": "positive", "max_iter": "count"}
    ham = ac.make_ham_slice(rng=0)
    study = ac.make_ham_study(rng=0, n_hams=12)
    any_count: frozenset[tuple[str, str]] = frozenset()
    shape = study.muscle(0, 0, "semimembranosus")
    ham_stage = {"ham": 0, "stage": 1}
    ham_stage_kinds = {"ham": "count", "stage": "count"}
    zero_ok = frozenset({("ham", "zero"), ("stage", "zero")})  # the first ham, the raw stage
    any_angles = frozenset({("theta", "an empty array"), ("theta", "one more axis"), ("theta", "a wrong trailing axis")})
    return {
        "make_ham_slice": Case(ac.make_ham_slice, {"rng": 0, "scale": 1.0, "noise": 0.04},
                               {"rng": "seed", "scale": "positive", "noise": "non_negative"}),
        "make_ham_study": Case(ac.make_ham_study, {"rng": 0, "n_hams": 12, "noise": 0.04},
                               {"rng": "seed", "n_hams": "count", "noise": "non_negative"}),
        "HamStudy": Case(ac.HamStudy, {"rng": 0, "n_hams": 12, "noise": 0.04},
                         {"rng": "seed", "n_hams": "count", "noise": "non_negative"}),
        "HamStudy.slice": Case(lambda ham, stage, index: study.slice(ham, stage, index),
                               {"ham": 0, "stage": 1, "index": 2}, {"ham": "count", "stage": "count",
                                                                    "index": "count"},
                               accept=frozenset({("ham", "zero"), ("index", "zero"), ("stage", "zero")})),
        "HamStudy.hams_at": Case(lambda stage: study.hams_at(stage), {"stage": 1}, {"stage": "count"},
                                 accept=frozenset({("stage", "zero")})),
        "HamStudy.muscle": Case(lambda ham, stage, muscle: study.muscle(ham, stage, muscle),
                                {**ham_stage, "muscle": "semimembranosus"}, {**ham_stage_kinds, "muscle": "name"},
                                accept=zero_ok),
        "HamStudy.volume": Case(lambda ham, stage, muscle: study.volume(ham, stage, muscle),
                                {**ham_stage, "muscle": "semimembranosus"}, {**ham_stage_kinds, "muscle": "name"},
                                accept=zero_ok),
        "HamStudy.slice_positions": Case(lambda ham, stage: study.slice_positions(ham, stage), ham_stage,
                                         ham_stage_kinds, accept=zero_ok),
        "MuscleShape.r0": Case(shape.r0, {"z_mm": 1.0}, {"z_mm": "real"}),
        "MuscleShape.area_mm2": Case(shape.area_mm2, {"z_mm": 1.0}, {"z_mm": "real"}),
        "MuscleShape.radius": Case(shape.radius, {"theta": theta, "z_mm": 1.0}, {"theta": "array", "z_mm": "real"},
                                   accept=any_angles),  # r(theta) is shaped as theta
        "MuscleShape.contour_px": Case(shape.contour_px, {"z_mm": 1.0}, {"z_mm": "real"}),
        "initial_contour": Case(ac.initial_contour, {"ham_slice": ham, "muscle": "semimembranosus", "rng": 0,
                                                     "enlarge": (0.1, 0.2), "n_points": 30},
                                {"ham_slice": "object", "muscle": "name", "rng": "seed", "enlarge": "array",
                                 "n_points": "count"}),
        "smooth_7x7": Case(ac.smooth_7x7, {"image": disc}, {"image": "array"},
                           accept=frozenset({("image", "a wrong trailing axis")})),
        "edge_strength": Case(ac.edge_strength, {"image": disc, "edges": "sobel"},
                              {"image": "array", "edges": "name"},
                              accept=frozenset({("image", "a wrong trailing axis")})),
        "equalise_histogram": Case(ac.equalise_histogram, {"image": np.arange(100).reshape(10, 10)},
                                   {"image": "array"}, accept=frozenset({("image", "a wrong trailing axis")})),
        "potential_field": Case(ac.potential_field, {"image": disc, "edge_share": 0.1, "min_object_px": 40,
                                                     "cap_px": 15.0, "edges": "sobel", "thin": True},
                                {"image": "array", "edge_share": "probability", "min_object_px": "count",
                                 "cap_px": "positive", "edges": "name", "thin": "flag"},
                                accept=frozenset({("image", "a wrong trailing axis")})),
        "gradient_vector_flow": Case(ac.gradient_vector_flow, {"edge_map": potential, "mu": 0.2, "n_iter": 3},
                                     {"edge_map": "array", "mu": "positive", "n_iter": "count"},
                                     accept=frozenset({("edge_map", "a wrong trailing axis")})),
        "candidate_offsets": Case(ac.candidate_offsets, {"window": 3}, {"window": "count"}),
        "respace": Case(ac.respace, {"points": init, "d_min_px": 2.0, "d_max_px": 6.0},
                        {"points": "array", "d_min_px": "positive", "d_max_px": "positive"}),
        "greedy_energies": Case(ac.greedy_energies, {"potential": potential, "points": init, "alpha": 0.4,
                                                     "beta": 0.4, "gamma": 1.2, "window": 3, "image_norm": "range"},
                                {"potential": "array", "points": "array", "alpha": "non_negative",
                                 "beta": "non_negative", "gamma": "non_negative", "window": "count",
                                 "image_norm": "name"},
                                accept=frozenset({("potential", "a wrong trailing axis")}), names={}),
        "greedy_snake": Case(ac.greedy_snake, {"potential": potential, "init": init, **snake, "normalise": "spacing",
                                                "image_norm": "range"},
                             {"potential": "array", "init": "array", **kinds, "normalise": "name", "image_norm": "name"},
                             accept=frozenset({("potential", "a wrong trailing axis")}) | any_count),
        "greedy_snake_loop": Case(ac.greedy_snake_loop, {"potential": potential, "init": init, **snake},
                                  {"potential": "array", "init": "array", **kinds},
                                  accept=frozenset({("potential", "a wrong trailing axis")}) | any_count),
        "dp_pass": Case(ac.dp_pass, {"potential": potential, "points": init, "fixed": 0, "alpha": 0.4, "beta": 0.4,
                                     "gamma": 2.4, "window": 3, "image_norm": "range"},
                        {"potential": "array", "points": "array", "fixed": "count", "alpha": "non_negative",
                         "beta": "non_negative", "gamma": "non_negative", "window": "count", "image_norm": "name"},
                        accept=frozenset({("potential", "a wrong trailing axis"),
                                          ("fixed", "zero")})),  # point 0 is a valid point to hold still
        "dp_snake": Case(ac.dp_snake, {"potential": potential, "init": init, **snake},
                         {"potential": "array", "init": "array", **kinds},
                         accept=frozenset({("potential", "a wrong trailing axis")}) | any_count),
        "variational_snake": Case(ac.variational_snake,
                                  {"edge_map": potential.max() - potential, "init": init, "alpha": 0.4, "beta": 0.4,
                                   "gamma": 1.2, "tau": 0.5, "d_min_px": 2.0, "d_max_px": 6.0, "max_iter": 5,
                                   "mu": 0.2, "gvf_iter": 3, "unit_flow": True},
                                  {"edge_map": "array", "init": "array", "alpha": "non_negative",
                                   "beta": "non_negative", "gamma": "non_negative", "tau": "positive",
                                   "d_min_px": "positive", "d_max_px": "positive", "max_iter": "count",
                                   "mu": "positive", "gvf_iter": "count", "unit_flow": "flag"},
                                  accept=frozenset({("edge_map", "a wrong trailing axis")}) | any_count),
        "polygon_area_mm2": Case(ac.polygon_area_mm2, {"points": init, "pixel_mm": (0.2, 0.23)},
                                 {"points": "array", "pixel_mm": "array"}),
        "volume_mm3": Case(ac.volume_mm3, {"areas_mm2": np.array([1.0, 2.0]), "slice_mm": 2.0},
                           {"areas_mm2": "array", "slice_mm": "positive"},
                           accept=frozenset({("areas_mm2", "a wrong trailing axis")})),
        "segment_contour": Case(ac.segment_contour, {"potential": potential, "init": init, "method": "greedy"},
                                {"potential": "array", "init": "array", "method": "name"},
                                accept=frozenset({("potential", "a wrong trailing axis")}) | any_count),
        "segment_study": Case(ac.segment_study, {"study": study, "method": "greedy", "every": 40, "hams": (0,)},
                              {"study": "object", "method": "name", "every": "count", "hams": "object"}),
    }
