"""The equation map of chapter 6: each equation the notebook cites, its code and its test.

Shown by ``help(amdo_lab.cue_fusion_pf)``; checked by ``tests/test_equation_paths.py``.
"""

from __future__ import annotations

from amdo_lab.common.equations import EquationPath

TEST_FILE = "test_cue_fusion_pf.py"

EQUATIONS: dict[int, EquationPath] = {
    1: EquationPath(code='amdo_lab.cue_fusion_pf.shape.ShapeSpace.curve',
                    test='test_template_spline_fits_its_ellipse_and_eq2_is_w_x_plus_template'),
    2: EquationPath(code='amdo_lab.cue_fusion_pf.shape.ShapeSpace.control_points',
                    test='test_template_spline_fits_its_ellipse_and_eq2_is_w_x_plus_template'),
    3: EquationPath(code='amdo_lab.cue_fusion_pf.shape.ShapeSpace.shape_matrix',
                    test='test_template_spline_fits_its_ellipse_and_eq2_is_w_x_plus_template'),
    4: EquationPath(code='amdo_lab.cue_fusion_pf.dynamics.ARDynamics.propagate',
                    test='test_printed_eq4_is_unstable_and_the_corrected_one_is_stable'),
    5: EquationPath(code='amdo_lab.cue_fusion_pf.dynamics.ARDynamics.step',
                    test='test_corrected_dynamics_reach_their_stationary_std'),
    6: EquationPath(code='amdo_lab.cue_fusion_pf.likelihoods.fused_log_likelihood',
                    test='test_printed_sigmas_make_the_fusion_edge_only'),
    7: EquationPath(code='amdo_lab.cue_fusion_pf.likelihoods.kernel_histogram',
                    test='test_fast_colour_path_equals_the_per_pixel_histogram'),
    8: EquationPath(code='amdo_lab.cue_fusion_pf.likelihoods.kernel_histogram',
                    test='test_fast_colour_path_equals_the_per_pixel_histogram'),
    9: EquationPath(code='amdo_lab.cue_fusion_pf.likelihoods.ColorLikelihood.distance',
                    test='test_colour_distance_and_likelihood_are_eqs_9_and_11'),
    10: EquationPath(code='amdo_lab.cue_fusion_pf.likelihoods.bhattacharyya',
                     test='test_fast_colour_path_equals_the_per_pixel_histogram'),
    11: EquationPath(code='amdo_lab.cue_fusion_pf.likelihoods.ColorLikelihood.log_likelihood',
                     test='test_colour_distance_and_likelihood_are_eqs_9_and_11'),
    12: EquationPath(code='amdo_lab.cue_fusion_pf.structure.StructureLikelihood.log_likelihood',
                     test='test_structure_likelihood_is_eq12_of_the_stages_passed'),
    13: EquationPath(code='amdo_lab.cue_fusion_pf.likelihoods.edge_line_likelihood',
                     test='test_eq13_matches_simulated_lines'),
    14: EquationPath(code='amdo_lab.cue_fusion_pf.likelihoods.EdgeLikelihood.log_likelihood',
                     test='test_fast_edge_path_equals_the_numpy_reference'),
    15: EquationPath(code='amdo_lab.cue_fusion_pf.tracker.weigh_particles',
                     test='test_weigh_particles_is_bayes_rule_with_the_fused_cues'),
    16: EquationPath(code='amdo_lab.cue_fusion_pf.dynamics.ARDynamics.step',
                     test='test_step_samples_the_prediction_of_eq16'),
}
