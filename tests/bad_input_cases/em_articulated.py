"""Bad-input table of ``amdo_lab.em_articulated``: a valid call and the kind of each argument.

The valid calls are tiny (a few dozen points, one σ level, one iteration, two frames) so that a
spoiled call that is wrongly accepted costs little.
"""

from __future__ import annotations

import numpy as np

from bad_input_cases._core import Case

#: (callable, argument, spoiled label) calls known to fail the test, with the reason; each must
#: still fail (remove it once fixed).
KNOWN_FAILURES: dict[tuple[str, str, str], str] = {}

#: Public names not called with user input, with the reason.
EXEMPT = {
    "EMResult": "a result record, built by register_em from checked input",
    "SoftAssignResult": "a result record, built by register_softassign from checked input",
    "SurfaceFitResult": "a result record, built by fit_surface from checked input",
    "DigitSearchResult": "a result record, built by refine_digits from checked input",
    "TrackResult": "a result record, built by track from checked input",
    "TrackingSequence": "a result record, built by make_tracking_sequence from checked input",
    "RegistrationProblem": "a result record, built by make_registration_problem from checked input",
    "TrialSummary": "a result record, built by run_registration_trials (its success_interval is tabled)",
    "ObjectiveCheck": "a result record, built by objective_check from checked input",
    "SkinTexture": "a result record, built by make_skin_texture (its positions is tabled)",
    "HandModel.rest_pose": "takes no argument",
    "HandModel.joint_limits": "takes no argument",
    "RegistrationProblem.true_matches": "takes no argument",
}

# Arguments whose default is None: None is a documented valid value.
_NONE_OK = frozenset({("problem", "None")})


