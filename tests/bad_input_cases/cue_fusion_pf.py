"""Bad-input table of ``amdo_lab.cue_fusion_pf``: a valid call and the kind of each argument.

The valid inputs are tiny: two frames of a seeded head sequence, a few particles, and a cascade
trained in under a second on one scene (the package's own cascade, cached under build/, is never
trained here).
"""

from __future__ import annotations

import numpy as np

from bad_input_cases._core import Case

#: (callable, argument, spoiled label) calls known to fail the test, with the reason; each must
#: still fail (remove it once fixed).
KNOWN_FAILURES: dict[tuple[str, str, str], str] = {}

#: Public names not called with user input, with the reason.
EXEMPT = {
    "CalibrationResult": "a result record, built by calibrate_sigma from checked input",
    "TrackResult": "a result record, built by track and the peers from checked input",
    "BoostedCascade": "a trained model, built by load_or_train_cascade (its stages_passed_patches method is tabled)",
    "WalkerSequence": "a result record, built by make_walker_sequence (its oracle method is tabled)",
    "ARDynamics.spectral_radius": "takes no argument",
    "ShapeSpace.shape_matrix": "takes no argument",
    "HeadSequence.segment_of_frames": "takes no argument",
    "WalkerSequence.segment_of_frames": "takes no argument",
    "WalkerSequence.shape_space": "takes no argument",
}

EMPTY = frozenset()


