"""The equation map of chapter 2: each equation the notebook cites, its code and its test.

Shown by ``help(amdo_lab.pdm_mixtures)``; checked by ``tests/test_equation_paths.py``.
"""

from __future__ import annotations

from amdo_lab.common.equations import EquationPath

TEST_FILE = "test_pdm_mixtures.py"

EQUATIONS: dict[int, EquationPath] = {
    1: EquationPath(code='amdo_lab.pdm_mixtures.pdm.fit_pdm',
                    test='test_pdm_modes_are_orthonormal_and_reproduce_training_data'),
    2: EquationPath(code='amdo_lab.pdm_mixtures.gmm.fit_gaussian_mixture',
                    test='test_gaussian_mixture_em_matches_sklearn'),
    3: EquationPath(code='amdo_lab.pdm_mixtures.gmm.fit_gaussian_mixture',
                    test='test_gaussian_mixture_em_matches_sklearn'),
    4: EquationPath(code='amdo_lab.pdm_mixtures.gmm.fit_gaussian_mixture',
                    test='test_batched_mixture_em_equals_one_run_at_a_time'),
    5: EquationPath(code='amdo_lab.pdm_mixtures.gmm.fit_gaussian_mixture',
                    test='test_batched_mixture_em_equals_one_run_at_a_time'),
    6: EquationPath(code='amdo_lab.pdm_mixtures.gmm.gaussian_log_density_reference',
                    test='test_reference_paths_equal_fast_paths'),
    7: EquationPath(code='amdo_lab.pdm_mixtures.gmm.fit_gaussian_mixture',
                    test='test_batched_mixture_em_equals_one_run_at_a_time'),
    8: EquationPath(code='amdo_lab.pdm_mixtures.gmm.fit_gaussian_mixture',
                    test='test_batched_mixture_em_equals_one_run_at_a_time'),
    9: EquationPath(code='amdo_lab.pdm_mixtures.pdm.fit_modes',
                    test='test_pdm_modes_are_orthonormal_and_reproduce_training_data'),
    10: EquationPath(code='amdo_lab.pdm_mixtures.recogniser.ArticulatedShapeRecogniser.limb_label_posteriors',
                     test='test_limb_posteriors_are_eq10_bayes_rule_over_the_eq16_residual'),
    11: EquationPath(code='amdo_lab.pdm_mixtures.recognition.gated_component_scores',
                     test='test_gated_component_scores_add_the_log_terms_or_multiply_ln_p_as_printed_eq11'),
    12: EquationPath(code='amdo_lab.pdm_mixtures.polar_mixture.PolarPDM.project',
                     test='test_polar_pdm_project_is_the_clamped_modal_fit_of_each_block_eq12'),
    13: EquationPath(code='amdo_lab.pdm_mixtures.recognition.winning_components',
                     test='test_winning_components_take_the_map_class_and_its_best_component_eq13'),
    14: EquationPath(code='amdo_lab.pdm_mixtures.recognition.relabel_limbs',
                     test='test_relabel_limbs_charges_k_p_per_disagreement_with_the_winning_string_eq14'),
    15: EquationPath(code='amdo_lab.pdm_mixtures.recogniser.ArticulatedShapeRecogniser.model_limbs',
                     test='test_model_limbs_are_each_label_pdm_fitted_to_the_observed_limb_eq15'),
    16: EquationPath(code='amdo_lab.pdm_mixtures.recogniser.ArticulatedShapeRecogniser.limb_label_posteriors',
                     test='test_limb_posteriors_are_eq10_bayes_rule_over_the_eq16_residual'),
    17: EquationPath(code='amdo_lab.pdm_mixtures.labels.hamming_distance_reference',
                     test='test_reference_paths_equal_fast_paths'),
    18: EquationPath(code='amdo_lab.pdm_mixtures.labels.label_string_log_prob',
                     test='test_hamming_counts_mismatches_and_label_probability'),
}