def cases() -> dict[str, Case]:
    """The public callables of ``amdo_lab.em_articulated``, by name."""
    from amdo_lab import em_articulated as e

    hand = e.HandModel()
    theta = hand.rest_pose()
    points = hand.sample_surface(theta, 12, rng=0)
    moved = points + 1.0
    binding = hand.texture_binding(points, theta)
    skin = e.make_skin_texture(hand, 8, rng=0)
    frames = hand.part_transforms(theta)
    camera = np.array([0.0, 40.0, 500.0])
    summary = e.TrialSummary(np.ones(3), np.array([1.0, 20.0, 2.0]), np.ones(3), np.ones(3), np.ones(3))
    tiny_problem = {"n_model": 10, "n_data": 10, "joint_error_deg": 5.0}
    tiny_settings = e.EMSettings(sigma_max=10.0, sigma_min=3.0, n_levels=1, max_iter=1)
    jacobian = hand.texture_jacobian(binding, theta)[1]
    em_kinds = {"model_points": "points", "data_points": "points", "hand": "object", "theta_init": "array"}
    em_valid = {"model_points": points, "data_points": moved, "hand": hand, "theta_init": theta}
    pose = {"theta": theta}

    return {
        # ---------------------------------------------------------------- the hand and its methods
        "HandModel": Case(e.HandModel, {"nu": 4.0}, {"nu": "positive"}),
        "HandModel.check_theta": Case(hand.check_theta, {"theta": theta, "within_limits": True, "name": "theta"},
                                      {"theta": "array", "within_limits": "flag", "name": "name"}),
        "HandModel.part_transforms": Case(hand.part_transforms, pose, {"theta": "array"}),
        "HandModel.digit_clearance": Case(hand.digit_clearance, {"theta": theta, "n_samples": 3},
                                          {"theta": "array", "n_samples": "count"}),
        "HandModel.part_distances": Case(hand.part_distances, {"points": points, "theta": theta},
                                         {"points": "points", "theta": "array"}),
        "HandModel.part_fields": Case(hand.part_fields, {"points": points, "theta": theta},
                                      {"points": "points", "theta": "array"}),
        "HandModel.fused_field": Case(hand.fused_field, {"points": points, "theta": theta, "neighbour_rule": True},
                                      {"points": "points", "theta": "array", "neighbour_rule": "flag"}),
        "HandModel.surface_distance": Case(hand.surface_distance,
                                           {"points": points, "theta": theta, "neighbour_rule": False},
                                           {"points": "points", "theta": "array", "neighbour_rule": "flag"}),
        "HandModel.surface_distance_jacobian": Case(hand.surface_distance_jacobian, {"points": points, "theta": theta},
                                                    {"points": "points", "theta": "array"}),
        "HandModel.sample_surface": Case(hand.sample_surface, {"theta": theta, "n": 5, "rng": 0, "newton_steps": 2},
                                         {"theta": "array", "n": "count", "rng": "seed", "newton_steps": "count"}),
        "HandModel.surface_normals": Case(hand.surface_normals, {"points": points, "theta": theta},
                                          {"points": "points", "theta": "array"}),
        "HandModel.ellipsoid_mesh": Case(hand.ellipsoid_mesh, {"theta": theta, "resolution": 4},
                                         {"theta": "array", "resolution": "count"}),
        "HandModel.texture_binding": Case(hand.texture_binding, {"points": points, "theta": theta, "a": 2.0},
                                          {"points": "points", "theta": "array", "a": "positive"}),
        "HandModel.transform_texture": Case(hand.transform_texture, {"binding": binding, "theta": theta},
                                            {"binding": "object", "theta": "array"}),
        "HandModel.texture_jacobian": Case(hand.texture_jacobian, {"binding": binding, "theta": theta},
                                           {"binding": "object", "theta": "array"}),
        "HandModel.move_texture": Case(hand.move_texture,
                                       {"points": points, "theta_from": theta, "theta_to": theta, "a": 2.0},
                                       {"points": "points", "theta_from": "array", "theta_to": "array",
                                        "a": "positive"}),
        "TextureBinding": Case(e.TextureBinding,
                               {"part_p": binding.part_p, "part_r": binding.part_r, "weight_p": binding.weight_p,
                                "local_p": binding.local_p, "local_r": binding.local_r},
                               {"part_p": "array", "part_r": "array", "weight_p": "array", "local_p": "points",
                                "local_r": "points"}),
        "TextureBinding.world_points": Case(binding.world_points, {"frames": frames}, {"frames": "array"}),
        "SkinTexture.positions": Case(skin.positions, {"hand": hand, "theta": theta},
                                      {"hand": "object", "theta": "array"}),
        "TrialSummary.success_interval": Case(summary.success_interval, {"confidence": 0.9},
                                              {"confidence": "probability"}),
        # ---------------------------------------------------------------- data
        "joint_rmse_deg": Case(e.joint_rmse_deg, {"theta_est": theta, "theta_true": theta},
                               {"theta_est": "array", "theta_true": "array"}),
        "worst_joint_deg": Case(e.worst_joint_deg, {"theta_est": theta, "theta_true": theta},
                                {"theta_est": "array", "theta_true": "array"}),
        "perturb_pose": Case(e.perturb_pose, {"hand": hand, "theta": theta, "joint_error_deg": 5.0, "rng": 0,
                                              "palm_rotation_deg": 2.0, "palm_translation_mm": 2.0},
                             {"hand": "object", "theta": "array", "joint_error_deg": "non_negative", "rng": "seed",
                              "palm_rotation_deg": "non_negative", "palm_translation_mm": "non_negative"}),
        "random_pose": Case(e.random_pose, {"hand": hand, "rng": 0}, {"hand": "object", "rng": "seed"}),
        "make_skin_texture": Case(e.make_skin_texture, {"hand": hand, "n_features": 5, "rng": 0, "a": 2.0},
                                  {"hand": "object", "n_features": "count", "rng": "seed", "a": "positive"}),
        "make_registration_problem": Case(
            e.make_registration_problem,
            {"hand": hand, "rng": 0, "joint_error_deg": 5.0, "noise_mm": 1.0, "outlier_ratio": 0.5, "n_model": 10,
             "n_data": 10, "occlusion": False, "repeatability": 0.8, "texture_noise_mm": 1.0},
            {"hand": "object", "rng": "seed", "joint_error_deg": "non_negative", "noise_mm": "non_negative",
             "outlier_ratio": "non_negative", "n_model": "count", "n_data": "count", "occlusion": "flag",
             "repeatability": "probability", "texture_noise_mm": "non_negative"},
            # None: the texture's noise is the data's (documented default)
            accept=frozenset({("texture_noise_mm", "None")})),
        "make_tracking_sequence": Case(
            e.make_tracking_sequence,
            {"hand": hand, "rng": 0, "n_frames": 2, "fps": 20.0, "n_features": 20, "noise_mm": 1.0, "n_clutter": 3,
             "repeatability": 0.8, "motion": "bend", "camera": camera},
            {"hand": "object", "rng": "seed", "n_frames": "count", "fps": "positive", "n_features": "count",
             "noise_mm": "non_negative", "n_clutter": "count", "repeatability": "probability", "motion": "name",
             "camera": "array"},
            # None: the default camera 500 mm above the hand; no clutter is documented (n_clutter ≥ 0)
            accept=frozenset({("camera", "None"), ("n_clutter", "zero")})),
        # ---------------------------------------------------------------- E- and M-steps
        "e_step_reference": Case(e.e_step_reference, {"model_points": points, "data_points": moved, "sigma": 3.0,
                                                      "c": 2.0},
                                 {"model_points": "points", "data_points": "points", "sigma": "positive",
                                  "c": "positive"}),
        "e_step_statistics": Case(e.e_step_statistics, {"model_points": points, "data_points": moved, "sigma": 3.0,
                                                        "log_c": 1.0, "chunk": 5, "precision": "double"},
                                  {"model_points": "points", "data_points": "points", "sigma": "positive",
                                   "log_c": "real", "chunk": "count", "precision": "name"}),
        "e_step_statistics_kdtree": Case(e.e_step_statistics_kdtree,
                                         {"model_points": points, "data_points": moved, "sigma": 3.0, "log_c": 1.0},
                                         {"model_points": "points", "data_points": "points", "sigma": "positive",
                                          "log_c": "real"}),
        "m_step_targets": Case(e.m_step_targets,
                               {"alpha": e.e_step_reference(points, moved, 3.0), "data_points": moved},
                               {"alpha": "array", "data_points": "points"}),
        "robust_log_likelihood": Case(e.robust_log_likelihood,
                                      {"model_points": points, "data_points": moved, "sigma": 3.0, "c": 2.0},
                                      {"model_points": "points", "data_points": "points", "sigma": "positive",
                                       "c": "positive"}),
        "robust_log_likelihood_reference": Case(e.robust_log_likelihood_reference,
                                                {"model_points": points, "data_points": moved, "sigma": 3.0,
                                                 "c": 2.0},
                                                {"model_points": "points", "data_points": "points",
                                                 "sigma": "positive", "c": "positive"}),
        # ---------------------------------------------------------------- the EM (eqs. 19-20)
        "EMSettings": Case(
            e.EMSettings,
            {"sigma_max": 10.0, "sigma_min": 3.0, "n_levels": 1, "max_iter": 1, "targets": "debiased",
             "e_step": "kdtree", "sigma_mode": "anneal", "schedule": "levels"},
            {"sigma_max": "positive", "sigma_min": "positive", "n_levels": "count", "max_iter": "count",
             "targets": "name", "e_step": "name", "sigma_mode": "name", "schedule": "name"}),
        "gauss_newton_step": Case(e.gauss_newton_step,
                                  {"jacobian": jacobian, "residuals": moved - points, "weights": np.ones(len(points)),
                                   "damping": 1e-3},
                                  {"jacobian": "array", "residuals": "array", "weights": "array",
                                   "damping": "non_negative"},
                                  # any number K of parameters is valid: one more is another valid problem
                                  accept=frozenset({("jacobian", "a wrong trailing axis")})),
        "register_em": Case(e.register_em, {**em_valid, "settings": tiny_settings},
                            {**em_kinds, "settings": "object"}),
        "register_em_reference": Case(e.register_em_reference, {**em_valid, "settings": tiny_settings},
                                      {**em_kinds, "settings": "object"}),
        "climb_objective": Case(e.climb_objective, {**em_valid, "theta_start": theta, "sigma": 3.0},
                                {**em_kinds, "theta_start": "array", "sigma": "positive"}),
        "refine_digits": Case(
            e.refine_digits,
            {**em_valid, "theta": theta, "settings": tiny_settings, "search_levels": 1, "max_passes": 1,
             "min_gain": 1.0},
            {**em_kinds, "theta": "array", "settings": "object", "search_levels": "count", "max_passes": "count",
             "min_gain": "non_negative"},
            # max_passes=0 is documented: only the re-run from theta
            accept=frozenset({("max_passes", "zero")})),
        "fit_known_correspondences": Case(e.fit_known_correspondences,
                                          {"model_points": points, "matched_points": moved, "hand": hand,
                                           "theta_init": theta},
                                          {"model_points": "points", "matched_points": "points", "hand": "object",
                                           "theta_init": "array"}),
        "fit_surface": Case(e.fit_surface,
                            {"data_points": moved, "hand": hand, "theta_init": theta, "weights": np.ones(len(moved)),
                             "sigma": 3.0, "max_iter": 1, "epsilon_mm": 5.0},
                            {"data_points": "points", "hand": "object", "theta_init": "array", "weights": "array",
                             "sigma": "positive", "max_iter": "count", "epsilon_mm": "positive"},
                            # None: all weights 1, no eq. (22), all points (documented defaults)
                            accept=frozenset({("weights", "None"), ("sigma", "None"), ("epsilon_mm", "None"),
                                              ("max_iter", "zero")})),  # max_iter=0: no step (documented)
        "register_softassign": Case(
            e.register_softassign,
            {**em_valid, "sigma_max": 10.0, "sigma_min": 3.0, "slack": 1e-2, "n_levels": 1, "n_iter": 1},
            {**em_kinds, "sigma_max": "positive", "sigma_min": "positive", "slack": "positive", "n_levels": "count",
             "n_iter": "count"}),
        "track": Case(
            e.track,
            {"frames": [points, moved], "hand": hand, "theta_start": theta, "settings": tiny_settings,
             "surface_max_iter": 1},
            {"frames": "object", "hand": "object", "theta_start": "array", "settings": "object",
             "surface_max_iter": "count"},
            accept=frozenset({("surface_max_iter", "zero")})),  # 0 skips the surface fit (documented)
        # ---------------------------------------------------------------- experiments
        "noise_floor_trials": Case(e.noise_floor_trials, {"hand": hand, "n_trials": 1, "rng": 0,
                                                          "problem": tiny_problem},
                                   {"hand": "object", "n_trials": "count", "rng": "seed", "problem": "object"},
                                   accept=_NONE_OK),
        "run_registration_trials": Case(
            e.run_registration_trials,
            {"hand": hand, "n_trials": 1, "rng": 0, "problem": tiny_problem, "settings": tiny_settings,
             "surface_max_iter": 1, "digit_search": False},
            {"hand": "object", "n_trials": "count", "rng": "seed", "problem": "object", "settings": "object",
             "surface_max_iter": "count", "digit_search": "flag"},
            accept=_NONE_OK | {("surface_max_iter", "zero")}),  # 0 skips the surface fit (documented)
        "objective_check": Case(e.objective_check, {"hand": hand, "n_trials": 1, "rng": 0, "problem": tiny_problem,
                                                    "settings": tiny_settings},
                                {"hand": "object", "n_trials": "count", "rng": "seed", "problem": "object",
                                 "settings": "object"},
                                accept=_NONE_OK),
    }