def cases() -> dict[str, Case]:
    """The public callables of ``amdo_lab.cue_fusion_pf``, by name."""
    from amdo_lab import cue_fusion_pf as cf
    from amdo_lab.cue_fusion_pf import data as data_module, likelihoods as likelihoods_module, structure as structure_module, tracker as tracker_module

    sequence = cf.make_head_sequence("twin", rng=0)
    frames = sequence.frames[:2]
    frame = frames[0]
    ellipse = sequence.true_ellipses[0]
    space = cf.ShapeSpace.from_ellipse(ellipse)
    states = sequence.truth[:3] + np.array([[0.0, 0.0, 0.0], [3.0, -2.0, 0.05], [-4.0, 1.0, -0.05]])
    training = cf.make_training_set(rng=0, n_scenes=1, per_scene=2, negatives_per_scene=30)
    tiny = {"first_stages": 1, "second_stages": 1, "n_features": 40, "n_negatives": 20, "max_stumps": 2,
            "min_detection": 0.99, "max_false_positive": 0.6}
    cascade = structure_module._train_cascade(training, rng=1, **tiny)
    color = cf.ColorLikelihood(space, frame, sequence.truth[0], bins=16)
    edge = cf.EdgeLikelihood(space, n_lines=12)
    structure = cf.StructureLikelihood(space, cascade)
    dynamics = cf.ARDynamics([2.0, 10.0], [0.0, 0.0], 0.04, [1.0, 0.1], [0.0, 0.0])
    pair = np.zeros((3, 2))
    histogram = cf.kernel_histogram(frame, ellipse, 8)
    at_truth, at_prior = np.array([0.1, 0.2, 0.15]), np.array([[0.3, 0.4], [0.2, 0.5], [0.35, 0.25]])

    # states: an empty (0, 3) stack of states is a stack of no particles, and gets an empty answer
    empty_states = frozenset({("states", "an empty array")})
    frame_kinds = {"frame": "image", "states": "array"}
    tracking = {"frames": frames, "init": ellipse, "rng": 0, "cues": ("color", "edge"), "n_particles": 6,
                "sigmas": "calibrated", "bins": 16, "stride": 4.0, "n_lines": 12, "half_length": 6, "p0": 0.2,
                "sigma_e": 1.5, "threshold": 6.0, "beta": (2.0, 2.0, 10.0), "stationary_std": (100.0, 100.0, 0.1),
                "printed_order": False, "init_spread": (2.0, 2.0, 0.02)}
    tracking_kinds = {"frames": "image", "init": "array", "rng": "seed", "cues": "object", "n_particles": "count",
                      "sigmas": "object", "bins": "count", "stride": "positive", "n_lines": "count",
                      "half_length": "count", "p0": "probability", "sigma_e": "positive", "threshold": "positive",
                      "beta": "array", "stationary_std": "array", "printed_order": "flag", "init_spread": "array"}

    def method(instance, name):
        """A call of ``instance.name(**kwargs)`` on an instance made once, above."""
        return lambda **kwargs: getattr(instance, name)(**kwargs)

    return {
        # --- shape space, eqs. (1)-(3)
        "ShapeSpace": Case(cf.ShapeSpace, {"template": space.template + 50.0, "kind": "translation_scale"},
                           {"template": "points", "kind": "name"}),
        "ShapeSpace.from_ellipse": Case(cf.ShapeSpace.from_ellipse,
                                        {"ellipse": ellipse, "n_control": 6, "kind": "translation_scale"},
                                        {"ellipse": "array", "n_control": "count", "kind": "name"}),
        "ShapeSpace.ellipses": Case(method(space, "ellipses"), {"states": states}, {"states": "array"},
                                    accept=empty_states),
        "ShapeSpace.control_points": Case(method(space, "control_points"), {"states": states}, {"states": "array"},
                                          accept=empty_states),
        "ShapeSpace.curve": Case(method(space, "curve"), {"states": states, "n_points": 10},
                                 {"states": "array", "n_points": "count"}, accept=empty_states),
        "ShapeSpace.template_normals": Case(method(space, "template_normals"), {"n_lines": 8}, {"n_lines": "count"}),
        # --- dynamics, eqs. (4)-(5)
        "ar2_coefficients": Case(cf.ar2_coefficients, {"beta": 2.0, "omega": 0.0, "tau": 0.04},
                                 {"beta": "non_negative", "omega": "real", "tau": "positive"}),
        "ARDynamics": Case(cf.ARDynamics, {"beta": [2.0, 10.0], "omega": [0.0, 0.0], "tau": 0.04,
                                           "stationary_std": [1.0, 0.1], "mean": [0.0, 0.0],
                                           "printed_order": False, "allow_unstable": False},
                           {"beta": "array", "omega": "array", "tau": "positive", "stationary_std": "array",
                            "mean": "array", "printed_order": "flag", "allow_unstable": "flag"}),
        "ARDynamics.step": Case(method(dynamics, "step"), {"previous": pair, "before": pair, "rng": 0},
                                {"previous": "array", "before": "array", "rng": "seed"},
                                accept=frozenset({("previous", "an empty array")})),  # no particles, no step
        "ARDynamics.propagate": Case(method(dynamics, "propagate"), {"previous": pair, "before": pair, "noise": pair},
                                     {"previous": "array", "before": "array", "noise": "array"}),
        "default_dynamics": Case(cf.default_dynamics, {"mean": sequence.truth[0], "beta": (2.0, 2.0, 10.0),
                                                       "stationary_std": (100.0, 100.0, 0.1), "printed_order": False},
                                 {"mean": "array", "beta": "array", "stationary_std": "array", "printed_order": "flag"}),
        # --- colour, eqs. (7)-(11)
        "kernel_histogram": Case(cf.kernel_histogram, {"frame": frame, "ellipse": ellipse, "bins": 8},
                                 {"frame": "image", "ellipse": "array", "bins": "count"}),
        "bhattacharyya": Case(cf.bhattacharyya, {"p": histogram, "q": histogram}, {"p": "array", "q": "array"},
                              # a stack of one histogram against one histogram (broadcast along the last axis)
                              accept=frozenset({("p", "one more axis"), ("q", "one more axis")})),
        "ColorLikelihood": Case(cf.ColorLikelihood, {"shape_space": space, "reference_frame": frame,
                                                     "reference_state": sequence.truth[0], "bins": 16, "sigma": 0.1,
                                                     "stride": 4.0, "color_space": "rgb"},
                                {"shape_space": "object", "reference_frame": "image", "reference_state": "array",
                                 "bins": "count", "sigma": "positive", "stride": "positive", "color_space": "name"}),
        "ColorLikelihood.log_likelihood": Case(method(color, "log_likelihood"), {"frame": frame, "states": states},
                                               frame_kinds, accept=empty_states),
        "ColorLikelihood.rho": Case(method(color, "rho"), {"frame": frame, "states": states},
                                              frame_kinds, accept=empty_states),
        "ColorLikelihood.distance": Case(method(color, "distance"), {"frame": frame, "states": states},
                                         frame_kinds, accept=empty_states),
        # --- edges, eqs. (13)-(14)
        "edge_line_likelihood": Case(cf.edge_line_likelihood, {"offsets": [0.5, -3.0], "p0": 0.2,
                                                               "clutter_density": 0.1, "sigma_e": 1.5},
                                     {"offsets": "array", "p0": "probability", "clutter_density": "positive",
                                      "sigma_e": "positive"},
                                     # no feature on the line; three features instead of two
                                     accept=frozenset({("offsets", "an empty array"), ("offsets", "a wrong trailing axis")})),
        "simulate_measurement_lines": Case(cf.simulate_measurement_lines,
                                           {"n_lines": 4, "half_length": 6.0, "p0": 0.2, "clutter_density": 0.1,
                                            "sigma_e": 1.5, "rng": 0},
                                           {"n_lines": "count", "half_length": "positive", "p0": "probability",
                                            "clutter_density": "non_negative", "sigma_e": "positive", "rng": "seed"}),
        "EdgeLikelihood": Case(cf.EdgeLikelihood, {"shape_space": space, "n_lines": 12, "half_length": 6, "p0": 0.2,
                                                   "sigma_e": 1.5, "threshold": 6.0, "exponent": 0.5},
                               {"shape_space": "object", "n_lines": "count", "half_length": "count",
                                "p0": "probability", "sigma_e": "positive", "threshold": "positive",
                                "exponent": "probability"}),
        "EdgeLikelihood.log_likelihood": Case(method(edge, "log_likelihood"),
                                              {"frame": frame, "states": states, "reference": False},
                                              {**frame_kinds, "reference": "flag"}, accept=empty_states),
        "EdgeLikelihood.profiles": Case(method(edge, "profiles"), {"frame": frame, "states": states, "reference": True},
                                        {**frame_kinds, "reference": "flag"}, accept=empty_states),
        "EdgeLikelihood.features": Case(method(edge, "features"), {"frame": frame, "states": states, "reference": False},
                                        {**frame_kinds, "reference": "flag"}, accept=empty_states),
        "EdgeLikelihood.grey": Case(method(edge, "grey"), {"frame": frame}, {"frame": "image"}),
        # --- structure, eq. (12)
        "make_training_set": Case(cf.make_training_set, {"rng": 0, "n_scenes": 1, "per_scene": 2,
                                                         "negatives_per_scene": 30},
                                  {"rng": "seed", "n_scenes": "count", "per_scene": "count",
                                   "negatives_per_scene": "count"}),
        "load_or_train_cascade": Case(cf.load_or_train_cascade, {"rng": cf.CASCADE_SEED, "cache": True},
                                      {"rng": "seed", "cache": "flag"}),
        "BoostedCascade.stages_passed_patches": Case(method(cascade, "stages_passed_patches"),
                                                     {"patches": training.negatives[:4]}, {"patches": "array"},
                                                     accept=frozenset({("patches", "an empty array")})),  # no window
        "StructureLikelihood": Case(cf.StructureLikelihood, {"shape_space": space, "cascade": cascade, "sigma": 0.3},
                                    {"shape_space": "object", "cascade": "object", "sigma": "positive"}),
        "StructureLikelihood.log_likelihood": Case(method(structure, "log_likelihood"),
                                                   {"frame": frame, "states": states}, frame_kinds,
                                                   accept=empty_states),
        "StructureLikelihood.distance": Case(method(structure, "distance"), {"frame": frame, "states": states},
                                             frame_kinds, accept=empty_states),
        "StructureLikelihood.boxes": Case(method(structure, "boxes"), {"states": states}, {"states": "array"},
                                          accept=empty_states),
        # --- fusion, eq. (6), calibration and the filter of Fig. 1
        "fused_log_likelihood": Case(cf.fused_log_likelihood, {"cues": {"color": color}, "frame": frame,
                                                               "states": states},
                                     {"cues": "object", **frame_kinds}, accept=empty_states),
        "calibrate_sigma": Case(cf.calibrate_sigma, {"distances_true": at_truth, "distances_prior": at_prior,
                                                     "grid": np.array([0.05, 0.1, 0.5])},
                                {"distances_true": "array", "distances_prior": "array", "grid": "array"},
                                # three prior samples per frame instead of two; the default grid
                                accept=frozenset({("distances_prior", "a wrong trailing axis"), ("grid", "None")})),
        "calibration_distances": Case(cf.calibration_distances,
                                      {"sequences": [cf.HeadSequence(sequence.frames[:3], sequence.truth[:3],
                                                                     sequence.true_ellipses[:3], {}, "twin")],
                                       "cue": "color", "rng": 0, "n_samples": 4, "frame_step": 1, "bins": 16},
                                      {"sequences": "object", "cue": "name", "rng": "seed", "n_samples": "count",
                                       "frame_step": "count", "bins": "count"}),
        "systematic_resample": Case(cf.systematic_resample, {"weights": np.array([0.2, 0.5, 0.3]), "u": 0.4},
                                    {"weights": "array", "u": "probability"}),
        "track": Case(cf.track, tracking, tracking_kinds),
        "weigh_and_resample": Case(cf.weigh_and_resample, {"cue_log_likelihoods": np.array([[0.0, -1.0, -0.5],
                                                                                          [-2.0, 0.0, -1.0]]),
                                                           "u": 0.4},
                                   {"cue_log_likelihoods": "array", "u": "probability"},
                                   accept=frozenset({("cue_log_likelihoods", "a wrong trailing axis")})),  # 4 particles
        "weigh_particles": Case(cf.weigh_particles, {"frame": frame, "particles": states, "cues": {"color": color}},
                                {"frame": "image", "particles": "array", "cues": "object"}),
        "likelihoods.check_cues": Case(likelihoods_module.check_cues, {"cues": {"color": color}}, {"cues": "object"}),
        # --- the checks the modules share (public, not re-exported): the message names the caller's argument
        "likelihoods.check_frame": Case(likelihoods_module.check_frame, {"frame": frame, "name": "reference_frame"},
                                        {"frame": "image", "name": "name"}, names={"frame": "reference_frame"}),
        "likelihoods.check_frames": Case(likelihoods_module.check_frames, {"frames": frames}, {"frames": "image"}),
        "data.as_ellipse": Case(data_module.as_ellipse, {"ellipse": ellipse, "name": "init",
                                                                  "allow_stack": False},
                                {"ellipse": "array", "name": "name", "allow_stack": "flag"}, names={"ellipse": "init"}),
        "tracker.shape_space_of": Case(tracker_module.shape_space_of, {"init": ellipse, "frame_shape": frame.shape[:2],
                                                                               "kind": "translation_scale"},
                                       {"init": "array", "frame_shape": "object", "kind": "name"}),
        "tracker.resolve_sigmas": Case(tracker_module.resolve_sigmas, {"sigmas": "calibrated"}, {"sigmas": "object"}),
        # --- data and peers
        "make_head_sequence": Case(cf.make_head_sequence, {"kind": "twin", "rng": 0, "noise_std": 5.0,
                                                           "cast_strength": 1.0},
                                   {"kind": "name", "rng": "seed", "noise_std": "non_negative",
                                    "cast_strength": "non_negative"}),
        # a record a user may build (calibration_distances takes a list of them): checked in __post_init__
        "HeadSequence": Case(cf.HeadSequence, {"frames": frames, "truth": sequence.truth[:2],
                                               "true_ellipses": sequence.true_ellipses[:2], "segments": {"a": (0, 2)},
                                               "kind": "twin", "oracle_std": (2.0, 0.02)},
                             {"frames": "image", "truth": "array", "true_ellipses": "array", "segments": "object",
                              "kind": "name", "oracle_std": "array"}),
        "HeadSequence.oracle_log_likelihood": Case(method(sequence, "oracle_log_likelihood"), {"t": 1, "states": states},
                                                   {"t": "count", "states": "array"},
                                                   accept=empty_states | {("t", "zero")}),  # frame 0
        "head_views": Case(cf.head_views, {"yaws": [0.0, 0.7], "rng": 0, "noise_std": 5.0},
                           {"yaws": "array", "rng": "seed", "noise_std": "non_negative"},
                           accept=frozenset({("yaws", "a wrong trailing axis")})),  # three yaws
        "ellipse_iou": Case(cf.ellipse_iou, {"first": ellipse, "second": ellipse + [3.0, 0.0, 1.0, 0.0, 0.0],
                                             "step": 0.5},
                            {"first": "array", "second": "array", "step": "positive"},
                            # a (1, 5) stack of one ellipse against one ellipse: one IoU
                            accept=frozenset({("first", "one more axis"), ("second", "one more axis")})),
        "track_camshift": Case(cf.track_camshift, {"frames": frames, "init": ellipse, "hue_bins": 16},
                               {"frames": "image", "init": "array", "hue_bins": "count"}),
        "track_mil": Case(cf.track_mil, {"frames": frames, "init": ellipse}, {"frames": "image", "init": "array"}),
        "track_pfilter": Case(cf.track_pfilter, {"frames": frames, "init": ellipse, "rng": 0, "cues": ("color",),
                                                 "n_particles": 6, "sigmas": "calibrated"},
                              {"frames": "image", "init": "array", "rng": "seed", "cues": "object",
                               "n_particles": "count", "sigmas": "object"}),
        **_walker_cases(cf, frames, space),
    }


def _walker_cases(cf, frames: np.ndarray, space) -> dict[str, Case]:
    """The walker of Fig. 6 and the similarity shape space (eqs. 2-3): a tiny hand-made walker record."""
    from amdo_lab.cue_fusion_pf import walker as walker_module

    template = space.template + np.array([128.0, 96.0])
    similarity = cf.ShapeSpace(template, "similarity")
    outlines = np.stack([template, template + [2.0, 1.0]])
    truth = walker_module._fit_similarity(template, outlines)
    walker = cf.WalkerSequence(frames, truth, similarity.ellipses(truth), outlines, {"walking": (0, 2)}, template)
    states = truth + np.array([[0.0, 0.0, 0.0, 0.0], [3.0, -2.0, 0.05, 0.1]])
    tracking = {"frames": frames, "init": template, "rng": 0, "cues": ("color", "edge"), "n_particles": 6,
                "bins": 16, "n_lines": 12, "shape": "similarity", "mean": truth[0],
                "init_spread": (2.0, 2.0, 0.02, 0.02), "beta": (2.0, 2.0, 10.0, 10.0),
                "stationary_std": (100.0, 100.0, 0.1, 0.1)}
    return {
        "make_walker_sequence": Case(cf.make_walker_sequence, {"rng": 0, "noise_std": 4.0, "distortion": 0.12,
                                                               "clutter_strength": 0.85},
                                     {"rng": "seed", "noise_std": "non_negative", "distortion": "non_negative",
                                      "clutter_strength": "probability"}),
        "WalkerSequence.oracle_log_likelihood": Case(lambda **kwargs: walker.oracle_log_likelihood(**kwargs),
                                                     {"t": 1, "states": states}, {"t": "count", "states": "array"},
                                                     accept=frozenset({("states", "an empty array"), ("t", "zero")})),
        "box_iou": Case(cf.box_iou, {"first": outlines[0], "second": outlines[1]}, {"first": "points", "second": "points"},
                        # a stack of one outline against a stack of one: one IoU
                        accept=frozenset()),
        "ShapeSpace.similarity_parts": Case(lambda **kwargs: similarity.similarity_parts(**kwargs), {"states": states},
                                            {"states": "array"}, accept=frozenset({("states", "an empty array")})),
        "ShapeSpace.from_ellipse (similarity)": Case(cf.ShapeSpace.from_ellipse,
                                                     {"ellipse": similarity.template_ellipse + [128.0, 96.0, 0, 0, 0],
                                                      "n_control": 8, "kind": "similarity"},
                                                     {"ellipse": "array", "n_control": "count", "kind": "name"}),
        # (init_spread and stationary_std are spoiled in the head's "track" entry above)
        "track (similarity)": Case(cf.track, tracking, {"init": "array", "shape": "name", "mean": "array",
                                                        "beta": "array"},
                                   accept=frozenset({("mean", "None")})),  # the default: the initial state
        # one state or a stack of any size (as similarity_parts)
        "ShapeSpace.check_states": Case(lambda **kwargs: similarity.check_states(**kwargs),
                                        {"states": states},
                                        {"states": "array"},
                                        accept=frozenset({("states", "one more axis"),
                                                          ("states", "an empty array")})),
    }
